"""Draw a built parking lot to a Pillow image: ``lotsim show SCENARIO -o lot.png``.

Only :mod:`PIL.ImageDraw` and the default font are used. World coordinates are
metres with y up; :class:`LotCanvas` maps them to pixels (y down), keeping the
aspect ratio. The static lot is drawn by :func:`paint_lot` onto any image made
by :meth:`LotCanvas.new_image`, so an animation can draw it once as a
background and then draw moving cars over copies of it with
:func:`paint_footprints`.

Drawing order: ground, aisles, slot paving, speed-zone tints, no-go hatching,
obstacles and walls, lane lines and arrows, slot lines, speed bumps, parked
cars, boundary, graph (optional), entrances and exits, labels, then the title,
legend and scale bar in the margins.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from PIL import Image, ImageChops, ImageDraw, ImageFont

from lotsim.atomic import atomic_write

Color = tuple[int, int, int]

# -- palette -----------------------------------------------------------------------------------
BACKGROUND: Color = (246, 246, 242)
"""Outside the lot."""
GROUND: Color = (200, 207, 190)
"""Inside the boundary where there is no aisle or slot."""
ASPHALT: Color = (104, 106, 112)
"""Aisles."""
SLOT_PAVING: Color = (126, 127, 132)
"""Inside slots."""
BOUNDARY: Color = (20, 20, 20)
SLOT_LINE: dict[str, Color] = {
    "perpendicular": (255, 255, 255),
    "parallel": (255, 214, 10),
    "angled": (110, 215, 255),
}
"""Slot outline colour by slot kind."""
SLOT_LABEL: Color = (240, 240, 240)
LANE_LINE: tuple[int, int, int, int] = (255, 255, 255, 90)
ARROW: Color = (250, 250, 250)
ARROW_EDGE: Color = (45, 45, 50)
WALL: Color = (28, 28, 28)
OBSTACLE: Color = (72, 70, 66)
OBSTACLE_EDGE: Color = (15, 15, 15)
NO_GO_TINT: tuple[int, int, int, int] = (235, 80, 80, 60)
NO_GO_HATCH: Color = (200, 30, 30)
ZONE_TINT: tuple[int, int, int, int] = (255, 150, 0, 55)
BUMP_REACH_TINT: tuple[int, int, int, int] = (255, 220, 0, 35)
BUMP_YELLOW: Color = (255, 205, 0)
BUMP_BLACK: Color = (20, 20, 20)
ENTRANCE: Color = (30, 185, 60)
EXIT: Color = (225, 40, 40)
PARKED_CAR: Color = (52, 101, 164)
"""Body of a car parked at start."""
PARKED_CAR_FRONT: Color = (20, 36, 70)
"""Its windscreen, which shows which way it faces."""
PARKED_CAR_EDGE: Color = (16, 28, 56)
GRAPH_EDGE: dict[str, Color] = {
    "lane": (0, 215, 255),
    "turn": (255, 40, 210),
    "join": (255, 255, 255),
    "park": (255, 150, 0),
    "leave": (255, 150, 0),
}
GRAPH_NODE: Color = (0, 240, 255)
SLOT_NODE: Color = (255, 150, 0)
TEXT: Color = (25, 25, 25)
HALO: Color = (255, 255, 255)

DEFAULT_PARKED = (4.5, 1.8)
"""Length and width [m] of the car drawn in taken slots when no vehicle type is given."""
PAD_PX = 14
"""Free pixels around the drawing and between panels [px] (not :data:`lotsim.settings.MARGIN`,
the planner's safety margin in metres)."""


# -- fonts and text ----------------------------------------------------------------------------
@lru_cache(maxsize=32)
def font(size: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    """Pillow's default font at ``size`` px; the fixed bitmap font on old Pillow."""
    try:
        return ImageFont.load_default(size=size)  # Pillow >= 10.1 with FreeType
    except (TypeError, AttributeError, OSError, ImportError):
        return ImageFont.load_default()


def _scalable(f: object) -> bool:
    return isinstance(f, ImageFont.FreeTypeFont)


def text_size(text: str, f: ImageFont.ImageFont | ImageFont.FreeTypeFont) -> tuple[int, int]:
    """Width and height of ``text`` drawn in ``f`` [px]."""
    x0, y0, x1, y1 = f.getbbox(text)
    return int(x1 - x0), int(y1 - y0)


def draw_text(
    draw: ImageDraw.ImageDraw,
    xy: tuple[float, float],
    text: str,
    f: ImageFont.ImageFont | ImageFont.FreeTypeFont,
    fill: Color = TEXT,
    *,
    anchor: str = "mm",
    halo: Color | None = None,
) -> tuple[float, float, float, float]:
    """Draw ``text`` placed by a two-letter ``anchor`` (l/m/r, t/m/b); return its box.

    Works with the bitmap font too (which has no anchors of its own).
    """
    x0, y0, x1, y1 = f.getbbox(text)
    w, h = x1 - x0, y1 - y0
    x = xy[0] - {"l": 0, "m": w / 2, "r": w}[anchor[0]] - x0
    y = xy[1] - {"t": 0, "m": h / 2, "b": h}[anchor[1]] - y0
    if halo is not None and _scalable(f):
        draw.text((x, y), text, font=f, fill=fill, stroke_width=2, stroke_fill=halo)
    else:
        draw.text((x, y), text, font=f, fill=fill)
    return (x + x0, y + y0, x + x1, y + y1)


# -- world → pixels ----------------------------------------------------------------------------
class LotCanvas:
    """Maps world metres (y up) to image pixels (y down) for a given image size.

    The world rectangle ``bounds`` is scaled uniformly (aspect ratio kept) to
    fit the pixel rectangle ``frame`` and centred in it.

    Parameters
    ----------
    bounds : (minx, miny, maxx, maxy)
        World rectangle to show [m].
    size : (width, height)
        Image size [px].
    frame : (left, top, right, bottom), optional
        Pixel rectangle the world is fitted into; default the whole image
        less :data:`PAD_PX` on each side.
    """

    def __init__(
        self,
        bounds: Sequence[float],
        size: tuple[int, int],
        frame: Sequence[float] | None = None,
    ):
        self.size = (int(size[0]), int(size[1]))
        if frame is None:
            frame = (PAD_PX, PAD_PX, self.size[0] - PAD_PX, self.size[1] - PAD_PX)
        minx, miny, maxx, maxy = (float(v) for v in bounds)
        bw, bh = max(maxx - minx, 1e-9), max(maxy - miny, 1e-9)
        fw, fh = max(frame[2] - frame[0], 1.0), max(frame[3] - frame[1], 1.0)
        self.bounds = (minx, miny, maxx, maxy)
        self.scale = min(fw / bw, fh / bh)
        """Pixels per metre."""
        self.x0 = frame[0] + (fw - bw * self.scale) / 2 - minx * self.scale
        self.y0 = frame[1] + (fh - bh * self.scale) / 2 + maxy * self.scale

    def to_px(self, xy: np.ndarray | Sequence) -> np.ndarray:
        """World points (..., 2) [m] → pixel points (..., 2), float."""
        p = np.asarray(xy, dtype=float)
        out = np.empty(p.shape[:-1] + (2,))
        out[..., 0] = self.x0 + p[..., 0] * self.scale
        out[..., 1] = self.y0 - p[..., 1] * self.scale
        return out

    def to_world(self, px: np.ndarray | Sequence) -> np.ndarray:
        """Pixel points (..., 2) → world points (..., 2) [m]."""
        p = np.asarray(px, dtype=float)
        out = np.empty(p.shape[:-1] + (2,))
        out[..., 0] = (p[..., 0] - self.x0) / self.scale
        out[..., 1] = (self.y0 - p[..., 1]) / self.scale
        return out

    def px(self, metres: float) -> float:
        """A length in metres → pixels."""
        return metres * self.scale

    @property
    def drawing_box(self) -> tuple[float, float, float, float]:
        """Pixel rectangle (left, top, right, bottom) covered by ``bounds``."""
        (left, bottom), (right, top) = self.to_px([self.bounds[:2], self.bounds[2:]])
        return (float(left), float(top), float(right), float(bottom))

    def new_image(self, color: Color = BACKGROUND) -> Image.Image:
        return Image.new("RGB", self.size, color)


def lot_bounds(lot) -> tuple[float, float, float, float]:
    """World rectangle holding the boundary and everything placed in the lot [m]."""
    boxes = [lot.boundary.bounds]
    boxes += [a.polygon.bounds for a in lot.aisles.values()]
    boxes += [a.polygon.bounds for a in lot.areas]
    if lot.slots:
        pts = np.concatenate([s.polygon for s in lot.slots])
        boxes.append((*pts.min(axis=0), *pts.max(axis=0)))
    for p in (*lot.entrances, *lot.exits):
        boxes.append((p.pose[0], p.pose[1], p.pose[0], p.pose[1]))
    b = np.array(boxes, dtype=float)
    return (b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max())


# -- primitive helpers -------------------------------------------------------------------------
def _rings(geom) -> Iterator[tuple[np.ndarray, list[np.ndarray]]]:
    """(exterior, holes) coordinate arrays of each polygon in a shapely geometry."""
    if geom is None or geom.is_empty:
        return
    if geom.geom_type == "Polygon":
        yield np.asarray(geom.exterior.coords)[:, :2], [
            np.asarray(r.coords)[:, :2] for r in geom.interiors
        ]
    elif hasattr(geom, "geoms"):
        for g in geom.geoms:
            yield from _rings(g)


def _flat(px: np.ndarray) -> list[int]:
    """Pixel points as the flat list Pillow takes, rounded to the nearest pixel.

    (Pillow truncates float coordinates; rounding here puts a world point on
    the pixel ``np.rint(canvas.to_px(point))``.)
    """
    return np.rint(np.asarray(px, dtype=float)).astype(int).reshape(-1).tolist()


def _mask(canvas: LotCanvas, geoms: Iterable, value: int = 255) -> Image.Image:
    """An ``L`` image that is ``value`` inside the polygons (holes excluded) and 0 outside."""
    mask = Image.new("L", canvas.size, 0)
    md = ImageDraw.Draw(mask)
    for geom in geoms:
        for ext, holes in _rings(geom):
            if len(ext) >= 3:
                md.polygon(_flat(canvas.to_px(ext)), fill=value)
            for h in holes:
                if len(h) >= 3:
                    md.polygon(_flat(canvas.to_px(h)), fill=0)
    return mask


def fill_geometry(
    img: Image.Image,
    canvas: LotCanvas,
    geom,
    fill: Color | tuple[int, int, int, int],
    outline: Color | None = None,
    width: int = 1,
) -> None:
    """Fill a shapely (multi)polygon, holes included; ``fill`` may have an alpha."""
    draw = ImageDraw.Draw(img)
    rings = list(_rings(geom))
    alpha = fill[3] if len(fill) == 4 else 255
    if alpha < 255 or any(h for _, h in rings):
        img.paste(tuple(fill[:3]), (0, 0), _mask(canvas, [geom], alpha))
    else:
        for ext, _ in rings:
            draw.polygon(_flat(canvas.to_px(ext)), fill=tuple(fill[:3]))
    if outline is not None:
        for ext, holes in rings:
            for ring in (ext, *holes):
                draw.line(_flat(canvas.to_px(ring)), fill=outline, width=width, joint="curve")


def dashes(px: np.ndarray, on: float, off: float) -> list[np.ndarray]:
    """Cut a pixel polyline (N, 2) into dashes ``on`` px long, ``off`` px apart."""
    p = np.asarray(px, dtype=float)
    if len(p) < 2:
        return []
    d = np.hypot(*np.diff(p, axis=0).T)
    keep = np.concatenate([[True], d > 1e-9])
    p, cum = p[keep], np.concatenate([[0.0], np.cumsum(d[d > 1e-9])])
    total = cum[-1]
    if total <= 0:
        return []
    starts = np.arange(0.0, total, on + off)
    ends = np.minimum(starts + on, total)
    ax, ay = np.interp(starts, cum, p[:, 0]), np.interp(starts, cum, p[:, 1])
    bx, by = np.interp(ends, cum, p[:, 0]), np.interp(ends, cum, p[:, 1])
    i0 = np.searchsorted(cum, starts, side="right")
    i1 = np.searchsorted(cum, ends, side="left")
    out = []
    for k in range(len(starts)):
        inner = p[i0[k] : i1[k]]
        out.append(np.vstack([[ax[k], ay[k]], inner, [bx[k], by[k]]]))
    return out


def dashed_line(
    draw: ImageDraw.ImageDraw,
    px: np.ndarray,
    fill: Color | tuple[int, int, int, int],
    *,
    width: int = 1,
    on: float = 6,
    off: float = 4,
) -> None:
    """Draw a pixel polyline as dashes."""
    for d in dashes(px, on, off):
        draw.line(_flat(d), fill=fill, width=width)


def arrow_polygon(
    tip_px: np.ndarray, heading: float, length: float, width: float
) -> np.ndarray:
    """An arrow (shaft + head) centred at ``tip_px`` pointing along world ``heading``; (7, 2) px."""
    f = np.array([math.cos(heading), -math.sin(heading)])  # forward, in pixels
    left = np.array([-math.sin(heading), -math.cos(heading)])  # left of heading, in pixels
    head = 0.45 * length
    shaft = 0.36 * width
    local = np.array(
        [
            [length / 2, 0.0],
            [length / 2 - head, width / 2],
            [length / 2 - head, shaft / 2],
            [-length / 2, shaft / 2],
            [-length / 2, -shaft / 2],
            [length / 2 - head, -shaft / 2],
            [length / 2 - head, -width / 2],
        ]
    )
    return tip_px + local[:, :1] * f + local[:, 1:] * left


def triangle_polygon(center_px: np.ndarray, heading: float, size: float) -> np.ndarray:
    """An isosceles triangle pointing along world ``heading``; (3, 2) px."""
    f = np.array([math.cos(heading), -math.sin(heading)])
    left = np.array([-math.sin(heading), -math.cos(heading)])
    local = np.array([[0.6, 0.0], [-0.4, 0.45], [-0.4, -0.45]]) * size
    return center_px + local[:, :1] * f + local[:, 1:] * left


def centered_footprints(
    slots: Sequence, vehicle=None
) -> np.ndarray:
    """Bodies of cars parked centred in ``slots``, facing ``slot.heading``; (N, 4, 2) [m].

    Corners run counter-clockwise from rear right, like
    :meth:`~lotsim.vehicles.model.VehicleType.footprints`.
    """
    if not slots:
        return np.zeros((0, 4, 2))
    centers = np.array([s.center for s in slots], dtype=float)
    heading = np.array([s.heading for s in slots], dtype=float)
    u = np.stack([np.cos(heading), np.sin(heading)], axis=-1)
    if vehicle is None:
        length, width = DEFAULT_PARKED
        front = rear = length / 2
    else:
        front, rear, width = float(vehicle.front), float(vehicle.rear), float(vehicle.width)
    axle = centers - u * (front - rear) / 2
    poses = np.column_stack([axle, heading])
    if vehicle is not None:
        return np.asarray(vehicle.footprints(poses), dtype=float)
    h = width / 2
    body = np.array([[-rear, -h], [front, -h], [front, h], [-rear, h]])
    c, s = np.cos(heading)[:, None], np.sin(heading)[:, None]
    x = axle[:, :1] + c * body[:, 0] - s * body[:, 1]
    y = axle[:, 1:] + s * body[:, 0] + c * body[:, 1]
    return np.stack([x, y], axis=-1)


def paint_footprints(
    img: Image.Image,
    canvas: LotCanvas,
    corners: np.ndarray,
    fill: Color | Sequence[Color] = PARKED_CAR,
    front: Color | Sequence[Color] | None = PARKED_CAR_FRONT,
    outline: Color | None = PARKED_CAR_EDGE,
) -> None:
    """Draw car bodies (N, 4, 2) [m] (corners from rear right, counter-clockwise).

    A darker windscreen band near the front shows the heading. ``fill`` and
    ``front`` are one colour or one per car.
    """
    corners = np.asarray(corners, dtype=float).reshape(-1, 4, 2)
    if len(corners) == 0:
        return
    draw = ImageDraw.Draw(img)
    px = canvas.to_px(corners)
    rr, fr, fl, rl = px[:, 0], px[:, 1], px[:, 2], px[:, 3]

    def at(t: float, s: float) -> np.ndarray:  # t along rear→front, s across right→left
        right = rr + t * (fr - rr)
        left = rl + t * (fl - rl)
        return right + s * (left - right)

    screen = np.stack([at(0.60, 0.12), at(0.78, 0.12), at(0.78, 0.88), at(0.60, 0.88)], axis=1)
    many_fill = not isinstance(fill[0], int)
    many_front = front is not None and not isinstance(front[0], int)
    w = 1 if canvas.px(0.3) < 4 else 2
    for k in range(len(px)):
        draw.polygon(
            _flat(px[k]), fill=tuple(fill[k] if many_fill else fill), outline=outline,
            width=w if outline is not None else 0,
        )
        if front is not None and canvas.px(1.0) >= 2:
            draw.polygon(_flat(screen[k]), fill=tuple(front[k] if many_front else front))


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
    fill_geometry(img, canvas, lot.boundary, GROUND)
    for aisle in lot.aisles.values():
        fill_geometry(img, canvas, aisle.polygon, ASPHALT)
    for s in lot.slots:
        draw.polygon(_flat(canvas.to_px(np.asarray(s.polygon, dtype=float))), fill=SLOT_PAVING)
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
    """``(slot id, centre px, font)`` of each slot id that fits inside its slot."""
    if not lot.slots:
        return []
    short = canvas.px(float(np.median([min(s.width, s.length) for s in lot.slots])))
    if short < SLOT_LABEL_MIN:
        return []
    f = font(int(np.clip(short * 0.4, 8, 13)))
    pad = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])
    out = []
    for slot in lot.slots:
        poly = canvas.to_px(np.asarray(slot.polygon, dtype=float))
        w, h = text_size(slot.id, f)
        c = poly.mean(axis=0)
        if shift:
            c = c + shift * canvas.px(slot.length) * np.array(
                [math.cos(slot.heading), -math.sin(slot.heading)]
            )
        box = c + np.array([[-w, -h], [w, -h], [w, h], [-w, h]]) * 0.5 + pad
        if _inside_convex(box, poly):
            out.append((slot.id, c, f))
    return out


