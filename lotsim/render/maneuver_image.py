"""A picture of one parking maneuver over its part of the lot (``lotsim maneuver -o``)."""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw

from lotsim.render.lot_image import (
    PAD_PX,
    TEXT,
    LotCanvas,
    _flat,
    draw_text,
    font,
    paint_labels,
    paint_lot,
    paint_portals,
    text_size,
)

FORWARD = (30, 120, 255)
"""Strokes driven forward."""
REVERSE = (255, 140, 0)
"""Strokes driven in reverse."""
CUSP = (220, 20, 60)
STEER = (128, 0, 160)
"""A ring where the car stands to turn its wheels."""
GHOST_EDGE = (245, 245, 245)
CAR_FILL = (250, 250, 250)
START_EDGE = (0, 170, 190)
"""Outline of the car where it stands in the lane (start of a way in, end of a way out)."""
PARKED_EDGE = (225, 0, 140)
"""Outline of the car standing in the slot."""
BAND = (250, 250, 248)
"""Opaque background of the title and key bands."""
BAND_EDGE = (200, 200, 200)
TITLE_BAND = 34
"""Pixel height of the title band (when there is a title)."""
KEY_BAND = 30
"""Pixel height of the key band at the bottom."""


def draw_maneuver(
    lot,  # a Lot
    maneuver,  # a Maneuver
    vehicle,  # the VehicleType it was planned for
    *,
    parked_vehicle=None,
    size: tuple[int, int] = (900, 700),
    every: float = 1.0,
    title: str | None = None,
) -> Image.Image:
    """Draw ``maneuver`` zoomed onto the lot around it.

    The path of the rear-axle centre is drawn blue where the car drives forward
    and orange in reverse, with a red dot at each cusp and a purple ring where the
    car stands to turn its wheels (at the start, at cusps, at the end, and wherever
    the curvature jumps); the car's outline every ``every`` metres of travel [m],
    and solid at the start and the end, edged and tagged ("start", "parked"; "parked",
    "end" for a way out). The title and the key sit in opaque bands above and below
    the drawing. The two solid outlines carry a triangle pointing to the car's front, and
    slot ids are drawn over the path.
    """
    poses, gears = maneuver.sample(0.05)
    bodies = vehicle.footprints(poses)
    w_img, h_img = size
    top = TITLE_BAND if title else 0
    bottom = h_img - KEY_BAND
    canvas = maneuver_canvas(maneuver, vehicle, size=size, title=bool(title))
    img = canvas.new_image()
    paint_lot(img, canvas, lot, parked_vehicle=parked_vehicle, labels=False)
    paint_portals(img, canvas, lot, labels=False)
    draw = ImageDraw.Draw(img, "RGBA")
    travelled = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(poses[:, :2], axis=0).T))])
    marks = np.unique(np.searchsorted(travelled, np.arange(0.0, travelled[-1], every)))
    for k in marks[1:]:
        draw.polygon(_flat(canvas.to_px(bodies[k])), outline=GHOST_EDGE + (170,), width=1)
    ends = end_marks(maneuver)
    edge = max(3, int(round(canvas.px(0.08))))
    for k, (_, color) in zip((0, len(bodies) - 1), ends, strict=True):
        draw.polygon(_flat(canvas.to_px(bodies[k])), fill=CAR_FILL + (150,),
                     outline=color, width=edge)
    px = canvas.to_px(poses[:, :2])
    w = max(2, int(round(canvas.px(0.12))))
    for a in range(len(px) - 1):
        color = FORWARD if gears[a + 1] > 0 else REVERSE
        draw.line(_flat(px[a : a + 2]), fill=color, width=w)
    r = max(3, int(round(canvas.px(0.18))))
    for x, y, _ in maneuver.cusps:
        cx, cy = canvas.to_px(np.array([x, y]))
        draw.ellipse((cx - r, cy - r, cx + r, cy + r), fill=CUSP, outline=(255, 255, 255))
    ring = r + max(2, w)
    for (x, y, _), _ in maneuver.motion(vehicle).steering_stops:
        cx, cy = canvas.to_px(np.array([x, y]))
        draw.ellipse((cx - ring, cy - ring, cx + ring, cy + ring), outline=STEER,
                     width=max(2, w // 2 + 1))
    for k, (_, color) in zip((0, len(bodies) - 1), ends, strict=True):  # over the path
        draw.polygon(_flat(canvas.to_px(nose(bodies[k]))), fill=color)
    paint_labels(img, canvas, lot)  # over the path: a slot's id stays readable
    d = ImageDraw.Draw(img)
    f = font(14)
    frame = (PAD_PX, top + PAD_PX, w_img - PAD_PX, bottom - PAD_PX)
    placed: list[tuple[float, float, float, float]] = []
    for k, (label, color) in zip((0, len(bodies) - 1), ends, strict=True):
        placed.append(_label_car(d, canvas.to_px(bodies[k]), label, color, f, frame, placed))
    # title and key in opaque bands above and below the lot, never on its drawing
    if title:
        d.rectangle((0, 0, w_img - 1, top - 1), fill=BAND)
        d.line((0, top - 1, w_img - 1, top - 1), fill=BAND_EDGE)
        draw_text(d, (PAD_PX, top / 2), title, font(18), anchor="lm")
    d.rectangle((0, bottom, w_img - 1, h_img - 1), fill=BAND)
    d.line((0, bottom, w_img - 1, bottom), fill=BAND_EDGE)
    key = [("forward", FORWARD, "line"), ("reverse", REVERSE, "line"), ("cusp", CUSP, "dot"),
           ("stops to steer", STEER, "ring")]
    key += [(label, color, "car") for label, color in ends]
    x = PAD_PX
    mid = bottom + KEY_BAND // 2
    fk = font(13)
    for label, color, kind in key:
        if kind == "line":
            d.rectangle((x, mid - 3, x + 22, mid + 3), fill=color)
        elif kind == "dot":
            d.ellipse((x + 6, mid - 5, x + 16, mid + 5), fill=color)
        elif kind == "ring":
            d.ellipse((x + 4, mid - 7, x + 18, mid + 7), outline=color, width=3)
        else:
            d.rectangle((x, mid - 6, x + 22, mid + 6), fill=CAR_FILL, outline=color, width=3)
        _, right = _text_on_line(d, x + 30, mid, label, fk)
        x = right + 22
    return img


def nose(body: np.ndarray) -> np.ndarray:
    """A triangle (3, 2) inside a car's outline (4, 2: rear right, front right, front
    left, rear left, as ``footprints`` gives them) pointing forward, its base a third of
    the car's length behind the front: which end is the front."""
    rear_mid = (body[0] + body[3]) / 2
    front_r, front_l = body[1], body[2]
    front_mid = (front_l + front_r) / 2
    base = front_mid + (rear_mid - front_mid) / 3
    half = (front_r - front_l) / 2 * 0.6
    return np.array([base - half, base + half, front_mid + (base - front_mid) * 0.1])


def maneuver_canvas(
    maneuver,  # a Maneuver
    vehicle,
    *,
    size: tuple[int, int] = (900, 700),
    title: bool = False,
) -> LotCanvas:
    """The world-to-pixel mapping :func:`draw_maneuver` uses: the car's swept area and
    3 m around it, between the title band (when there is a title) and the key band."""
    bodies = vehicle.footprints(maneuver.sample(0.05)[0])
    lo = bodies.reshape(-1, 2).min(axis=0) - 3.0
    hi = bodies.reshape(-1, 2).max(axis=0) + 3.0
    top = TITLE_BAND if title else 0
    return LotCanvas((lo[0], lo[1], hi[0], hi[1]), size,
                     frame=(PAD_PX, top + PAD_PX, size[0] - PAD_PX, size[1] - KEY_BAND - PAD_PX))


def end_marks(maneuver) -> list[tuple[str, tuple[int, int, int]]]:
    """Label and outline colour of the car at the maneuver's first and last pose."""
    if getattr(maneuver, "leaving", False):
        return [("parked", PARKED_EDGE), ("end", START_EDGE)]
    return [("start", START_EDGE), ("parked", PARKED_EDGE)]


def _text_on_line(d: ImageDraw.ImageDraw, x: float, mid: float, text: str, f,
                  fill: tuple[int, int, int] = TEXT) -> tuple[float, float]:
    """Draw ``text`` from ``x`` with its x-height centred on ``mid``, so that labels with
    and without ascenders or descenders share one baseline; returns (left, right) [px]."""
    ref = f.getbbox("x")
    left, _, right, _ = f.getbbox(text)
    y = mid - (ref[1] + ref[3]) / 2
    d.text((x - left, y), text, font=f, fill=fill)
    return x, x + (right - left)


def _label_car(d: ImageDraw.ImageDraw, corners: np.ndarray, label: str,
               color: tuple[int, int, int], f, frame: tuple[float, float, float, float],
               placed: list[tuple[float, float, float, float]]
               ) -> tuple[float, float, float, float]:
    """Write ``label`` just above (else below) the car outline ``corners`` (pixels), on a
    white tag edged in ``color``, inside ``frame`` and off the tags in ``placed``."""
    tw, th = text_size(label, f)
    (x0, y0), (x1, y1) = corners.min(axis=0), corners.max(axis=0)
    cx = (x0 + x1) / 2
    options = [(cx, y0 - th / 2 - 8), (cx, y1 + th / 2 + 8), (cx, (y0 + y1) / 2)]
    hw, hh = tw / 2 + 5, th / 2 + 4

    def box(c: tuple[float, float]) -> tuple[float, float, float, float]:
        x = min(max(c[0], frame[0] + hw), frame[2] - hw)
        y = min(max(c[1], frame[1] + hh), frame[3] - hh)
        return (x - hw, y - hh, x + hw, y + hh)

    def fits(c: tuple[float, float]) -> bool:
        b = box(c)
        return not any(b[0] < q[2] and q[0] < b[2] and b[1] < q[3] and q[1] < b[3]
                       for q in placed)

    chosen = box(next((c for c in options if fits(c)), options[0]))
    d.rectangle(chosen, fill=CAR_FILL, outline=color, width=2)
    draw_text(d, ((chosen[0] + chosen[2]) / 2, (chosen[1] + chosen[3]) / 2), label, f,
              anchor="mm")
    return chosen
