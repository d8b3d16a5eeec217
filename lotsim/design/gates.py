"""The gates of a candidate (:mod:`lotsim.design.candidates`): each gate's straight aisle
in from the boundary, or its opening straight onto a ring leg beside its edge; its entrance
and exit on that aisle; and its mouth, the stretch of boundary where the aisle meets it,
with the zone round it that no bay's centre may lie in."""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from lotsim.design.drawn import CLEAR, EPS, MIN_JUNCTION_DEG, DrawnAisle, DrawnGate
from lotsim.design.plot import PlotSpec

GATE_INSET = 0.02
"""A gate's aisle begins this far inside the boundary [m]: written to the centimetre, its
first point stays inside."""
GATE_MIN = 7.0
"""A gate aisle is at least this long [m]: room for its entrance and exit."""
GATE_MAX = 80.0
"""A gate aisle meets another aisle within this distance of its gate [m]."""


def _gate(plot: PlotSpec, gid: str, at: np.ndarray, outline: Polygon,
          lines: list[tuple[LineString, DrawnAisle]]) -> tuple[DrawnAisle, DrawnGate] | None:
    """The aisle from a gate square to its boundary edge into the lot, to the first aisle
    it meets, with the gate's entrance and exit on it; None when it meets none in reach."""
    start, n = _inward(outline, at, plot.circulation_width)
    ray = LineString([start, start + n * GATE_MAX])
    best = None
    for line, _ in lines:
        hit = ray.intersection(line)
        if hit.is_empty or hit.geom_type != "Point":
            continue
        t = float(np.dot(np.asarray(hit.coords[0]) - start, n))
        (ax, ay), (bx, by) = line.coords
        ang = abs(math.degrees(math.atan2(by - ay, bx - ax) - math.atan2(n[1], n[0]))) % 180
        if min(ang, 180 - ang) < MIN_JUNCTION_DEG:
            continue
        if t >= GATE_MIN and (best is None or t < best[0]):
            best = (t, np.asarray(hit.coords[0]))
    if best is None:
        return None
    end = best[1]
    if not outline.buffer(1e-6).covers(LineString([start, end])):
        return None
    aisle = DrawnAisle(f"gate-{gid}", tuple(start), tuple(end), plot.circulation_width, False,
                       "gate")
    return aisle, _gate_poses(plot, gid, aisle.id, start, n)


def gate_edges(plot: PlotSpec) -> tuple[int, ...]:
    """The boundary's edges a ring may run beside so that the gates open straight onto it:
    each gate's edge, and the edge beyond the nearer corner of a gate closer to it than a
    perimeter row and half the ring (its aisle would meet the ring at that corner)."""
    outline = Polygon(plot.boundary)
    pts = np.asarray(plot.boundary, dtype=float)
    reach = plot.bay_length + plot.circulation_width / 2 + CLEAR
    out: set[int] = set()
    for g in plot.gates:
        k = edge_of(outline, g.at)
        a, b = pts[k], pts[(k + 1) % len(pts)]
        s = float(np.dot(np.asarray(g.at) - a, (b - a) / np.hypot(*(b - a))))
        out.add(k)
        if s < reach:
            out.add((k - 1) % len(pts))
        if np.hypot(*(b - a)) - s < reach:
            out.add((k + 1) % len(pts))
    return tuple(sorted(out))


def edge_of(outline: Polygon, at) -> int:
    """The index of the boundary's edge nearest the point ``at`` (edge ``k`` runs from
    point ``k`` to the next)."""
    ring = np.asarray(outline.exterior.coords)
    g = Point(at)
    return int(np.argmin([LineString(ring[i:i + 2]).distance(g) for i in range(len(ring) - 1)]))


