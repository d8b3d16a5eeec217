"""Scheduling benchmarks: ``lotsim bench SUITE.yaml``.

A *suite* (``docs/bench.md``) names scenarios and the settings to sweep: planners (CA*,
HCA*, WHCA* with windows), slot-assignment policies, priority orders, arrival rates and
traffic seeds. :func:`load_suite` reads and validates it; :meth:`Suite.specs` expands the
grid into :class:`RunSpec` in a fixed order; :func:`run_spec` plans one grid point and
verifies the result with :func:`lotsim.check.check_result`, as ``lotsim check`` does;
:func:`run_suite` runs them all, in this process, in a pool of processes or on a Dask
cluster, and returns one row (a dict keyed by :data:`COLUMNS`) per run, in grid order
whatever order they finished in; :func:`write_outputs` writes ``runs.csv``, ``summary.md``
and the plots.

Same suite, same rows: every column but :data:`TIMING_COLUMNS` (the last ones) depends only
on the suite, not on the machine, the number of workers or the order runs finish in.
"""

from __future__ import annotations

import csv
import dataclasses
import hashlib
import io
import os
import resource
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from lotsim import __version__
from lotsim.atomic import atomic_write
from lotsim.check import check_result
from lotsim.errors import LotsimError, ScenarioError, SettingsError
from lotsim.io.kinds import refuse_other_kind, top_level
from lotsim.io.result import result_dict
from lotsim.io.scenario import MAX_ITEMS, load_scenario, name_from_file, parse_scenario
from lotsim.io.yamlnodes import YNode, parse_text, read_yaml
from lotsim.priority import plan_run
from lotsim.settings import (
    ASSIGNMENTS,
    BOOKING_HORIZON,
    PLANNERS,
    PRIORITIES,
    GASettings,
    RunSettings,
)
from lotsim.sim import RunResult, prepare

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from lotsim.lot.graph import LotGraph
    from lotsim.scenario import Scenario

GA_KEYS = ("population", "generations", "seed")
MAX_RUNS = 100_000
"""Largest grid a suite may expand to."""
CONNECT_TIMEOUT = 5.0
"""How long to try reaching a Dask scheduler before giving up [s]."""
SATURATED = 0.9
"""A load is saturated when the throughput is below this fraction of the arrival rate."""
SATURATION_VEHICLES = 20
"""Fewest vehicles per run for :func:`saturation` to judge: rates estimated from a handful
of arrivals are noise."""


class DaskMissing(LotsimError):
    """``--scheduler`` was asked for but ``distributed`` is not installed."""


class SchedulerUnreachable(LotsimError):
    """The Dask scheduler at the given address did not answer."""


# -- the suite --------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class PlannerVariant:
    """A planner and, for WHCA*, its window [s] (None for CA* and HCA*)."""

    planner: str
    window: float | None = None

    @property
    def label(self) -> str:
        """How rows and tables name it.

        >>> PlannerVariant("hca").label, PlannerVariant("whca", 10.0).label
        ('hca', 'whca-10')
        """
        return self.planner if self.window is None else f"{self.planner}-{self.window:g}"


@dataclass(frozen=True, slots=True)
class SuiteScenario:
    """A scenario of the suite: its name, the file as given, and its YAML text (so a
    worker on another machine needs no file system)."""

    name: str
    file: str
    text: str = field(repr=False)
    stream_rate: float | None
    """The scenario's own stream rate [vehicles/h], None without a stream."""
    stream_count: int | None


@dataclass(frozen=True, slots=True)
class RunSpec:
    """One grid point: what :func:`run_spec` plans.

    ``rate_per_hour`` and ``count`` replace the scenario's stream rate and count when not
    None; ``ga`` holds the suite's GA settings as ``(key, value)`` pairs.
    """

    index: int
    scenario: SuiteScenario
    planner: PlannerVariant
    assignment: str
    priority: str
    rate_per_hour: float | None
    count: int | None
    seed: int
    ga: tuple[tuple[str, int], ...] = ()
    horizon: float = BOOKING_HORIZON


@dataclass(frozen=True, slots=True)
class Suite:
    """A validated suite file (see ``docs/bench.md``)."""

    name: str
    description: str
    source: str
    scenarios: tuple[SuiteScenario, ...]
    planners: tuple[PlannerVariant, ...]
    assignments: tuple[str, ...]
    priorities: tuple[str, ...]
    rates_per_hour: tuple[float, ...] | None
    count: int | None
    seeds: tuple[int, ...]
    ga: tuple[tuple[str, int], ...] = ()
    horizon: float = BOOKING_HORIZON
    """How far ahead booked priorities (shortest_first, ga) know the arrivals [s]."""

    @property
    def size(self) -> int:
        """Number of runs in the grid."""
        rates = len(self.rates_per_hour) if self.rates_per_hour else 1
        return (len(self.scenarios) * len(self.planners) * len(self.assignments)
                * len(self.priorities) * rates * len(self.seeds))

    def specs(self) -> list[RunSpec]:
        """The grid in its fixed order: scenario, planner, assignment, priority, rate,
        seed (the last varies fastest)."""
        rates = self.rates_per_hour or (None,)
        out = []
        for sc in self.scenarios:
            for pv in self.planners:
                for asg in self.assignments:
                    for prio in self.priorities:
                        for rate in rates:
                            for seed in self.seeds:
                                out.append(RunSpec(len(out), sc, pv, asg, prio, rate,
                                                   self.count, seed,
                                                   self.ga if prio == "ga" else (),
                                                   self.horizon))
        return out


