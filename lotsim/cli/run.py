"""``lotsim run``: plan a scenario's traffic, write OUTDIR/result.json (and the pictures the
scenario or the options ask for), and summarise the run on one screen."""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

from lotsim import api
from lotsim.cli import disturb
from lotsim.cli.output import (
    EXIT_INCOMPLETE,
    EXIT_OK,
    bad,
    given,
    name_problem,
    plural,
)
from lotsim.cli.pictures import save_gif, save_html, save_mp4
from lotsim.cli.progress import Preparing, ProgressBar, noting_sigint

HELP = "plan a scenario's traffic and write OUTDIR/result.json"
RESULT_NAMES = ("result.json", "result.json.gz")
"""The result's file, and its compact form's (``--compact``)."""
BIG_RESULT = 50e6
"""A result.json over this many bytes is told it could be written compact."""
EXITS = ("0 every car was served or rejected; 1 a car is still waiting when the run "
         "ends; 2 bad input, or a memory or time limit stopped the run (nothing written); "
         "130 interrupted")
MIN_MEMORY = 2**20
"""The smallest ``--memory-limit`` taken [bytes]: less is a unit forgotten (``4`` for 4G)."""


def add_arguments(r: argparse.ArgumentParser) -> None:
    r.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file with traffic")
    r.add_argument("-o", "--output", metavar="OUTDIR",
                   help="directory for result.json (default runs/<scenario name>)")
    rs = api.RunSettings()  # defaults and choices: the library's, checked there too
    r.add_argument("--planner", choices=api.PLANNERS, default=rs.planner,
                   help=f"cooperative A* variant (default {rs.planner})")
    r.add_argument("--assignment", "--assign", dest="assign", choices=api.ASSIGNMENTS,
                   default=rs.assignment,
                   help=f"slot choice: straight-line distance, travel time, or travel "
                   f"time plus the delay the car's maneuvers cause the others (default "
                   f"{rs.assignment})")
    r.add_argument("--seed", type=int, help="seed of the traffic stream (default the "
                   "scenario's)")
    r.add_argument("--window", type=float,
                   help=f"with --planner whca: the window [s] ({rs.window:g})")
    r.add_argument("--omega", type=float, default=rs.omega,
                   help=f"expansion limit: expansions allowed per reverse-search node "
                   f"({rs.omega:g})")
    r.add_argument("--priority", choices=api.PRIORITIES,
                   default=rs.priority, help=f"planning order (default {rs.priority}): "
                   "online in arrival order, or booked in advance: shortest static time "
                   "first, or the best order a genetic algorithm finds (total time to park)")
    r.add_argument("--horizon", type=float,
                   help="with --priority shortest_first/ga: how far ahead arrivals are "
                   f"booked [s] ({rs.horizon:g}; inf: all)")
    r.add_argument("--compact", action="store_true",
                   help="write the result compressed, as OUTDIR/result.json.gz (a long "
                        "run's; lotsim check, render and export read it as result.json)")
    r.add_argument("--memory-limit", metavar="SIZE", help="stop, writing nothing, when the "
                   "run holds or is projected to need more memory than this, e.g. 4G "
                   "(default 80%% of the memory available)")
    r.add_argument("--time-limit", type=float, default=7200.0, metavar="SECONDS",
                   help="stop, writing nothing, when planning takes or is projected to take "
                   "longer than this (default 7200; 0: no limit)")
    disturb.add_arguments(r)
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


