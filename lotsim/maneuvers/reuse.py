"""Solving a perpendicular or angled bay's maneuver once per shape and checking it per bay.

A real lot's bays differ by centimetres: in where the neighbours stand, where the far side
of the aisle is, where the lane's start grid falls beside them. Each such bay is a problem of
its own to the planner's cache (:meth:`~lotsim.maneuvers.problem.LotProblems.digest`), yet
the maneuver found for one of them very often fits the next. Problems of one *shape* — the
same car, slot kind, slot outline and lane line in the slot's local frame
(:func:`~lotsim.maneuvers.problem.shape_key`), the same style, and slots served by as many
lanes — form a class; within a class:

1. every few problems (in slot order) one is searched;
2. every other problem takes a maneuver already found in its class when that maneuver fits
   it (:func:`fitted`): begun where a search would begin it on its own start grid,
   inside the stretch of lane a maneuver may begin on, and clear of everything it must
   keep out of — the very checks a search makes of every path it returns;
3. a problem no found maneuver fits is searched in its turn (:func:`settle`), and its
   answer is offered to the rest.

A fitted maneuver never has more direction changes than the problem's own search would
find: one with changes is taken only after a search of that problem bounded to fewer
changes finds none (:func:`~lotsim.maneuvers.planner.search_maneuver`, ``fewer_than``);
when it finds one, that is the answer. What a fit may cost is length within the same number
of changes. Every answer is a function of the lot alone (the classes, their order and the
rounds), so a lot's maneuvers are the same on any number of workers and in any order of
asking.
"""

from __future__ import annotations

import math
import pickle
from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass

from lotsim.core.geometry import Segment
from lotsim.core.keys import inputs, key_of
from lotsim.core.outcome import Outcome
from lotsim.maneuvers.problem import ManeuverProblem
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.maneuvers.validity import Validity

Pair = tuple[Outcome, Outcome]
"""A search's answer, eased and as planned (:func:`~lotsim.maneuvers.planner.search_maneuver`)."""


@dataclass(frozen=True, slots=True)
class Found:
    """A maneuver found in a class, offered to its other problems: its direction changes and
    length (what orders the offers), the answer eased and as planned, and what names it
    where fits are kept (:func:`answer_key`; None when they are not)."""

    changes: int
    length: float
    answer: Outcome
    raw: Outcome
    source: bytes | None = None

    @classmethod
    def of(cls, pair: Pair, named: bool = False) -> Found | None:
        """The offer of a search's answer, or None when it found none; ``named``: with its
        :attr:`source` (:func:`answer_key`), for a caller that keeps fits by it."""
        answer, raw = pair
        if not answer.found:
            return None
        segs = answer.value[0]
        return cls(changes(segs), sum(s.length for s in segs), answer, raw,
                   answer_key(pair) if named else None)


@inputs
class FoundAnswer:
    """What names a found answer where fits of it are kept (:func:`answer_key`): its pieces
    eased and as planned, and where each begins, pickled."""

    pickled: bytes


def answer_key(pair: Pair) -> bytes:
    """What names a found answer where fits of it are kept: its pieces eased and as
    planned, and where each begins, to the last bit (all :func:`fitted` reads of it), so a
    problem searched again that finds the same maneuver leaves the fits of it standing.
    They are read pickled (every float's bits, five times quicker than their text): equal
    names are equal maneuvers, and a maneuver found again by the same steps is pickled
    alike."""
    answer, raw = pair
    return key_of(FoundAnswer(pickle.dumps((answer.value, raw.value), protocol=5)))


def changes(segments: Sequence[Segment]) -> int:
    """Direction changes of a path (as :attr:`Maneuver.changes` counts them)."""
    return sum(1 for a, b in zip(segments[:-1], segments[1:], strict=True) if a.gear != b.gear)


def _begun_at(segs: tuple[Segment, ...], x: float) -> tuple[Segment, ...] | None:
    """``segs`` (beginning on the lane, heading along it) begun at local x = ``x``: its
    first straight lengthened or shortened, or a straight along the lane put before it;
    None when that would leave a straight under 5 cm or turn one round."""
    first = segs[0]
    x0, y0, th = first.start
    ahead = (x - x0) * math.cos(th) * first.gear  # > 0: the start moves forward
    if abs(ahead) < 1e-12:
        return segs
    if first.curvature == 0.0 and first.sharpness == 0.0:
        if first.length - ahead < 0.05:
            return None
        return (Segment((x, y0, th), first.gear * (first.length - ahead), 0.0), *segs[1:])
    if ahead > 0.0:
        return None
    return (Segment((x, y0, th), -first.gear * ahead, 0.0), *segs)


