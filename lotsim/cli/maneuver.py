"""``lotsim maneuver``: plan one slot's parking maneuver, describe it and draw it."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lotsim import api
from lotsim.cli.output import (
    EXIT_INCOMPLETE,
    EXIT_OK,
    bad,
    cannot_write,
    into_folder,
    output_problem,
    picture_size,
    plural,
    sizes,
)
from lotsim.errors import InfeasibleManeuver

HELP = "plan one slot's parking maneuver and draw it"
EXITS = "0 planned; 1 the vehicle type cannot park there; 2 bad input"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file")
    parser.add_argument("--slot", required=True, help="slot id")
    parser.add_argument("--vehicle", "--car", dest="vehicle", metavar="TYPE",
                        help="vehicle type of the scenario (default its first)")
    parser.add_argument("--lane", help="lane id to start from (default the best)")
    parser.add_argument("--style", choices=api.STYLES, default=api.STYLES[0],
                        help="nose-in (forward), backed in (reverse) or the better (any)")
    parser.add_argument("--leave", action="store_true",
                        help="the way out instead of the way in")
    parser.add_argument("--margin", type=float, default=None,
                        help=f"safety margin [m] (default the scenario's maneuvers.margin, "
                             f"{api.MARGIN:g} unless it says)")
    parser.add_argument("-o", "--output", help="PNG to write; a folder gets "
                        "SCENARIO-SLOT.png in it")
    parser.add_argument("--size", default="900x700",
                        help=f"image size WxH in pixels, {sizes()} (900x700)")


def execute(args: argparse.Namespace) -> int:
    size = picture_size(args.size)
    if isinstance(size, str):
        return bad(size)
    if args.output:
        args.output = into_folder(args.output, f"{Path(args.scenario).stem}-{args.slot}.png")
    problem = args.output and output_problem("-o", args.output, ".png")
    if problem:
        return bad(problem)
    try:
        case = api.maneuver_case(args.scenario, args.slot, vehicle=args.vehicle,
                                 lane=args.lane, style=args.style, margin=args.margin)
        m = case.plan(leave=args.leave)
    except InfeasibleManeuver as exc:
        print(f"lotsim: {exc}", file=sys.stderr)
        return EXIT_INCOMPLETE
    vehicle = case.vehicle
    way, lane_word = ("out of", "to") if args.leave else ("into", "from")
    strokes = ", ".join(f"{'F' if g > 0 else 'R'} {length:.2f} m" for g, length in m.strokes())
    print(f"{vehicle.name} {way} slot {case.slot.id} {lane_word} lane {m.lane} at station "
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
        title = (f"{case.scenario.name}: {vehicle.name} {way} {case.slot.id}, "
                 f"{plural(m.changes, 'change')} of direction, {m.length:.1f} m")
        try:
            api.render_maneuver(case, m, args.output, size=size, title=title)
        except OSError as exc:
            return cannot_write(args.output, exc)
        print(f"  wrote {args.output}")
    return EXIT_OK