def load_suite(path: str | os.PathLike) -> Suite:
    """Read and validate a suite file; scenario paths are relative to it.

    Raises
    ------
    ScenarioError
        On the first problem, as ``file:line:col: key: message`` (problems inside a
        scenario file are located in that file).
    """
    return parse_suite(read_yaml(path, expect="suite"))


def parse_suite(root: YNode) -> Suite:
    """Validate a composed suite document (:func:`load_suite`)."""
    refuse_other_kind(top_level(root), "suite", root.file)
    f = root.fields(required=["scenarios", "planners", "seeds"],
                    optional=["name", "description", "assignments", "priorities",
                              "rates_per_hour", "count", "ga", "horizon"])
    base = Path(root.file).parent
    if "name" in f:
        name = f["name"].file_name(purpose="it names the output folder runs/bench/NAME")
    else:
        name = name_from_file(root.file)
    rates = None
    if "rates_per_hour" in f:
        rates = tuple(_unique(f["rates_per_hour"], lambda n: n.number(positive=True, max=1e6),
                              "rate"))
    count = f["count"].integer(min=1, max=MAX_ITEMS) if "count" in f else None
    scenarios = []
    for n in _nonempty(f["scenarios"], "scenario"):
        sc = _suite_scenario(n, base, override=next((k for k in ("rates_per_hour", "count")
                                                     if k in f), None))
        if any(s.name == sc.name for s in scenarios):
            raise n.error(f"two scenarios are named {sc.name!r}: rows could not tell them "
                          "apart")
        scenarios.append(sc)
    planners = _planners(f["planners"])
    assignments = (tuple(_unique(f["assignments"], lambda n: n.string(choices=ASSIGNMENTS),
                                 "assignment"))
                   if "assignments" in f else ("shortest",))
    priorities = ("arrival",)
    if "priorities" in f:
        priorities = tuple(_unique(f["priorities"], lambda n: n.string(choices=PRIORITIES),
                                   "priority"))
    ga: tuple[tuple[str, int], ...] = ()
    if "ga" in f:
        if "ga" not in priorities:
            raise f["ga"].error("GA settings are given but 'priorities' has no 'ga'")
        g = f["ga"].fields(optional=GA_KEYS)
        ga = tuple((k, _checked(n, GASettings, k, n.integer())) for k, n in g.items())
        _checked(f["ga"], GASettings, "", None, **dict(ga))
    seeds = tuple(_unique(f["seeds"], lambda n: _checked(n, RunSettings, "seed", n.integer()),
                          "seed"))
    horizon = BOOKING_HORIZON
    if "horizon" in f:
        if not set(priorities) & {"shortest_first", "ga"}:
            raise f["horizon"].error("a booking horizon is given but 'priorities' has no "
                                     "booked order (shortest_first, ga)")
        horizon = _checked(f["horizon"], RunSettings, "horizon", f["horizon"].number())
    suite = Suite(
        name=name,
        description=f["description"].string(max_len=2000) if "description" in f else "",
        source=root.file,
        scenarios=tuple(scenarios),
        planners=planners,
        assignments=assignments,
        priorities=priorities,
        rates_per_hour=rates,
        count=count,
        seeds=seeds,
        ga=ga,
        horizon=horizon,
    )
    if suite.size > MAX_RUNS:
        raise root.error(f"the grid has {suite.size} runs; at most {MAX_RUNS}")
    return suite


def _checked(node: YNode, cls: type, name: str, value: Any, **more: Any) -> Any:
    """``value`` of setting ``name`` (with ``more``), checked as ``cls`` checks it on
    construction (:mod:`lotsim.settings`): the same message as from Python or the CLI,
    located at ``node``."""
    try:
        cls(**({name: value} if name else {}), **more)
    except SettingsError as exc:
        raise node.error(exc.message) from None
    return value


def _nonempty(node: YNode, what: str) -> list[YNode]:
    items = node.items()
    if not items:
        raise node.error(f"expected at least one {what}, found an empty list")
    return items


def _unique(node: YNode, read: Callable[[YNode], Any], what: str) -> list:
    """A non-empty list read item by item, no item given twice."""
    out: list = []
    for n in _nonempty(node, what):
        value = read(n)
        if value in out:
            raise n.error(f"{what} {value!r} is given twice")
        out.append(value)
    return out


def _suite_scenario(node: YNode, base: Path, *, override: str | None) -> SuiteScenario:
    given = node.string(max_len=1000)
    path = base / given
    if not path.is_file():
        raise node.error(f"no scenario file {given!r} (looked for {path})")
    scenario = load_scenario(path)
    if scenario.traffic is None:
        raise node.error(f"{given} has no 'traffic' section to run")
    stream = scenario.traffic.stream
    if override is not None and stream is None:
        raise node.error(f"{given} lists its vehicles one by one and has no traffic stream, "
                         f"so '{override}' cannot apply to it")
    return SuiteScenario(
        name=scenario.name, file=str(path), text=path.read_text(encoding="utf-8"),
        stream_rate=None if stream is None else stream.rate * 3600.0,
        stream_count=None if stream is None else stream.count,
    )


def _planners(node: YNode) -> tuple[PlannerVariant, ...]:
    """``[ca, hca, whca, {whca: [5, 10, 20]}]``: a bare ``whca`` has the default window."""
    out: list[PlannerVariant] = []
    for n in _nonempty(node, "planner"):
        if n.is_mapping:
            w = n.fields(required=["whca"])["whca"]
            windows = _nonempty(w, "window") if w.is_sequence else [w]
            variants = [(x, PlannerVariant("whca", _checked(
                x, RunSettings, "window", x.number(what="a window in seconds"))))
                for x in windows]
        else:
            name = n.string(choices=PLANNERS)
            window = RunSettings().window if name == "whca" else None
            variants = [(n, PlannerVariant(name, window))]
        for where, pv in variants:
            if pv in out:
                raise where.error(f"planner {pv.label} is given twice")
            out.append(pv)
    return tuple(out)


