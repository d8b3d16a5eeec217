"""The reservation table: where every planned vehicle is, in space and time.

An entry is a body (a polygon) held by an owner over a time interval
``[t0, t1]`` [s]. A moving vehicle reserves, for each short chunk of its motion,
the convex hull of its footprints over that chunk — a cover of what it sweeps,
so two vehicles whose overlapping-in-time entries do not touch cannot touch at
any instant, not only at samples. A standing vehicle reserves its footprint
over the time it stands; a parked one with ``t1 = inf``.

Entries are filed in a space-time grid — cells of :data:`CELL` metres and
``bucket`` seconds — so a query in free space is a few dictionary lookups;
candidates are filtered by time and bounding box and tested exactly with
shapely in one batch. Long entries (long waits, a WHCA* stop) are filed by
space only.
"""

from __future__ import annotations

import bisect
import functools
import heapq
import math
import operator
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from lotsim.core.geometry import FloatArray
from lotsim.vehicles.model import VehicleType
from lotsim.vehicles.motion import Motion, Profile, Stroke, Trajectory

CHUNK = 0.5
"""Longest time one swept hull covers [s]."""
_SAMPLE = 0.2  # largest distance between footprints inside a hull [m]
CELL = 6.0
"""Side of the spatial grid cells entries are filed under [m]."""
_LONG = 16  # entries spanning more time buckets than this are filed by space only
_EPS = 1e-9
_FEW_PAIRS = 256  # candidate pairs up to which ReservationTable.blocked filters in Python
_FEW_ENTRIES = 512  # candidate entries up to which ReservationTable.nearby filters in Python

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
    edges = chunk_edges(0.0, motion.duration, chunk)
    if all(g.curvature == 0 and g.sharpness == 0 for st in motion.strokes for g in st.segments):
        # along straights the hull of the ends is the exact sweep
        tau = np.union1d(edges, motion.cusps)
    else:
        top = max(vehicle.limits.max_forward_speed, vehicle.limits.max_reverse_speed)
        tau = np.union1d(motion.times(_SAMPLE / top), edges)
    poses = motion.at(tau, wheelbase=vehicle.wheelbase)[0]
    return swept(poses, tau, vehicle, chunk=chunk)


def swept_motions(motions: Sequence[Motion], vehicle: VehicleType, *, chunk: float = CHUNK
                  ) -> list[Swept]:
    """:func:`swept_motion` of each of ``motions``, as :class:`Swept`.

    Motions that drive the same straight path in one stroke (one lane edge between
    different speeds) are done together, each step one numpy call for all of them: the
    same numbers, element by element, at a fraction of the cost per motion.
    """
    first = motions[0].phases if motions else ()
    if not (first and all(len(m.phases) == 1 and isinstance(m.phases[0], Stroke)
                          and m.phases[0].segments == first[0].segments and m.duration > 0
                          for m in motions)
            and all(g.curvature == 0 and g.sharpness == 0 for g in first[0].segments)):
        return [Swept.of(swept_motion(m, vehicle, chunk=chunk)) for m in motions]
    # as swept_motion and swept do for each: samples at the chunk edges only (along
    # straights the hull of the ends is the exact sweep), each chunk the hull of the
    # footprints at its two ends
    edges, s, spans = zip(*(_chunk_samples(m.phases[0].profile, chunk) for m in motions),
                          strict=True)
    s = np.concatenate(s)
    pts = vehicle.footprints(first[0].poses(s)[0])
    # chunk i of a motion takes its samples i and i + 1 (a motion's samples start after the
    # previous motion's): the indices as a Python list, a few motions' worth
    idx: list[int] = []
    start = 0
    for e in edges:
        for i in range(start, start + len(e) - 1):
            idx += (i, i + 1)
        start += len(e)
    # one linestring of 8 corners a chunk: as an (N, 8, 2) array, not by indices (the
    # same points, several times quicker to build)
    hulls = shapely.convex_hull(shapely.linestrings(pts[idx].reshape(-1, 8, 2)))
    bounds = shapely.bounds(hulls)
    cells = _cells_of_all(bounds)
    out = []
    c = 0
    for e, span in zip(edges, spans, strict=True):
        k = len(e) - 1
        b = bounds[c: c + k]
        # rows share their times' float objects with every hull of the profile
        out.append(Swept(hulls[c: c + k], cells[c: c + k],
                         tuple((*ab, *xy) for ab, xy in zip(span, b.tolist(), strict=True))))
        c += k
    return out


@functools.lru_cache(maxsize=1 << 14)
def _chunk_samples(profile: Profile, chunk: float
                   ) -> tuple[FloatArray, FloatArray, tuple[tuple[float, float], ...]]:
    """A profile's chunk edges [s], path lengths there [m] and each chunk's ``(t0, t1)``
    (kept: profiles are shared by every edge of a length driven between the same
    speeds)."""
    edges = chunk_edges(0.0, profile.duration, chunk)
    s = profile.at(edges)[0]
    edges.flags.writeable = s.flags.writeable = False
    e = edges.tolist()
    return edges, s, tuple(zip(e[:-1], e[1:], strict=True))


def swept_trajectory(trajectory: Trajectory, vehicle: VehicleType, *,
                     chunk: float = CHUNK) -> list[Interval]:
    """:func:`swept` for a sampled trajectory (in its own absolute times)."""
    return swept(trajectory.poses, trajectory.t, vehicle, chunk=chunk)


