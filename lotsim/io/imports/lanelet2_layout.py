"""A Lanelet2 map's roads and spots as a lot's aisles and slots.

Each road (:mod:`.lanelet2_roads`) becomes an aisle along its carriageway, widened over the
``parking_access`` ground on each side so that its edge lies along the entries of the spots
that open onto it: lotsim's slots open onto an aisle's edge within 0.3 m
(``docs/scenario.md``), and a car parks only from a straight stretch of lane. So the aisle
keeps the road's straight legs (corners too close for lotsim to round them merged:
:func:`~lotsim.io.imports.lanelet2_lines.drivable`), each shifted sideways on its own, and
one width: the width and the shifts that reach the entries of the most spots without
covering any. A road may be cut at a corner into aisles meeting in an L where that serves
more spots (:func:`cut_at_corners`).
A spot opens onto the road its entry faces (the nearest centre line in front of it); a
spot the aisle's edge cannot reach, or that lies beside a bend of its lanes, is reported,
with why.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon

from lotsim.core.geometry import FloatArray
from lotsim.io.imports.draft import SlotDraft
from lotsim.io.imports.lanelet2_lines import Bends, crossing, drivable, normalised, turn_angles
from lotsim.io.imports.lanelet2_map import id_key
from lotsim.io.imports.lanelet2_roads import Road
from lotsim.io.imports.lanelet2_spots import Spot, classified, rectangle

ENTRY_REACH = 0.3
"""A slot's entry must lie within this of its aisle [m] (lotsim's rule)."""
MARGIN = 0.04
"""Kept between an aisle's edge and a slot, and inside the 0.3 m, against rounding [m]."""
SIMPLIFY = 0.1
"""Tolerance of the road lines' simplification [m]."""
TIE_DEG = 3.0
"""Legs meeting at a smaller bend [degrees] are shifted together."""
FACING = 12.0
"""How far in front of its entry a spot looks for the road it opens onto [m]."""
FACING_DEG = 50.0
"""A spot faces a road whose nearest point lies within this of straight out of its entry
[degrees]."""
FREE_SIDE = 1.0
"""On a side with no spots the aisle's edge keeps within this of the carriageway's [m]."""
MIN_WIDTH = 4.2
"""The narrowest aisle: two lanes of a 1.8 m car with 0.15 m each side [m]."""
MAX_EDGE = 8.0
"""The farthest an aisle's edge lies from its road's centre line [m]."""
GRID = 0.01
"""Resolution of the widths and shifts searched [m]."""
SPLIT_DEG = 20.0
"""A road bending this much or more may be cut there into two aisles meeting in an L
[degrees]."""
MIN_GAIN = 2
"""Cut a road into two aisles only where that serves at least this many more spots."""
BEND_CLEAR = 0.3
"""A spot's entry this close to where a lane starts to bend is beside the bend [m]."""


@dataclass(frozen=True)
class Facing:
    """A spot opening onto an aisle's road: the leg of the road's line it faces, its side
    (+1 left, -1 right), the distances [m] of its entry's middle and nearer end from the
    leg's line."""

    spot: Spot
    leg: int
    side: int
    mid: float
    near: float

    @property
    def reach(self) -> float:
        """The distance [m] the aisle's edge must come within :data:`ENTRY_REACH` of: the
        entry's middle; an angled spot's nearer end (its entry slants away from the aisle,
        as in an angled row, or it lies inside a parallelogram whose entry side does)."""
        return self.near if self.spot.kind == "angled" else self.mid


@dataclass
class AisleLayout:
    """One aisle: its road, the road's line as straight legs (``base``), the spots facing
    it, and once fitted its centre line [m], width [m] and slots."""

    road: Road
    base: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    facing: list[Facing] = field(default_factory=list)
    line: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    width: float = 0.0
    slots: list[Spot] = field(default_factory=list)
    ends: list[tuple[str, int | None]] = field(default_factory=list)

    def __post_init__(self) -> None:
        if not self.ends:
            self.ends = list(self.road.ends)

    @property
    def half(self) -> float:
        """Half the carriageway's width [m]."""
        return self.road.width / 2

    @property
    def polygon(self) -> Polygon:
        """As lotsim builds it: the centre line grown by half the width, flat ends."""
        return LineString(self.line).buffer(self.width / 2, cap_style="flat",
                                            join_style="round")