def slot_labels_drawn(lot_graph, size: tuple[int, int], *, show_graph: bool = False
                      ) -> int:
    """How many slot ids :func:`draw_lot` draws at ``size`` (an id is drawn where it fits
    inside its slot)."""
    lot = getattr(lot_graph, "lot", lot_graph)
    canvas = lot_layout(lot_graph, size=size, show_graph=show_graph).canvas
    return len(_slot_label_spots(canvas, lot, 0.3 if show_graph else 0.0))


def _label_slots(img: Image.Image, canvas: LotCanvas, lot, shift: float) -> None:
    draw = ImageDraw.Draw(img)
    for text, c, f in _slot_label_spots(canvas, lot, shift):
        draw_text(draw, (c[0], c[1]), text, f, SLOT_LABEL)


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


# -- title, legend, scale bar ------------------------------------------------------------------
@dataclass(frozen=True)
class _Entry:
    label: str
    swatch: Callable[[Image.Image, tuple[int, int, int, int]], None]


def _swatch_rect(fill: Color, outline: Color | None = None, width: int = 1):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        ImageDraw.Draw(img).rectangle(box, fill=fill, outline=outline, width=width)

    return paint


def _swatch_slot(color: Color):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        d = ImageDraw.Draw(img)
        x0, y0, x1, y1 = box
        d.rectangle(box, fill=SLOT_PAVING)
        d.line([(x0 + 2, y1), (x0 + 2, y0 + 2), (x1 - 2, y0 + 2), (x1 - 2, y1)], fill=color,
               width=2)
        dashed_line(d, np.array([[x0 + 2, y1 - 1], [x1 - 2, y1 - 1]]), color, on=2, off=3)

    return paint


