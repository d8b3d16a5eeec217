"""Scheduling benchmarks: ``lotsim bench SUITE.yaml``.

A *suite* (``docs/bench.md``) names scenarios and the settings to sweep: planners (CA*,
HCA*, WHCA* with windows), slot-assignment policies, priority orders, arrival rates and
traffic seeds. :func:`load_suite` reads and validates it; :meth:`Suite.specs` expands the
grid into :class:`RunSpec` in a fixed order; :func:`run_spec` plans one grid point and
verifies the result with :func:`lotsim.verify.check_result`, as ``lotsim check`` does;
:func:`run_suite` runs them all, in this process, in a pool of processes or on a Dask
cluster, and returns one row (a dict keyed by :data:`COLUMNS`) per run, in grid order
whatever order they finished in, each with the run's ``hours`` (its
:meth:`~lotsim.sim.results.RunResult.hourly`); :func:`write_outputs` writes ``runs.csv``,
``hours.csv`` (:func:`hour_rows`), ``summary.md`` and the plots; :func:`table_text` and
:func:`hours_text` are what ``lotsim bench`` prints.

Same suite, same rows: every column but :data:`TIMING_COLUMNS` (the last ones), and every
hour, depends only on the suite, not on the machine, the number of workers or the order runs
finish in.

The package: :mod:`~lotsim.bench.suite` (the suite and its grid),
:mod:`~lotsim.bench.runner` (one run, the grid in processes or on Dask),
:mod:`~lotsim.bench.table` (the columns of ``runs.csv`` and ``hours.csv``, the means over
seeds), :mod:`~lotsim.bench.report` (``summary.md``, the terminal tables, the outputs); the plots
are drawn beside the other plots, by :mod:`lotsim.bench.plots` (:func:`bench_figure`,
loaded when first asked for: matplotlib is optional).
"""

from __future__ import annotations

from lotsim.bench.report import (
    PLOTS,
    hours_text,
    summary_markdown,
    table_text,
    write_outputs,
)
from lotsim.bench.runner import (
    CONNECT_TIMEOUT,
    DaskMissing,
    SchedulerUnreachable,
    connect,
    peak_memory_mb,
    prepared,
    run_spec,
    run_suite,
    spec_scenario,
    spec_settings,
)
from lotsim.bench.suite import (
    GA_KEYS,
    MAX_RUNS,
    PlannerVariant,
    RunSpec,
    Suite,
    SuiteScenario,
    load_suite,
    parse_suite,
)
from lotsim.bench.table import (
    COLUMNS,
    GROUP,
    HOUR_FIGURES,
    HOURS_COLUMNS,
    MEANS,
    RUN_KEYS,
    SATURATED,
    SATURATION_VEHICLES,
    TIMING_COLUMNS,
    aggregate,
    aggregate_hours,
    csv_text,
    ga_gains,
    hour_figures,
    hour_rows,
    hours_csv_text,
    planner_label,
    read_csv,
    read_hours_csv,
    saturation,
)

__all__ = [
    "COLUMNS",
    "CONNECT_TIMEOUT",
    "DaskMissing",
    "GA_KEYS",
    "GROUP",
    "HOURS_COLUMNS",
    "HOUR_FIGURES",
    "MAX_RUNS",
    "MEANS",
    "PLOTS",
    "PlannerVariant",
    "RUN_KEYS",
    "RunSpec",
    "SATURATED",
    "SATURATION_VEHICLES",
    "SchedulerUnreachable",
    "Suite",
    "SuiteScenario",
    "TIMING_COLUMNS",
    "aggregate",
    "aggregate_hours",
    "bench_figure",
    "connect",
    "csv_text",
    "ga_gains",
    "hour_figures",
    "hour_rows",
    "hours_csv_text",
    "hours_text",
    "load_suite",
    "parse_suite",
    "peak_memory_mb",
    "planner_label",
    "prepared",
    "read_csv",
    "read_hours_csv",
    "run_spec",
    "run_suite",
    "saturation",
    "spec_scenario",
    "spec_settings",
    "summary_markdown",
    "table_text",
    "write_outputs",
]


def __getattr__(name: str):
    # the plots are loaded when asked for: reading and running a suite needs no picture code
    if name == "bench_figure":
        from lotsim.bench.plots import bench_figure

        return bench_figure
    raise AttributeError(f"module 'lotsim.bench' has no attribute {name!r}")
