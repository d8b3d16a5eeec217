"""A Lanelet2 map's roads and spots as a lot's aisles and slots.

Each road (:mod:`.lanelet2_roads`) becomes an aisle along its carriageway, widened over the
``parking_access`` ground on each side so that its edge lies along the entries of the spots
that open onto it: lotsim's slots open onto an aisle's edge within 0.3 m
(``docs/scenario.md``), and a car parks only from a straight stretch of lane. So the aisle
keeps the road's straight legs (a road drawn with corners too close for lotsim to round
them has them merged, :func:`drivable`), each shifted sideways on its own, and one width:
the width and the shifts that reach the entries of the most spots without covering any.
A spot opens onto the road its entry faces (the nearest centre line in front of it); a
spot the aisle's edge cannot reach, or that lies beside a bend of its lanes, is reported,
with why.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon

from lotsim.core.corners import corner_sharpness
from lotsim.core.geometry import FloatArray, cc_polyline, cc_turn, sample_segments
from lotsim.io.imports.lanelet2_roads import Road
from lotsim.io.imports.lanelet2_spots import Spot
from lotsim.lot.build import CRAWL_SPEED, SWEEP_STEP, bend_sharpness, offset_polyline
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle

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
    leg's line, and the station of its entry's middle along the road's line [m]."""

    spot: Spot
    leg: int
    side: int
    mid: float
    near: float
    station: float


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
    first_leg: int = 0  # of the road's legs, this piece's first

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
        turns = np.degrees(np.abs(_turns(line)))
        if not len(turns) or turns.min() >= TIE_DEG / 2:
            break
        line = np.delete(line, int(np.argmin(turns)) + 1, axis=0)
    return drivable(line, short)


def _unit(v: FloatArray) -> FloatArray:
    return v / float(np.hypot(*v))


