"""``lotsim bench``: run a benchmark suite (scenarios × planners × assignments × priorities
× arrival rates × seeds) here or on a Dask cluster, and write its table, summary and plots."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from lotsim import api
from lotsim.cli.output import EXIT_INCOMPLETE, EXIT_OK, bad, cannot_write, given
from lotsim.cli.progress import ProgressBar

HELP = ("run a benchmark suite: scenarios × planners × assignments × priorities × arrival "
        "rates × seeds")
EXITS = "0 every run passed its check; 1 some run failed; 2 bad input"
MAX_JOBS = 1024
"""The most local worker processes ``--jobs`` takes."""
FAILED_LISTED = 10
"""Failed runs named on the terminal (summary.md lists them all)."""


def add_arguments(b: argparse.ArgumentParser) -> None:
    b.add_argument("suite", metavar="SUITE", help="suite YAML file (docs/bench.md)")
    b.add_argument("-o", "--output", metavar="OUTDIR",
                   help="directory for runs.csv, hours.csv, summary.md and the plots "
                   "(default runs/bench/<suite name>)")
    where = b.add_mutually_exclusive_group()
    where.add_argument("--jobs", type=int, metavar="N", help="local worker processes "
                       "(default: the number of CPUs; 1 runs in this process)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="run on the Dask distributed "
                       "cluster whose scheduler is at ADDRESS (pip install 'lotsim[dask]')")


def connected(address: str | None):
    """``(client, None)`` of the Dask scheduler at ``address`` (``(None, None)`` without
    one), or ``(None, why not)``."""
    if address is None:
        return None, None
    try:
        return api.connect_scheduler(address), None
    except (api.DaskMissing, api.SchedulerUnreachable) as exc:
        return None, str(exc)


def execute(args: argparse.Namespace) -> int:
    if args.jobs is not None and not 1 <= args.jobs <= MAX_JOBS:
        return bad(f"--jobs: expected 1 to {MAX_JOBS}, found {args.jobs}")
    suite = api.load_suite(args.suite)
    out = Path(args.output) if args.output else Path("runs") / "bench" / suite.name
    with api.OutputSet() as outputs:  # checked before the runs, written whole or not at all
        staged = outputs.folder(out, name=given("-o", out) if args.output else str(out))
        try:
            api.require_matplotlib()
            plots = True
        except ImportError:
            plots = False
        client, problem = connected(args.scheduler)
        if problem is not None:
            return bad(problem)
        if client is not None:
            where = f"on the Dask cluster at {args.scheduler}"
        else:
            jobs = min(args.jobs or os.cpu_count() or 1, suite.size)
            where = "in this process" if jobs == 1 else f"on {jobs} local processes"
        print(f"{suite.name}: {suite.size} run{'s' * (suite.size != 1)} {where}", flush=True)
        bar = ProgressBar("runs")
        bar(0, suite.size)
        try:
            with bar:
                rows = api.run_suite(suite, jobs=args.jobs, client=client, progress=bar)
        finally:
            if client is not None:
                client.close()
        try:
            paths = api.write_outputs(suite, rows, staged, where=where, plots=plots)
        except OSError as exc:
            return cannot_write(out, exc)
        if not plots:  # the outputs are one set: no plot of an earlier suite run stays
            for name in api.PLOTS:
                outputs.remove(out / name)
        outputs.commit()
    print(api.table_text(rows))
    by_hour = api.hours_text(api.hour_rows(rows))
    if by_hour:  # traffic over a few hours: the day hour by hour
        print(by_hour)
    failed = [r for r in rows if not r["ok"]]
    for r in failed[:FAILED_LISTED]:
        print(f"  run {r['run']} failed (seed {r['seed']}): {r['problem']}")
    if len(failed) > FAILED_LISTED:
        print(f"  … and {len(failed) - FAILED_LISTED} more failed runs (summary.md lists "
              "them all)")
    for path in paths:
        print(f"  wrote {out / path.name}")
    if not plots:
        print("  no plots: they need matplotlib (pip install 'lotsim[plot]')")
    return EXIT_INCOMPLETE if failed else EXIT_OK
