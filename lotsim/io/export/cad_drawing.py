"""A built lot as the plain figures a CAD drawing holds, layer by layer
(:data:`~lotsim.io.cad_layers.LAYERS`): polylines, lines, points and texts in the lot's
metres (:func:`scaled` gives them in another unit). :mod:`lotsim.io.export.dxf` writes them
as DXF entities; nothing here needs a CAD package.

What is drawn, and where it comes from:

* the boundary, the pavement (where not wall to wall), each aisle's centreline as given,
  the outline of all aisles together (their pavement edges) and the areas (islands and
  no-go zones, obstacles, walls), ring by ring, exactly as lotsim holds them, each area's
  id inside it;
* every bay as its four corners on the layer of its use (:data:`lotsim.lot.uses.USES`),
  its stripes (every side but the entry, a side two bays share drawn once) and its id at
  its centre, along its length; a bay taken at start is crossed; each access aisle as its
  four corners, hatched, on a layer of its own;
* each lane's direction arrows, spaced along it as ``lotsim show`` spaces them, and an
  arrow at each entrance and exit, the way cars go;
* speed bumps as lines and speed zones as outlines, each with its limit;
* gates: where the lane of an entrance (followed back) or of an exit (followed on) crosses
  the boundary; crossings closer than :data:`GATE_MERGE` are one gate, on the boundary
  nearest their middle, named after its first entrance (else its first exit);
* the scenario's service routes, when given their reports
  (:func:`~lotsim.roadmap.service_routes.plan_routes`): each swept envelope ring by ring,
  exactly as planned, with the route's id inside it, and its path (the rear-axle line) a
  polyline per stroke, reverse strokes dashed; a failed route draws what its report holds.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import shapely
from shapely.geometry import LineString, Point
from shapely.geometry.base import BaseGeometry

from lotsim.core.geometry import sample_segments
from lotsim.io.cad_layers import LAYER_NAMES, bay_layer
from lotsim.lot.model import Lot, Portal, Slot
from lotsim.roadmap.service_routes import RouteReport

XY = tuple[float, float]

GATE_MERGE = 10.0
"""Crossings of the boundary closer than this are one gate [m]: the entrance and exit lanes
of one two-way aisle cross it a lane's width apart."""
PORTAL_SIZE = 3.0
"""Length of the arrow drawn at an entrance or exit [m] (as ``lotsim show`` draws it)."""
TAKEN_INSET = 0.3
"""How far inside its bay the outline of a taken bay is drawn [m]."""
PATH_STEP = 0.1
"""Spacing of a route path's vertices along its arcs [m] (a straight keeps its two ends)."""
AREA_LAYERS = {"no_go": "island", "obstacle": "obstacle", "wall": "wall"}
"""Kind of area → what layer it is drawn on (:data:`~lotsim.io.cad_layers.LAYER_NAMES`)."""


@dataclass(frozen=True, slots=True)
class Polyline:
    """An LWPOLYLINE: its vertices [m], closed or not; ``fill``: filled solid (a HATCH);
    ``hatch``: hatched with parallel lines (a HATCH of a line pattern); ``linetype``: its
    own, else "" (the layer's); ``of``: the id of what it draws (a route's), written as its
    extended data under :data:`~lotsim.io.export.dxf.APPID`, else ""."""

    layer: str
    points: tuple[XY, ...]
    closed: bool
    fill: bool = False
    hatch: bool = False
    linetype: str = ""
    of: str = ""


@dataclass(frozen=True, slots=True)
class Segment:
    """A LINE from ``start`` to ``end`` [m]."""

    layer: str
    start: XY
    end: XY


@dataclass(frozen=True, slots=True)
class Mark:
    """A POINT [m]."""

    layer: str
    at: XY


@dataclass(frozen=True, slots=True)
class Label:
    """A TEXT centred at ``at`` [m], ``height`` tall [m], turned ``rotation`` [degrees]
    counter-clockwise from the x axis."""

    layer: str
    text: str
    at: XY
    height: float
    rotation: float = 0.0


@dataclass(frozen=True, slots=True)
class CadDrawing:
    """Every figure of a lot, in the order it is to be written."""

    polylines: tuple[Polyline, ...]
    segments: tuple[Segment, ...]
    marks: tuple[Mark, ...]
    labels: tuple[Label, ...]
    bounds: tuple[float, float, float, float]
    """(min x, min y, max x, max y) of the lot's boundary [m]."""


def _xy(points) -> tuple[XY, ...]:
    return tuple((float(x), float(y)) for x, y in np.asarray(points, dtype=float)[:, :2])


