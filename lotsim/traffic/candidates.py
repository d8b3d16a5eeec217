"""The candidate pairs a reservation-table query tests exactly: which of a query's hulls
may meet which entries, by time and bounding box, before shapely decides.

:class:`Near` holds the entries gathered near a query (by the grid,
:meth:`~lotsim.traffic.reservation.ReservationTable.nearby`); :func:`pairs` pairs them
with a :class:`~lotsim.traffic.swept.Swept`'s hulls; :func:`merged` joins the departure
intervals a query forbids. Below :data:`FEW_PAIRS` candidate pairs the filters run as
Python loops over rows of floats (numpy's fixed cost per call is more than their work),
above it as numpy arrays: the same tests on the same floats, the same answers.
"""

from __future__ import annotations

import bisect
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import shapely

from lotsim.traffic.grid import EPS
from lotsim.traffic.store import EntryStore
from lotsim.traffic.swept import Swept

FEW_PAIRS = 256
"""Candidate pairs up to which queries filter them in Python (changes no answer)."""
Row = tuple[float, ...]
"""An entry's or a hull's ``(t0, t1, x0, y0, x1, y1)``: held from ``t0`` to ``t1`` [s], its
bounding box [m]."""


@dataclass(slots=True)
class Near:
    """Entries filed near a query
    (:meth:`~lotsim.traffic.reservation.ReservationTable.nearby`): their ids, ascending,
    and each one's ``(t0, t1, x0, y0, x1, y1)``; false when there are none.

    (Never changed once made, but not frozen: a search makes one or two for every edge it
    looks along, and a frozen dataclass takes over twice as long to make.)"""

    ids: list[int]
    rows: list[Row]

    def __bool__(self) -> bool:
        return bool(self.ids)

    def within(self, box: tuple[float, float, float, float]) -> Near:
        """Those whose box meets ``box`` ``(x0, y0, x1, y1)`` [m]: as
        :meth:`~lotsim.traffic.reservation.ReservationTable.nearby` with that ``box``."""
        x0, y0, x1, y1 = box
        kept = [k for k, r in enumerate(self.rows)
                if r[2] <= x1 and r[4] >= x0 and r[3] <= y1 and r[5] >= y0]
        if len(kept) == len(self.ids):
            return self
        return Near([self.ids[k] for k in kept], [self.rows[k] for k in kept])


NOBODY = Near([], [])  # no entries (shared: a Near is never changed)


def within_window(ids: list[int], rows: list[Row], t0: float, t1: float,
                  box: tuple[float, float, float, float] | None) -> Near:
    """Those of entries ``ids`` (rows ``rows``) whose time overlaps ``[t0, t1]`` [s] and,
    given ``box``, whose box meets it: the last filter of
    :meth:`~lotsim.traffic.reservation.ReservationTable.nearby`."""
    lo, hi = t0 - EPS, t1 + EPS
    if box is None:
        kept = [k for k, r in enumerate(rows) if r[0] <= hi and r[1] >= lo]
    else:
        x0, y0, x1, y1 = box
        kept = [k for k, r in enumerate(rows) if r[0] <= hi and r[1] >= lo and r[2] <= x1
                and r[4] >= x0 and r[3] <= y1 and r[5] >= y0]
    if not kept:
        return NOBODY
    if len(kept) == len(ids):
        return Near(ids, rows)
    return Near([ids[k] for k in kept], [rows[k] for k in kept])