# -- one run ----------------------------------------------------------------------------------
_PREPARED: dict[str, tuple[Scenario, LotGraph]] = {}
_PREPARING = threading.Lock()


def prepared(sc: SuiteScenario) -> tuple[Scenario, LotGraph]:
    """The scenario and its prepared lot, made once per process and scenario text: preparing
    a large lot takes seconds, and every worker keeps what it prepared."""
    key = hashlib.sha256(f"{sc.file}\0{sc.text}".encode()).hexdigest()
    with _PREPARING:  # Dask threads of one worker share this cache: prepare each lot once
        if key not in _PREPARED:
            scenario = parse_scenario(parse_text(sc.text, sc.file))
            _PREPARED[key] = (scenario, prepare(scenario))
        return _PREPARED[key]


def spec_scenario(spec: RunSpec, scenario: Scenario) -> Scenario:
    """``scenario`` with the spec's stream rate and count."""
    stream = scenario.traffic.stream
    if stream is None or (spec.rate_per_hour is None and spec.count is None):
        return scenario
    new = {}
    if spec.rate_per_hour is not None:
        new["rate"] = spec.rate_per_hour / 3600.0
    if spec.count is not None:
        new["count"] = spec.count
    traffic = dataclasses.replace(scenario.traffic,
                                  stream=dataclasses.replace(stream, **new))
    return dataclasses.replace(scenario, traffic=traffic)


def spec_settings(spec: RunSpec) -> RunSettings:
    """The :class:`~lotsim.sim.RunSettings` of a spec."""
    kw: dict[str, Any] = {"planner": spec.planner.planner, "assignment": spec.assignment,
                          "seed": spec.seed, "priority": spec.priority,
                          "ga": GASettings(**dict(spec.ga))}
    if spec.planner.window is not None:
        kw["window"] = spec.planner.window
    return RunSettings(**kw, horizon=spec.horizon)


def _plan(spec: RunSpec, scenario: Scenario, lg: LotGraph) -> tuple[RunResult, dict]:
    """Plan with the spec's priority order, as ``lotsim run`` does
    (:func:`lotsim.priority.plan_run`)."""
    rr = plan_run(scenario, spec_settings(spec), lot_graph=lg)
    return rr, rr.ordering


