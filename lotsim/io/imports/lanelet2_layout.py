"""A Lanelet2 map's roads and spots as a lot's aisles and slots.

Each road (:mod:`.lanelet2_roads`) becomes an aisle along its carriageway, widened over the
``parking_access`` ground on each side so that its edge lies along the entries of the spots
that open onto it: lotsim's slots open onto an aisle's edge within 0.3 m
(``docs/scenario.md``). A spot opens onto the road its entry faces (the first centre line
straight out of it). The aisle keeps one width; its centre line is the road's, shifted
sideways by an offset that may change along it (rows drawn along a curve beside a straight
road, access strips of different depths), never faster than :data:`SLOPE` metres a metre:
the offsets are chosen by dynamic programming so that the aisle's edge reaches the most
entries without covering a spot, and then drawn with as few bends as they allow. A spot
its edge cannot reach so is reported, with why.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon

from lotsim.core.geometry import FloatArray, cc_turn
from lotsim.io.imports.lanelet2_roads import Road
from lotsim.io.imports.lanelet2_spots import Spot
from lotsim.lot.build import bend_sharpness, offset_polyline
from lotsim.lot.model import DesignVehicle

ENTRY_REACH = 0.3
"""A slot's entry must lie within this of its aisle [m] (lotsim's rule)."""
MARGIN = 0.04
"""Kept between an aisle's edge and a slot, and inside the 0.3 m, against rounding [m]."""
SIMPLIFY = 0.05
"""Tolerance of the road lines' simplification [m]."""
FACING = 12.0
"""How far straight out of its entry a spot looks for the road it opens onto [m]."""
FACING_DEG = 50.0
"""A spot faces a road whose nearest point lies within this of straight out of its entry
[degrees]."""
FREE_SIDE = 1.0
"""On a side with no spots the aisle's edge keeps within this of the carriageway's [m]."""
MIN_WIDTH = 4.2
"""The narrowest aisle: two lanes of a 1.8 m car with 0.15 m each side [m]."""
SLOPE = 0.2
"""The fastest the centre line's offset changes along the road [m/m] (11°)."""
GRID = 0.01
"""Resolution of the offsets searched [m]."""
REACH = 4.0
"""The farthest the centre line is shifted off the road's [m]."""
KNOT_GAP = 4.0
"""Offsets are chosen at least this often along the road [m]."""


@dataclass(frozen=True)
class Facing:
    """A spot opening onto an aisle's road: its side (+1 left, -1 right), and the stations
    [m] and distances [m] from the road's line of its entry's ends and middle."""

    spot: Spot
    side: int
    stations: tuple[float, float, float]  # one end, the middle, the other end
    distances: tuple[float, float, float]


@dataclass
class AisleLayout:
    """One aisle: its road, its centre line [m] and width [m], its slots."""

    road: Road
    base: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    facing: list[Facing] = field(default_factory=list)
    line: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    width: float = 0.0
    slots: list[Spot] = field(default_factory=list)

    def __post_init__(self) -> None:
        if not len(self.base) and len(self.road.line):
            self.base = np.asarray(shapely.simplify(LineString(self.road.line),
                                                    SIMPLIFY).coords)

    @property
    def half(self) -> float:
        """Half the carriageway's width [m]."""
        return self.road.width / 2

    @property
    def polygon(self) -> Polygon:
        """As lotsim builds it: the centre line grown by half the width, flat ends."""
        return LineString(self.line).buffer(self.width / 2, cap_style="flat",
                                            join_style="round")


def _unit(v: FloatArray) -> FloatArray:
    return v / float(np.hypot(*v))


