"""Replay a ``result.json``: where each vehicle is, and what it is doing, at any time.

Everything here is read from the result document alone (``docs/result.md``), so a
GIF or a timeline can be drawn for any result, without the scenario or the planner.
A vehicle's life is cut into phases:

``outside``
    arrived, queued at its entrance (no samples yet); a rejected vehicle stays
    outside until it is turned away;
``driving``
    in the lot on its way in: from its first sample until it stands in its slot
    (stops on the way included);
``parked``
    standing in its slot;
``leaving``
    from the end of that stand until it vanishes at an exit.

A run that met disturbances (``result.json``'s ``disturbances``) also has what the
pictures mark of them (:class:`MetDisturbances`): ground closed over an interval, bays
taken by cars the plan does not know, and the stalls of its cars.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely

from lotsim.errors import ReplayError
from lotsim.io.visits import Visit, visits

PHASES = ("outside", "driving", "parked", "leaving")
"""Phases of a vehicle's life, in order."""
COUNTERS = ("arrived", "waiting", "driving", "parked", "departed", "rejected")
"""What :meth:`Replay.counts` counts at a time."""
QUIET_MIN = 4.0
"""A stretch in which no vehicle moves is skipped ("skip quiet stretches") when it is at
least this long [s], besides its margins."""
QUIET_MARGIN = 1.0
"""Run time kept at each end of a skipped stretch [s]: the last car stopping, the next
one starting."""
MET_KINDS = ("stalled", "closed", "taken")
"""What the pictures mark of a run's disturbances: cars stalled, ground closed, bays
taken from outside (:attr:`MetDisturbances.kinds`)."""


@dataclass(frozen=True, eq=False)
class Track:
    """One vehicle of a result: its body, samples and phase times.

    Times are seconds of run time; ``inf`` means "never" (or "until the end").
    """

    id: str
    type_name: str
    width: float
    front: float
    rear: float
    wheelbase: float
    arrival: float
    status: str
    slot: str | None
    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    v: np.ndarray
    steer: np.ndarray
    gear: np.ndarray
    entered: float
    """First sample; ``inf`` if it never entered."""
    parked_from: float
    """Start of the stand in its slot; ``inf`` if it never parked."""
    parked_until: float
    """End of that stand (start of leaving); ``inf`` if it stays."""
    gone: float
    """When it vanished at an exit (last sample of a departed vehicle); ``inf`` otherwise."""
    rejected_at: float
    """When it was turned away; ``inf`` if it was not."""

    @property
    def length(self) -> float:
        return self.front + self.rear

    def phases(self, end: float) -> list[tuple[str, float, float]]:
        """``(phase, t0, t1)`` intervals of this vehicle's life up to ``end`` (non-empty ones)."""
        leave_from = self.parked_until if math.isfinite(self.parked_from) else self.gone
        cuts = [
            ("outside", self.arrival, min(self.entered, self.rejected_at)),
            ("driving", self.entered, min(self.parked_from, self.gone)),
            ("parked", self.parked_from, self.parked_until),
            ("leaving", leave_from, self.gone),
        ]
        out = []
        for name, t0, t1 in cuts:
            t0, t1 = t0, min(t1, end)
            if math.isfinite(t0) and t1 > t0:
                out.append((name, float(t0), float(t1)))
        return out

    def active(self, end: float) -> list[tuple[float, float]]:
        """Intervals in which the vehicle moves about the lot (driving or leaving)."""
        return [(t0, t1) for name, t0, t1 in self.phases(end) if name in ("driving", "leaving")]


@dataclass(frozen=True, eq=False)
class ClosedGround:
    """An aisle or gate closed over ``t0`` to ``t1`` [s], as the run met it."""

    kind: str
    """``aisle`` or ``gate``."""
    id: str
    t0: float
    t1: float
    polygon: np.ndarray
    """The closed ground, (K, 2) [m]."""

    @property
    def label(self) -> str:
        """What the pictures' headers say while it is closed (``gate out closed``)."""
        return f"{self.kind} {self.id} closed"

    def closed_at(self, t: float) -> bool:
        """Closed at ``t`` [s] (both ends included)."""
        return self.t0 <= t <= self.t1