def _swatch_arrow(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    d.rectangle(box, fill=ASPHALT)
    c = np.array([(box[0] + box[2]) / 2, (box[1] + box[3]) / 2])
    d.polygon(_flat(arrow_polygon(c, 0.0, box[2] - box[0] - 6, box[3] - box[1] - 3)),
              fill=ARROW, outline=ARROW_EDGE)


def _swatch_hatch(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    sub = Image.new("RGB", (box[2] - box[0] + 1, box[3] - box[1] + 1), GROUND)
    overlay = Image.new("RGB", sub.size, NO_GO_TINT[:3])
    sub = Image.blend(sub, overlay, NO_GO_TINT[3] / 255)
    d = ImageDraw.Draw(sub)
    w, h = sub.size
    for c in range(-h, w, 8):
        d.line([(c, h), (c + h, 0)], fill=NO_GO_HATCH, width=2)
    d.rectangle([0, 0, w - 1, h - 1], outline=NO_GO_HATCH, width=2)
    img.paste(sub, box[:2])


def _swatch_bump(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    _swatch_tint(BUMP_REACH_TINT)(img, box)
    d = ImageDraw.Draw(img)
    y = (box[1] + box[3]) / 2
    line = np.array([[box[0], y], [box[2], y]], dtype=float)
    d.line(_flat(line), fill=BUMP_YELLOW, width=7)
    dashed_line(d, line, BUMP_BLACK, width=7, on=5, off=5)


def _swatch_tint(tint: tuple[int, int, int, int]):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        ImageDraw.Draw(img, "RGBA").rectangle(box, fill=ASPHALT)
        ImageDraw.Draw(img, "RGBA").rectangle(box, fill=tint, outline=tint[:3])

    return paint


def _swatch_triangle(color: Color):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        c = np.array([(box[0] + box[2]) / 2, (box[1] + box[3]) / 2])
        tri = triangle_polygon(c, 0.0, min(box[2] - box[0], box[3] - box[1]) * 1.25)
        ImageDraw.Draw(img).polygon(_flat(tri), fill=color, outline=(0, 0, 0))

    return paint


def _swatch_car(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    x0, y0, x1, y1 = box
    d.rectangle([x0 + 1, y0 + 2, x1 - 1, y1 - 2], fill=PARKED_CAR, outline=PARKED_CAR_EDGE)
    w = x1 - x0
    d.rectangle([x0 + 0.6 * w, y0 + 3, x0 + 0.78 * w, y1 - 3], fill=PARKED_CAR_FRONT)


def _swatch_graph(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    x0, y0, x1, y1 = box
    y = (y0 + y1) / 2
    d.rectangle(box, fill=ASPHALT)
    d.line([(x0 + 3, y), (x1 - 3, y)], fill=GRAPH_EDGE["lane"], width=1)
    for x in (x0 + 4, x1 - 4):
        d.ellipse([x - 2.5, y - 2.5, x + 2.5, y + 2.5], fill=GRAPH_NODE, outline=(0, 0, 0))


def _swatch_link(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    d = ImageDraw.Draw(img)
    x0, y0, x1, y1 = box
    d.rectangle(box, fill=ASPHALT)
    y = (y0 + y1) / 2
    dashed_line(d, np.array([[x0 + 3, y], [x1 - 3, y]]), GRAPH_EDGE["park"], on=2, off=3)
    d.line([(x0 + 3, y - 5), (x1 - 3, y + 5)], fill=GRAPH_EDGE["turn"], width=1)


def _legend_entries(lot_graph, lot, show_graph: bool) -> list[_Entry]:
    out = [_Entry("aisle, lane direction", _swatch_arrow)]
    kinds = {s.kind for s in lot.slots}
    for kind in ("perpendicular", "parallel", "angled"):
        if kind in kinds:
            out.append(_Entry(f"{kind} slot", _swatch_slot(SLOT_LINE[kind])))
    if lot.occupied:
        out.append(_Entry("parked car", _swatch_car))
    area_kinds = {a.kind for a in lot.areas}
    if "wall" in area_kinds:
        out.append(_Entry("wall", _swatch_rect(WALL)))
    if "obstacle" in area_kinds:
        out.append(_Entry("obstacle", _swatch_rect(OBSTACLE, OBSTACLE_EDGE, 2)))
    if "no_go" in area_kinds:
        out.append(_Entry("no-go zone", _swatch_hatch))
    sources = {z.source for z in lot.zones}
    if "bump" in sources:
        out.append(_Entry("speed bump, its reach", _swatch_bump))
    if "zone" in sources:
        out.append(_Entry("speed zone", _swatch_tint(ZONE_TINT)))
    if lot.entrances:
        out.append(_Entry("entrance", _swatch_triangle(ENTRANCE)))
    if lot.exits:
        out.append(_Entry("exit", _swatch_triangle(EXIT)))
    if show_graph and lot_graph is not None:
        out.append(_Entry("graph node, lane edge", _swatch_graph))
        out.append(_Entry("turn, park link", _swatch_link))
    return out


_SW, _ROW, _PAD = 26, 18, 8  # swatch width, row height, legend padding [px]


class _Legend:
    """The legend box: a summary line, one row per entry, then the scale bar."""

    def __init__(self, entries: list[_Entry], summary: str):
        self.entries = entries
        self.summary = summary
        self.font = font(12)
        self.text_w = max([text_size(e.label, self.font)[0] for e in entries] + [0])
        self.col_w = _SW + 6 + self.text_w + 14
        self.summary_w = text_size(summary, self.font)[0]

    def size(self, columns: int) -> tuple[int, int]:
        rows = math.ceil(len(self.entries) / columns)
        w = max(columns * self.col_w - 14, self.summary_w, 150) + 2 * _PAD
        h = 2 * _PAD + _ROW + rows * _ROW + 8 + 30  # summary, rows, gap, scale bar
        return int(w), int(h)

    def columns_for(self, width: float) -> int:
        """The fewest columns that make the fewest rows within ``width`` px."""
        n = max(len(self.entries), 1)
        cols = int(max(1, min(n, (width - 2 * _PAD + 14) // self.col_w)))
        return math.ceil(n / math.ceil(n / cols))

    def paint(self, img: Image.Image, x: int, y: int, columns: int, canvas: LotCanvas) -> None:
        w, h = self.size(columns)
        d = ImageDraw.Draw(img)
        d.rectangle([x, y, x + w, y + h], fill=(255, 255, 255), outline=(90, 90, 90))
        draw_text(d, (x + _PAD, y + _PAD + _ROW / 2), self.summary, self.font, anchor="lm")
        rows = math.ceil(len(self.entries) / columns)
        for i, e in enumerate(self.entries):
            cx = x + _PAD + (i // rows) * self.col_w
            cy = y + _PAD + _ROW * (1 + i % rows)
            e.swatch(img, (cx, cy + 2, cx + _SW, cy + _ROW - 3))
            draw_text(d, (cx + _SW + 6, cy + _ROW / 2), e.label, self.font, anchor="lm")
        paint_scale_bar(img, canvas, x + _PAD, y + h - _PAD - 6, w - 2 * _PAD)


def _nice_length(max_m: float) -> float:
    """The largest 1-2-5 length not above ``max_m`` [m] (at least 0.1 m)."""
    best = 0.1
    for e in range(-1, 6):
        for m in (1, 2, 5):
            v = m * 10.0**e
            if v <= max_m:
                best = v
    return best


def paint_scale_bar(img: Image.Image, canvas: LotCanvas, x: float, y: float, width: float) -> None:
    """A black/white bar of a round length with its value, bottom-left at (x, y)."""
    d = ImageDraw.Draw(img)
    f = font(12)
    metres = _nice_length((min(width, 260) - 50) / canvas.scale)
    length = canvas.px(metres)
    parts = 5 if metres >= 5 and length >= 50 else 2
    for k in range(parts):
        x0, x1 = x + k * length / parts, x + (k + 1) * length / parts
        d.rectangle([x0, y - 6, x1, y], fill=(0, 0, 0) if k % 2 == 0 else (255, 255, 255),
                    outline=(0, 0, 0))
    label = f"{metres:g} m"
    draw_text(d, (x + length + 6, y - 3), label, f, anchor="lm")
    draw_text(d, (x, y - 9), "0", f, anchor="mb")


def _grid(img: Image.Image, canvas: LotCanvas, step: float) -> None:
    """Faint world grid every ``step`` metres with coordinates along the left and top."""
    d = ImageDraw.Draw(img, "RGBA")
    f = font(10)
    left, top, right, bottom = canvas.drawing_box
    minx, miny, maxx, maxy = canvas.bounds
    for gx in np.arange(math.ceil(minx / step) * step, maxx + 1e-9, step):
        px = canvas.to_px([gx, 0.0])[0]
        d.line([(px, top), (px, bottom)], fill=(0, 0, 0, 40))
        draw_text(d, (px, top - 2), f"{gx:g}", f, anchor="mb")
    for gy in np.arange(math.ceil(miny / step) * step, maxy + 1e-9, step):
        py = canvas.to_px([0.0, gy])[1]
        d.line([(left, py), (right, py)], fill=(0, 0, 0, 40))
        draw_text(d, (left - 3, py), f"{gy:g}", f, anchor="rm")


# -- public API --------------------------------------------------------------------------------
@dataclass(frozen=True)
class Layout:
    """Where the lot, the title and the legend go in an image."""

    canvas: LotCanvas
    title_xy: tuple[int, int] | None
    legend_xy: tuple[int, int] | None
    legend_columns: int
    legend: _Legend | None = None


def plan_layout(
    bounds: Sequence[float],
    size: tuple[int, int],
    *,
    title: str | None = None,
    legend: _Legend | None = None,
    margin: int = PAD_PX,
) -> Layout:
    """Put the legend right of or under the lot, whichever draws the lot larger.

    The title, the lot and the legend are then centred as one group.
    """
    w, h = int(size[0]), int(size[1])
    m = margin
    th = 28 if title else 0
    bw = max(bounds[2] - bounds[0], 1e-9)
    bh = max(bounds[3] - bounds[1], 1e-9)

    def fit(avail_w: float, avail_h: float) -> float:
        return min(max(avail_w, 1.0) / bw, max(avail_h, 1.0) / bh)

    options = []  # (scale, mode, columns)
    if legend is not None:
        lw, lh = legend.size(1)
        if lw + 3 * m < 0.5 * w and lh + th + 2 * m <= h:
            options.append((fit(w - 3 * m - lw, h - 2 * m - th), "right", 1))
        cols = legend.columns_for(w - 2 * m)
        lw, lh = legend.size(cols)
        if lh + th + 3 * m < 0.5 * h and lw + 2 * m <= w:
            options.append((fit(w - 2 * m, h - 3 * m - th - lh), "bottom", cols))
    if not options:
        options.append((fit(w - 2 * m, h - 2 * m - th), None, 1))
    scale, mode, cols = max(options, key=lambda o: o[0])  # first of equals
    lot_w, lot_h = bw * scale, bh * scale
    lw, lh = legend.size(cols) if (legend is not None and mode) else (0, 0)
    if mode == "right":
        gx = m + (w - 2 * m - (lot_w + m + lw)) / 2
        gy = m + (h - 2 * m - (th + lot_h)) / 2
        frame = (gx, gy + th, gx + lot_w, gy + th + lot_h)
        legend_xy = (int(gx + lot_w + m), int(max(m, min(gy + th, h - m - lh))))
    elif mode == "bottom":
        gx = m + (w - 2 * m - lot_w) / 2
        gy = m + (h - 2 * m - (th + lot_h + m + lh)) / 2
        frame = (gx, gy + th, gx + lot_w, gy + th + lot_h)
        legend_xy = (int(max(m, min(gx, w - m - lw))), int(gy + th + lot_h + m))
    else:
        gx = m + (w - 2 * m - lot_w) / 2
        gy = m + (h - 2 * m - (th + lot_h)) / 2
        frame = (gx, gy + th, gx + lot_w, gy + th + lot_h)
        legend_xy = None
    canvas = LotCanvas(bounds, size, frame)
    title_x = min(gx, legend_xy[0]) if legend_xy else gx
    title_xy = (int(max(m, title_x)), int(max(m // 2, gy))) if title else None
    return Layout(canvas, title_xy, legend_xy, cols, legend if legend_xy else None)


def lot_layout(
    lot_graph,
    *,
    size: tuple[int, int] = (1200, 900),
    show_graph: bool = False,
    title: str | None = None,
    legend: bool = True,
) -> Layout:
    """The layout :func:`draw_lot` uses with the same arguments; ``.canvas`` maps
    world points to the pixels of that image."""
    lot = getattr(lot_graph, "lot", lot_graph)
    box = None
    if legend:
        n = len(lot.slots)
        na = len(lot.aisles)
        summary = (f"{n} slot{'s' * (n != 1)}, {len(lot.occupied)} taken, "
                   f"{na} aisle{'s' * (na != 1)}")
        box = _Legend(_legend_entries(lot_graph, lot, show_graph), summary)
    return plan_layout(lot_bounds(lot), size, title=title, legend=box)


def draw_lot(
    lot_graph,
    *,
    size: tuple[int, int] = (1200, 900),
    show_graph: bool = False,
    parked_vehicle=None,
    labels: bool = True,
    title: str | None = None,
    legend: bool = True,
    grid: float | None = None,
) -> Image.Image:
    """Draw a built lot as an RGB image.

    Parameters
    ----------
    lot_graph : LotGraph
        The lot and its graph (a bare :class:`~lotsim.lot.model.Lot` works
        when ``show_graph`` is false).
    size : (width, height), keyword-only
        Image size [px].
    show_graph : bool
        Also draw the graph's edges (placeholder park/leave links dotted) and nodes.
    parked_vehicle : VehicleType or None
        The car drawn in slots taken at start; ``None`` draws a 4.5 m × 1.8 m box.
    labels : bool
        Draw slot ids (where they fit), entrance/exit ids and speed limits.
    title : str or None
        Heading at the top, e.g. the scenario name.
    legend : bool
        Draw the legend box with the scale bar.
    grid : float or None
        Spacing of a faint coordinate grid [m]; ``None`` draws none.

    Returns
    -------
    PIL.Image.Image
    """
    lot = getattr(lot_graph, "lot", lot_graph)
    if show_graph and not hasattr(lot_graph, "graph"):
        raise TypeError("show_graph needs a LotGraph, not a bare Lot")
    layout = lot_layout(lot_graph, size=size, show_graph=show_graph, title=title, legend=legend)
    canvas, box = layout.canvas, layout.legend
    img = canvas.new_image()
    paint_lot(img, canvas, lot, parked_vehicle=parked_vehicle, labels=False)
    if show_graph:
        paint_graph(img, canvas, lot_graph)
    if labels:
        paint_labels(img, canvas, lot, slot_shift=0.3 if show_graph else 0.0)
    paint_portals(img, canvas, lot, labels=labels)
    if grid:
        _grid(img, canvas, float(grid))
    if title and layout.title_xy is not None:
        d = ImageDraw.Draw(img)
        draw_text(d, layout.title_xy, title, font(18), anchor="lt")
    if box is not None and layout.legend_xy is not None:
        box.paint(img, *layout.legend_xy, layout.legend_columns, canvas)
    return img


def save_lot_png(lot_graph, path: str | os.PathLike, **kwargs) -> None:
    """Draw the lot (keywords as :func:`draw_lot`) and write it to ``path`` as PNG.

    The file is written to a temporary file in the same directory and moved
    into place, so ``path`` is never left half-written.
    """
    save_png(draw_lot(lot_graph, **kwargs), path)


def save_png(img: Image.Image, path: str | os.PathLike) -> None:
    """Write ``img`` to ``path`` as PNG through a temporary file in the same directory,
    so ``path`` is never left half-written."""
    with atomic_write(path) as fh:
        img.save(fh, format="PNG")
