"""The static lot, layer by layer: lanes, slots, bumps, zones, labels, portals, graph."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from PIL import Image, ImageChops, ImageDraw

from lotsim.render.lot_image.canvas import (
    LotCanvas,
    _flat,
    _mask,
    arrow_polygon,
    centered_footprints,
    dashed_line,
    fill_geometry,
    paint_footprints,
    triangle_polygon,
)
from lotsim.render.lot_image.theme import (
    ACCESS_AISLE,
    ARROW,
    ARROW_EDGE,
    ASPHALT,
    BOUNDARY,
    BUMP_BLACK,
    BUMP_REACH_TINT,
    BUMP_YELLOW,
    ENTRANCE,
    EXIT,
    GRAPH_EDGE,
    GRAPH_NODE,
    GROUND,
    HALO,
    LANE_LINE,
    NO_GO_HATCH,
    NO_GO_TINT,
    OBSTACLE,
    OBSTACLE_EDGE,
    PAVED,
    SLOT_LABEL,
    SLOT_LINE,
    SLOT_NODE,
    SLOT_PAVING,
    TEXT,
    WALL,
    ZONE_TINT,
    Color,
    draw_text,
    font,
    text_size,
)


# -- the static lot ----------------------------------------------------------------------------
def _lane_width(aisle) -> float:
    return aisle.width if aisle.one_way or len(aisle.lanes) < 2 else aisle.width / 2


def _paint_lanes(img: Image.Image, canvas: LotCanvas, lot) -> None:
    draw = ImageDraw.Draw(img, "RGBA")
    step = max(0.05, 2.0 / canvas.scale)
    portals = canvas.to_px(np.array([p.pose[:2] for p in (*lot.entrances, *lot.exits)],
                                    dtype=float).reshape(-1, 2))
    keep_out = [spot[3] for spot in _zone_label_spots(canvas, lot)]
    for aisle in lot.aisles.values():
        lane_w = _lane_width(aisle)
        length = float(np.clip(canvas.px(lane_w) * 1.1, 10, 44))
        width = float(np.clip(0.55 * length, 7, canvas.px(lane_w) * 0.8 + 2))
        spacing = max(4.0 * length, 90.0) / canvas.scale  # [m]
        for lane in aisle.lanes:
            pts = canvas.to_px(lane.sample(step)[:, :2])
            dashed_line(draw, pts, LANE_LINE, width=1, on=8, off=8)
            if canvas.px(lane_w) < 5:
                continue  # too narrow to hold a readable arrow
            total = lane.length
            n = max(1, int(total // spacing))
            stations = (np.arange(n) + 0.5) * total / n
            for s in stations:
                x, y, t = lane.pose_at(float(s))
                c = canvas.to_px([x, y])
                if len(portals) and np.min(np.hypot(*(portals - c).T)) < (
                    length / 2 + 0.6 * portal_size(canvas) + 4
                ):
                    continue  # an entrance or exit arrow stands there
                arrow = arrow_polygon(c, t, length, width)
                box = (*arrow.min(axis=0), *arrow.max(axis=0))
                if any(_overlap(box, k) for k in keep_out):
                    continue  # a speed limit is written there
                draw.polygon(_flat(arrow), fill=ARROW, outline=ARROW_EDGE)


def _paint_slot_lines(img: Image.Image, canvas: LotCanvas, lot) -> None:
    draw = ImageDraw.Draw(img)
    if not lot.slots:
        return
    width = 2 if canvas.px(min(s.width for s in lot.slots)) >= 30 else 1
    for slot in lot.slots:
        poly = np.asarray(slot.polygon, dtype=float)
        entry = np.asarray(slot.entry, dtype=float)
        color = SLOT_LINE.get(slot.kind, SLOT_LINE["perpendicular"])
        # the edge of the polygon that is the entry: the one whose midpoint is nearest
        mids = (poly + np.roll(poly, -1, axis=0)) / 2
        k = int(np.argmin(np.hypot(*(mids - entry.mean(axis=0)).T)))
        ring = np.roll(poly, -(k + 1), axis=0)  # starts at the entry edge's far corner
        draw.line(_flat(canvas.to_px(ring)), fill=color, width=width, joint="curve")
        dashed_line(draw, canvas.to_px(entry), color, width=1, on=2, off=3)


def _bump_width(canvas: LotCanvas) -> int:
    return int(np.clip(canvas.px(0.6), 5, 16))


def _paint_bumps(img: Image.Image, canvas: LotCanvas, lot) -> None:
    draw = ImageDraw.Draw(img)
    w = _bump_width(canvas)
    for z in lot.zones:
        if z.source != "bump" or z.line is None:
            continue
        pts = canvas.to_px(np.asarray(z.line.coords)[:, :2])
        draw.line(_flat(pts), fill=BUMP_YELLOW, width=w, joint="curve")
        dashed_line(draw, pts, BUMP_BLACK, width=w, on=w, off=w)


def _hatch(img: Image.Image, canvas: LotCanvas, geoms: list, color: Color) -> None:
    """Diagonal lines clipped to the polygons."""
    if not geoms:
        return
    mask = _mask(canvas, geoms)
    lines = Image.new("L", canvas.size, 0)
    ld = ImageDraw.Draw(lines)
    w, h = canvas.size
    for c in range(-h, w, 8):
        ld.line([(c, h), (c + h, 0)], fill=255, width=2)
    img.paste(color, (0, 0), ImageChops.multiply(mask, lines))


def paint_lot(
    img: Image.Image,
    canvas: LotCanvas,
    lot,
    *,
    parked_vehicle=None,
    parked_bodies: np.ndarray | None = None,
    labels: bool = True,
) -> None:
    """Draw the static lot (everything but the graph and the margins) onto ``img``.

    Cars in the slots taken at start are ``parked_vehicle`` centred in them, or the
    bodies ``parked_bodies`` (N, 4, 2) [m] when given (as a result file lists them).
    """
    draw = ImageDraw.Draw(img)
    if lot.pavement is None:
        fill_geometry(img, canvas, lot.boundary, PAVED)
    else:
        fill_geometry(img, canvas, lot.boundary, GROUND)
        fill_geometry(img, canvas, lot.pavement, PAVED)
    for aisle in lot.aisles.values():
        fill_geometry(img, canvas, aisle.polygon, ASPHALT)
    for s in lot.slots:
        draw.polygon(_flat(canvas.to_px(np.asarray(s.polygon, dtype=float))), fill=SLOT_PAVING)
    # access aisles: ground no car parks or drives on, hatched in the accessible blue
    access = [a.shape for a in getattr(lot, "access_aisles", ())]
    _hatch(img, canvas, access, ACCESS_AISLE)
    for g in access:
        fill_geometry(img, canvas, g, (0, 0, 0, 0), outline=ACCESS_AISLE, width=1)
    for z in lot.zones:
        tint = ZONE_TINT if z.source == "zone" else BUMP_REACH_TINT
        fill_geometry(img, canvas, z.polygon.intersection(lot.boundary), tint)
    no_go = [a.polygon for a in lot.areas if a.kind == "no_go"]
    for g in no_go:
        fill_geometry(img, canvas, g, NO_GO_TINT)
    _hatch(img, canvas, no_go, NO_GO_HATCH)
    for g in no_go:
        fill_geometry(img, canvas, g, (0, 0, 0, 0), outline=NO_GO_HATCH, width=2)
    for a in lot.areas:
        if a.kind == "obstacle":
            fill_geometry(img, canvas, a.polygon, OBSTACLE, outline=OBSTACLE_EDGE, width=2)
        elif a.kind == "wall":
            fill_geometry(img, canvas, a.polygon, WALL, outline=WALL, width=1)
    _paint_lanes(img, canvas, lot)
    _paint_slot_lines(img, canvas, lot)
    _paint_bumps(img, canvas, lot)
    if parked_bodies is None:
        taken = [s for s in lot.slots if s.id in lot.occupied]
        parked_bodies = centered_footprints(taken, parked_vehicle)
    paint_footprints(img, canvas, parked_bodies)
    fill_geometry(img, canvas, lot.boundary, (0, 0, 0, 0), outline=BOUNDARY, width=3)
    if labels:
        paint_labels(img, canvas, lot)


def paint_labels(
    img: Image.Image, canvas: LotCanvas, lot, *, slot_shift: float = 0.0
) -> None:
    """Slot ids (where they fit inside the slot) and speed limits.

    ``slot_shift`` moves each slot id along the slot's heading by that fraction
    of the slot length, to keep it off a graph node at the slot centre.
    """
    _label_slots(img, canvas, lot, slot_shift)
    _label_zones(img, canvas, lot)


SLOT_LABEL_MIN = 14
"""Slot ids are drawn when the slots' typical short side is at least this many pixels."""


