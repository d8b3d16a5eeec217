"""The ``lotsim`` command line.

Exit codes: 0 ok, 1 incomplete (something could not be planned or reached, with
``--strict``), 2 bad input, or a run stopped by its memory or time limit. Errors go to
stderr as ``file:line:col: key: message``; results go to files; a one-screen summary goes
to stdout.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from lotsim import __version__
from lotsim.errors import ScenarioError, SettingsError
from lotsim.maneuvers.settings import MARGIN, STYLES, MinSlotSettings
from lotsim.scenario import MAX_SIZE, MIN_SIZE, GifSettings, size_problem
from lotsim.sim.settings import ASSIGNMENTS, PLANNERS, PRIORITIES, RunSettings

EXIT_OK, EXIT_INCOMPLETE, EXIT_BAD_INPUT = 0, 1, 2
_SIZES = f"{MIN_SIZE[0]}x{MIN_SIZE[1]} to {MAX_SIZE[0]}x{MAX_SIZE[1]}"


class _Parser(argparse.ArgumentParser):
    """argparse that exits with 2 and a one-line message, as every other bad input does."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


_EXITS = {
    "cars": "0 listed",
    "validate": "0 every file is a valid scenario; 1 with --strict, a free slot or exit "
                "cannot be reached, or a vehicle type cannot park in a slot; 2 a file is not "
                "a valid scenario",
    "minslot": "0 the table was computed; 2 bad input",
    "maneuver": "0 planned; 1 the vehicle type cannot park there; 2 bad input",
    "run": "0 every car parked, left or was turned away; 1 a car is still waiting when the "
           "run ends; 2 bad input, or a memory or time limit stopped the run (nothing "
           "written); 130 interrupted",
    "render": "0 written; 2 bad input, or a result that cannot be drawn",
    "check": "0 the result holds every rule; 1 violations (the first are listed); 2 the "
             "file is not a lotsim result",
    "show": "0 written; 2 bad input",
    "bench": "0 every run passed its check; 1 some run failed; 2 bad input",
    "export": "0 written; 2 bad input, a result that cannot be exported, or the format's "
              "packages missing",
}
"""Each command's exit codes, for its --help."""


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="lotsim", description="Plan many car-like vehicles in a parking lot.",
                epilog="exit codes: 0 ok, 1 incomplete (something could not be planned, "
                "reached or checked), 2 bad input, 130 interrupted; 'lotsim COMMAND --help' "
                "says what each command does and its own")
    p.add_argument("--version", action="version", version=f"lotsim {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser,
                           metavar="COMMAND")

    sub.add_parser("cars", help="list the built-in vehicle types")

    v = sub.add_parser("validate", help="check scenario files and summarise each lot")
    v.add_argument("scenarios", nargs="+", metavar="SCENARIO",
                   help="scenario YAML files (docs/scenario.md)")
    v.add_argument("--strict", action="store_true",
                   help="exit 1 when a slot or exit cannot be reached, or a vehicle "
                   "type cannot park in a slot")

    m = sub.add_parser("minslot", help="shortest parallel slot for each number of direction "
                       "changes")
    which = m.add_mutually_exclusive_group(required=True)
    which.add_argument("--car", "--vehicle", dest="car", metavar="CAR",
                       help="a catalogue name (see `lotsim cars`) or a vehicle YAML file")
    which.add_argument("--all-cars", action="store_true", help="every catalogue car")
    m.add_argument("--width", type=float, nargs="+", required=True, metavar="WIDTH",
                   help="slot width [m]; several give one table (and curve) per width")
    ms = MinSlotSettings()
    m.add_argument("--max-changes", type=int, default=ms.max_changes, help="largest number of "
                   f"direction changes to report (default {ms.max_changes})")
    m.add_argument("--resolution", type=float, default=ms.resolution,
                   help=f"length step [m] ({ms.resolution:g})")
    m.add_argument("--step-deg", type=float, default=ms.step_deg,
                   help=f"start-heading sweep step [deg] ({ms.step_deg:g})")
    m.add_argument("--json", action="store_true", help="print JSON instead of a table")
    m.add_argument("--plot", metavar="PNG", help="plot length against changes (matplotlib)")

    mv = sub.add_parser("maneuver", help="plan one slot's parking maneuver and draw it")
    mv.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file")
    mv.add_argument("--slot", required=True, help="slot id")
    mv.add_argument("--car", "--vehicle", dest="vehicle", metavar="TYPE",
                    help="vehicle type of the scenario (default its first)")
    mv.add_argument("--lane", help="lane id to start from (default the best)")
    mv.add_argument("--style", choices=STYLES, default=STYLES[0],
                    help="nose-in (forward), backed in (reverse) or the better (any)")
    mv.add_argument("--leave", action="store_true", help="the way out instead of the way in")
    mv.add_argument("--margin", type=float, default=MARGIN,
                    help=f"safety margin [m] ({MARGIN:g})")
    mv.add_argument("-o", "--output", help="PNG to write")
    mv.add_argument("--size", default="900x700", help=f"image size WxH in pixels, {_SIZES} "
                    "(900x700)")

    r = sub.add_parser("run", help="plan a scenario's traffic and write OUTDIR/result.json")
    r.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file with traffic")
    r.add_argument("-o", "--output", metavar="OUTDIR",
                   help="directory for result.json (default runs/<scenario name>)")
    rs = RunSettings()  # defaults and choices: the library's, checked there too
    r.add_argument("--planner", choices=PLANNERS, default=rs.planner,
                   help=f"cooperative A* variant (default {rs.planner})")
    r.add_argument("--assign", choices=ASSIGNMENTS, default=rs.assignment,
                   help=f"slot choice: straight-line distance or travel time (default "
                   f"{rs.assignment})")
    r.add_argument("--seed", type=int, help="seed of the traffic stream (default the "
                   "scenario's)")
    r.add_argument("--window", type=float,
                   help=f"with --planner whca: the window [s] ({rs.window:g})")
    r.add_argument("--omega", type=float, default=rs.omega,
                   help=f"search fuse: expansions allowed per reverse-search node "
                   f"({rs.omega:g})")
    r.add_argument("--priority", choices=PRIORITIES,
                   default=rs.priority, help=f"planning order (default {rs.priority}): "
                   "online in arrival order, or booked in advance: shortest static time "
                   "first, or the best order a genetic algorithm finds (total time to park)")
    r.add_argument("--horizon", type=float,
                   help="with --priority shortest_first/ga: how far ahead arrivals are "
                   f"booked [s] ({rs.horizon:g}; inf: all)")
    r.add_argument("--memory-limit", metavar="SIZE", help="stop, writing nothing, when the "
                   "run holds or is projected to need more memory than this, e.g. 4G "
                   "(default 80%% of the memory available)")
    r.add_argument("--time-limit", type=float, default=7200.0, metavar="SECONDS",
                   help="stop, writing nothing, when planning takes or is projected to take "
                   "longer than this (default 7200; 0: no limit)")
    gif = r.add_mutually_exclusive_group()
    gif.add_argument("--gif", metavar="GIF", help="also write an animated GIF of the run "
                     "(default: OUTDIR/run.gif when the scenario has an 'animation' section)")
    gif.add_argument("--no-gif", action="store_true", help="write no GIF, whatever the "
                     "scenario asks")
    r.add_argument("--html", metavar="HTML", help="also write the interactive replay of the "
                   "run, one HTML file (default: OUTDIR/NAME when the scenario's 'animation' "
                   "section names one)")
    r.add_argument("--mp4", metavar="MP4", help="also write the GIF's frames as an H.264 "
                   "video (needs pip install 'lotsim[video]'; default: OUTDIR/NAME when the "
                   "scenario's 'animation' section names one)")

    rd = sub.add_parser("render", help="draw a result.json: animated GIF, interactive HTML "
                        "replay, MP4 video, timeline plot")
    rd.add_argument("result", metavar="RESULT_JSON", help="a result.json of lotsim run")
    rd.add_argument("--gif", metavar="GIF", help="animated GIF to write")
    rd.add_argument("--html", metavar="HTML", help="interactive replay to write: one "
                    "self-contained HTML file that opens from disk in a browser")
    rd.add_argument("--mp4", metavar="MP4", help="the GIF's frames as an H.264 video (needs "
                    "pip install 'lotsim[video]'; even --size)")
    rd.add_argument("--timeline", metavar="PNG", help="timeline plot to write (matplotlib)")
    gs = GifSettings()
    rd.add_argument("--fps", type=float, default=gs.fps,
                    help=f"GIF frames per second ({gs.fps:g})")
    rd.add_argument("--speed", type=float, default=gs.speed,
                    help=f"run seconds per GIF second ({gs.speed:g})")
    size = "x".join(map(str, gs.size))
    rd.add_argument("--size", default=size, help=f"GIF size WxH in pixels, {_SIZES} ({size})")
    rd.add_argument("--from", dest="start", type=float, help="first run time shown [s] "
                    "(default the first arrival)")
    rd.add_argument("--to", dest="end", type=float, help="last run time shown [s] "
                    "(default the last event)")
    rd.add_argument("--max-frames", type=int, default=gs.max_frames,
                    help=f"at most this many frames; a longer span plays faster "
                    f"({gs.max_frames})")
    rd.add_argument("--trail", type=float, default=gs.trail,
                    help=f"seconds of path drawn behind a moving car ({gs.trail:g})")
    rd.add_argument("--skip-quiet", action="store_true", help="GIF and MP4: leave out "
                    "stretches in which no car moves (the frame says how long was skipped)")
    rd.add_argument("--no-legend", dest="legend", action="store_false", help="GIF and MP4: "
                    "no key of the cars' colours in the footer")

    c = sub.add_parser("check", help="verify a result.json independently of the planner")
    c.add_argument("result", metavar="RESULT_JSON", help="a result.json of lotsim run")
    c.add_argument("--max", type=int, default=20, help="violations to list (20)")

    s = sub.add_parser("show", help="draw a scenario's lot to a PNG")
    s.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file")
    s.add_argument("-o", "--output", default="lot.png", help="PNG to write (default lot.png)")
    s.add_argument("--graph", action="store_true", help="draw the lot graph too")
    s.add_argument("--size", default="1200x900", help=f"image size WxH in pixels, {_SIZES} "
                   "(1200x900)")

    b = sub.add_parser("bench", help="run a benchmark suite: scenarios × planners × "
                       "assignments × priorities × arrival rates × seeds")
    b.add_argument("suite", metavar="SUITE", help="suite YAML file (docs/bench.md)")
    b.add_argument("-o", "--output", metavar="OUTDIR",
                   help="directory for runs.csv, summary.md and the plots "
                   "(default runs/bench/<suite name>)")
    where = b.add_mutually_exclusive_group()
    where.add_argument("--jobs", type=int, metavar="N", help="local worker processes "
                       "(default: the number of CPUs; 1 runs in this process)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="run on the Dask distributed "
                       "cluster whose scheduler is at ADDRESS (pip install 'lotsim[dask]')")
    # -- export: a result.json in other tools' formats (docs/export.md) --
    ex = sub.add_parser("export", help="write a result.json as CommonRoad, SUMO or "
                        "OpenSCENARIO files (docs/export.md)")
    ex.add_argument("result", metavar="RESULT_JSON", help="a result.json of lotsim run")
    ex.add_argument("--commonroad", metavar="DIR", help="CommonRoad scenarios and KS "
                    "solutions, one per trip (pip install 'lotsim[commonroad]')")
    ex.add_argument("--sumo", metavar="DIR", help="a SUMO network, a parking area per slot "
                    "and a trip per car, with lot.sumocfg (pip install 'lotsim[sumo]')")
    ex.add_argument("--openscenario", metavar="DIR", help="OpenSCENARIO (a timed trajectory "
                    "per car) on an OpenDRIVE lot with a parking space per slot "
                    "(pip install 'lotsim[openscenario]')")

    for action in sub._choices_actions:  # each command's --help: what it does, its exit codes
        command = sub.choices[action.dest]
        command.description = command.description or action.help[0].upper() + action.help[1:]
        command.epilog = f"exit codes: {_EXITS[action.dest]}"
    p.commands = sub.choices  # for errors in the command's own words
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code."""
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # the command's usage, not lotsim's
        parser.commands[args.command].error(f"unrecognized arguments: {' '.join(extra)}")
    try:
        if args.command == "cars":
            return _cars()
        if args.command == "validate":
            return _validate(args.scenarios, strict=args.strict)
        if args.command == "show":
            return _show(args)
        if args.command == "minslot":
            return _minslot(args)
        if args.command == "maneuver":
            return _maneuver(args)
        if args.command == "run":
            return _run(args)
        if args.command == "check":
            return _check(args)
        if args.command == "render":
            return _render(args)
        if args.command == "bench":
            return _bench(args)
        if args.command == "export":
            return _export(args)
    except ScenarioError as exc:
        print(f"lotsim: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except SettingsError as exc:  # the library's check of an option: name the option
        return _bad(f"{_option(exc.name)}: {exc.message}")
    except KeyboardInterrupt:
        print("lotsim: interrupted; nothing was written", file=sys.stderr)
        return 130
    except BrokenPipeError:  # stdout closed early (| head): stop quietly
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    raise AssertionError(args.command)


_OPTIONS = {"assignment": "--assign", "start": "--from", "end": "--to",
            "max_violations": "--max", "path": "-o"}
"""Setting (:mod:`lotsim.sim.settings`, :mod:`lotsim.api` keyword) → the option that sets it,
where the two are not named alike."""


def _option(name: str) -> str:
    """The option that sets the setting ``name``: ``window`` → ``--window``."""
    return _OPTIONS.get(name, "--" + name.replace("_", "-"))


def _cars() -> int:
    from lotsim.vehicles.catalogue import CATALOGUE

    print(f"{'name':8} {'length':>7} {'width':>6} {'wheelbase':>9} {'max steer':>9} {'R':>6}")
    for v in CATALOGUE.values():
        print(
            f"{v.name:8} {v.length:6.3f}m {v.width:5.3f}m {v.wheelbase:8.3f}m "
            f"{math.degrees(v.max_steer):8.2f}° {v.min_turning_radius:5.2f}m"
        )
    print("R: minimum turning radius of the rear-axle centre, wheelbase / tan(max steer)")
    return EXIT_OK


def _validate(paths: Sequence[str], *, strict: bool) -> int:
    from lotsim.api import validate

    worst = EXIT_OK
    for path in paths:
        try:
            with _Preparing() as bar:
                report = validate(path, progress=bar)
        except ScenarioError as exc:
            print(f"lotsim: {exc}", file=sys.stderr)
            worst = EXIT_BAD_INPUT
            continue
        print(report.summary())
        if strict and not report.complete:
            worst = max(worst, EXIT_INCOMPLETE)
    return worst


def _size(text: str) -> tuple[int, int] | str:
    """``--size WxH`` as ``(w, h)`` pixels, or what is wrong with it (the same limits for
    every picture: :func:`lotsim.scenario.size_problem`)."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        return f"--size: expected WxH in pixels, such as 800x600, found {text!r}"
    problem = size_problem((w, h))
    return f"--size: {problem}" if problem else (w, h)


