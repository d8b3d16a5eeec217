"""Running a suite: :func:`run_spec` plans and checks one grid point, :func:`run_suite` runs
them all in this process, in a pool of processes or on a Dask cluster (:func:`connect`)."""

from __future__ import annotations

import dataclasses
import hashlib
import os
import resource
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from lotsim.bench.suite import RunSpec, Suite, SuiteScenario, one_stream
from lotsim.bench.table import _rounded, hour_figures
from lotsim.errors import LotsimError, ScenarioError
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.sim.execution import execute
from lotsim.sim.orders import plan_run
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.results import RunResult
from lotsim.sim.running import collector_tuned
from lotsim.sim.settings import GASettings, RunSettings
from lotsim.traffic.searchgraph import SearchGraphMemo
from lotsim.verify import check_result

if TYPE_CHECKING:

    from lotsim.roadmap.model import LotGraph
    from lotsim.scenario import Scenario


CONNECT_TIMEOUT = 5.0
"""How long to try reaching a Dask scheduler before giving up [s]."""


class DaskMissing(LotsimError):
    """``--scheduler`` was asked for but ``distributed`` is not installed."""


class SchedulerUnreachable(LotsimError):
    """The Dask scheduler at the given address did not answer."""


_PREPARED: dict[str, tuple[Scenario, LotGraph, SearchGraphMemo]] = {}
_PREPARING = threading.Lock()


def prepared(sc: SuiteScenario) -> tuple[Scenario, LotGraph, SearchGraphMemo]:
    """The scenario, its prepared lot and the lot's search graphs, made once per process and
    scenario text: preparing a large lot takes seconds, and every worker keeps what it
    prepared for its next runs on the lot."""
    key = hashlib.sha256(f"{sc.file}\0{sc.text}".encode()).hexdigest()
    with _PREPARING:  # Dask threads of one worker share this cache: prepare each lot once
        if key not in _PREPARED:
            scenario = parse_scenario(parse_text(sc.text, sc.file))
            _PREPARED[key] = (scenario, prepare_graph(scenario), SearchGraphMemo())
        return _PREPARED[key]


def spec_scenario(spec: RunSpec, scenario: Scenario) -> Scenario:
    """``scenario`` with the spec's stream rate and count, and its disturbances (over the
    scenario's own: a suite's variant ``none`` drives the plan as planned)."""
    scenario = dataclasses.replace(scenario, disturbances=spec.disturbances)
    stream = one_stream(scenario)
    if stream is None or (spec.rate_per_hour is None and spec.count is None):
        return scenario
    new = {}
    if spec.rate_per_hour is not None:
        new["rate"] = spec.rate_per_hour / 3600.0
    if spec.count is not None:
        new["count"] = spec.count
    traffic = dataclasses.replace(scenario.traffic,
                                  streams=(dataclasses.replace(stream, **new),))
    return dataclasses.replace(scenario, traffic=traffic)


def spec_settings(spec: RunSpec) -> RunSettings:
    """The :class:`~lotsim.sim.settings.RunSettings` of a spec."""
    kw: dict[str, Any] = {"planner": spec.planner.planner, "assignment": spec.assignment,
                          "seed": spec.seed, "priority": spec.priority,
                          "ga": GASettings(**dict(spec.ga))}
    if spec.planner.window is not None:
        kw["window"] = spec.planner.window
    return RunSettings(**kw, horizon=spec.horizon)


def _plan(spec: RunSpec, scenario: Scenario, lg: LotGraph, memo: SearchGraphMemo
          ) -> tuple[RunResult, dict]:
    """Plan with the spec's priority order, as ``lotsim run`` does
    (:func:`lotsim.sim.orders.plan_run`)."""
    with collector_tuned():
        rr = plan_run(scenario, spec_settings(spec), lot_graph=lg, memo=memo)
    return rr, rr.ordering


