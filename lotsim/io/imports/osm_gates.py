"""Gates of an OpenStreetMap lot: where cars come in and leave.

A gate is an aisle end at the lot's edge that a road reaches (:data:`CAR_ROADS`): the aisle
way goes on outside the lot to a node of a road, or its end node is a road's, or it ends
within :data:`GATE_EDGE` of the lot's edge with a road passing or ending within
:data:`GATE_ROAD` of it outside the lot. An aisle that stops short of the edge is
lengthened to 0.5 m past it. The entrance stands on the aisle's inward lane and the exit on
its outward lane, :data:`GATE_DEPTH` in from the end, each heading its lane's way (a quarter
of the width right of the centre line; on a one-way aisle on the centre line, only the
entrance where it runs inward, only the exit where it runs outward).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from shapely.geometry import LineString, Point, Polygon

from lotsim.io.imports.osm_aisles import Vertex, is_aisle
from lotsim.io.imports.osm_chains import Chain, end_counts

GATE_EDGE = 4.0
"""A gate's aisle end lies within this distance of the lot's edge [m]."""
GATE_ROAD = 5.0
"""A road passing or ending within this distance of an aisle end makes it a gate [m]."""
GATE_DEPTH = 5.0
"""Entrances and exits stand this far in from the aisle's end [m]: a car (the valet car is
4.9 m long) standing there is wholly inside the lot."""
CAR_ROADS = frozenset({
    "motorway", "trunk", "primary", "secondary", "tertiary", "motorway_link", "trunk_link",
    "primary_link", "secondary_link", "tertiary_link", "unclassified", "residential",
    "living_street", "service", "road", "track"})
"""``highway`` values of the roads cars come from (footways, cycleways, paths and steps
are not)."""


def is_road(tags: dict[str, str]) -> bool:
    """A road cars drive on, other than a parking aisle."""
    return tags.get("highway") in CAR_ROADS and not is_aisle(tags)


@dataclass
class Gate:
    """An aisle end where cars come in or leave: ``end`` 0 (the aisle's first point) or -1;
    ``road`` the road way that reaches it (None for an assumed gate)."""

    chain: Chain
    end: int
    road: int | None
    entrance: tuple[float, float, float] | None
    exit: tuple[float, float, float] | None
    note: str


def find_gates(chains: list[Chain], vertices: dict[int, Vertex], lot: Polygon,
               road_lines: dict[int, LineString], road_name: Callable[[int], str]
               ) -> list[Gate]:
    """The aisle ends a road reaches at the lot's edge, extended to the edge when they stop
    short of it, each with its entrance and exit."""
    shared = end_counts(chains)
    edge = lot.exterior
    beyond = {rid: line.difference(lot) for rid, line in road_lines.items()
              if line.distance(edge) <= GATE_EDGE + GATE_ROAD}
    gates = []
    for c in chains:
        for end in (0, -1):
            k = c.keys[end]
            if not c.free(end, shared):
                continue
            p = Point(c.pts[end])
            inside = lot.contains(p)
            near_edge = not inside or edge.distance(p) <= GATE_EDGE
            if not near_edge:
                continue
            roads = sorted(vertices[k].roads) if k in vertices else []
            how = "shares its node with" if roads and not vertices[k].cut else \
                "goes on outside the lot to" if roads else ""
            if not roads:
                outside = [(line.distance(p), rid) for rid, line in beyond.items()
                           if not line.is_empty]
                outside = [(d, rid) for d, rid in outside if d <= GATE_ROAD]
                if outside:
                    roads = [min(outside)[1]]
                    how = f"ends {min(outside)[0]:.1f} m from"
            if not roads:
                continue
            if inside:
                _extend_to_edge(c, end, lot)
            road = roads[0]
            ways = sorted(vertices[k].ways & set(c.ways)) or c.ways
            gates.append(_gate(c, end, road, f"gate {len(gates) + 1}, at the lot's "
                               f"{_side(c.pts[end], lot)} edge: the "
                               f"{'first' if end == 0 else 'last'} end of aisle {c.id} (way "
                               f"{_way_list(ways)}) {how} {road_name(road)}"))
    return gates


def assumed_gate(chains: list[Chain], lot: Polygon) -> list[Gate]:
    """For a lot no road reaches: an entrance (and exit) at the free aisle end nearest the
    lot's edge, so that the scenario runs; the user should move it where cars come in."""
    shared = end_counts(chains)
    ends = sorted((round(lot.exterior.distance(Point(c.pts[end])), 3), i, -end, end)
                  for i, c in enumerate(chains) for end in (0, -1)
                  if c.free(end, shared) and not (c.one_way and end == -1))
    if not ends:  # every end joins another aisle: a ring
        c = chains[0]
        return [_gate(c, 0, None, f"assumed gate on aisle {c.id}: no road reaches the lot; "
                      "move it where cars come in")]
    _, i, _, end = ends[0]
    c = chains[i]
    return [_gate(c, end, None, f"assumed gate at the {'first' if end == 0 else 'last'} end "
                  f"of aisle {c.id}, the aisle end nearest the lot's edge ("
                  f"{_side(c.pts[end], lot)}): move it where cars come in")]


def _side(p: tuple[float, float], lot: Polygon) -> str:
    """Which side of the lot a point is on, as a compass point seen from its centroid.

    >>> from shapely.geometry import box
    >>> _side((0, 9), box(-5, -5, 5, 5)), _side((7, -6), box(-5, -5, 5, 5))
    ('north', 'south-east')
    """
    c = lot.centroid
    angle = math.degrees(math.atan2(p[1] - c.y, p[0] - c.x)) % 360
    names = ("east", "north-east", "north", "north-west", "west", "south-west", "south",
             "south-east")
    return names[int((angle + 22.5) // 45) % 8]


def _way_list(ways: list[int]) -> str:
    return ", ".join(str(w) for w in ways)


def _extend_to_edge(c: Chain, end: int, lot: Polygon) -> None:
    """Lengthen the aisle's last leg to 0.5 m past the lot's edge."""
    p = np.asarray(c.pts[end])
    prev = np.asarray(c.pts[1 if end == 0 else -2])
    d = (p - prev) / np.hypot(*(p - prev))
    ray = LineString([p, p + d * (GATE_EDGE + 1.0)])
    hit = ray.intersection(lot.exterior)
    if hit.is_empty:
        return
    t = min(Point(p).distance(g) for g in getattr(hit, "geoms", [hit]))
    new = p + d * (t + 0.5)
    c.pts[end] = (float(new[0]), float(new[1]))


def _gate(c: Chain, end: int, road: int | None, note: str) -> Gate:
    path = np.asarray(c.pts if end == 0 else c.pts[::-1], dtype=float)
    line = LineString(path)
    s = GATE_DEPTH if line.length >= GATE_DEPTH + 1.0 else line.length / 2
    p = line.interpolate(s)
    a = line.interpolate(max(0.0, s - 0.05))
    b = line.interpolate(min(line.length, s + 0.05))
    u = np.array([b.x - a.x, b.y - a.y])
    u = u / np.hypot(*u)
    left = np.array([-u[1], u[0]])
    heading = math.atan2(u[1], u[0])
    at = np.array([p.x, p.y])
    inward = end == 0  # the aisle's own direction runs inward from its first point
    if c.one_way:
        entrance = (*at, heading) if inward else None
        exit_ = (*at, heading + math.pi) if not inward else None
    else:
        off = c.width / 4
        entrance = (*(at - left * off), heading)
        exit_ = (*(at + left * off), heading + math.pi)
    return Gate(c, end, road, _pose(entrance), _pose(exit_), note)


def _pose(p) -> tuple[float, float, float] | None:
    if p is None:
        return None
    return float(p[0]), float(p[1]), float(math.atan2(math.sin(p[2]), math.cos(p[2])))
