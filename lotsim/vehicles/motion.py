"""Timed trajectories: paths driven the way a real car drives them.

A path is a list of :class:`Piece` — a :class:`~lotsim.core.geometry.Segment` (a
straight, an arc or a clothoid) and the speed limit that applies on it. A car
drives it within every one of its limits:

* **speed** along each stroke follows a jerk-limited S-curve
  (:func:`scurve`): acceleration ramps at most at ``max_jerk``, stays within
  ``max_accel`` speeding up and ``max_brake`` slowing down, and is zero where a
  profile starts and ends, so it is continuous from one profile to the next;
* **curves** cap the speed: ``v² · |κ| ≤ max_lateral_accel`` on arcs and
  clothoids, and on a clothoid of sharpness ``σ`` the steering rate the car
  needs, ``v · σ · b / (1 + (κ b)²)``, stays within ``max_steer_rate``
  (:func:`speed_cap`);
* **steering** is continuous: where consecutive pieces' curvatures differ (a
  cusp, or an arc straight after a straight in a parking maneuver), the car
  stops and turns its wheels standing (:class:`Steering`), which takes
  ``|Δφ| / max_steer_rate`` seconds.

The car stops at the end of every stroke; a :class:`Motion` is the strokes and
the standing steering between them, timed one after the other. Trajectories
are sampled in time, with the pose taken on the exact geometry of the segments.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from lotsim.core.geometry import FloatArray, Pose, Segment, travel
from lotsim.vehicles.model import VehicleType

DT = 0.05
"""Default sampling interval [s]: at 20 km/h samples are 0.28 m apart."""


@dataclass(frozen=True, slots=True)
class Piece:
    """A segment and the speed limit that applies along it [m/s]."""

    segment: Segment
    speed_limit: float = math.inf


@dataclass(frozen=True)
class Trajectory:
    """Samples of a vehicle's motion, equal-length arrays.

    Attributes
    ----------
    t : ndarray
        Times [s], strictly increasing.
    x, y, theta : ndarray
        Rear-axle centre pose [m, m, rad].
    v : ndarray
        Speed, signed: negative in reverse [m/s].
    steer : ndarray
        Road-wheel angle [rad], ``atan(curvature · wheelbase)``.
    gear : ndarray of int
        +1 forward, -1 reverse, 0 standing.
    """

    t: FloatArray
    x: FloatArray
    y: FloatArray
    theta: FloatArray
    v: FloatArray
    steer: FloatArray
    gear: np.ndarray

    def __len__(self) -> int:
        return len(self.t)

    @property
    def poses(self) -> FloatArray:
        return np.column_stack([self.x, self.y, self.theta])

    @property
    def start_time(self) -> float:
        return float(self.t[0])

    @property
    def end_time(self) -> float:
        return float(self.t[-1])

    def then(self, other: Trajectory) -> Trajectory:
        """This trajectory followed by ``other`` (which starts where and when this ends)."""
        if abs(other.t[0] - self.t[-1]) > 1e-9:
            raise ValueError("the second trajectory must start when the first ends")
        cols = [np.concatenate([a, b[1:]]) for a, b in zip(self._cols(), other._cols(),
                                                          strict=True)]
        return Trajectory(*cols)

    def _cols(self) -> tuple[np.ndarray, ...]:
        return (self.t, self.x, self.y, self.theta, self.v, self.steer, self.gear)


def standing_still(pose: Pose, t0: float, duration: float, *, dt: float = DT) -> Trajectory:
    """A vehicle standing still at ``pose`` from ``t0`` for ``duration`` seconds."""
    n = max(1, math.ceil(duration / dt - 1e-9))
    t = np.linspace(t0, t0 + duration, n + 1)
    z = np.zeros(n + 1)
    return Trajectory(t, z + pose[0], z + pose[1], z + pose[2], z, z, np.zeros(n + 1, dtype=int))


_KAPPA_TOL = 1e-9  # curvatures this close are one: no steering between the pieces [1/m]


def speed_cap(segment: Segment, vehicle: VehicleType) -> float:
    """The highest constant speed [m/s] at which ``vehicle`` drives ``segment`` within its
    lateral-acceleration and steering-rate limits (not its top speed: see the limits).

    >>> from lotsim.vehicles import CATALOGUE
    >>> valet = CATALOGUE["valet"]
    >>> round(speed_cap(Segment((0.0, 0.0, 0.0), 5.0, 0.2), valet) * 3.6, 2)   # √(2 m/s² · 5 m)
    11.38
    """
    lim = vehicle.limits
    cap = math.inf
    k = segment.max_curvature
    if k > 0:
        cap = math.sqrt(lim.max_lateral_accel / k)
    if segment.sharpness:
        k0, k1 = segment.curvature, segment.end_curvature
        least = 0.0 if k0 * k1 <= 0 else min(abs(k0), abs(k1))
        b = vehicle.wheelbase
        cap = min(cap, lim.max_steer_rate * (1 + (least * b) ** 2) / (abs(segment.sharpness) * b))
    return cap


def steer_time(a: float, b: float, vehicle: VehicleType) -> float:
    """Time to turn the road wheels from ``a`` to ``b`` [rad] standing [s]."""
    return abs(b - a) / vehicle.limits.max_steer_rate


def _shift(dv: float, limit: float, jerk: float) -> tuple[float, float]:
    """The fastest change of speed by ``dv`` ≥ 0 [m/s] from and to zero acceleration, within
    acceleration ``limit`` and ``jerk``: (time of each jerk ramp, time at full
    acceleration) [s]."""
    if dv <= 0:
        return 0.0, 0.0
    if dv >= limit * limit / jerk:
        return limit / jerk, dv / limit - limit / jerk
    return math.sqrt(dv / jerk), 0.0


def _shift_distance(v0: float, v1: float, accel: float, brake: float, jerk: float) -> float:
    """Distance [m] of the fastest change from speed ``v0`` to ``v1``: its mean speed times
    its time (the acceleration is symmetric in time)."""
    ramp, hold = _shift(abs(v1 - v0), accel if v1 >= v0 else brake, jerk)
    return (2 * ramp + hold) * (v0 + v1) / 2


@functools.lru_cache(maxsize=1 << 16)
def scurve(length: float, v0: float, v1: float, vmax: float, accel: float, brake: float,
           jerk: float) -> Profile | None:
    """The fastest jerk-limited speed profile over ``length`` [m] from speed ``v0`` to ``v1``
    [m/s], with zero acceleration at both ends; None when they cannot be joined.

    The speed rises to a peak, cruises there when the peak is ``vmax``, and falls,
    each change being the fastest one within ``accel`` (speeding up), ``brake``
    (slowing down) [m/s²] and ``jerk`` [m/s³]: jerk ramps, then full acceleration
    if the change is large enough to reach it. The peak is the highest whose
    changes fit in the length (by bisection: the distance grows with the peak).

    Examples
    --------
    >>> p = scurve(20.0, 0.0, 0.0, 20 / 3.6, 3.0, 6.0, 20.0)
    >>> round(p.duration, 3), round(float(p.v.max()) * 3.6, 3), round(float(p.a.max()), 3)
    (5.214, 20.0, 3.0)
    >>> scurve(0.5, 5.0, 0.0, 5.0, 3.0, 6.0, 20.0) is None   # 5 m/s cannot stop in 0.5 m
    True

    Profiles are kept (a lot's edges repeat a few lengths, each searched between every
    pair of speed levels) and shared: their arrays are read-only.
    """
    eps = 1e-9
    if length < 0 or v0 < 0 or v1 < 0 or v0 > vmax + eps or v1 > vmax + eps:
        return None
    v0, v1 = min(v0, vmax), min(v1, vmax)

    def need(peak: float) -> float:
        return (_shift_distance(v0, peak, accel, brake, jerk)
                + _shift_distance(peak, v1, accel, brake, jerk))

    if need(max(v0, v1)) > length + eps:
        return None
    peak = _largest(lambda p: need(p) <= length, max(v0, v1), vmax)
    if peak <= 0:
        return None
    cruise = max(0.0, length - need(peak))
    pieces: list[tuple[float, float]] = []  # (duration, jerk)
    for dv, limit, sign in ((peak - v0, accel, 1.0), (peak - v1, brake, -1.0)):
        ramp, hold = _shift(dv, limit, jerk)
        pieces += [(ramp, sign * jerk), (hold, 0.0), (ramp, -sign * jerk)]
        if sign > 0:
            pieces.append((cruise / peak, 0.0))
    pieces = [(d, j) for d, j in pieces if d > 0]
    t, sv, v, a = [0.0], [0.0], [v0], [0.0]
    for d, j in pieces:
        a0, v0_, s0 = a[-1], v[-1], sv[-1]
        t.append(t[-1] + d)
        a.append(a0 + j * d)
        v.append(v0_ + a0 * d + j * d * d / 2)
        sv.append(s0 + v0_ * d + a0 * d * d / 2 + j * d ** 3 / 6)
    arr = [np.array(c) for c in (t, sv, v, a)]
    arr[1][-1] = length  # the integration's rounding (under a nanometre)
    arr[2][-1], arr[3][-1] = v1, 0.0
    if len(arr[0]) == 1:  # nothing to drive
        arr = [np.array([0.0, 0.0]), np.array([0.0, 0.0]), np.array([v0, v1]),
               np.zeros(2)]
    for col in arr:  # kept and shared: read-only
        col.flags.writeable = False
    return Profile(*arr)


@dataclass(frozen=True, eq=False)
class Profile:
    """Speed along one stroke in time: constant jerk between breakpoints.

    Compared and hashed by identity: :func:`scurve` keeps and shares them, and what is
    worked out from one can be kept by it.

    Attributes
    ----------
    t, s, v, a : ndarray
        Breakpoint times [s] (from 0), path lengths [m], speeds (≥ 0) [m/s] and
        accelerations [m/s²].
    """

    t: FloatArray
    s: FloatArray
    v: FloatArray
    a: FloatArray

    @property
    def duration(self) -> float:
        return float(self.t[-1])

    @property
    def length(self) -> float:
        return float(self.s[-1])

    def at(self, tau: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Path length [m] and speed [m/s] at times ``tau`` (0 ≤ tau ≤ duration) [s]."""
        tau = np.asarray(tau, dtype=float)
        s, v = _profiles_at([self], np.zeros(tau.size, dtype=int), tau.reshape(-1))
        return s.reshape(tau.shape), v.reshape(tau.shape)