def execute(args: argparse.Namespace) -> int:
    problem = _pointless(args)
    if problem:
        return bad(problem)
    given_settings = {k: v for k, v in (("window", args.window), ("horizon", args.horizon))
                      if v is not None}
    settings = api.RunSettings(planner=args.planner, assignment=args.assign, seed=args.seed,
                               omega=args.omega, priority=args.priority, **given_settings)
    scenario_file = api.read_scenario(args.scenario)
    scenario, anim = scenario_file.scenario, scenario_file.animation
    api.require_traffic(scenario)
    args.disturbances = disturb.disturbances(args, scenario)
    if isinstance(args.disturbances, str):
        return bad(args.disturbances)
    out = Path(args.output) if args.output else Path("runs") / scenario.name
    pictures = _pictures(args, out, anim)
    if isinstance(pictures, str):
        return bad(pictures)
    budget = _budget(args)
    if isinstance(budget, str):
        return bad(budget)
    name, other = RESULT_NAMES[::-1] if args.compact else RESULT_NAMES
    with api.OutputSet() as outputs:  # every output checked before the planning
        result_json = outputs.file(out / name,
                                   name=given("-o", out) if args.output else str(out))
        staged = {key: (outputs.file(path, name=_named(args, key, path))
                        if path is not None else None) for key, path in pictures.items()}
        drawn = any(p is not None for p in pictures.values())
        spec = args.disturbances  # (None: driven as planned)
        # without pictures or disturbances, each car is written once it is done, as the run
        # goes (its moves then let go): a day's run holds the cars present, not those served
        streamed = not drawn and not (spec is not None and spec.active)
        rr = _plan(args, scenario, settings, budget, write=result_json if streamed else None)
        if not streamed:
            with ProgressBar("writing the result") as bar:
                if drawn:  # the pictures are drawn from the document
                    doc = api.result_dict(rr, progress=bar)
                    api.write_result(doc, result_json)
                else:  # car by car, never the whole document at once
                    api.write_result(rr, result_json, progress=bar)
        m = rr.metrics()
        _summary(args, scenario, rr, m)
        code, said = _draw(doc, pictures, staged, anim) if drawn else (EXIT_OK, [])
        if code != EXIT_OK:
            return code  # nothing is written: the outputs are one set
        written = [p for p in pictures.values() if p is not None]
        # the other form of the result, from an earlier run, would show that run
        removed = _earlier(out, written) + [p for p in [out / other] if p.is_file()]
        for p in removed:
            outputs.remove(p)
        _note_written(outputs, out, written)
        outputs.commit()
    size = result_json_size(out / name)
    print(f"  wrote {out / name}" + (f" ({size / 1e6:.0f} MB: --compact writes it as "
                                     f"{RESULT_NAMES[1]}, several times smaller)"
                                     if not args.compact and size > BIG_RESULT else ""))
    for p in removed:
        print(f"  removed {p}: it showed an earlier run")
    for line in said:
        print(line)
    return EXIT_INCOMPLETE if m["waiting"] else EXIT_OK


def _named(args: argparse.Namespace, key: str, path: Path) -> str:
    """A picture's file as the user named it: the option and its path, or the path the
    scenario's animation section gave it."""
    return given(f"--{key}", path) if getattr(args, key) else str(path)


def _pointless(args: argparse.Namespace) -> str | None:
    """An option that would change nothing is refused, not ignored."""
    if args.window is not None and args.planner != "whca":
        return (f"--window: only --planner whca plans in windows; with --planner "
                f"{args.planner} it would change nothing")
    if args.horizon is not None and args.priority == "arrival":
        return ("--horizon: only booked orders (--priority shortest_first or ga) look ahead; "
                "with --priority arrival it would change nothing")
    return None


def _pictures(args: argparse.Namespace, out: Path, anim) -> dict[str, Path | None] | str:
    """The GIF, replay and video to write (``"gif"``, ``"html"``, ``"mp4"`` → a path, or
    None): as the options say, else as the scenario's animation section says; or what is
    wrong with them."""
    paths: dict[str, Path | None] = {}
    for key in ("gif", "html", "mp4"):
        typed = getattr(args, key)
        paths[key] = None
        if typed:
            problem = name_problem(f"--{key}", typed, f".{key}")
            if problem:
                return problem
            paths[key] = Path(typed)
        elif anim is not None and key == "gif" and not args.no_gif:
            paths[key] = out / anim.gif
        elif anim is not None and key != "gif" and getattr(anim, key):
            paths[key] = out / getattr(anim, key)
    if paths["mp4"] is not None:
        w, h = (anim.gif_settings() if anim is not None else api.GifSettings()).size
        if w % 2 or h % 2:
            return (f"--mp4: an H.264 video needs an even width and height; the animation's "
                    f"size is {w}x{h}")
        try:
            api.require_ffmpeg()
        except api.VideoUnavailable as exc:
            return f"--mp4: {exc}"
    return paths


