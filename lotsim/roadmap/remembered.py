"""Pieces of a lot's roadmap remembered from an earlier preparation of the lot, by what each
read: an edited lot plans again only the pieces its edit touched.

A piece (the junction turns out of one lane for one vehicle type, the turns through one
short stretch) is a function of the lot's lanes and aisles, its own arguments and what its
collision checks found. It is worked out with a :class:`~lotsim.lot.clearance.Watched`
collider, which notes the box every body it checked lies in, and kept with that box and
the digest of what the collider holds inside it (:meth:`~lotsim.lot.clearance.Collider.around`).
A later preparation takes the piece when its key is the same and the collider's digest of
that box is too: every check the piece made would come out the same, so the piece would.
The answers are the same with the store as without it.

With a reuse check (:attr:`RoadmapMemo.reuse_check
<lotsim.roadmap.memo.RoadmapMemo.reuse_check>`,
:class:`~lotsim.core.reusecheck.ReuseCheck`), every piece recalled is worked out again
and compared with what was recalled (:func:`verified`); the store and the counts are the
same as without.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from lotsim.core.keys import inputs, key_of
from lotsim.core.workers import fork_map
from lotsim.lot.clearance import Collider, Watched
from lotsim.lot.model import Aisle, DesignVehicle, Lane, Lot
from lotsim.lot.settings import LotSettings
from lotsim.roadmap.model import Turn
from lotsim.roadmap.multipoint import plan_onto
from lotsim.roadmap.settings import MultipointSettings, RoadmapSettings

if TYPE_CHECKING:
    from lotsim.roadmap.turnarounds import Turnaround

KEEP = 3
"""Most versions of one piece a store keeps (most recent first)."""


@inputs
class RoadmapLot:
    """What every piece of a lot's roadmap reads besides its collisions: the lot's speed
    limit [m/s], design vehicle, aisles and lanes, the settings it was built with (its
    sweeps' spacing, which the turns' sweeps read) and the roadmap's settings."""

    speed_limit: float
    design: DesignVehicle
    aisles: tuple[Aisle, ...]
    lanes: tuple[Lane, ...]
    lot_settings: LotSettings
    settings: RoadmapSettings


def lot_key(lot: Lot, settings: RoadmapSettings | None = None) -> bytes:
    """The key of ``lot``'s :class:`RoadmapLot` with the roadmap's ``settings`` (None: the
    defaults): what every piece's key begins with."""
    return key_of(RoadmapLot(lot.speed_limit, lot.design, tuple(lot.aisles.values()),
                             tuple(lot.lanes), lot.settings,
                             RoadmapSettings() if settings is None else settings))


# The pieces of the store, each keyed by what it reads (``lot``: its lot's :func:`lot_key`)
@inputs
class JunctionTurns:
    """The junction turns out of one lane for one design, and where the lot's gates lie:
    ((lane id, ``"in"`` or ``"out"``), the entrances' or exits' stations on it [m]), by
    lane."""

    lot: bytes
    design: DesignVehicle
    lane: str
    gates: tuple[tuple[tuple[str, str], tuple[float, ...]], ...]


@inputs
class ThroughTurns:
    """The turns of one design through a chain of short stretches (lane ids and the
    stations between them)."""

    lot: bytes
    design: DesignVehicle
    chain: tuple


@inputs
class TurnSuits:
    """Which of the vehicle types (name → design, by name) one turn suits."""

    lot: bytes
    designs: tuple[tuple[str, DesignVehicle], ...]
    turn: Turn


@inputs
class TurnaroundSuits:
    """Whether one turnaround suits one design."""

    lot: bytes
    turnaround: Turnaround
    design: DesignVehicle


@inputs
class TurnaroundPlan:
    """The turnarounds of a dead end: from ``lane`` onto its opposite ``back``, with the
    body checked and the turning radius [m]."""

    lot: bytes
    lane: str
    back: str
    body: DesignVehicle
    radius: float


@inputs
class ReachingSearch:
    """A multi-point search onto a dead end's opposite lane from stations ``starts`` of
    ``lane``, ending by ``hi`` along ``back`` [m], with the body checked and the radius."""

    lot: bytes
    lane: str
    back: str
    starts: tuple[float, ...]
    hi: float
    body: DesignVehicle
    radius: float


