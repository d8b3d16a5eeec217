"""Traffic: the vehicles that come to a lot, when, where, and how long they stay.

A scenario's ``traffic`` lists vehicles one by one, and any number of streams drawn from a
seeded :class:`numpy.random.Generator`, each with its own ids, mix of types, entrances,
arrival rate and dwell law. A stream comes at a constant rate (``count`` cars, exponential
gaps, the first at its start) or at a rate that changes over the day (a
:class:`RateProfile`: the arrivals of a non-homogeneous Poisson process). Its cars stay
for good or for a dwell drawn from a :data:`DwellLaw` (uniform, lognormal, or an empirical
histogram). :func:`arrivals` turns it all into one list in arrival order.
"""

from __future__ import annotations

import math
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


# -- arrival rates over the day ---------------------------------------------------------------

Segment = tuple[float, float, float, float]
"""A piece of a rate profile: ``(t0, t1, r0, r1)``, the rate going linearly from ``r0`` at
``t0`` to ``r1`` at ``t1`` [s, 1/s]."""


@dataclass(frozen=True, slots=True)
class RateProfile:
    """An arrival rate that changes over time: piecewise linear (a piecewise-constant
    profile has ``r0 == r1`` in every piece), zero outside its pieces and in the gaps
    between them. ``segments`` are in time order and do not overlap.

    Examples
    --------
    >>> p = RateProfile(((0.0, 3600.0, 0.0, 0.02), (3600.0, 7200.0, 0.01, 0.01)))
    >>> p.expected(), p.expected(3600.0, 7200.0)
    (72.0, 36.0)
    >>> p.rate(np.array([1800.0, 5000.0, 9000.0])) * 3600
    array([36., 36.,  0.])
    """

    segments: tuple[Segment, ...]

    @property
    def begin(self) -> float:
        """When the profile's first piece begins [s]."""
        return self.segments[0][0]

    @property
    def end(self) -> float:
        """When its last piece ends [s]."""
        return self.segments[-1][1]

    def _array(self) -> np.ndarray:
        return np.array(self.segments, dtype=float).reshape(-1, 4)

    def rate(self, t: np.ndarray) -> np.ndarray:
        """The rate at times ``t`` [1/s] (the later piece's where two meet)."""
        t = np.asarray(t, dtype=float)
        out = np.zeros_like(t)
        for t0, t1, r0, r1 in self.segments:
            inside = (t >= t0) & (t < t1)
            out[inside] = r0 + (r1 - r0) * (t[inside] - t0) / (t1 - t0)
        return out

    def cumulative(self, t: np.ndarray | float) -> np.ndarray:
        """The integrated rate Λ(t) = ∫ λ from the profile's beginning to ``t``: the
        expected number of arrivals by then."""
        s = self._array()
        t = np.asarray(t, dtype=float)[..., None]
        x = np.clip(t - s[:, 0], 0.0, s[:, 1] - s[:, 0])
        slope = (s[:, 3] - s[:, 2]) / (s[:, 1] - s[:, 0])
        return np.sum(s[:, 2] * x + 0.5 * slope * x * x, axis=-1)

    def expected(self, t0: float | None = None, t1: float | None = None) -> float:
        """The expected number of arrivals between ``t0`` and ``t1`` [s] (default: the
        whole profile)."""
        t0 = self.begin if t0 is None else t0
        t1 = self.end if t1 is None else t1
        return float(self.cumulative(t1) - self.cumulative(t0))

    def inverse(self, v: np.ndarray) -> np.ndarray:
        """The times at which Λ reaches ``v`` (0 ≤ v ≤ Λ(end)) [s]: inside the piece that
        holds v, the root of r0·x + (r1 − r0)/(t1 − t0)·x²/2 = v − Λ(t0), in a form that
        loses no digits when the rate is flat or falling."""
        s = self._array()
        length = s[:, 1] - s[:, 0]
        mass = 0.5 * (s[:, 2] + s[:, 3]) * length
        before = np.concatenate([[0.0], np.cumsum(mass)])
        v = np.asarray(v, dtype=float)
        # the last piece whose mass begins at or below v: a piece without mass is skipped
        k = np.clip(np.searchsorted(before, v, side="right") - 1, 0, len(s) - 1)
        rest = np.maximum(v - before[k], 0.0)
        r0, slope = s[k, 2], (s[k, 3] - s[k, 2]) / length[k]
        root = np.sqrt(np.maximum(r0 * r0 + 2.0 * slope * rest, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            x = np.where(r0 + root > 0, 2.0 * rest / (r0 + root), 0.0)
        return s[k, 0] + np.clip(x, 0.0, length[k])

    def draw(self, rng: np.random.Generator) -> np.ndarray:
        """The arrival times of a non-homogeneous Poisson process of this rate, sorted [s].

        Drawn exactly by inverting the integrated rate: the number of arrivals is Poisson
        with mean Λ(end), and given it the times are independent with density λ/Λ(end)
        (the order-statistics property of the Poisson process, Cox & Lewis, *The
        Statistical Analysis of Series of Events*, 1966), each Λ⁻¹ of a uniform draw.
        """
        total = self.expected()
        n = int(rng.poisson(total))
        u = np.sort(rng.uniform(0.0, total, size=n))
        return self.inverse(u)


# -- how long a car stays ---------------------------------------------------------------------


def _clipped(x: np.ndarray, clip: tuple[float, float] | None) -> np.ndarray:
    return x if clip is None else np.clip(x, clip[0], clip[1])


@dataclass(frozen=True, slots=True)
class UniformDwell:
    """A dwell uniform between ``low`` and ``high`` [s] (equal: always that long)."""

    low: float
    high: float
    clip: tuple[float, float] | None = None

    @property
    def least(self) -> float:
        """The shortest dwell it draws [s]."""
        return self.low if self.clip is None else max(self.low, self.clip[0])

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` dwells [s] from ``rng`` (one uniform draw each)."""
        return _clipped(rng.uniform(self.low, self.high, size=n), self.clip)


@dataclass(frozen=True, slots=True)
class LognormalDwell:
    """A lognormal dwell: ln(dwell / 1 s) is normal with mean μ = ln(``median``) and
    standard deviation ``sigma``, so half the cars stay less than ``median`` [s]; then
    clipped to ``clip`` (min, max) [s], if given (a dwell drawn outside becomes the bound).

    Examples
    --------
    >>> d = LognormalDwell(median=1500.0, sigma=0.8)
    >>> x = d.draw(np.random.default_rng(1), 20_000)
    >>> round(float(np.median(x)) / 60), round(float(np.std(np.log(x))), 1)
    (25, 0.8)
    """

    median: float
    sigma: float
    clip: tuple[float, float] | None = None

    @property
    def least(self) -> float:
        """The shortest dwell it draws, or the bound below them all [s]."""
        return 0.0 if self.clip is None else self.clip[0]

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` dwells [s] from ``rng`` (one normal draw each)."""
        return _clipped(rng.lognormal(math.log(self.median), self.sigma, size=n), self.clip)


@dataclass(frozen=True, slots=True)
class HistogramDwell:
    """An empirical dwell: bins between ``edges`` [s], each chosen with its share of
    ``weights``, the dwell uniform within its bin; then clipped to ``clip`` (min, max) [s],
    if given.

    Examples
    --------
    >>> d = HistogramDwell(edges=(600.0, 1200.0, 3600.0), weights=(3.0, 1.0))
    >>> x = d.draw(np.random.default_rng(2), 8000)
    >>> float(np.mean(x < 1200.0))  # the first bin's share: 3 / (3 + 1)
    0.744
    >>> bool(x.min() >= 600.0), bool(x.max() < 3600.0)
    (True, True)
    """

    edges: tuple[float, ...]
    weights: tuple[float, ...]
    clip: tuple[float, float] | None = None

    @property
    def least(self) -> float:
        """The shortest dwell it draws [s]."""
        first = next(k for k, w in enumerate(self.weights) if w > 0)
        low = self.edges[first]
        return low if self.clip is None else max(low, self.clip[0])

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` dwells [s] from ``rng``: one uniform draw each, through the inverse of the
        histogram's piecewise-linear distribution function (a bin without weight is never
        drawn)."""
        edges = np.asarray(self.edges, dtype=float)
        w = np.asarray(self.weights, dtype=float)
        before = np.concatenate([[0.0], np.cumsum(w)])
        v = rng.uniform(0.0, before[-1], size=n)
        k = np.clip(np.searchsorted(before, v, side="right") - 1, 0, len(w) - 1)
        frac = np.clip((v - before[k]) / w[k], 0.0, 1.0)
        return _clipped(edges[k] + frac * (edges[k + 1] - edges[k]), self.clip)


DwellLaw = UniformDwell | LognormalDwell | HistogramDwell
"""How long a stream's cars stay once parked."""


# -- streams ----------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class StreamSpec:
    """Cars drawn from a seeded generator.

    ``rate`` is a constant [1/s]: ``count`` cars with exponential gaps, the first at
    ``start`` [s]; or a :class:`RateProfile` (its times already counted from ``start``):
    the arrivals of a Poisson process of that rate, the first ``count`` of them if
    ``count`` is given. Types are drawn by ``mix`` weights, entrances uniformly, dwells
    from ``dwell`` (None: the cars stay); ``seed`` None means the run's seed. Ids are
    ``prefix`` and a number from 1, zero-padded."""

    count: int | None
    rate: float | RateProfile
    mix: tuple[tuple[str, float], ...]
    entrances: tuple[str, ...]
    start: float = 0.0
    dwell: DwellLaw | None = None
    seed: int | None = None
    prefix: str = "s"
    where: Location | None = field(default=None, repr=False, compare=False)

    @property
    def constant(self) -> bool:
        """Whether the stream comes at a constant rate (``count`` cars)."""
        return not isinstance(self.rate, RateProfile)

    @property
    def digits(self) -> int:
        """How many digits its ids' numbers are padded to: those of ``count`` (of the
        expected count for a profile without one), at least 2."""
        n = self.count if self.count is not None else math.ceil(self.rate.expected())
        return len(str(n)) if n >= 10 else 2


@dataclass(frozen=True, slots=True)
class TrafficSpec:
    """The vehicles listed one by one, the streams, and the patience [s]."""

    vehicles: tuple[Arrival, ...] = ()
    streams: tuple[StreamSpec, ...] = ()
    patience: float = PATIENCE
    where: Location | None = field(default=None, repr=False, compare=False)


def draw_stream(stream: StreamSpec, rng: np.random.Generator) -> list[Arrival]:
    """The stream's vehicles, drawn from ``rng``: times, then types, entrances and dwells.

    Examples
    --------
    >>> s = StreamSpec(count=3, rate=30 / 3600, mix=(("valet", 1.0),), entrances=("in",))
    >>> [a.id for a in draw_stream(s, np.random.default_rng(0))]
    ['s01', 's02', 's03']
    >>> day = RateProfile(((7 * 3600.0, 9 * 3600.0, 60 / 3600, 60 / 3600),))
    >>> cars = draw_stream(StreamSpec(None, day, (("valet", 1.0),), ("in",), prefix="c"),
    ...                    np.random.default_rng(0))
    >>> len(cars), all(7 * 3600 <= a.time < 9 * 3600 for a in cars), cars[0].id
    (124, True, 'c001')
    """
    if stream.constant:
        n = stream.count
        gaps = rng.exponential(1.0 / stream.rate, size=n)
        times = stream.start + np.cumsum(gaps) - gaps[0]  # the first arrives at ``start``
    else:
        times = stream.rate.draw(rng)
        if stream.count is not None:
            times = times[:stream.count]
        n = len(times)
    names = [m for m, _ in stream.mix]
    w = np.array([w for _, w in stream.mix], dtype=float)
    kinds = rng.choice(len(names), size=n, p=w / w.sum())
    gates = rng.integers(0, len(stream.entrances), size=n)
    dwell = stream.dwell.draw(rng, n) if stream.dwell is not None else [None] * n
    width = stream.digits
    return [
        Arrival(f"{stream.prefix}{k + 1:0{width}d}", names[kinds[k]],
                stream.entrances[gates[k]], round(float(times[k]), 3),
                None if dwell[k] is None else round(float(dwell[k]), 3), stream.where)
        for k in range(n)
    ]


def stream_rng(stream: StreamSpec, index: int, seed: int) -> np.random.Generator:
    """The generator of the ``index``-th stream (from 0) of a run seeded ``seed``: the
    stream's own seed if it has one, else the run's seed for the first and, for the k-th
    after it, the k-th independent generator spawned from the run's seed (numpy's
    ``SeedSequence(seed, spawn_key=(k,))``), so that streams alike draw different cars."""
    if stream.seed is not None:
        return np.random.default_rng(stream.seed)
    if index == 0:
        return np.random.default_rng(seed)
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index,)))


def arrivals(traffic: TrafficSpec, seed: int) -> list[Arrival]:
    """Every vehicle of ``traffic`` in arrival order (ties by id); each stream is drawn
    from its own generator (:func:`stream_rng`)."""
    out = list(traffic.vehicles)
    for k, s in enumerate(traffic.streams):
        out += draw_stream(s, stream_rng(s, k, seed))
    return sorted(out, key=lambda a: (a.time, a.id))
