"""Bays by use in a layout (``docs/layout.md``, ``uses``): which of a candidate's usable bays
become accessible, van-accessible and EV bays (:func:`allocate`).

A candidate's bays, once every one is usable, stand in *stretches*: unbroken runs of equal
bays along one side of an aisle (:func:`stretches`). Uses are then allotted by the walk to
the nearest building entrance of the plot:

* **Accessible and van-accessible bays** go in *groups* on 90° stretches of full-size
  bays: two bays sharing one access aisle between them (ADA 2010 §502.3), or one with its
  own after it. A group takes the place of as many standard bays as its bays and aisle
  span (three 2.5 m bays for two accessible bays and a 1.52 m aisle, or two with a van
  bay's 2.44 m aisle), so access aisles cost bays. Each group in turn goes where its
  farthest bay's walk is least, van-accessible groups first. The walk is the one ``lotsim
  validate`` reports (:func:`~lotsim.lot.walks.shortest_walk`): from the middle of the
  bay's side on its access aisle, over the plot less its drawn bays and islands, across
  the bay and its aisle. Places are walked in order of their straight lines, which no walk
  is shorter than, until the next straight line is no shorter than the best walk found:
  so the place found is the best of all, unless :data:`SHORTLIST` places were walked
  first (then the best of those).
* **As the standard requires** (``uses.accessible: ada_2010``): the fewest accessible bays
  that meet ADA 2010 Table 208.2 for the total the layout holds *with* its groups (which is
  less than the total without them), one in six of them van-accessible (§208.2.4), or
  one more where that pairs the odd van-accessible bay with the odd accessible one (two
  van bays share one aisle, where a van bay and an accessible bay would need one each).
* **EV bays**: the standard bays left nearest the entrance in a straight line from their
  centres (EV bays are full-size, so they cost nothing), a count or a share of the
  layout's total.
* **Compact bays** are drawn with the candidate (:mod:`lotsim.design.candidates`), not
  allotted here.

Where a layout has no room for all the bays asked for, it holds those it has room for,
and its figures say so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import Polygon

from lotsim.design.plot import PlotSpec
from lotsim.lot.uses import STANDARD, USES, ada_accessible, ada_van
from lotsim.lot.walks import shortest_walk, walking_ground

Key = tuple[str, str, float]
"""A drawn bay: its aisle, side and the station of its entry [m]."""
Point2 = tuple[float, float]


@dataclass(frozen=True, slots=True)
class Stretch:
    """Bays written as one row of the scenario: ``count`` bays of ``use``, ``width`` by
    ``length`` [m] at ``angle`` [degrees] to aisle ``aisle``, on ``side``, the first entry at
    station ``start`` [m]. ``places`` are the drawn bays each stands on (for an accessible
    group: every bay of the group's span), ``centres`` the drawn bays' centres and
    ``shapes`` their polygons [m]."""

    aisle: str
    side: str
    angle: int
    width: float
    length: float
    use: str
    start: float
    count: int
    places: tuple[tuple[Key, ...], ...]
    centres: tuple[Point2, ...] = field(default=(), compare=False)
    shapes: tuple[Polygon, ...] = field(default=(), compare=False)

    @property
    def pitch(self) -> float:
        """The distance between neighbouring bays' entries along the aisle [m]."""
        return self.width / math.sin(math.radians(self.angle))


@dataclass(frozen=True, slots=True)
class Allocation:
    """What :func:`allocate` made of a candidate's stretches: the stretches to write, the
    accessible groups (the first drawn bay of each → every drawn bay of its span), and the
    bays by use asked for that the layout has no room for."""

    stretches: tuple[Stretch, ...]
    groups: dict[Key, tuple[Key, ...]]
    short: dict[str, int]

    @property
    def total(self) -> int:
        return sum(s.count for s in self.stretches)

    def count(self, use: str) -> int:
        return sum(s.count for s in self.stretches if s.use == use)


def stretches(plot: PlotSpec, rows, keep: set[Key] | None) -> list[Stretch]:
    """The unbroken runs of the drawn ``rows`` (:class:`~lotsim.design.drawn.DrawnRow`)
    whose bays are in ``keep`` (None: all), in the rows' order; standard bays, or compact
    bays for a row of the compact size."""
    out = []
    for r in rows:
        width, length = r.size or (plot.bay_width, plot.bay_length)
        step = width / math.sin(math.radians(r.angle))
        runs: list[list[tuple[float, Point2, Polygon]]] = []
        for k in range(r.count):
            s = round(r.start + k * step, 9)
            if keep is not None and (r.aisle, r.side, s) not in keep:
                runs.append([])
                continue
            if not runs or (runs[-1] and abs(runs[-1][-1][0] + step - s) > 1e-6):
                runs.append([])
            c = r.polygons[k].centroid
            runs[-1].append((s, (float(c.x), float(c.y)), r.polygons[k]))
        for run in runs:
            if run:
                out.append(Stretch(r.aisle, r.side, r.angle, width, length,
                                   "compact" if r.size else STANDARD, run[0][0], len(run),
                                   tuple(((r.aisle, r.side, s),) for s, _, _ in run),
                                   tuple(c for _, c, _ in run), tuple(p for _, _, p in run)))
    return out


def group_span(use: str, width: float, bays: int) -> float:
    """The length along the aisle [m] of a group of ``bays`` (1 or 2) accessible bays of
    ``use`` ``width`` wide on a 90° row: the bays, and one access aisle (the least their
    use asks, :meth:`~lotsim.lot.uses.BayUse.least_aisle`).

    >>> round(group_span("accessible", 2.5, 2), 3), round(group_span("van_accessible", 2.5, 1), 3)
    (6.524, 4.938)
    """
    return bays * width + USES[use].least_aisle(width)


def allocate(plot: PlotSpec, runs: list[Stretch], *, barred: set[Key] = frozenset()
             ) -> Allocation:
    """The stretches of ``runs`` (:func:`stretches`) with the bays by use the plot asks for
    (module docstring); no accessible group stands on a drawn bay of ``barred``.

    Examples
    --------
    >>> from lotsim.design.plot import PlotSpec, UsesSpec, GateSpec, BuildingEntranceSpec
    >>> plot = PlotSpec("p", ((0, 0), (40, 0), (40, 20), (0, 20)), (GateSpec("g", (0, 0)),),
    ...                 (), uses=UsesSpec(accessible=None, ev=2),
    ...                 building_entrances=(BuildingEntranceSpec("door", (0.0, 10.0)),))
    >>> row = Stretch("A", "left", 90, 2.5, 5.0, "standard", 0.0, 12,
    ...               tuple((("A", "left", 2.5 * k),) for k in range(12)),
    ...               tuple((1.25 + 2.5 * k, 5.0) for k in range(12)))
    >>> a = allocate(plot, [row])
    >>> [(s.use, s.start, s.count) for s in a.stretches]  # the van bay's aisle takes a bay
    [('van_accessible', 0.0, 1), ('ev', 5.0, 2), ('standard', 10.0, 8)]
    >>> a.total, a.short
    (11, {})
    """
    uses = plot.uses
    walk = _Walks(plot, runs)

    drawn = sum(s.count for s in runs)
    if uses.accessible is None:
        best = None
        for need in range(ada_accessible(drawn), -1, -1):
            got = _carve(runs, need, uses.van_accessible, walk, barred)
            total = sum(s.count for s in got[0])
            placed = _placed(got[0])
            ok = (placed[0] >= ada_accessible(total)
                  and placed[1] >= ada_van(ada_accessible(total)))
            if best is not None and not ok:
                break
            best = got
            if not ok:  # no room for what the standard asks: keep the most placed
                break
        assert best is not None
        carved, groups = best
        total = sum(s.count for s in carved)
        need = ada_accessible(total)
        want = {"accessible": need, "van_accessible": uses.van_accessible
                if uses.van_accessible is not None else ada_van(need)}
    else:
        carved, groups = _carve(runs, uses.accessible, uses.van_accessible, walk, barred)
        total = sum(s.count for s in carved)
        want = {"accessible": uses.accessible,
                "van_accessible": uses.van_accessible if uses.van_accessible is not None
                else ada_van(uses.accessible)}
    placed = _placed(carved)
    short = {u: want[u] - n for u, n in zip(("accessible", "van_accessible"), placed,
                                            strict=True) if n < want[u]}
    ev = uses.ev_count(total)
    out, got_ev = _electric(carved, ev, walk.straight)
    if got_ev < ev:
        short["ev"] = ev - got_ev
    return Allocation(tuple(out), groups, short)


def _placed(runs: list[Stretch]) -> tuple[int, int]:
    """Accessible bays (van-accessible ones included) and van-accessible bays."""
    van = sum(s.count for s in runs if s.use == "van_accessible")
    return sum(s.count for s in runs if s.use == "accessible") + van, van


def _carve(runs: list[Stretch], accessible: int, van: int | None, walk, barred
           ) -> tuple[list[Stretch], dict[Key, tuple[Key, ...]]]:
    """``runs`` with groups of ``accessible`` accessible bays, ``van`` of them (None: one
    in six) van-accessible, each where its farthest bay is nearest the entrance."""
    vans = ada_van(accessible) if van is None else min(van, accessible)
    if van is None and vans % 2 and (accessible - vans) % 2:
        vans += 1  # two van bays share one aisle where a van and an accessible bay need two
    wanted = ([("van_accessible", 2)] * (vans // 2) + [("van_accessible", 1)] * (vans % 2)
              + [("accessible", 2)] * ((accessible - vans) // 2)
              + [("accessible", 1)] * ((accessible - vans) % 2))
    # per stretch: which of its drawn bays a group took (group number), None: free
    taken: list[list[int | None]] = [[None] * s.count for s in runs]
    placed: list[tuple[int, int, int, str, int]] = []  # stretch, first bay, span, use, bays
    for g, (use, bays) in enumerate(wanted):
        free = []  # each place the group may stand, by its straight lines
        for i, s in enumerate(runs):
            if s.angle != 90 or s.use != STANDARD or s.count < 2:
                continue
            if USES[use].size_problem(s.width, None) is not None:
                continue
            k = math.ceil(group_span(use, s.width, bays) / s.pitch - 1e-9)
            for j in range(s.count - k + 1):
                if any(taken[i][j + t] is not None or s.places[j + t][0] in barred
                       for t in range(k)):
                    continue
                far = [walk.straight(p) for p, _ in _group(s, j, use, bays)]
                free.append(((max(far), sum(far), i, j), k))
        best = _nearest(free, lambda i, j, use=use, bays=bays:
                        walk.group(runs[i], (i, j), use, bays))
        if best is None:
            continue  # no room for this group: the layout says how many are short
        i, j, k = best
        for t in range(k):
            taken[i][j + t] = g
        placed.append((i, j, k, use, bays))
    groups: dict[Key, tuple[Key, ...]] = {}
    out: list[Stretch] = []
    by_first = {(i, j): (k, use, bays) for i, j, k, use, bays in placed}
    for i, s in enumerate(runs):
        j = 0
        plain: list[int] = []

        def flush(plain=plain, s=s) -> None:
            if plain:
                out.append(_part(s, plain[0], len(plain), s.use))
                plain.clear()

        while j < s.count:
            if (i, j) in by_first:
                flush()
                k, use, bays = by_first[(i, j)]
                span = tuple(s.places[j + t][0] for t in range(k))
                groups[span[0]] = span
                c0, u = np.asarray(s.centres[j]), _along(s)
                centres = tuple(tuple(map(float, c0 + u * d))
                                for d in _offsets(use, s.width, bays))
                out.append(Stretch(s.aisle, s.side, s.angle, s.width, s.length, use,
                                   round(s.start + j * s.pitch, 9), bays, (span,) * bays,
                                   centres))
                j += k
                continue
            plain.append(j)
            j += 1
        flush()
    return out, groups


SHORTLIST = 24
"""The most places a group's walks are worked out for: past them, a group goes to the best
of those (the places taken in order of the straight line)."""


def _nearest(free: list, walks) -> tuple[int, int, int] | None:
    """The place of ``free`` (``((straight, sum, i, j), k)``) whose group's farthest walk
    is least, by ``walks(i, j)`` (the walks of its bays): places taken in order of their
    straight lines, which no walk is shorter than, until the next one's straight line is
    no shorter than the best walk found, or :data:`SHORTLIST` places."""
    best = None
    for (straight, _, i, j), k in sorted(free)[:SHORTLIST]:
        if best is not None and straight >= best[0][0]:
            break
        far = walks(i, j)
        score = (max(far), sum(far), i, j)
        if best is None or score < best[0]:
            best = (score, i, j, k)
    return None if best is None else best[1:]


class _Walks:
    """The walks of one candidate's bays to the plot's building entrances, as ``lotsim
    validate`` measures them (:func:`~lotsim.lot.walks.shortest_walk`): over the plot
    less its drawn bays and islands, from the middle of a bay's side on its access aisle,
    across the bay and the aisle themselves. Remembered per place for one
    :func:`allocate`."""

    def __init__(self, plot: PlotSpec, runs: list[Stretch]) -> None:
        self.doors = [tuple(map(float, e.at)) for e in plot.building_entrances]
        shapes = [p for s in runs for p in s.shapes]
        self.ground = (walking_ground(Polygon(plot.boundary), shapes,
                                      [Polygon(i.polygon) for i in plot.islands])
                       if self.doors else None)
        self.memo: dict[tuple, list[float]] = {}

    def straight(self, p) -> float:
        """The straight line from ``p`` to the nearest entrance [m] (0: none)."""
        return min((math.dist(p, d) for d in self.doors), default=0.0)

    def group(self, s: Stretch, at: tuple[int, int], use: str, bays: int) -> list[float]:
        """The walks of a group of ``bays`` of ``use`` whose first bay stands on drawn bay
        ``at[1]`` of ``s`` [m]."""
        key = (at, use, bays)
        if key not in self.memo:
            if self.ground is None or not s.shapes:
                self.memo[key] = [self.straight(p) for p, _ in _group(s, at[1], use, bays)]
            else:
                self.memo[key] = [min(shortest_walk(self.ground, p, d, opened=own).length
                                      for d in self.doors)
                                  for p, own in _group(s, at[1], use, bays)]
        return self.memo[key]


def _group(s: Stretch, j: int, use: str, bays: int) -> list[tuple[Point2, Polygon | None]]:
    """Per bay of a group whose first bay stands on drawn bay ``j`` of the 90° stretch
    ``s``: where its walk starts (the middle of its side on the access aisle) and the
    ground of the bay and its aisle (None without the drawn bays' shapes)."""
    u = _along(s)
    c0 = np.asarray(s.centres[j])
    aisle = USES[use].least_aisle(s.width)
    half = s.width / 2
    starts = [c0 + u * half, c0 + u * (half + aisle)][:bays]
    if not s.shapes:
        return [(tuple(map(float, p)), None) for p in starts]
    corners = np.asarray(s.shapes[j].exterior.coords)[:-1]
    along = (corners - c0) @ u  # -half or +half
    first = Polygon(corners)
    between = Polygon(corners + np.outer(half + (along + half) * aisle / s.width - along, u))
    out = [(tuple(map(float, starts[0])), shapely.union(first, between))]
    if bays == 2:
        second = Polygon(corners + np.outer(np.full(4, s.width + aisle), u))
        out.append((tuple(map(float, starts[1])), shapely.union(second, between)))
    return out


def _offsets(use: str, width: float, bays: int) -> list[float]:
    """How far along the aisle each bay of a group stands from its first [m]: the second of
    a pair beyond the access aisle they share."""
    return [0.0] if bays == 1 else [0.0, width + USES[use].least_aisle(width)]


def _along(s: Stretch) -> np.ndarray:
    """The unit along the aisle, the way a stretch's stations grow."""
    d = np.asarray(s.centres[1]) - np.asarray(s.centres[0])
    return d / np.hypot(*d)


def _part(s: Stretch, first: int, count: int, use: str) -> Stretch:
    return Stretch(s.aisle, s.side, s.angle, s.width, s.length, use,
                   round(s.start + first * s.pitch, 9), count,
                   s.places[first:first + count], s.centres[first:first + count],
                   s.shapes[first:first + count])


def _electric(runs: list[Stretch], count: int, walk) -> tuple[list[Stretch], int]:
    """``runs`` with the ``count`` standard bays nearest the entrance made EV bays, and how
    many it made."""
    if count <= 0:
        return runs, 0
    bays = sorted(((walk(c), i, j) for i, s in enumerate(runs) if s.use == STANDARD
                   for j, c in enumerate(s.centres)))
    chosen = {(i, j) for _, i, j in bays[:count]}
    out: list[Stretch] = []
    for i, s in enumerate(runs):
        if s.use != STANDARD:
            out.append(s)
            continue
        j = 0
        while j < s.count:
            ev = (i, j) in chosen
            k = j
            while k < s.count and ((i, k) in chosen) == ev:
                k += 1
            out.append(_part(s, j, k - j, "ev" if ev else STANDARD))
            j = k
    return out, len(chosen)
