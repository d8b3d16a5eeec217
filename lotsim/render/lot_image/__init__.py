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

import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from PIL import Image, ImageDraw

from lotsim.core.atomic import atomic_write
from lotsim.render.lot_image.canvas import LotCanvas, lot_bounds
from lotsim.render.lot_image.canvas import _flat as _flat
from lotsim.render.lot_image.canvas import _rings as _rings
from lotsim.render.lot_image.canvas import centered_footprints as centered_footprints
from lotsim.render.lot_image.canvas import paint_footprints as paint_footprints
from lotsim.render.lot_image.layers import _kmh as _kmh
from lotsim.render.lot_image.layers import _lane_width as _lane_width
from lotsim.render.lot_image.layers import (
    _slot_label_spots,
    paint_graph,
    paint_labels,
    paint_lot,
    paint_portals,
)
from lotsim.render.lot_image.legend import _Entry, _grid, _Legend, _legend_entries
from lotsim.render.lot_image.legend import paint_scale_bar as paint_scale_bar

# re-exported: the names other modules and the tests take from here
from lotsim.render.lot_image.theme import ARROW as ARROW
from lotsim.render.lot_image.theme import ARROW_EDGE as ARROW_EDGE
from lotsim.render.lot_image.theme import ASPHALT as ASPHALT
from lotsim.render.lot_image.theme import BACKGROUND as BACKGROUND
from lotsim.render.lot_image.theme import BOUNDARY as BOUNDARY
from lotsim.render.lot_image.theme import BUMP_BLACK as BUMP_BLACK
from lotsim.render.lot_image.theme import BUMP_REACH_TINT as BUMP_REACH_TINT
from lotsim.render.lot_image.theme import BUMP_YELLOW as BUMP_YELLOW
from lotsim.render.lot_image.theme import ENTRANCE as ENTRANCE
from lotsim.render.lot_image.theme import EXIT as EXIT
from lotsim.render.lot_image.theme import GRAPH_EDGE as GRAPH_EDGE
from lotsim.render.lot_image.theme import GROUND as GROUND
from lotsim.render.lot_image.theme import LANE_LINE as LANE_LINE
from lotsim.render.lot_image.theme import NO_GO_HATCH as NO_GO_HATCH
from lotsim.render.lot_image.theme import NO_GO_TINT as NO_GO_TINT
from lotsim.render.lot_image.theme import OBSTACLE as OBSTACLE
from lotsim.render.lot_image.theme import OBSTACLE_EDGE as OBSTACLE_EDGE
from lotsim.render.lot_image.theme import PAD_PX, draw_text, font
from lotsim.render.lot_image.theme import PARKED_CAR as PARKED_CAR
from lotsim.render.lot_image.theme import PARKED_CAR_EDGE as PARKED_CAR_EDGE
from lotsim.render.lot_image.theme import PARKED_CAR_FRONT as PARKED_CAR_FRONT
from lotsim.render.lot_image.theme import PAVED as PAVED
from lotsim.render.lot_image.theme import SLOT_LABEL as SLOT_LABEL
from lotsim.render.lot_image.theme import SLOT_LINE as SLOT_LINE
from lotsim.render.lot_image.theme import SLOT_PAVING as SLOT_PAVING
from lotsim.render.lot_image.theme import TEXT as TEXT
from lotsim.render.lot_image.theme import WALL as WALL
from lotsim.render.lot_image.theme import ZONE_TINT as ZONE_TINT
from lotsim.render.lot_image.theme import Color as Color
from lotsim.render.lot_image.theme import text_size as text_size


# -- public API --------------------------------------------------------------------------------
class Overlay(Protocol):
    """What a picture draws over the lot, and names in its legend (the service routes of
    ``lotsim show --routes``, :mod:`lotsim.render.route_image`)."""

    def bounds(self) -> tuple[float, float, float, float] | None:
        """The world rectangle [m] it needs beyond the lot's, or None."""

    def entries(self) -> list[_Entry]:
        """Its rows of the legend, after the lot's."""

    def paint(self, img: Image.Image, canvas: LotCanvas) -> None:
        """Draw it over the lot (under its labels, entrances and exits)."""


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
    overlay: Overlay | None = None,
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
        entries = _legend_entries(lot_graph, lot, show_graph)
        if overlay is not None:
            entries += overlay.entries()
        box = _Legend(entries, summary)
    bounds = lot_bounds(lot)
    more = overlay.bounds() if overlay is not None else None
    if more is not None:
        bounds = (min(bounds[0], more[0]), min(bounds[1], more[1]),
                  max(bounds[2], more[2]), max(bounds[3], more[3]))
    return plan_layout(bounds, size, title=title, legend=box)


def slot_labels_drawn(lot_graph, size: tuple[int, int], *, show_graph: bool = False
                      ) -> int:
    """How many slot ids :func:`draw_lot` draws at ``size`` (an id is drawn where it fits
    inside its slot)."""
    lot = getattr(lot_graph, "lot", lot_graph)
    canvas = lot_layout(lot_graph, size=size, show_graph=show_graph).canvas
    return len(_slot_label_spots(canvas, lot, 0.3 if show_graph else 0.0))


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
    overlay: Overlay | None = None,
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
    overlay : Overlay or None
        Drawn over the lot, its rows added to the legend, the picture widened to hold it
        (the service routes: :func:`lotsim.render.route_image.draw_routes`).

    Returns
    -------
    PIL.Image.Image
    """
    lot = getattr(lot_graph, "lot", lot_graph)
    if show_graph and not hasattr(lot_graph, "graph"):
        raise TypeError("show_graph needs a LotGraph, not a bare Lot")
    layout = lot_layout(lot_graph, size=size, show_graph=show_graph, title=title, legend=legend,
                        overlay=overlay)
    canvas, box = layout.canvas, layout.legend
    img = canvas.new_image()
    paint_lot(img, canvas, lot, parked_vehicle=parked_vehicle, labels=False)
    if show_graph:
        paint_graph(img, canvas, lot_graph)
    if overlay is not None:  # under the labels and the entrances: they stay readable
        overlay.paint(img, canvas)
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