def _gate_on_ring(plot: PlotSpec, gid: str, at: np.ndarray, aisles: list[DrawnAisle]
                  ) -> DrawnGate | None:
    """A gate that opens straight onto the ring leg running beside its edge: its entrance
    on the leg's lane nearer the boundary, heading the way that lane runs, and its exit on
    the other lane, heading the other way, both abeam of the gate (moved along the leg, at
    most half its width and :data:`CLEAR`, where the gate lies beyond the leg's end); None
    where no leg runs beside it."""
    w = plot.circulation_width
    g = np.asarray(at, dtype=float)
    for a in aisles:
        if a.role != "ring":
            continue
        p0, p1 = np.asarray(a.start, dtype=float), np.asarray(a.end, dtype=float)
        length = float(np.hypot(*(p1 - p0)))
        u = (p1 - p0) / length
        s = float(np.dot(g - p0, u))
        off = float(u[0] * (g - p0)[1] - u[1] * (g - p0)[0])  # > 0: the gate is left of it
        if abs(abs(off) - (w / 2 + CLEAR)) > 0.5 or not -(w / 2 + CLEAR) - EPS <= s <= \
                length + w / 2 + CLEAR + EPS:
            continue
        s = min(max(s, 0.0), length)
        heading = math.atan2(u[1], u[0])
        if off > 0:  # the lane nearer the gate runs against the leg
            heading += math.pi
        side = math.copysign(w / 4, off)
        left = np.array([-u[1], u[0]])
        inward = p0 + u * s + left * side
        outward = p0 + u * s - left * side
        edge = p0 + u * s + left * math.copysign(w / 2 + CLEAR, off)
        mouth = (tuple(map(float, edge - u * w / 2)), tuple(map(float, edge + u * w / 2)))
        return DrawnGate(gid, a.id, (*map(float, inward), heading),
                         (*map(float, outward), heading + math.pi), mouth)
    return None


def _inward(outline: Polygon, at: np.ndarray, width: float) -> tuple[np.ndarray, np.ndarray]:
    """Where a gate's aisle of ``width`` [m] begins: :data:`GATE_INSET` inside the boundary
    from the point of it nearest ``at``, moved along that edge, where the gate lies near one
    of its ends, until the aisle's mouth lies on the edge with :data:`CLEAR` to spare (at
    most half the width and that: the mouth still takes the gate in); and the unit square
    to the edge, inward."""
    ring = np.asarray(outline.exterior.coords)
    g = Point(at)
    k = int(np.argmin([LineString(ring[i:i + 2]).distance(g) for i in range(len(ring) - 1)]))
    e = ring[k + 1] - ring[k]
    span = float(np.hypot(*e))
    e = e / span
    n = np.array([-e[1], e[0]])  # left of a counter-clockwise edge is inward
    if not outline.exterior.is_ccw:
        n = -n
    s = float(np.dot(np.asarray(at, dtype=float) - ring[k], e))
    room = width / 2 + CLEAR
    s = min(max(s, room), span - room) if span >= 2 * room else span / 2
    start = ring[k] + e * s
    return start + n * GATE_INSET, n


def _gate_poses(plot: PlotSpec, gid: str, aisle: str, start: np.ndarray, n: np.ndarray
                ) -> DrawnGate:
    """A gate's entrance and exit near the boundary, on the inward and outward lanes of its
    aisle, which runs from ``start`` along ``n``."""
    width = plot.circulation_width
    heading = math.atan2(n[1], n[0])
    right = np.array([n[1], -n[0]])
    longest = max(v.front for v in plot.vehicle_types)
    rear = max(v.rear for v in plot.vehicle_types)
    inward = start + n * (rear + 0.5) + right * width / 4
    outward = start + n * (longest + 0.5) - right * width / 4
    edge = start - n * GATE_INSET
    mouth = (tuple(map(float, edge - right * width / 2)),
             tuple(map(float, edge + right * width / 2)))
    return DrawnGate(gid, aisle, (*map(float, inward), heading),
                     (*map(float, outward), heading + math.pi), mouth)


def _mouths(plot: PlotSpec, gates: list[DrawnGate]):
    """Where no bay's centre may lie: within :attr:`PlotSpec.gate_clearance` of a gate's
    mouth (None: nowhere)."""
    if plot.gate_clearance <= 0:
        return None
    zones = [LineString(g.mouth).buffer(plot.gate_clearance) for g in gates
             if g.mouth is not None]
    if not zones:
        return None
    zone = unary_union(zones)
    shapely.prepare(zone)
    return zone
