"""The reservation table: where every planned vehicle is, in space and time.

An entry is a body (a polygon) held by an owner over a time interval
``[t0, t1]`` [s]. A moving vehicle reserves, for each short chunk of its motion,
the convex hull of its footprints over that chunk — a cover of what it sweeps,
so two vehicles whose overlapping-in-time entries do not touch cannot touch at
any instant, not only at samples. A standing vehicle reserves its footprint
over the time it stands; a parked one with ``t1 = inf``.

Time is bucketed (``bucket`` seconds); each bucket lists the entries whose
interval meets it, and a query filters candidates by time and bounding box in
numpy before an exact shapely test. Long entries (parked cars, long waits) sit
in one list that every query scans.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from lotsim.geometry import FloatArray
from lotsim.trajectory import Motion, Trajectory
from lotsim.vehicles.model import VehicleType

CHUNK = 0.5
"""Longest time one swept hull covers [s]."""
_SAMPLE = 0.2  # largest distance between footprints inside a hull [m]
_LONG = 16  # entries spanning more buckets than this go to the long list
_EPS = 1e-9

Interval = tuple[float, float, BaseGeometry]
"""A body held from ``t0`` to ``t1`` [s]."""


@dataclass(frozen=True, slots=True)
class Conflict:
    """A clash with ``owner``'s body held over ``[t0, t1]`` [s]."""

    owner: str
    t0: float
    t1: float


def chunk_edges(t0: float, t1: float, chunk: float = CHUNK) -> FloatArray:
    """Boundaries of the chunks ``[t0, t1]`` is cut into, none longer than ``chunk`` [s]."""
    n = max(1, math.ceil((t1 - t0) / chunk - 1e-9))
    return np.linspace(t0, t1, n + 1)


def swept(poses: FloatArray, times: FloatArray, vehicle: VehicleType, *,
          chunk: float = CHUNK) -> list[Interval]:
    """Hulls of the footprints at ``poses`` (N, 3) sampled at ``times`` (N,) [s], one per
    chunk of at most ``chunk`` seconds: ``[(t0, t1, hull), ...]``.

    The samples must include the chunk boundaries (:func:`chunk_edges`; missing
    ones are interpolated linearly) and be dense enough that consecutive
    footprints cover the swept area's bulge (a few millimetres at 0.2 m steps
    on the tightest arc).
    """
    times = np.asarray(times, dtype=float)
    poses = np.asarray(poses, dtype=float)
    if len(times) == 1 or times[-1] - times[0] <= 0:
        body = shapely.Polygon(vehicle.footprints(poses[:1])[0])
        return [(float(times[0]), float(times[-1]), body)]
    edges = chunk_edges(float(times[0]), float(times[-1]), chunk)
    missing = edges[~np.isin(edges, times)]
    if missing.size:
        theta = np.unwrap(poses[:, 2])
        extra = np.column_stack([np.interp(missing, times, poses[:, 0]),
                                 np.interp(missing, times, poses[:, 1]),
                                 np.interp(missing, times, theta)])
        order = np.argsort(np.concatenate([times, missing]), kind="stable")
        times = np.concatenate([times, missing])[order]
        poses = np.concatenate([np.column_stack([poses[:, :2], theta]), extra])[order]
    n = len(edges) - 1
    # chunk i takes the samples in [edges[i], edges[i+1]]; boundary samples belong to both
    lo = np.searchsorted(times, edges[:-1] - _EPS, side="left")
    hi = np.searchsorted(times, edges[1:] + _EPS, side="right")
    idx = np.concatenate([np.arange(a, b) for a, b in zip(lo, hi, strict=True)])
    owner = np.repeat(np.arange(n), hi - lo)
    pts = vehicle.footprints(poses[idx]).reshape(-1, 2)
    # hulls of linestrings through the corners: cheaper to build than of multipoints
    hulls = shapely.convex_hull(shapely.linestrings(pts, indices=np.repeat(owner, 4)))
    return [(float(edges[i]), float(edges[i + 1]), hulls[i]) for i in range(n)]


def swept_motion(motion: Motion, vehicle: VehicleType, *, chunk: float = CHUNK
                 ) -> list[Interval]:
    """:func:`swept` for a timed motion, in the motion's own time (from 0) [s]."""
    top = max(vehicle.limits.max_forward_speed, vehicle.limits.max_reverse_speed)
    tau = np.union1d(motion.times(_SAMPLE / top), chunk_edges(0.0, motion.duration, chunk))
    poses = motion.at(tau, wheelbase=vehicle.wheelbase)[0]
    return swept(poses, tau, vehicle, chunk=chunk)


