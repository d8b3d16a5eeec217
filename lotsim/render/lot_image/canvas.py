"""World coordinates to pixels, and the drawing primitives of the lot pictures."""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence

import numpy as np
from PIL import Image, ImageDraw

from lotsim.render.lot_image.theme import (
    BACKGROUND,
    DEFAULT_PARKED,
    PAD_PX,
    PARKED_CAR,
    PARKED_CAR_EDGE,
    PARKED_CAR_FRONT,
    Color,
)


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