def peak_memory_mb() -> float:
    """Peak resident memory of this process so far [MB] (``ru_maxrss``: kB on Linux, bytes
    on macOS)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 2**20 if sys.platform == "darwin" else peak / 1024


def run_spec(spec: RunSpec) -> dict:
    """Plan one grid point, check the result, and return its row (keys :data:`COLUMNS`).

    A run that raises is a failed row (``ok`` false, the exception in ``problem``) so that
    one broken run does not lose a sweep; a :class:`ScenarioError` (the lot does not build,
    the traffic cannot be served) is bad input, returned as ``{"bad_input": message}``
    (exceptions with extra arguments do not survive pickling between processes).
    """
    row = _identity(spec)
    try:
        scenario, lg = prepared(spec.scenario)
        scenario = spec_scenario(spec, scenario)
        row.update(_traffic_columns(scenario))
        clock = time.perf_counter()
        rr, extra = _plan(spec, scenario, lg)
        report = check_result(result_dict(rr))
        row["wall_time_s"] = time.perf_counter() - clock
        row.update(_result_columns(rr, report, extra))
    except ScenarioError as exc:
        return {"bad_input": str(exc)}
    except Exception as exc:  # noqa: BLE001 - a crash is a failed run, recorded with its cause
        row.update(_crash(exc))
    row["peak_memory_mb"] = peak_memory_mb()
    return _rounded(row)


def _crash(exc: BaseException) -> dict:
    return {"ok": False, "solved": False, "problem": f"crash: {type(exc).__name__}: {exc}"}


def _lost(spec: RunSpec, exc: BaseException) -> dict:
    """The row of a run whose worker died (killed, out of memory, lost by the cluster)."""
    return _rounded({**_identity(spec), **_crash(exc)})


def _identity(spec: RunSpec) -> dict:
    return {"run": spec.index, "scenario": spec.scenario.name, "planner": spec.planner.planner,
            "window_s": spec.planner.window, "assignment": spec.assignment,
            "priority": spec.priority, "seed": spec.seed}


def _traffic_columns(scenario: Scenario) -> dict:
    stream = scenario.traffic.stream
    return {"rate_per_h": None if stream is None else stream.rate * 3600.0,
            "count": None if stream is None else stream.count}


def _rate(times: Sequence[float]) -> float | None:
    """Events per hour between the first and the last of ``times``: (n − 1) / span."""
    if len(times) < 2 or max(times) <= min(times):
        return None
    return (len(times) - 1) / (max(times) - min(times)) * 3600.0


def _result_columns(rr: RunResult, report: Any, extra: dict) -> dict:
    m = rr.metrics()
    parked_at = [v.parked_at for v in rr.vehicles if v.parked_at is not None]
    violations = report.stats.get("violations", len(report.violations))
    problem = ""
    if not report.ok:
        first = report.violations[0] if report.violations else None
        problem = f"check: {first.rule}: {first.message}" if first else "check failed"
    return {
        "ok": report.ok,
        "solved": report.ok and m["waiting"] == 0,
        "violations": violations,
        "problem": problem,
        "vehicles": m["vehicles"],
        "parked": m["parked"],
        "departed": m["departed"],
        "waiting": m["waiting"],
        "rejected": m["rejected"],
        "makespan_s": m["makespan"],
        "mean_time_to_park_s": m["mean_time_to_park"],
        "max_time_to_park_s": m["max_time_to_park"],
        "total_waiting_s": m["total_waiting"],
        "arrival_rate_per_h": _rate([v.arrival.time for v in rr.vehicles]),
        "throughput_per_h": _rate(parked_at),
        "searches": m["searches"],
        "expansions": m["expansions"],
        "evaluations": extra.get("evaluations"),
        "fitness_s": extra.get("fitness"),
        # the GA's own starting points, planned with the same booking in the same run
        "ga_arrival_fitness_s": extra.get("fitness_arrival"),
        "ga_shortest_first_fitness_s": extra.get("fitness_shortest_first"),
        "planning_time_s": m["planning_time"],
        "planning_median_ms": 1000 * m["planning_time_median"],
        "planning_p95_ms": 1000 * m["planning_time_p95"],
        "order_time_s": extra.get("order_time"),
    }


# -- columns ----------------------------------------------------------------------------------
COLUMNS = (
    "run", "scenario", "planner", "window_s", "assignment", "priority", "rate_per_h", "count",
    "seed", "ok", "solved", "violations", "problem", "vehicles", "parked", "departed",
    "waiting", "rejected", "makespan_s", "mean_time_to_park_s", "max_time_to_park_s",
    "total_waiting_s", "arrival_rate_per_h", "throughput_per_h", "searches", "expansions",
    "evaluations", "fitness_s", "ga_arrival_fitness_s", "ga_shortest_first_fitness_s",
    "planning_time_s", "planning_median_ms", "planning_p95_ms", "order_time_s", "wall_time_s",
    "peak_memory_mb",
)
"""Columns of ``runs.csv``, in order (``docs/bench.md`` defines each)."""
TIMING_COLUMNS = ("planning_time_s", "planning_median_ms", "planning_p95_ms", "order_time_s",
                  "wall_time_s", "peak_memory_mb")
"""The columns that depend on the machine and the moment; all the others depend only on
the suite."""
_DIGITS = {"window_s": 3, "rate_per_h": 3, "makespan_s": 3, "mean_time_to_park_s": 3,
           "max_time_to_park_s": 3, "total_waiting_s": 3, "arrival_rate_per_h": 2,
           "throughput_per_h": 2, "fitness_s": 3, "ga_arrival_fitness_s": 3,
           "ga_shortest_first_fitness_s": 3, "planning_time_s": 4,
           "planning_median_ms": 2, "planning_p95_ms": 2, "order_time_s": 4,
           "wall_time_s": 3, "peak_memory_mb": 1}


def _rounded(row: dict) -> dict:
    out = {k: row.get(k) for k in COLUMNS}
    for k, nd in _DIGITS.items():
        if isinstance(out[k], float):
            out[k] = round(out[k], nd)
    return out


_INTS = ("run", "count", "seed", "violations", "vehicles", "parked", "departed", "waiting",
         "rejected", "searches", "expansions", "evaluations")
_TEXTS = ("scenario", "planner", "assignment", "priority", "problem")


def read_csv(path: str | os.PathLike) -> list[dict]:
    """The rows of a ``runs.csv``, typed as :func:`run_suite` returns them (to tabulate or
    plot a sweep again without running it)."""
    with open(path, newline="", encoding="utf-8") as fh:
        raw = list(csv.DictReader(fh))
    rows = []
    for r in raw:
        row: dict[str, Any] = {}
        for k in COLUMNS:
            v = r.get(k, "")
            if k in _TEXTS:
                row[k] = v
            elif k in ("ok", "solved"):
                row[k] = v == "true"
            elif v == "":
                row[k] = None
            else:
                row[k] = int(v) if k in _INTS else float(v)
        rows.append(row)
    return rows


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return str(value)


# -- running the grid -------------------------------------------------------------------------
def run_suite(suite: Suite, *, jobs: int | None = None, client: Any = None,
              progress: Callable[[int, int], None] | None = None) -> list[dict]:
    """Run every grid point and return the rows in grid order.

    Parameters
    ----------
    suite : Suite
    jobs : int, optional
        Local worker processes (default ``os.cpu_count()``); 1 runs in this process.
    client : distributed.Client, optional
        Run on this Dask cluster instead (:func:`connect`).
    progress : callable, optional
        Called as ``progress(done, total)`` as runs finish.

    Raises
    ------
    ScenarioError
        A scenario whose lot does not build or whose traffic it cannot serve.
    """
    specs = suite.specs()
    total = len(specs)
    rows: dict[int, dict] = {}

    def take(index: int, row: dict) -> None:
        if "bad_input" in row:
            raise ScenarioError(None, row["bad_input"])
        rows[index] = row
        if progress is not None:
            progress(len(rows), total)

    if progress is not None:
        progress(0, total)
    if client is not None:
        _run_dask(client, specs, take)
    else:
        workers = min(jobs or os.cpu_count() or 1, total)
        if workers <= 1:
            for spec in specs:
                take(spec.index, run_spec(spec))
        else:
            _run_pool(workers, specs, take)
    return [rows[i] for i in range(total)]


def _run_pool(workers: int, specs: list[RunSpec], take: Callable[[int, dict], None]) -> None:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # forkserver, not fork: a forked copy of a process that holds threads (a Dask client,
    # a notebook's) can deadlock; workers keep their prepared lots between runs
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("forkserver" if "forkserver" in methods else None)
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx)
    try:
        futures = {pool.submit(run_spec, s): s for s in specs}
        for fut in as_completed(futures):
            spec = futures[fut]
            try:
                row = fut.result()
            except Exception as exc:  # noqa: BLE001 - BrokenProcessPool: a worker died
                row = _lost(spec, exc)
            take(spec.index, row)
    except BaseException:  # Ctrl-C, or an error: stop the runs in flight instead of waiting
        for proc in list((getattr(pool, "_processes", None) or {}).values()):
            proc.terminate()
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def connect(address: str, *, timeout: float = CONNECT_TIMEOUT) -> Any:
    """A :class:`distributed.Client` of the scheduler at ``address``.

    Raises
    ------
    DaskMissing
        ``distributed`` is not installed.
    SchedulerUnreachable
        ``address`` is malformed, or no Dask scheduler answered there within ``timeout``
        seconds.
    """
    try:
        import distributed
        from distributed.comm import resolve_address
    except ImportError as exc:
        raise DaskMissing("--scheduler needs dask.distributed: pip install 'lotsim[dask]'") \
            from exc
    try:
        resolved = resolve_address(address)
    except (ValueError, OSError) as exc:
        raise SchedulerUnreachable(f"--scheduler: {address!r} is not the address of a Dask "
                                   f"scheduler ({_first_line(exc)})") from None
    # probe first: a Client that fails to start leaves an object whose clean-up waits twice
    # the timeout when it is collected. In-process (inproc://) schedulers answer only on
    # their own event loop; the Client reaches them.
    try:
        if not resolved.startswith("inproc://"):
            import asyncio

            asyncio.run(_probe(resolved, timeout))
        return distributed.Client(address, timeout=timeout, set_as_default=False)
    except OSError as exc:
        why = _first_line(exc)
    except Exception as exc:  # noqa: BLE001 - whatever answers there is not a scheduler
        why = f"what answers is not a Dask scheduler: {type(exc).__name__}"
    raise SchedulerUnreachable(f"--scheduler: cannot reach a Dask scheduler at {address!r} "
                               f"within {timeout:g} s ({why})")


async def _probe(address: str, timeout: float) -> None:
    """Connect to ``address`` and shake hands as Dask does; raises when nobody answers."""
    from distributed.comm import connect

    comm = await connect(address, timeout=timeout)
    await comm.close()


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _run_dask(client: Any, specs: list[RunSpec], take: Callable[[int, dict], None]) -> None:
    import distributed

    # pure=False: two runs of the same spec are still two runs (timings differ)
    futures = client.map(run_spec, specs, pure=False)
    by_key = {f.key: s for f, s in zip(futures, specs, strict=True)}
    try:
        for fut in distributed.as_completed(futures, loop=client.loop):
            spec = by_key[fut.key]
            try:
                row = fut.result()
            except Exception as exc:  # noqa: BLE001 - KilledWorker and the like
                row = _lost(spec, exc)
            take(spec.index, row)
    finally:
        client.cancel(futures)


# -- aggregation ------------------------------------------------------------------------------
GROUP = ("scenario", "planner_label", "assignment", "priority", "rate_per_h")
"""What a row of the summary is: the grid point less the seed."""
MEANS = ("vehicles", "parked", "departed", "rejected", "waiting", "mean_time_to_park_s",
         "max_time_to_park_s", "total_waiting_s", "makespan_s", "arrival_rate_per_h",
         "throughput_per_h", "expansions", "evaluations", "fitness_s", "ga_arrival_fitness_s",
         "ga_shortest_first_fitness_s", "planning_median_ms",
         "planning_p95_ms", "order_time_s", "wall_time_s", "peak_memory_mb")


def planner_label(row: dict) -> str:
    """``hca``, ``whca-10``: the planner of a row with its window."""
    w = row["window_s"]
    return row["planner"] if w in (None, "") else f"{row['planner']}-{float(w):g}"


def aggregate(rows: Sequence[dict]) -> list[dict]:
    """One dict per :data:`GROUP` (in grid order): ``runs``, ``ok`` and ``solved``
    (counts), ``failed`` (run numbers), ``served`` (mean of parked + departed: the
    vehicles that got a slot), and for each of :data:`MEANS` the mean over the
    seeds (None where no run has a value), ``<name>_min`` and ``<name>_max``."""
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        key = (r["scenario"], planner_label(r), r["assignment"], r["priority"], r["rate_per_h"])
        groups.setdefault(key, []).append(r)
    out = []
    for key, rs in groups.items():
        g: dict[str, Any] = dict(zip(GROUP, key, strict=True))
        g["runs"] = len(rs)
        g["ok"] = sum(bool(r["ok"]) for r in rs)
        g["solved"] = sum(bool(r["solved"]) for r in rs)
        g["failed"] = [r["run"] for r in rs if not r["ok"]]
        served = [float(r["parked"]) + float(r["departed"]) for r in rs
                  if r.get("parked") is not None]
        g["served"] = float(np.mean(served)) if served else None
        for k in MEANS:
            vals = [float(r[k]) for r in rs if r.get(k) is not None]
            g[k] = float(np.mean(vals)) if vals else None
            g[f"{k}_min"] = min(vals) if vals else None
            g[f"{k}_max"] = max(vals) if vals else None
        out.append(g)
    return out


def ga_gains(groups: Sequence[dict]) -> list[str]:
    """One line per GA group: its total time to park against its own arrival-order and
    shortest-first starting points (same booking, same run), and the order search's cost."""
    out = []
    for g in groups:
        if g["priority"] != "ga" or not g.get("ga_arrival_fitness_s") or g["fitness_s"] is None:
            continue
        base, sf, got = g["ga_arrival_fitness_s"], g["ga_shortest_first_fitness_s"], g["fitness_s"]
        out.append(f"{g['scenario']}, {g['planner_label']}, {g['assignment']}"
                   + (f", rate {g['rate_per_h']:g}/h" if g["rate_per_h"] is not None else "")
                   + f": {got:.1f} s against {base:.1f} s in arrival order "
                   f"({100 * (got - base) / base:+.1f} %) and {sf:.1f} s shortest first "
                   f"({100 * (got - sf) / sf:+.1f} %); {g['evaluations']:.0f} orders planned "
                   f"in {g['order_time_s']:.1f} s")
    return out