def peak_memory_mb() -> float:
    """Peak resident memory of this process so far [MB] (``ru_maxrss``: kB on Linux, bytes
    on macOS)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 2**20 if sys.platform == "darwin" else peak / 1024


def run_spec(spec: RunSpec) -> dict:
    """Plan one grid point, check the result, and return its row: the keys :data:`COLUMNS`
    and ``hours``, the run hour by hour (:meth:`RunResult.hourly`, keyed by
    :data:`~lotsim.bench.table.HOUR_FIGURES`; empty for a run that crashed). The row is
    plain data, a few hundred bytes an hour: what a worker sends back, not the result.

    A run that raises is a failed row (``ok`` false, the exception in ``problem``) so that
    one broken run does not lose a sweep; a :class:`ScenarioError` (the lot does not build,
    the traffic cannot be served) is bad input, returned as ``{"bad_input": message}``
    (exceptions with extra arguments do not survive pickling between processes).
    """
    row = _identity(spec)
    hours: list[dict] = []
    try:
        scenario, lg, memo = prepared(spec.scenario)
        scenario = spec_scenario(spec, scenario)
        row.update(_traffic_columns(scenario))
        clock = time.perf_counter()
        rr, extra = _plan(spec, scenario, lg, memo)
        if spec.disturbances is not None and spec.disturbances.driven:
            rr = execute(rr, spec.disturbances, memo=memo)
        report = check_result(result_dict(rr))
        row["wall_time_s"] = time.perf_counter() - clock
        row.update(_result_columns(rr, report, extra))
        hours = hour_figures(rr.hourly())
    except ScenarioError as exc:
        return {"bad_input": str(exc)}
    except Exception as exc:  # a crash is a failed run, recorded with its cause
        row.update(_crash(exc))
        hours = []
    row["peak_memory_mb"] = peak_memory_mb()
    return {**_rounded(row), "hours": hours}


def _crash(exc: BaseException) -> dict:
    return {"ok": False, "solved": False, "problem": f"crash: {type(exc).__name__}: {exc}"}


def _lost(spec: RunSpec, exc: BaseException) -> dict:
    """The row of a run whose worker died (killed, out of memory, lost by the cluster)."""
    return {**_rounded({**_identity(spec), **_crash(exc)}), "hours": []}


def _identity(spec: RunSpec) -> dict:
    return {"run": spec.index, "scenario": spec.scenario.name, "planner": spec.planner.planner,
            "window_s": spec.planner.window, "assignment": spec.assignment,
            "priority": spec.priority, "disturbance": spec.disturbance, "seed": spec.seed}


def _traffic_columns(scenario: Scenario) -> dict:
    stream = one_stream(scenario)
    return {"rate_per_h": None if stream is None else stream.rate * 3600.0,
            "count": None if stream is None else stream.count}


def _rate(times: Sequence[float]) -> float | None:
    """Events per hour between the first and the last of ``times``: (n − 1) / span."""
    if len(times) < 2 or max(times) <= min(times):
        return None
    return (len(times) - 1) / (max(times) - min(times)) * 3600.0


def _result_columns(rr: RunResult, report: Any, extra: dict) -> dict:
    m = rr.metrics()
    trips = rr.trip_figures()
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
        "served": m["served"],
        "parked": m["parked"],
        "departed": m["departed"],
        "waiting": m["waiting"],
        "rejected": m["rejected"],
        "makespan_s": m["makespan"],
        "mean_time_to_park_s": m["mean_time_to_park"],
        "max_time_to_park_s": m["max_time_to_park"],
        "median_time_to_park_s": trips["median_time_to_park"],
        "p90_time_to_park_s": trips["p90_time_to_park"],
        "median_time_to_leave_s": trips["median_time_to_leave"],
        "p90_time_to_leave_s": trips["p90_time_to_leave"],
        "standing_per_car_s": trips["standing_per_car"],
        "standing_outside_per_car_s": trips["standing_outside_per_car"],
        "standing_in_per_car_s": trips["standing_in_per_car"],
        "standing_out_per_car_s": trips["standing_out_per_car"],
        "total_waiting_s": m["total_waiting"],
        "arrival_rate_per_h": _rate([v.arrival.time for v in rr.vehicles]),
        "throughput_per_h": _rate(parked_at),
        "searches": m["searches"],
        "expansions": m["expansions"],
        **_disturbance_columns(rr),
        "evaluations": extra.get("evaluations"),
        "fitness_s": extra.get("fitness"),
        # the GA's own starting points, planned with the same booking in the same run
        "ga_arrival_fitness_s": extra.get("fitness_arrival"),
        "ga_shortest_first_fitness_s": extra.get("fitness_shortest_first"),
        "planning_time_s": m["planning_time"],
        "planning_median_ms": 1000 * m["planning_time_median"],
        "planning_p95_ms": 1000 * m["planning_time_p95"],
        "motions_s": m["planning_time_motions"],
        "order_time_s": extra.get("order_time"),
    }


def _disturbance_columns(rr: RunResult) -> dict:
    """What the run's disturbances did: late starts, stalls, cars planned again, and the
    seconds the cars stood beyond their plans' waits."""
    rec, changes = rr.execution, rr.lot_changes
    return {"late_starts": len(rec.late) if rec else 0, "stalls": len(rec.stalls) if rec else 0,
            "replans": len(changes.replans) if changes else 0,
            "stood_more_s": rec.waited if rec else 0.0}


