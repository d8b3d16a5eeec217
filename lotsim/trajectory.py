"""Timed trajectories: a path of segments driven within a vehicle's limits.

A path is a list of :class:`Piece` — a :class:`~lotsim.geometry.Segment` and the
speed limit that applies on it. Consecutive pieces in one gear form a *stroke*;
the car stops at the end of every stroke (a cusp or the end of the path). Along
each stroke the speed follows the fastest profile that respects the piecewise
speed limit, the vehicle's forward or reverse top speed, its acceleration and its
braking: a forward pass accelerating from the entry speed, a backward pass braking
to every lower limit ahead and to rest at the end (the classic two-pass profile).

Trajectories are sampled in time — every ``dt`` seconds — with the pose taken on
the exact geometry of the segments, so samples never cut corners.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from lotsim.geometry import FloatArray, Pose, Segment, advance
from lotsim.vehicles.model import VehicleType

DT = 0.05
"""Default sampling interval [s]: at 20 km/h samples are 0.28 m apart."""
_DS = 0.05  # arc-length grid of the speed profile [m]


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


def standing(pose: Pose, t0: float, duration: float, *, dt: float = DT) -> Trajectory:
    """A vehicle standing still at ``pose`` from ``t0`` for ``duration`` seconds."""
    n = max(1, math.ceil(duration / dt - 1e-9))
    t = np.linspace(t0, t0 + duration, n + 1)
    z = np.zeros(n + 1)
    return Trajectory(t, z + pose[0], z + pose[1], z + pose[2], z, z, np.zeros(n + 1, dtype=int))


def strokes(pieces: Sequence[Piece]) -> list[list[Piece]]:
    """Consecutive pieces grouped into runs of one gear."""
    out: list[list[Piece]] = []
    for p in pieces:
        if p.segment.length <= 0:
            continue
        if out and out[-1][-1].segment.gear == p.segment.gear:
            out[-1].append(p)
        else:
            out.append([p])
    return out


def speed_profile(limits: FloatArray, ds: float, accel: float, brake: float,
                  v0: float = 0.0) -> FloatArray:
    """Fastest speeds [m/s] at grid points ``ds`` apart under ``limits`` (per point),
    starting at ``v0`` and ending at rest, with the given acceleration and braking."""
    v = limits.astype(float)  # a copy
    v[0] = min(v0, v[0])
    v[-1] = 0.0
    for i in range(1, len(v)):
        v[i] = min(v[i], math.sqrt(v[i - 1] ** 2 + 2 * accel * ds))
    for i in range(len(v) - 2, -1, -1):
        v[i] = min(v[i], math.sqrt(v[i + 1] ** 2 + 2 * brake * ds))
    return v


def trapezoid(length: float, v0: float, v1: float, vmax: float, accel: float,
              brake: float) -> Profile | None:
    """The fastest speed profile over ``length`` [m] from speed ``v0`` to ``v1`` [m/s] with
    top speed ``vmax``, acceleration ``accel`` and braking ``brake`` [m/s²] (closed form);
    None when the ends cannot be joined within the length.

    Examples
    --------
    >>> p = trapezoid(10.0, 0.0, 0.0, 5.0, 2.5, 5.0)   # 5 m ramp up, 2.5 m down, 2.5 m cruise
    >>> round(p.duration, 6), p.at(np.array([2.0]))[1].tolist()
    (3.5, [5.0])
    """
    if length <= 0 or v0 > vmax + 1e-9 or v1 > vmax + 1e-9:
        return None
    v0, v1 = min(v0, vmax), min(v1, vmax)
    if (v1 * v1 - v0 * v0) / (2 * accel) > length + 1e-9:
        return None
    if (v0 * v0 - v1 * v1) / (2 * brake) > length + 1e-9:
        return None
    peak2 = (2 * accel * brake * length + brake * v0 * v0 + accel * v1 * v1) / (accel + brake)
    p = max(min(vmax, math.sqrt(peak2)), v0, v1)
    d_acc = (p * p - v0 * v0) / (2 * accel)
    d_dec = (p * p - v1 * v1) / (2 * brake)
    cruise = max(0.0, length - d_acc - d_dec)
    if p <= 0:
        return None
    t_acc, t_dec = (p - v0) / accel, (p - v1) / brake
    t = np.array([0.0, t_acc, t_acc + cruise / p, t_acc + cruise / p + t_dec])
    s = np.array([0.0, d_acc, d_acc + cruise, length])
    return Profile(t, s, np.array([v0, p, p, v1]))


@dataclass(frozen=True)
class Profile:
    """Speed along one stroke in time: constant acceleration between breakpoints.

    Attributes
    ----------
    t, s, v : ndarray
        Breakpoint times [s] (from 0), path lengths [m] and speeds (≥ 0) [m/s].
    """

    t: FloatArray
    s: FloatArray
    v: FloatArray

    @property
    def duration(self) -> float:
        return float(self.t[-1])

    @property
    def length(self) -> float:
        return float(self.s[-1])

    def at(self, tau: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Path length [m] and speed [m/s] at times ``tau`` (0 ≤ tau ≤ duration) [s]."""
        t, s, v = self.t, self.s, self.v
        k = np.clip(np.searchsorted(t, tau, side="right") - 1, 0, len(t) - 2)
        cell = t[k + 1] - t[k]
        acc = np.where(cell > 0, (v[k + 1] - v[k]) / np.where(cell > 0, cell, 1.0), 0.0)
        d = np.clip(tau - t[k], 0.0, cell)
        pos = np.minimum(s[k] + v[k] * d + 0.5 * acc * d * d, s[k + 1])
        return pos, np.maximum(v[k] + acc * d, 0.0)


