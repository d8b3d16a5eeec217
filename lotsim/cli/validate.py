"""``lotsim validate``: check scenario files and summarise each lot."""

from __future__ import annotations

import argparse
import sys

from lotsim import api
from lotsim.cli.output import EXIT_BAD_INPUT, EXIT_INCOMPLETE, EXIT_OK, located
from lotsim.cli.progress import Preparing
from lotsim.errors import ScenarioError

HELP = "check scenario files and summarise each lot"
EXITS = ("0 every file is a valid scenario; 1 with --strict, a free slot or exit cannot be "
         "reached, or a vehicle type cannot park in a slot; 2 a file is not a valid scenario")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scenarios", nargs="+", metavar="SCENARIO",
                        help="scenario YAML files (docs/scenario.md)")
    parser.add_argument("--strict", action="store_true",
                        help="exit 1 when a slot or exit cannot be reached, or a vehicle "
                        "type cannot park in a slot")
    parser.add_argument("--verbose", action="store_true",
                        help="also how the maneuvers were found (problems searched, repeats "
                        "answered from them, whether the lot came from the cache)")


def execute(args: argparse.Namespace) -> int:
    worst = EXIT_OK
    for path in args.scenarios:
        try:
            with Preparing() as bar:
                report = api.validate(path, progress=bar)
        except ScenarioError as exc:
            print(located(exc), file=sys.stderr)
            worst = EXIT_BAD_INPUT
            continue
        print(report.summary(verbose=args.verbose))
        if args.strict and not report.complete:
            worst = max(worst, EXIT_INCOMPLETE)
    return worst
