"""``lotsim check``: verify a result.json independently of the planner."""

from __future__ import annotations

import argparse

from lotsim import api
from lotsim.cli.output import EXIT_INCOMPLETE, EXIT_OK, bad
from lotsim.errors import ResultFormatError

HELP = "verify a result.json independently of the planner"
EXITS = ("0 the result holds every rule; 1 violations (the first are listed); 2 the file is "
         "not a lotsim result")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("result", metavar="RESULT_JSON", help="a result.json of lotsim run")
    parser.add_argument("--max", type=int, default=20, help="violations to list (20)")
    parser.add_argument("--verbose", action="store_true",
                        help="also the checker's own counts (samples, footprints, tests, "
                        "seconds)")


def execute(args: argparse.Namespace) -> int:
    try:
        report = api.check(args.result, max_violations=args.max)
    except ResultFormatError as exc:
        return bad(str(exc))
    st = report.stats
    cars = st.get("vehicles_checked", st.get("vehicles", 0))
    if report.ok:
        print(f"{args.result}: ok — {cars} vehicles checked, every rule holds "
              f"(docs/result.md)")
    else:
        n = st.get("violations", len(report.violations))
        print(f"{args.result}: {n} violation{'s' if n != 1 else ''} of {cars} vehicles")
        for vi in report.violations:
            print(f"  {vi.rule}: {vi.message}")
    if args.verbose:
        print("  checker: " + ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in st.items()))
    return EXIT_OK if report.ok else EXIT_INCOMPLETE