def fitted(problem: ManeuverProblem, found: Found, settings: ManeuverSettings
           ) -> Pair | None:
    """``found`` (eased and as planned) fitted to ``problem``: begun on the problem's own
    start grid (:attr:`~ManeuverSettings.start_grid`) where a search's closing move would
    begin it, at least :attr:`~ManeuverSettings.approach` short of where it leaves the lane
    (or, when the eased path cannot start there, at the grid station at or behind where it
    began); inside the stretch of lane a maneuver may begin on, and both paths clear of
    everything the problem keeps out of. None when it does not fit."""
    raw, _ = found.raw.value
    eased, _ = found.answer.value
    first = raw[0]
    x0, y0, th = first.start
    if (first.curvature != 0.0 or first.sharpness != 0.0 or abs(math.sin(th)) > 1e-9
            or abs(y0 - problem.lane_y) > 1e-6 or eased[0].start != first.start
            or eased[0].curvature != 0.0):
        return None  # it does not begin along the lane: nothing to move onto the grid
    onto = x0 + first.distance * math.cos(th)  # where the path leaves the lane
    grid, s0 = settings.start_grid, problem.lane_s0
    starts = [x0]
    if grid > 0:
        forward = first.distance * math.cos(th) > 0  # the car drives towards +x

        def on_grid(x: float) -> float:
            """The grid station at or behind local x, as local x."""
            k = (math.floor((s0 + x) / grid + 1e-9) if forward
                 else math.ceil((s0 + x) / grid - 1e-9))
            return k * grid - s0

        lead = settings.approach if forward else -settings.approach
        starts = list(dict.fromkeys([on_grid(onto - lead), on_grid(x0)]))
    lo, hi = problem.lane_x
    if not lo - 1e-9 <= onto <= hi + 1e-9:
        return None
    for x in starts:
        if not lo - 1e-9 <= x <= hi + 1e-9:
            continue
        raw_at, eased_at = _begun_at(raw, x), _begun_at(eased, x)
        if raw_at is None or eased_at is None:
            continue
        paths = [eased_at] if eased_at == raw_at else [eased_at, raw_at]
        if Validity(problem).paths_blocked(paths).any():
            return None
        return Outcome.of((eased_at, x)), Outcome.of((raw_at, x))
    return None


Member = Hashable

STRIDE = 8
"""Of a class, every this many problems (in slot order) are searched first; a found maneuver
is offered to the problems up to this many places either side of it."""


def settle(classes: Sequence[Sequence[Member]],
           search: Callable[[list[Member]], list[Pair]],
           fit: Callable[[list[tuple[Member, list[Found]]]], list[Pair | None]], *,
           offer: Callable[[Member, Pair], Found | None] = lambda _, pair: Found.of(pair)
           ) -> dict[Member, tuple[Pair, bool]]:
    """Every member of every class answered, in rounds. The first round searches every
    :data:`STRIDE`-th member of each class (in order, the first first); each later one the
    first member of each run of members still unanswered. What a round's searches find is
    offered to the members left up to :data:`STRIDE` places either side (bays near each
    other are most alike), and ``fit`` answers those an offer fits.

    ``search(members)`` answers each member by its own search; ``fit(jobs)`` answers each
    ``(member, offers)`` by the first offer that fits it (fewest changes first, then
    shortest), or by its own search when that finds fewer changes, or None
    (:func:`fit_first`). Both may work on other processes: the answers depend on the
    classes alone. ``offer(member, pair)``: what a member's search's answer offers the
    others (:meth:`Found.of`).

    Returns member → (its answer eased and as planned, whether it was searched).
    """
    out: dict[Member, tuple[Pair, bool]] = {}
    picked = [list(range(0, len(c), STRIDE)) for c in classes]
    while any(picked):
        flat = [(c, i) for c, at in enumerate(picked) for i in at]
        offers: list[dict[int, Found]] = [{} for _ in classes]
        for (c, i), pair in zip(flat, search([classes[c][i] for c, i in flat]), strict=True):
            out[classes[c][i]] = pair, True
            found = offer(classes[c][i], pair)
            if found is not None:
                offers[c][i] = found
        jobs, where = [], []
        for c, members in enumerate(classes):
            for i, m in enumerate(members):
                if m in out:
                    continue
                near = [(f.changes, f.length, j, f) for j, f in offers[c].items()
                        if abs(j - i) <= STRIDE]
                if near:
                    jobs.append((m, [f for *_, f in sorted(near, key=lambda x: x[:3])]))
                    where.append(m)
        for m, pair in zip(where, fit(jobs), strict=True):
            if pair is not None:
                out[m] = pair, False
        picked = [[i for i, m in enumerate(members)
                   if m not in out and (i == 0 or members[i - 1] in out)]
                  for members in classes]
    return out


def fit_first(problem: ManeuverProblem, style: str, offers: Sequence[Found],
              settings: ManeuverSettings, fewer: Callable[[ManeuverProblem, str, int], Pair]
              ) -> tuple[Pair | None, int]:
    """The first of ``offers`` that fits ``problem`` (:func:`fitted`); when it has direction
    changes, ``fewer(problem, style, changes)`` (its own search bounded to fewer changes)
    answers instead if it finds one. None when no offer fits. With it, how many offers it
    read: the answer depends on those alone."""
    for k, found in enumerate(offers):
        pair = fitted(problem, found, settings)
        if pair is None:
            continue
        if found.changes == 0:
            return pair, k + 1
        own = fewer(problem, style, found.changes)
        return (own if own[0].found else pair), k + 1
    return None, len(offers)
