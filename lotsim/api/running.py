"""Running a prepared lot's traffic (:func:`run`); a run gives back a
:class:`~lotsim.sim.results.RunResult`, which :func:`~lotsim.io.result.result_dict` turns into
the JSON document of ``docs/result.md`` and :func:`lotsim.write_result` writes."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from lotsim.api.scenarios import (
    EXAMPLE,  # noqa: F401 (the examples)
    ScenarioLike,
    prepare,
)
from lotsim.core import checks as _checks
from lotsim.errors import SettingsError
from lotsim.sim.preparation import PreparedLot
from lotsim.sim.results import RunResult
from lotsim.sim.settings import RunSettings
from lotsim.traffic.disturbances import Disturbances


def run(scenario_or_prepared: ScenarioLike | PreparedLot, settings: RunSettings | None = None,
        *, progress=None, disturbances: Disturbances | None = None,
        write: str | Path | None = None, **overrides: Any) -> RunResult:
    """Plan the scenario's traffic: assign slots, plan every vehicle in, and out again.

    Parameters
    ----------
    scenario_or_prepared : PreparedLot, Scenario, path or YAML text
        A :class:`PreparedLot` is run as it is; anything else is prepared first
        (:func:`prepare`, from the cache when it can): prepare once to run many times.
    settings : RunSettings, optional
        How to plan (the defaults of ``lotsim run`` when not given).
    progress : callable, optional, keyword-only
        Called as ``progress(done, total)``: trips planned, or, with ``priority="ga"``,
        orders the genetic algorithm has tried. A callback that takes a third argument is
        given, with the trips, the run's clock as a time of day and the cars served so far
        (``"08:42, 512 served"``).
    disturbances : Disturbances, optional, keyword-only
        What departs from the plan as the cars drive it (late starts, slow cars, stalls);
        the scenario's ``disturbances`` section when not given. The run is planned, then
        driven through them keeping the plan's order at every piece of the lot
        (:func:`lotsim.sim.execution.execute`): the result's moves are those executed, and
        its ``execution`` says what was drawn and what it did.
    write : path, optional, keyword-only
        Write the run's document there as the run goes (as :func:`write_result` would
        after it, byte for byte; ``.json.gz`` for the compact form): each car once it is
        done, its moves then let go, so that a long run's memory follows the cars present,
        not those served. The result's cars keep their figures (``metrics()``,
        ``trip_figures()``, ``hourly()``), not their moves. Atomic: nothing is at the path
        unless the run ends. Not with disturbances.
    **overrides
        Fields of :class:`RunSettings` to change: ``planner``, ``assignment``, ``seed``,
        ``window``, ``omega``, ``retry``, ``order``, ``horizon``, ``priority``, ``ga``.

    Returns
    -------
    RunResult
        ``.metrics()``, ``.vehicles``, ``.settings``, ``.ordering``; its document is
        :func:`lotsim.result_dict`, and :func:`lotsim.write_result` writes it.

    Raises
    ------
    SettingsError
        For a setting out of range or unknown (``window: expected 1 to 600 seconds,
        found 0``).
    ScenarioError
        For a bad scenario, one without traffic, or traffic the lot cannot serve at all.

    Examples
    --------
    >>> prepared = prepare(EXAMPLE)
    >>> a = run(prepared, planner="hca")
    >>> b = run(prepared, RunSettings(planner="hca", priority="shortest_first"))
    >>> a.metrics()["vehicles"], b.settings.order
    (3, ('ada', 'cy', 'bob'))
    >>> run(prepared, planner="whca", window=0)
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: window: expected 1 to 600 seconds, found 0
    """
    if settings is not None and not isinstance(settings, RunSettings):
        raise SettingsError("settings", f"expected RunSettings, found "
                                        f"{type(settings).__name__}")
    settings = _checks.replace(settings or RunSettings(), overrides)
    prepared = (scenario_or_prepared if isinstance(scenario_or_prepared, PreparedLot)
                else prepare(scenario_or_prepared))
    traffic = prepared.scenario.traffic
    if settings.seed is not None and traffic is not None:
        if not traffic.streams:
            raise SettingsError("seed", "seeds the traffic stream, and this scenario has "
                                        "none (its vehicles are listed): it would change "
                                        "nothing")
        if all(s.seed is not None for s in traffic.streams):
            stream = traffic.streams[0]
            own = ("stream has its own seed" if len(traffic.streams) == 1
                   else "streams each have their own seed, the first")
            raise SettingsError("seed", f"the scenario's {own} ({stream.seed}, "
                                        f"{stream.where}): it would change nothing")
    from lotsim.sim.orders import plan_run

    if progress is None:  # in a notebook, the cell shows it
        from lotsim.api.notebook import progress_for

        progress = progress_for("planning trips")
    spec = prepared.scenario.disturbances if disturbances is None else disturbances
    if spec is not None and not isinstance(spec, Disturbances):
        raise SettingsError("disturbances", f"expected Disturbances, found "
                                            f"{type(spec).__name__}")
    scenario = (prepared.scenario if disturbances is None
                else dataclasses.replace(prepared.scenario, disturbances=disturbances))
    if write is not None:
        if spec is not None and spec.active:
            raise SettingsError("write", "a run with disturbances is written when it ends "
                                         "(write_result): they can still change a car that "
                                         "is done")
        from lotsim.io.result import ResultWriter

        Path(write).parent.mkdir(parents=True, exist_ok=True)  # (as write_result)
        with ResultWriter(write, scenario, prepared.lot_graph) as out:
            rr = plan_run(scenario, settings, lot_graph=prepared.lot_graph,
                          progress=progress, memo=prepared.search_graphs, release=out.add)
            out.finish(rr)
        return rr
    rr = plan_run(scenario, settings, lot_graph=prepared.lot_graph,
                  progress=progress, memo=prepared.search_graphs)
    if spec is not None and spec.driven:
        from lotsim.sim.execution import execute

        rr = execute(rr, spec, memo=prepared.search_graphs)
    return rr
