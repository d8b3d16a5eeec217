"""The colours of a run's pictures and their key, shared by the GIF
(:mod:`lotsim.render.animation`) and the HTML replay (:mod:`lotsim.render.html`): the cars'
colours (:func:`vehicle_palette`, each also :func:`pale`), those of what is drawn on and
around the cars, the entries of the key (:data:`LEGEND`, :func:`legend_entries`), and the
key in the GIF's footer (:func:`paint_key`), each swatch drawn as the frames draw what it
names.
"""

from __future__ import annotations

import colorsys
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from typing import Any

from PIL import Image, ImageDraw

from lotsim.render.lot_image import PAD_PX
from lotsim.render.replay import MET_KINDS

VEHICLE_COLOURS = 16
"""Distinct vehicle colours (each also in a pale version, for parked cars and trails).

The palette is kept short on purpose: given a palette, Pillow's GIF writer matches it to
each frame colour by colour in Python, at a cost that grows with the cube of its length:
with a palette of some 90 colours that matching costs more than drawing the frame."""
INK = (25, 25, 25)
GLASS = (40, 48, 60)
WHITE = (255, 255, 255)
TYRE = (15, 15, 15)
CLOSED = (205, 70, 40)
"""Closed ground (an aisle or gate closed over an interval) is hatched and outlined in
this (a stalled car is ringed in white on ink)."""
HATCH = 7
"""Spacing of the closed ground's hatching [px]."""
KEY_SWATCH, KEY_GAP = 18, 12
"""Width of a swatch of the key and the gap between its entries [px]."""
LEGEND = (("driving", "car"), ("parked", "pale"), ("parked at start", "start"),
          ("reversing", "reversing"), ("its slot", "slot"), ("stalled", "stalled"),
          ("closed", "closed"), ("bay taken", "taken"))
"""The colour key of a run's pictures, in order (the GIF's footer, the HTML replay's bar):
each label with what its swatch shows: a car in its own colour, in the pale version, a car
parked at the start, a car with the white rear band, a slot outlined in a car's colour; and
what a run met (:data:`~lotsim.render.replay.MET_KINDS`): a car ringed in white on ink
(stalled), hatched ground (closed), the dark car of a bay taken from outside."""
LEGEND_CARS = 3
"""Cars' colours shown side by side in the swatches of cars drawn in their own colour
(driving, parked, stalled): each car has its own colour, and a swatch of one would say that
"driving" is that colour."""

Stamp = Callable[[Image.Image, tuple[int, int], str, Any], int]
"""Pastes a text in ink at a point of an image, vertically centred on it, in a font;
returns its advance [px]."""


def legend_entries(parked_at_start: bool, met: Collection[str] = ()) -> list[tuple[str, str]]:
    """:data:`LEGEND` for a run: "parked at start" only when some car is, and what the run
    met only when it did (``met``: some of :data:`~lotsim.render.replay.MET_KINDS`, as
    :attr:`MetDisturbances.kinds <lotsim.render.replay.MetDisturbances.kinds>`).

    Examples
    --------
    >>> [label for label, _ in legend_entries(False, {"closed"})]
    ['driving', 'parked', 'reversing', 'its slot', 'closed']
    """
    return [(label, kind) for label, kind in LEGEND
            if (kind != "start" or parked_at_start) and (kind not in MET_KINDS or kind in met)]