@dataclass(frozen=True, slots=True)
class Swept:
    """Intervals for batched queries: hulls (N,), each one's grid cells, and each one's
    times and bounds as rows of Python floats; :attr:`t` (N, 2) [s] and :attr:`bounds`
    (N, 4) [m] as arrays, made from the rows when asked.

    (Slots, and no arrays of times and bounds kept: a run keeps one for every edge motion
    it has checked, some 60 000 for 1000 cars on the large lot, and the searches read the
    rows.)"""

    geoms: np.ndarray
    cells: tuple[tuple[tuple[int, int], ...], ...] = ()
    rows: tuple[tuple[float, ...], ...] = ()
    """Each interval's ``(t0, t1, x0, y0, x1, y1)`` as Python floats (for loops over a few
    pairs, where numpy's fixed cost per call is more than the work)."""

    @classmethod
    def of(cls, intervals: Sequence[Interval]) -> Swept:
        geoms = np.empty(len(intervals), dtype=object)
        geoms[:] = [g for _, _, g in intervals]
        t = np.array([(a, b) for a, b, _ in intervals], dtype=float).reshape(-1, 2)
        bounds = shapely.bounds(geoms).reshape(-1, 4)
        return cls(geoms, _cells_of_all(bounds),
                   tuple(map(tuple, np.hstack([t, bounds]).tolist())))

    @property
    def t(self) -> np.ndarray:
        """(N, 2) each interval's start and end [s] (the rows' floats)."""
        return np.array([r[:2] for r in self.rows], dtype=float).reshape(-1, 2)

    @property
    def bounds(self) -> np.ndarray:
        """(N, 4) each hull's ``(x0, y0, x1, y1)`` [m] (the rows' floats)."""
        return np.array([r[2:] for r in self.rows], dtype=float).reshape(-1, 4)

    def held(self, t0: float, t1: float) -> Swept:
        """The first body held from ``t0`` to ``t1`` [s] (a standing body's)."""
        return Swept(self.geoms[:1], self.cells[:1], ((float(t0), float(t1),
                                                       *self.rows[0][2:]),))

    extent: tuple[float, ...] = field(init=False, repr=False, compare=False)
    """``(t0, t1, x0, y0, x1, y1)`` of all the intervals together: the earliest start and
    latest end [s], and the box holding every hull [m] (empty with no intervals)."""
    in_order: bool = field(init=False, repr=False, compare=False)
    """Whether the intervals' starts and their ends each never decrease (a motion's chunks
    do)."""

    def __post_init__(self) -> None:
        # the rows' columns (zip in C), each reduced by min or max and compared with itself
        # one step on: the same floats and answers as pair by pair, for the ~60 000 made
        a, z, x0, y0, x1, y1 = zip(*self.rows, strict=True) if self.rows else ((),) * 6
        extent = (min(a), max(z), min(x0), min(y0), max(x1), max(y1)) if a else ()
        object.__setattr__(self, "extent", extent)
        object.__setattr__(self, "in_order", all(map(operator.le, a, a[1:]))
                           and all(map(operator.le, z, z[1:])))

    def __len__(self) -> int:
        return len(self.geoms)

    def __iter__(self):
        for r, g in zip(self.rows, self.geoms, strict=True):
            yield r[0], r[1], g


def cells_of(bounds: Sequence[float]) -> tuple[tuple[int, int], ...]:
    """The grid cells a bounding box ``(x0, y0, x1, y1)`` meets."""
    return _block(*(math.floor(float(c) / CELL) for c in bounds))


def _cells_of_all(bounds: np.ndarray) -> tuple[tuple[tuple[int, int], ...], ...]:
    """:func:`cells_of` of each row of ``bounds`` (N, 4), the divisions in one call."""
    return tuple(_block(*r) for r in np.floor(bounds / CELL).astype(np.int64).tolist())


@functools.lru_cache(maxsize=1 << 16)
def _block(x0: int, y0: int, x1: int, y1: int) -> tuple[tuple[int, int], ...]:
    """The cells from ``(x0, y0)`` to ``(x1, y1)``, kept: the same few blocks are asked for
    by hundreds of thousands of hulls and entries, which then share one tuple."""
    return tuple((i, j) for i in range(x0, x1 + 1) for j in range(y0, y1 + 1))


@dataclass(slots=True)
class Near:
    """Entries filed near a query (:meth:`ReservationTable.nearby`): their ids, ascending,
    and each one's ``(t0, t1, x0, y0, x1, y1)``; false when there are none.

    (Never changed once made, but not frozen: a search makes one or two for every edge it
    looks along, and a frozen dataclass takes over twice as long to make.)"""

    ids: list[int]
    rows: list[tuple[float, ...]]

    def __bool__(self) -> bool:
        return bool(self.ids)

    def within(self, box: tuple[float, float, float, float]) -> Near:
        """Those whose box meets ``box`` ``(x0, y0, x1, y1)`` [m]: as :meth:`ReservationTable.
        nearby` with that ``box``."""
        x0, y0, x1, y1 = box
        kept = [k for k, r in enumerate(self.rows)
                if r[2] <= x1 and r[4] >= x0 and r[3] <= y1 and r[5] >= y0]
        if len(kept) == len(self.ids):
            return self
        return Near([self.ids[k] for k in kept], [self.rows[k] for k in kept])


_NOBODY = Near([], [])  # no entries (shared: a Near is never changed)


def _within_window(ids: list[int], rows: list[tuple[float, ...]], t0: float, t1: float,
                   box: tuple[float, float, float, float] | None) -> Near:
    """Those of entries ``ids`` (rows ``rows``) whose time overlaps ``[t0, t1]`` [s] and,
    given ``box``, whose box meets it: :meth:`ReservationTable.nearby`'s last filter."""
    lo, hi = t0 - _EPS, t1 + _EPS
    if box is None:
        kept = [k for k, r in enumerate(rows) if r[0] <= hi and r[1] >= lo]
    else:
        x0, y0, x1, y1 = box
        kept = [k for k, r in enumerate(rows) if r[0] <= hi and r[1] >= lo and r[2] <= x1
                and r[4] >= x0 and r[3] <= y1 and r[5] >= y0]
    if not kept:
        return _NOBODY
    if len(kept) == len(ids):
        return Near(ids, rows)
    return Near([ids[k] for k in kept], [rows[k] for k in kept])


