"""The reservation table: where every planned vehicle is, in space and time.

An entry is a body (a polygon) held by an owner over a time interval
``[t0, t1]`` [s]. A moving vehicle reserves, for each short chunk of its motion,
the convex hull of its footprints over that chunk (:mod:`~lotsim.traffic.swept`) — a
cover of what it sweeps, so two vehicles whose overlapping-in-time entries do not touch
cannot touch at any instant, not only at samples. A standing vehicle reserves its
footprint over the time it stands; a parked one with ``t1 = inf``.

Entries are kept in columns (:mod:`~lotsim.traffic.store`) and filed in a space-time
grid (:mod:`~lotsim.traffic.grid`), so a query in free space is a few dictionary lookups;
candidates are filtered by time and bounding box (:mod:`~lotsim.traffic.candidates`) and
tested exactly with shapely in one batch.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from lotsim.traffic.candidates import (
    FEW_PAIRS,
    NOBODY,
    Near,
    blocked_among,
    blocked_few,
    blocked_many,
    merged,
    pairs,
    within_window,
)
from lotsim.traffic.grid import EPS, NEVER, Cells, SpaceTimeGrid, cells_of
from lotsim.traffic.store import EntryStore
from lotsim.traffic.swept import Interval, Swept

COMPACT_FROM = 50_000
"""Dropped entries past which :meth:`ReservationTable.forget_before` makes the table
compact, when they are also as many as the live ones (changes no answer)."""
FEW_ENTRIES = 512
"""Candidate entries up to which :meth:`ReservationTable.nearby` filters them in Python
(changes no answer)."""


@dataclass(frozen=True, slots=True)
class Conflict:
    """A clash with ``owner``'s body held over ``[t0, t1]`` [s]."""

    owner: str
    t0: float
    t1: float


