"""The ring of a candidate (:mod:`lotsim.design.candidates`): the inside of its two-way
ring aisle, whose every edge is one straight aisle, and how module aisles meet it: where
they end on it, which of its sides faces the inside, and whether a module runs too close
beside one of its legs."""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon

from lotsim.design.drawn import EPS, MIN_JUNCTION_DEG, DrawnAisle, Point2

SIMPLIFY = 0.3
"""The ring's outline is simplified within this [m]: no leg of a few centimetres."""
MIN_LEG = 4.0
"""A ring with a leg shorter than this is simplified further [m]."""
BESIDE_DEG = 15.0
"""A module aisle runs beside a ring leg that makes less than this angle with it
[degrees]."""


def _rings(region: Polygon) -> list[np.ndarray]:
    """The closed outlines (exterior, then holes) of ``region``, counter-clockwise, without
    the repeated last point."""
    out = []
    for ring in [region.exterior, *region.interiors]:
        pts = np.asarray(ring.coords)[:-1]
        out.append(pts)
    return out


def _beside_ring(ax: float, bx: float, y: float, legs: list[tuple[Point2, Point2]],
                 room: float) -> bool:
    """Whether the module aisle along x from ``ax`` to ``bx`` at ``y`` runs beside a ring leg
    (within :data:`BESIDE_DEG` of its direction, alongside it for a metre or more) closer
    than ``room`` [m], measured at the middle of the stretch they run alongside: two aisles
    side by side with no room for a row of bays each between them."""
    lo, hi = min(ax, bx), max(ax, bx)
    for (px, py), (qx, qy) in legs:
        dx, dy = qx - px, qy - py
        if abs(dy) > math.sin(math.radians(BESIDE_DEG)) * math.hypot(dx, dy):
            continue
        a, b = max(lo, min(px, qx)), min(hi, max(px, qx))
        if b - a < 1.0:
            continue
        mid = (a + b) / 2
        if abs(py + (mid - px) * dy / dx - y) < room - EPS:
            return True
    return False


def _ring_region(outline: Polygon, islands: list[Polygon], d: float,
                 along: tuple[int, ...] = (), near: float = 0.0) -> Polygon | None:
    """The inside of the ring aisle: the outline shrunk by ``d`` (by ``near`` along the
    edges ``along``), less the islands grown by ``d``; its largest part, simplified so that
    no leg is very short."""
    if along:
        inner = outline.buffer(-near, join_style="mitre")
        pts = np.asarray(outline.exterior.coords)[:-1]
        turn = 1.0 if outline.exterior.is_ccw else -1.0
        for k in range(len(pts)):
            if k in along:
                continue
            a, b = pts[k], pts[(k + 1) % len(pts)]
            u = (b - a) / np.hypot(*(b - a))
            n = turn * np.array([-u[1], u[0]])  # inward
            inner = inner.difference(Polygon([a - u * d, b + u * d, b + u * d + n * d,
                                              a - u * d + n * d]))
    else:
        inner = outline.buffer(-d, join_style="mitre")
    for isl in islands:
        inner = inner.difference(isl.buffer(d, join_style="mitre"))
    if inner.is_empty:
        return None
    if inner.geom_type != "Polygon":
        parts = [g for g in getattr(inner, "geoms", []) if g.geom_type == "Polygon"]
        if not parts:
            return None
        inner = max(parts, key=lambda g: (g.area, g.bounds))
    tol = SIMPLIFY
    for _ in range(6):
        simple = inner.simplify(tol, preserve_topology=True)
        if simple.is_valid and not simple.is_empty and simple.geom_type == "Polygon":
            legs = [np.hypot(*np.diff(r, axis=0, append=r[:1]).T) for r in _rings(simple)]
            if min(float(x.min()) for x in legs) >= MIN_LEG:
                return shapely.geometry.polygon.orient(simple)
        tol *= 2
    return None


def _meets_ring(p: Point2, ring_lines: list[LineString]) -> float | None:
    """The angle [rad] at which a line along x through ``p`` meets the ring leg ``p`` lies
    on, where it is at least :data:`MIN_JUNCTION_DEG`; else None."""
    pt = Point(p)
    for line in ring_lines:
        if line.distance(pt) < 1e-6:
            (ax, ay), (bx, by) = line.coords
            ang = abs(math.degrees(math.atan2(by - ay, bx - ax))) % 180
            ang = min(ang, 180 - ang)
            if ang >= MIN_JUNCTION_DEG:
                return math.radians(ang)
    return None


def _side_is_inner(a: DrawnAisle, side: str, inside: Polygon) -> bool:
    """Whether ``side`` of ring aisle ``a`` faces the inside of the ring."""
    mx, my = (a.start[0] + a.end[0]) / 2, (a.start[1] + a.end[1]) / 2
    ux, uy = a.end[0] - a.start[0], a.end[1] - a.start[1]
    n = math.hypot(ux, uy)
    lx, ly = -uy / n, ux / n
    s = 1.0 if side == "left" else -1.0
    return inside.contains(Point(mx + s * lx * 0.5, my + s * ly * 0.5))