class _Store:
    """Growable columns of entries."""

    def __init__(self) -> None:
        self.n = 0
        cap = 1024
        self.owner = np.zeros(cap, dtype=np.int64)
        self.t = np.zeros((cap, 2))
        self.box = np.zeros((cap, 4))
        self.alive = np.zeros(cap, dtype=bool)
        self.in_slot = np.zeros(cap, dtype=bool)
        self.geom = np.empty(cap, dtype=object)
        # the same as Python values, for queries that meet a few entries (numpy's fixed
        # cost per call is more than their work): each entry's owner, and its
        # (t0, t1, x0, y0, x1, y1) while alive (None once dropped)
        self.who: list[int] = []
        self.rows: list[tuple[float, ...] | None] = []

    def add(self, owner: int, t0: float, t1: float, geom: BaseGeometry,
            in_slot: bool = False, bounds: Sequence[float] | None = None) -> int:
        """Entry ``i`` (returned): ``geom`` held by ``owner`` from ``t0`` to ``t1`` [s];
        ``bounds``, if given, ``geom.bounds`` worked out before (as a :class:`Swept`'s rows
        hold them: the same floats)."""
        if bounds is None:
            bounds = geom.bounds
        if self.n == len(self.owner):
            cap = 2 * self.n
            for name in ("owner", "t", "box", "alive", "in_slot", "geom"):
                old = getattr(self, name)
                new = (np.empty if name == "geom" else np.zeros)(
                    (cap,) + old.shape[1:], dtype=old.dtype)
                new[: self.n] = old[: self.n]
                setattr(self, name, new)
        i = self.n
        self.owner[i] = owner
        self.t[i] = (t0, t1)
        self.box[i] = bounds
        self.alive[i] = True
        self.in_slot[i] = in_slot
        self.geom[i] = geom
        self.who.append(owner)
        self.rows.append((float(t0), float(t1), *map(float, bounds)))  # (the arrays' floats)
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
        self._grid: dict[tuple[int, int], dict[int, list[int]]] = {}  # cell → bucket → ids
        self._long_cells: dict[tuple[int, int], list[int]] = {}
        self._ids: dict[str, int] = {}
        self._names: list[str] = []
        self._by_owner: dict[int, list[int]] = {}
        self._last = -math.inf  # the latest finite time any grid-filed entry reaches [s]
        self._bucket_cells: dict[int, list[tuple[int, int]]] = {}  # bucket → cells filed in it
        self._long_ends: list[tuple[float, int]] = []  # heap of (t1, id) of finite long entries
        self._forgot = -(2 ** 62)  # buckets before this one are forgotten
        # blocked_standing's bodies: id → [the body, entries tested up to, those it meets]
        self._standing: dict[int, list] = {}
        self._log: dict[tuple[int, int], list[int]] = {}  # cell → ids ever filed there
        self.releases: list[tuple[float, str, bool]] = []
        """Every :meth:`release` that dropped or cut something, in order: the time from
        which it freed space [s], whose it was, and whether all it freed stood in a slot
        (space is freed in no other way)."""

    def __len__(self) -> int:
        return int(self._store.alive[: self._store.n].sum())

    # -- reserving ----------------------------------------------------------------------------
    def reserve(self, owner: str, intervals: Iterable[Interval], *, offset: float = 0.0) -> None:
        """Hold each ``(t0, t1, body)`` for ``owner``, shifted by ``offset`` [s]."""
        oid = self._owner_id(owner)
        if isinstance(intervals, Swept):  # its bounds and cells are known
            for (t0, t1, *bounds), geom, cells in zip(intervals.rows, intervals.geoms,
                                                      intervals.cells, strict=True):
                self._add(oid, t0 + offset, t1 + offset, geom, bounds=bounds, cells=cells)
            return
        for t0, t1, geom in intervals:
            self._add(oid, t0 + offset, t1 + offset, geom)

    def reserve_standing(self, owner: str, body: BaseGeometry, since: float,
                         until: float = math.inf, *, in_slot: bool = False) -> None:
        """A body standing from ``since`` to ``until`` [s] (for ever by default: parked).

        With ``in_slot`` the body stands inside a parking slot. Such bodies are
        seen only by :meth:`free_from` (the goal test), not by :meth:`first_conflict`:
        lanes and turns are swept clear of every slot when the lot graph is
        built, and each maneuver clear of a car parked in every other slot, so
        no move can reach them, and the queries skip hundreds of parked cars.
        """
        self._add(self._owner_id(owner), since, until, body, in_slot=in_slot)

    def release(self, owner: str, *, after: float | None = None) -> None:
        """Drop ``owner``'s entries that begin at or after ``after`` [s] (all, if None);
        entries running past ``after`` are cut short there."""
        oid = self._ids.get(owner)
        if oid is None:
            return
        st = self._store
        keep = []
        freed = []
        for i in self._by_owner.get(oid, []):
            if not st.alive[i]:
                continue
            t0, t1 = st.t[i]
            if after is None or t0 >= after:
                st.alive[i] = False
                st.rows[i] = None
                freed.append(i)
            else:
                if t1 > after:
                    st.t[i, 1] = after
                    st.rows[i] = (*st.t[i].tolist(), *st.rows[i][2:])
                    freed.append(i)
                keep.append(i)
        self._by_owner[oid] = keep
        if freed:
            self.releases.append((-math.inf if after is None else after, owner,
                                  bool(st.in_slot[freed].all())))

    def forget_before(self, t: float) -> None:
        """Drop what no query about time ``t`` [s] or later can meet: the grid's time buckets
        before ``t``'s, and the entries that end before ``t``.

        The caller promises that every later query asks about times from ``t`` on (a
        simulation whose clock has reached ``t``: every later search starts then or later).
        Its answers are then those of a table that kept everything: a query from ``t0 >= t``
        looks only in buckets from ``floor((t0 - eps) / bucket)`` on and keeps only entries
        with ``t1 >= t0 - eps``; and :meth:`taken_until`, which may now say ``-inf`` for a
        time before ``t``, is compared only with times after it. What it saves: memory (each
        entry's row and, for standing bodies, polygon) and the scans of long entries that
        are over.
        """
        k = math.floor((t - _EPS) / self.bucket)
        if k <= self._forgot:
            return
        self._forgot = k
        st, grid = self._store, self._grid
        rows, times = st.rows, st.t
        for kk in [b for b in self._bucket_cells if b < k]:
            for cell in self._bucket_cells.pop(kk):
                by_bucket = grid[cell]
                for i in by_bucket.pop(kk):
                    if rows[i] is not None and times[i, 1] + _EPS < t:
                        self._forget(i)
                if not by_bucket:
                    del grid[cell]
                # the log's dead beginning (nobody needs a dead entry: blocked_standing
                # passes over them), so that logs hold about what the grid does
                log = self._log.get(cell)
                if log and rows[log[0]] is None:
                    j = 1
                    while j < len(log) and rows[log[j]] is None:
                        j += 1
                    del log[:j]
        ends = self._long_ends
        while ends and ends[0][0] + _EPS < t:
            _, i = heapq.heappop(ends)
            if rows[i] is not None and times[i, 1] + _EPS < t:
                self._forget(i)
                for cell in cells_of(st.box[i]):
                    self._long_cells[cell].remove(i)

    def _forget(self, i: int) -> None:
        """Entry ``i`` is over for every query to come: as if dropped. (:attr:`releases` is
        as before as long as every later :meth:`release` is from a time ``after`` at or
        past the forgetting's: such a release would have kept the entry whole.)"""
        st = self._store
        st.alive[i] = False
        st.rows[i] = None
        st.geom[i] = None

    # -- asking -------------------------------------------------------------------------------
    def first_conflict(self, intervals: Sequence[Interval] | Swept, *, offset: float = 0.0,
                       ignore: str | None = None, among: Near | None = None
                       ) -> Conflict | None:
        """The earliest of ``intervals`` (shifted by ``offset``) that meets someone else's
        body over overlapping time, as that body's owner and interval; None when all are
        free.

        Entries are filed in a space-time grid (cells of :data:`CELL` metres and
        ``bucket`` seconds), so a query in free space costs a few dictionary
        lookups; the few candidates are tested exactly with shapely in one batch.
        ``among`` (from :meth:`nearby`, over grid cells and a time window that hold
        the shifted intervals, for the same ``ignore``) saves gathering them again.
        """
        sw = intervals if isinstance(intervals, Swept) else Swept.of(intervals)
        st = self._store
        if among is not None:
            pairs_j, pairs_i = _pairs(sw, among, offset)
        else:
            skip = self._ids.get(ignore, -1) if ignore is not None else -1
            b = self.bucket
            pairs_i: list[int] = []
            pairs_j: list[int] = []
            for j, (a, z, x0, y0, x1, y1) in enumerate(sw.rows):
                a, z = a + offset, z + offset
                found = self._filed(sw.cells[j], math.floor((a - _EPS) / b),
                                    math.floor((z + _EPS) / b))
                if not found:
                    continue
                for i in sorted(found):
                    if (st.alive[i] and st.owner[i] != skip and st.t[i, 0] <= z + _EPS
                            and st.t[i, 1] >= a - _EPS and st.box[i, 0] <= x1
                            and st.box[i, 2] >= x0 and st.box[i, 1] <= y1
                            and st.box[i, 3] >= y0):
                        pairs_i.append(i)
                        pairs_j.append(j)
        if not pairs_i:
            return None
        hit = shapely.intersects(sw.geoms[pairs_j], st.geom[pairs_i]).tolist()
        if True not in hit:
            return None
        i = pairs_i[hit.index(True)]  # pairs come in chunk order: the earliest first
        return Conflict(self._names[st.owner[i]], float(st.t[i, 0]), float(st.t[i, 1]))

    def nearby(self, cells: Sequence[tuple[int, int]], t0: float, t1: float, *,
               ignore: str | None = None,
               box: tuple[float, float, float, float] | None = None,
               memo: dict | None = None) -> Near:
        """The entries of anybody but ``ignore`` filed in grid ``cells`` whose time overlaps
        ``[t0, t1]`` [s]: what any query within those cells and times may meet (none: the
        queries are all free, with no exact test). Pass it to :meth:`first_conflict` and
        :meth:`blocked` as ``among``, to gather it once for several queries.

        With ``box`` ``(x0, y0, x1, y1)`` [m], only the entries whose box meets it: enough
        for queries whose every hull's box lies within it (a pair is tested only where the
        boxes meet), and fewer for each of them to go through.

        ``memo`` (a dict the caller keeps while the table does not change, for one
        ``ignore``; ``cells`` then a tuple) keeps, for each ``cells`` and span of time
        buckets asked about, the entries filed there: a search asks about the same edge in
        the same buckets again and again (58 % of its queries, 300 cars into the large
        lot), and then only the times and boxes are compared again — the same tests on
        the same entries, in the same order, as without it."""
        k0, k1 = math.floor((t0 - _EPS) / self.bucket), self._last_bucket(t1)
        if memo is not None:
            filed = memo.get((cells, k0, k1))
            if filed is None:
                filed = memo[cells, k0, k1] = self._gathered(cells, k0, k1, ignore)
            if not filed[0]:
                return _NOBODY
            return _within_window(*filed, t0, t1, box)
        found = self._filed(cells, k0, k1)
        if not found:
            return _NOBODY
        skip = self._ids.get(ignore, -1) if ignore is not None else -1
        st = self._store
        if len(found) <= _FEW_ENTRIES:
            return _within_window(*self._live(found, skip), t0, t1, box)
        x0, y0, x1, y1 = box if box is not None else (math.inf, math.inf, -math.inf, -math.inf)
        ids = np.fromiter(sorted(found), dtype=np.int64, count=len(found))
        ids = ids[st.alive[ids] & (st.owner[ids] != skip) & (st.t[ids, 0] <= t1 + _EPS)
                  & (st.t[ids, 1] >= t0 - _EPS)]
        if box is not None:
            b = st.box[ids]
            ids = ids[(b[:, 0] <= x1) & (b[:, 2] >= x0) & (b[:, 1] <= y1) & (b[:, 3] >= y0)]
        if not ids.size:
            return _NOBODY
        return Near(ids.tolist(), list(map(tuple, np.hstack([st.t[ids], st.box[ids]]).tolist())))

    def _gathered(self, cells: Sequence[tuple[int, int]], k0: int, k1: int,
                  ignore: str | None) -> tuple[list[int], list[tuple[float, ...]]]:
        """The ids, ascending, and rows of the live entries of anybody but ``ignore`` filed in
        grid ``cells`` in time buckets ``k0 .. k1`` (or by space only)."""
        found = self._filed(cells, k0, k1)
        if not found:
            return [], []
        return self._live(found, self._ids.get(ignore, -1) if ignore is not None else -1)

    def _live(self, found: Iterable[int], skip: int
              ) -> tuple[list[int], list[tuple[float, ...]]]:
        """The ids, ascending, and rows of those of entries ``found`` that are live and not
        owned by ``skip``."""
        who, live = self._store.who, self._store.rows
        ids = [i for i in sorted(found) if live[i] is not None and who[i] != skip]
        return ids, [live[i] for i in ids]

    def quiet(self, cells: Sequence[tuple[int, int]], t0: float, t1: float, *,
              ignore: str | None = None) -> bool:
        """Whether nobody but ``ignore`` has an entry filed in grid ``cells`` that overlaps
        ``[t0, t1]`` [s] — a cheap test that makes exact ones unnecessary."""
        return not self.nearby(cells, t0, t1, ignore=ignore)

    def blocked(self, sw: Swept, since: float, until: float, *,
                cells: Sequence[tuple[int, int]] | None = None,
                ignore: str | None = None, among: Near | None = None
                ) -> list[tuple[float, float]]:
        """The departure times ``d`` in ``[since, until]`` [s] at which ``sw`` shifted by
        ``d`` meets someone else's body over overlapping time: sorted, disjoint closed
        intervals ``[(lo, hi), ...]`` (the first may begin before ``since``, the last end
        after ``until``); ``d`` outside them all is free (:meth:`is_free` with ``offset=d``).

        Chunk ``[a, z]`` of ``sw`` (hull ``H``) and an entry held over ``[t0, t1]`` whose
        body meets ``H`` forbid ``d`` in ``[t0 - z, t1 - a]``: the geometric test is
        time-free, so each pair is tested once, whatever the window. ``cells`` (all the
        grid cells ``sw`` meets, if known) saves working them out; ``among`` (from
        :meth:`nearby`, over cells that hold ``sw`` and a window that holds it shifted by
        any ``d`` in ``[since, until]``, for the same ``ignore``) saves gathering what it
        may meet.

        Examples
        --------
        >>> from shapely.geometry import box
        >>> table = ReservationTable()
        >>> table.reserve("a", [(2.0, 3.0, box(0, 0, 1, 1))])
        >>> moving = Swept.of([(0.0, 0.5, box(5, 0, 6, 1)), (0.5, 1.0, box(0.5, 0, 5, 1))])
        >>> [(round(lo, 6), round(hi, 6)) for lo, hi in table.blocked(moving, 0.0, 10.0)]
        [(1.0, 2.5)]
        """
        if not len(sw):
            return []
        if among is not None:
            return self._blocked_among(sw, among, since, until)
        skip = self._ids.get(ignore, -1) if ignore is not None else -1
        st = self._store
        b = self.bucket
        first, last = since + sw.extent[0], until + sw.extent[1]
        if cells is None:  # (one hull's cells are distinct already)
            cells = sw.cells[0] if len(sw.cells) == 1 else {c for cs in sw.cells for c in cs}
        found = self._filed(cells, math.floor((first - _EPS) / b), self._last_bucket(last))
        if not found:
            return []
        if len(found) * len(sw) <= _FEW_PAIRS:
            # (in any order: the intervals are sorted when merged)
            return self._blocked_few(sw, found, since, until, first, last, skip)
        ids = np.fromiter(sorted(found), dtype=np.int64, count=len(found))
        ids = ids[st.alive[ids] & (st.owner[ids] != skip) & (st.t[ids, 0] <= last + _EPS)
                  & (st.t[ids, 1] >= first - _EPS)]
        if not ids.size:
            return []
        box, own = st.box[ids], np.array(sw.rows)
        bd = own[:, 2:]
        near = ((box[None, :, 0] <= bd[:, None, 2]) & (box[None, :, 2] >= bd[:, None, 0])
                & (box[None, :, 1] <= bd[:, None, 3]) & (box[None, :, 3] >= bd[:, None, 1]))
        jj, kk = np.nonzero(near)
        if not jj.size:
            return []
        ii = ids[kk]
        hit = shapely.intersects(sw.geoms[jj], st.geom[ii])
        jj, ii = jj[hit], ii[hit]
        lo = st.t[ii, 0] - own[jj, 1] - _EPS
        hi = st.t[ii, 1] - own[jj, 0] + _EPS
        keep = (hi >= since) & (lo <= until)
        return _merged(lo[keep].tolist(), hi[keep].tolist())

    def blocked_standing(self, sw: Swept, since: float, until: float, *,
                         ignore: str | None = None) -> list[tuple[float, float]]:
        """:meth:`blocked` for a standing body, one hull (:meth:`Swept.held` or a
        :class:`~lotsim.traffic.search.SearchGraph`'s ``standing``), asked about again
        and again: the same intervals.

        The entries its hull meets are kept with it (by the object: keep it alive and
        unchanged), whenever filed: an entry's body never changes, only its time (cut
        short or dropped). A query tests exactly only the entries reserved since the last
        one, and reads the times of those kept — where :meth:`blocked` gathers every entry
        of the body's cells over the window and tests them again (a search asks once for
        every node it stops at, each search anew: 35 000 queries of 85 µs each for 300 cars
        into the large lot).
        """
        st = self._store
        n = st.n
        if len(sw) != 1:
            raise ValueError("blocked_standing takes one hull")
        kept = self._standing.get(id(sw))
        if kept is None:  # (kept[0] holds the body, so its id is not another's meanwhile)
            kept = self._standing[id(sw)] = [sw, 0, []]
        a, z, x0, y0, x1, y1 = sw.rows[0]
        seen = kept[1]
        rows, who = st.rows, st.who
        if seen < n:
            # the entries filed in the hull's cells since (ids ascend: the end of each cell's
            # log; the first time, what the grid holds now), live and meeting the hull's box,
            # tested by shapely (an entry dropped before it is seen is never met again; one
            # standing in a slot is never filed: only free_from sees those)
            if seen == 0:
                found: Iterable[int] = self._filed(sw.cells[0], self._forgot, 2 ** 62)
            else:
                found = set()
                for cell in sw.cells[0]:
                    log = self._log.get(cell)
                    if log and log[-1] >= seen:
                        found.update(log[bisect.bisect_left(log, seen):])
            cand = [i for i in found if (r := rows[i]) is not None and r[2] <= x1
                    and r[4] >= x0 and r[3] <= y1 and r[5] >= y0]
            if cand:
                met = shapely.intersects(st.geom[cand], sw.geoms[0]).tolist()
                kept[2].extend(i for i, m in zip(cand, met, strict=True) if m)
            kept[1] = n
        skip = self._ids.get(ignore, -1) if ignore is not None else -1
        # as blocked: the window's first and last instants, each entry's time compared with
        # them and its interval worked out with the same sums (the order of the pairs does
        # not matter: they are sorted when merged)
        first, last = since + a, until + z
        lo_t, hi_t = first - _EPS, last + _EPS
        live: list[int] = []
        lo: list[float] = []
        hi: list[float] = []
        for i in kept[2]:
            r = rows[i]
            if r is None:  # dropped, or forgotten: for good
                continue
            live.append(i)
            t0, t1 = r[0], r[1]
            if who[i] != skip and t0 <= hi_t and t1 >= lo_t and (
                    t1 - a + _EPS >= since and t0 - z - _EPS <= until):
                lo.append(t0 - z - _EPS)
                hi.append(t1 - a + _EPS)
        kept[2] = live
        return _merged(lo, hi)

    def _blocked_few(self, sw: Swept, found: Iterable[int], since: float, until: float,
                     first: float, last: float, skip: int) -> list[tuple[float, float]]:
        """:meth:`blocked` for a few candidate pairs, filtered one by one: there numpy's
        fixed cost per call is more than the work (with this, the 16682 queries of 100
        cars into the large lot took 0.67 times as long, the same answers; the jammed
        lot of ``benchmarks/bench_validate.py``, whose queries meet more, is unchanged)."""
        st = self._store
        # the entries' and chunks' rows: the same floats as their arrays hold, without
        # numpy's cost per element read (a dropped entry's row is None)
        rows, who, chunks = st.rows, st.who, sw.rows
        lo_t, hi_t = first - _EPS, last + _EPS
        pj: list[int] = []
        pi: list[int] = []
        if len(chunks) == 1:  # a standing body (the search asks for each node it stops at)
            _, _, a0, b0, a1, b1 = chunks[0]
            for i in found:
                r = rows[i]
                if r is not None and who[i] != skip and r[0] <= hi_t and r[1] >= lo_t and (
                        r[2] <= a1 and r[4] >= a0 and r[3] <= b1 and r[5] >= b0):
                    pi.append(i)
            pj = [0] * len(pi)
        else:
            for i in found:
                r = rows[i]
                if r is None or who[i] == skip:
                    continue
                t0, t1, x0, y0, x1, y1 = r
                if t0 > hi_t or t1 < lo_t:
                    continue
                for j, (_, _, a0, b0, a1, b1) in enumerate(chunks):
                    if x0 <= a1 and x1 >= a0 and y0 <= b1 and y1 >= b0:
                        pj.append(j)
                        pi.append(i)
        if not pj:
            return []
        lo: list[float] = []
        hi: list[float] = []
        for met, j, i in zip(shapely.intersects(sw.geoms[pj], st.geom[pi]).tolist(), pj, pi,
                             strict=True):
            if met:
                a, z = chunks[j][:2]
                t0, t1 = rows[i][:2]
                if t1 - a + _EPS >= since and t0 - z - _EPS <= until:
                    lo.append(t0 - z - _EPS)
                    hi.append(t1 - a + _EPS)
        return _merged(lo, hi)

    def _blocked_among(self, sw: Swept, among: Near, since: float, until: float
                       ) -> list[tuple[float, float]]:
        """:meth:`blocked` against candidates gathered by :meth:`nearby`: the same pairs,
        found by the same tests, give the same intervals."""
        # (the earliest start and latest end: the same floats as sw.t's, without numpy's
        # fixed cost per call)
        first, last = since + sw.extent[0], until + sw.extent[1]
        rows = among.rows
        lo_t, hi_t = first - _EPS, last + _EPS
        keep = [k for k, r in enumerate(rows) if r[0] <= hi_t and r[1] >= lo_t]
        if not keep:
            return []
        near = (among if len(keep) == len(rows)
                else Near([among.ids[k] for k in keep], [rows[k] for k in keep]))
        pj, pi = _pairs(sw, near, None)
        if not pj:
            return []
        st = self._store
        # each pair's interval first, and only the pairs whose interval reaches into
        # [since, until] tested by shapely (about 30 % of them do not, 100 cars into the
        # large lot): the same intervals kept, with the same sums
        lo: list[float] = []
        hi: list[float] = []
        qj: list[int] = []
        qi: list[int] = []
        times, rows = sw.rows, st.rows
        for j, i in zip(pj, pi, strict=True):
            a, z = times[j][0], times[j][1]
            t0, t1 = rows[i][:2]
            if t1 - a + _EPS >= since and t0 - z - _EPS <= until:
                lo.append(t0 - z - _EPS)
                hi.append(t1 - a + _EPS)
                qj.append(j)
                qi.append(i)
        if not qj:
            return []
        hit = shapely.intersects(sw.geoms[qj], st.geom[qi]).tolist()
        if False not in hit:
            return _merged(lo, hi)
        return _merged([x for x, met in zip(lo, hit, strict=True) if met],
                       [x for x, met in zip(hi, hit, strict=True) if met])

    def taken_until(self, body: BaseGeometry, *, ignore: str | None = None) -> float:
        """Till when [s] someone else's body meets ``body`` (``inf``: for ever; ``-inf``:
        nobody's ever does): ``body`` is free from a time on (:meth:`free_from` is None)
        if and only if that time is past this."""
        st = self._store
        n = st.n
        skip = self._ids.get(ignore, -1) if ignore is not None else -1
        x0, y0, x1, y1 = body.bounds
        bx = st.box[:n]
        sel = (st.alive[:n] & (st.owner[:n] != skip)
               & (bx[:, 0] <= x1) & (bx[:, 2] >= x0) & (bx[:, 1] <= y1) & (bx[:, 3] >= y0))
        cand = np.flatnonzero(sel)
        if cand.size == 0:
            return -math.inf
        hit = shapely.intersects(st.geom[cand], body)
        return float(st.t[cand[hit], 1].max()) + _EPS if hit.any() else -math.inf

    def is_free(self, intervals: Sequence[Interval] | Swept, *, offset: float = 0.0,
                ignore: str | None = None, among: Near | None = None) -> bool:
        """Whether :meth:`first_conflict` finds nothing (with ``among``: the same pairs tested,
        without making the conflict, the search's question at every move from a speed)."""
        if among is None or not isinstance(intervals, Swept):
            return self.first_conflict(intervals, offset=offset, ignore=ignore,
                                       among=among) is None
        pairs_j, pairs_i = _pairs(intervals, among, offset, ordered=False)
        return not pairs_i or True not in shapely.intersects(
            intervals.geoms[pairs_j], self._store.geom[pairs_i]).tolist()

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

    def _filed(self, cells, k0: int, k1: int) -> set[int]:
        """Ids of the entries filed in grid ``cells`` in time buckets ``k0 .. k1``, and of
        the long entries filed there by space only: the candidates a query tests."""
        grid, long_cells = self._grid, self._long_cells
        # the lists filed, gathered by comprehensions and put in the set by one call
        parts: list[list[int]] = []
        for cell in cells:
            by_bucket = grid.get(cell)
            if by_bucket is not None:
                if k1 - k0 >= len(by_bucket):  # a long window: what the cell holds is less
                    parts += [ids for k, ids in by_bucket.items() if k0 <= k <= k1]
                else:
                    get = by_bucket.get
                    parts += [ids for k in range(k0, k1 + 1) if (ids := get(k))]
            ids = long_cells.get(cell)
            if ids:
                parts.append(ids)
        found: set[int] = set()
        found.update(*parts)
        return found

    def _last_bucket(self, t: float) -> int:
        """The last time bucket a query reaching ``t`` [s] need look in: none after the
        latest entry filed by bucket (a query with no end scans only what is there)."""
        last = min(t, self._last)
        return math.floor((last + _EPS) / self.bucket) if last > -math.inf else -(2 ** 62)

    def _add(self, oid: int, t0: float, t1: float, geom: BaseGeometry, *,
             in_slot: bool = False, bounds: Sequence[float] | None = None,
             cells: tuple[tuple[int, int], ...] | None = None) -> None:
        """File ``geom`` held from ``t0`` to ``t1`` [s]; ``bounds`` and ``cells``, if given,
        its bounds and :func:`cells_of` them, worked out before."""
        if bounds is None:
            bounds = geom.bounds
        i = self._store.add(oid, t0, t1, geom, in_slot, bounds)
        self._by_owner.setdefault(oid, []).append(i)
        if in_slot:
            return  # found by free_from's scan of the whole store only
        if cells is None:
            cells = cells_of(bounds)
        log = self._log
        for cell in cells:
            filed = log.get(cell)
            if filed is None:
                log[cell] = [i]
            else:
                filed.append(i)
        if math.isinf(t0) or math.isinf(t1) or math.floor(t1 / self.bucket) - math.floor(
                t0 / self.bucket) > _LONG:
            for cell in cells:
                self._long_cells.setdefault(cell, []).append(i)
            if not math.isinf(t1):
                heapq.heappush(self._long_ends, (t1, i))
            return
        self._last = max(self._last, t1)
        bucket_cells = self._bucket_cells
        for cell in cells:
            by_bucket = self._grid.setdefault(cell, {})
            for k in range(math.floor(t0 / self.bucket), math.floor(t1 / self.bucket) + 1):
                filed = by_bucket.get(k)
                if filed is None:
                    filed = by_bucket[k] = []
                    bucket_cells.setdefault(k, []).append(cell)
                filed.append(i)