def assign(spots: list[Spot], aisles: list[AisleLayout]) -> dict[str, str]:
    """Put each spot on the aisle whose road its entry faces: the nearest road line within
    :data:`FACING` that lies within :data:`FACING_DEG` of straight out of the entry; the
    spots that face none, with why."""
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
            s = float(line.project(Point(mid)))
            q = np.asarray(line.interpolate(s).coords[0])
            d = float(np.hypot(*(q - mid)))
            if d > FACING or d < 1e-6 or float(np.dot(q - mid, spot.outward)) < cos_max * d:
                continue
            if best is None or d < best[0]:
                best = (d, a, s)
        if best is None:
            reasons[spot.id] = (f"no road's centre line lies within {FACING:g} m in front of "
                                "its entry")
            continue
        _, a, s = best
        aisle, line = aisles[a], lines[a]
        pts = (spot.entry[0], mid, spot.entry[1])
        stations = tuple(float(line.project(Point(p))) for p in pts)
        distances = tuple(float(line.distance(Point(p))) for p in pts)
        q = np.asarray(line.interpolate(s).coords[0])
        t = _tangent(aisle.base, s)
        side = 1 if t[0] * (mid - q)[1] - t[1] * (mid - q)[0] > 0 else -1
        aisle.facing.append(Facing(spot, side, stations, distances))
    return reasons


def _tangent(line: FloatArray, s: float) -> FloatArray:
    """Unit direction of the polyline at station ``s``."""
    seg = np.hypot(*np.diff(line, axis=0).T)
    k = int(np.clip(np.searchsorted(np.cumsum(seg), s), 0, len(seg) - 1))
    return _unit(line[k + 1] - line[k])


def _bounds(f: Facing, width: float) -> list[tuple[float, float, float]]:
    """The spot's demands on the centre line's offset: (station, lowest, highest)."""
    (sa, sm, sb), (ya, ym, yb) = f.stations, f.distances
    h = width / 2
    if f.side > 0:  # left edge = offset + h: short of each entry end, within reach of its middle
        return [(sa, -np.inf, ya - MARGIN - h), (sb, -np.inf, yb - MARGIN - h),
                (sm, ym - ENTRY_REACH + MARGIN - h, np.inf)]
    return [(sa, h - ya + MARGIN, np.inf), (sb, h - yb + MARGIN, np.inf),
            (sm, -np.inf, h - ym + ENTRY_REACH - MARGIN)]


def _width(aisle: AisleLayout) -> float:
    """The width that suits the most stretches: where spots face each other across the road,
    the gap between their entries less 0.06 to 0.54 m; where one side has none, the spots'
    side within reach and the other near the carriageway's edge."""
    spans = []
    for f in aisle.facing:
        lo_f = f.distances[1] - ENTRY_REACH + MARGIN
        hi_f = min(f.distances[0], f.distances[2]) - MARGIN
        across = [g for g in aisle.facing if g.side != f.side
                  and min(g.stations[0], g.stations[2]) - 0.5 <= f.stations[1]
                  <= max(g.stations[0], g.stations[2]) + 0.5]
        if across:
            for g in across:
                lo_g = g.distances[1] - ENTRY_REACH + MARGIN
                hi_g = min(g.distances[0], g.distances[2]) - MARGIN
                spans.append((lo_f + lo_g, hi_f + hi_g, 1.0))
        else:
            spans.append((lo_f + aisle.half - FREE_SIDE, hi_f + aisle.half + FREE_SIDE, 0.5))
    if not spans:
        return max(MIN_WIDTH, 2 * aisle.half)
    grid = np.arange(MIN_WIDTH, 2 * (REACH + aisle.half) + GRID, GRID)
    score = np.zeros(len(grid))
    for lo, hi, weight in spans:
        score[(grid >= lo - 1e-9) & (grid <= hi + 1e-9)] += weight
    best = np.flatnonzero(score >= score.max() - 1e-9)
    # the middle of the longest run of best widths
    runs = np.split(best, np.flatnonzero(np.diff(best) > 1) + 1)
    run = max(runs, key=len)
    return float(grid[run[len(run) // 2]])


def fit(aisle: AisleLayout) -> dict[str, str]:
    """Choose the aisle's width and its centre line; the spots left out, with why."""
    width = _width(aisle)
    length = float(LineString(aisle.base).length)
    knots: dict[float, list[tuple[float, float, int]]] = {}  # station -> (lo, hi, facing)

    def at(s: float) -> list[tuple[float, float, int]]:
        s = float(np.clip(s, 0.0, length))
        for known in knots:
            if abs(known - s) < 0.05:
                return knots[known]
        return knots.setdefault(s, [])

    for k, f in enumerate(aisle.facing):
        for s, lo, hi in _bounds(f, width):
            at(s).append((lo, hi, k))
    cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(aisle.base, axis=0).T))])
    for s in cum:
        at(float(s))
    for s in np.arange(0.0, length, KNOT_GAP):
        at(float(s))
    stations = np.array(sorted(knots))
    grid = np.arange(-REACH, REACH + GRID / 2, GRID)
    offsets = _profile(aisle, stations, [knots[s] for s in stations], grid, width)
    reasons = {}
    kept = []
    for k, f in enumerate(aisle.facing):
        bad = [(s, lo, hi) for s, lo, hi in _bounds(f, width)
               if not lo - 1e-6 <= float(np.interp(s, stations, offsets)) <= hi + 1e-6]
        if bad:
            reasons[f.spot.id] = _why(f, width, float(np.interp(f.stations[1], stations,
                                                                 offsets)))
        else:
            kept.append(k)
    aisle.slots = [aisle.facing[k].spot for k in kept]
    aisle.width = width
    bands = []
    for s, o in zip(stations, offsets, strict=True):
        cons = [(lo, hi) for lo, hi, k in knots[s] if k in kept]
        lo = max([c[0] for c in cons], default=o - 0.2)
        hi = min([c[1] for c in cons], default=o + 0.2)
        bands.append((min(lo, o), max(hi, o)))
    breaks = _few_bends(stations, offsets, bands)
    aisle.line = _offset_line(aisle.base, breaks)
    return reasons


