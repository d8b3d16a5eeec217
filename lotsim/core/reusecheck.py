"""Checking what lotsim recalls against what it would work out afresh: the reuse check.

lotsim remembers work and recalls it instead of doing it again: prepared lots on disk, the
pieces of a lot's roadmap, the answers to maneuver problems, the search graphs of a
prepared lot (docs/caching.md lists them all). Each store recalls a piece by a key, and a
key that misses something the work reads recalls a wrong piece without anyone noticing.
With the check on (``LOTSIM_VERIFY_REUSE=1``, read by :meth:`ReuseCheck.from_environment`
where a lot is prepared, or a :class:`ReuseCheck` handed in), every store that recalls a
piece also works it out afresh and compares the two (:meth:`ReuseCheck.compare`): any
difference raises :class:`~lotsim.errors.ReuseMismatch` naming the store, the key and
where the two differ. The check only adds work: what a run plans is the same with it as
without.

The comparison is exact (:func:`difference`): every work a store recalls is a function of
its inputs, done by the same steps, so the fresh piece has the same floats to the last
bit, the same order of lists and of dicts' keys.

Examples
--------
>>> check = ReuseCheck()
>>> check.compare("roadmap", b"\\x01\\x02", (1.0, [2, 3]), (1.0, [2, 3]))
>>> check.counts["roadmap"]
[1, 1, 0]
>>> try:
...     check.compare("roadmap", b"\\x01\\x02", (1.0, [2, 3]), (1.0, [2, 4]))
... except ReuseMismatch as e:
...     print(e.store, e.key, e.what, sep=" | ")
roadmap | 0102 | [1][1]: 3 recalled, 4 afresh
"""

from __future__ import annotations

import dataclasses
import enum
import math
import os
from collections.abc import Callable, Mapping

import numpy as np

from lotsim.errors import ReuseMismatch

VARIABLE = "LOTSIM_VERIFY_REUSE"
"""The environment variable that turns the reuse check on (``1``) for every preparation
that is not handed a check of its own."""
ON = ("1", "on", "yes", "true")


def _text(x: object) -> str:
    """A short text of ``x`` for a message (the start of a long one)."""
    text = repr(x)
    return text if len(text) <= 80 else text[:77] + "..."


def _float_difference(a: float, b: float) -> str | None:
    if a == b and math.copysign(1.0, a) == math.copysign(1.0, b):
        return None
    if math.isnan(a) and math.isnan(b):
        return None
    return f"{a!r} recalled, {b!r} afresh"


def difference(recalled: object, fresh: object, where: str = "") -> str | None:
    """Where ``recalled`` and ``fresh`` first differ and how (``[1].segments[0]: 2.5
    recalled, 2.5000000000000004 afresh``), or None when they are the same: floats to the
    last bit (and the sign of zero), arrays by dtype, shape and bytes, geometries by their
    WKB, lists, tuples and dicts in order, dataclasses and other objects field by field,
    sets as sets.

    >>> difference({"a": (0.1 + 0.2,)}, {"a": (0.3,)})
    "['a'][0]: 0.30000000000000004 recalled, 0.3 afresh"
    >>> difference([0.0], [-0.0])
    '[0]: 0.0 recalled, -0.0 afresh'
    """
    return _difference(recalled, fresh, where, set())


def _difference(a: object, b: object, where: str, seen: set) -> str | None:
    at = where or "the piece"
    if a is b:
        return None
    if type(a) is not type(b):
        return f"{at}: a {type(a).__name__} recalled, a {type(b).__name__} afresh"
    if isinstance(a, float):
        got = _float_difference(a, b)
        return None if got is None else f"{at}: {got}"
    if a is None or isinstance(a, (int, str, bytes, bool, enum.Enum)):
        return None if a == b else f"{at}: {_text(a)} recalled, {_text(b)} afresh"
    pair = (id(a), id(b))  # objects met before on this walk (shared or cyclic)
    if pair in seen:
        return None
    seen.add(pair)
    if isinstance(a, np.ndarray):
        if a.dtype != b.dtype or a.shape != b.shape:
            return f"{at}: array {a.dtype}{a.shape} recalled, {b.dtype}{b.shape} afresh"
        if a.dtype == object:
            return _sequence(a.ravel().tolist(), b.ravel().tolist(), where, seen)
        if a.tobytes() != b.tobytes():
            ra, rb = (np.ascontiguousarray(x).reshape(-1) for x in (a, b))
            bits = ra.view(np.uint8).reshape(ra.size, -1) != rb.view(np.uint8).reshape(
                rb.size, -1)
            k = int(np.flatnonzero(bits.any(axis=1))[0])
            return f"{at}: element {k}: {ra[k]!r} recalled, {rb[k]!r} afresh"
        return None
    if isinstance(a, np.generic):
        return _difference(a.item(), b.item(), where, seen)
    if isinstance(a, (list, tuple)):
        return _sequence(a, b, where, seen)
    if isinstance(a, Mapping):
        ka, kb = list(a), list(b)
        if ka != kb:
            if set(ka) != set(kb):
                extra = [k for k in ka if k not in b][:3]
                lacking = [k for k in kb if k not in a][:3]
                return (f"{at}: keys {_text(extra)} recalled only, {_text(lacking)} afresh "
                        f"only")
            return f"{at}: the same keys in another order"
        for k in ka:
            got = _difference(a[k], b[k], f"{where}[{k!r}]", seen)
            if got is not None:
                return got
        return None
    if isinstance(a, (set, frozenset)):
        if a == b:
            return None
        return (f"{at}: {len(a - b)} element(s) recalled only, {len(b - a)} afresh only "
                f"(e.g. {_text(next(iter(a - b or b - a)))})")
    if hasattr(a, "wkb") and hasattr(a, "geom_type"):  # a shapely geometry
        return None if a.wkb == b.wkb else f"{at}: geometry {_text(a.wkt)} recalled, " \
                                           f"{_text(b.wkt)} afresh"
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            got = _difference(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}",
                              seen)
            if got is not None:
                return got
        return None
    if hasattr(a, "__dict__") or hasattr(type(a), "__slots__"):
        fa, fb = _fields(a), _fields(b)
        if list(fa) != list(fb):
            return f"{at}: attributes {list(fa)} recalled, {list(fb)} afresh"
        for name in fa:
            got = _difference(fa[name], fb[name], f"{where}.{name}", seen)
            if got is not None:
                return got
        return None
    return None if a == b else f"{at}: {_text(a)} recalled, {_text(b)} afresh"


