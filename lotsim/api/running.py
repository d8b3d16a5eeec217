"""Running a prepared lot's traffic (:func:`run`) and what a run gives back
(:class:`RunResult`)."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path
from typing import Any

from lotsim.api.scenarios import (
    EXAMPLE,  # noqa: F401 (the examples)
    ScenarioLike,
    prepare,
)
from lotsim.core import checks as _checks
from lotsim.errors import SettingsError
from lotsim.sim import results as _results
from lotsim.sim.preparation import PreparedLot
from lotsim.sim.settings import RunSettings


@dataclasses.dataclass
class RunResult(_results.RunResult):
    """What :func:`run` returns: the lot, the settings and every vehicle's story.

    ``metrics()`` counts the vehicles by status and gives the timing figures of
    ``docs/result.md``; ``vehicles`` holds each one's arrival, slot, status, reason and
    moves; ``settings`` the :class:`RunSettings` it was planned with (the order its
    priority chose included: running them again plans the same run); ``ordering`` how the
    order was chosen.
    """

    def to_dict(self) -> dict:
        """The run as the JSON document ``lotsim run`` writes (``docs/result.md``).

        >>> doc = run(EXAMPLE).to_dict()
        >>> doc["format"], [v["status"] for v in doc["vehicles"]]
        ('lotsim-result', ['parked', 'departed', 'parked'])
        """
        from lotsim.io.result import result_dict

        return result_dict(self)

    def write(self, path: str | os.PathLike) -> Path:
        """Write the run to ``path`` as ``result.json`` (atomically: nothing half-written;
        its folder is made if need be); byte for byte what ``lotsim run`` writes for the
        same scenario and seed.

        >>> import tempfile
        >>> folder = tempfile.mkdtemp()
        >>> run(EXAMPLE).write(f"{folder}/result.json").name
        'result.json'
        """
        from lotsim.io.result import write_json

        Path(path).parent.mkdir(parents=True, exist_ok=True)
        write_json(self.to_dict(), path)
        return Path(path)


def run(scenario_or_prepared: ScenarioLike | PreparedLot, settings: RunSettings | None = None,
        *, progress=None, **overrides: Any) -> RunResult:
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
        orders the genetic algorithm has tried.
    **overrides
        Fields of :class:`RunSettings` to change: ``planner``, ``assignment``, ``seed``,
        ``window``, ``omega``, ``retry``, ``order``, ``horizon``, ``priority``, ``ga``.

    Returns
    -------
    RunResult
        ``.metrics()``, ``.vehicles``, ``.to_dict()``, ``.write(path)``.

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
        stream = traffic.stream
        if stream is None:
            raise SettingsError("seed", "seeds the traffic stream, and this scenario has "
                                        "none (its vehicles are listed): it would change "
                                        "nothing")
        if stream.seed is not None:
            raise SettingsError("seed", f"the scenario's stream has its own seed "
                                        f"({stream.seed}, {stream.where}): it would change "
                                        f"nothing")
    from lotsim.sim.orders import plan_run

    rr = plan_run(prepared.scenario, settings, lot_graph=prepared.lot_graph,
                  progress=progress)
    return RunResult(**{f.name: getattr(rr, f.name) for f in dataclasses.fields(rr)})
