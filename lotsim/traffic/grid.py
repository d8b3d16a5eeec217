"""Where the reservation table files its entries: a space-time grid of square cells
:data:`CELL` metres wide and time buckets ``bucket`` seconds long.

A query in free space is then a few dictionary lookups; the grid only gathers candidates,
which are filtered by time and bounding box and tested exactly afterwards, so its cell and
bucket sizes change how fast a query is, never its answer (an entry whose box meets a query's
box shares a cell with it). Entries spanning more than :data:`LONG` buckets (long waits, a
parked car) are filed by space only.
"""

from __future__ import annotations

import bisect
import functools
import heapq
import math
from collections.abc import Callable, Iterable, Sequence

import numpy as np

CELL = 6.0
"""Side of the grid cells entries are filed under [m] (changes no answer: see above)."""
LONG = 16
"""Entries spanning more time buckets than this are filed by space only."""
EPS = 1e-9
"""Slack of every time comparison [s]: bodies held over intervals that touch at an instant
count as held at once."""
NEVER = 2 ** 62
"""A bucket index later than any time filed (and, negated, earlier)."""

Cells = tuple[tuple[int, int], ...]
"""Grid cells ``(i, j)``: the one at ``(i, j)`` holds ``[i, i + 1) × [j, j + 1)`` × CELL."""


def cells_of(bounds: Sequence[float]) -> Cells:
    """The grid cells a bounding box ``(x0, y0, x1, y1)`` [m] meets."""
    return _block(*(math.floor(float(c) / CELL) for c in bounds))


def cells_of_all(bounds: np.ndarray) -> tuple[Cells, ...]:
    """:func:`cells_of` of each row of ``bounds`` (N, 4), the divisions in one call."""
    return tuple(_block(*r) for r in np.floor(bounds / CELL).astype(np.int64).tolist())


@functools.lru_cache(maxsize=1 << 16)
def _block(x0: int, y0: int, x1: int, y1: int) -> Cells:
    """The cells from ``(x0, y0)`` to ``(x1, y1)``, kept: the same few blocks are asked for
    by hundreds of thousands of hulls and entries, which then share one tuple."""
    return tuple((i, j) for i in range(x0, x1 + 1) for j in range(y0, y1 + 1))