def saturation(groups: Sequence[dict]) -> list[str]:
    """For each scenario × planner × assignment × priority swept over two or more rates
    with at least :data:`SATURATION_VEHICLES` vehicles a run, one line: the highest rate
    the lot keeps up with and the lowest it does not (throughput below :data:`SATURATED`
    × the arrival rate, both means over seeds)."""
    lines = []
    series: dict[tuple, list[dict]] = {}
    for g in groups:
        if g["rate_per_h"] is not None and (g["vehicles"] or 0) >= SATURATION_VEHICLES:
            series.setdefault(tuple(g[k] for k in GROUP[:4]), []).append(g)
    for key, gs in series.items():
        if len(gs) < 2:
            continue
        gs = sorted(gs, key=lambda g: g["rate_per_h"])

        def keeps_up(g: dict) -> bool:
            thr, arr = g["throughput_per_h"], g["arrival_rate_per_h"]
            return thr is not None and arr is not None and thr >= SATURATED * arr

        def says(g: dict) -> str:
            return (f"{g['rate_per_h']:g}/h (throughput {_num(g['throughput_per_h'], 0)}/h "
                    f"for {_num(g['arrival_rate_per_h'], 0)}/h arriving, mean time to park "
                    f"{_num(g['mean_time_to_park_s'], 1)} s, mean total waiting "
                    f"{_num(g['total_waiting_s'], 0)} s)")

        first_bad = next((g for g in gs if not keeps_up(g)), None)
        what = " ".join(str(k) for k in key)
        if first_bad is None:
            lines.append(f"{what}: keeps up at every rate, up to {says(gs[-1])}")
            continue
        ok = [g for g in gs if g["rate_per_h"] < first_bad["rate_per_h"] and keeps_up(g)]
        head = f"keeps up at {says(ok[-1])}; " if ok else ""
        lines.append(f"{what}: {head}saturated from {says(first_bad)}")
    return lines


