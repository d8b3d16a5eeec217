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
    lim = vehicle.limits
    parts: list[Trajectory] = []
    t = t0
    for stroke in strokes(pieces):
        tr = _drive_stroke(stroke, vehicle, t, dt, lim.max_accel, lim.max_brake)
        parts.append(tr)
        t = tr.end_time
    if not parts:
        first = pieces[0].segment.start if pieces else (0.0, 0.0, 0.0)
        return standing(first, t0, 0.0, dt=dt)
    out = parts[0]
    for p in parts[1:]:
        out = out.then(p)
    return out


def _drive_stroke(stroke: list[Piece], vehicle: VehicleType, t0: float, dt: float,
                  accel: float, brake: float) -> Trajectory:
    gear = stroke[0].segment.gear
    top = vehicle.limits.max_forward_speed if gear > 0 else vehicle.limits.max_reverse_speed
    lengths = np.array([p.segment.length for p in stroke])
    starts = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    total = float(lengths.sum())
    n = max(1, math.ceil(total / _DS))
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
    times = np.concatenate([[0.0], np.cumsum(dtime)])
    duration = float(times[-1])
    m = max(1, math.ceil(duration / dt - 1e-9))
    ts = np.linspace(0.0, duration, m + 1)
    # arc length at each sample time: within a grid cell speed varies linearly with time
    k = np.clip(np.searchsorted(times, ts, side="right") - 1, 0, n - 1)
    tau = ts - times[k]
    cell = np.maximum(dtime[k], 1e-12)
    acc = (v[k + 1] - v[k]) / cell
    ss = np.minimum(s[k] + v[k] * tau + 0.5 * acc * tau * tau, s[k + 1])
    ss[-1] = total
    vs = v[k] + acc * tau
    vs[-1] = 0.0
    pid = np.clip(np.searchsorted(starts, ss, side="right") - 1, 0, len(stroke) - 1)
    into = np.minimum(ss - starts[pid], lengths[pid])
    seg_start = np.array([p.segment.start for p in stroke])[pid]
    kappa = np.array([p.segment.curvature for p in stroke])[pid]
    poses = advance(seg_start, gear * into, kappa)
    steer = np.arctan(kappa * vehicle.wheelbase)
    gears = np.full(len(ts), gear, dtype=int)
    return Trajectory(t0 + ts, poses[:, 0], poses[:, 1], poses[:, 2], gear * vs, steer, gears)