def pairs(sw: Swept, near: Near, offset: float | None, ordered: bool = True, *,
          few: int = FEW_PAIRS) -> tuple[list[int], list[int]]:
    """The pairs ``(j, i)`` of ``sw``'s interval ``j`` and entry ``near.ids[k] = i`` whose
    bounding boxes meet and, unless ``offset`` is None, whose times overlap with ``sw``
    shifted by ``offset``: interval by interval, entries ascending (the order the earliest
    conflict is read from), or, not ``ordered``, the same pairs in any order (for a
    question of whether any meets). Up to ``few`` candidate pairs filtered in Python,
    more with numpy."""
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
        a, z = a + offset - EPS, z + offset + EPS
    kept = [k for k, (t0, t1, b0, c0, b1, c1) in enumerate(rows)
            if b0 <= x1 and b1 >= x0 and c0 <= y1 and c1 >= y0
            and (offset is None or (t0 <= z and t1 >= a))]
    if len(kept) < len(ids):
        if not kept:
            return [], []
        ids, rows = [ids[k] for k in kept], [rows[k] for k in kept]
    if len(sw.rows) * len(ids) <= few:
        if offset is None:  # (boxes only)
            for j, (_, _, x0, y0, x1, y1) in enumerate(sw.rows):
                for i, (_, _, b0, c0, b1, c1) in zip(ids, rows, strict=True):
                    if b0 <= x1 and b1 >= x0 and c0 <= y1 and c1 >= y0:
                        pj.append(j)
                        pi.append(i)
            return pj, pi
        if len(sw.rows) > 2 and sw.in_order:
            return pairs_in_order(sw, ids, rows, offset, ordered)
        for j, (a, z, x0, y0, x1, y1) in enumerate(sw.rows):
            a, z = a + offset, z + offset
            for i, (t0, t1, b0, c0, b1, c1) in zip(ids, rows, strict=True):
                if (t0 <= z + EPS and t1 >= a - EPS
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
        ok &= (r[None, :, 0] <= (z + EPS)[:, None]) & (r[None, :, 1] >= (a - EPS)[:, None])
    jj, kk = np.nonzero(ok)
    return jj.tolist(), np.asarray(ids, dtype=np.int64)[kk].tolist()


def pairs_in_order(sw: Swept, ids: list[int], rows: list[Row], offset: float,
                   ordered: bool = True) -> tuple[list[int], list[int]]:
    """:func:`pairs` with an offset for intervals whose starts and ends both never decrease
    (a motion's chunks): the intervals an entry overlaps in time are a run, found by two
    bisections, and only those are tested by box — the same tests, with the same sums, on
    the same pairs, given in the same order (entry by entry, unless ``ordered``)."""
    boxes = sw.rows
    # interval j overlaps an entry from t0 to t1 if t1 >= a_j + offset - eps (from the first
    # j on) and t0 <= z_j + offset + eps (up to the last j): the sums, in the same order of
    # operations, for every interval once (two lists, bisected in C without a key)
    lo = [r[0] + offset - EPS for r in boxes]
    hi = [r[1] + offset + EPS for r in boxes]
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


def merged(lo: list[float], hi: list[float]) -> list[tuple[float, float]]:
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


def blocked_few(st: EntryStore, sw: Swept, found: Iterable[int], since: float, until: float,
                first: float, last: float, skip: int) -> list[tuple[float, float]]:
    """:meth:`~lotsim.traffic.reservation.ReservationTable.blocked` among entries ``found``
    (ids, any order) of ``st`` for a few candidate pairs, filtered one by one: there
    numpy's fixed cost per call is more than the work. ``first`` and ``last`` [s]: the
    earliest instant ``sw`` shifted by ``since`` holds, the latest shifted by ``until``;
    ``skip``: the owner id ignored."""
    # the entries' and chunks' rows: the same floats as their arrays hold, without
    # numpy's cost per element read (a dropped entry's row is None)
    rows, who, chunks = st.rows, st.who, sw.rows
    lo_t, hi_t = first - EPS, last + EPS
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
            if t1 - a + EPS >= since and t0 - z - EPS <= until:
                lo.append(t0 - z - EPS)
                hi.append(t1 - a + EPS)
    return merged(lo, hi)


def blocked_among(st: EntryStore, sw: Swept, among: Near, since: float, until: float, *,
                  few: int = FEW_PAIRS) -> list[tuple[float, float]]:
    """:meth:`~lotsim.traffic.reservation.ReservationTable.blocked` against candidates
    gathered by its ``nearby`` (entries of ``st``): the same pairs, found by the same
    tests, give the same intervals."""
    # (the earliest start and latest end: the same floats as sw.t's, without numpy's
    # fixed cost per call)
    first, last = since + sw.extent[0], until + sw.extent[1]
    rows = among.rows
    lo_t, hi_t = first - EPS, last + EPS
    keep = [k for k, r in enumerate(rows) if r[0] <= hi_t and r[1] >= lo_t]
    if not keep:
        return []
    near = (among if len(keep) == len(rows)
            else Near([among.ids[k] for k in keep], [rows[k] for k in keep]))
    pj, pi = pairs(sw, near, None, few=few)
    if not pj:
        return []
    # each pair's interval first, and only the pairs whose interval reaches into
    # [since, until] tested by shapely (many do not): the same intervals kept, with the
    # same sums
    lo: list[float] = []
    hi: list[float] = []
    qj: list[int] = []
    qi: list[int] = []
    times, rows = sw.rows, st.rows
    for j, i in zip(pj, pi, strict=True):
        a, z = times[j][0], times[j][1]
        t0, t1 = rows[i][:2]
        if t1 - a + EPS >= since and t0 - z - EPS <= until:
            lo.append(t0 - z - EPS)
            hi.append(t1 - a + EPS)
            qj.append(j)
            qi.append(i)
    if not qj:
        return []
    hit = shapely.intersects(sw.geoms[qj], st.geom[qi]).tolist()
    if False not in hit:
        return merged(lo, hi)
    return merged([x for x, met in zip(lo, hit, strict=True) if met],
                  [x for x, met in zip(hi, hit, strict=True) if met])


def blocked_many(st: EntryStore, sw: Swept, found: Iterable[int], since: float, until: float,
                 first: float, last: float, skip: int) -> list[tuple[float, float]]:
    """:func:`blocked_few` for many candidate pairs, filtered with numpy arrays: the same
    tests on the same floats, the same intervals."""
    order = sorted(found)
    ids = np.fromiter(order, dtype=np.int64, count=len(order))
    ids = ids[st.alive[ids] & (st.owner[ids] != skip) & (st.t[ids, 0] <= last + EPS)
              & (st.t[ids, 1] >= first - EPS)]
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
    lo = st.t[ii, 0] - own[jj, 1] - EPS
    hi = st.t[ii, 1] - own[jj, 0] + EPS
    keep = (hi >= since) & (lo <= until)
    return merged(lo[keep].tolist(), hi[keep].tolist())