@dataclass(frozen=True, eq=False)
class StrangerCar:
    """The car the plan does not know, standing in bay ``slot`` from ``t`` [s] on."""

    slot: str
    t: float
    polygon: np.ndarray
    """Its body, (4, 2) [m]."""


@dataclass(frozen=True)
class StallSpan:
    """Vehicle ``vehicle`` (index into :attr:`Replay.tracks`), ``car`` by id, stands
    stalled from ``t0`` to ``t1`` [s] (both ends included)."""

    vehicle: int
    car: str
    t0: float
    t1: float

    def stalled_at(self, t: float) -> bool:
        return self.t0 <= t <= self.t1


@dataclass(frozen=True, eq=False)
class MetDisturbances:
    """What the pictures show of the disturbances a run met: each closure, each bay taken
    from outside (those refused have no car to draw) and each stall of a vehicle of the
    run; all empty for a run that met none."""

    closures: tuple[ClosedGround, ...] = ()
    strangers: tuple[StrangerCar, ...] = ()
    stalls: tuple[StallSpan, ...] = ()

    @property
    def kinds(self) -> frozenset[str]:
        """Which of :data:`MET_KINDS` the run has."""
        return frozenset(k for k, there in zip(
            MET_KINDS, (self.stalls, self.closures, self.strangers), strict=True) if there)