def legs_of(road: Road, short: Callable[[FloatArray], FloatArray]) -> FloatArray:
    """The road's line as straight legs: simplified, bends under :data:`TIE_DEG` / 2
    straightened, corners lotsim could not round merged (:func:`drivable`)."""
    line = np.asarray(shapely.simplify(LineString(road.line), SIMPLIFY).coords)
    for _ in range(len(line)):
        turns = np.degrees(np.abs(turn_angles(line)))
        if not len(turns) or turns.min() >= TIE_DEG / 2:
            break
        line = np.delete(line, int(np.argmin(turns)) + 1, axis=0)
    return drivable(line, short)


def assign(spots: list[Spot], aisles: list[AisleLayout]) -> dict[str, str]:
    """Put each spot on the aisle whose road its entry faces: the nearest road line within
    :data:`FACING` that lies within :data:`FACING_DEG` of straight out of the entry, on the
    leg nearest its entry; the spots that face none, with why."""
    lines = [LineString(a.base) for a in aisles]
    reasons: dict[str, str] = {}
    cos_max = float(np.cos(np.radians(FACING_DEG)))
    for spot in spots:
        if spot.reason:
            reasons[spot.id] = spot.reason
            continue
        mid = spot.entry_mid
        best = None
        for a, line in enumerate(lines):
            q = np.asarray(line.interpolate(line.project(Point(mid))).coords[0])
            d = float(np.hypot(*(q - mid)))
            if d > FACING or d < 1e-6 or float(np.dot(q - mid, spot.outward)) < cos_max * d:
                continue
            if best is None or d < best[0]:
                best = (d, a)
        if best is None:
            reasons[spot.id] = (f"no road's centre line lies within {FACING:g} m in front of "
                                "its entry")
            continue
        aisle = aisles[best[1]]
        base = aisle.base
        j = _leg_faced(base, mid, spot.outward)
        u = normalised(base[j + 1] - base[j])
        n = np.array([-u[1], u[0]])
        ya, ym, yb = (float(np.dot(p - base[j], n)) for p in (spot.entry[0], mid,
                                                              spot.entry[1]))
        side = 1 if ym > 0 else -1
        spot = classified(spot, math.atan2(u[1], u[0]))
        aisle.facing.append(Facing(spot, j, side, abs(ym), min(side * ya, side * yb)))
    return reasons


def _leg_faced(base: FloatArray, mid: FloatArray, outward: FloatArray) -> int:
    """The leg of ``base`` an entry at ``mid`` facing ``outward`` opens onto: of the legs
    within a metre of the nearest, one it lies beside (its foot on the leg), else (past a
    corner) the one it faces most squarely."""
    legs = []
    for j in range(len(base) - 1):
        a, b = base[j], base[j + 1]
        d = b - a
        t = float(np.dot(mid - a, d) / np.dot(d, d))
        n = np.array([-d[1], d[0]]) / float(np.hypot(*d))
        legs.append((LineString([a, b]).distance(Point(mid)), 0.0 <= t <= 1.0,
                     abs(float(np.dot(n, outward))), j))
    near = min(g for g, *_ in legs) + 1.0
    return min((lg for lg in legs if lg[0] <= near),
               key=lambda lg: (not lg[1], lg[0] if lg[1] else -lg[2]))[3]


def _counts(spans: list[tuple[float, float]], size: int) -> FloatArray:
    """How many of ``spans`` hold each edge distance ``k * GRID`` [m], k < size."""
    diff = np.zeros(size + 1)
    for lo, hi in spans:
        a, b = max(int(np.ceil(lo / GRID - 1e-9)), 0), min(int(np.floor(hi / GRID + 1e-9)),
                                                           size - 1)
        if a <= b:
            diff[a] += 1
            diff[b + 1] -= 1
    return np.cumsum(diff)[:size]