@inputs
class OntoSearch:
    """One multi-point search of ``what`` (a junction's multi-point turn, a U-turn): from
    the stations ``starts`` of lane ``a`` (its straight starting at ``sa0``) onto lane
    ``b`` (its straight starting at ``sb0``) between ``lo`` and ``hi`` along it [m], with
    the body checked and the radius [m]."""

    lot: bytes
    what: str
    a: str
    sa0: float
    b: str
    sb0: float
    starts: tuple[float, ...]
    lo: float
    hi: float
    body: DesignVehicle
    radius: float


MISSING = object()
"""What :func:`recall` answers for a piece it does not hold."""
STORE = "roadmap"
"""The roadmap store's name in a reuse check's counts and messages."""


def verified(memo, keys: Sequence[bytes | None], got: Sequence,
             work: Callable[[int], object]) -> None:
    """With ``memo``'s reuse check (none: nothing), each piece of ``got`` recalled from its
    store (not :data:`MISSING`) worked out again, ``work(k)`` on the workers
    (:func:`~lotsim.core.workers.fork_map`), and compared with what was recalled as
    ``keys[k]``."""
    check = getattr(memo, "reuse_check", None)
    if check is None:
        return
    again = [k for k, piece in enumerate(got) if piece is not MISSING]
    for k, fresh in zip(again, fork_map(work, again), strict=True):
        check.compare(STORE, keys[k], got[k], fresh)


def recall(known: dict | None, key: bytes, collider: Collider) -> object:
    """The piece ``known`` (piece key → versions) holds as ``key`` whose box ``collider``
    holds what it did, else :data:`MISSING`."""
    return recall_all(known, [key], [collider])[0]


def recall_all(known: dict | None, keys: Sequence[bytes | None],
               colliders: Sequence[Collider]) -> list:
    """:func:`recall` of each of ``keys`` with its collider, the digests of each
    collider's boxes made at once (:meth:`~lotsim.lot.clearance.Collider.around_many`)."""
    versions = [(known or {}).get(key, ()) if key is not None else () for key in keys]
    boxes: dict[int, list] = {}  # by collider: its boxes, and whose version each is
    for k, held in enumerate(versions):
        for v, (box, _, _) in enumerate(held):
            boxes.setdefault(id(colliders[k]), []).append((k, v, box))
    digests: dict[tuple[int, int], bytes] = {}
    for asked in boxes.values():
        collider = colliders[asked[0][0]]
        digests.update(zip([(k, v) for k, v, _ in asked],
                           collider.around_many([box for *_, box in asked]), strict=True))
    return [next((piece for v, (_, digest, piece) in enumerate(held)
                  if digests[k, v] == digest), MISSING)
            for k, held in enumerate(versions)]


def watched(work: Callable[[Collider], object], collider: Collider, watch: bool = True
            ) -> tuple:
    """``work(collider)``, with the box its checks lay in and ``collider``'s digest of it
    (None, None without ``watch``): a version of the piece for :func:`keep`."""
    if not watch:
        return work(collider), None, None
    eye = Watched(collider)
    piece = work(eye)
    return piece, eye.box, collider.around(eye.box)


def keep(known: dict | None, key: bytes, version: tuple) -> None:
    """Add ``version`` (:func:`watched`: the piece, its box and digest) of piece ``key`` to
    ``known``, most recent first."""
    if known is not None:
        piece, box, digest = version
        known[key] = [(box, digest, piece), *known.get(key, ())][:KEEP]


def worked_out(memo, keys: Sequence[bytes | None],
               collider: Collider | Sequence[Collider],
               work: Callable[[int, Collider], object]) -> list:
    """``[work(k, collider) for k in range(len(keys))]`` (``collider``: one for all, or
    each piece's), each taken from ``memo``'s store (:attr:`RoadmapMemo.known
    <lotsim.roadmap.memo.RoadmapMemo.known>`: piece key → versions) where a version's box
    holds what it did (:func:`recall`), the others worked out on the workers
    (:func:`~lotsim.core.workers.fork_map`) and added to it; both counted in ``memo``.
    Without a memo or a store, all are worked out."""
    known = memo.known if memo is not None else None
    each = (list(collider) if isinstance(collider, (list, tuple))
            else [collider] * len(keys))
    out = recall_all(known, keys, each)
    verified(memo, keys, out, lambda k: work(k, each[k]))
    todo = [k for k, got in enumerate(out) if got is MISSING]
    got = fork_map(lambda k: watched(lambda eye: work(k, eye), each[k], known is not None),
                   todo)
    for k, version in zip(todo, got, strict=True):
        out[k] = version[0]
        keep(known, keys[k], version)
    if memo is not None:
        memo.recalled += len(keys) - len(todo)
        memo.worked += len(todo)
    return out