def _budget(args: argparse.Namespace) -> api.Budget | str:
    """The run's budget from ``--memory-limit``/``--time-limit``, or what is wrong with
    them."""
    memory = None
    if args.memory_limit is not None:
        try:
            memory = api.parse_size(args.memory_limit)
        except ValueError as exc:
            return f"--memory-limit: {exc}"
        if memory < MIN_MEMORY:
            return f"--memory-limit: expected at least 1M, found {args.memory_limit!r}"
    t = args.time_limit
    if not t >= 0:
        return f"--time-limit: expected a number of seconds ≥ 0, found {t:g}"
    return api.Budget.default(memory=memory, seconds=None if t in (0, math.inf) else t)


def _plan(args: argparse.Namespace, scenario, settings, budget, *,
          write: Path | None = None) -> api.RunResult:
    """Prepare the lot and run it within ``budget``, showing progress as it goes; with
    ``write``, the result written there as the run goes."""
    with ProgressBar("trips in and out planned") as progress:
        return _planned(args, scenario, settings, budget, progress, write)


def _planned(args: argparse.Namespace, scenario, settings, budget,
             progress: ProgressBar, write: Path | None) -> api.RunResult:
    traffic = scenario.traffic
    where = traffic.streams[0].where if traffic.streams else traffic.where
    seen: list[bool] = []  # Ctrl-C, even where a finaliser swallowed its KeyboardInterrupt
    if settings.priority == "arrival":
        with noting_sigint(seen), api.Watchdog(budget, where, then=progress) as dog:
            with Preparing() as bar, api.collector_tuned():
                prepared = api.prepare(scenario, progress=bar)
            with api.collector_tuned():
                rr = api.run(prepared, settings, progress=dog.progress,
                             disturbances=args.disturbances or api.Disturbances(),
                             write=write)
    else:  # the watchdog cannot project from trips: orders are tried
        with ProgressBar("trying orders") as bar, noting_sigint(seen), \
                api.Watchdog(budget, where):
            with Preparing() as preparing, api.collector_tuned():
                prepared = api.prepare(scenario, progress=preparing)
            with api.collector_tuned():
                rr = api.run(prepared, settings,
                             progress=bar if settings.priority == "ga" else None,
                             disturbances=args.disturbances or api.Disturbances(),
                             write=write)
        found = rr.ordering
        extra = (f", arrival order {found['fitness_arrival']:.1f} s, shortest first "
                 f"{found['fitness_shortest_first']:.1f} s ({found['evaluations']} orders "
                 "tried)" if args.priority == "ga" else "")
        print(f"priority {args.priority}: total time to park {found['fitness']:.1f} s{extra}; "
              f"choosing the order took {found['order_time']:.1f} s")
    if seen:
        raise KeyboardInterrupt
    return rr


MANIFEST = ".lotsim-run"
"""The file in a run's folder that lists the pictures ``lotsim run`` wrote there, one name
a line: the only files a later run removes."""


def _earlier(out: Path, written: list[Path]) -> list[Path]:
    """A run's outputs are one set: the pictures an earlier run wrote into ``out`` (its
    :data:`MANIFEST` lists them) that this run does not write again, to be removed as this
    run's files are put in place. A file lotsim did not write there is left alone."""
    try:
        names = (out / MANIFEST).read_text(encoding="utf-8").splitlines()
    except OSError:
        names = []
    earlier = [out / n for n in names if n and "/" not in n and n not in (".", "..")]
    again = {os.path.abspath(p) for p in written}
    return [p for p in dict.fromkeys(earlier) if p.is_file() and os.path.abspath(p) not in again]