def rings(geometry: BaseGeometry) -> list[tuple[XY, ...]]:
    """Every ring of a (multi)polygon, exterior then holes, without the repeated last
    point."""
    out = []
    for poly in getattr(geometry, "geoms", [geometry]):
        if poly.is_empty or poly.geom_type != "Polygon":
            continue
        for ring in (poly.exterior, *poly.interiors):
            out.append(_xy(ring.coords)[:-1])
    return out


def entry_side(slot: Slot) -> int:
    """Index ``k`` of the bay's entry side: from corner ``k`` to corner ``k + 1``."""
    poly = np.asarray(slot.polygon, dtype=float)
    mids = (poly + np.roll(poly, -1, axis=0)) / 2
    return int(np.argmin(np.hypot(*(mids - np.asarray(slot.entry).mean(axis=0)).T)))


def stripes(slots: tuple[Slot, ...]) -> list[tuple[XY, XY]]:
    """The painted lines of the bays: every side but the entry, a side two bays share (the
    same ends to the millimetre) once, in the bays' order."""
    seen: set = set()
    out = []
    for slot in slots:
        poly = _xy(slot.polygon)
        skip = entry_side(slot)
        for k in range(len(poly)):
            if k == skip:
                continue
            a, b = poly[k], poly[(k + 1) % len(poly)]
            key = tuple(sorted((tuple(round(v, 3) for v in a), tuple(round(v, 3) for v in b))))
            if key not in seen:
                seen.add(key)
                out.append((a, b))
    return out


def reading_angle(heading: float) -> float:
    """A heading [rad] as a text's rotation [degrees] that reads left to right or bottom
    to top: within (-90, 90]."""
    deg = math.degrees(heading) % 360.0
    if deg > 90.0 and deg <= 270.0:
        deg -= 180.0
    elif deg > 270.0:
        deg -= 360.0
    return round(deg, 9)


def arrow(x: float, y: float, t: float, length: float, width: float) -> tuple[XY, ...]:
    """The seven corners of an arrow centred at ``(x, y)`` pointing along ``t`` [m, rad],
    shaped as ``lotsim show`` draws it."""
    head, shaft = 0.45 * length, 0.36 * width
    local = np.array([[length / 2, 0.0], [length / 2 - head, width / 2],
                      [length / 2 - head, shaft / 2], [-length / 2, shaft / 2],
                      [-length / 2, -shaft / 2], [length / 2 - head, -shaft / 2],
                      [length / 2 - head, -width / 2]])
    c, s = math.cos(t), math.sin(t)
    return _xy(np.column_stack([x + c * local[:, 0] - s * local[:, 1],
                                y + s * local[:, 0] + c * local[:, 1]]))