def _num(value: float | None, nd: int) -> str:
    return "–" if value is None else f"{value:.{nd}f}"


# -- writing ----------------------------------------------------------------------------------
def csv_text(rows: Sequence[dict]) -> str:
    """``runs.csv``: a header of :data:`COLUMNS`, one line per run."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(COLUMNS)
    for r in rows:
        w.writerow([_cell(r.get(k)) for k in COLUMNS])
    return buf.getvalue()


_TABLE = (  # (summary key, heading, digits)
    ("parked", "parked", 1), ("departed", "departed", 1), ("rejected", "rejected", 1),
    ("waiting", "waiting", 1), ("mean_time_to_park_s", "time to park mean [s]", 1),
    ("max_time_to_park_s", "max [s]", 1), ("total_waiting_s", "total waiting [s]", 1),
    ("makespan_s", "makespan [s]", 0), ("arrival_rate_per_h", "arriving [veh/h]", 0),
    ("throughput_per_h", "throughput [veh/h]", 0), ("expansions", "expansions", 0),
    ("planning_median_ms", "planning median [ms]", 1), ("planning_p95_ms", "p95 [ms]", 1),
    ("peak_memory_mb", "peak memory [MB]", 0),
)
_ORDERED = (("fitness_s", "total time to park [s]", 1), ("evaluations", "evaluations", 0),
            ("order_time_s", "order time [s]", 2))
_IDENT = (("scenario", "scenario"), ("planner_label", "planner"), ("assignment", "assignment"),
          ("priority", "priority"), ("rate_per_h", "rate [veh/h]"))


def _varying(groups: Sequence[dict]) -> tuple[list[tuple[str, str]], list[str]]:
    """The identity columns that differ between groups, and ``key value`` for the others."""
    vary, fixed = [], []
    for key, head in _IDENT:
        values = list(dict.fromkeys(g[key] for g in groups))
        if len(values) > 1 or key in ("scenario", "planner_label"):
            vary.append((key, head))
        else:
            fixed.append(f"{head} {_ident(values[0])}")
    return vary, fixed


def _ident(value: Any) -> str:
    if value is None:
        return "as in the scenario"
    return f"{value:g}" if isinstance(value, float) else str(value)


PLOTS = ("throughput.png", "time_to_park.png")
"""The plots a suite's outputs hold (with matplotlib)."""