def _slot_label_spots(canvas: LotCanvas, lot, shift: float) -> list:
    """``(slot id, centre px, font, angle)`` of each slot id that fits inside its slot:
    upright (angle 0) where it fits so, else turned along the slot's long side (``angle``
    degrees counter-clockwise as seen, in (-90, 90]: read from the left or from below), as
    on a big lot whose slots are narrower than their ids are long."""
    if not lot.slots:
        return []
    short = canvas.px(float(np.median([min(s.width, s.length) for s in lot.slots])))
    if short < SLOT_LABEL_MIN:
        return []
    f = font(int(np.clip(short * 0.4, 8, 13)))
    out = []
    for slot in lot.slots:
        poly = canvas.to_px(np.asarray(slot.polygon, dtype=float))
        w, h = text_size(slot.id, f)
        c = poly.mean(axis=0)
        if shift:
            c = c + shift * canvas.px(slot.length) * np.array(
                [math.cos(slot.heading), -math.sin(slot.heading)]
            )
        for angle in (0.0, _long_side_angle(poly)):
            if _inside_convex(text_box(c, w + 2, h + 2, angle), poly):
                out.append((slot.id, c, f, angle))
                break
    return out


def _long_side_angle(poly: np.ndarray) -> float:
    """The direction of a quadrilateral's longest side as seen [deg], in (-90, 90]."""
    e = np.roll(poly, -1, axis=0) - poly
    dx, dy = e[int(np.argmax(np.hypot(e[:, 0], e[:, 1])))]
    angle = math.degrees(math.atan2(-dy, dx))  # the image's y axis points down
    return float(angle - 180.0 if angle > 90.0 else angle + 180.0 if angle <= -90.0 else angle)


