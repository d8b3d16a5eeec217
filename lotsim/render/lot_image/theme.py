"""Colours, sizes and text of the lot pictures (:mod:`lotsim.render.lot_image`)."""

from __future__ import annotations

from functools import lru_cache

from PIL import ImageDraw, ImageFont

Color = tuple[int, int, int]

# -- palette -----------------------------------------------------------------------------------
BACKGROUND: Color = (246, 246, 242)
"""Outside the lot."""
GROUND: Color = (200, 207, 190)
"""Unpaved ground inside the boundary (a verge, a planted island)."""
PAVED: Color = (150, 152, 157)
"""Paved ground that is neither aisle nor slot (all of it in a lot paved wall to wall)."""
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
ACCESS_AISLE: Color = (40, 110, 220)
"""The hatching of an access aisle beside an accessible bay (the blue of its marking)."""
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
    "turnaround": (150, 255, 60),  # multi-point turns: dead ends and small junctions
}
GRAPH_NODE: Color = (0, 240, 255)
SLOT_NODE: Color = (255, 150, 0)
TEXT: Color = (25, 25, 25)
HALO: Color = (255, 255, 255)

DEFAULT_PARKED = (4.5, 1.8)
"""Length and width [m] of the car drawn in taken slots when no vehicle type is given."""
PAD_PX = 14
"""Free pixels around the drawing and between panels [px] (not
:data:`lotsim.maneuvers.settings.MARGIN`, the planner's safety margin in metres)."""


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