def _maneuver(args: argparse.Namespace) -> int:
    from lotsim.api import maneuver_case
    from lotsim.errors import InfeasibleManeuver

    size = _size(args.size)
    if isinstance(size, str):
        return _bad(size)
    problem = args.output and _output_problem("-o", args.output, ".png")
    if problem:
        return _bad(problem)
    case = maneuver_case(args.scenario, args.slot, vehicle=args.vehicle, lane=args.lane,
                         style=args.style, margin=args.margin)
    scenario, lot, vehicle, slot, planner = (case.scenario, case.lot, case.vehicle, case.slot,
                                             case.planner)
    try:
        if case.lane is not None:
            lanes = {lane.id: lane for lane in planner.lanes_for(slot)}
            m = planner.plan(vehicle, slot, lanes[case.lane], style=args.style)
        else:
            m = planner.best(vehicle, slot, style=args.style)
    except InfeasibleManeuver as exc:
        print(f"lotsim: {exc}", file=sys.stderr)
        return EXIT_INCOMPLETE
    if args.leave:
        m = m.reversed()
    way, lane_word = ("out of", "to") if args.leave else ("into", "from")
    strokes = ", ".join(f"{'F' if g > 0 else 'R'} {length:.2f} m" for g, length in m.strokes())
    print(f"{vehicle.name} {way} slot {slot.id} {lane_word} lane {m.lane} at station "
          f"{m.station:.2f} m: "
          f"{m.changes} direction change{'s' * (m.changes != 1)}, {m.length:.2f} m, "
          f"{m.duration(vehicle):.1f} s")
    print(f"  strokes: {strokes}")
    stops = m.motion(vehicle).steering_stops
    if stops:
        print(f"  steers standing {len(stops)} time{'s' * (len(stops) != 1)}, "
              f"{sum(d for _, d in stops):.1f} s in all (at cusps, and where a change of "
              f"curvature could not be eased into a clothoid)")
    else:
        print("  steers only while rolling (clothoids)")
    if args.output:
        from lotsim.render.lot_image import save_png
        from lotsim.render.maneuver_image import draw_maneuver

        title = (f"{scenario.name}: {vehicle.name} {way} {slot.id}, "
                 f"{_n(m.changes, 'change')} of direction, {m.length:.1f} m")
        img = draw_maneuver(lot, m, vehicle, parked_vehicle=scenario.parked_vehicle,
                            size=size, title=title)
        try:
            save_png(img, args.output)
        except OSError as exc:
            print(f"lotsim: {args.output}: cannot write: {exc.strerror or exc}",
                  file=sys.stderr)
            return EXIT_BAD_INPUT
        print(f"  wrote {args.output}")
    return EXIT_OK