def text_box(c: np.ndarray, w: float, h: float, angle: float) -> np.ndarray:
    """Corners [px] of a ``w`` x ``h`` box centred at ``c``, turned ``angle`` degrees
    counter-clockwise as seen."""
    a = math.radians(angle)
    along = np.array([math.cos(a), -math.sin(a)]) * (w / 2)
    down = np.array([math.sin(a), math.cos(a)]) * (h / 2)
    return np.asarray(c) + np.array([-along - down, along - down, along + down, -along + down])


def _label_slots(img: Image.Image, canvas: LotCanvas, lot, shift: float) -> None:
    draw = ImageDraw.Draw(img)
    for text, c, f, angle in _slot_label_spots(canvas, lot, shift):
        if not angle:
            draw_text(draw, (c[0], c[1]), text, f, SLOT_LABEL)
            continue
        # turned: drawn on a mask of its own, turned about its centre, pasted centred at c
        w, h = text_size(text, f)
        mask = Image.new("L", (w + 4, h + 4), 0)
        draw_text(ImageDraw.Draw(mask), ((w + 4) / 2, (h + 4) / 2), text, f, 255)
        mask = mask.rotate(angle, resample=Image.BICUBIC, expand=True)
        corner = (int(round(c[0] - mask.width / 2)), int(round(c[1] - mask.height / 2)))
        img.paste(Image.new(img.mode, mask.size, SLOT_LABEL), corner, mask)


def _inside_convex(points: np.ndarray, poly: np.ndarray) -> bool:
    """Whether every point lies inside the convex polygon (either orientation)."""
    a = poly
    b = np.roll(poly, -1, axis=0)
    e = b - a  # (M, 2)
    r = points[:, None, :] - a[None, :, :]  # (K, M, 2)
    cross = e[None, :, 0] * r[..., 1] - e[None, :, 1] * r[..., 0]
    return bool(np.all(cross >= 0) or np.all(cross <= 0))


def _kmh(limit: float) -> str:
    v = limit * 3.6
    return f"{v:.0f} km/h" if abs(v - round(v)) < 0.05 else f"{v:.1f} km/h"


def _zone_label_spots(canvas: LotCanvas, lot) -> list[tuple[np.ndarray, str, Color, tuple]]:
    """Where each speed limit is written: (centre px, text, colour, box)."""
    f = font(12)
    out = []
    for z in lot.zones:
        text = _kmh(z.limit)
        w, h = text_size(text, f)
        if z.source == "bump" and z.line is not None:
            # beside the middle of the bump, on the side the line's normal points to
            mid = z.line.interpolate(0.5, normalized=True)
            a = z.line.interpolate(0.45, normalized=True)
            b = z.line.interpolate(0.55, normalized=True)
            d = canvas.to_px([b.x, b.y]) - canvas.to_px([a.x, a.y])
            n = np.array([d[1], -d[0]]) / (np.hypot(*d) or 1.0)
            reach = _bump_width(canvas) / 2 + 5 + 0.5 * (abs(n[0]) * w + abs(n[1]) * h)
            pos, color = canvas.to_px([mid.x, mid.y]) + n * reach, TEXT
        else:
            p = z.polygon.intersection(lot.boundary).representative_point()
            if p.is_empty:
                continue
            pos, color = canvas.to_px([p.x, p.y]), (150, 70, 0)
        out.append((pos, text, color, _box_around(pos, w / 2 + 3, h / 2 + 3)))
    return out


def _label_zones(img: Image.Image, canvas: LotCanvas, lot) -> None:
    draw = ImageDraw.Draw(img)
    f = font(12)
    for pos, text, color, _ in _zone_label_spots(canvas, lot):
        draw_text(draw, (pos[0], pos[1]), text, f, color, halo=HALO)