def lane_arrows(lot: Lot) -> list[tuple[XY, ...]]:
    """Each lane's direction arrows: sized by the lane's width, spaced evenly along it,
    none where an entrance's or exit's arrow stands."""
    portals = np.array([p.pose[:2] for p in (*lot.entrances, *lot.exits)],
                       dtype=float).reshape(-1, 2)
    out = []
    for aisle in lot.aisles.values():
        lane_w = aisle.width if aisle.one_way or len(aisle.lanes) < 2 else aisle.width / 2
        length = float(np.clip(1.1 * lane_w, 1.5, 4.5))
        spacing = max(4.0 * length, 12.0)
        for lane in aisle.lanes:
            n = max(1, int(lane.length // spacing))
            for s in (np.arange(n) + 0.5) * lane.length / n:
                x, y, t = lane.pose_at(float(s))
                if len(portals) and np.min(np.hypot(*(portals - [x, y]).T)) < (
                        length / 2 + 0.6 * PORTAL_SIZE + 0.5):
                    continue
                out.append(arrow(x, y, t, length, 0.55 * length))
    return out


def _crossing(lot: Lot, portal: Portal, backwards: bool) -> XY | None:
    """Where the lane through ``portal``, followed back (an entrance) or on (an exit),
    first crosses the boundary."""
    x, y, t = portal.pose
    if backwards:
        t += math.pi
    x0, y0, x1, y1 = lot.boundary.bounds
    reach = math.hypot(x1 - x0, y1 - y0) + 1.0
    ray = LineString([(x, y), (x + reach * math.cos(t), y + reach * math.sin(t))])
    hit = ray.intersection(lot.boundary.exterior)
    if hit.is_empty:
        return None
    pts = [p for g in getattr(hit, "geoms", [hit]) for p in g.coords]
    best = min(pts, key=lambda p: math.hypot(p[0] - x, p[1] - y))
    return (float(best[0]), float(best[1]))


def gates(lot: Lot) -> list[tuple[str, XY]]:
    """The lot's gates as a plot names them: (name, point on the boundary) (module
    docstring)."""
    edge = lot.boundary.exterior
    groups: list[tuple[str, list[XY]]] = []
    for portals, backwards in ((lot.entrances, True), (lot.exits, False)):
        for p in portals:
            at = _crossing(lot, p, backwards)
            if at is None:
                continue
            near = next((g for g in groups if any(math.dist(at, q) < GATE_MERGE
                                                  for q in g[1])), None)
            if near is None:
                groups.append((p.id, [at]))
            else:
                near[1].append(at)
    out = []
    for name, pts in groups:
        mid = Point(np.mean(np.asarray(pts), axis=0))
        on = edge.interpolate(edge.project(mid))
        out.append((name, (float(on.x), float(on.y))))
    return out


def beside(line: LineString, offset: float) -> XY:
    """The point ``offset`` [m] to the left of the middle of ``line``."""
    mid = line.interpolate(0.5, normalized=True)
    a = line.interpolate(0.45, normalized=True)
    b = line.interpolate(0.55, normalized=True)
    d = np.array([b.x - a.x, b.y - a.y])
    n = np.array([-d[1], d[0]]) / (np.hypot(*d) or 1.0)
    return (float(mid.x + offset * n[0]), float(mid.y + offset * n[1]))


def outside(boundary, at: XY, offset: float) -> XY:
    """The point ``offset`` [m] out of ``boundary`` (a polygon) from ``at`` on its edge,
    square to the edge there."""
    edge = boundary.exterior
    s = edge.project(Point(at))
    a, b = edge.interpolate(max(s - 0.5, 0.0)), edge.interpolate(min(s + 0.5, edge.length))
    d = np.array([b.x - a.x, b.y - a.y])
    n = np.array([-d[1], d[0]]) / (np.hypot(*d) or 1.0)
    for sign in (1.0, -1.0):
        p = (at[0] + sign * offset * n[0], at[1] + sign * offset * n[1])
        if not boundary.contains(Point(p)):
            return (float(p[0]), float(p[1]))
    return at


def number_height(slot: Slot) -> float:
    """How tall a bay's number is written [m]: a quarter of the bay's width, less where
    the number would be longer than 85 % of the bay (a letter taken as 0.75 of the height
    wide)."""
    fit = 0.85 * slot.length / (0.75 * max(len(slot.id), 1))
    return round(min(0.25 * min(slot.width, slot.length), fit), 6)


def _kmh(limit: float) -> str:
    return f"{limit * 3.6:.0f} km/h"


def route_figures(reports: Sequence[RouteReport]) -> tuple[list[Polyline], list[Label]]:
    """The envelopes and paths of service routes, and each route's id inside its envelope
    (module docstring)."""
    name = LAYER_NAMES
    polylines, labels = [], []
    for r in reports:
        if r.envelope is not None and not r.envelope.is_empty:
            polylines += [Polyline(name["route_envelope"], ring, True, of=r.id)
                          for ring in rings(r.envelope)]
            p = r.envelope.representative_point()
            labels.append(Label(name["route_envelope"], r.id, (p.x, p.y), 1.0))
        strokes: list[list] = []
        for seg in r.segments:
            if seg.length < 1e-9:
                continue
            if strokes and strokes[-1][0].gear == seg.gear:
                strokes[-1].append(seg)
            else:
                strokes.append([seg])
        for stroke in strokes:
            straight = all(s.curvature == 0.0 and s.sharpness == 0.0 for s in stroke)
            step = max(s.length for s in stroke) if straight else PATH_STEP
            poses, _ = sample_segments(stroke, step)
            keep = np.concatenate([[True], np.any(np.abs(np.diff(poses[:, :2], axis=0))
                                                  > 1e-9, axis=1)])
            polylines.append(Polyline(name["route_path"], _xy(poses[keep]), False,
                                      linetype="DASHED" if stroke[0].gear < 0 else "",
                                      of=r.id))
    return polylines, labels


def lot_drawing(lot: Lot, routes: Sequence[RouteReport] = ()) -> CadDrawing:
    """Every figure of ``lot`` on its layer, and of its service routes' ``routes`` (their
    reports) (module docstring)."""
    name = LAYER_NAMES
    polylines: list[Polyline] = []
    segments: list[Segment] = []
    marks: list[Mark] = []
    labels: list[Label] = []

    def outline(geometry: BaseGeometry, layer: str) -> None:
        polylines.extend(Polyline(layer, ring, True) for ring in rings(geometry))

    outline(lot.boundary, name["boundary"])
    if lot.pavement is not None:
        outline(lot.pavement, name["pavement"])
    for aisle in lot.aisles.values():
        polylines.append(Polyline(name["centreline"], _xy(aisle.centerline), False))
    if lot.aisles:
        outline(shapely.union_all([a.polygon for a in lot.aisles.values()]),
                name["aisle_edge"])
    for corners in lane_arrows(lot):
        polylines.append(Polyline(name["arrow"], corners, True, fill=True))
    for area in lot.areas:
        layer = name[AREA_LAYERS[area.kind]]
        outline(area.polygon, layer)
        p = area.polygon.representative_point()
        size = min(1.0, 0.3 * min(area.polygon.bounds[2] - area.polygon.bounds[0],
                                  area.polygon.bounds[3] - area.polygon.bounds[1]))
        labels.append(Label(layer, area.id, (p.x, p.y), round(max(size, 0.05), 6)))
    for zone in lot.zones:
        if zone.source == "bump" and zone.line is not None:
            line = _xy(zone.line.coords)
            polylines.append(Polyline(name["bump"], line, False))
            a, b, at = line[0], line[-1], beside(zone.line, 0.8)
            labels.append(Label(name["bump"], _kmh(zone.limit), at, 0.8,
                                reading_angle(math.atan2(b[1] - a[1], b[0] - a[0]))))
        elif zone.source == "zone":
            outline(zone.polygon, name["speed_zone"])
            p = zone.polygon.representative_point()
            labels.append(Label(name["speed_zone"], _kmh(zone.limit), (p.x, p.y), 1.0))
    for slot in lot.slots:
        polylines.append(Polyline(bay_layer(slot.use), _xy(slot.polygon), True))
    for aisle in lot.access_aisles:
        polylines.append(Polyline(name["access_aisle"], _xy(aisle.polygon), True,
                                  hatch=True))
    segments += [Segment(name["stripe"], a, b) for a, b in stripes(lot.slots)]
    for slot in lot.slots:
        labels.append(Label(name["bay_number"], slot.id, slot.center, number_height(slot),
                            reading_angle(slot.heading)))
    for slot in lot.slots:
        if slot.id in lot.occupied:
            inner = slot.shape.buffer(-TAKEN_INSET, join_style="mitre")
            if inner.is_empty:
                continue
            corners = rings(inner)[0]
            polylines.append(Polyline(name["taken"], corners, True))
            if len(corners) == 4:
                segments += [Segment(name["taken"], corners[0], corners[2]),
                             Segment(name["taken"], corners[1], corners[3])]
    for portals, layer in ((lot.entrances, name["entrance"]), (lot.exits, name["exit"])):
        for p in portals:
            x, y, t = p.pose
            tri = np.array([[0.6, 0.0], [-0.4, 0.45], [-0.4, -0.45]]) * PORTAL_SIZE
            c, s = math.cos(t), math.sin(t)
            polylines.append(Polyline(layer, _xy(np.column_stack(
                [x + c * tri[:, 0] - s * tri[:, 1], y + s * tri[:, 0] + c * tri[:, 1]])),
                True, fill=True))
            # on the right of the way cars go: outside the lanes of a two-way aisle
            labels.append(Label(layer, p.id, (x + 2.2 * s, y - 2.2 * c), 1.0,
                                reading_angle(t)))
    for gate, at in gates(lot):
        marks.append(Mark(name["gate"], at))
        labels.append(Label(name["gate"], gate, outside(lot.boundary, at, 2.0), 1.0))
    more_lines, more_labels = route_figures(routes)
    polylines += more_lines
    labels += more_labels
    x0, y0, x1, y1 = lot.boundary.bounds
    return CadDrawing(tuple(polylines), tuple(segments), tuple(marks), tuple(labels),
                      (float(x0), float(y0), float(x1), float(y1)))


def scaled(drawing: CadDrawing, factor: float) -> CadDrawing:
    """``drawing`` with every coordinate and length times ``factor``: its points, its texts'
    heights and its bounds, so that the drawing in another unit (``1 / 0.3048`` for feet)
    looks the same on paper. Angles and what each figure is stay as they are.

    >>> d = CadDrawing((), (Segment("S", (0.0, 0.0), (3.048, 0.0)),), (),
    ...                (Label("T", "A1", (0.3048, 0.0), 0.6096),), (0.0, 0.0, 3.048, 1.0))
    >>> f = scaled(d, 1 / 0.3048)
    >>> [round(v, 9) for v in (*f.segments[0].end, f.labels[0].height, f.bounds[2])]
    [10.0, 0.0, 2.0, 10.0]
    """
    def xy(p: XY) -> XY:
        return (p[0] * factor, p[1] * factor)

    x0, y0, x1, y1 = drawing.bounds
    return CadDrawing(
        polylines=tuple(replace(p, points=tuple(map(xy, p.points)))
                        for p in drawing.polylines),
        segments=tuple(replace(s, start=xy(s.start), end=xy(s.end))
                       for s in drawing.segments),
        marks=tuple(replace(m, at=xy(m.at)) for m in drawing.marks),
        labels=tuple(replace(t, at=xy(t.at), height=t.height * factor)
                     for t in drawing.labels),
        bounds=(x0 * factor, y0 * factor, x1 * factor, y1 * factor))
