"""The ``lotsim`` command line.

Exit codes: 0 ok, 1 incomplete (something could not be planned or reached, with
``--strict``), 2 bad input. Errors go to stderr as ``file:line:col: key: message``;
results go to files; a one-screen summary goes to stdout.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence

from lotsim import __version__
from lotsim.errors import ScenarioError

EXIT_OK, EXIT_INCOMPLETE, EXIT_BAD_INPUT = 0, 1, 2


class _Parser(argparse.ArgumentParser):
    """argparse that exits with 2 and a one-line message, as every other bad input does."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="lotsim", description="Plan many car-like vehicles in a parking lot.")
    p.add_argument("--version", action="version", version=f"lotsim {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    sub.add_parser("cars", help="list the built-in vehicle types")

    v = sub.add_parser("validate", help="check scenario files and summarise each lot")
    v.add_argument("scenarios", nargs="+", metavar="SCENARIO")
    v.add_argument("--strict", action="store_true",
                   help="exit 1 when a slot or exit cannot be reached")

    s = sub.add_parser("show", help="draw a scenario's lot to a PNG")
    s.add_argument("scenario", metavar="SCENARIO")
    s.add_argument("-o", "--output", default="lot.png", help="PNG to write (default lot.png)")
    s.add_argument("--graph", action="store_true", help="draw the lot graph too")
    s.add_argument("--size", default="1200x900", help="image size WxH in pixels")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code."""
    args = _parser().parse_args(argv)
    try:
        if args.command == "cars":
            return _cars()
        if args.command == "validate":
            return _validate(args.scenarios, strict=args.strict)
        if args.command == "show":
            return _show(args)
    except ScenarioError as exc:
        print(f"lotsim: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("lotsim: interrupted; nothing was written", file=sys.stderr)
        return 130
    raise AssertionError(args.command)


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
    from lotsim.io.scenario import load_scenario
    from lotsim.sim import prepare

    worst = EXIT_OK
    for path in paths:
        try:
            scenario = load_scenario(path)
            lg = prepare(scenario)
        except ScenarioError as exc:
            print(f"lotsim: {exc}", file=sys.stderr)
            worst = EXIT_BAD_INPUT
            continue
        reach = lg.reachability()
        print(_summary(path, scenario, lg, reach))
        if strict and not reach.ok:
            worst = max(worst, EXIT_INCOMPLETE)
    return worst


def _summary(path, scenario, lg, reach) -> str:  # noqa: ANN001
    lot = lg.lot
    counts = lot.slot_counts()
    kinds = ", ".join(f"{k} {n}" for k, n in counts.items())
    taken = len(lot.occupied)
    lines = [
        f"{path}: ok — {scenario.name}",
        f"  slots: {len(lot.slots)} ({kinds}); free {len(lot.slots) - taken}, taken {taken}",
        "  vehicle types: "
        + "; ".join(
            f"{v.name} (L {v.length:.2f} m, W {v.width:.2f} m, R {v.min_turning_radius:.2f} m)"
            for v in scenario.vehicle_types
        ),
        f"  aisles: {len(lot.aisles)}, lanes: {len(lot.lanes)}, "
        f"graph: {lg.graph.number_of_nodes()} nodes, {lg.graph.number_of_edges()} edges",
        f"  entrances: {', '.join(lg.entrances) or 'none'}; "
        f"exits: {', '.join(lg.exits) or 'none (vehicles cannot leave)'}",
    ]
    bad = {k: v for k, v in reach.unreachable.items() if v}
    stranded = {k: v for k, v in reach.stranded.items() if v}
    if not bad and not stranded:
        lines.append("  unreachable: none")
    for name, slots in bad.items():
        lines.append(f"  warning: from entrance {name!r}, {len(slots)} free slots cannot be "
                     f"reached: {_ids(slots)}")
    for name, slots in stranded.items():
        lines.append(f"  warning: exit {name!r} cannot be reached from {len(slots)} slots: "
                     f"{_ids(slots)}")
    for note in lg.skipped_turns:
        lines.append(f"  note: {note}")
    return "\n".join(lines)


def _ids(ids: list[str], most: int = 12) -> str:
    head = ", ".join(ids[:most])
    return head + (f", … (+{len(ids) - most})" if len(ids) > most else "")


def _show(args: argparse.Namespace) -> int:
    from lotsim.io.scenario import load_scenario
    from lotsim.render import save_lot_png
    from lotsim.sim import prepare

    try:
        w, h = (int(v) for v in args.size.lower().split("x"))
        if not (64 <= w <= 8000 and 64 <= h <= 8000):
            raise ValueError
    except ValueError:
        print(f"lotsim: --size: expected WxH between 64 and 8000 pixels, found {args.size!r}",
              file=sys.stderr)
        return EXIT_BAD_INPUT
    scenario = load_scenario(args.scenario)
    lg = prepare(scenario)
    try:
        save_lot_png(lg, args.output, size=(w, h), show_graph=args.graph,
                     parked_vehicle=scenario.parked_vehicle, title=scenario.name)
    except OSError as exc:
        print(f"lotsim: {args.output}: cannot write: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    print(f"wrote {args.output}")
    return EXIT_OK