def swept_trajectory(trajectory: Trajectory, vehicle: VehicleType, *,
                     chunk: float = CHUNK) -> list[Interval]:
    """:func:`swept` for a sampled trajectory (in its own absolute times)."""
    return swept(trajectory.poses, trajectory.t, vehicle, chunk=chunk)


class _Store:
    """Growable columns of entries."""

    def __init__(self) -> None:
        self.n = 0
        cap = 1024
        self.owner = np.zeros(cap, dtype=np.int64)
        self.t = np.zeros((cap, 2))
        self.box = np.zeros((cap, 4))
        self.alive = np.zeros(cap, dtype=bool)
        self.geom = np.empty(cap, dtype=object)

    def add(self, owner: int, t0: float, t1: float, geom: BaseGeometry) -> int:
        if self.n == len(self.owner):
            cap = 2 * self.n
            for name in ("owner", "t", "box", "alive", "geom"):
                old = getattr(self, name)
                new = (np.empty if name == "geom" else np.zeros)(
                    (cap,) + old.shape[1:], dtype=old.dtype)
                new[: self.n] = old[: self.n]
                setattr(self, name, new)
        i = self.n
        self.owner[i] = owner
        self.t[i] = (t0, t1)
        self.box[i] = geom.bounds
        self.alive[i] = True
        self.geom[i] = geom
        self.n += 1
        return i