def _sequence(a, b, where: str, seen: set) -> str | None:
    if len(a) != len(b):
        return f"{where or 'the piece'}: {len(a)} items recalled, {len(b)} afresh"
    for k, (x, y) in enumerate(zip(a, b, strict=True)):
        got = _difference(x, y, f"{where}[{k}]", seen)
        if got is not None:
            return got
    return None


def _fields(x: object) -> dict:
    """An object's attributes by name (its ``__dict__`` and its slots)."""
    out = dict(getattr(x, "__dict__", {}))
    for cls in type(x).__mro__:
        for name in getattr(cls, "__slots__", ()):
            if name not in out and name != "__weakref__" and hasattr(x, name):
                out[name] = getattr(x, name)
    return dict(sorted(out.items()))


def key_text(key: object) -> str:
    """A store's key as a message gives it: bytes as hex, anything else as its repr."""
    if isinstance(key, (bytes, bytearray)):
        return bytes(key).hex()
    return _text(key)


class ReuseCheck:
    """The reuse check of one preparation (or of anything else that recalls work): every
    store given it compares what it recalls with the same work done afresh
    (:meth:`compare`) and counts them by store.

    Parameters
    ----------
    strict : bool
        Raise :class:`~lotsim.errors.ReuseMismatch` at the first difference (the
        default); without, count and keep every mismatch (:attr:`mismatches`) and go on
        with the recalled piece, as without the check.

    Attributes
    ----------
    counts : dict
        Store → [pieces recalled, pieces compared with the work done afresh, mismatches].
    mismatches : list of ReuseMismatch
        Those found (without ``strict``).
    """

    def __init__(self, *, strict: bool = True) -> None:
        self.strict = strict
        self.counts: dict[str, list[int]] = {}
        self.mismatches: list[ReuseMismatch] = []

    @classmethod
    def from_environment(cls, environ: Mapping[str, str] | None = None) -> ReuseCheck | None:
        """A check when ``LOTSIM_VERIFY_REUSE`` (in ``environ``, default the process's
        environment) is ``1``, else None (no check).

        >>> ReuseCheck.from_environment({}) is None
        True
        >>> ReuseCheck.from_environment({"LOTSIM_VERIFY_REUSE": "1"}).counts
        {}
        """
        environ = os.environ if environ is None else environ
        on = environ.get(VARIABLE, "").strip().lower() in ON
        return cls() if on else None

    def compare(self, store: str, key: object, recalled: object, fresh: object, *,
                differ: Callable[[object, object], str | None] = difference) -> None:
        """Count ``recalled`` (recalled from ``store`` as ``key``) and compare it with
        ``fresh`` (the same work done afresh) by ``differ`` (:func:`difference`); a
        difference raises :class:`~lotsim.errors.ReuseMismatch` (or is kept, without
        :attr:`strict`)."""
        counts = self.counts.setdefault(store, [0, 0, 0])
        counts[0] += 1
        counts[1] += 1
        what = differ(recalled, fresh)
        if what is None:
            return
        counts[2] += 1
        error = ReuseMismatch(store, key_text(key), what)
        if self.strict:
            raise error
        self.mismatches.append(error)

    def counted(self) -> dict[str, list[int]]:
        """A copy of :attr:`counts` (for :meth:`add`: a forked worker's counts)."""
        return {store: list(c) for store, c in self.counts.items()}

    def add(self, before: dict[str, list[int]], after: dict[str, list[int]],
            mismatches: list[ReuseMismatch] = ()) -> None:
        """Add what a copy of this check counted between ``before`` and ``after`` (its
        :meth:`counted`; a forked worker's), and the mismatches it kept."""
        for store, c in after.items():
            was = before.get(store, [0, 0, 0])
            mine = self.counts.setdefault(store, [0, 0, 0])
            for k in range(3):
                mine[k] += c[k] - was[k]
        self.mismatches.extend(mismatches)

    def summary(self) -> str:
        """One line per store: ``roadmap: 120 recalled, 120 verified, 0 mismatches``."""
        return "\n".join(f"{store}: {r} recalled, {v} verified, {m} mismatches"
                         for store, (r, v, m) in sorted(self.counts.items())
                         ) or "nothing recalled"
