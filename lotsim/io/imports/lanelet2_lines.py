"""Centre lines of the imported aisles as lotsim builds them: how it rounds their corners
(:class:`Bends`: the lanes, the clothoids' sharpness, the ground a car sweeps), corners it
could not round merged (:func:`drivable`), ends put on another aisle's centre line
(:func:`end_on`) or carried on to the lot's edge (:func:`extend_to`), and kept inside the
lot's boundary as written (:func:`inside_part`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon

from lotsim.core.corners import corner_sharpness
from lotsim.core.geometry import FloatArray, cc_polyline, cc_turn, sample_segments
from lotsim.lot.build import bend_sharpness, offset_polyline
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle
from lotsim.lot.settings import DEFAULTS as LOT_DEFAULTS


def normalised(v: FloatArray) -> FloatArray:
    return v / float(np.hypot(*v))


def turn_angles(line: FloatArray) -> FloatArray:
    d = np.diff(line, axis=0)
    h = np.arctan2(d[:, 1], d[:, 0])
    return (np.diff(h) + np.pi) % (2 * np.pi) - np.pi


def end_on(line: FloatArray, end: int, host: FloatArray) -> FloatArray:
    """``line`` with its end ``end`` (0 first, 1 last) on the centre line ``host``: its end
    leg carried on or cut back to where it crosses it, else a leg to its nearest point."""
    pts = line if end == 1 else line[::-1]
    target = LineString(host)
    base, tip = pts[-2], pts[-1]
    d = normalised(tip - base)
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
    d = normalised(tip - base)
    ray = LineString([tip, tip + d * 50.0])
    # every point where the ray meets the outline, also where it runs along an edge
    cands = list(shapely.get_coordinates(ray.intersection(boundary.exterior)))
    if cands:
        q = min(cands, key=lambda q: float(np.hypot(*(q - tip))))
        far = q - d * inset
        if float(np.dot(far - tip, d)) > 0:
            pts = np.vstack([pts[:-1], far])
    return pts if end == 1 else pts[::-1]


def as_written(points) -> FloatArray:
    """``points`` [m] as a scenario writes them: to the centimetre."""
    return np.array([(round(float(x), 2), round(float(y), 2)) for x, y in points])


def inside_part(line: FloatArray, area: Polygon, inset: float,
                least: float) -> FloatArray | None:
    """``line`` as lotsim will read it, inside ``area`` (a polygon to the centimetre, as
    written): the line itself when it lies inside as written, else its longest piece
    ``inset`` metres or more inside ``area`` (further in until the piece, written, lies
    inside); None when no piece of ``least`` metres [m] does."""
    cover = area.buffer(1e-6)
    if cover.covers(LineString(as_written(line))):
        return line
    for k in range(8):
        part = LineString(line).intersection(area.buffer(-inset * 2 ** k, join_style="mitre"))
        pieces = [g for g in shapely.get_parts(part)
                  if g.geom_type == "LineString" and g.length >= least]
        if not pieces:
            return None
        piece = np.asarray(max(pieces, key=lambda g: g.length).coords)
        if cover.covers(LineString(as_written(piece))):
            return piece
    return None


@dataclass(frozen=True)
class Bends:
    """How lotsim rounds an aisle's corners (:func:`~lotsim.lot.build.build_lot`): the
    default bend radius on the centre line, concentric on the lanes a quarter of the width
    either side (one lane on the line when one-way), clothoids of cruising speed, sharper
    down to a crawl where legs are short; with the lot's default settings
    (:data:`lotsim.lot.settings.DEFAULTS`: the lot written has no ``lot.build``)."""

    width: float
    two_way: bool
    design: DesignVehicle
    speed: float  # the lot's speed limit [m/s]

    def paths(self, line: FloatArray) -> list[tuple[FloatArray, FloatArray, bool]]:
        """The centre line and each lane: (points, each corner's radius, reversed)."""
        offset = self.width / 4 if self.two_way else 0.0
        radius = self.design.min_radius + offset
        turns = turn_angles(line)
        out = [(line, np.full(len(turns), radius), False)]
        for pts, rev in ([(line, False), (line[::-1], True)] if self.two_way
                         else [(line, False)]):
            t = turn_angles(pts)
            out.append((offset_polyline(pts, offset) if offset else pts,
                        radius + offset * np.sign(t), rev))
        return out

    @property
    def sharpness(self) -> tuple[float, float]:
        """The clothoids' sharpness at cruising speed and at a crawl [1/m²]."""
        offset = self.width / 4 if self.two_way else 0.0
        radius = self.design.min_radius + offset
        return (bend_sharpness(radius, offset, self.design, self.speed),
                self.design.sharpness(LOT_DEFAULTS.crawl_speed))

    def short(self, line: FloatArray) -> FloatArray:
        """By how much each leg is too short for the corners at its ends [m] (positive:
        lotsim refuses it), on the centre line or a lane, at a crawl."""
        _, sharpest = self.sharpness
        worst = np.full(len(line) - 1, -np.inf)
        for pts, radii, rev in self.paths(line):
            cut = np.array([cc_turn(float(t), 1 / float(r), sharpest)[1] if abs(t) > 1e-12
                            else 0.0 for t, r in zip(turn_angles(pts), radii, strict=True)])
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
            poses, _ = sample_segments(segs, LOT_DEFAULTS.sweep)
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
            turns = turn_angles(pts)
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
            p = crossing(pts[i - 1], pts[i], pts[i + 1], pts[i + 2])
            length = float(np.hypot(*legs[i]))
            if float(np.hypot(*(p - (pts[i] + pts[i + 1]) / 2))) < 3 * length + 2.0:
                pts = np.vstack([pts[:i], p, pts[i + 2:]])
                continue
        v = min(inner, key=lambda v: abs(turns[v - 1]))
        pts = np.delete(pts, v, axis=0)
    return pts


def crossing(a0: FloatArray, a1: FloatArray, b0: FloatArray, b1: FloatArray) -> FloatArray:
    """Where the line through a0, a1 meets the line through b0, b1."""
    da, db = a1 - a0, b1 - b0
    den = da[0] * db[1] - da[1] * db[0]
    if abs(den) < 1e-12:
        return (a1 + b0) / 2
    t = ((b0 - a0)[0] * db[1] - (b0 - a0)[1] * db[0]) / den
    return a0 + t * da