def summary_markdown(suite: Suite, rows: Sequence[dict], *, where: str = "",
                     plots: bool = True) -> str:
    """``summary.md``: the suite, the means over seeds, saturation, failed runs, and the
    plots when they are drawn (``plots``)."""
    groups = aggregate(rows)
    vary, fixed = _varying(groups)
    failed = [r for r in rows if not r["ok"]]
    unsolved = sum(not r["solved"] for r in rows)
    rates = ("as in each scenario" if suite.rates_per_hour is None
             else ", ".join(f"{r:g}" for r in suite.rates_per_hour) + " vehicles/h")
    lines = [f"# Benchmark `{suite.name}`", ""]
    if suite.description:
        lines += [suite.description, ""]
    ga = ", ".join(f"{k} {v}" for k, v in suite.ga)
    lines += [
        f"- suite: `{suite.source}`",
        f"- scenarios: {', '.join(f'{s.name} (`{Path(s.file).name}`)' for s in suite.scenarios)}",
        f"- planners: {', '.join(p.label for p in suite.planners)}; assignments: "
        f"{', '.join(suite.assignments)}; priorities: {', '.join(suite.priorities)}"
        + (f" (GA: {ga})" if ga else "")
        + (f"; booked orders know arrivals {suite.horizon:g} s ahead"
           if set(suite.priorities) & {"shortest_first", "ga"} else ""),
        f"- arrival rates: {rates}" + (f"; {suite.count} vehicles" if suite.count else ""),
        f"- seeds: {', '.join(str(s) for s in suite.seeds)}",
        f"- {len(rows)} runs: {len(rows) - len(failed)} pass `lotsim check`, "
        f"{len(failed)} fail; {len(rows) - unsolved} solved (no vehicle left waiting)",
        f"- lotsim {__version__}" + (f"; {where}" if where else ""),
        "",
        "## Means over seeds",
        "",
    ]
    if fixed:
        lines += ["All runs: " + "; ".join(fixed) + ".", ""]
    extra = _ORDERED if any(p != "arrival" for p in suite.priorities) else ()
    cols = [*_TABLE, *extra]
    head = [h for _, h in vary] + ["runs", "ok", "solved"] + [h for _, h, _ in cols]
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "|".join("---" if i < len(vary) else "---:"
                                for i in range(len(head))) + "|")
    for g in groups:
        cells = [_ident(g[k]) for k, _ in vary] + [str(g["runs"]), str(g["ok"]),
                                                   str(g["solved"])]
        cells += [_num(g[k], nd) for k, _, nd in cols]
        lines.append("| " + " | ".join(cells) + " |")
    gains = ga_gains(groups)
    if gains:
        lines += ["", "## The GA's gain", "",
                  "Total time to park of the GA's order against the arrival and shortest-first "
                  "orders it started from, planned with the same booking horizon in the same "
                  "run (means over seeds), and what the search cost:", ""]
        lines += [f"- {s}" for s in gains]
    sat = saturation(groups)
    if sat:
        lines += ["", "## Saturation", "",
                  f"Saturated: throughput below {SATURATED:.0%} of the arrival rate "
                  "(means over seeds).", ""]
        lines += [f"- {s}" for s in sat]
    lines += ["", "## Failed runs", ""]
    if not failed:
        lines.append("None: every run passes `lotsim check`.")
    for r in failed:
        lines.append(f"- run {r['run']} ({r['scenario']}, {planner_label(r)}, {r['assignment']}, "
                     f"{r['priority']}, rate {_ident(r['rate_per_h'])}, seed {r['seed']}): "
                     f"{r['problem'] or 'failed'}")
    lines += ["", "## Plots", ""]
    lines += (["![throughput](throughput.png)", "", "![time to park](time_to_park.png)"]
              if plots else ["None: they need matplotlib (`pip install 'lotsim[plot]'`)."])
    lines += ["", "Columns and definitions: `docs/bench.md` in lotsim.", ""]
    return "\n".join(lines)


def table_text(rows: Sequence[dict]) -> str:
    """The means over seeds as a compact plain-text table for the terminal."""
    groups = aggregate(rows)
    vary, fixed = _varying(groups)
    cols = (("ok", "ok", None), ("served", "served", 1), ("rejected", "rej", 1),
            ("waiting", "wait", 1), ("mean_time_to_park_s", "park s", 1),
            ("max_time_to_park_s", "max s", 1), ("total_waiting_s", "waited s", 0),
            ("throughput_per_h", "veh/h", 0), ("planning_p95_ms", "p95 ms", 0))
    head = [h for _, h in vary] + [h for _, h, _ in cols]
    body = []
    for g in groups:
        cells = [_ident(g[k]) for k, _ in vary]
        for k, _, nd in cols:
            cells.append(f"{g['ok']}/{g['runs']}" if k == "ok" else _num(g[k], nd))
        body.append(cells)
    widths = [max(len(x) for x in col) for col in zip(head, *body, strict=True)]
    n_id = len(vary)

    def line(cells: list[str]) -> str:
        return "  ".join(c.ljust(w) if i < n_id else c.rjust(w)
                         for i, (c, w) in enumerate(zip(cells, widths, strict=True))).rstrip()

    out = ["  " + line(head)] + ["  " + line(c) for c in body]
    if fixed:
        out.insert(0, "  all runs: " + "; ".join(fixed))
    return "\n".join(out)


