"""The reservation table's entries as growable columns, and who holds them.

Entry ``i`` is a body (a shapely polygon) held by an owner over ``[t0, t1]`` [s], with its
bounding box; it is alive until dropped. The columns are numpy arrays for queries over many
entries, and the same values as Python rows (:attr:`EntryStore.rows`) for queries that meet
a few, where numpy's fixed cost per call is more than their work.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from shapely.geometry.base import BaseGeometry

NOBODY = -1
"""The owner id no entry has (a query that ignores nobody skips it)."""


class EntryStore:
    """Growable columns of entries, and their owners' names and ids.

    Attributes
    ----------
    n : int
        Entries made so far (ids ``0 .. n - 1``, in the order they were made).
    owner, t, box, alive, in_slot, geom : numpy.ndarray
        Each entry's owner id, ``(t0, t1)`` [s], ``(x0, y0, x1, y1)`` [m], whether it is
        alive, whether it stands in a parking slot, and its body (the first ``n`` rows).
    who : list of int
        Each entry's owner id, as Python ints.
    rows : list
        Each entry's ``(t0, t1, x0, y0, x1, y1)`` as Python floats while alive, None once
        dropped (the arrays' floats).
    """

    def __init__(self) -> None:
        self.n = 0
        cap = 1024
        self.owner = np.zeros(cap, dtype=np.int64)
        self.t = np.zeros((cap, 2))
        self.box = np.zeros((cap, 4))
        self.alive = np.zeros(cap, dtype=bool)
        self.in_slot = np.zeros(cap, dtype=bool)
        self.geom = np.empty(cap, dtype=object)
        self.who: list[int] = []
        self.rows: list[tuple[float, ...] | None] = []
        self.ids: dict[str, int] = {}
        """Owner name → id."""
        self.names: list[str] = []
        """Owner id → name."""
        self.by_owner: dict[int, list[int]] = {}
        """Owner id → its entries not yet dropped by a release."""
        self.dead = 0
        """Entries dropped since the store was last made compact (:meth:`compact`)."""

    # -- owners -------------------------------------------------------------------------------
    def owner_id(self, owner: str) -> int:
        """``owner``'s id, made on first use."""
        if owner not in self.ids:
            self.ids[owner] = len(self.names)
            self.names.append(owner)
        return self.ids[owner]

    def skip(self, ignore: str | None) -> int:
        """The owner id a query ignoring ``ignore`` skips (:data:`NOBODY`: none)."""
        return self.ids.get(ignore, NOBODY) if ignore is not None else NOBODY

    # -- entries ------------------------------------------------------------------------------
    def add(self, owner: int, t0: float, t1: float, geom: BaseGeometry,
            in_slot: bool = False, bounds: Sequence[float] | None = None) -> int:
        """Entry ``i`` (returned): ``geom`` held by ``owner`` from ``t0`` to ``t1`` [s];
        ``bounds``, if given, ``geom.bounds`` worked out before (as a
        :class:`~lotsim.traffic.swept.Swept`'s rows hold them: the same floats)."""
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
        self.by_owner.setdefault(owner, []).append(i)
        self.n += 1
        return i

    def drop(self, i: int) -> None:
        """Entry ``i`` is released: no query meets it again."""
        if self.rows[i] is not None:
            self.dead += 1
        self.alive[i] = False
        self.rows[i] = None

    def compact(self) -> list[int]:
        """Let the dropped entries go: the live ones are numbered again from 0 in the order
        they were made (ids keep their order), the columns hold them alone. Returns each old
        id's new one (-1: dropped), for whoever holds ids to number theirs again."""
        rows = self.rows
        new: list[int] = []
        k = 0
        for r in rows:
            if r is None:
                new.append(-1)
            else:
                new.append(k)
                k += 1
        keep = np.fromiter((i for i, j in enumerate(new) if j >= 0), dtype=np.int64, count=k)
        cap = max(1024, 2 * k)
        for name in ("owner", "t", "box", "alive", "in_slot", "geom"):
            old = getattr(self, name)
            fresh = (np.empty if name == "geom" else np.zeros)((cap,) + old.shape[1:],
                                                              dtype=old.dtype)
            fresh[:k] = old[keep]
            setattr(self, name, fresh)
        self.who = [self.who[i] for i in keep.tolist()]
        self.rows = [rows[i] for i in keep.tolist()]
        self.by_owner = {o: [new[i] for i in ids if new[i] >= 0]
                         for o, ids in self.by_owner.items()}
        self.n = k
        self.dead = 0
        return new

    def forget(self, i: int) -> None:
        """Entry ``i`` is over for every query to come: dropped, and its body let go."""
        self.drop(i)
        self.geom[i] = None

    def cut(self, i: int, after: float) -> None:
        """Entry ``i`` ends at ``after`` [s] now."""
        self.t[i, 1] = after
        self.rows[i] = (*self.t[i].tolist(), *self.rows[i][2:])

    def live(self, found: Sequence[int] | set[int], skip: int
             ) -> tuple[list[int], list[tuple[float, ...]]]:
        """The ids, ascending, and rows of those of entries ``found`` that are alive and not
        owned by ``skip``."""
        who, rows = self.who, self.rows
        ids = [i for i in sorted(found) if rows[i] is not None and who[i] != skip]
        return ids, [rows[i] for i in ids]