def _why(f: Facing, width: float, offset: float) -> str:
    edge = offset + width / 2 if f.side > 0 else width / 2 - offset
    ym = f.distances[1]
    if ym - edge > ENTRY_REACH - MARGIN:
        return (f"its entry lies {ym:.2f} m from the road's centre line, {ym - edge:.2f} m "
                f"beyond the edge of its {width:.2f} m aisle, which reaches more of its "
                f"neighbours' entries there")
    return (f"its entry lies {ym:.2f} m from the road's centre line, within the "
            f"{width:.2f} m aisle, which reaches more of its neighbours' entries there")


def _profile(aisle: AisleLayout, stations: FloatArray, cons: list, grid: FloatArray,
             width: float) -> FloatArray:
    """The offsets at ``stations`` that break the fewest demands of spots, change by at most
    :data:`SLOPE` a metre, and keep a side without spots near the carriageway's edge."""
    n, size = len(stations), len(grid)
    sides = {1: [], -1: []}
    for f in aisle.facing:
        sides[f.side].append((min(f.stations[0], f.stations[2]) - 3.0,
                              max(f.stations[0], f.stations[2]) + 3.0))
    h = width / 2
    cost = np.zeros((n, size))
    for i, s in enumerate(stations):
        for lo, hi, _ in cons[i]:
            cost[i] += (grid < lo - 1e-9) | (grid > hi + 1e-9)
        for side, spans in sides.items():
            if not any(a <= s <= b for a, b in spans):
                edge = grid + h if side > 0 else h - grid
                cost[i] += 0.3 * (np.abs(edge - aisle.half) > FREE_SIDE)
        cost[i] += 1e-3 * np.abs(grid)  # otherwise: on the road's line
    value = cost[0].copy()
    back = np.zeros((n, size), dtype=np.int64)
    step_cost = 0.02  # per metre of offset change: fewer bends
    idx = np.arange(size)
    for i in range(1, n):
        reach = min(int(SLOPE * (stations[i] - stations[i - 1]) / GRID), 200)
        best = value.copy()
        src = idx.copy()
        for d in range(1, reach + 1):
            pen = step_cost * d * GRID
            for cand, came in ((np.concatenate([np.full(d, np.inf), value[:-d] + pen]), idx - d),
                               (np.concatenate([value[d:] + pen, np.full(d, np.inf)]), idx + d)):
                better = cand < best - 1e-12
                best[better] = cand[better]
                src[better] = came[better]
        back[i] = src
        value = best + cost[i]
    j = int(np.argmin(value))
    out = np.empty(n)
    for i in range(n - 1, -1, -1):
        out[i] = grid[j]
        j = int(back[i][j]) if i else j
    return out