@dataclass(frozen=True)
class Stroke:
    """Consecutive segments in one gear, curvature-continuous, and the speed profile they
    are driven with."""

    segments: tuple[Segment, ...]
    profile: Profile

    @property
    def gear(self) -> int:
        return self.segments[0].gear

    @property
    def duration(self) -> float:
        return self.profile.duration

    @property
    def end(self) -> Pose:
        return self.segments[-1].end

    def poses(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Poses (N, 3) and curvatures (N,) after path lengths ``s`` [m]."""
        s = np.asarray(s, dtype=float).reshape(-1)
        return _paths_at([self], np.zeros(s.size, dtype=int), s)[:2]


@dataclass(frozen=True)
class Steering:
    """Standing at ``pose`` while the road wheels turn from ``start`` to ``end`` [rad] at a
    steady rate, for ``duration`` [s]."""

    pose: Pose
    start: float
    end: float
    duration: float


Phase = Stroke | Steering


@dataclass(frozen=True)
class Motion:
    """Strokes and standing steering, timed one after the other from ``0`` to ``duration``
    [s].

    The vehicle stops at the end of every stroke but the last, whose end speed
    may be non-zero (a lane edge driven through).
    """

    phases: tuple[Phase, ...]

    @property
    def strokes(self) -> tuple[Stroke, ...]:
        return tuple(p for p in self.phases if isinstance(p, Stroke))

    @property
    def duration(self) -> float:
        return float(sum(p.duration for p in self.phases))

    @property
    def offsets(self) -> FloatArray:
        """Start time of each phase [s]."""
        d = [p.duration for p in self.phases]
        return np.concatenate([[0.0], np.cumsum(d)[:-1]])

    @property
    def cusps(self) -> FloatArray:
        """Times where one phase ends and the next begins (the car stands there) [s]."""
        return self.offsets[1:]

    @property
    def end(self) -> Pose:
        last = self.phases[-1]
        return last.end if isinstance(last, Stroke) else last.pose

    @property
    def steering_stops(self) -> list[tuple[Pose, float]]:
        """Where the car stands to steer, and for how long [s]."""
        return [(p.pose, p.duration) for p in self.phases if isinstance(p, Steering)]

    def at(self, tau: FloatArray, *, wheelbase: float) -> tuple[FloatArray, ...]:
        """Poses (N, 3), signed speeds, steering angles and gears at times ``tau`` [s] (a
        time at a boundary between phases belongs to the phase that ends there)."""
        return motions_at([self], [tau], wheelbase=wheelbase)

    def times(self, dt: float) -> FloatArray:
        """Sample times every ``dt`` within each phase, each phase's ends included."""
        out = []
        for ph, t0 in zip(self.phases, self.offsets, strict=True):
            d = ph.duration
            m = max(1, math.ceil(d / dt - 1e-9))
            out.append(t0 + np.linspace(0.0, d, m + 1))
        return np.unique(np.concatenate(out)) if out else np.zeros(1)


def motions_at(motions: Sequence[Motion], taus: Sequence[FloatArray], *, wheelbase: float
               ) -> tuple[FloatArray, ...]:
    """:meth:`Motion.at` of each of ``motions`` at its own times ``taus`` [s], one after the
    other: poses (N, 3), signed speeds, steering angles and gears of all the samples.

    The numbers are those of each motion asked alone, sample by sample: every phase's and
    profile's breakpoints are found as :func:`numpy.searchsorted` finds them and every
    formula is the same element by element, so a car's many moves (a day's result holds
    some hundred thousand) take a few numpy calls in all instead of some fifty each. The
    one exception to batching is a stroke whose samples meet a clothoid: its quadrature's
    cells follow the stroke's largest turn (:func:`~lotsim.core.geometry.travel`), so it is
    worked out by itself, as alone.
    """
    taus = [np.asarray(t, dtype=float).reshape(-1) for t in taus]
    # the phases of all the motions, one table: each one's start in its motion's time (the
    # running sums np.cumsum makes); a motion with none stands nowhere (zeros)
    offsets: list[float] = []
    first: list[int] = []  # each motion's first phase
    count: list[int] = []  # and how many it has
    phases: list[Phase] = []
    for m in motions:
        first.append(len(phases))
        count.append(len(m.phases))
        acc = 0.0
        for ph in m.phases:
            offsets.append(acc)
            acc += ph.duration
        phases.extend(m.phases)
    if len(motions) == 1:  # (numpy's own search)
        tau = taus[0]
        if not phases or not len(tau):
            return np.zeros((len(tau), 3)), np.zeros(len(tau)), np.zeros(len(tau)), \
                np.zeros(len(tau), dtype=int)
        phase = np.clip(np.searchsorted(np.array(offsets), tau, side="left") - 1, 0,
                        len(offsets) - 1)
        return _phases_at(phases, phase, tau - np.array(offsets)[phase], wheelbase)
    tau = np.concatenate(taus) if taus else np.zeros(0)
    n = len(tau)
    out = (np.zeros((n, 3)), np.zeros(n), np.zeros(n), np.zeros(n, dtype=int))
    motion_of = np.repeat(np.arange(len(motions)), [len(t) for t in taus])
    some = np.array(count)[motion_of] > 0
    if not some.any():
        return out
    motion_of, tau = motion_of[some], tau[some]
    which = _rank(np.array(offsets), np.array(first), np.array(count), motion_of, tau,
                  strict=True)
    phase = np.array(first)[motion_of] + np.clip(which - 1, 0, np.array(count)[motion_of] - 1)
    for col, got in zip(out, _phases_at(phases, phase, tau - np.array(offsets)[phase],
                                        wheelbase), strict=True):
        col[some] = got
    return out


def _phases_at(phases: Sequence[Phase], phase: np.ndarray, local: FloatArray,
               wheelbase: float) -> tuple[FloatArray, ...]:
    """:meth:`Motion.at`'s columns at times ``local`` [s] into ``phases[phase]``."""
    is_stroke = np.array([isinstance(ph, Stroke) for ph in phases])
    if is_stroke.all():  # (no standing to steer: every sample drives)
        poses, sp, kappa, g = _strokes_at(phases, is_stroke, phase, local)
        return poses, g * sp, np.arctan(kappa * wheelbase), g
    n = len(local)
    poses = np.zeros((n, 3))
    v = np.zeros(n)
    steer = np.zeros(n)
    gear = np.zeros(n, dtype=int)
    at_rest = ~is_stroke[phase]
    if at_rest.any():
        turns = [ph if isinstance(ph, Steering) else Steering((0.0, 0.0, 0.0), 0.0, 0.0, 0.0)
                 for ph in phases]
        where = phase[at_rest]
        poses[at_rest] = np.array([ph.pose for ph in turns])[where]
        dur = np.array([ph.duration for ph in turns])[where]
        frac = np.ones(len(where))
        timed = dur != 0
        frac[timed] = np.clip(local[at_rest][timed] / dur[timed], 0.0, 1.0)
        start = np.array([ph.start for ph in turns])
        end = np.array([ph.end for ph in turns])
        steer[at_rest] = start[where] + (end - start)[where] * frac
    driving = ~at_rest
    if driving.any():
        p, sp, kappa, g = _strokes_at(phases, is_stroke, phase[driving], local[driving])
        poses[driving] = p
        v[driving] = g * sp
        steer[driving] = np.arctan(kappa * wheelbase)
        gear[driving] = g
    return poses, v, steer, gear


def _rank(values: FloatArray, first: np.ndarray, count: np.ndarray, group: np.ndarray,
          x: FloatArray, *, strict: bool) -> np.ndarray:
    """For each ``x[i]``, how many of its group's values (``values[first[g]:first[g] +
    count[g]]``, sorted, for ``g = group[i]``) are below it (``strict``), or at most it:
    :func:`numpy.searchsorted` of each group's values, ``side="left"`` or ``"right"``."""
    if len(count) == 1:  # (one group: numpy's own search)
        return np.searchsorted(values[first[0]: first[0] + count[0]], x,
                               side="left" if strict else "right")
    width = int(count.max()) if len(count) else 0
    cols = np.arange(width)
    idx = first[:, None] + cols[None, :]
    padded = np.where(cols[None, :] < count[:, None],
                      values[np.minimum(idx, len(values) - 1)], np.inf)[group]
    return ((padded < x[:, None]) if strict else (padded <= x[:, None])).sum(axis=1)


def _strokes_at(phases: Sequence[Phase], is_stroke: np.ndarray, phase: np.ndarray,
                local: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, np.ndarray]:
    """Poses, speeds (unsigned), curvatures and gears of samples ``local`` [s] into strokes
    ``phases[phase]`` (each as :meth:`Profile.at` and :meth:`Stroke.poses` work them out)."""
    strokes = [ph for ph, s in zip(phases, is_stroke, strict=True) if s]
    which = (np.cumsum(is_stroke) - 1)[phase]  # each sample's stroke
    s, speed = _profiles_at([st.profile for st in strokes], which, local)
    poses, kappa, gears = _paths_at(strokes, which, s)
    return poses, speed, kappa, np.broadcast_to(gears, which.shape).astype(int)


def _profiles_at(profiles: Sequence[Profile], which: np.ndarray, tau: FloatArray
                 ) -> tuple[FloatArray, FloatArray]:
    """Path lengths [m] and speeds [m/s] at times ``tau`` [s] along ``profiles[which]``
    (:meth:`Profile.at`)."""
    if len(profiles) == 1:  # (one profile: its own arrays, and scalars for the tables)
        t, s, v, a = (getattr(profiles[0], c) for c in "tsva")
        k = np.clip(np.searchsorted(t, tau, side="right") - 1, 0, len(t) - 2)
        end = len(t) - 1
    else:
        first = np.cumsum([0] + [len(p.t) for p in profiles[:-1]])
        count = np.array([len(p.t) for p in profiles])
        t, s, v, a = (np.concatenate([getattr(p, c) for p in profiles]) for c in "tsva")
        k = np.clip(_rank(t, first, count, which, tau, strict=False) - 1, 0,
                    count[which] - 2) + first[which]
        end = (first + count - 1)[which]
    cell = t[k + 1] - t[k]
    jerk = np.where(cell > 0, (a[k + 1] - a[k]) / np.where(cell > 0, cell, 1.0), 0.0)
    d = np.clip(tau - t[k], 0.0, cell)
    pos = s[k] + v[k] * d + a[k] * d * d / 2 + jerk * d ** 3 / 6
    speed = v[k] + a[k] * d + jerk * d * d / 2
    done = tau >= t[end]  # the end exactly, without the cubic's rounding
    pos, speed = np.where(done, s[end], pos), np.where(done, v[end], speed)
    return np.clip(pos, 0.0, s[end]), np.maximum(speed, 0.0)


def _paths_at(strokes: Sequence[Stroke], which: np.ndarray, s: FloatArray
              ) -> tuple[FloatArray, FloatArray, np.ndarray | int]:
    """Poses (N, 3), curvatures (N,) and gears (N,; one number for one stroke) after path
    lengths ``s`` [m] along ``strokes[which]`` (:meth:`Stroke.poses`)."""
    segs = [g for st in strokes for g in st.segments]
    lengths = np.array([g.length for g in segs])
    starts: list[float] = []
    for st in strokes:  # (each stroke's running sums, as np.cumsum makes them)
        acc = 0.0
        for g in st.segments:
            starts.append(acc)
            acc += g.length
    starts_a = np.array(starts)
    if len(strokes) == 1:  # (one stroke: numpy's own search, and its gear as a number)
        pid = np.clip(np.searchsorted(starts_a, s, side="right") - 1, 0, len(segs) - 1)
        gears: np.ndarray | int = strokes[0].gear
    else:
        first = np.cumsum([0] + [len(st.segments) for st in strokes[:-1]])
        count = np.array([len(st.segments) for st in strokes])
        pid = np.clip(_rank(starts_a, first, count, which, s, strict=False) - 1, 0,
                      count[which] - 1) + first[which]
        gears = np.array([st.gear for st in strokes])[which]
    into = np.clip(s - starts_a[pid], 0.0, lengths[pid])
    seg_start = np.array([g.start for g in segs]).reshape(-1, 3)[pid]
    kappa = np.array([g.curvature for g in segs])[pid]
    sigma = np.array([g.sharpness for g in segs])[pid]
    dist = gears * into
    if len(strokes) == 1:  # (as travel takes it)
        return travel(seg_start, dist, kappa, sigma), kappa + sigma * into, gears
    out = np.empty((len(s), 3))
    # a stroke whose samples meet a clothoid by itself (its quadrature follows its turn)
    curved = np.zeros(len(strokes), dtype=bool)
    curved[which[sigma != 0]] = True
    rest = ~curved[which]
    if rest.any():
        out[rest] = travel(seg_start[rest], dist[rest], kappa[rest], 0.0)
    for j in np.flatnonzero(curved):
        sel = which == j
        out[sel] = travel(seg_start[sel], dist[sel], kappa[sel], sigma[sel])
    return out, kappa + sigma * into, gears


def slowed(motion: Motion, factor: float) -> Motion:
    """``motion`` driven ``factor`` (0 < factor ≤ 1) times as fast along the same path:
    every time stretched by ``1 / factor``, so speeds are ``factor``, accelerations
    ``factor²``, jerks ``factor³`` and steering rates ``factor`` times the original's, each
    within the same limits.

    Examples
    --------
    >>> from lotsim.core.geometry import Segment
    >>> from lotsim.vehicles.catalogue import get_vehicle
    >>> valet = get_vehicle("valet")
    >>> m = timed_path([Piece(Segment((0.0, 0.0, 0.0), 10.0, 0.0, 0.0), 5.0)], valet)
    >>> half = slowed(m, 0.5)
    >>> round(half.duration / m.duration, 9), half.end == m.end
    (2.0, True)
    """
    if factor == 1.0:
        return motion
    phases: list[Phase] = []
    for ph in motion.phases:
        if isinstance(ph, Steering):
            phases.append(Steering(ph.pose, ph.start, ph.end, ph.duration / factor))
            continue
        p = ph.profile
        phases.append(Stroke(ph.segments, Profile(p.t / factor, p.s, p.v * factor,
                                                  p.a * factor ** 2)))
    return Motion(tuple(phases))


def runs(pieces: Sequence[Piece]) -> list[list[Piece]]:
    """Consecutive pieces grouped into runs a car drives without stopping: one gear, and
    each piece starting with the curvature the one before ends with."""
    out: list[list[Piece]] = []
    for p in pieces:
        if p.segment.length <= 0:
            continue
        if out:
            last = out[-1][-1].segment
            if (last.gear == p.segment.gear
                    and abs(last.end_curvature - p.segment.curvature) <= _KAPPA_TOL):
                out[-1].append(p)
                continue
        out.append([p])
    return out


def piece_caps(run: Sequence[Piece], vehicle: VehicleType) -> list[float]:
    """Each piece's speed limit [m/s]: its own, the gear's top speed and what its curvature
    allows (:func:`speed_cap`)."""
    lim = vehicle.limits
    top = lim.max_forward_speed if run[0].segment.gear > 0 else lim.max_reverse_speed
    return [min(top, p.speed_limit, speed_cap(p.segment, vehicle)) for p in run]


def _reach(length: float, v: float, cap: float, accel: float, jerk: float) -> float:
    """The highest speed ≤ ``cap`` [m/s] a change from ``v`` can reach (or, braking, come
    from) within ``length`` [m]."""
    return _largest(lambda w: _shift_distance(v, w, accel, accel, jerk) <= length, v, cap)


def _largest(fits, lo: float, hi: float) -> float:  # float -> bool
    """The largest speed in ``[lo, hi]`` that ``fits`` (monotone: true up to a point,
    and true at ``lo``), by bisection to 1e-12 m/s."""
    if fits(hi):
        return hi
    for _ in range(100):
        mid = (lo + hi) / 2
        if fits(mid):
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-12:
            break
    return lo


def run_profile(lengths: Sequence[float], caps: Sequence[float], vehicle: VehicleType
                ) -> Profile:
    """The rest-to-rest profile of a run of pieces with their own speed limits: the speed at
    each boundary is as high as the limits on both sides and the braking and accelerating
    around it allow (a backward then a forward pass), and each piece is the fastest
    :func:`scurve` between its boundary speeds, with zero acceleration at the boundaries."""
    lim = vehicle.limits
    return _run_profile(tuple(map(float, lengths)), tuple(map(float, caps)), lim.max_accel,
                        lim.max_brake, lim.max_jerk)


@functools.lru_cache(maxsize=1 << 16)
def _run_profile(lengths: tuple[float, ...], caps: tuple[float, ...], a: float, b: float,
                 j: float) -> Profile:
    """:func:`run_profile` for hashable arguments, kept: a lot's maneuvers repeat a few
    shapes, each timed once."""
    # merge neighbours with the same limit: no boundary needed between them
    merged: list[list[float]] = []
    for length, cap in zip(lengths, caps, strict=True):
        if merged and abs(merged[-1][1] - cap) <= 1e-12:
            merged[-1][0] += length
        else:
            merged.append([length, cap])
    n = len(merged)
    w = [0.0] + [min(merged[k][1], merged[k + 1][1]) for k in range(n - 1)] + [0.0]
    for k in range(n - 1, -1, -1):
        w[k] = min(w[k], _reach(merged[k][0], w[k + 1], merged[k][1], b, j))
    for k in range(n):
        w[k + 1] = min(w[k + 1], _reach(merged[k][0], w[k], merged[k][1], a, j))
    parts = []
    for k, (length, cap) in enumerate(merged):
        prof = scurve(length, w[k], w[k + 1], cap, a, b, j)
        assert prof is not None, "the passes keep every piece's ends joinable"
        parts.append(prof)
    if len(parts) == 1:
        return parts[0]
    t0 = np.cumsum([0.0] + [p.duration for p in parts[:-1]])
    s0 = np.cumsum([0.0] + [p.length for p in parts[:-1]])
    cols = [np.concatenate([parts[0].t] + [p.t[1:] + t for p, t in zip(parts[1:], t0[1:],
                                                                      strict=True)]),
            np.concatenate([parts[0].s] + [p.s[1:] + s for p, s in zip(parts[1:], s0[1:],
                                                                      strict=True)])]
    cols += [np.concatenate([parts[0].v] + [p.v[1:] for p in parts[1:]]),
             np.concatenate([parts[0].a] + [p.a[1:] for p in parts[1:]])]
    return Profile(*cols)


def timed_path(pieces: Sequence[Piece], vehicle: VehicleType, *, steer_from: float = 0.0,
               steer_to: float = 0.0) -> Motion:
    """Time a path from rest to rest within the vehicle's limits.

    The car stops at every cusp and wherever the curvature jumps between pieces,
    and turns its wheels there standing; it also steers standing from
    ``steer_from`` to the first piece's steering before it moves, and to
    ``steer_to`` after it stops [rad]. Each run between stops is driven from rest to
    rest by :func:`run_profile` under :func:`piece_caps`.
    """
    b = vehicle.wheelbase
    phases: list[Phase] = []
    steer = steer_from
    pose = pieces[0].segment.start if pieces else (0.0, 0.0, 0.0)
    for run in runs(pieces):
        first, last = run[0].segment, run[-1].segment
        want = math.atan(first.curvature * b)
        if abs(want - steer) > 1e-12:
            phases.append(Steering(pose, steer, want, steer_time(steer, want, vehicle)))
        prof = run_profile([p.segment.length for p in run], piece_caps(run, vehicle), vehicle)
        phases.append(Stroke(tuple(p.segment for p in run), prof))
        steer, pose = math.atan(last.end_curvature * b), last.end
    if phases and abs(steer_to - steer) > 1e-12:
        phases.append(Steering(pose, steer, steer_to, steer_time(steer, steer_to, vehicle)))
    return Motion(tuple(phases))


def drive(pieces: Sequence[Piece], vehicle: VehicleType, *, t0: float = 0.0,
          dt: float = DT) -> Trajectory:
    """Time-parameterise a path from rest to rest (:func:`timed_path`) and sample it.

    Parameters
    ----------
    pieces : sequence of Piece
        Consecutive segments (each starting where the last ends).
    vehicle : VehicleType
        Its limits bound the speed, acceleration and braking.
    t0 : float, keyword-only
        Start time [s].
    dt : float, keyword-only
        Sampling interval [s].

    Returns
    -------
    Trajectory
        Sampled every ``dt`` (the last interval of each stroke may be shorter).

    Examples
    --------
    >>> from lotsim.vehicles import CATALOGUE
    >>> tr = drive([Piece(Segment((0.0, 0.0, 0.0), 20.0, 0.0))], CATALOGUE["valet"])
    >>> round(float(tr.x[-1]), 6), float(tr.v[-1]), round(float(tr.v.max()) * 3.6, 3)
    (20.0, 0.0, 20.0)
    """
    motion = timed_path(pieces, vehicle)
    if not motion.phases:
        first = pieces[0].segment.start if pieces else (0.0, 0.0, 0.0)
        return standing_still(first, t0, 0.0, dt=dt)
    return sampled(motion, vehicle, t0, motion.times(dt))


def sampled(motion: Motion, vehicle: VehicleType, t0: float, tau: FloatArray) -> Trajectory:
    """``motion`` started at ``t0`` [s], sampled at times ``tau`` after it [s]."""
    poses, v, steer, gear = motion.at(tau, wheelbase=vehicle.wheelbase)
    return Trajectory(t0 + tau, poses[:, 0], poses[:, 1], poses[:, 2], v, steer, gear)
