"""Traffic: the vehicles that come to a lot, when, where, and how long they stay.

A scenario's ``traffic`` lists vehicles one by one, or as a stream drawn from a
seeded :class:`numpy.random.Generator` (exponential gaps at a rate per hour, a
mix of types, optional dwell times). :func:`arrivals` turns both into one list
in arrival order.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from lotsim.errors import Location

PATIENCE = 600.0
"""Default time a vehicle waits outside for a slot or a route before it is turned away [s]."""


@dataclass(frozen=True, slots=True)
class Arrival:
    """One vehicle: ``id``, its type's name, the entrance it arrives at, the arrival time
    [s], and how long it stays once parked [s] (None: it stays).

    A car already inside the lot has no entrance (None) but ``slot``, the bay it stands in
    from ``time`` (to be called out ``dwell`` seconds later), or ``pose``, where it stands
    on a lane (a roadmap node's ``(x, y, theta)``) from ``time``, holding its space until it
    sets off for a slot."""

    id: str
    vehicle: str
    entrance: str | None
    time: float
    dwell: float | None = None
    where: Location | None = field(default=None, repr=False, compare=False)
    slot: str | None = None
    pose: tuple[float, float, float] | None = None

    @property
    def inside(self) -> bool:
        """Whether the car is inside the lot when it comes (in a bay, or on a lane)."""
        return self.entrance is None


@dataclass(frozen=True, slots=True)
class StreamSpec:
    """``count`` vehicles arriving at ``rate`` per second (exponential gaps) from ``start``
    [s], types drawn by ``mix`` weights, entrances uniformly, dwell uniform in
    ``dwell`` (min, max) [s] or None; ``seed`` None means the run's seed."""

    count: int
    rate: float
    mix: tuple[tuple[str, float], ...]
    entrances: tuple[str, ...]
    start: float = 0.0
    dwell: tuple[float, float] | None = None
    seed: int | None = None
    prefix: str = "s"
    where: Location | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True, slots=True)
class TrafficSpec:
    """The vehicles listed one by one, an optional stream, and the patience [s]."""

    vehicles: tuple[Arrival, ...] = ()
    stream: StreamSpec | None = None
    patience: float = PATIENCE
    where: Location | None = field(default=None, repr=False, compare=False)


def draw_stream(stream: StreamSpec, rng: np.random.Generator) -> list[Arrival]:
    """The stream's vehicles, drawn from ``rng``.

    Examples
    --------
    >>> s = StreamSpec(count=3, rate=30 / 3600, mix=(("valet", 1.0),), entrances=("in",))
    >>> [a.id for a in draw_stream(s, np.random.default_rng(0))]
    ['s01', 's02', 's03']
    """
    n = stream.count
    gaps = rng.exponential(1.0 / stream.rate, size=n)
    times = stream.start + np.cumsum(gaps) - gaps[0]  # the first arrives at ``start``
    names = [m for m, _ in stream.mix]
    w = np.array([w for _, w in stream.mix], dtype=float)
    kinds = rng.choice(len(names), size=n, p=w / w.sum())
    gates = rng.integers(0, len(stream.entrances), size=n)
    dwell = (rng.uniform(stream.dwell[0], stream.dwell[1], size=n)
             if stream.dwell is not None else [None] * n)
    width = len(str(n)) if n >= 10 else 2
    return [
        Arrival(f"{stream.prefix}{k + 1:0{width}d}", names[kinds[k]],
                stream.entrances[gates[k]], round(float(times[k]), 3),
                None if dwell[k] is None else round(float(dwell[k]), 3), stream.where)
        for k in range(n)
    ]


def arrivals(traffic: TrafficSpec, seed: int) -> list[Arrival]:
    """Every vehicle of ``traffic`` in arrival order (ties by id); the stream is drawn
    with its own seed, or ``seed``."""
    out = list(traffic.vehicles)
    if traffic.stream is not None:
        s = traffic.stream
        out += draw_stream(s, np.random.default_rng(seed if s.seed is None else s.seed))
    return sorted(out, key=lambda a: (a.time, a.id))