def vehicle_palette(n: int = VEHICLE_COLOURS) -> list[tuple[int, int, int]]:
    """``n`` saturated colours, consecutive ones far apart in hue and brightness, none
    close to the asphalt grey or the blue of cars parked at start (hue ~0.59)."""
    out: list[tuple[int, int, int]] = []
    k = 0
    while len(out) < n:
        hue = (k * 0.618034 + 0.02) % 1.0
        k += 1
        if 0.53 < hue < 0.66:
            continue
        m = len(out)
        sat = (1.0, 0.8, 0.9)[m % 3]
        val = (1.0, 0.85, 0.95, 0.75)[(m // 3) % 4]
        r, g, b = colorsys.hsv_to_rgb(hue, sat, val)
        out.append((int(r * 255), int(g * 255), int(b * 255)))
    return out


def pale(c: tuple[int, int, int], amount: float = 0.55) -> tuple[int, int, int]:
    """``c`` mixed with white."""
    return tuple(int(round(v + (255 - v) * amount)) for v in c)  # type: ignore[return-value]


# -- the GIF's key -----------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class KeyInks:
    """The palette indices of a GIF's key: those its frames draw cars and marks in."""

    ink: int
    white: int
    tyre: int
    closed: int
    cars: tuple[int, ...]
    """Each car colour (:func:`vehicle_palette`'s order)."""
    pales: tuple[int, ...]
    """The pale version of each."""
    at_start: int | None
    """The colour cars parked at the start are drawn in; None when there are none."""


def scale_bar_width(width: int) -> int:
    """The longest scale bar in the footer of a frame ``width`` px wide [px]."""
    return min(260, width // 3)


def key_room(width: int) -> int:
    """Pixel width the key's bottom line has in a frame ``width`` px wide: right of the
    scale bar."""
    return width - PAD_PX - (PAD_PX + scale_bar_width(width) + 40)


def key_width(entries: Sequence[tuple[str, str]], font) -> int:
    """Pixel width of the key's ``entries`` on one line, their labels in ``font``."""
    widths = [KEY_SWATCH + 4 + int(round(font.getlength(label))) for label, _ in entries]
    return sum(widths) + KEY_GAP * max(0, len(widths) - 1)


def paint_key(img: Image.Image, entries: Sequence[tuple[str, str]], inks: KeyInks, *,
              font, stamp: Stamp, line_height: int, two_lines: bool = False
              ) -> dict[str, tuple[int, int, int, int]]:
    """The key of ``entries`` (:func:`legend_entries`) in the footer of the frame ``img``,
    right-aligned, right of the scale bar: cars in their own colours (driving or waiting),
    in the pale versions (parked), a car parked at the start (when there are some),
    reversing (white rear band), the slot a car is heading for (outlined in its colour);
    and what the run met, when it did: a stalled car (ringed in white on ink), closed ground
    (hatched), the car in a bay taken from outside. The footer's lines are ``line_height``
    px high; with ``two_lines`` the cars' entries take the upper line, the whole width, and
    what the run met the lower one. Entries that do not fit are left out from the last.
    Labels are written with ``stamp``. Returns each label's swatch box."""
    w, h = img.size
    bottom = h - line_height // 2 - 1
    if two_lines:
        lines = [([e for e in entries if e[1] not in MET_KINDS], bottom - line_height,
                  w - 2 * PAD_PX),
                 ([e for e in entries if e[1] in MET_KINDS], bottom, key_room(w))]
    else:
        lines = [(list(entries), bottom, key_room(w))]
    boxes: dict[str, tuple[int, int, int, int]] = {}
    d = ImageDraw.Draw(img)
    for line, mid, room in lines:
        while line and key_width(line, font) > room:
            line = line[:-1]
        x = w - PAD_PX - key_width(line, font)
        for label, kind in line:
            boxes[label] = paint_swatch(d, x, mid, kind, inks)
            stamp(img, (x + KEY_SWATCH + 4, mid), label, font)
            x += KEY_SWATCH + 4 + int(round(font.getlength(label))) + KEY_GAP
    return boxes


def paint_swatch(d: ImageDraw.ImageDraw, x: int, mid: int, kind: str, inks: KeyInks
                 ) -> tuple[int, int, int, int]:
    """One swatch of the key (:data:`LEGEND`'s ``kind``) from ``x``, centred on line
    ``mid``; returns its box."""
    sw = KEY_SWATCH
    car, pale_car = inks.cars[0], inks.pales[0]
    box = (x, mid - 5, x + sw, mid + 5)
    if kind == "slot":
        box = (x + 4, mid - 7, x + sw - 4, mid + 7)
        d.rectangle(box, outline=car, width=2)
    elif kind == "closed":
        x0, y0, x1, y1 = box
        for c in range(x0 + y0 + 3, x1 + y1, HATCH // 2 + 1):  # lines x + y = c, as the
            a, b = max(x0, c - y1), min(x1, c - y0)           # ground's, within the box
            d.line((a, c - a, b, c - b), fill=inks.closed, width=1)
        d.rectangle(box, outline=inks.closed, width=2)
    elif kind == "taken":
        d.rectangle(box, fill=inks.tyre, outline=inks.ink)
    else:
        fill = {"pale": pale_car, "start": inks.at_start}.get(kind, car)
        d.rectangle(box, fill=fill, outline=inks.ink)
        several = {"car": inks.cars, "pale": inks.pales, "stalled": inks.cars}.get(kind)
        if several is not None:
            cols = list(several[:LEGEND_CARS])
            step = (sw - 1) / len(cols)
            for k, c in enumerate(cols):
                d.rectangle((x + 1 + round(k * step), mid - 4,
                             x + round((k + 1) * step) - 1 + (k == len(cols) - 1),
                             mid + 4), fill=c)
        if kind == "reversing":
            d.rectangle((x + 1, mid - 4, x + 4, mid + 4), fill=inks.white)
        elif kind == "stalled":  # the ring a stalled car gets: white on an ink halo
            d.rectangle((x - 1, mid - 6, x + sw + 1, mid + 6), outline=inks.ink, width=2)
            d.rectangle((x + 1, mid - 4, x + sw - 1, mid + 4), outline=inks.white, width=1)
    return box