def standing_body(vehicle: VehicleType, pose: FloatArray) -> BaseGeometry:
    """The footprint polygon of ``vehicle`` standing at ``pose``."""
    return shapely.Polygon(vehicle.footprints(np.asarray(pose, dtype=float)[None, :])[0])


def _pairs(sw: Swept, near: Near, offset: float | None, ordered: bool = True
           ) -> tuple[list[int], list[int]]:
    """The pairs ``(j, i)`` of ``sw``'s interval ``j`` and entry ``near.ids[k] = i`` whose
    bounding boxes meet and, unless ``offset`` is None, whose times overlap with ``sw``
    shifted by ``offset``: interval by interval, entries ascending (the order the earliest
    conflict is read from), or, not ``ordered``, the same pairs in any order (for a
    question of whether any meets)."""
    pj: list[int] = []
    pi: list[int] = []
    ids, rows = near.ids, near.rows
    if not sw.rows:
        return [], []
    # first the entries that meet the box and time span of the whole of ``sw``: only they
    # can pass a pair's tests (the same sums, each at least as large), and most entries
    # gathered for an edge's cells and a window of departures meet no chunk of one motion
    a, z, x0, y0, x1, y1 = sw.extent
    if offset is not None:
        a, z = a + offset - _EPS, z + offset + _EPS
    kept = [k for k, (t0, t1, b0, c0, b1, c1) in enumerate(rows)
            if b0 <= x1 and b1 >= x0 and c0 <= y1 and c1 >= y0
            and (offset is None or (t0 <= z and t1 >= a))]
    if len(kept) < len(ids):
        if not kept:
            return [], []
        ids, rows = [ids[k] for k in kept], [rows[k] for k in kept]
    if len(sw.rows) * len(ids) <= _FEW_PAIRS:
        if offset is None:  # (boxes only)
            for j, (_, _, x0, y0, x1, y1) in enumerate(sw.rows):
                for i, (_, _, b0, c0, b1, c1) in zip(ids, rows, strict=True):
                    if b0 <= x1 and b1 >= x0 and c0 <= y1 and c1 >= y0:
                        pj.append(j)
                        pi.append(i)
            return pj, pi
        if len(sw.rows) > 2 and sw.in_order:
            return _pairs_in_order(sw, ids, rows, offset, ordered)
        for j, (a, z, x0, y0, x1, y1) in enumerate(sw.rows):
            a, z = a + offset, z + offset
            for i, (t0, t1, b0, c0, b1, c1) in zip(ids, rows, strict=True):
                if (t0 <= z + _EPS and t1 >= a - _EPS
                        and b0 <= x1 and b1 >= x0 and c0 <= y1 and c1 >= y0):
                    pj.append(j)
                    pi.append(i)
        return pj, pi
    r = np.array(rows)
    own = np.array(sw.rows)
    bd = own[:, 2:]
    ok = ((r[None, :, 2] <= bd[:, None, 2]) & (r[None, :, 4] >= bd[:, None, 0])
          & (r[None, :, 3] <= bd[:, None, 3]) & (r[None, :, 5] >= bd[:, None, 1]))
    if offset is not None:
        a, z = own[:, 0] + offset, own[:, 1] + offset
        ok &= (r[None, :, 0] <= (z + _EPS)[:, None]) & (r[None, :, 1] >= (a - _EPS)[:, None])
    jj, kk = np.nonzero(ok)
    return jj.tolist(), np.asarray(ids, dtype=np.int64)[kk].tolist()