class ReservationTable:
    """Space-time reservations of vehicles' bodies.

    Parameters
    ----------
    bucket : float
        Width of a time bucket of the grid [s].
    few_pairs, few_entries : int, keyword-only
        Candidate pairs (entries) up to which queries filter them in Python loops, more
        with numpy: the same answers either way (numpy's fixed cost per call is more than
        the work of a few).
    compact_from : int, keyword-only
        Dropped entries past which the table is made compact (:meth:`compact`): the same
        answers.

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

    def __init__(self, bucket: float = 1.0, *, few_pairs: int = FEW_PAIRS,
                 few_entries: int = FEW_ENTRIES, compact_from: int = COMPACT_FROM):
        self._grid = SpaceTimeGrid(bucket)
        self.bucket = bucket
        self.few_pairs = few_pairs
        self.few_entries = few_entries
        self.compact_from = compact_from
        self.compactions = 0
        """How many times the table was made compact (:meth:`compact`)."""
        self._store = EntryStore()
        # blocked_standing's bodies: id → [the body, entries tested up to, those it meets]
        self._standing: dict[int, list] = {}
        # the entries standing in slots (not filed in the grid), by the grid's cells
        self._in_slots: dict[tuple[int, int], list[int]] = {}
        # heap of (t1, id) of those standing in slots whose end is known
        self._slot_ends: list[tuple[float, int]] = []
        self.releases: list[tuple[float, str, bool]] = []
        """Every :meth:`release` that dropped or cut something, in order: the time from
        which it freed space [s], whose it was, and whether all it freed stood in a slot
        (space is freed in no other way)."""

    def __len__(self) -> int:
        return int(self._store.alive[: self._store.n].sum())

    # -- reserving ----------------------------------------------------------------------------
    def reserve(self, owner: str, intervals: Iterable[Interval], *, offset: float = 0.0) -> None:
        """Hold each ``(t0, t1, body)`` for ``owner``, shifted by ``offset`` [s]."""
        oid = self._store.owner_id(owner)
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

        With ``in_slot`` the body stands inside a parking slot. Such bodies are seen only
        by :meth:`taken_until` (whether a car may park in a slot and stay), not by the
        queries of moves: lanes and turns are swept clear of every slot when the lot
        graph is built, and each maneuver clear of a car parked in every other slot, so
        no move can reach them, and the queries skip hundreds of parked cars.
        """
        self._add(self._store.owner_id(owner), since, until, body, in_slot=in_slot)

    def release(self, owner: str, *, after: float | None = None) -> None:
        """Drop ``owner``'s entries that begin at or after ``after`` [s] (all, if None);
        entries running past ``after`` are cut short there."""
        st = self._store
        oid = st.ids.get(owner)
        if oid is None:
            return
        keep = []
        freed = []
        for i in st.by_owner.get(oid, []):
            if not st.alive[i]:
                continue
            t0, t1 = st.t[i]
            if after is None or t0 >= after:
                st.drop(i)
                freed.append(i)
            else:
                if t1 > after:
                    st.cut(i, after)
                    freed.append(i)
                    if st.in_slot[i]:
                        heapq.heappush(self._slot_ends, (after, i))
                keep.append(i)
        st.by_owner[oid] = keep
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
        entry's row and polygon) and the scans of long entries that are over. (:attr:`
        releases` is as before as long as every later :meth:`release` is from a time
        ``after`` at or past the forgetting's: such a release would have kept the entry
        whole.)
        """
        self._grid.forget_before(t, self._store.rows, self._store.forget)
        st = self._store
        ends, rows = self._slot_ends, st.rows
        while ends and ends[0][0] + EPS < t:
            _, i = heapq.heappop(ends)
            if rows[i] is not None and rows[i][1] + EPS < t:  # (not cut later still)
                st.forget(i)
        if st.dead >= max(self.compact_from, st.n - st.dead):
            self.compact()

    def compact(self) -> None:
        """Let go of the entries dropped or forgotten (a day's cars leave hundreds of
        thousands behind): the live ones are numbered again in the order they were made, so
        every query meets the same entries in the same order as before, and the table's
        memory follows what it holds, not what it has held. Called by :meth:`forget_before`
        once the dropped are :data:`COMPACT_FROM` and as many as the live; the caller holds
        no ids of the table's (a :class:`~lotsim.traffic.candidates.Near` from before is
        stale)."""
        st = self._store
        n = st.n
        new = st.compact()
        self.compactions += 1
        self._grid.renumber(new)
        for cell, ids in self._in_slots.items():
            self._in_slots[cell] = [j for i in ids if (j := new[i]) >= 0]
        self._slot_ends = [(t1, j) for t1, i in self._slot_ends if (j := new[i]) >= 0]
        heapq.heapify(self._slot_ends)
        # a standing body's entries tested up to (old) id ``seen``: the live ones before it
        before = [0] * (n + 1)
        k = 0
        for i, j in enumerate(new):
            before[i] = k
            k += j >= 0
        before[n] = k
        for kept in self._standing.values():
            kept[1] = before[kept[1]]
            kept[2] = [j for i in kept[2] if (j := new[i]) >= 0]

    # -- asking -------------------------------------------------------------------------------
    def first_conflict(self, intervals: Sequence[Interval] | Swept, *, offset: float = 0.0,
                       ignore: str | None = None, among: Near | None = None
                       ) -> Conflict | None:
        """The earliest of ``intervals`` (shifted by ``offset``) that meets someone else's
        body over overlapping time, as that body's owner and interval; None when all are
        free.

        A query in free space costs a few dictionary lookups in the grid; the few
        candidates are tested exactly with shapely in one batch. ``among`` (from
        :meth:`nearby`, over grid cells and a time window that hold the shifted
        intervals, for the same ``ignore``) saves gathering them again.
        """
        sw = intervals if isinstance(intervals, Swept) else Swept.of(intervals)
        st = self._store
        if among is not None:
            pairs_j, pairs_i = pairs(sw, among, offset, few=self.few_pairs)
        else:
            pairs_j, pairs_i = self._pairs_filed(sw, offset, st.skip(ignore))
        if not pairs_i:
            return None
        hit = shapely.intersects(sw.geoms[pairs_j], st.geom[pairs_i]).tolist()
        if True not in hit:
            return None
        i = pairs_i[hit.index(True)]  # pairs come in chunk order: the earliest first
        return Conflict(st.names[st.owner[i]], float(st.t[i, 0]), float(st.t[i, 1]))

    def _pairs_filed(self, sw: Swept, offset: float, skip: int
                     ) -> tuple[list[int], list[int]]:
        """The candidate pairs ``(j, i)`` of :meth:`first_conflict` without ``among``: each
        interval's own cells and buckets gathered, chunk by chunk, entries ascending."""
        st, grid = self._store, self._grid
        b = self.bucket
        pairs_i: list[int] = []
        pairs_j: list[int] = []
        for j, (a, z, x0, y0, x1, y1) in enumerate(sw.rows):
            a, z = a + offset, z + offset
            found = grid.filed(sw.cells[j], math.floor((a - EPS) / b), math.floor((z + EPS) / b))
            if not found:
                continue
            for i in sorted(found):
                if (st.alive[i] and st.owner[i] != skip and st.t[i, 0] <= z + EPS
                        and st.t[i, 1] >= a - EPS and st.box[i, 0] <= x1
                        and st.box[i, 2] >= x0 and st.box[i, 1] <= y1
                        and st.box[i, 3] >= y0):
                    pairs_i.append(i)
                    pairs_j.append(j)
        return pairs_j, pairs_i

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
        the same buckets again and again, and then only the times and boxes are compared
        again — the same tests on the same entries, in the same order, as without it."""
        grid, st = self._grid, self._store
        k0, k1 = math.floor((t0 - EPS) / self.bucket), grid.last_bucket(t1)
        if memo is not None:
            filed = memo.get((cells, k0, k1))
            if filed is None:
                found = grid.filed(cells, k0, k1)
                filed = memo[cells, k0, k1] = (st.live(found, st.skip(ignore)) if found
                                               else ([], []))
            if not filed[0]:
                return NOBODY
            return within_window(*filed, t0, t1, box)
        found = grid.filed(cells, k0, k1)
        if not found:
            return NOBODY
        skip = st.skip(ignore)
        if len(found) <= self.few_entries:
            return within_window(*st.live(found, skip), t0, t1, box)
        x0, y0, x1, y1 = box if box is not None else (math.inf, math.inf, -math.inf, -math.inf)
        ids = np.fromiter(sorted(found), dtype=np.int64, count=len(found))
        ids = ids[st.alive[ids] & (st.owner[ids] != skip) & (st.t[ids, 0] <= t1 + EPS)
                  & (st.t[ids, 1] >= t0 - EPS)]
        if box is not None:
            b = st.box[ids]
            ids = ids[(b[:, 0] <= x1) & (b[:, 2] >= x0) & (b[:, 1] <= y1) & (b[:, 3] >= y0)]
        if not ids.size:
            return NOBODY
        return Near(ids.tolist(), list(map(tuple, np.hstack([st.t[ids], st.box[ids]]).tolist())))

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
        st = self._store
        if among is not None:
            return blocked_among(st, sw, among, since, until, few=self.few_pairs)
        first, last = since + sw.extent[0], until + sw.extent[1]
        if cells is None:  # (one hull's cells are distinct already)
            cells = sw.cells[0] if len(sw.cells) == 1 else {c for cs in sw.cells for c in cs}
        found = self._grid.filed(cells, self._grid.bucket_of(first), self._grid.last_bucket(last))
        if not found:
            return []
        # (in any order: the intervals are sorted when merged)
        by = blocked_few if len(found) * len(sw) <= self.few_pairs else blocked_many
        return by(st, sw, found, since, until, first, last, st.skip(ignore))

    def blocked_standing(self, sw: Swept, since: float, until: float, *,
                         ignore: str | None = None) -> list[tuple[float, float]]:
        """:meth:`blocked` for a standing body, one hull (a
        :class:`~lotsim.traffic.searchgraph.SearchGraph`'s ``standing``), asked about again
        and again: the same intervals.

        The entries its hull meets are kept with it (by the object: keep it alive and
        unchanged), whenever filed: an entry's body never changes, only its time (cut
        short or dropped). A query tests exactly only the entries reserved since the last
        one, and reads the times of those kept — where :meth:`blocked` gathers every entry
        of the body's cells over the window and tests them again (a search asks once for
        every node it stops at, each search anew).
        """
        if len(sw) != 1:
            raise ValueError("blocked_standing takes one hull")
        st = self._store
        met = self._met_by(sw)
        a, z = sw.rows[0][:2]
        rows, who, skip = st.rows, st.who, st.skip(ignore)
        # as blocked: the window's first and last instants, each entry's time compared with
        # them and its interval worked out with the same sums (the order of the pairs does
        # not matter: they are sorted when merged)
        first, last = since + a, until + z
        lo_t, hi_t = first - EPS, last + EPS
        live: list[int] = []
        lo: list[float] = []
        hi: list[float] = []
        for i in met:
            r = rows[i]
            if r is None:  # dropped, or forgotten: for good
                continue
            live.append(i)
            t0, t1 = r[0], r[1]
            if who[i] != skip and t0 <= hi_t and t1 >= lo_t and (
                    t1 - a + EPS >= since and t0 - z - EPS <= until):
                lo.append(t0 - z - EPS)
                hi.append(t1 - a + EPS)
        met[:] = live
        return merged(lo, hi)

    def _met_by(self, sw: Swept) -> list[int]:
        """The entries (live or not) whose body meets standing ``sw``'s hull, kept with it
        and brought up to date: only the entries filed in its cells since it was last asked
        about are tested (ids ascend: the end of each cell's log; the first time, what the
        grid holds now). An entry dropped before it is seen is never met again; one
        standing in a slot is never filed (only :meth:`taken_until` sees those)."""
        st, grid = self._store, self._grid
        n = st.n
        kept = self._standing.get(id(sw))
        if kept is None:  # (kept[0] holds the body, so its id is not another's meanwhile)
            kept = self._standing[id(sw)] = [sw, 0, []]
        seen = kept[1]
        if seen < n:
            _, _, x0, y0, x1, y1 = sw.rows[0]
            rows = st.rows
            found = (grid.filed(sw.cells[0], grid.forgot, NEVER) if seen == 0
                     else grid.filed_since(sw.cells[0], seen))
            cand = [i for i in found if (r := rows[i]) is not None and r[2] <= x1
                    and r[4] >= x0 and r[3] <= y1 and r[5] >= y0]
            if cand:
                met = shapely.intersects(st.geom[cand], sw.geoms[0]).tolist()
                kept[2].extend(i for i, m in zip(cand, met, strict=True) if m)
            kept[1] = n
        return kept[2]

    def taken_until(self, body: BaseGeometry, *, ignore: str | None = None) -> float:
        """Till when [s] someone else's body meets ``body`` (``inf``: for ever; ``-inf``:
        nobody's ever does): a car may stand on ``body`` from a time on, for ever (parked),
        if and only if that time is past this. Bodies standing in slots count too."""
        st = self._store
        skip = st.skip(ignore)
        bounds = body.bounds
        x0, y0, x1, y1 = bounds
        cells = cells_of(bounds)
        # every live entry that may meet it: those filed in its cells (the grid holds every
        # live entry not standing in a slot), and those standing in a slot there
        found = self._grid.filed(cells, self._grid.forgot, NEVER)
        for cell in cells:
            ids = self._in_slots.get(cell)
            if ids:
                found.update(ids)
        rows, who = st.rows, st.who
        cand = np.array(sorted(i for i in found if (r := rows[i]) is not None
                               and who[i] != skip and r[2] <= x1 and r[4] >= x0
                               and r[3] <= y1 and r[5] >= y0), dtype=np.int64)
        if cand.size == 0:
            return -math.inf
        hit = shapely.intersects(st.geom[cand], body)
        return float(st.t[cand[hit], 1].max()) + EPS if hit.any() else -math.inf

    def is_free(self, intervals: Sequence[Interval] | Swept, *, offset: float = 0.0,
                ignore: str | None = None, among: Near | None = None) -> bool:
        """Whether :meth:`first_conflict` finds nothing (with ``among``: the same pairs tested,
        without making the conflict, the search's question at every move from a speed)."""
        if among is None or not isinstance(intervals, Swept):
            return self.first_conflict(intervals, offset=offset, ignore=ignore,
                                       among=among) is None
        pairs_j, pairs_i = pairs(intervals, among, offset, ordered=False, few=self.few_pairs)
        return not pairs_i or True not in shapely.intersects(
            intervals.geoms[pairs_j], self._store.geom[pairs_i]).tolist()

    # -- internals ----------------------------------------------------------------------------
    def _add(self, oid: int, t0: float, t1: float, geom: BaseGeometry, *,
             in_slot: bool = False, bounds: Sequence[float] | None = None,
             cells: Cells | None = None) -> None:
        """File ``geom`` held from ``t0`` to ``t1`` [s]; ``bounds`` and ``cells``, if given,
        its bounds and :func:`~lotsim.traffic.grid.cells_of` them, worked out before."""
        if bounds is None:
            bounds = geom.bounds
        i = self._store.add(oid, t0, t1, geom, in_slot, bounds)
        if in_slot:  # found by taken_until only, by its cells
            if not math.isinf(t1):
                heapq.heappush(self._slot_ends, (t1, i))
            rows = self._store.rows
            for cell in cells_of(bounds) if cells is None else cells:
                ids = self._in_slots.setdefault(cell, [])
                if len(ids) > 8 and rows[ids[0]] is None:  # dropped ones let go
                    ids[:] = [k for k in ids if rows[k] is not None]
                ids.append(i)
            return
        self._grid.file(i, t0, t1, cells_of(bounds) if cells is None else cells)