class Replay:
    """The vehicles of a result document, ready to be asked where they are.

    Parameters
    ----------
    doc : dict
        A ``result.json`` document (already read with :func:`json.load`).
    """

    def __init__(self, doc: dict):
        try:
            vs = visits(doc)
            self.tracks = [self._track(v, vs[str(v["id"])]) for v in doc["vehicles"]]
        except (KeyError, TypeError, ValueError, IndexError, shapely.errors.ShapelyError) as exc:
            if isinstance(exc, ReplayError):
                raise
            raise ReplayError(f"not a lotsim result: {type(exc).__name__}: {exc}") from None
        self.doc = doc

    @cached_property
    def met(self) -> MetDisturbances:
        """The disturbances the run met, as the pictures mark them (the result's
        ``disturbances`` section; empty without one).

        Raises
        ------
        ReplayError
            When that section is not as ``docs/result.md`` describes it.
        """
        met = self.doc.get("disturbances") or {}
        index = {tr.id: j for j, tr in enumerate(self.tracks)}
        try:
            closures = tuple(
                ClosedGround(str(c["kind"]), str(c["id"]), float(c["t0"]), float(c["t1"]),
                             np.asarray(c["polygon"], dtype=float).reshape(-1, 2))
                for c in met.get("closures", []))
            strangers = tuple(
                StrangerCar(str(b["slot"]), float(b["t"]),
                            np.asarray(b["polygon"], dtype=float).reshape(-1, 2))
                for b in met.get("taken", []) if b.get("polygon"))
            stalls = tuple(StallSpan(index[st["car"]], st["car"], float(st["t0"]),
                                     float(st["t1"]))
                           for st in met.get("stalls", []) if st.get("car") in index)
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise ReplayError(f"disturbances: not as a lotsim result has them: "
                              f"{type(exc).__name__}: {exc}") from None
        return MetDisturbances(closures, strangers, stalls)

    @staticmethod
    def _track(v: dict, visit: Visit) -> Track:
        s = v["samples"]
        cols = {k: np.asarray(s[k], dtype=float) for k in ("t", "x", "y", "theta", "v", "steer")}
        gear = np.asarray(s["gear"], dtype=np.int8)
        n = len(cols["t"])
        if any(len(c) != n for c in cols.values()) or len(gear) != n:
            raise ReplayError(f"vehicle {v['id']!r}: sample arrays of different lengths")
        typ = v["type"]
        t, status = cols["t"], v["status"]

        def known(time: float | None) -> float:
            return math.inf if time is None else time

        return Track(
            id=str(v["id"]), type_name=str(typ["name"]), width=float(typ["width"]),
            front=float(typ["front"]), rear=float(typ["rear"]),
            wheelbase=float(typ["wheelbase"]), arrival=float(v["arrival"]), status=status,
            slot=v["slot"], t=t, x=cols["x"], y=cols["y"], theta=cols["theta"], v=cols["v"],
            steer=cols["steer"], gear=gear, entered=known(visit.start),
            parked_from=known(visit.park), parked_until=known(visit.leave),
            gone=known(visit.end if status == "departed" else None),
            rejected_at=known(visit.rejected),
        )

    # -- time span -----------------------------------------------------------------------------
    @cached_property
    def start(self) -> float:
        """The first arrival [s] (0 for a result without vehicles)."""
        return min((tr.arrival for tr in self.tracks), default=0.0)

    @cached_property
    def end(self) -> float:
        """The last thing that happens: the last sample, arrival or rejection [s]."""
        ends = [self.start]
        for tr in self.tracks:
            ends.append(tr.arrival)
            if len(tr.t):
                ends.append(float(tr.t[-1]))
            if math.isfinite(tr.rejected_at):
                ends.append(tr.rejected_at)
        return max(ends)

    # -- where is everybody --------------------------------------------------------------------
    def states(self, times: np.ndarray) -> dict[str, np.ndarray]:
        """Every vehicle's state at each of ``times``; arrays shaped (len(times), vehicles).

        Keys: ``x``, ``y``, ``theta`` (rear-axle pose, interpolated linearly, heading the
        short way round), ``steer``, ``v``, ``visible`` (in the lot: from its first sample
        to its last, or for ever after it when it did not leave) and ``phase`` (index into
        :data:`PHASES`, -1 before arrival or after it is gone or turned away).
        """
        times = np.asarray(times, dtype=float)
        m, n = len(times), len(self.tracks)
        out = {k: np.zeros((m, n)) for k in ("x", "y", "theta", "steer", "v")}
        out["visible"] = np.zeros((m, n), dtype=bool)
        out["phase"] = np.full((m, n), -1, dtype=np.int8)
        for j, tr in enumerate(self.tracks):
            for name, t0, t1 in tr.phases(math.inf):
                out["phase"][(times >= t0) & (times < t1), j] = PHASES.index(name)
            if not len(tr.t):
                continue
            t = tr.t
            last = t[-1] if tr.status == "departed" else math.inf
            vis = (times >= t[0]) & (times <= last)
            out["visible"][:, j] = vis
            i = np.clip(np.searchsorted(t, times, side="right") - 1, 0, len(t) - 1)
            i1 = np.minimum(i + 1, len(t) - 1)
            span = t[i1] - t[i]
            f = np.where(span > 0, np.clip((times - t[i]) / np.where(span > 0, span, 1), 0, 1),
                         0.0)
            for k in ("x", "y", "steer", "v"):
                a = getattr(tr, k)
                out[k][:, j] = a[i] + f * (a[i1] - a[i])
            dth = (tr.theta[i1] - tr.theta[i] + math.pi) % (2 * math.pi) - math.pi
            out["theta"][:, j] = tr.theta[i] + f * dth
        return out

    def events(self) -> np.ndarray:
        """Times at which something happens, sorted, each once [s]: arrivals, entering the
        lot, standing in a slot, leaving it, vanishing at an exit, being turned away, and
        every start of a move (a car that stood still moves again)."""
        times = []
        for tr in self.tracks:
            times += [tr.arrival, tr.entered, tr.parked_from, tr.parked_until, tr.gone,
                      tr.rejected_at]
            times += tr.t[self._move_starts(tr)].tolist()
        out = np.unique(np.asarray(times, dtype=float))
        return out[np.isfinite(out)]

    @staticmethod
    def _moving(tr: Track) -> np.ndarray:
        """Per gap between consecutive samples: whether the vehicle moves (its pose or its
        wheels change) in it."""
        return ((tr.x[1:] != tr.x[:-1]) | (tr.y[1:] != tr.y[:-1])
                | (tr.theta[1:] != tr.theta[:-1]) | (tr.steer[1:] != tr.steer[:-1]))

    @classmethod
    def _move_starts(cls, tr: Track) -> np.ndarray:
        """Indices of the samples at which a stretch of motion begins."""
        if len(tr.t) < 2:
            return np.zeros(0, dtype=int)
        mv = cls._moving(tr)
        before = np.concatenate([[False], mv[:-1]])
        return np.flatnonzero(mv & ~before)

    def busy(self) -> list[tuple[float, float]]:
        """Time spans in which some vehicle moves (drives, or turns its wheels standing),
        merged and sorted [s]."""
        spans = []
        for tr in self.tracks:
            if len(tr.t) < 2:
                continue
            mv = self._moving(tr)
            # runs of moving gaps: [start sample, end sample]
            edge = np.diff(np.concatenate([[0], mv.astype(np.int8), [0]]))
            for a, b in zip(np.flatnonzero(edge == 1), np.flatnonzero(edge == -1), strict=True):
                spans.append((float(tr.t[a]), float(tr.t[b])))
        spans.sort()
        merged: list[tuple[float, float]] = []
        for a, b in spans:
            if merged and a <= merged[-1][1]:
                merged[-1] = (merged[-1][0], max(merged[-1][1], b))
            else:
                merged.append((a, b))
        return merged

    def quiet(self, *, min_gap: float = QUIET_MIN, margin: float = QUIET_MARGIN
              ) -> list[tuple[float, float]]:
        """Stretches of the run, at least ``min_gap`` long, in which no vehicle moves,
        less ``margin`` at each end (so a skip shows the last car stop and the next one
        start) [s]. From the first arrival (or the first motion, if later) to the end."""
        out = []
        t = self.start
        for a, b in [*self.busy(), (self.end, self.end)]:
            if a - t >= min_gap + 2 * margin:
                out.append((t + margin if out or t > self.start else t, a - margin))
            t = max(t, b)
        return out

    def waits(self, tr: Track) -> list[tuple[float, float]]:
        """Spans in which ``tr`` stands still on its way in or out (not parked): every
        pose and the wheels unchanged for longer than the 0.05 s clock [s]."""
        if len(tr.t) < 2:
            return []
        dt = np.diff(tr.t)
        still = ~self._moving(tr) & (dt > 0.0501)
        inside = np.ones(len(dt), dtype=bool)
        if math.isfinite(tr.parked_from):
            inside &= ~((tr.t[:-1] >= tr.parked_from) & (tr.t[1:] <= tr.parked_until))
        if tr.status == "parked":
            inside &= tr.t[1:] <= tr.parked_from
        k = np.flatnonzero(still & inside)
        return [(float(tr.t[i]), float(tr.t[i + 1])) for i in k]

    def counts(self, t: float) -> dict[str, int]:
        """How many vehicles, at time ``t``, have arrived, wait outside, drive (in or out),
        stand parked, have departed and have been turned away (:data:`COUNTERS`)."""
        c = dict.fromkeys(COUNTERS, 0)
        for tr in self.tracks:
            if tr.arrival > t:
                continue
            c["arrived"] += 1
            if tr.rejected_at <= t:
                c["rejected"] += 1
            elif tr.gone <= t:
                c["departed"] += 1
            elif tr.entered > t:
                c["waiting"] += 1
            elif tr.parked_from <= t < tr.parked_until:
                c["parked"] += 1
            else:
                c["driving"] += 1
        return c