def portal_size(canvas: LotCanvas) -> float:
    """Size of an entrance/exit triangle [px]."""
    return float(np.clip(canvas.px(3.0), 14, 34))


def paint_portals(img: Image.Image, canvas: LotCanvas, lot, *, labels: bool = True) -> None:
    """Entrances as green, exits as red triangles pointing the way traffic goes.

    Each id goes behind its triangle, or beside or ahead of it when that would
    leave the lot or cover another portal's id.
    """
    draw = ImageDraw.Draw(img)
    size = portal_size(canvas)
    f = font(14)
    portals = [(p, ENTRANCE) for p in lot.entrances] + [(p, EXIT) for p in lot.exits]
    for p, color in portals:
        c = canvas.to_px(p.pose[:2])
        draw.polygon(_flat(triangle_polygon(c, p.pose[2], size)), fill=color,
                     outline=(0, 0, 0), width=2)
    if not labels:
        return
    inner = canvas.drawing_box
    outer = (0.0, 0.0, float(canvas.size[0]), float(canvas.size[1]))
    placed: list[tuple[float, float, float, float]] = [
        _box_around(canvas.to_px(p.pose[:2]), size * 0.6, size * 0.6) for p, _ in portals
    ]
    for p, color in portals:
        c = canvas.to_px(p.pose[:2])
        w, h = text_size(p.id, f)
        t = p.pose[2]
        fwd = np.array([math.cos(t), -math.sin(t)])
        right = np.array([math.sin(t), math.cos(t)])
        options = []
        for v in (-fwd, right, -right, fwd):
            reach = 0.45 * size + 5 + 0.5 * (abs(v[0]) * w + abs(v[1]) * h)
            pos = c + v * reach
            options.append((pos, _box_around(pos, w / 2 + 2, h / 2 + 2)))

        def score(o, placed=placed) -> int:
            box = o[1]
            clear = not any(_overlap(box, q) for q in placed)
            return int(_within(box, inner)) + int(_within(box, outer)) + int(clear)

        pos, box = max(options, key=score)  # max keeps the first of equals
        pos = np.array([min(max(pos[0], w / 2 + 2), outer[2] - w / 2 - 2),
                        min(max(pos[1], h / 2 + 2), outer[3] - h / 2 - 2)])
        placed.append(box)
        draw_text(draw, (pos[0], pos[1]), p.id, f, color, halo=HALO)


def _box_around(c: np.ndarray, hw: float, hh: float) -> tuple[float, float, float, float]:
    return (float(c[0] - hw), float(c[1] - hh), float(c[0] + hw), float(c[1] + hh))


def _within(a: Sequence[float], b: Sequence[float]) -> bool:
    return a[0] >= b[0] and a[1] >= b[1] and a[2] <= b[2] and a[3] <= b[3]


def _overlap(a: Sequence[float], b: Sequence[float]) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _segment_points(seg, step: float) -> np.ndarray | None:
    if seg is None:
        return None
    if hasattr(seg, "sample"):
        return np.asarray(seg.sample(step))[:, :2]
    parts = [np.asarray(s.sample(step))[:, :2] for s in seg]
    return np.concatenate(parts) if parts else None


def paint_graph(img: Image.Image, canvas: LotCanvas, lot_graph) -> None:
    """Graph edges as thin lines (placeholder park links dotted) and nodes as dots."""
    g = lot_graph.graph
    draw = ImageDraw.Draw(img)
    step = max(0.1, 3.0 / canvas.scale)
    pose = {n: d["pose"] for n, d in g.nodes(data=True)}
    done: set[tuple[int, int]] = set()
    for u, v, d in g.edges(data=True):
        kind = d.get("kind", "lane")
        color = GRAPH_EDGE.get(kind, GRAPH_EDGE["lane"])
        pts = None if d.get("placeholder") else _segment_points(d.get("path"), step)
        if pts is None:
            key = (min(u, v), max(u, v))
            if key in done:
                continue
            done.add(key)
            line = canvas.to_px(np.array([pose[u][:2], pose[v][:2]], dtype=float))
            dashed_line(draw, line, color, width=1, on=2, off=3)
        else:
            draw.line(_flat(canvas.to_px(pts)), fill=color, width=1)
    r = float(np.clip(canvas.px(0.25), 1.5, 3.5))
    for n, d in g.nodes(data=True):
        x, y = canvas.to_px(pose[n][:2])
        color = SLOT_NODE if d.get("kind") == "slot" else GRAPH_NODE
        draw.ellipse([x - r, y - r, x + r, y + r], fill=color, outline=(0, 0, 0))
