"""``lotsim show``: draw a scenario's lot to a PNG, and list its slots and lanes; with
``--routes``, its service routes over it (each route's line as ``lotsim validate`` says
it)."""

from __future__ import annotations

import argparse
from pathlib import Path

from lotsim import api
from lotsim.cli.output import (
    EXIT_OK,
    bad,
    cannot_write,
    given,
    into_folder,
    name_problem,
    picture_size,
    sizes,
)

HELP = "draw a scenario's lot to a PNG"
EXITS = "0 written; 2 bad input"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file")
    parser.add_argument("-o", "--output", default="lot.png",
                        help="PNG to write (default lot.png); a folder gets SCENARIO.png in it")
    parser.add_argument("--graph", action="store_true", help="draw the lot graph too")
    parser.add_argument("--routes", action="store_true",
                        help="draw the scenario's service routes too: each swept envelope, "
                        "path and tightest clearance, and whether it passes")
    parser.add_argument("--size", default="1200x900",
                        help=f"image size WxH in pixels, {sizes()} (1200x900)")


def execute(args: argparse.Namespace) -> int:
    size = picture_size(args.size)
    if isinstance(size, str):
        return bad(size)
    args.output = into_folder(args.output, f"{Path(args.scenario).stem}.png")
    problem = name_problem("-o", args.output, ".png")
    if problem:
        return bad(problem)
    scenario = api.load_scenario(args.scenario)
    if args.routes and not scenario.routes:
        return bad(f"{args.scenario}: --routes: the scenario has no routes to draw (a "
                   "'routes' section: docs/scenario.md)")
    reports = ()
    with api.OutputSet() as outputs:  # checked before the lot is built
        staged = outputs.file(args.output, name=given("-o", args.output))
        # built once, drawn and listed
        prepared = api.prepare_for_drawing(scenario, graph=args.graph)
        try:
            if args.routes:
                reports = api.plan_routes(prepared.lot, scenario.routes)
                api.render_routes(prepared, staged, size=size, graph=args.graph,
                                  reports=reports)
            else:
                api.render_lot(prepared, staged, size=size, graph=args.graph)
        except OSError as exc:
            return cannot_write(args.output, exc)
        outputs.commit()
    print(f"wrote {args.output}")
    lot = prepared.lot
    print(f"  slots: {api.id_ranges([s.id for s in lot.slots], most=40)}")
    print(f"  lanes: {', '.join(sorted((ln.id for ln in lot.lanes), key=api.natural))}")
    for r in reports:
        print(f"  {r.line()}")
    drawn = api.slot_labels_drawn(prepared.lot_graph, size, show_graph=args.graph)
    if drawn < len(lot.slots):  # say where they can all be read, if anywhere
        print(f"  slot ids drawn: {drawn} of {len(lot.slots)} at {size[0]}x{size[1]} "
              f"({_bigger(prepared, size, graph=args.graph)})")
    return EXIT_OK


def _bigger(prepared, size: tuple[int, int], *, graph: bool) -> str:
    """The advice on a ``--size`` that draws every slot id, up to the largest allowed."""
    count = len(prepared.lot.slots)
    for k in range(1, 40):
        w, h = (round(v * 1.2**k) for v in size)
        if api.size_problem((w, h)) is not None:
            break
        if api.slot_labels_drawn(prepared.lot_graph, (w, h), show_graph=graph) == count:
            return f"--size {w}x{h} draws them all"
    return (f"no --size up to {api.MAX_SIZE[0]}x{api.MAX_SIZE[1]} draws them all: they are "
            "listed above")
