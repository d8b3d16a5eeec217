"""The plot of an OpenStreetMap lot that maps no aisles (``lotsim import osm --layout``): its
outline, the islands to keep clear (inner rings, mapped buildings, barriers and green areas)
and its gates, where a road meets it, as a plot file for ``lotsim layout``.

A gate is where a road cars drive (:data:`~lotsim.io.imports.osm_gates.CAR_ROADS`) crosses
the lot's edge, or where a road ends within :data:`~lotsim.io.imports.osm_gates.GATE_ROAD`
of it outside the lot (the gate then stands at the nearest point of the edge); gates closer
than :data:`GATE_APART` to one found before are one. A gate is named by the compass point
of the edge it is on, seen from the lot's centre (``south``, ``north-east``). A lot no road
reaches gets an assumed gate in the middle of its longest edge, and says so.
"""

from __future__ import annotations

import textwrap

from shapely.geometry import Point, Polygon
from shapely.ops import nearest_points

from lotsim.io.imports.draft import AreaDraft, PlotDraft
from lotsim.io.imports.osm_gates import GATE_ROAD, _side
from lotsim.io.imports.osm_near import NearLot, polygons_of, ring_points

GATE_APART = 15.0
"""Gates closer than this along the edge are one [m]."""
MOST_GATES = 4
"""A plot gets at most this many gates (the first found, by road id)."""
ISLAND_INSET = 0.1
"""Islands are shrunk by this much, so that each lies strictly inside the lot [m]."""
DEMAND = {"count": 20, "rate_per_hour": 60, "dwell": [300, 900]}
"""The plot's demand: the importer's default traffic (20 cars, 60 an hour, staying 5 to 15
minutes)."""


def plot_of(name: str, description: str, lot: Polygon, near: NearLot, own: int | None,
            header: list[str]) -> PlotDraft:
    """The plot of a lot with no aisle (the module's description)."""
    boundary = ring_points(lot.exterior)
    outline = Polygon(boundary)
    islands: list[AreaDraft] = []
    shapes = [(f"island{i + 1}", Polygon(r), f"inner ring {i + 1} of the lot")
              for i, r in enumerate(lot.interiors)]
    obstacles, no_go = near.areas(lot, [], own)
    shapes += [(a.id, Polygon(a.polygon), a.note) for a in obstacles + no_go]
    for ident, poly, note in shapes:
        parts = polygons_of(poly.intersection(outline).buffer(-ISLAND_INSET,
                                                                join_style="mitre"))
        for j, part in enumerate(p for p in parts if p.area >= 0.5):
            pts = ring_points(part.exterior)
            if len(pts) >= 3 and Polygon(pts).is_valid and outline.contains(Polygon(pts)):
                islands.append(AreaDraft(ident + (f"-{j + 1}" if len(parts) > 1 else ""),
                                         pts, note=note))
    gates = bare_gates(outline, near)
    lines = []
    for line in header:
        lines += textwrap.wrap(line, 96, break_long_words=False, break_on_hyphens=False) or [""]
    return PlotDraft(name=name, description=description, boundary=boundary, gates=gates,
                     islands=islands, header=lines, demand=dict(DEMAND))


def bare_gates(outline: Polygon, near: NearLot) -> list[tuple[str, tuple[float, float], str]]:
    """Where roads meet the lot's edge: (id, point, where it came from), at most
    :data:`MOST_GATES`; an assumed one where no road does."""
    edge = outline.exterior
    found: list[tuple[str, tuple[float, float], str]] = []

    def add(p: Point, note: str) -> None:
        at = edge.interpolate(edge.project(p))
        if len(found) < MOST_GATES and all(at.distance(Point(q)) >= GATE_APART
                                           for _, q, _ in found):
            xy = (round(at.x, 2), round(at.y, 2))
            name = _side(xy, outline)  # the compass point of the lot's edge it is on
            taken = sum(g.split("-")[0] == name.split("-")[0] and g.startswith(name)
                        for g, _, _ in found)
            found.append((name + (f"-{taken + 1}" if taken else ""), xy, note))

    for rid, line in sorted(near.road_lines().items()):
        name = near.road_name(rid)
        crossing = line.intersection(edge)
        for p in sorted(getattr(crossing, "geoms", [crossing]), key=lambda g: g.coords[0]
                        if not g.is_empty else (0, 0)):
            if p.is_empty:
                continue
            point = p if p.geom_type == "Point" else Point(p.coords[0])
            add(point, f"where {name} crosses the lot's edge")
        for end in (Point(line.coords[0]), Point(line.coords[-1])):
            if not outline.contains(end) and end.distance(edge) <= GATE_ROAD:
                add(nearest_points(edge, end)[0],
                    f"where {name} ends {end.distance(edge):.1f} m from the lot's edge")
    if not found:
        pts = list(edge.coords)
        a, b = max(zip(pts[:-1], pts[1:], strict=True),
                   key=lambda ab: Point(ab[0]).distance(Point(ab[1])))
        mid = Point((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        add(mid, "assumed: no road reaches the lot; move it where cars come in")
    return found