def _turns(line: FloatArray) -> FloatArray:
    d = np.diff(line, axis=0)
    h = np.arctan2(d[:, 1], d[:, 0])
    return (np.diff(h) + np.pi) % (2 * np.pi) - np.pi


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
        gaps = [LineString(base[j:j + 2]).distance(Point(mid)) for j in range(len(base) - 1)]
        j = int(np.argmin(gaps))
        u = _unit(base[j + 1] - base[j])
        n = np.array([-u[1], u[0]])
        ya, ym, yb = (float(np.dot(p - base[j], n)) for p in (spot.entry[0], mid,
                                                              spot.entry[1]))
        side = 1 if ym > 0 else -1
        aisle.facing.append(Facing(spot, j, side, abs(ym), min(side * ya, side * yb),
                                   float(lines[best[1]].project(Point(mid)))))
    return reasons


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
    turns = np.degrees(np.abs(_turns(base)))
    stretch = np.concatenate([[0], np.cumsum(turns >= TIE_DEG)])  # leg -> stretch
    count = int(stretch[-1]) + 1
    size = int(MAX_EDGE / GRID) + 1
    tables = []
    for k in range(count):
        score = {}
        for side in (1, -1):
            items = [f for f in aisle.facing if stretch[f.leg] == k and f.side == side]
            if items:
                score[side] = _counts([(f.mid - ENTRY_REACH + MARGIN, f.near - MARGIN)
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
        elif f.mid - edge > ENTRY_REACH - MARGIN + 1e-9:
            reasons[f.spot.id] = (
                f"its entry lies {f.mid:.2f} m from the road's centre line, "
                f"{f.mid - edge:.2f} m beyond the edge of the {width:.2f} m aisle, which "
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

    turns = np.degrees(np.abs(_turns(aisle.base)))
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
    second = [Facing(f.spot, f.leg - k, f.side, f.mid, f.near, f.station)
              for f in aisle.facing if f.leg >= k]
    a = AisleLayout(aisle.road, aisle.base[:k + 1], first,
                    ends=[aisle.ends[0], ("corner", None)], first_leg=aisle.first_leg)
    b = AisleLayout(aisle.road, aisle.base[k:], second,
                    ends=[("corner", None), aisle.ends[1]], first_leg=aisle.first_leg + k)
    return a, b


def join_corner(a: AisleLayout, b: AisleLayout) -> None:
    """Put the end of ``a`` and the start of ``b`` on the point where their end legs meet."""
    p = _crossing(a.line[-2], a.line[-1], b.line[0], b.line[1])
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
        pts.append(_crossing(a[j - 1], b[j - 1], a[j], b[j]))
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


def end_on(line: FloatArray, end: int, host: FloatArray) -> FloatArray:
    """``line`` with its end ``end`` (0 first, 1 last) on the centre line ``host``: its end
    leg carried on or cut back to where it crosses it, else a leg to its nearest point."""
    pts = line if end == 1 else line[::-1]
    target = LineString(host)
    base, tip = pts[-2], pts[-1]
    d = _unit(tip - base)
    ray = LineString([base, tip + d * 60.0])
    hit = ray.intersection(target)
    cands = [np.asarray(g.coords[0]) for g in getattr(hit, "geoms", [hit])
             if not g.is_empty and g.geom_type == "Point"]
    cands = [q for q in cands if float(np.dot(q - base, d)) > 0.5]
    if cands:
        q = min(cands, key=lambda q: float(np.hypot(*(q - tip))))
        pts = np.vstack([pts[:-1], q])
    else:
        q = np.asarray(target.interpolate(target.project(Point(tip))).coords[0])
        pts = np.vstack([pts, q])
    return pts if end == 1 else pts[::-1]


def extend_to(line: FloatArray, end: int, boundary: Polygon, inset: float) -> FloatArray:
    """``line`` with its end ``end`` carried on to ``inset`` metres inside ``boundary``."""
    pts = line if end == 1 else line[::-1]
    base, tip = pts[-2], pts[-1]
    d = _unit(tip - base)
    ray = LineString([tip, tip + d * 50.0])
    hit = ray.intersection(boundary.exterior)
    cands = [np.asarray(g.coords[0]) for g in getattr(hit, "geoms", [hit])
             if not g.is_empty and g.geom_type == "Point"]
    if cands:
        q = min(cands, key=lambda q: float(np.hypot(*(q - tip))))
        far = q - d * inset
        if float(np.dot(far - tip, d)) > 0:
            pts = np.vstack([pts[:-1], far])
    return pts if end == 1 else pts[::-1]


@dataclass(frozen=True)
class Bends:
    """How lotsim rounds an aisle's corners (:func:`~lotsim.lot.build.build_lot`): the
    default bend radius on the centre line, concentric on the lanes a quarter of the width
    either side (one lane on the line when one-way), clothoids of cruising speed, sharper
    down to a crawl where legs are short."""

    width: float
    two_way: bool
    design: DesignVehicle
    speed: float  # the lot's speed limit [m/s]

    def paths(self, line: FloatArray) -> list[tuple[FloatArray, FloatArray, bool]]:
        """The centre line and each lane: (points, each corner's radius, reversed)."""
        offset = self.width / 4 if self.two_way else 0.0
        radius = self.design.min_radius + offset
        turns = _turns(line)
        out = [(line, np.full(len(turns), radius), False)]
        for pts, rev in ([(line, False), (line[::-1], True)] if self.two_way
                         else [(line, False)]):
            t = _turns(pts)
            out.append((offset_polyline(pts, offset) if offset else pts,
                        radius + offset * np.sign(t), rev))
        return out

    @property
    def sharpness(self) -> tuple[float, float]:
        """The clothoids' sharpness at cruising speed and at a crawl [1/m²]."""
        offset = self.width / 4 if self.two_way else 0.0
        radius = self.design.min_radius + offset
        return (bend_sharpness(radius, offset, self.design, self.speed),
                self.design.sharpness(CRAWL_SPEED))

    def short(self, line: FloatArray) -> FloatArray:
        """By how much each leg is too short for the corners at its ends [m] (positive:
        lotsim refuses it), on the centre line or a lane, at a crawl."""
        _, sharpest = self.sharpness
        worst = np.full(len(line) - 1, -np.inf)
        for pts, radii, rev in self.paths(line):
            cut = np.array([cc_turn(float(t), 1 / float(r), sharpest)[1] if abs(t) > 1e-12
                            else 0.0 for t, r in zip(_turns(pts), radii, strict=True)])
            need = np.concatenate([[0.0], cut]) + np.concatenate([cut, [0.0]])
            lack = need - np.hypot(*np.diff(pts, axis=0).T)
            worst = np.maximum(worst, lack[::-1] if rev else lack)
        return worst

    def corners(self, line: FloatArray) -> FloatArray:
        """Each corner's clothoid sharpness [1/m²], as lotsim picks it: the cruising one,
        sharper where the centre line's or a lane's legs are short."""
        cruise, sharpest = self.sharpness
        sharp = np.full(len(line) - 2, cruise)
        for pts, radii, rev in self.paths(line):
            need = np.asarray(corner_sharpness(pts, radii, cruise, sharpest))
            sharp = np.maximum(sharp, need[::-1] if rev else need)
        return sharp

    def sweep(self, line: FloatArray) -> Polygon:
        """The ground the envelope car covers driving every lane of the aisle [m²]."""
        sharp = self.corners(line)
        parts = []
        for pts, radii, rev in self.paths(line)[1:]:
            segs = cc_polyline(pts, radii, sharp[::-1] if rev else sharp)
            poses, _ = sample_segments(segs, SWEEP_STEP)
            hulls = shapely.convex_hull(shapely.multipoints(
                Collider.sweeps(self.design.footprints(poses))))
            parts.append(shapely.union_all(hulls))
        return shapely.union_all(parts)

    def zones(self, line: FloatArray) -> list[tuple[float, float]]:
        """The stretches of the centre line [m] beside which a lane turns at a corner."""
        sharp = self.corners(line)
        cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(line, axis=0).T))])
        reach = np.zeros(len(line) - 2)
        for pts, radii, rev in self.paths(line):
            sig = sharp[::-1] if rev else sharp
            turns = _turns(pts)
            cut = np.array([cc_turn(float(t), 1 / float(r), float(g))[1]
                            + abs((pts is not line) * self.width / 4 * np.tan(t / 2))
                            if abs(t) > 1e-12 else 0.0
                            for t, r, g in zip(turns, radii, sig, strict=True)])
            reach = np.maximum(reach, cut[::-1] if rev else cut)
        return [(cum[k + 1] - c, cum[k + 1] + c) for k, c in enumerate(reach) if c > 0]