@dataclass(frozen=True)
class Stroke:
    """Consecutive segments in one gear and the speed profile they are driven with."""

    segments: tuple[Segment, ...]
    profile: Profile

    @property
    def gear(self) -> int:
        return self.segments[0].gear

    def poses(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Poses (N, 3) and curvatures (N,) after path lengths ``s`` [m]."""
        segs = self.segments
        lengths = np.array([g.length for g in segs])
        starts = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
        pid = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(segs) - 1)
        into = np.clip(s - starts[pid], 0.0, lengths[pid])
        seg_start = np.array([g.start for g in segs])[pid]
        kappa = np.array([g.curvature for g in segs])[pid]
        return advance(seg_start, self.gear * into, kappa), kappa


@dataclass(frozen=True)
class Motion:
    """A path timed stroke after stroke, from ``0`` to ``duration`` [s].

    The vehicle stops at the end of every stroke but the last, whose end
    speed may be non-zero (a lane edge driven through).
    """

    strokes: tuple[Stroke, ...]

    @property
    def duration(self) -> float:
        return float(sum(st.profile.duration for st in self.strokes))

    @property
    def offsets(self) -> FloatArray:
        """Start time of each stroke [s]."""
        d = [st.profile.duration for st in self.strokes]
        return np.concatenate([[0.0], np.cumsum(d)[:-1]])

    @property
    def cusps(self) -> FloatArray:
        """Times of the stops between strokes [s]."""
        return self.offsets[1:]

    def at(self, tau: FloatArray, *, wheelbase: float) -> tuple[FloatArray, ...]:
        """Poses (N, 3), signed speeds, steering angles and gears at times ``tau`` [s]."""
        tau = np.asarray(tau, dtype=float)
        off = self.offsets
        # a time at a stop between strokes belongs to the stroke that ends there
        which = np.clip(np.searchsorted(off, tau, side="left") - 1, 0, len(off) - 1)
        poses = np.empty((len(tau), 3))
        v = np.empty(len(tau))
        steer = np.empty(len(tau))
        gear = np.empty(len(tau), dtype=int)
        for i, st in enumerate(self.strokes):
            sel = which == i
            if not sel.any():
                continue
            s, speed = st.profile.at(tau[sel] - off[i])
            poses[sel], kappa = st.poses(s)
            v[sel] = st.gear * speed
            steer[sel] = np.arctan(kappa * wheelbase)
            gear[sel] = st.gear
        return poses, v, steer, gear

    def times(self, dt: float) -> FloatArray:
        """Sample times every ``dt`` within each stroke, each stroke's ends included."""
        out = []
        for st, t0 in zip(self.strokes, self.offsets, strict=True):
            d = st.profile.duration
            m = max(1, math.ceil(d / dt - 1e-9))
            out.append(t0 + np.linspace(0.0, d, m + 1))
        return np.unique(np.concatenate(out)) if out else np.zeros(1)


def rest_to_rest(pieces: Sequence[Piece], vehicle: VehicleType) -> Motion:
    """Time a path from rest to rest within the vehicle's limits, stopping at every cusp."""
    lim = vehicle.limits
    out = []
    for stroke in strokes(pieces):
        top = lim.max_forward_speed if stroke[0].segment.gear > 0 else lim.max_reverse_speed
        out.append(Stroke(tuple(p.segment for p in stroke),
                          _grid_profile(stroke, top, lim.max_accel, lim.max_brake)))
    return Motion(tuple(out))


def drive(pieces: Sequence[Piece], vehicle: VehicleType, *, t0: float = 0.0,
          dt: float = DT) -> Trajectory:
    """Time-parameterise a path from rest to rest, stopping at every cusp.

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
    motion = rest_to_rest(pieces, vehicle)
    if not motion.strokes:
        first = pieces[0].segment.start if pieces else (0.0, 0.0, 0.0)
        return standing(first, t0, 0.0, dt=dt)
    return sampled(motion, vehicle, t0, motion.times(dt))


def sampled(motion: Motion, vehicle: VehicleType, t0: float, tau: FloatArray) -> Trajectory:
    """``motion`` started at ``t0`` [s], sampled at times ``tau`` after it [s]."""
    poses, v, steer, gear = motion.at(tau, wheelbase=vehicle.wheelbase)
    return Trajectory(t0 + tau, poses[:, 0], poses[:, 1], poses[:, 2], v, steer, gear)


def _grid_profile(stroke: list[Piece], top: float, accel: float, brake: float) -> Profile:
    """Two-pass rest-to-rest profile on a fine arc-length grid under per-piece limits."""
    lengths = np.array([p.segment.length for p in stroke])
    starts = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    total = float(lengths.sum())
    # at least two steps: with one, both grid points are at rest and a stroke under _DS
    # would last 0 s and never be driven
    n = max(2, math.ceil(total / _DS))
    s = np.linspace(0.0, total, n + 1)
    which = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(stroke) - 1)
    piece_limit = np.array([min(p.speed_limit, top) for p in stroke])
    limit = piece_limit[which]
    # a grid point on a boundary obeys the lower of the two pieces' limits
    on_edge = np.isin(np.round(s, 9), np.round(starts[1:], 9))
    prev = np.clip(which - 1, 0, None)
    limit = np.where(on_edge, np.minimum(limit, piece_limit[prev]), limit)
    v = speed_profile(limit, total / n, accel, brake)
    vm = (v[:-1] + v[1:]) / 2
    with np.errstate(divide="ignore"):
        dtime = np.where(vm > 0, (total / n) / vm, 0.0)
    return Profile(np.concatenate([[0.0], np.cumsum(dtime)]), s, v)
