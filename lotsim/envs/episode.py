"""One episode of the parking operator: a stepped run (:class:`~lotsim.sim.live.Live` with
the :data:`~lotsim.sim.policies.ASK` policy) whose slot choices are the actions, read as
arrays.

The Gymnasium and PettingZoo environments (:mod:`lotsim.envs.operator`,
:mod:`lotsim.envs.parallel`) are thin wrappers over :class:`Episode`; this module needs
numpy only. What an episode gives the learner:

* the **slots** in a fixed order (:class:`LotIndex`: the lot's own order, ``lot.slots``),
  an action being a slot's index, or the last index to wait;
* the **mask** of the actions the lot can honour now: the free slots the car at the gate
  can use (those :meth:`~lotsim.sim.live.Live.decide` accepts), and waiting;
* the **features** (:func:`features`), each scaled into [0, 1];
* the **cost** of each car once it is settled (:meth:`Episode.settle`): the minutes from
  its arrival to standing in its slot, or :attr:`OperatorSettings.rejected_cost` for a
  car that never parked (turned away, or still waiting when the run ended).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from lotsim.core.checks import choice_problem, raise_first, range_problem, set_field
from lotsim.errors import DecisionError, SettingsError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.scenario import Scenario
from lotsim.sim.live import Live
from lotsim.sim.policies import ASK, SlotRequest
from lotsim.sim.preparation import PreparedLot, prepare_lot
from lotsim.sim.results import RunResult
from lotsim.sim.settings import ASSIGNMENTS, RunSettings
from lotsim.traffic.demand import PATIENCE

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
"""The shipped scenarios (a checkout of the repository): ``scenarios/*.yaml`` and
``scenarios/lots/*.yaml``, each named by its file's stem."""
MOVING = ("driving", "parking", "leaving")
"""The phases (:data:`lotsim.sim.live.PHASES`) of a car counted on an aisle: on its lanes,
not parked."""
REFUSED = ("wait", "raise")
"""What an action the lot cannot honour does (:attr:`OperatorSettings.refused`)."""
SPAN_WITHOUT_PATIENCE = 3600.0
"""The default horizon's allowance after the last arrival when the traffic waits for ever
[s]."""


@dataclass(frozen=True, slots=True)
class OperatorSettings:
    """How an episode is read and scored; checked on construction
    (:class:`~lotsim.errors.SettingsError`).

    Attributes
    ----------
    horizon : float or None
        Run time after which the episode is truncated at its next decision [s], more than
        0; None: the traffic's last arrival plus its patience (when every car has had its
        chances, so the episode ends with the run). The time feature is the run time over
        it.
    time_cap : float
        Static times are seen up to this [s] (the feature is ``min(t, cap) / cap``), more
        than 0.
    queue_cap, aisle_cap : int
        Cars queued at a gate, and cars on an aisle's lanes, are seen up to this many, at
        least 1.
    rejected_cost : float
        Minutes a car that never parks costs (turned away after its patience, or waiting
        when the run ended), at least 0.
    refused : {"wait", "raise"}
        An action the lot cannot honour (a masked slot): the car waits, at a cost of
        ``refused_cost`` minutes, and ``info["refused"]`` says which slot and why; or
        :class:`~lotsim.errors.DecisionError` naming them is raised.
    refused_cost : float
        Minutes an action refused costs, at least 0.
    rankings : tuple of str
        The run's rankings whose best slot ``info["best"]`` gives (of
        :data:`~lotsim.sim.settings.ASSIGNMENTS`; all by default): each costs a step some
        time (``priced`` the most), and a learner that reads none can leave them out.
    """

    horizon: float | None = None
    time_cap: float = 300.0
    queue_cap: int = 10
    aisle_cap: int = 10
    rejected_cost: float = 10.0
    refused: str = "wait"
    refused_cost: float = 1.0
    rankings: tuple[str, ...] = ASSIGNMENTS

    def __post_init__(self) -> None:
        checks = [("horizon", None if self.horizon is None
                   else range_problem(self.horizon, 1e-9, 1e9, " seconds")),
                  ("time_cap", range_problem(self.time_cap, 1e-9, 1e9, " seconds")),
                  ("queue_cap", range_problem(self.queue_cap, 1, 10**6, integer=True)),
                  ("aisle_cap", range_problem(self.aisle_cap, 1, 10**6, integer=True)),
                  ("rejected_cost", range_problem(self.rejected_cost, 0, 1e9, " minutes")),
                  ("refused", choice_problem(self.refused, REFUSED)),
                  ("refused_cost", range_problem(self.refused_cost, 0, 1e9, " minutes"))]
        if isinstance(self.rankings, str) or not all(isinstance(r, str)
                                                      for r in self.rankings):
            checks.append(("rankings", f"expected a sequence of {', '.join(ASSIGNMENTS)}, "
                                       f"found {self.rankings!r}"))
        else:
            checks += [("rankings", choice_problem(r, ASSIGNMENTS)) for r in self.rankings]
        raise_first([(k, m) for k, m in checks if m is not None])
        set_field(self, "rankings", tuple(dict.fromkeys(self.rankings)))
        for name in ("time_cap", "rejected_cost", "refused_cost"):
            set_field(self, name, float(getattr(self, name)))
        if self.horizon is not None:
            set_field(self, "horizon", float(self.horizon))


# -- the lot behind an episode -------------------------------------------------------------------
def shipped_scenarios() -> dict[str, Path]:
    """The shipped scenarios by name (``"quickstart"``, ``"mixed_lot"``, ``"ring"``, ...):
    empty where lotsim is installed without its repository's ``scenarios/`` folder."""
    found = {}
    for folder in (SCENARIOS / "lots", SCENARIOS):
        found.update({p.stem: p for p in sorted(folder.glob("*.yaml"))})
    return dict(sorted(found.items()))


def prepared_lot(scenario: PreparedLot | Scenario | str | os.PathLike) -> PreparedLot:
    """The prepared lot behind an episode: a :class:`PreparedLot` as it is; a
    :class:`Scenario`, a scenario file, its YAML text or a shipped scenario's name
    (:func:`shipped_scenarios`) prepared (from the on-disk cache when it can).

    Raises
    ------
    SettingsError
        For a name that is no shipped scenario (and no file), or something else.
    ScenarioError
        For a scenario that does not hold together.
    """
    if isinstance(scenario, PreparedLot):
        return scenario
    if isinstance(scenario, str) and "\n" not in scenario and not Path(scenario).exists():
        shipped = shipped_scenarios()
        if scenario in shipped:
            scenario = shipped[scenario]
        elif "/" not in scenario and not scenario.endswith((".yaml", ".yml")):
            there = ", ".join(shipped) or "none: lotsim's repository is not beside it"
            raise SettingsError("scenario", f"expected a shipped scenario's name ({there}), "
                                            f"a scenario file or its text, found "
                                            f"{scenario!r}")
    if isinstance(scenario, (str, os.PathLike)):
        scenario = load_scenario(scenario)
    if not isinstance(scenario, Scenario):
        raise SettingsError("scenario", f"expected a PreparedLot, a Scenario, a path, YAML "
                                        f"text or a shipped scenario's name, found "
                                        f"{type(scenario).__name__}")
    return prepare_lot(scenario)


def run_settings(prepared: PreparedLot, settings: RunSettings | None) -> RunSettings:
    """The run's settings for an operator's episodes: ``settings`` (the defaults when
    None), which must plan cars as they come.

    Raises
    ------
    SettingsError
        For settings that are no :class:`RunSettings`, a booked planning order, or a
        scenario without traffic.
    """
    settings = RunSettings() if settings is None else settings
    if not isinstance(settings, RunSettings):
        raise SettingsError("settings", f"expected RunSettings, found "
                                        f"{type(settings).__name__}")
    if settings.priority != "arrival" or settings.order is not None:
        raise SettingsError("priority", f"the operator chooses each car's slot as it comes: "
                                        f"expected 'arrival', found {settings.priority!r}")
    if prepared.scenario.traffic is None:
        raise SettingsError("scenario", f"{prepared.scenario.name!r} has no traffic: an "
                                        f"episode needs cars to park")
    return settings


def seeds_traffic(prepared: PreparedLot) -> bool:
    """Whether the run's seed draws the scenario's traffic: it has a stream without a seed
    of its own (listed cars are the same whatever the seed)."""
    traffic = prepared.scenario.traffic
    return traffic is not None and any(s.seed is None for s in traffic.streams)


@dataclass(frozen=True)
class LotIndex:
    """The fixed order of what a lot's arrays hold: its slots (``lot.slots``' order), its
    vehicle types (the scenario's), its entrances and its aisles (by name)."""

    slots: tuple[str, ...]
    types: tuple[str, ...]
    gates: tuple[str, ...]
    aisles: tuple[str, ...]

    @classmethod
    def of(cls, prepared: PreparedLot) -> LotIndex:
        lg = prepared.lot_graph
        return cls(tuple(s.id for s in lg.lot.slots),
                   tuple(t.name for t in prepared.scenario.vehicle_types),
                   tuple(sorted(lg.entrances)), tuple(sorted(lg.lot.aisles)))

    @property
    def wait(self) -> int:
        """The action that waits: the last."""
        return len(self.slots)

    @functools.cached_property
    def _position(self) -> dict[str, int]:
        return {sid: k for k, sid in enumerate(self.slots)}

    def slot_of(self, sid: str) -> int:
        """The index of slot ``sid``."""
        return self._position[sid]

    def sizes(self) -> dict[str, int]:
        """Each feature's length (:func:`features`)."""
        n = len(self.slots)
        return {"occupancy": n, "vehicle": len(self.types), "entrance": len(self.gates),
                "static_time": n, "queues": len(self.gates), "aisles": len(self.aisles),
                "time": 1}


def features(index: LotIndex, rules: OperatorSettings, state: dict, horizon: float,
             car: dict | None, request: SlotRequest | None) -> dict[str, np.ndarray]:
    """What the operator sees (each ``float32`` in [0, 1], in :meth:`LotIndex.sizes`):

    ``occupancy``
        1 for a slot that holds a car or one on its way to it (or taken at the start);
    ``vehicle``, ``entrance``
        the car's type and gate, one-hot (``car``: its :meth:`~lotsim.sim.live.Live.state`
        entry; zeros without one);
    ``static_time``
        each slot's static time for the car (``request``: its choice; the way in and the
        maneuver, and the way out for a car that will leave), ``min(t, time_cap) /
        time_cap``; 1 for a slot it cannot take now;
    ``queues``
        cars queued outside each gate, up to ``queue_cap``, over it;
    ``aisles``
        cars on each aisle's lanes (not parked), up to ``aisle_cap``, over it;
    ``time``
        the run time over ``horizon``, at most 1.
    """
    n = len(index.slots)
    occupancy = np.array([state["occupancy"][s] is not None for s in index.slots],
                         dtype=np.float32)
    vehicle = np.zeros(len(index.types), dtype=np.float32)
    entrance = np.zeros(len(index.gates), dtype=np.float32)
    if car is not None:
        vehicle[index.types.index(car["type"])] = 1.0
        if car["entrance"] is not None:
            entrance[index.gates.index(car["entrance"])] = 1.0
    static = np.ones(n, dtype=np.float32)
    if request is not None:
        cap = rules.time_cap
        for sid, tt in request.static_times.items():
            static[index.slot_of(sid)] = min(tt, cap) / cap
    queues = np.array([min(len(state["queues"][g]), rules.queue_cap) / rules.queue_cap
                       for g in index.gates], dtype=np.float32)
    phase = {c["id"]: c["phase"] for c in state["cars"]}
    aisles = np.array([min(sum(phase[c] in MOVING for c in state["aisles"][a]),
                           rules.aisle_cap) / rules.aisle_cap for a in index.aisles],
                      dtype=np.float32)
    time = np.array([min(max(state["time"], 0.0) / horizon, 1.0)], dtype=np.float32)
    return {"occupancy": occupancy, "vehicle": vehicle, "entrance": entrance,
            "static_time": static, "queues": queues, "aisles": aisles, "time": time}


def mask(index: LotIndex, request: SlotRequest | None) -> np.ndarray:
    """The actions the lot can honour now (``int8``, 1 for each): the slots of ``request``
    (the free slots its car can take) and waiting; waiting alone without one."""
    out = np.zeros(len(index.slots) + 1, dtype=np.int8)
    out[index.wait] = 1
    if request is not None:
        out[[index.slot_of(s) for s in request.slots]] = 1
    return out


# -- an episode -----------------------------------------------------------------------------------
class Episode:
    """One run of a prepared lot whose slot choices are taken as actions.

    Parameters
    ----------
    prepared : PreparedLot
    settings : RunSettings
        How to plan (:func:`run_settings`); its ``seed`` is replaced by ``seed`` where the
        seed draws the traffic (:func:`seeds_traffic`).
    rules : OperatorSettings
    seed : int
        The episode's seed: the traffic stream drawn from it.
    index : LotIndex, optional
        The lot's order (made when not given).
    """

    def __init__(self, prepared: PreparedLot, settings: RunSettings, rules: OperatorSettings,
                 seed: int, *, index: LotIndex | None = None) -> None:
        if seeds_traffic(prepared):
            settings = dataclasses.replace(settings, seed=int(seed))
        self.prepared, self.settings, self.rules = prepared, settings, rules
        self.index = index or LotIndex.of(prepared)
        self.live = Live(prepared, settings, policy=ASK)
        self.costs: dict[str, float] = {}  # each car settled so far: its cost [min]
        self.refusals = 0
        self.truncated = False
        self._result: RunResult | None = None
        cars = self.live.state()["cars"]
        if rules.horizon is not None:
            self.horizon = rules.horizon
        else:
            traffic = prepared.scenario.traffic
            patience = traffic.patience if traffic is not None else PATIENCE
            last = max((c["arrival"] for c in cars), default=0.0)
            self.horizon = max(last + (patience if math.isfinite(patience)
                                       else SPAN_WITHOUT_PATIENCE), 1.0)
        self.request: SlotRequest | None = None
        self._next()

    @property
    def done(self) -> bool:
        """Whether the episode is over: the run ended, or it reached the horizon."""
        return self._result is not None or self.truncated

    def _next(self) -> None:
        """On to the next choice: the run ends when none is left (its result kept), and the
        episode is truncated at a choice past the horizon."""
        self.request = self.live.next_decision()
        if self.request is None:
            self._result = self.live.finish()
        elif self.request.time > self.horizon:
            self.truncated = True

    def act(self, action: int) -> str | None:
        """Take ``action`` for the car that waits for a choice (a slot's index, or
        :attr:`LotIndex.wait`) and go on to the next choice; what was refused, and why,
        when the lot could not honour it (the car then waits).

        Raises
        ------
        SettingsError
            For an action out of range, or an episode that is over.
        DecisionError
            For an action the lot cannot honour, with ``rules.refused == "raise"``.
        """
        if self.done:
            raise SettingsError("action", "the episode is over: reset it")
        if isinstance(action, np.ndarray) and action.shape == ():
            action = action.item()
        if not (isinstance(action, (int, np.integer)) and 0 <= action <= self.index.wait):
            raise SettingsError("action", f"expected a slot's index (0 to "
                                          f"{self.index.wait - 1}) or {self.index.wait} to "
                                          f"wait, found {action!r}")
        slot = None if action == self.index.wait else self.index.slots[int(action)]
        refused = None
        try:
            self.live.decide(slot)
        except DecisionError as err:
            if self.rules.refused == "raise":
                raise
            refused = str(err)
            self.refusals += 1
            self.live.decide(None)
        self._next()
        return refused

    def state(self) -> dict:
        """The run now (:meth:`lotsim.sim.live.Live.state`)."""
        return self.live.state()

    def settle(self, state: dict) -> dict[str, float]:
        """The cars settled since the last call, each with its cost [min]: a car standing in
        its slot, the minutes from its arrival (none for a car that was inside the lot when
        it came); one turned away, ``rules.rejected_cost``. When the run has ended, every
        car not settled yet is, by its result: those that never parked cost
        ``rejected_cost``."""
        new: dict[str, float] = {}
        if self._result is not None:
            for v in self._result.vehicles:
                if v.id not in self.costs:
                    new[v.id] = self._cost(v.arrival.entrance, v.arrival.time, v.parked_at)
        else:
            for c in state["cars"]:
                if c["id"] not in self.costs and (c["parked_at"] is not None
                                                  or c["phase"] == "rejected"):
                    new[c["id"]] = self._cost(c["entrance"], c["arrival"], c["parked_at"])
        self.costs.update(new)
        return new

    def _cost(self, entrance: str | None, arrival: float, parked_at: float | None) -> float:
        if parked_at is None:
            return self.rules.rejected_cost
        return 0.0 if entrance is None else (parked_at - arrival) / 60.0

    def info(self, refused: str | None = None) -> dict:
        """What the operator is told beside the features: ``action_mask``; for the car that
        waits for a choice, its ``car``, ``vehicle``, ``entrance`` and the ``time`` [s],
        ``static_times`` (each slot's [s], ``inf`` for one it cannot take now, ``float64``)
        and ``best``: the best slot's index by each of the run's rankings
        (:data:`~lotsim.sim.settings.ASSIGNMENTS`, those of ``rules.rankings``);
        ``refused`` when the last action was (what and why); ``metrics`` once the run has
        ended (its counts and times to park, :meth:`~lotsim.sim.results.RunResult.metrics`
        without the planning times)."""
        out: dict = {"action_mask": mask(self.index, None if self.done else self.request)}
        r = self.request
        if r is not None and not self.done:
            times = np.full(len(self.index.slots), np.inf)
            for sid, tt in r.static_times.items():
                times[self.index.slot_of(sid)] = tt
            out.update(car=r.car, vehicle=r.vehicle, entrance=r.entrance, time=r.time,
                       static_times=times,
                       best={by: self.index.slot_of(r.ranked(by)[0])
                             for by in self.rules.rankings})
        if refused is not None:
            out["refused"] = refused
        if self._result is not None:
            out["metrics"] = {k: v for k, v in self._result.metrics().items()
                              if not k.startswith("planning_time")}
        return out

    def result(self) -> RunResult:
        """The episode's run as a :class:`RunResult` (:func:`lotsim.check` verifies it):
        once it ended, the run's; once truncated, the run carried to its end with the
        choices past the horizon taken by the run's own ranking (``settings.assignment``).

        Raises
        ------
        SettingsError
            While the episode goes on.
        """
        if self._result is None:
            if not self.truncated:
                raise SettingsError("result", "the episode goes on: step it to its end first")
            request = self.request
            while request is not None:
                self.live.decide(request.ranked(self.settings.assignment))
                request = self.live.next_decision()
            self._result = self.live.finish()
        return self._result