def fit(aisle: AisleLayout) -> dict[str, str]:
    """Choose the aisle's width and each stretch's shift so that the edge reaches the most
    spots' entries within :data:`ENTRY_REACH` and covers none; the spots left out, with why.

    A stretch is a run of legs meeting at bends under :data:`TIE_DEG`. Each side of a
    stretch scores every edge distance by the spots it serves (a side with none: 0 within
    :data:`FREE_SIDE` of the carriageway's edge); the width is the one whose best split
    between the sides, summed over the stretches, serves the most."""
    base = aisle.base
    aisle.slots = []
    turns = np.degrees(np.abs(turn_angles(base)))
    stretch = np.concatenate([[0], np.cumsum(turns >= TIE_DEG)])  # leg -> stretch
    count = int(stretch[-1]) + 1
    size = int(MAX_EDGE / GRID) + 1
    tables = []
    for k in range(count):
        score = {}
        for side in (1, -1):
            items = [f for f in aisle.facing if stretch[f.leg] == k and f.side == side]
            if items:
                score[side] = _counts([(f.reach - ENTRY_REACH + MARGIN, f.near - MARGIN)
                                       for f in items], size)
            else:
                free = np.full(size, -np.inf)
                lo = max(int((aisle.half - FREE_SIDE) / GRID), 0)
                free[lo:min(int((aisle.half + FREE_SIDE) / GRID), size - 1) + 1] = 0.0
                score[side] = free
        left, right = score[1], score[-1]
        total = np.full(2 * size - 1, -np.inf)
        for e in np.flatnonzero(np.isfinite(left)):
            total[e:e + size] = np.maximum(total[e:e + size], left[e] + right)
        tables.append((left, right, total))
    overall = np.sum([t[2] for t in tables], axis=0)
    overall[:int(np.ceil(MIN_WIDTH / GRID))] = -np.inf
    best = np.flatnonzero(overall >= overall.max() - 1e-9)
    runs = np.split(best, np.flatnonzero(np.diff(best) > 1) + 1)
    run = max(runs, key=len)
    w = int(run[len(run) // 2])  # the middle of the widest range of best widths
    width = w * GRID
    edges = []
    for left, right, _ in tables:
        ks = np.arange(max(0, w - size + 1), min(size, w + 1))
        sums = left[ks] + right[w - ks]
        top = ks[sums >= sums.max() - 1e-9]
        e = int(top[len(top) // 2])
        edges.append((e * GRID, width - e * GRID))
    reasons = {}
    for f in aisle.facing:
        edge = edges[stretch[f.leg]][0 if f.side > 0 else 1]
        if f.near - edge < MARGIN - 1e-9:
            reasons[f.spot.id] = (
                f"its entry lies {f.mid:.2f} m from the road's centre line, inside the "
                f"{width:.2f} m aisle whose edge reaches more of the entries there")
        elif f.reach - edge > ENTRY_REACH - MARGIN + 1e-9:
            reasons[f.spot.id] = (
                f"its entry lies {f.reach:.2f} m from the road's centre line, "
                f"{f.reach - edge:.2f} m beyond the edge of the {width:.2f} m aisle, which "
                "reaches more of the entries there")
        else:
            aisle.slots.append(f.spot)
    aisle.width = width
    shifts = [(left - right) / 2 for left, right in edges]
    aisle.line = _shifted(base, [shifts[stretch[j]] for j in range(len(base) - 1)])
    return reasons


def cut_at_corners(aisle: AisleLayout, bends: Callable[[float], Bends]) -> list[AisleLayout]:
    """The aisle cut into pieces at corners of :data:`SPLIT_DEG` or more where that lets
    more spots be served (each piece fitted on its own, :func:`fit`, and its spots beside
    its bends left out, :func:`beside_bends`): pieces that meet at a corner make an L.
    ``bends`` gives the :class:`Bends` of a piece of a width."""
    def served(piece: AisleLayout) -> int:
        trial = AisleLayout(piece.road, piece.base, piece.facing)
        fit(trial)
        trial.line = drivable(trial.line, bends(trial.width).short)
        beside_bends(trial, bends(trial.width))
        return len(trial.slots)

    turns = np.degrees(np.abs(turn_angles(aisle.base)))
    best = (served(aisle) + MIN_GAIN - 1, None)
    for k in np.flatnonzero(turns >= SPLIT_DEG) + 1:
        a, b = _cut(aisle, int(k))
        gain = served(a) + served(b)
        if gain > best[0]:
            best = (gain, (a, b))
    if best[1] is None:
        return [aisle]
    a, b = best[1]
    return cut_at_corners(a, bends) + cut_at_corners(b, bends)


def _cut(aisle: AisleLayout, k: int) -> tuple[AisleLayout, AisleLayout]:
    """The aisle's pieces before and after its base's vertex ``k``."""
    first = [f for f in aisle.facing if f.leg < k]
    second = [Facing(f.spot, f.leg - k, f.side, f.mid, f.near)
              for f in aisle.facing if f.leg >= k]
    a = AisleLayout(aisle.road, aisle.base[:k + 1], first,
                    ends=[aisle.ends[0], ("corner", None)])
    b = AisleLayout(aisle.road, aisle.base[k:], second,
                    ends=[("corner", None), aisle.ends[1]])
    return a, b


def join_corner(a: AisleLayout, b: AisleLayout) -> None:
    """Put the end of ``a`` and the start of ``b`` on the point where their end legs meet."""
    p = crossing(a.line[-2], a.line[-1], b.line[0], b.line[1])
    a.line = np.vstack([a.line[:-1], p])
    b.line = np.vstack([p, b.line[1:]])


def _shifted(base: FloatArray, shifts: list[float]) -> FloatArray:
    """``base`` with each leg moved ``shifts[j]`` to its left, corners where the moved legs
    meet."""
    d = np.diff(base, axis=0)
    n = np.column_stack([-d[:, 1], d[:, 0]]) / np.hypot(*d.T)[:, None]
    a = base[:-1] + n * np.asarray(shifts)[:, None]
    b = base[1:] + n * np.asarray(shifts)[:, None]
    pts = [a[0]]
    for j in range(1, len(a)):
        pts.append(crossing(a[j - 1], b[j - 1], a[j], b[j]))
    pts.append(b[-1])
    return np.array(pts)


def beside_bends(aisle: AisleLayout, bends: Bends) -> dict[str, str]:
    """Drop the aisle's slots whose entry lies beside a bend of its lanes (lotsim parks a
    car only from a straight stretch of lane): within :data:`BEND_CLEAR` of where a lane
    turns at a corner of the centre line."""
    line = LineString(aisle.line)
    zones = [(lo - BEND_CLEAR, hi + BEND_CLEAR) for lo, hi in bends.zones(aisle.line)]
    reasons = {}
    kept = []
    for spot in aisle.slots:
        s = line.project(Point(spot.entry_mid))
        hit = next(((lo, hi) for lo, hi in zones if lo <= s <= hi), None)
        if hit is None:
            kept.append(spot)
        else:
            reasons[spot.id] = ("its entry faces a bend of its aisle, where the lanes turn "
                                f"(over {hit[1] - hit[0]:.1f} m): lotsim parks a car from a "
                                "straight stretch of lane")
    aisle.slots = kept
    return reasons


SHRINK = 0.01
"""Each slot is drawn this much inside the mapped spot's long sides and ends [m], so that
neighbours that share a side do not overlap once written to the centimetre."""


def rounded_slot(spot: Spot, shrink: float) -> tuple[SlotDraft, Polygon]:
    """The slot of ``spot`` as written (to the centimetre and the hundredth of a degree),
    ``shrink`` [m] in from the sides it shares with its neighbours (a bay's long sides, a
    kerbside space's ends) and :data:`SHRINK` from the others, and the rectangle lotsim
    will build from those numbers; an angled spot with its angle to its aisle."""
    cx, cy = (round(float(v), 2) for v in spot.center)
    heading = round(math.degrees(spot.heading), 2)
    across, along = (SHRINK, shrink) if spot.parallel else (shrink, SHRINK)
    # to the centimetre below: a spot a hair under 2.5 m is 2.5 m less the rim, not 2.47
    width = math.floor(round((spot.width - 2 * across) * 100, 2)) / 100
    length = math.floor(round((spot.length - 2 * along) * 100, 2)) / 100
    angle = round(spot.angle, 2) if spot.kind == "angled" else None
    draft = SlotDraft(f"P{spot.id}", spot.kind, width, length, (cx, cy), heading,
                      angle_deg=angle)
    return draft, rectangle((cx, cy), math.radians(heading), width, length)


def written_slots(aisles: list[AisleLayout], ids: list[str], reasons: dict[str, str],
                  boundary: Polygon) -> list[tuple[SlotDraft, str]]:
    """The kept spots as slots, as lotsim will build them from the written numbers: drawn
    inside their outlines so that neighbours do not overlap, each opening onto an aisle's
    edge within reach and covered by none; a spot that does not is reported."""
    spots = sorted(((s, ids[k]) for k, a in enumerate(aisles) for s in a.slots),
                   key=lambda sa: id_key(sa[0].id))
    if not spots:  # every spot was dropped before (their reasons are said)
        return []
    shrink = {s.id: SHRINK for s, _ in spots}
    while True:
        built = [rounded_slot(s, shrink[s.id]) for s, _ in spots]
        polys = np.array([p for _, p in built])
        tree = shapely.STRtree(polys)
        left, right = tree.query(polys, predicate="intersects")
        keep = left < right
        left, right = left[keep], right[keep]
        area = shapely.area(shapely.intersection(polys[left], polys[right]))
        bad = sorted({int(i) for k in np.flatnonzero(area > 1e-7) for i in (left[k],
                                                                            right[k])})
        if not bad:
            break
        for i in bad:
            shrink[spots[i][0].id] += 0.01
    rounded = [np.round(a.line, 2) for a in aisles]
    shapes = [LineString(line).buffer(a.width / 2, cap_style="flat", join_style="round")
              for line, a in zip(rounded, aisles, strict=True)]
    out = []
    for (spot, aid), (draft, poly) in zip(spots, built, strict=True):
        covered = [ids[k] for k, sh in enumerate(shapes) if poly.intersection(sh).area > 1e-7]
        c = np.asarray(draft.center)
        d = np.array([math.cos(math.radians(draft.heading_deg)),
                      math.sin(math.radians(draft.heading_deg))])
        n = np.array([-d[1], d[0]])
        # lotsim's reach: the middle of the entry (the back of a bay, either long side of a
        # kerbside space); the whole entry of an angled bay, whose nearer end counts
        back = c - d * draft.length / 2
        entries = ([shapely.Point(c + n * draft.width / 2), shapely.Point(c - n * draft.width / 2)]
                   if spot.parallel else
                   [LineString([back - n * draft.width / 2, back + n * draft.width / 2])]
                   if spot.kind == "angled" else [shapely.Point(back)])
        gap = min(sh.distance(e) for sh in shapes for e in entries)
        if covered:
            reasons[spot.id] = f"aisle {covered[0]} covers part of it"
        elif gap > ENTRY_REACH - 1e-3:
            reasons[spot.id] = f"its entry is {gap:.2f} m from the nearest aisle"
        elif not boundary.covers(poly):
            reasons[spot.id] = "it lies partly outside the lot's boundary"
        else:
            out.append((draft, aid))
    return out