def run_suite(suite: Suite, *, jobs: int | None = None, client: Any = None,
              progress: Callable[[int, int], None] | None = None) -> list[dict]:
    """Run every grid point and return the rows in grid order (each as :func:`run_spec`
    returns it: the columns of ``runs.csv`` and the run's ``hours``, the rows of
    ``hours.csv`` by :func:`~lotsim.bench.table.hour_rows`).

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
    run_all(run_spec, specs, lambda k, row: take(specs[k].index, row),
            lambda k, exc: _lost(specs[k], exc), jobs=jobs, client=client)
    return [rows[i] for i in range(total)]


def run_all(fn: Callable[[Any], Any], items: Sequence[Any], take: Callable[[int, Any], None],
            lost: Callable[[int, BaseException], Any], *, jobs: int | None = None,
            client: Any = None) -> None:
    """``fn(item)`` for every item: on the Dask cluster of ``client``, or on ``jobs`` local
    processes (default ``os.cpu_count()``; 1: in this process, in order). ``take(k,
    answer)`` is called here as each is done, ``k`` the item's place; the answer of an item
    whose worker died (killed, out of memory, lost by the cluster) is ``lost(k, exc)``.
    ``fn`` and the items must pickle (``fn`` by name: a module-level function). Ctrl-C
    stops the workers and raises KeyboardInterrupt here."""
    if client is not None:
        _run_dask(client, fn, items, take, lost)
        return
    workers = min(jobs or os.cpu_count() or 1, len(items))
    if workers <= 1:
        for k, item in enumerate(items):
            take(k, fn(item))
    else:
        _run_pool(workers, fn, items, take, lost)


def _run_pool(workers: int, fn: Callable[[Any], Any], items: Sequence[Any],
              take: Callable[[int, Any], None],
              lost: Callable[[int, BaseException], Any]) -> None:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # forkserver, not fork: a forked copy of a process that holds threads (a Dask client,
    # a notebook's) can deadlock; workers keep their prepared lots between runs
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("forkserver" if "forkserver" in methods else None)
    if ctx.get_start_method() == "forkserver":
        # started before Ctrl-C is held: starting it lets Ctrl-C through again
        from multiprocessing import resource_tracker

        resource_tracker.ensure_running()
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx,
                               initializer=_deaf_to_ctrl_c)
    try:
        with _ctrl_c_held():  # the pool's processes start here, in submit
            futures = {pool.submit(fn, item): k for k, item in enumerate(items)}
        for fut in as_completed(futures):
            k = futures[fut]
            try:
                answer = fut.result()
            except Exception as exc:  # BrokenProcessPool: a worker died
                answer = lost(k, exc)
            take(k, answer)
    except BaseException:  # Ctrl-C, or an error: stop the runs in flight instead of waiting
        for proc in list((getattr(pool, "_processes", None) or {}).values()):
            proc.terminate()
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


@contextmanager
def _ctrl_c_held() -> Iterator[None]:
    """Hold Ctrl-C (SIGINT) back in the block and raise KeyboardInterrupt when it ends, if
    one came. The processes started in it (the forkserver, the pool's workers) inherit
    SIGINT blocked, so a Ctrl-C to the terminal's process group reaches only lotsim, which
    stops them and says so in one line. Interrupted while they started up (importing
    lotsim), they printed Python's own tracebacks; lotsim interrupted while it started one,
    which it then did not know of, left it running, or failing on what lotsim had already
    removed. (A Ctrl-C that came just before the block is noted too: Python runs the
    handler of the moment it looks, not of the moment the signal came.)"""
    if not hasattr(signal, "pthread_sigmask") or (
            threading.current_thread() is not threading.main_thread()):
        yield
        return
    came: list[int] = []
    handler = signal.signal(signal.SIGINT, lambda signum, frame: came.append(signum))
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # one held back is noted now
        signal.signal(signal.SIGINT, handler)
    if came:
        raise KeyboardInterrupt


def _deaf_to_ctrl_c() -> None:
    """A worker's first act: Ctrl-C is for lotsim, which stops the workers (also where the
    forkserver was started before, not holding it back, as by an earlier suite run in the
    same process)."""
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    else:
        signal.signal(signal.SIGINT, signal.SIG_IGN)


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
    except Exception as exc:  # whatever answers there is not a scheduler
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


def _run_dask(client: Any, fn: Callable[[Any], Any], items: Sequence[Any],
              take: Callable[[int, Any], None],
              lost: Callable[[int, BaseException], Any]) -> None:
    import distributed

    # pure=False: two runs of the same item are still two runs (timings differ)
    futures = client.map(fn, list(items), pure=False)
    by_key = {f.key: k for k, f in enumerate(futures)}
    try:
        for fut in distributed.as_completed(futures, loop=client.loop):
            k = by_key[fut.key]
            try:
                answer = fut.result()
            except Exception as exc:  # KilledWorker and the like
                answer = lost(k, exc)
            take(k, answer)
    finally:
        client.cancel(futures)