def _pairs_in_order(sw: Swept, ids: list[int], rows: list[tuple[float, ...]], offset: float,
                    ordered: bool = True) -> tuple[list[int], list[int]]:
    """:func:`_pairs` with an offset for intervals whose starts and ends both never decrease
    (a motion's chunks): the intervals an entry overlaps in time are a run, found by two
    bisections, and only those are tested by box — the same tests, with the same sums, on
    the same pairs, given in the same order (entry by entry, unless ``ordered``)."""
    boxes = sw.rows
    # interval j overlaps an entry from t0 to t1 if t1 >= a_j + offset - eps (from the first
    # j on) and t0 <= z_j + offset + eps (up to the last j): the sums, in the same order of
    # operations, for every interval once (two lists, bisected in C without a key)
    lo = [r[0] + offset - _EPS for r in boxes]
    hi = [r[1] + offset + _EPS for r in boxes]
    left, right = bisect.bisect_left, bisect.bisect_right
    found: list[tuple[int, int]] = []  # (j, i), entry by entry
    for i, (t0, t1, b0, c0, b1, c1) in zip(ids, rows, strict=True):
        for j in range(left(hi, t0), right(lo, t1)):
            _, _, x0, y0, x1, y1 = boxes[j]
            if b0 <= x1 and b1 >= x0 and c0 <= y1 and c1 >= y0:
                found.append((j, i))
    if ordered:  # interval by interval, entries ascending (ids are)
        found.sort()
    return [j for j, _ in found], [i for _, i in found]


def _merged(lo: list[float], hi: list[float]) -> list[tuple[float, float]]:
    """The union of closed intervals ``[lo[k], hi[k]]`` as sorted disjoint ones."""
    if len(lo) < 2:  # (nothing to sort or join)
        return list(zip(lo, hi, strict=True))
    out: list[tuple[float, float]] = []
    for a, z in sorted(zip(lo, hi, strict=True)):
        if out and a <= out[-1][1]:
            if z > out[-1][1]:
                out[-1] = (out[-1][0], z)
        else:
            out.append((a, z))
    return out