def _show(args: argparse.Namespace) -> int:
    from lotsim.api import load_scenario, render_lot
    from lotsim.render.lot_image import slot_labels_drawn
    from lotsim.sim.preparation import PreparedLot
    from lotsim.sim.preparation import prepare as prepare_lot
    from lotsim.sim.validation import id_ranges, natural

    size = _size(args.size)
    if isinstance(size, str):
        return _bad(size)
    scenario = load_scenario(args.scenario)
    lot_graph = prepare_lot(scenario, maneuvers=args.graph)  # built once, drawn and listed
    try:
        render_lot(PreparedLot(scenario, lot_graph), args.output, size=size, graph=args.graph)
    except OSError as exc:
        print(f"lotsim: {args.output}: cannot write: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    print(f"wrote {args.output}")
    lot = lot_graph.lot
    print(f"  slots: {id_ranges([s.id for s in lot.slots], most=40)}")
    print(f"  lanes: {', '.join(sorted((ln.id for ln in lot.lanes), key=natural))}")
    drawn = slot_labels_drawn(lot_graph, size, show_graph=args.graph)
    if drawn < len(lot.slots):  # say where they can all be read, if anywhere
        bigger = (f"no --size up to {MAX_SIZE[0]}x{MAX_SIZE[1]} draws them all: they are "
                  "listed above")
        for k in range(1, 40):
            w, h = (round(v * 1.2**k) for v in size)
            if size_problem((w, h)) is not None:
                break
            if slot_labels_drawn(lot_graph, (w, h), show_graph=args.graph) == len(lot.slots):
                bigger = f"--size {w}x{h} draws them all"
                break
        print(f"  slot ids drawn: {drawn} of {len(lot.slots)} at {size[0]}x{size[1]} "
              f"({bigger})")
    return EXIT_OK


def _run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from lotsim.api import prepare, run
    from lotsim.io.result import write_json
    from lotsim.io.scenario_yaml import read_scenario
    from lotsim.sim.limits import Watchdog
    from lotsim.sim.running import collector_tuned, require_traffic

    # an option that would change nothing is refused, not ignored
    if args.window is not None and args.planner != "whca":
        return _bad(f"--window: only --planner whca plans in windows; with --planner "
                    f"{args.planner} it would change nothing")
    if args.horizon is not None and args.priority == "arrival":
        return _bad("--horizon: only booked orders (--priority shortest_first or ga) look "
                    "ahead; with --priority arrival it would change nothing")
    given = {k: v for k, v in (("window", args.window), ("horizon", args.horizon))
             if v is not None}
    settings = RunSettings(planner=args.planner, assignment=args.assign, seed=args.seed,
                           omega=args.omega, priority=args.priority, **given)
    scenario_file = read_scenario(args.scenario)
    scenario, anim = scenario_file.scenario, scenario_file.animation
    require_traffic(scenario)
    out = Path(args.output) if args.output else Path("runs") / scenario.name
    gif_path = None
    if args.gif:
        gif_path = Path(args.gif)
        problem = _output_problem("--gif", args.gif, ".gif", made=out)
        if problem:
            return _bad(problem)
    elif anim is not None and not args.no_gif:
        gif_path = out / anim.gif
    more: dict[str, Path | None] = {}  # the replay and the video, as the GIF
    for key in ("html", "mp4"):
        given = getattr(args, key)
        more[key] = None
        if given:
            problem = _output_problem(f"--{key}", given, f".{key}", made=out)
            if problem:
                return _bad(problem)
            more[key] = Path(given)
        elif anim is not None and getattr(anim, key):
            more[key] = out / getattr(anim, key)
    settings_gif = anim.gif_settings() if anim is not None else GifSettings()
    if more["mp4"] is not None:
        from lotsim.render.video import VideoUnavailable, require_ffmpeg

        w, h = settings_gif.size
        if w % 2 or h % 2:
            return _bad(f"--mp4: an H.264 video needs an even width and height; the "
                        f"animation's size is {w}x{h}")
        try:
            require_ffmpeg()
        except VideoUnavailable as exc:
            return _bad(f"--mp4: {exc}")
    if out.exists() and not out.is_dir():
        return _bad(f"-o: {out} exists and is not a directory")
    tty = sys.stderr.isatty()

    def progress(done: int, total: int) -> None:
        if tty:
            print(f"\rplanned {done}/{total} trips in and out", end="", file=sys.stderr, flush=True)

    budget = _budget(args)
    if isinstance(budget, int):
        return budget
    traffic = scenario.traffic
    where = traffic.stream.where if traffic.stream is not None else traffic.where
    seen: list[bool] = []  # Ctrl-C, even where a finaliser swallowed its KeyboardInterrupt
    if settings.priority == "arrival":
        with _noting_sigint(seen), Watchdog(budget, where, then=progress) as dog:
            with _Preparing() as bar:
                prepared = prepare(scenario, progress=bar)
            with collector_tuned():
                rr = run(prepared, settings, progress=dog.progress)
    else:  # the watchdog cannot project from trips: orders are tried
        bar = _ProgressBar("trying orders")
        try:
            with _noting_sigint(seen), Watchdog(budget, where):
                with _Preparing() as preparing:
                    prepared = prepare(scenario, progress=preparing)
                with collector_tuned():
                    rr = run(prepared, settings,
                             progress=bar if settings.priority == "ga" else None)
        finally:
            bar.close()
        found = rr.ordering
        extra = (f", arrival order {found['fitness_arrival']:.1f} s, shortest first "
                 f"{found['fitness_shortest_first']:.1f} s ({found['evaluations']} orders "
                 "tried)" if args.priority == "ga" else "")
        print(f"priority {args.priority}: total time to park {found['fitness']:.1f} s{extra}; "
              f"choosing the order took {found['order_time']:.1f} s")
    if seen:
        raise KeyboardInterrupt
    if tty:
        print("\r" + " " * 40 + "\r", end="", file=sys.stderr)
    doc = rr.to_dict()
    out.mkdir(parents=True, exist_ok=True)
    # a run's outputs are one set: no GIF of an earlier run is left beside this result
    # (one this run writes is removed first, in case it is interrupted before it is done)
    earlier = [out / (anim.gif if anim is not None else "run.gif"),
               out / ((anim.html if anim is not None else None) or "replay.html"),
               out / ((anim.mp4 if anim is not None else None) or "run.mp4")]
    written = [q for q in (gif_path, more["html"], more["mp4"]) if q is not None]
    removed = [p for p in dict.fromkeys([*earlier, *written]) if p.is_file()]
    for p in removed:
        p.unlink()
    write_json(doc, out / "result.json")
    m = rr.metrics()
    print(f"{scenario.name}: {m['vehicles']} vehicles, planner {args.planner}, "
          f"assignment {args.assign}, seed {rr.seed}")
    print("  " + _counts(m))
    away = (f", {m['rejected']} of them turned away after {scenario.traffic.patience:g} s"
            if m["rejected"] and scenario.traffic.patience > 0 else "")
    parked = m["parked"] + m["departed"]
    park = (f"mean {m['mean_time_to_park']:.1f} s, max {m['max_time_to_park']:.1f} s"
            if parked else "no car parked")
    moved = any(v.moves for v in rr.vehicles)
    end = f"the last move ends at {m['makespan']:.1f} s" if moved else "no car moved"
    print(f"  time to park: {park}; total waiting {m['total_waiting']:.1f} s (queued outside "
          f"or standing on the way{away}); {end}")
    print(f"  planning {m['planning_time']:.2f} s ({_n(m['searches'], 'search', 'searches')}, "
          f"{_n(m['expansions'], 'expansion')}; per vehicle median "
          f"{1000 * m['planning_time_median']:.0f} ms, p95 {1000 * m['planning_time_p95']:.0f} ms)")
    for v in doc["vehicles"]:
        if v["status"] in ("waiting", "rejected"):
            status = "turned away" if v["status"] == "rejected" else "still waiting"
            print(f"  {v['id']}: {status}: {v['reason']}")
    print(f"  wrote {out / 'result.json'}")
    for p in removed:
        if p not in written:
            print(f"  removed {p}: it showed an earlier run")
    html_settings = anim.html_settings() if anim is not None else None
    for path, write, what in (
            (gif_path, lambda p: _write_gif(doc, p, settings_gif), "the GIF"),
            (more["html"], lambda p: _write_html(doc, p, html_settings), "the replay"),
            (more["mp4"], lambda p: _write_mp4(doc, p, settings_gif), "the video")):
        if path is None:
            continue
        try:
            code = write(path)
        except KeyboardInterrupt:
            print(f"lotsim: interrupted; {out / 'result.json'} was written, {what} was not",
                  file=sys.stderr)
            return 130
        if code != EXIT_OK:
            return code
    return EXIT_INCOMPLETE if m["waiting"] else EXIT_OK


def _n(count: int, one: str, many: str | None = None) -> str:
    """``1 search``, ``3 searches``."""
    return f"{count} {one if count == 1 else many or one + 's'}"


def _counts(m: dict) -> str:
    """What became of the run's vehicles: ``6 parked (2 of them left again), 0 still
    waiting, 1 turned away`` (the result's ``parked`` counts those still in their slot,
    ``departed`` those that parked and left)."""
    parked = m["parked"] + m["departed"]
    left = f" ({m['departed']} of them left again)" if m["departed"] else ""
    return (f"{parked} parked{left}, {m['waiting']} still waiting, {m['rejected']} turned "
            f"away")


def _budget(args: argparse.Namespace):
    """The run's :class:`~lotsim.sim.limits.Budget` from ``--memory-limit``/``--time-limit``, or
    the exit code of a bad value."""
    from lotsim.sim.limits import Budget, parse_size

    memory = None
    if args.memory_limit is not None:
        try:
            memory = parse_size(args.memory_limit)
        except ValueError as exc:
            return _bad(f"--memory-limit: {exc}")
        if memory < 2**20:
            return _bad(f"--memory-limit: expected at least 1M, found {args.memory_limit!r}")
    t = args.time_limit
    if not t >= 0:
        return _bad(f"--time-limit: expected a number of seconds ≥ 0, found {t:g}")
    return Budget.default(memory=memory, seconds=None if t in (0, math.inf) else t)




class _ProgressBar:
    """``label [#####-----] done/total, ~N s left`` on a terminal; silent otherwise."""

    def __init__(self, label: str):
        import time

        self.label = label
        self.on = sys.stderr.isatty()
        self.t0 = time.perf_counter()
        self.shown = False

    def __call__(self, done: int, total: int) -> None:
        import time

        if not self.on or total <= 0:
            return
        frac = done / total
        bar = "#" * int(24 * frac) + "-" * (24 - int(24 * frac))
        spent = time.perf_counter() - self.t0
        left = f", ~{spent / frac * (1 - frac):.0f} s left" if 0 < frac < 1 else ""
        print(f"\r{self.label} [{bar}] {done}/{total}{left}   ", end="", file=sys.stderr,
              flush=True)
        self.shown = True

    def close(self) -> None:
        if self.shown:
            print("\r" + " " * 79 + "\r", end="", file=sys.stderr, flush=True)


class _Preparing(_ProgressBar):
    """A lot being prepared, on one terminal line: ``preparing the lot …``, then
    ``planning maneuvers [###---] 412/2080``, then ``building the lot graph …``; silent
    when stderr is not a terminal (and when the lot comes from the cache, quick)."""

    def __init__(self):
        super().__init__("planning maneuvers")
        self.note("preparing the lot …")

    def note(self, text: str) -> None:
        if self.on:
            print(f"\r{text:<79}", end="", file=sys.stderr, flush=True)
            self.shown = True

    def __call__(self, done: int, total: int) -> None:
        super().__call__(done, total)
        if done >= total:
            self.note("building the lot graph …")

    def __enter__(self) -> _Preparing:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _write_gif(doc: dict, path, settings) -> int:
    from lotsim.api import render_gif
    from lotsim.errors import ReplayError
    from lotsim.io.lot_json import LotFormatError

    bar = _ProgressBar("rendering frames")
    seen: list[bool] = []
    hook = sys.unraisablehook
    error, interrupted = None, False
    try:
        with _noting_sigint(seen):
            info = render_gif(doc, path, settings, progress=bar)
    except (KeyboardInterrupt, ReplayError, LotFormatError, ValueError, OSError) as exc:
        interrupted = bool(seen) or isinstance(exc, KeyboardInterrupt)
        if interrupted:
            # Ctrl-C, which Pillow may turn into an error of its own; the half-made writer
            # complains as it is collected (when this block lets go of it): not for the
            # user's eyes
            sys.unraisablehook = lambda _: None
        else:
            error = exc
    finally:
        bar.close()
    if interrupted:
        import gc

        gc.collect()
        sys.unraisablehook = hook
        raise KeyboardInterrupt
    if isinstance(error, (ReplayError, LotFormatError)):
        return _bad(f"cannot draw this result: {error}")
    if isinstance(error, SettingsError):  # the asked span is outside the run
        return _bad(f"{_option(error.name)}: {error.message}")
    if isinstance(error, ValueError):
        return _bad(str(error))
    if isinstance(error, OSError):
        return _bad(f"{path}: cannot write: {error.strerror or error}")
    faster = (f" (sped up from {settings.speed:g}× to fit {info.frames} frames)"
              if info.speed > settings.speed * (1 + 1e-9) else "")
    print(f"  wrote {info.path}: {info.frames} frames, {info.duration:.1f} s at "
          f"{info.speed:.3g}× run time{faster}, {info.start:.1f}–{info.end:.1f} s of the run, "
          f"{info.bytes / 1e6:.1f} MB")
    return EXIT_OK


def _write_html(doc: dict, path, settings) -> int:
    from lotsim.api import render_html
    from lotsim.errors import ReplayError
    from lotsim.io.lot_json import LotFormatError

    try:
        info = render_html(doc, path, settings)
    except (ReplayError, LotFormatError) as exc:
        return _bad(f"cannot draw this result: {exc}")
    except OSError as exc:
        return _bad(f"{path}: cannot write: {exc.strerror or exc}")
    print(f"  wrote {info.path}: replay of {_n(info.vehicles, 'vehicle')}, "
          f"{info.kept} of {info.samples} samples kept (within "
          f"{(settings.tolerance if settings else 0.01) * 100:g} cm), "
          f"{info.bytes / 1e6:.2f} MB")
    return EXIT_OK


def _write_mp4(doc: dict, path, settings) -> int:
    from lotsim.api import render_mp4
    from lotsim.errors import ReplayError
    from lotsim.io.lot_json import LotFormatError
    from lotsim.render.video import VideoUnavailable

    bar = _ProgressBar("encoding video")
    try:
        info = render_mp4(doc, path, settings, progress=bar)
    except (ReplayError, LotFormatError) as exc:
        return _bad(f"cannot draw this result: {exc}")
    except VideoUnavailable as exc:
        return _bad(f"--mp4: {exc}")
    except SettingsError as exc:
        return _bad(f"{_option(exc.name)}: {exc.message}")
    except OSError as exc:
        return _bad(f"{path}: cannot write: {exc.strerror or exc}")
    finally:
        bar.close()
    skipped = f", {info.skipped:.0f} s of quiet run time skipped" if info.skipped else ""
    print(f"  wrote {info.path}: {info.frames} frames, {info.duration:.1f} s at "
          f"{info.speed:.3g}× run time, {info.start:.1f}–{info.end:.1f} s of the run"
          f"{skipped}, {info.bytes / 1e6:.1f} MB")
    return EXIT_OK


@contextlib.contextmanager
def _noting_sigint(seen: list[bool]):
    """Within: Ctrl-C raises KeyboardInterrupt as usual and is also noted in ``seen`` (a
    library may catch the interrupt and raise an error of its own)."""
    import signal

    def on_sigint(signum, frame):
        seen.append(True)
        raise KeyboardInterrupt

    try:
        old = signal.signal(signal.SIGINT, on_sigint)
    except ValueError:  # not the main thread: leave Ctrl-C alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


def _output_problem(opt: str, path: str, suffix: str, made: Path | None = None
                    ) -> str | None:
    """What is wrong with an output file named by option ``opt`` (None if nothing); its
    folder must exist, unless it is ``made`` (the run's output folder, made by the run)."""
    p = Path(path)
    if p.suffix.lower() != suffix:
        return f"{opt}: expected a file name ending in {suffix}, found {path!r}"
    if made is not None and os.path.abspath(p.parent) == os.path.abspath(made):
        return None
    if not p.parent.is_dir():
        return f"{opt}: folder {str(p.parent)!r} does not exist"
    return None


def _render(args: argparse.Namespace) -> int:
    from lotsim.api import load_result
    from lotsim.errors import ResultFormatError

    if not (args.gif or args.html or args.mp4 or args.timeline):
        return _bad("render: nothing to do: give --gif GIF, --html HTML, --mp4 MP4 and/or "
                    "--timeline PNG")
    size = _size(args.size)
    if isinstance(size, str):
        return _bad(size)
    try:
        settings = GifSettings(fps=args.fps, speed=args.speed, size=size, start=args.start,
                               end=args.end, max_frames=args.max_frames, trail=args.trail,
                               skip_quiet=args.skip_quiet, legend=args.legend)
    except SettingsError as exc:
        return _bad(f"{_option(exc.name)}: {exc.message}")
    outputs = (("--gif", args.gif, ".gif"), ("--html", args.html, ".html"),
               ("--mp4", args.mp4, ".mp4"), ("--timeline", args.timeline, ".png"))
    for opt, path, suffix in outputs:
        problem = path and _output_problem(opt, path, suffix)
        if problem:
            return _bad(problem)
    given = [path for _, path, _ in outputs if path]
    if len({os.path.realpath(p) for p in given}) < len(given):
        return _bad("render: two outputs name the same file")
    if args.mp4 and (size[0] % 2 or size[1] % 2):
        return _bad(f"--size: an H.264 video needs an even width and height, found "
                    f"{size[0]}x{size[1]}")
    if args.mp4:
        from lotsim.render.video import VideoUnavailable, require_ffmpeg

        try:
            require_ffmpeg()
        except VideoUnavailable as exc:
            return _bad(f"--mp4: {exc}")
    try:
        doc = load_result(args.result, packed=True)
    except ResultFormatError as exc:
        return _bad(str(exc))
    if not isinstance(doc.get("lot"), dict) or "drawing" not in doc["lot"]:
        return _bad(f"{args.result}: no lot.drawing: written by an older lotsim? run the "
                    "scenario again")
    done = []
    for path, write in ((args.gif, lambda p: _write_gif(doc, p, settings)),
                        (args.html, lambda p: _write_html(doc, p, None)),
                        (args.mp4, lambda p: _write_mp4(doc, p, settings))):
        if not path:
            continue
        try:
            code = write(path)
        except KeyboardInterrupt:
            if done:
                print(f"lotsim: interrupted; {', '.join(done)} written, {path} not",
                      file=sys.stderr)
                return 130
            raise
        if code != EXIT_OK:
            return code
        done.append(path)
    if args.timeline:
        try:
            return _timeline(doc, args.timeline)
        except KeyboardInterrupt:
            if done:
                print(f"lotsim: interrupted; {', '.join(done)} written, the timeline not",
                      file=sys.stderr)
                return 130
            raise
    return EXIT_OK


def _timeline(doc: dict, path: str) -> int:
    from lotsim.render.replay import ReplayError

    try:
        from lotsim.render.plots import plot_timeline

        plot_timeline(doc, path)
    except ImportError:
        return _bad("--timeline needs matplotlib: pip install 'lotsim[plot]'")
    except ReplayError as exc:
        return _bad(f"cannot draw this result: {exc}")
    except OSError as exc:
        return _bad(f"{path}: cannot write: {exc.strerror or exc}")
    print(f"  wrote {path}")
    return EXIT_OK


def _check(args: argparse.Namespace) -> int:
    from lotsim.api import check
    from lotsim.errors import ResultFormatError

    try:
        report = check(args.result, max_violations=args.max)
    except ResultFormatError as exc:
        return _bad(str(exc))
    st = report.stats
    if report.ok:
        print(f"{args.result}: ok ({', '.join(f'{k} {v}' for k, v in st.items())})")
        return EXIT_OK
    print(f"{args.result}: {st.get('violations', len(report.violations))} violation(s)")
    for vi in report.violations:
        print(f"  {vi.rule}: {vi.message}")
    return EXIT_INCOMPLETE


def _bad(message: str) -> int:
    print(f"lotsim: {message}", file=sys.stderr)
    return EXIT_BAD_INPUT


def _minslot(args: argparse.Namespace) -> int:
    import json

    from lotsim.api import car, check_slot_width, minslot
    from lotsim.vehicles.catalogue import CATALOGUE

    widths = list(dict.fromkeys(args.width))  # a width given twice is computed once
    settings = MinSlotSettings(max_changes=args.max_changes, resolution=args.resolution,
                               step_deg=args.step_deg)
    cars = list(CATALOGUE.values()) if args.all_cars else [car(args.car)]
    for width in widths:  # every width checked before the sweep, which takes a while
        for vehicle in cars:
            check_slot_width(vehicle, width, narrow_ok=args.all_cars)
    if args.plot:
        from lotsim.render.plots import MatplotlibMissing, require_matplotlib

        try:  # before the sweep, which takes a while with --all-cars
            require_matplotlib()
        except MatplotlibMissing:
            return _bad("--plot needs matplotlib: pip install 'lotsim[plot]'")
    jobs = [(vehicle, width) for vehicle in cars for width in widths]
    show_progress = sys.stderr.isatty() and len(jobs) > 1
    docs = []
    for i, (vehicle, width) in enumerate(jobs):
        if show_progress:
            print(f"\r{i}/{len(jobs)} … {vehicle.name:8} {width:g} m", end="", file=sys.stderr,
                  flush=True)
        docs.append(minslot(vehicle, width, settings, narrow_ok=args.all_cars).to_dict())
    if show_progress:
        print("\r" + " " * 40 + "\r", end="", file=sys.stderr)
    if args.json:
        print(json.dumps(docs[0] if len(docs) == 1 and not args.all_cars else docs, indent=2))
    else:
        for doc in docs:
            print(f"{doc['car']}: car length {doc['car_length']:.3f} m, slot width "
                  f"{doc['width']:g} m")
            print(f"  {'changes':>7}  {'min length':>10}  {'L / car':>7}")
            for r in doc["rows"]:
                if r["length"] is None:
                    print(f"  {r['changes']:>7}  {'none':>10}  {'':>7}")
                else:
                    print(f"  {r['changes']:>7}  {r['length']:>8.2f} m  {r['ratio']:>7.3f}")
    if args.plot:
        return _plot_minslot(docs, args.plot, stdout_is_json=args.json)
    return EXIT_OK


def _plot_minslot(docs: list, path: str, *, stdout_is_json: bool = False) -> int:
    from lotsim.render.plots import MatplotlibMissing, plot_minslot

    try:
        plot_minslot(docs, path)
    except MatplotlibMissing:
        return _bad("--plot needs matplotlib: pip install 'lotsim[plot]'")
    except OSError as exc:
        return _bad(f"{path}: cannot write: {exc.strerror or exc}")
    # with --json, stdout holds the JSON alone
    print(f"wrote {path}", file=sys.stderr if stdout_is_json else sys.stdout)
    return EXIT_OK


def _bench(args: argparse.Namespace) -> int:
    import os
    from pathlib import Path

    from lotsim import bench

    if args.jobs is not None and not 1 <= args.jobs <= 1024:
        return _bad(f"--jobs: expected 1 to 1024, found {args.jobs}")
    suite = bench.load_suite(args.suite)
    out = Path(args.output) if args.output else Path("runs") / "bench" / suite.name
    if out.exists() and not out.is_dir():
        return _bad(f"-o: {out} exists and is not a directory")
    try:
        from lotsim.render.plots import require_matplotlib

        require_matplotlib()
        plots = True
    except ImportError:
        plots = False
    client = None
    if args.scheduler is not None:
        try:
            client = bench.connect(args.scheduler, timeout=bench.CONNECT_TIMEOUT)
        except (bench.DaskMissing, bench.SchedulerUnreachable) as exc:
            return _bad(str(exc))
        where = f"on the Dask cluster at {args.scheduler}"
    else:
        jobs = min(args.jobs or os.cpu_count() or 1, suite.size)
        where = "in this process" if jobs == 1 else f"on {jobs} local processes"
    print(f"{suite.name}: {suite.size} run{'s' * (suite.size != 1)} {where}", flush=True)
    bar = _ProgressBar("runs")
    try:
        rows = bench.run_suite(suite, jobs=args.jobs, client=client, progress=bar)
    finally:
        bar.close()
        if client is not None:
            client.close()
    try:
        paths = bench.write_outputs(suite, rows, out, where=where, plots=plots)
    except OSError as exc:
        return _bad(f"{out}: cannot write: {exc.strerror or exc}")
    print(bench.table_text(rows))
    failed = [r for r in rows if not r["ok"]]
    for r in failed[:10]:
        print(f"  run {r['run']} failed (seed {r['seed']}): {r['problem']}")
    if len(failed) > 10:
        print(f"  … and {len(failed) - 10} more failed runs (summary.md lists them all)")
    for path in paths:
        print(f"  wrote {path}")
    if not plots:
        print("  no plots: they need matplotlib (pip install 'lotsim[plot]')")
    return EXIT_INCOMPLETE if failed else EXIT_OK


_FORMATS = ("commonroad", "sumo", "openscenario")
"""The formats of ``lotsim export``, each an option and an ``api.export_<name>``."""


def _export(args: argparse.Namespace) -> int:
    """``lotsim export``: each format asked for, through the library (docs/export.md)."""
    import time

    from lotsim import api
    from lotsim.errors import LotsimError

    asked = [(name, getattr(args, name)) for name in _FORMATS if getattr(args, name)]
    if not asked:
        return _bad(f"export: give at least one of "
                    f"{', '.join(f'--{name} DIR' for name in _FORMATS)}")
    try:
        doc = api.load_result(args.result)
        for name, folder in asked:
            start = time.perf_counter()
            info = getattr(api, f"export_{name}")(doc, folder)
            print(f"{name}: wrote {folder} ({info.bytes / 1e6:.1f} MB, "
                  f"{time.perf_counter() - start:.1f} s)")
    except SettingsError:
        raise
    except LotsimError as exc:
        return _bad(str(exc))
    except OSError as exc:
        return _bad(f"{exc.filename or args.result}: {exc.strerror}")
    return EXIT_OK