def _note_written(outputs, out: Path, pictures: list[Path]) -> None:
    """Record, in the set of ``outputs``, the pictures this run writes into its folder
    (:data:`MANIFEST`)."""
    mine = [p.name for p in pictures if p.resolve().parent == out.resolve()]
    if not mine:
        outputs.remove(out / MANIFEST)
        return
    outputs.file(out / MANIFEST).write_text("".join(f"{n}\n" for n in mine), encoding="utf-8")


def _summary(args: argparse.Namespace, scenario, rr, m: dict) -> None:
    """The run on one screen: what became of the vehicles, how long they took, what the
    planning cost (``m``: the run's metrics), and why any car did not park."""
    print(f"{scenario.name}: {m['vehicles']} vehicles, planner {args.planner}, "
          f"assignment {args.assign}, seed {rr.seed}")
    print("  " + _counts(m))
    away = (", and rejected cars' wait for a slot" if m["rejected"] else "")
    park = (f"mean {m['mean_time_to_park']:.1f} s, max {m['max_time_to_park']:.1f} s"
            if m["served"] else "no car parked")
    moved = any(v.end is not None for v in rr.vehicles)
    end = f"the last move ends at {m['makespan']:.1f} s" if moved else "no car moved"
    print(f"  time to park: {park}; total waiting {m['total_waiting']:.1f} s (queued outside "
          f"or standing on the way{away}); {end}")
    print(f"  planning {m['planning_time']:.2f} s "
          f"({plural(m['searches'], 'search', 'searches')}, "
          f"{plural(m['expansions'], 'expansion')}; per vehicle median "
          f"{1000 * m['planning_time_median']:.0f} ms, p95 {1000 * m['planning_time_p95']:.0f} ms)"
          f"; and {m['planning_time_motions']:.2f} s working out the edge motions it drove")
    line = disturb.summary(rr)
    if line:
        print(line)
    hours = rr.hourly()
    if len(hours) >= api.HOURLY_FROM:
        print("  by the hour the cars came (cars, parked; time to park median / p90; "
              "standing per car):")
        for h in hours:
            print(f"    {h['hour']:02d}–{h['hour'] + 1:02d} h: {h['arrivals']:4d} cars, "
                  f"{h['parked']:4d} parked; {h['median_time_to_park']:6.1f} / "
                  f"{h['p90_time_to_park']:6.1f} s; {h['standing_per_car']:6.1f} s"
                  + (f"; {h['rejected']} rejected" if h["rejected"] else ""))
    for v in rr.vehicles:
        if v.status in ("waiting", "rejected"):
            print(f"  {v.id}: {v.status}: {v.reason}")


def _counts(m: dict) -> str:
    """What became of the run's vehicles, in the result's words (``docs/result.md``):
    ``6 served (4 parked at the end, 2 departed), 0 waiting, 1 rejected``."""
    return (f"{m['served']} served ({m['parked']} parked at the end, {m['departed']} "
            f"departed), {m['waiting']} waiting, {m['rejected']} rejected")


def _draw(doc: dict, pictures: dict[str, Path | None], staged: dict[str, Path | None],
          anim) -> tuple[int, list[str]]:
    """Write the run's GIF, replay and video (to their ``staged`` files); the exit code and
    the lines that report them."""
    gif_settings = anim.gif_settings() if anim is not None else api.GifSettings()
    html_settings = anim.html_settings() if anim is not None else None
    said: list[str] = []
    for key, write, settings in (("gif", save_gif, gif_settings),
                                 ("html", save_html, html_settings),
                                 ("mp4", save_mp4, gif_settings)):
        if staged[key] is None:
            continue
        code, line = write(doc, staged[key], settings, shown=pictures[key])
        if code != EXIT_OK:
            return code, said
        said.append(line)
    return EXIT_OK, said


def result_json_size(path: Path) -> int:
    """The size of the result written at ``path`` [bytes] (0 when it cannot be read)."""
    try:
        return path.stat().st_size
    except OSError:
        return 0