class ReservationTable:
    """Space-time reservations of vehicles' bodies.

    Parameters
    ----------
    bucket : float
        Width of a time bucket [s].

    Examples
    --------
    >>> from shapely.geometry import box
    >>> table = ReservationTable()
    >>> table.reserve("a", [(0.0, 0.5, box(0, 0, 2, 2)), (0.5, 1.0, box(1, 0, 3, 2))])
    >>> table.first_conflict([(0.6, 0.9, box(2.5, 0, 4, 1))]).owner
    'a'
    >>> table.first_conflict([(0.0, 0.4, box(2.5, 0, 4, 1))]) is None
    True
    """

    def __init__(self, bucket: float = 1.0):
        if not bucket > 0:
            raise ValueError("bucket must be positive")
        self.bucket = bucket
        self._store = _Store()
        self._buckets: dict[int, list[int]] = {}
        self._bucket_arrays: dict[int, np.ndarray] = {}
        self._long: list[int] = []
        self._long_array: np.ndarray | None = None
        self._ids: dict[str, int] = {}
        self._names: list[str] = []
        self._by_owner: dict[int, list[int]] = {}

    def __len__(self) -> int:
        return int(self._store.alive[: self._store.n].sum())

    # -- reserving ----------------------------------------------------------------------------
    def reserve(self, owner: str, intervals: Iterable[Interval], *, offset: float = 0.0) -> None:
        """Hold each ``(t0, t1, body)`` for ``owner``, shifted by ``offset`` [s]."""
        oid = self._owner_id(owner)
        for t0, t1, geom in intervals:
            self._add(oid, t0 + offset, t1 + offset, geom)

    def reserve_standing(self, owner: str, body: BaseGeometry, since: float,
                         until: float = math.inf) -> None:
        """A body standing from ``since`` to ``until`` [s] (for ever by default: parked)."""
        self._add(self._owner_id(owner), since, until, body)

    def release(self, owner: str, *, after: float | None = None) -> None:
        """Drop ``owner``'s entries that begin at or after ``after`` [s] (all, if None);
        entries running past ``after`` are cut short there."""
        oid = self._ids.get(owner)
        if oid is None:
            return
        st = self._store
        keep = []
        for i in self._by_owner.get(oid, []):
            if not st.alive[i]:
                continue
            t0, t1 = st.t[i]
            if after is None or t0 >= after:
                st.alive[i] = False
            else:
                if t1 > after:
                    st.t[i, 1] = after
                keep.append(i)
        self._by_owner[oid] = keep

    # -- asking -------------------------------------------------------------------------------
    def first_conflict(self, intervals: Sequence[Interval], *, offset: float = 0.0,
                       ignore: str | None = None) -> Conflict | None:
        """The first of ``intervals`` (shifted by ``offset``) that meets someone else's body
        over overlapping time, as that body's owner and interval; None when all are free."""
        skip = self._ids.get(ignore, -1) if ignore is not None else -1
        st = self._store
        for t0, t1, geom in intervals:
            a, b = t0 + offset, t1 + offset
            cand = self._candidates(a, b)
            if cand.size == 0:
                continue
            x0, y0, x1, y1 = geom.bounds
            bx = st.box[cand]
            tt = st.t[cand]
            sel = (st.alive[cand] & (st.owner[cand] != skip)
                   & (tt[:, 0] <= b + _EPS) & (tt[:, 1] >= a - _EPS)
                   & (bx[:, 0] <= x1) & (bx[:, 2] >= x0) & (bx[:, 1] <= y1) & (bx[:, 3] >= y0))
            cand = cand[sel]
            if cand.size == 0:
                continue
            hit = shapely.intersects(st.geom[cand], geom)
            if hit.any():
                i = int(cand[np.argmax(hit)])
                return Conflict(self._names[st.owner[i]], float(st.t[i, 0]), float(st.t[i, 1]))
        return None

    def is_free(self, intervals: Sequence[Interval], *, offset: float = 0.0,
                ignore: str | None = None) -> bool:
        return self.first_conflict(intervals, offset=offset, ignore=ignore) is None

    def free_from(self, body: BaseGeometry, since: float, *, ignore: str | None = None
                  ) -> Conflict | None:
        """Whoever's body meets ``body`` at some time from ``since`` on [s] (None: nobody)."""
        st = self._store
        n = st.n
        skip = self._ids.get(ignore, -1) if ignore is not None else -1
        x0, y0, x1, y1 = body.bounds
        bx = st.box[:n]
        sel = (st.alive[:n] & (st.owner[:n] != skip) & (st.t[:n, 1] >= since - _EPS)
               & (bx[:, 0] <= x1) & (bx[:, 2] >= x0) & (bx[:, 1] <= y1) & (bx[:, 3] >= y0))
        cand = np.flatnonzero(sel)
        if cand.size == 0:
            return None
        hit = shapely.intersects(st.geom[cand], body)
        if not hit.any():
            return None
        i = int(cand[np.argmax(hit)])
        return Conflict(self._names[st.owner[i]], float(st.t[i, 0]), float(st.t[i, 1]))

    def owners(self) -> set[str]:
        st = self._store
        return {self._names[o] for o in np.unique(st.owner[: st.n][st.alive[: st.n]])}

    # -- internals ----------------------------------------------------------------------------
    def _owner_id(self, owner: str) -> int:
        if owner not in self._ids:
            self._ids[owner] = len(self._names)
            self._names.append(owner)
        return self._ids[owner]

    def _add(self, oid: int, t0: float, t1: float, geom: BaseGeometry) -> None:
        i = self._store.add(oid, t0, t1, geom)
        self._by_owner.setdefault(oid, []).append(i)
        if math.isinf(t0) or math.isinf(t1) or math.floor(t1 / self.bucket) - math.floor(
                t0 / self.bucket) > _LONG:
            self._long.append(i)
            self._long_array = None
            return
        for k in range(math.floor(t0 / self.bucket), math.floor(t1 / self.bucket) + 1):
            self._buckets.setdefault(k, []).append(i)
            self._bucket_arrays.pop(k, None)

    def _candidates(self, t0: float, t1: float) -> np.ndarray:
        parts = []
        for k in range(math.floor((t0 - _EPS) / self.bucket),
                       math.floor((t1 + _EPS) / self.bucket) + 1):
            if k in self._buckets:
                arr = self._bucket_arrays.get(k)
                if arr is None:
                    arr = self._bucket_arrays[k] = np.array(self._buckets[k], dtype=np.int64)
                parts.append(arr)
        if self._long:
            if self._long_array is None:
                self._long_array = np.array(self._long, dtype=np.int64)
            parts.append(self._long_array)
        if not parts:
            return np.zeros(0, dtype=np.int64)
        return parts[0] if len(parts) == 1 else np.concatenate(parts)


def standing_body(vehicle: VehicleType, pose: FloatArray) -> BaseGeometry:
    """The footprint polygon of ``vehicle`` standing at ``pose``."""
    return shapely.Polygon(vehicle.footprints(np.asarray(pose, dtype=float)[None, :])[0])
