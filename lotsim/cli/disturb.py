"""``lotsim run``'s options for disturbances: late starts, slow cars and stalls, over or
instead of the scenario's ``disturbances`` section (``docs/scenario.md``)."""

from __future__ import annotations

import argparse
import dataclasses

from lotsim import api


def add_arguments(r: argparse.ArgumentParser) -> None:
    g = r.add_argument_group("disturbances (drive the plan through them; over the "
                             "scenario's 'disturbances' section)")
    g.add_argument("--late", metavar="P,MAX", help="each start from a standstill comes late "
                   "with probability P, by up to MAX seconds, e.g. 0.1,5")
    g.add_argument("--speed", metavar="LO[,HI]", help="each car drives a factor LO to HI "
                   "(at most 1) as fast as planned, e.g. 0.8,1")
    g.add_argument("--stalls", metavar="RATE[,LO,HI]", help="RATE stalls an hour over the "
                   "lot, each LO to HI seconds long (default 30,120), e.g. 10,60,60")
    g.add_argument("--repair-after", metavar="SECONDS", help="plan again a car held up on "
                   "the lanes this long past its plan, when a sooner way is found (default "
                   "30; 'never': it waits its turn)")
    g.add_argument("--disturbance-seed", type=int, metavar="N",
                   help="seed of what is drawn (default the run's)")
    g.add_argument("--no-disturbances", action="store_true",
                   help="drive the plan as planned, whatever the scenario says")


def _numbers(option: str, text: str, counts: tuple[int, ...]) -> list[float] | str:
    try:
        xs = [float(x) for x in text.split(",")]
    except ValueError:
        xs = []
    if len(xs) not in counts:
        shapes = " or ".join(str(n) for n in counts)
        return f"{option}: expected {shapes} numbers separated by commas, found {text!r}"
    return xs


def disturbances(args: argparse.Namespace, scenario) -> api.Disturbances | None | str:
    """The disturbances the run is driven through (None: as planned), or what is wrong
    with the options."""
    given = [args.late, args.speed, args.stalls, args.repair_after, args.disturbance_seed]
    if args.no_disturbances:
        if any(x is not None for x in given):
            return ("--no-disturbances: drives the plan as planned; it cannot go with "
                    "--late, --speed, --stalls, --repair-after or --disturbance-seed")
        return None
    spec = scenario.disturbances or api.Disturbances()
    kw: dict = {}
    if args.late is not None:
        xs = _numbers("--late", args.late, (2,))
        if isinstance(xs, str):
            return xs
        kw["late_probability"], kw["late_max"] = xs
    if args.speed is not None:
        xs = _numbers("--speed", args.speed, (1, 2))
        if isinstance(xs, str):
            return xs
        kw["speed"] = (xs[0], xs[-1])
    if args.stalls is not None:
        xs = _numbers("--stalls", args.stalls, (1, 3))
        if isinstance(xs, str):
            return xs
        kw["stall_rate"] = xs[0]
        if len(xs) == 3:
            kw["stall_duration"] = (xs[1], xs[2])
    if args.repair_after is not None:
        text = args.repair_after.strip()
        try:
            kw["repair_after"] = None if text == "never" else float(text)
        except ValueError:
            return f"--repair-after: expected seconds or never, found {text!r}"
    if args.disturbance_seed is not None:
        kw["seed"] = args.disturbance_seed
    try:
        spec = dataclasses.replace(spec, **kw)
    except api.SettingsError as err:
        option = {"late_probability": "--late", "late_max": "--late", "speed": "--speed",
                  "stall_rate": "--stalls", "stall_duration": "--stalls",
                  "repair_after": "--repair-after",
                  "seed": "--disturbance-seed"}.get(err.name, err.name)
        return f"{option}: {err.message}"
    return spec if spec.active else None


def summary(rr) -> str | None:
    """One line on what the disturbances did, for the run's summary (None without any)."""
    rec = rr.execution
    if rec is None:
        return None
    parts = [f"{len(rec.late)} late starts", f"{len(rec.stalls)} stalls"]
    if rec.repaired:
        parts.append(f"{rec.repaired} cars held up planned again")
    if rec.moved:
        parts.append(f"{rec.moved} taken at the car's next stop")
    if rec.slowed:
        parts.append(f"{rec.slowed} runs slowed to a slower car's pace")
    speeds = list(rec.speed.values())
    if speeds and min(speeds) < 1:
        parts.append(f"speed factors {min(speeds):.2f}–{max(speeds):.2f}")
    planned = rec.planned.get("median_time_to_park", 0.0)
    now = rr.trip_figures()["median_time_to_park"]
    return (f"  disturbances: {', '.join(parts)}; cars stood {rec.waited:.1f} s more in "
            f"all; median time to park {now:.1f} s (planned {planned:.1f} s)")