def remembered(memo, piece: OntoSearch, collider: Collider,
               work: Callable[[Collider], object]) -> object:
    """``work(collider)`` — one search of a piece worked out in order with others (a
    junction's multi-point turn, a U-turn) — taken from ``memo``'s store
    (:attr:`~lotsim.roadmap.memo.RoadmapMemo.known`) where what it read is unchanged, else
    worked out and kept there (its key noted in ``memo.touched``, for a worker to hand
    back: :func:`handed_back`). ``piece``: what the search reads but its collisions."""
    if memo.known is None:
        return work(collider)
    key = key_of(piece)
    got = recall(memo.known, key, collider)
    if got is not MISSING:
        memo.recalled += 1
        if memo.reuse_check is not None:
            memo.reuse_check.compare(STORE, key, got, work(collider))
        return got
    version = watched(work, collider)
    keep(memo.known, key, version)
    memo.touched.add(key)
    memo.worked += 1
    return version[0]


def handed_back(memo, work: Callable[[], object]) -> Callable[[], tuple]:
    """``work`` for a forked worker: its answer with what it added to ``memo``'s store and
    counted (:func:`remembered`), for :func:`take_back` in the process that forked it."""

    def job() -> tuple:
        before = (memo.recalled, memo.worked)
        checked = memo.reuse_check.counted() if memo.reuse_check is not None else None
        kept = len(memo.reuse_check.mismatches) if memo.reuse_check is not None else 0
        memo.touched = set()
        out = work()
        added = {k: memo.known[k] for k in memo.touched} if memo.known is not None else {}
        counted = memo.recalled - before[0], memo.worked - before[1]
        # counted once, by take_back, whether the job ran in a worker or in this process
        memo.recalled, memo.worked = before
        if memo.reuse_check is None:
            return out, added, *counted, None
        now, found = memo.reuse_check.counted(), memo.reuse_check.mismatches[kept:]
        memo.reuse_check.counts = checked
        del memo.reuse_check.mismatches[kept:]
        return out, added, *counted, (checked, now, found)

    return job


def take_back(memo, answer: tuple) -> object:
    """The answer of a :func:`handed_back` job, its additions put into ``memo``."""
    out, added, recalled, worked, checked = answer
    if memo.known is not None:
        memo.known.update(added)
    memo.recalled += recalled
    memo.worked += worked
    if checked is not None:
        memo.reuse_check.add(*checked)
    return out


def plan_onto_remembered(memo, what: str, a, sa0: float, pa, b, sb0: float, pb,
                         starts: list[float], lo: float, hi: float,
                         checks: tuple[Collider, object], radius: float, *,
                         settings: MultipointSettings | None = None):
    """:func:`~lotsim.roadmap.multipoint.plan_onto` from the stations ``starts`` of
    straight ``pa`` (of lane ``a``, starting at station ``sa0``) onto straight ``pb`` (of
    lane ``b``) between ``lo`` and ``hi`` along it, ``checks`` (collider and body) and
    ``radius``, tuned by ``settings`` (None: the defaults): a search of ``what`` (a
    junction's multi-point turn, a U-turn), taken from ``memo``'s store where what it read
    is unchanged (:func:`remembered`; the memo's key holds its roadmap settings). Its
    :class:`~lotsim.core.outcome.Outcome`."""
    collider, body = checks
    search = MultipointSettings() if settings is None else settings
    piece = OntoSearch(memo.lot_key if memo.known is not None else b"", what, a.id, sa0,
                       b.id, sb0, tuple(starts), lo, hi, body, radius)
    return remembered(memo, piece, collider,
                      lambda eye: plan_onto(list(pa.poses_at(starts)), pb.start, lo, hi, eye,
                                            body, radius, settings=search))
