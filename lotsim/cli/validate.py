"""``lotsim validate``: check scenario files and summarise each lot."""

from __future__ import annotations

import argparse
import json
import sys

from lotsim import api
from lotsim.cli.bench import MAX_JOBS, connected
from lotsim.cli.output import (
    EXIT_BAD_INPUT,
    EXIT_INCOMPLETE,
    EXIT_OK,
    bad,
    cannot_write,
    located,
    output_problem,
    problem_lines,
)
from lotsim.cli.progress import Preparing, ProgressBar
from lotsim.errors import OutputError, ScenarioError

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
    parser.add_argument("--unusable", action="store_true",
                        help="also list, per vehicle type, every free slot it cannot use, "
                        "by row, with why")
    parser.add_argument("--json", metavar="FILE.json",
                        help="write, for each file, per vehicle type the free slots it can "
                        "use and those it cannot, by row, with why, as JSON")
    parser.add_argument("--schedule", metavar="FILE.csv",
                        help="write the bay schedule of the (one) scenario: a line per row, "
                        "use and size, with the count, the bays, length and width [m], "
                        "angle [°] and the access aisles, as CSV")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--jobs", type=int, metavar="N",
                       help="validate N files at once on local processes, each lot on one "
                       "core (default: one file after another, each on every core)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="validate the files on the Dask distributed cluster whose "
                       "scheduler is at ADDRESS (pip install 'lotsim[dask]')")


def execute(args: argparse.Namespace) -> int:
    if args.jobs is not None and not 1 <= args.jobs <= MAX_JOBS:
        return bad(f"--jobs: expected 1 to {MAX_JOBS}, found {args.jobs}")
    if args.json is not None:
        problem = output_problem("--json", args.json, ".json")
        if problem is not None:
            return bad(problem)
    if args.schedule is not None:
        problem = output_problem("--schedule", args.schedule, ".csv")
        if problem is not None:
            return bad(problem)
        if len(args.scenarios) != 1 or args.jobs is not None or args.scheduler is not None:
            return bad("--schedule: expected one scenario, validated here (no --jobs or "
                       "--scheduler)")
    if args.jobs is not None or args.scheduler is not None:
        return _many(args)
    worst = EXIT_OK
    answers = []
    for path in args.scenarios:
        try:
            with Preparing() as bar, api.collector_tuned():
                report = api.validate(path, progress=bar)
        except ScenarioError as exc:
            print(located(exc), file=sys.stderr)
            worst = EXIT_BAD_INPUT
            continue
        print(report.summary(verbose=args.verbose))
        answers.append(report.as_dict())
        if args.unusable:
            print(api.unusable_text(answers[-1]))
        if args.strict and not report.complete:
            worst = max(worst, EXIT_INCOMPLETE)
        if args.schedule is not None:
            written = _schedule(args.schedule, report.schedule_csv())
            if written:
                return written
    return _written(args.json, answers) or worst


def _schedule(path: str, text: str) -> int:
    """Write the bay schedule whole or not at all: 0, or the exit code of bad input."""
    try:
        with api.OutputSet() as outputs:
            staged = outputs.file(path, name=f"--schedule {path}")
            staged.write_text(text, encoding="utf-8")
            outputs.commit()
    except OutputError as exc:
        return bad(str(exc))
    except OSError as exc:
        return cannot_write(path, exc)
    print(f"wrote {path}")
    return EXIT_OK


def _written(path: str | None, answers: list[dict]) -> int:
    """Write ``--json``'s file (nothing without it): 0, or the exit code of bad input when
    it cannot be written."""
    if path is None:
        return EXIT_OK
    try:
        with open(path, "w", encoding="utf-8") as fh:
            json.dump(answers, fh, indent=1, ensure_ascii=False)
            fh.write("\n")
    except OSError as exc:
        return cannot_write(path, exc)
    print(f"wrote {path}")
    return EXIT_OK


def _many(args: argparse.Namespace) -> int:
    """The files validated several at once (``--jobs``, ``--scheduler``), printed in their
    order as they would be one after another."""
    client, problem = connected(args.scheduler)
    if problem is not None:
        return bad(problem)
    try:
        with ProgressBar("lots validated") as bar:
            found = api.validate_files(args.scenarios, verbose=args.verbose, jobs=args.jobs,
                                       client=client, progress=bar)
    finally:
        if client is not None:
            client.close()
    worst = EXIT_OK
    answers = []
    for f in found:
        if not f.valid:
            print(problem_lines(f.problems), file=sys.stderr)
            worst = EXIT_BAD_INPUT
            continue
        print(f.summary)
        answers.append(f.answer)
        if args.unusable:
            print(api.unusable_text(f.answer))
        if args.strict and not f.complete:
            worst = max(worst, EXIT_INCOMPLETE)
    return _written(args.json, answers) or worst
