"""How a run plans: :class:`RunSettings` (the cooperative A* variant, slot choice, the
planning order, ...), :class:`RunTuning` (how hard a car looks at each slot before it tries
another) and :class:`GASettings` (the genetic algorithm over planning orders).

Each is a frozen dataclass that validates on construction and raises
:class:`~lotsim.errors.SettingsError` (``window: expected 1 to 600 seconds, found 0``) for
the first value out of range or not one of its choices.

Examples
--------
>>> RunSettings(planner="whca", window=5).window
5.0
>>> RunSettings(planner="whca", window=0)
Traceback (most recent call last):
...
lotsim.errors.SettingsError: window: expected 1 to 600 seconds, found 0
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from lotsim.core.checks import (
    choice_problem,
    is_integral,
    is_real,
    raise_first,
    range_problem,
    set_field,
    shown,
)
from lotsim.traffic.settings import OMEGA, PLANNERS, SearchSettings

ASSIGNMENTS = ("nearest", "shortest", "priced")
"""Slot choice: straight-line distance from the entrance, travel time, or travel time plus
the delay the car's maneuvers are expected to cause the others
(:meth:`lotsim.sim.assignment.SlotAssigner.prices`)."""
PRIORITIES = ("arrival", "shortest_first", "ga")
"""``arrival``: online, each vehicle planned when it arrives; ``shortest_first``: booked,
the vehicle with the least static time to a slot first; ``ga``: booked, the order a
genetic algorithm finds (:mod:`lotsim.sim.orders`)."""
BOOKING_HORIZON = 60.0
"""Default of :attr:`RunSettings.horizon` [s]."""
MAX_SEED = 2**63 - 1
MAX_WINDOW = 600.0
"""Longest WHCA* window [s]."""
MAX_PENALTY = 86_400.0
"""Largest :attr:`GASettings.unparked_penalty` [s]: a day."""
MAX_BUDGET = 10**9
"""Most expansions a setting may give a search."""


# -- how hard a car looks at each slot ---------------------------------------------------------
@dataclass(frozen=True, slots=True)
class RunTuning:
    """How a run spends its searches on the slots a car could take; every field can change
    which slot a car gets and when it parks, so a result's ``settings`` hold them all.

    A car first *probes* each of its few best slots with a small budget of expansions,
    then searches fully where a probe ran out: a slot it can reach without a long wait is
    found within the probe, so the car does not queue behind cars parking in its best slot's
    aisle while a slot in another aisle is free to reach.

    Attributes
    ----------
    probes : int
        Slots a car probes, 1 to 1000: its best, then the best in each other aisle,
        then the next best (when the best cannot be reached in time its aisle is busy, and
        its neighbours seldom can be).
    probe_floor : int
        Fewest expansions a probe gets, 1 to 10**9.
    probe_rate : float
        Expansions a probe gets per second of the slot's static time from the
        entrance (at least ``probe_floor``), at least 0: a far slot gets a budget as long as
        its way.
    congested_for : float
        How long an aisle counts as congested after a probe into it ran out [s], at least
        0 (0: never): meanwhile the next cars look first at their best slots in the other
        aisles, where a probe seldom runs out, and at its slots only after those.
    heuristics_kept : int
        Reverse searches towards a slot a run keeps for the next searches there, at least
        0: memory against time (a kept one answers as a new one would, so no plan changes).
    skip_fruitless : bool
        WHCA*: skip a replan when nothing another car reserved was dropped or cut short
        since the car last searched: the replan could then only find what the last search
        passed over by its weighted heuristic, milliseconds in practice.
    flow_window : float
        ``priced`` assignment: the flows of cars in and out it prices a slot by are those
        seen over this many seconds before the car (1 to 86 400 [s]).
    """

    probes: int = 3
    probe_floor: int = 400
    probe_rate: float = 8.0
    congested_for: float = 5.0
    heuristics_kept: int = 16
    skip_fruitless: bool = True
    flow_window: float = 600.0

    def __post_init__(self) -> None:
        checks = [("probes", range_problem(self.probes, 1, 1000, integer=True)),
                  ("probe_floor", range_problem(self.probe_floor, 1, MAX_BUDGET, integer=True)),
                  ("probe_rate", range_problem(self.probe_rate, 0, MAX_BUDGET)),
                  ("congested_for", range_problem(self.congested_for, 0, MAX_WINDOW * 6,
                                               " seconds")),
                  ("heuristics_kept", range_problem(self.heuristics_kept, 0, 100_000,
                                                    integer=True)),
                  ("flow_window", range_problem(self.flow_window, 1, MAX_PENALTY, " seconds"))]
        if not isinstance(self.skip_fruitless, bool):
            checks.append(("skip_fruitless", f"expected true or false, found "
                                             f"{self.skip_fruitless!r}"))
        raise_first([(k, m) for k, m in checks if m is not None])
        for name in ("probe_rate", "congested_for", "flow_window"):
            set_field(self, name, float(getattr(self, name)))


# -- the genetic algorithm over planning orders -----------------------------------------------
@dataclass(frozen=True, slots=True)
class GASettings:
    """The genetic algorithm over planning orders (:func:`lotsim.sim.orders.genetic_order`).

    Attributes
    ----------
    population : int
        Orders per generation, 2 to 10000; the first holds the arrival order, shortest
        first, and random orders.
    generations : int
        Generations bred after the first, 0 to 100000.
    seed : int
        Seed of the GA's ``numpy.random.Generator`` (independent of the traffic's).
    mutation : float
        Chance that a child has two of its vehicles swapped (once more with the same
        chance, and so on), 0 to 1.
    elite : int
        Best orders carried over unchanged, 0 to ``population``.
    tournament : int
        Orders drawn for each parent (at least 1); the fittest is taken.
    unparked_penalty : float
        Seconds a vehicle that never parks adds to an order's fitness beyond the traffic's
        patience (:func:`lotsim.sim.orders.fitness`), at least 0: an order that turns a car
        away must score worse than one that parks it late.
    """

    population: int = 12
    generations: int = 10
    seed: int = 0
    mutation: float = 0.5
    elite: int = 2
    tournament: int = 3
    unparked_penalty: float = 600.0

    def __post_init__(self) -> None:
        checks = [("population", range_problem(self.population, 2, 10_000, integer=True)),
                  ("generations", range_problem(self.generations, 0, 100_000, integer=True)),
                  ("seed", range_problem(self.seed, 0, MAX_SEED, integer=True)),
                  ("mutation", range_problem(self.mutation, 0, 1)),
                  ("tournament", range_problem(self.tournament, 1, 10_000, integer=True)),
                  ("unparked_penalty", range_problem(self.unparked_penalty, 0, MAX_PENALTY,
                                                     " seconds"))]
        if checks[0][1] is None:
            checks.append(("elite", range_problem(self.elite, 0, self.population, integer=True)))
        raise_first([(k, m) for k, m in checks if m is not None])
        set_field(self, "unparked_penalty", float(self.unparked_penalty))


# -- a run --------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class RunSettings:
    """How :func:`lotsim.run` plans; checked on construction.

    Attributes
    ----------
    planner : {"ca", "hca", "whca"}
        The cooperative A* variant (:data:`PLANNERS`).
    assignment : {"nearest", "shortest", "priced"}
        Slot choice: straight-line distance from the entrance, or travel time
        along the graph plus the maneuver's time (and, for a car that will leave, the way
        out), or that time plus the delay its maneuvers are expected to cause the cars
        that pass (``priced``: :meth:`lotsim.sim.assignment.SlotAssigner.prices`).
    seed : int or None
        Seed of the traffic stream, 0 to 2**63-1 (None: the scenario's).
    window : float
        WHCA*: the vehicle replans every ``window / 2`` seconds while it drives and keeps
        the new plan when it arrives sooner, 1 to 600 [s].
    omega : float
        The expansion limit's factor, at least 1.
    retry : float
        Wait before a vehicle whose search failed tries again [s], positive; it doubles
        with each failure in a row, up to a minute.
    order : tuple of str or None
        None: each vehicle is planned when it arrives, earlier arrivals first (online).
        Otherwise every vehicle id once: the traffic is booked ``horizon`` seconds ahead.
        Arrivals are cut into batches ``horizon`` long from the first one; the vehicles of
        a batch are planned at its start, in this order (their priority), each from its
        own arrival time, against the reservations of those planned before it — later
        arrivals of the batch included. Slots freed by departures go to queued vehicles
        in this order. An order given is planned as given, whatever ``priority`` says:
        a run's result holds the settings with the order its priority chose, so running
        them again plans the same run without searching again.
    horizon : float
        How far ahead booked traffic is known [s], positive (``inf``: all of it, one
        batch). Slots are assigned when a batch is planned, so slots freed by departures
        during a batch go unseen by its vehicles: a long horizon can cost more than a
        better order gains.
    priority : {"arrival", "shortest_first", "ga"}
        How the planning order is chosen when ``order`` is None (:data:`PRIORITIES`):
        online in arrival order, or booked (``horizon``) shortest static time first, or
        booked in the best order the genetic algorithm finds (total time to park).
    ga : GASettings
        The genetic algorithm, for ``priority="ga"``.
    tuning : RunTuning
        How hard a car looks at each slot before it tries another.
    search : SearchSettings
        The cooperative search's own tuning (:class:`~lotsim.traffic.settings.SearchSettings`:
        speed levels, express edges, the reservations' chunks, the heuristic's weight, ...).
    """

    planner: str = "hca"
    assignment: str = "shortest"
    seed: int | None = None
    window: float = 10.0
    omega: float = OMEGA
    retry: float = 5.0
    order: tuple[str, ...] | None = None
    horizon: float = BOOKING_HORIZON
    priority: str = "arrival"
    ga: GASettings = field(default_factory=GASettings)
    tuning: RunTuning = field(default_factory=RunTuning)
    search: SearchSettings = field(default_factory=SearchSettings)

    def __post_init__(self) -> None:
        raise_first(self._problems())
        for name in ("window", "omega", "retry", "horizon"):
            set_field(self, name, float(getattr(self, name)))
        if self.seed is not None:
            set_field(self, "seed", int(self.seed))
        if self.order is not None:
            set_field(self, "order", tuple(self.order))

    def _problems(self) -> list[tuple[str, str]]:
        out = []
        for name, choices in (("planner", PLANNERS), ("assignment", ASSIGNMENTS),
                              ("priority", PRIORITIES)):
            problem = choice_problem(getattr(self, name), choices)
            if problem:
                out.append((name, problem))
        if self.seed is not None and not is_integral(self.seed):
            out.append(("seed", f"expected an integer, found {self.seed!r}"))
        elif self.seed is not None and not 0 <= self.seed <= MAX_SEED:
            out.append(("seed", f"expected 0 to 2**63-1, found {self.seed}"))
        problem = range_problem(self.window, 1, MAX_WINDOW, " seconds")
        if problem:
            out.append(("window", problem))
        if not (is_real(self.omega) and math.isfinite(self.omega) and self.omega >= 1):
            out.append(("omega", f"expected a number of at least 1, found "
                                  f"{shown(self.omega)}"))
        if not (is_real(self.retry) and math.isfinite(self.retry) and self.retry > 0):
            out.append(("retry", f"expected a positive number of seconds, found "
                                  f"{shown(self.retry)}"))
        if not (is_real(self.horizon) and self.horizon > 0):  # inf: all of it; nan fails
            out.append(("horizon", f"expected a positive number of seconds, found "
                                    f"{shown(self.horizon)}"))
        if self.order is not None:
            if isinstance(self.order, str) or not isinstance(self.order, Sequence) or not all(
                    isinstance(v, str) for v in self.order):
                out.append(("order", f"expected a sequence of vehicle ids, found "
                                      f"{self.order!r}"))
            elif len(set(self.order)) != len(self.order):
                twice = next(v for v in self.order if self.order.count(v) > 1)
                out.append(("order", f"expected every vehicle id of the traffic exactly "
                                      f"once, found {twice!r} twice"))
        if not isinstance(self.ga, GASettings):
            out.append(("ga", f"expected GASettings, found {self.ga!r}"))
        if not isinstance(self.tuning, RunTuning):
            out.append(("tuning", f"expected RunTuning, found {self.tuning!r}"))
        if not isinstance(self.search, SearchSettings):
            out.append(("search", f"expected SearchSettings, found {self.search!r}"))
        return out
