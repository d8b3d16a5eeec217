"""``lotsim minslot``: the shortest parallel slot for each number of direction changes, as
a table, JSON or a plot."""

from __future__ import annotations

import argparse
import json
import sys

from lotsim import api
from lotsim.cli.output import EXIT_OK, bad, cannot_write
from lotsim.cli.progress import ProgressBar

HELP = "shortest parallel slot for each number of direction changes"
EXITS = "0 the table was computed; 2 bad input"
NO_MATPLOTLIB = "--plot needs matplotlib: pip install 'lotsim[plot]'"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    which = parser.add_mutually_exclusive_group(required=True)
    which.add_argument("--vehicle", "--car", dest="car", metavar="TYPE",
                       help="a catalogue name (see `lotsim cars`) or a vehicle YAML file")
    which.add_argument("--all-vehicles", "--all-cars", dest="all_cars", action="store_true",
                       help="every catalogue vehicle")
    parser.add_argument("--width", type=float, nargs="+", required=True, metavar="WIDTH",
                        help="slot width [m]; several give one table (and curve) per width")
    ms = api.MinSlotSettings()
    parser.add_argument("--max-changes", type=int, default=ms.max_changes,
                        help="largest number of direction changes to report (default "
                        f"{ms.max_changes})")
    parser.add_argument("--resolution", type=float, default=ms.resolution,
                        help=f"length step [m] ({ms.resolution:g})")
    parser.add_argument("--step-deg", type=float, default=ms.step_deg,
                        help=f"start-heading sweep step [deg] ({ms.step_deg:g})")
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument("--plot", metavar="PNG",
                        help="plot length against changes (matplotlib)")


def execute(args: argparse.Namespace) -> int:
    widths = list(dict.fromkeys(args.width))  # a width given twice is computed once
    settings = api.MinSlotSettings(max_changes=args.max_changes, resolution=args.resolution,
                                   step_deg=args.step_deg)
    cars = list(api.CATALOGUE.values()) if args.all_cars else [api.car(args.car)]
    for width in widths:  # every width checked before the sweep, which takes a while
        for vehicle in cars:
            api.check_slot_width(vehicle, width, narrow_ok=args.all_cars)
    if args.plot:
        try:  # before the sweep, which takes a while with --all-vehicles
            api.require_matplotlib()
        except api.MatplotlibMissing:
            return bad(NO_MATPLOTLIB)
    docs = _tables(cars, widths, settings, narrow_ok=args.all_cars)
    if args.json:
        print(json.dumps(docs[0] if len(docs) == 1 and not args.all_cars else docs, indent=2))
    else:
        for doc in docs:
            _print_table(doc)
    if args.plot:
        return _plot(docs, args.plot, stdout_is_json=args.json)
    return EXIT_OK


def _tables(cars: list, widths: list[float], settings, *, narrow_ok: bool) -> list[dict]:
    """Each car's table for each width, as :meth:`MinSlotTable.to_dict`, showing which one
    is being computed."""
    jobs = [(vehicle, width) for vehicle in cars for width in widths]
    docs = []
    with ProgressBar("minimum-slot tables") as bar:
        for i, (vehicle, width) in enumerate(jobs):
            if len(jobs) > 1:
                bar(i, len(jobs), f"{vehicle.name} {width:g} m")
            docs.append(api.minslot(vehicle, width, settings, narrow_ok=narrow_ok).to_dict())
    return docs


def _print_table(doc: dict) -> None:
    print(f"{doc['car']}: car length {doc['car_length']:.3f} m, slot width {doc['width']:g} m")
    print(f"  {'changes':>7}  {'min length':>10}  {'L / car':>7}")
    for r in doc["rows"]:
        if r["length"] is None:
            print(f"  {r['changes']:>7}  {'none':>10}  {'':>7}")
        else:
            print(f"  {r['changes']:>7}  {r['length']:>8.2f} m  {r['ratio']:>7.3f}")


def _plot(docs: list, path: str, *, stdout_is_json: bool = False) -> int:
    try:
        api.plot_minslot(docs, path)
    except api.MatplotlibMissing:
        return bad(NO_MATPLOTLIB)
    except OSError as exc:
        return cannot_write(path, exc)
    # with --json, stdout holds the JSON alone
    print(f"wrote {path}", file=sys.stderr if stdout_is_json else sys.stdout)
    return EXIT_OK
