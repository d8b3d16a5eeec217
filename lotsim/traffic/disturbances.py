"""Disturbances: what makes real cars depart from their plans — starts that come late, cars
slower than planned, cars that stall — as a frozen spec (:class:`Disturbances`) and what it
draws for one run (:func:`draw`), every random part from the run's seeded generator.

How a run is driven under them, without a collision, is :mod:`lotsim.sim.execution`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from lotsim.core.checks import raise_first, range_problem, set_field
from lotsim.errors import Location

MAX_LATE = 3600.0
"""Longest late start [s]."""
MAX_STALL = 86_400.0
"""Longest stall [s]: a day."""
MAX_STALL_RATE = 3600.0
"""Most stalls an hour."""
MAX_TIME = 1e9
"""Latest time a disturbance may be set at [s]."""
REPAIR_AFTER = 30.0
"""How long a car held up on the lanes waits past its plan before it is planned again, by
default [s] (:attr:`Disturbances.repair_after`)."""


@dataclass(frozen=True, slots=True)
class Stall:
    """Car ``car`` stalls at time ``at`` [s] for ``duration`` [s]: it stops at the first
    place its plan brings it to rest at or after ``at`` on the lanes (not in a slot, not
    queued at a gate) and stands there that long before it can go on."""

    car: str
    at: float
    duration: float

    def __post_init__(self) -> None:
        checks = [("stalls.car", None if isinstance(self.car, str) and self.car else
                   f"expected a car id, found {self.car!r}"),
                  ("stalls.at", range_problem(self.at, 0, MAX_TIME, " s")),
                  ("stalls.duration", range_problem(self.duration, 0, MAX_STALL, " seconds"))]
        raise_first([(k, m) for k, m in checks if m is not None])
        set_field(self, "at", float(self.at))
        set_field(self, "duration", float(self.duration))


CLOSABLE = ("aisle", "lane", "gate")
"""What a :class:`Closure` may close: an aisle (its whole paved width), one lane of a
two-way aisle (its side of the aisle, the other lane staying open; a one-way aisle's lane
is the whole aisle), or a gate (an entrance or exit: the ground a car stands on there)."""


@dataclass(frozen=True, slots=True)
class Closure:
    """The ``kind`` (:data:`CLOSABLE`) ``id`` is closed from ``start`` to ``end`` [s]: from
    ``start`` no car enters it (cars already in it, or driving into it then, go on as
    planned), and those whose plans pass it then are planned again."""

    kind: str
    id: str
    start: float
    end: float
    where: Location | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        checks = [("closures.kind", None if self.kind in CLOSABLE else
                   f"expected one of {', '.join(CLOSABLE)}, found {self.kind!r}"),
                  ("closures.id", None if isinstance(self.id, str) and self.id else
                   f"expected an id, found {self.id!r}"),
                  ("closures.start", range_problem(self.start, 0, MAX_TIME, " s")),
                  ("closures.end", range_problem(self.end, 0, MAX_TIME, " s"))]
        if all(m is None for _, m in checks) and self.end <= self.start:
            checks.append(("closures.end", f"expected a time after start ({self.start:g} "
                                           f"s), found {self.end:g}"))
        raise_first([(k, m) for k, m in checks if m is not None])
        set_field(self, "start", float(self.start))
        set_field(self, "end", float(self.end))


@dataclass(frozen=True, slots=True)
class TakenBay:
    """At time ``at`` [s] a car the plan does not know parks in ``slot`` and stays: a car
    that was to park there (and has not begun to) is given another."""

    slot: str
    at: float
    where: Location | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        checks = [("taken.slot", None if isinstance(self.slot, str) and self.slot else
                   f"expected a slot id, found {self.slot!r}"),
                  ("taken.at", range_problem(self.at, 0, MAX_TIME, " s"))]
        raise_first([(k, m) for k, m in checks if m is not None])
        set_field(self, "at", float(self.at))


@dataclass(frozen=True, slots=True)
class Disturbances:
    """What departs from the plan in a run (all off by default).

    Attributes
    ----------
    late_probability : float
        Chance that a car sets off late from a standstill (each time it sets off: from
        its gate, after a wait, out of its slot), 0 to 1.
    late_max : float
        How late such a start is: uniform in ``(0, late_max]`` [s], 0 to 3600.
    speed : tuple of float
        Each car drives ``factor`` times as fast as planned, ``factor`` drawn uniformly
        from ``(lo, hi)``, ``0.1 ≤ lo ≤ hi ≤ 1`` (``(1, 1)``: as planned).
    stall_rate : float
        Stalls an hour over the whole lot, at exponential gaps from the first arrival; each
        stops a car chosen uniformly among those on the lanes then (:class:`Stall`), 0 to
        3600.
    stall_duration : tuple of float
        How long a drawn stall lasts: uniform in ``(lo, hi)`` [s].
    stalls : tuple of Stall
        Stalls at given times, besides the drawn ones.
    closures : tuple of Closure
        Aisles and gates closed over an interval.
    taken : tuple of TakenBay
        Bays taken by cars the plan does not know.
    repair_after : float or None
        A car at rest on the lanes that has waited this long [s] past the moment its plan
        had it set off (held up by the cars the plan has pass before it) is planned again
        from where it stands, and takes the new way when it brings it to its slot, or out,
        sooner (:mod:`lotsim.sim.rerouting`); 1 to 3600, or None: it always waits its turn.
    seed : int or None
        Seed of the generator the random parts are drawn from (None: the run's seed).

    Examples
    --------
    >>> Disturbances(late_probability=0.1, late_max=5).active
    True
    >>> Disturbances(late_probability=2)
    Traceback (most recent call last):
    ...
    lotsim.errors.SettingsError: late_probability: expected 0 to 1, found 2
    """

    late_probability: float = 0.0
    late_max: float = 0.0
    speed: tuple[float, float] = (1.0, 1.0)
    stall_rate: float = 0.0
    stall_duration: tuple[float, float] = (30.0, 120.0)
    stalls: tuple[Stall, ...] = ()
    closures: tuple[Closure, ...] = ()
    taken: tuple[TakenBay, ...] = ()
    repair_after: float | None = REPAIR_AFTER
    seed: int | None = None

    def __post_init__(self) -> None:
        checks = [("late_probability", range_problem(self.late_probability, 0, 1)),
                  ("late_max", range_problem(self.late_max, 0, MAX_LATE, " seconds")),
                  ("stall_rate", range_problem(self.stall_rate, 0, MAX_STALL_RATE,
                                               " an hour"))]
        checks += _pair("speed", self.speed, 0.1, 1.0)
        checks += _pair("stall_duration", self.stall_duration, 0.0, MAX_STALL)
        if self.seed is not None:
            checks.append(("seed", range_problem(self.seed, 0, 2**63 - 1, integer=True)))
        if self.repair_after is not None:
            checks.append(("repair_after", range_problem(self.repair_after, 1, MAX_LATE,
                                                         " seconds")))
        for name, kind in (("stalls", Stall), ("closures", Closure), ("taken", TakenBay)):
            value = getattr(self, name)
            if not isinstance(value, (tuple, list)) or not all(
                    isinstance(x, kind) for x in value):
                checks.append((name, f"expected a list of {kind.__name__}, found {value!r}"))
        raise_first([(k, m) for k, m in checks if m is not None])
        for name in ("late_probability", "late_max", "stall_rate"):
            set_field(self, name, float(getattr(self, name)))
        if self.repair_after is not None:
            set_field(self, "repair_after", float(self.repair_after))
        set_field(self, "speed", tuple(float(x) for x in self.speed))
        set_field(self, "stall_duration", tuple(float(x) for x in self.stall_duration))
        for name in ("stalls", "closures", "taken"):
            set_field(self, name, tuple(getattr(self, name)))

    @property
    def active(self) -> bool:
        """Whether anything departs from the plan."""
        return self.driven or bool(self.closures) or bool(self.taken)

    @property
    def driven(self) -> bool:
        """Whether the cars depart from their plans as they drive them (late starts, slow
        cars, stalls), besides what changes the lot (closures, bays taken)."""
        return ((self.late_probability > 0 and self.late_max > 0) or self.speed != (1.0, 1.0)
                or self.stall_rate > 0 or bool(self.stalls))

    def as_dict(self) -> dict:
        """The spec as plain data, as a result's ``disturbances.settings`` holds it."""
        return {"late_probability": self.late_probability, "late_max": self.late_max,
                "speed": list(self.speed), "stall_rate": self.stall_rate,
                "stall_duration": list(self.stall_duration),
                "stalls": [{"car": s.car, "at": s.at, "duration": s.duration}
                           for s in self.stalls],
                "closures": [{"kind": c.kind, "id": c.id, "start": c.start, "end": c.end}
                             for c in self.closures],
                "taken": [{"slot": b.slot, "at": b.at} for b in self.taken],
                "repair_after": self.repair_after, "seed": self.seed}


def _pair(name: str, value, lo: float, hi: float) -> list[tuple[str, str | None]]:
    try:
        a, b = value
    except (TypeError, ValueError):
        return [(name, f"expected [low, high], found {value!r}")]
    problems = [(name, range_problem(a, lo, hi)), (name, range_problem(b, lo, hi))]
    if all(m is None for _, m in problems) and a > b:
        problems.append((name, f"expected low ≤ high, found [{a:g}, {b:g}]"))
    return problems


@dataclass(frozen=True)
class Drawn:
    """What :func:`draw` drew for one run: each car's speed factor, the late starts
    (``late[car][k]``: seconds the car's ``k``-th start from a standstill comes late) and
    the stalls, given ones first."""

    speed: dict[str, float]
    late: dict[str, list[float]]
    stalls: tuple[Stall, ...] = field(default=())


def draw(spec: Disturbances, cars: list[tuple[str, int, float, float]],
         rng: np.random.Generator) -> Drawn:
    """Draw ``spec``'s random parts for ``cars``: ``(id, starts, first, last)`` each, with
    how many times the car sets off from a standstill and the span it is on the lanes
    [s] (first set-off, last arrival; NaN when it never enters). Drawn in one fixed order:
    speeds, then late starts car by car, then stall times, cars and durations."""
    lo, hi = spec.speed
    factors = rng.uniform(lo, hi, size=len(cars)) if hi > lo else np.full(len(cars), lo)
    speed = {cid: float(f) for (cid, *_), f in zip(cars, factors, strict=True)}
    late: dict[str, list[float]] = {}
    for cid, starts, _, _ in cars:
        hit = rng.random(starts) < spec.late_probability
        by = rng.uniform(0.0, 1.0, size=starts) * spec.late_max
        late[cid] = [float(x) if h and spec.late_max > 0 else 0.0
                     for h, x in zip(hit, by, strict=True)]
    stalls = list(spec.stalls)
    spans = [(cid, first, last) for cid, _, first, last in cars if math.isfinite(first)]
    if spec.stall_rate > 0 and spans:
        t = min(first for _, first, _ in spans)
        end = max(last for _, _, last in spans)
        gap = 3600.0 / spec.stall_rate
        lo_d, hi_d = spec.stall_duration
        while True:
            t += float(rng.exponential(gap))
            if t > end:
                break
            on = [cid for cid, first, last in spans if first <= t < last]
            pick = int(rng.integers(len(on))) if on else -1
            duration = float(rng.uniform(lo_d, hi_d)) if hi_d > lo_d else lo_d
            if on:
                stalls.append(Stall(on[pick], round(t, 3), round(duration, 3)))
    return Drawn(speed, late, tuple(stalls))
