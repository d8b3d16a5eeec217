"""``lotsim layout``: lay a lot out on a plot and write the best as a scenario
(``docs/layout.md``)."""

from __future__ import annotations

import argparse

from lotsim import api
from lotsim.cli.bench import connected
from lotsim.cli.output import EXIT_OK, bad, cannot_write, given, name_problem
from lotsim.cli.progress import ProgressBar

HELP = ("lay a lot out on a plot (outline, islands, gates): the layout with the most usable "
        "bays, then the quickest to park in, written as a scenario (docs/layout.md)")
EXITS = "0 a layout written; 2 bad input, or no layout of the plot has a usable bay"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("plot", metavar="PLOT", help="the plot's YAML file (docs/layout.md)")
    parser.add_argument("-o", "--output", metavar="LOT.yaml", required=True,
                        help="the scenario to write; with --keep N the next best go beside "
                        "it as LOT-2.yaml ... LOT-N.yaml")
    parser.add_argument("--keep", type=int, default=1, metavar="N",
                        help="write the N best layouts (1 to 20; default 1)")
    parser.add_argument("--pictures", action="store_true",
                        help="also draw the best lot (LOT.png) and the best candidates side "
                        "by side with their figures (LOT-candidates.png)")
    parser.add_argument("--show", type=int, default=5, metavar="N",
                        help="list the N best candidates side by side (default 5)")
    parser.add_argument("--orientations", type=int, metavar="N",
                        help="try module aisles in at most N directions (along and square to "
                        "the boundary's edges, longest first; default %(default)s)",
                        default=api.LayoutSettings().orientations)
    parser.add_argument("--offsets", type=int, metavar="N",
                        default=api.LayoutSettings().offsets,
                        help="module offsets tried per direction (default %(default)s)")
    parser.add_argument("--prepared", type=int, metavar="N",
                        default=api.LayoutSettings().prepared,
                        help="prepare and run at most N candidates, those whose aisles "
                        "serve the most bays first (default %(default)s)")
    parser.add_argument("--dead-end-cost", type=float, metavar="BAYS",
                        default=api.LayoutSettings().dead_end_cost,
                        help="what 100 m of dead-end aisle costs a layout in the ranking, in "
                        "bays: a loop comes before a layout of up to this many bays more per "
                        "100 m of dead ends (0: rank by bays alone; default %(default)s)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--jobs", type=int, metavar="N",
                       help="worker processes (default: one per core)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="prepare the candidates on the Dask distributed cluster whose "
                       "scheduler is at ADDRESS, as many at once as its workers have threads "
                       "(pip install 'lotsim[dask]')")


def execute(args: argparse.Namespace) -> int:
    problem = name_problem("-o", args.output, ".yaml")
    if problem:
        return bad(problem)
    if not 1 <= args.show <= 100:
        return bad(f"--show: expected 1 to 100, found {args.show}")
    settings = api.LayoutSettings(orientations=args.orientations, offsets=args.offsets,
                                  prepared=args.prepared, workers=args.jobs,
                                  dead_end_cost=args.dead_end_cost)
    with api.OutputSet() as outputs:  # checked before the search, written whole or not at all
        # the next best layouts and the pictures go beside it, into the same staging folder
        staged = outputs.file(args.output, name=given("-o", args.output))
        client, problem = connected(args.scheduler)
        if problem is not None:
            return bad(problem)
        try:
            with ProgressBar("laying out") as bar, api.collector_tuned():
                found = api.layout(args.plot, staged, keep=args.keep, settings=settings,
                                   pictures=args.pictures, progress=bar, client=client)
        except OSError as exc:
            return cannot_write(args.output, exc)
        finally:
            if client is not None:
                client.close()
        outputs.commit()
    plot = found.plot
    print(f"{plot.source}: {plot.name}, {found.best.area:.0f} m²; {found.drawn} candidates "
          f"drawn, {len(found.ranked)} prepared in {found.seconds:.1f} s")
    print(found.table(args.show))
    files = api.layout_files(args.output, found, args.keep, pictures=args.pictures)
    best = found.best
    print(f"wrote {', '.join(str(f) for f in files)}: {best.bays} bays "
          f"({best.bays_per_100m2:.2f} per 100 m², one per {best.area / best.bays:.1f} m²)"
          + (f"; by use: {best.uses_text()}" if best.by_use else ""))
    return EXIT_OK