def assign_colours(tracks: list[Track], n_colours: int, end: float) -> list[int]:
    """One colour index per vehicle, so that vehicles moving about the lot at the same time
    get different colours whenever there are enough of them.

    Vehicles are taken by the time they first move; each gets, of the indices that no
    vehicle moving during any of its moves holds, the one used longest ago (never-used ones
    first, lowest first), so colours repeat as seldom as they can; when every index is held,
    the one held by the fewest such vehicles (greedy colouring of the overlap graph).
    """
    spans = [tr.active(end) for tr in tracks]
    owner = np.array([j for j, s in enumerate(spans) for _ in s], dtype=int)
    a = np.array([t0 for s in spans for t0, _ in s], dtype=float)
    b = np.array([t1 for s in spans for _, t1 in s], dtype=float)
    first = [s[0][0] if s else math.inf for s in spans]
    colour = np.full(len(tracks), -1, dtype=int)
    last_used = np.arange(n_colours, dtype=float) - n_colours  # never used: by index
    for step, j in enumerate(sorted(range(len(tracks)), key=lambda j: (first[j], j))):
        near = np.zeros(len(owner), dtype=bool)
        for t0, t1 in spans[j]:
            near |= (a < t1) & (t0 < b)
        others = np.unique(owner[near & (colour[owner] >= 0)])
        held = np.bincount(colour[others], minlength=n_colours)
        # fewest holders first (none, when there are free colours), then used longest ago
        c = int(np.lexsort((last_used, held))[0])
        colour[j] = c
        last_used[c] = step
    return colour.tolist()
