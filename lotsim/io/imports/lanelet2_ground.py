"""The ground of an imported Lanelet2 lot: its boundary, what is paved and what blocks.

The boundary is a simple polygon holding everything the map draws (lanelets, access areas,
spots) and the aisles laid on it, grown by :data:`BOUNDARY_GROW`. The pavement is the
map's drawn ground, written as simple polygons (:func:`drawn_areas`), the aisles' strips,
the outside of each L where two aisles of one road meet (:func:`corner_areas`) and the
inside of bends that a car on a lane cuts (:func:`swept_areas`). Walls, columns and kerbs
that cross the ground driven on become thin obstacles (:func:`blocking`).
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon
from shapely.ops import split

from lotsim.io.imports.draft import AreaDraft
from lotsim.io.imports.lanelet2_layout import AisleLayout
from lotsim.io.imports.lanelet2_lines import Bends
from lotsim.io.imports.lanelet2_map import Lanelet2Map

BOUNDARY_GROW = 0.5
"""The boundary is the drawn ground grown by this [m]."""
BOUNDARY_CLOSE = 0.5
"""The grown outline is closed by this [m] (grown by it, then shrunk by it): a slit or notch
narrower than twice this, which no car could use, is filled; elsewhere the outline keeps
its place."""


def boundary_of(drawn) -> Polygon:
    """A simple polygon holding everything drawn: its outline grown by
    :data:`BOUNDARY_GROW` and closed by :data:`BOUNDARY_CLOSE`, holes filled.

    Without the close, ground drawn a little more than twice the growth apart (the sweeps
    of a two-way aisle's lanes past its end, 1 m apart) leaves a slit of a few centimetres
    in the outline, and an aisle carried on to the edge can end inside it."""
    grown = drawn.buffer(BOUNDARY_GROW + BOUNDARY_CLOSE, join_style="mitre",
                         mitre_limit=2.0).buffer(-BOUNDARY_CLOSE, join_style="mitre",
                                                 mitre_limit=2.0)
    parts = getattr(grown, "geoms", [grown])
    outer = max(parts, key=lambda p: p.area)
    shell = Polygon(outer.exterior)
    simple = shapely.simplify(shell, 0.1)
    if not simple.covers(drawn.buffer(BOUNDARY_GROW / 2)):
        simple = shell
    return simple


def ring(poly: Polygon) -> list[tuple[float, float]]:
    return [(float(x), float(y)) for x, y in np.asarray(poly.exterior.coords)[:-1]]


def simple_rings(poly: Polygon) -> list[list[tuple[float, float]]]:
    """``poly`` as rings to the centimetre, each a simple polygon (a ring that rounding makes
    cross itself is split where it does)."""
    ring = [(round(float(x), 2), round(float(y), 2)) for x, y in poly.exterior.coords[:-1]]
    ring = [p for k, p in enumerate(ring) if p != ring[k - 1]]
    rounded = Polygon(ring)
    if len(ring) >= 3 and rounded.is_valid and rounded.area > 0.01:
        return [ring]
    fixed = shapely.make_valid(rounded) if len(ring) >= 3 else Polygon()
    out = []
    for piece in shapely.get_parts(fixed):
        if piece.geom_type == "Polygon" and piece.area > 0.01:
            out.extend(simple_rings(Polygon(piece.exterior)))
    return out


def drawn_areas(drawn) -> list[AreaDraft]:
    """The drawn ground as simple polygons: each part cut across its holes, written to the
    centimetre."""
    healed = drawn.buffer(0.01, join_style="mitre").buffer(-0.01, join_style="mitre")
    parts = [p for p in shapely.get_parts(healed) if p.area > 0.01]
    out = []
    while parts:
        part = parts.pop()
        if part.interiors:
            x = Polygon(part.interiors[0]).centroid.x
            lo, hi = part.bounds[1] - 1, part.bounds[3] + 1
            parts.extend(p for p in split(part, LineString([(x, lo), (x, hi)])).geoms
                         if p.area > 0.01)
            continue
        out.extend(simple_rings(shapely.simplify(part, 0.005)))
    out.sort(key=lambda r: (round(Polygon(r).centroid.x, 2), round(Polygon(r).centroid.y, 2)))
    return [AreaDraft(f"drawn-{k + 1}", ring,
                      "lanelets, parking_access areas and spots of the map")
            for k, ring in enumerate(out)]


def corner_areas(aisles: list[AisleLayout], ids: list[str]) -> list[AreaDraft]:
    """The outside of each L where two pieces of a road meet, paved as the corner of a road
    is: the hull of their strips near the corner."""
    out = []
    for k in range(1, len(aisles)):
        a, b = aisles[k - 1], aisles[k]
        if b.ends[0][0] != "corner":
            continue
        p = shapely.Point(np.round(b.line[0], 2))
        near = p.buffer(max(a.width, b.width), quad_segs=4)
        strips = [LineString(np.round(x.line, 2)).buffer(x.width / 2, cap_style="flat",
                                                         join_style="round") for x in (a, b)]
        hull = shapely.union_all(strips).intersection(near).convex_hull
        extra = hull.difference(shapely.union_all(strips))
        for piece in shapely.get_parts(extra):
            if piece.area > 0.01:
                for ring in simple_rings(piece.buffer(0.02, join_style="mitre")):
                    out.append(AreaDraft(f"corner-{ids[k - 1]}-{ids[k]}", ring,
                                         f"the outside of the corner where {ids[k - 1]} "
                                         f"meets {ids[k]}"))
    return out


def swept_areas(aisles: list[AisleLayout], ids: list[str], bends: list[Bends],
                paved) -> list[AreaDraft]:
    """Ground a car driving round an aisle's bends covers beyond the aisle's strip and the
    map's drawn ground ``paved`` (the inside of a bend, which a car cuts): paved too. (At
    an aisle's ends lotsim cuts its lanes back where a car would leave the ground.)"""
    out = []
    for aisle, aid, bend in zip(aisles, ids, bends, strict=True):
        line = np.round(aisle.line, 2)
        if len(line) < 3:
            continue
        strip = LineString(line).buffer(aisle.width / 2, cap_style="flat",
                                        join_style="round")
        corners = shapely.multipoints(line[1:-1]).buffer(aisle.width + BEND_REACH)
        extra = bend.sweep(line).buffer(0.05, join_style="mitre").difference(
            shapely.union_all([strip, paved])).intersection(corners)
        pieces = [p for p in shapely.get_parts(extra) if p.area > 0.01]
        pieces.sort(key=lambda p: (round(p.centroid.x, 2), round(p.centroid.y, 2)))
        for piece in pieces:
            grown = shapely.simplify(piece.buffer(0.02, join_style="mitre"), 0.01)
            for ring in simple_rings(grown):
                out.append(AreaDraft(f"swept-{aid}-{len(out) + 1}", ring,
                                     f"where a car on a lane of aisle {aid} cuts a bend"))
    return out


BEND_REACH = 10.0
"""How far beyond its width from a corner a car rounding it may leave an aisle's strip
[m]."""
BLOCKING = ("Walls", "Columns", "Kerbs")
"""The map's line features that block a car where they cross its drawn ground."""


def blocking(m: Lanelet2Map, ground, spots) -> tuple[list[AreaDraft], str]:
    """Walls, columns and kerbs that cross the ground driven on (lanelets and access areas,
    clear of the spots: a row's kerb runs along its spots' backs), as thin obstacles; a
    line saying what of the map's lines is left out."""
    out = []
    left = 0
    inner = ground.buffer(-0.05).difference(spots.buffer(0.1))
    for ln in m.lines:
        if ln.subtype not in BLOCKING:
            continue
        inside = LineString(ln.points).intersection(inner)
        if inside.is_empty or inside.length < 0.2:
            left += 1
            continue
        shape = inside.buffer(0.05, cap_style="flat", join_style="mitre")
        for piece in getattr(shape, "geoms", [shape]):
            out.append(AreaDraft(f"{ln.subtype.lower()}-{ln.id}", ring(piece),
                                 f"{ln.subtype} way {ln.id} across the ground driven on"))
    kinds = sorted({ln.subtype for ln in m.lines} - set(BLOCKING))
    note = (f"Dropped: {left} wall, column and kerb lines that stay off the ground driven on, "
            f"and the map's {', '.join(kinds)} lines.") if left or kinds else ""
    return out, note