def write_outputs(suite: Suite, rows: Sequence[dict], outdir: str | os.PathLike, *,
                  where: str = "", plots: bool = True) -> list[Path]:
    """Write ``runs.csv``, ``summary.md`` and (with matplotlib and ``plots``)
    ``throughput.png`` and ``time_to_park.png`` to ``outdir``, each atomically; returns
    the paths written."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    with atomic_write(out / "runs.csv", "w", encoding="utf-8") as fh:
        fh.write(csv_text(rows))
    written.append(out / "runs.csv")
    with atomic_write(out / "summary.md", "w", encoding="utf-8") as fh:
        fh.write(summary_markdown(suite, rows, where=where, plots=plots))
    written.append(out / "summary.md")
    if plots:
        from lotsim.render.plots import save_figure

        for metric, name in zip(("throughput_per_h", "mean_time_to_park_s"), PLOTS,
                                strict=True):
            save_figure(bench_figure(rows, metric), out / name)
            written.append(out / name)
    else:  # the outputs are one set: no plot of an earlier suite run stays beside them
        for name in PLOTS:
            (out / name).unlink(missing_ok=True)
    return written


# -- plots ------------------------------------------------------------------------------------
_YLABEL = {"throughput_per_h": "throughput [vehicles/h]",
           "mean_time_to_park_s": "mean time to park [s]"}


def bench_figure(rows: Sequence[dict], metric: str) -> Figure:
    """``metric`` (a column of :data:`MEANS`) per scenario, one axes each, mean over seeds
    with min–max whiskers.

    Against the arrival rate (one line per planner; per assignment and priority too when
    the suite has several, told apart by line style) where a scenario is run at two rates
    or more; otherwise as bars per planner, side by side per assignment and priority.
    A throughput plot against the rate also draws the arrival rate itself (dotted): a line
    below it is a lot that does not keep up.

    Raises
    ------
    lotsim.render.plots.MatplotlibMissing
    """
    from lotsim.render.plots import require_matplotlib

    require_matplotlib()
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    groups = aggregate(rows)
    scenarios = list(dict.fromkeys(g["scenario"] for g in groups))
    fig = Figure(figsize=(6.0 * len(scenarios) + 1.5, 4.5), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)  # our own canvas: no pyplot, no backend switch (as plots.py)
    axes = fig.subplots(1, len(scenarios), squeeze=False)[0]
    planners = list(dict.fromkeys(g["planner_label"] for g in groups))
    ways = list(dict.fromkeys((g["assignment"], g["priority"]) for g in groups))
    several = len(ways) > 1
    ways = _way_labels(ways)
    colours = matplotlib.colormaps["tab10"].colors
    styles = ("-", "--", ":", "-.")
    for ax, name in zip(axes, scenarios, strict=True):
        gs = [g for g in groups if g["scenario"] == name]
        rates = {g["rate_per_h"] for g in gs}
        if len(rates) > 1 and None not in rates:
            _lines(ax, gs, metric, planners, ways, colours, styles, several)
        else:
            _bars(ax, gs, metric, planners, ways, colours, several)
        ax.set_title(name)
        ax.set_ylabel(_YLABEL.get(metric, metric))
        ax.grid(alpha=0.3)
        ax.set_axisbelow(True)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    return fig


def _way_labels(ways: Sequence[tuple[str, str]]) -> dict[tuple[str, str], str]:
    """``shortest``, ``nearest, ga``: the parts of (assignment, priority) that vary."""
    vary = [k for k in range(2) if len({w[k] for w in ways}) > 1]
    return {w: ", ".join(w[k] for k in vary) for w in ways}


def _spread(gs: Sequence[dict], metric: str) -> tuple[np.ndarray, np.ndarray]:
    mean = np.array([np.nan if g[metric] is None else g[metric] for g in gs], dtype=float)
    lo = np.array([np.nan if g[f"{metric}_min"] is None else g[f"{metric}_min"] for g in gs])
    hi = np.array([np.nan if g[f"{metric}_max"] is None else g[f"{metric}_max"] for g in gs])
    # a mean can land a rounding error outside its own min and max: whiskers never negative
    return mean, np.clip(np.vstack([mean - lo, hi - mean]), 0.0, None)


def _lines(ax, gs, metric, planners, ways, colours, styles, several) -> None:  # noqa: ANN001
    for p in planners:
        for w in ways:
            line = sorted((g for g in gs if g["planner_label"] == p
                           and (g["assignment"], g["priority"]) == w),
                          key=lambda g: g["rate_per_h"])
            if not line:
                continue
            x = np.array([g["rate_per_h"] for g in line])
            mean, err = _spread(line, metric)
            ax.errorbar(x, mean, yerr=err, color=colours[planners.index(p) % len(colours)],
                        linestyle=styles[list(ways).index(w) % len(styles)], marker="o", ms=4,
                        capsize=3, label=p + (f" ({ways[w]})" if several else ""))
    x_all = sorted({g["rate_per_h"] for g in gs})
    if metric == "throughput_per_h":
        ax.plot(x_all, x_all, color="0.5", linestyle=":", label="arrival rate")
    if x_all[-1] / x_all[0] >= 8:
        ax.set_xscale("log")
        ax.set_xticks(x_all, [f"{x:g}" for x in x_all])
        ax.minorticks_off()
    values = [g[metric] for g in gs if g[metric]]
    if metric != "throughput_per_h" and values and max(values) / min(values) > 50:
        ax.set_yscale("log")
    ax.set_xlabel("arrival rate [vehicles/h]")


def _bars(ax, gs, metric, planners, ways, colours, several) -> None:  # noqa: ANN001
    width = 0.8 / len(ways)
    for k, w in enumerate(ways):
        bars = [next((g for g in gs if g["planner_label"] == p
                      and (g["assignment"], g["priority"]) == w), None) for p in planners]
        xs = [i + (k - (len(ways) - 1) / 2) * width for i, b in enumerate(bars) if b]
        have = [b for b in bars if b]
        if not have:
            continue
        mean, err = _spread(have, metric)
        colour = (colours[k % len(colours)] if several
                  else [colours[planners.index(b["planner_label"]) % len(colours)]
                        for b in have])
        ax.bar(xs, mean, width=width * 0.9, yerr=err, capsize=3, color=colour,
               label=ways[w] if several else None)
    ax.set_xticks(range(len(planners)), planners)
    rates = {g["rate_per_h"] for g in gs}
    rate = next(iter(rates)) if len(rates) == 1 else None
    ax.set_xlabel("planner" + (f" (arrival rate {rate:g} vehicles/h)" if rate else ""))