class SpaceTimeGrid:
    """Entry ids filed by grid cell and time bucket.

    Parameters
    ----------
    bucket : float
        Width of a time bucket [s], positive.

    Attributes
    ----------
    by_cell : dict
        Cell → bucket → ids of the entries filed there (ascending: ids are filed in the
        order they are made).
    long_cells : dict
        Cell → ids of the long entries filed there by space only.
    log : dict
        Cell → every id ever filed there, ascending (for queries that ask what is new).
    forgot : int
        Buckets before this one are forgotten (:meth:`forget_before`).
    """

    def __init__(self, bucket: float = 1.0):
        if not bucket > 0:
            raise ValueError("bucket must be positive")
        self.bucket = bucket
        self.by_cell: dict[tuple[int, int], dict[int, list[int]]] = {}
        self.long_cells: dict[tuple[int, int], list[int]] = {}
        self.log: dict[tuple[int, int], list[int]] = {}
        self.last = -math.inf  # the latest finite time any entry filed by bucket reaches [s]
        self.bucket_cells: dict[int, list[tuple[int, int]]] = {}  # bucket → cells filed in it
        self.long_ends: list[tuple[float, int]] = []  # heap of (t1, id) of finite long entries
        self.forgot = -NEVER

    def bucket_of(self, t: float) -> int:
        """The first bucket a query from ``t`` [s] looks in."""
        return math.floor((t - EPS) / self.bucket)

    def last_bucket(self, t: float) -> int:
        """The last time bucket a query reaching ``t`` [s] need look in: none after the
        latest entry filed by bucket (a query with no end scans only what is there)."""
        last = min(t, self.last)
        return math.floor((last + EPS) / self.bucket) if last > -math.inf else -NEVER

    def file(self, i: int, t0: float, t1: float, cells: Cells) -> None:
        """File entry ``i``, held from ``t0`` to ``t1`` [s] over grid ``cells``."""
        log = self.log
        for cell in cells:
            filed = log.get(cell)
            if filed is None:
                log[cell] = [i]
            else:
                filed.append(i)
        bucket = self.bucket
        if math.isinf(t0) or math.isinf(t1) or math.floor(t1 / bucket) - math.floor(
                t0 / bucket) > LONG:
            for cell in cells:
                self.long_cells.setdefault(cell, []).append(i)
            if not math.isinf(t1):
                heapq.heappush(self.long_ends, (t1, i))
            return
        self.last = max(self.last, t1)
        bucket_cells = self.bucket_cells
        for cell in cells:
            by_bucket = self.by_cell.setdefault(cell, {})
            for k in range(math.floor(t0 / bucket), math.floor(t1 / bucket) + 1):
                filed = by_bucket.get(k)
                if filed is None:
                    filed = by_bucket[k] = []
                    bucket_cells.setdefault(k, []).append(cell)
                filed.append(i)

    def filed(self, cells: Iterable[tuple[int, int]], k0: int, k1: int) -> set[int]:
        """Ids of the entries filed in grid ``cells`` in time buckets ``k0 .. k1``, and of
        the long entries filed there by space only: the candidates a query tests."""
        grid, long_cells = self.by_cell, self.long_cells
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

    def filed_since(self, cells: Cells, seen: int) -> set[int]:
        """Ids from ``seen`` on ever filed in grid ``cells`` (the end of each cell's log)."""
        found: set[int] = set()
        for cell in cells:
            log = self.log.get(cell)
            if log and log[-1] >= seen:
                found.update(log[bisect.bisect_left(log, seen):])
        return found

    def renumber(self, new: Sequence[int]) -> None:
        """Entry ``i`` is entry ``new[i]`` from now, or gone where that is -1 (the store made
        compact, :meth:`~lotsim.traffic.store.EntryStore.compact`; ids keep their order)."""
        for by_bucket in self.by_cell.values():
            for k, ids in by_bucket.items():
                by_bucket[k] = [j for i in ids if (j := new[i]) >= 0]
        for cells in (self.long_cells, self.log):
            for cell, ids in cells.items():
                cells[cell] = [j for i in ids if (j := new[i]) >= 0]
        self.long_ends = [(t1, j) for t1, i in self.long_ends if (j := new[i]) >= 0]
        heapq.heapify(self.long_ends)

    def forget_before(self, t: float, rows: Sequence[tuple[float, ...] | None],
                      forget: Callable[[int], None]) -> None:
        """Drop the time buckets before ``t``'s [s], and call ``forget(i)`` for every entry
        ``i`` filed in them, or filed long, that is over before ``t``. ``rows[i]`` is entry
        ``i``'s ``(t0, t1, x0, y0, x1, y1)``, None once dropped (``forget`` makes it so).
        Each cell's log loses its dead beginning too, so that logs hold about what the grid
        does."""
        k = self.bucket_of(t)
        if k <= self.forgot:
            return
        self.forgot = k
        grid = self.by_cell
        for kk in [b for b in self.bucket_cells if b < k]:
            for cell in self.bucket_cells.pop(kk):
                by_bucket = grid[cell]
                for i in by_bucket.pop(kk):
                    if rows[i] is not None and rows[i][1] + EPS < t:
                        forget(i)
                if not by_bucket:
                    del grid[cell]
                log = self.log.get(cell)
                if log and rows[log[0]] is None:
                    j = 1
                    while j < len(log) and rows[log[j]] is None:
                        j += 1
                    del log[:j]
        ends = self.long_ends
        while ends and ends[0][0] + EPS < t:
            _, i = heapq.heappop(ends)
            row = rows[i]
            if row is not None and row[1] + EPS < t:
                forget(i)
                for cell in cells_of(row[2:]):
                    self.long_cells[cell].remove(i)
