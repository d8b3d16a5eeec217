"""A picture of one parking maneuver over its part of the lot (``lotsim maneuver -o``)."""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw

from lotsim.render.lot_image import (
    MARGIN,
    LotCanvas,
    _flat,
    draw_text,
    font,
    paint_lot,
    paint_portals,
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


def draw_maneuver(
    lot,  # noqa: ANN001 - a Lot
    maneuver,  # noqa: ANN001 - a Maneuver
    vehicle,  # noqa: ANN001 - the VehicleType it was planned for
    *,
    parked_vehicle=None,  # noqa: ANN001
    size: tuple[int, int] = (900, 700),
    every: float = 1.0,
    title: str | None = None,
) -> Image.Image:
    """Draw ``maneuver`` zoomed onto the lot around it.

    The path of the rear-axle centre is drawn blue where the car drives forward
    and orange in reverse, with a red dot at each cusp and a purple ring where the
    car stands to turn its wheels (at the start, at cusps, at the end, and wherever
    the curvature jumps); the car's outline every ``every`` metres of travel [m],
    and solid at the start and the end.
    """
    poses, gears = maneuver.sample(0.05)
    bodies = vehicle.footprints(poses)
    lo = bodies.reshape(-1, 2).min(axis=0) - 3.0
    hi = bodies.reshape(-1, 2).max(axis=0) + 3.0
    top = 34 if title else 0
    canvas = LotCanvas((lo[0], lo[1], hi[0], hi[1]), size,
                       frame=(MARGIN, MARGIN + top, size[0] - MARGIN, size[1] - MARGIN))
    img = canvas.new_image()
    paint_lot(img, canvas, lot, parked_vehicle=parked_vehicle, labels=True)
    paint_portals(img, canvas, lot, labels=False)
    draw = ImageDraw.Draw(img, "RGBA")
    travelled = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(poses[:, :2], axis=0).T))])
    marks = np.unique(np.searchsorted(travelled, np.arange(0.0, travelled[-1], every)))
    for k in marks[1:]:
        draw.polygon(_flat(canvas.to_px(bodies[k])), outline=GHOST_EDGE + (170,), width=1)
    for k in (0, len(bodies) - 1):
        draw.polygon(_flat(canvas.to_px(bodies[k])), fill=CAR_FILL + (150,),
                     outline=(20, 20, 20), width=2)
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
    d = ImageDraw.Draw(img)
    if title:
        draw_text(d, (MARGIN, MARGIN), title, font(18), anchor="lt")
    key = [("forward", FORWARD), ("reverse", REVERSE), ("cusp", CUSP),
           ("stops to steer", STEER)]
    x = MARGIN
    y = size[1] - MARGIN - 16
    for label, color in key:
        d.rectangle((x, y + 3, x + 22, y + 11), fill=color)
        draw_text(d, (x + 28, y), label, font(13), anchor="lt")
        x += 110
    return img