def _few_bends(stations: FloatArray, offsets: FloatArray,
               bands: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Breakpoints (station, offset) of a piecewise-linear offset that stays in every band
    and changes by at most :data:`SLOPE` a metre, with few pieces: each piece runs as far as
    a line from its start can stay in the bands."""
    out = [(float(stations[0]), float(offsets[0]))]
    i = 0
    n = len(stations)
    while i < n - 1:
        s0, o0 = out[-1]
        lo_t, hi_t = -SLOPE, SLOPE
        last = None
        for k in range(i + 1, n):
            ds = stations[k] - s0
            a, b = (bands[k][0] - o0) / ds, (bands[k][1] - o0) / ds
            if max(lo_t, a) > min(hi_t, b) + 1e-12:
                break
            lo_t, hi_t = max(lo_t, a), min(hi_t, b)
            last = (k, lo_t, hi_t)
        if last is None:  # not even the next knot: follow the chosen offsets
            k = i + 1
            out.append((float(stations[k]), float(offsets[k])))
            i = k
            continue
        k, lo_t, hi_t = last
        want = (offsets[k] - o0) / (stations[k] - s0)
        t = float(np.clip(want, lo_t, hi_t))
        out.append((float(stations[k]), o0 + t * float(stations[k] - s0)))
        i = k
    return out


def _offset_line(base: FloatArray, breaks: list[tuple[float, float]]) -> FloatArray:
    """The base line shifted left by the piecewise-linear offset ``breaks``: points at its
    breakpoints and at the base's corners (mitred)."""
    seg = np.hypot(*np.diff(base, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    bs = np.array([b[0] for b in breaks])
    bo = np.array([b[1] for b in breaks])
    normals = np.array([[-d[1], d[0]] for d in (np.diff(base, axis=0) / seg[:, None])])
    pts = []
    for s in sorted(set(bs.tolist()) | set(cum.tolist())):
        o = float(np.interp(s, bs, bo))
        k = int(np.searchsorted(cum, s, side="right") - 1)
        k = min(k, len(seg) - 1)
        if abs(s - cum[k]) < 1e-9 and k > 0:
            a, b = normals[k - 1], normals[k]
            n = (a + b) / (1 + float(np.dot(a, b)))
            p = base[k]
        elif abs(s - cum[-1]) < 1e-9:
            n, p = normals[-1], base[-1]
        else:
            n = normals[k]
            p = base[k] + (base[k + 1] - base[k]) * (s - cum[k]) / seg[k]
        pts.append(p + n * o)
    line = np.array(pts)
    keep = np.concatenate([[True], np.hypot(*np.diff(line, axis=0).T) > 1e-6])
    line = line[keep]
    return np.asarray(shapely.simplify(LineString(line), 0.005).coords)


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


def corner_needs(width: float, two_way: bool, design: DesignVehicle,
                 speed: float) -> Callable[[FloatArray], FloatArray]:
    """For a centre line, by how much each leg is too short for lotsim to round the corners at
    its ends on every lane [m] (positive: too short): lotsim rounds each lane's corners with
    continuous-curvature turns of the default bend radius, concentric about the centre
    line's (:func:`~lotsim.lot.build.bend_sharpness`)."""
    offset = width / 4 if two_way else 0.0
    radius = design.min_radius + offset
    sharp = bend_sharpness(radius, offset, design, speed)
    lanes = [offset] if not two_way else [offset, -offset]  # right of the line, and left

    def short(pts: FloatArray) -> FloatArray:
        legs = np.diff(pts, axis=0)
        heading = np.arctan2(legs[:, 1], legs[:, 0])
        turns = (np.diff(heading) + np.pi) % (2 * np.pi) - np.pi
        worst = np.full(len(legs), -np.inf)
        for right in lanes or [0.0]:
            lane = offset_polyline(pts, right)
            lengths = np.hypot(*np.diff(lane, axis=0).T)
            radii = radius + right * np.sign(turns)
            cut = np.array([cc_turn(float(t), 1 / float(r), sharp)[1] if abs(t) > 1e-12
                            else 0.0 for t, r in zip(turns, radii, strict=True)])
            need = np.concatenate([[0.0], cut]) + np.concatenate([cut, [0.0]])
            worst = np.maximum(worst, need - lengths)
        return worst
    return short


def drivable(line: FloatArray, short: Callable[[FloatArray], FloatArray]) -> FloatArray:
    """``line`` with its corners few enough and far enough apart for lotsim to round each
    (``short``: :func:`corner_needs`): two corners too close that turn the same way become
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