def drivable(line: FloatArray, short: Callable[[FloatArray], FloatArray]) -> FloatArray:
    """``line`` with its corners few enough and far enough apart for lotsim to round each
    (``short``: :meth:`Bends.short`): two corners too close that turn the same way become
    one where their outer legs meet; of two that turn opposite ways (a jog), the smaller
    goes. The ends stay."""
    pts = np.asarray(line, dtype=float)
    for _ in range(len(pts)):
        if len(pts) < 3:
            return pts
        lack = short(pts)
        i = int(np.argmax(lack))
        if lack[i] <= 1e-6:
            return pts
        legs = np.diff(pts, axis=0)
        heading = np.arctan2(legs[:, 1], legs[:, 0])
        turns = (np.diff(heading) + np.pi) % (2 * np.pi) - np.pi
        # leg i runs from vertex i to i + 1; vertices 1..n-2 are corners (turns[v - 1])
        inner = [v for v in (i, i + 1) if 0 < v < len(pts) - 1]
        if len(inner) == 2 and turns[i - 1] * turns[i] > 0 and i + 2 < len(pts):
            p = _crossing(pts[i - 1], pts[i], pts[i + 1], pts[i + 2])
            length = float(np.hypot(*legs[i]))
            if float(np.hypot(*(p - (pts[i] + pts[i + 1]) / 2))) < 3 * length + 2.0:
                pts = np.vstack([pts[:i], p, pts[i + 2:]])
                continue
        v = min(inner, key=lambda v: abs(turns[v - 1]))
        pts = np.delete(pts, v, axis=0)
    return pts


def _crossing(a0: FloatArray, a1: FloatArray, b0: FloatArray, b1: FloatArray) -> FloatArray:
    """Where the line through a0, a1 meets the line through b0, b1."""
    da, db = a1 - a0, b1 - b0
    den = da[0] * db[1] - da[1] * db[0]
    if abs(den) < 1e-12:
        return (a1 + b0) / 2
    t = ((b0 - a0)[0] * db[1] - (b0 - a0)[1] * db[0]) / den
    return a0 + t * da
