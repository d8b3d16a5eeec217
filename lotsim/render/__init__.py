"""Pictures of lots: :func:`draw_lot` and :func:`save_lot_png` (``lotsim show``).

For animation frames, draw the static lot once with :func:`paint_lot` on an
image from :meth:`LotCanvas.new_image` (or take :func:`draw_lot`'s image and
:func:`lot_layout`'s canvas), copy it per frame and draw cars with
:func:`paint_footprints`.
"""

from lotsim.render.lot_image import (
    Layout,
    LotCanvas,
    centered_footprints,
    draw_lot,
    lot_bounds,
    lot_layout,
    paint_footprints,
    paint_graph,
    paint_labels,
    paint_lot,
    paint_portals,
    save_lot_png,
)

__all__ = [
    "Layout",
    "LotCanvas",
    "centered_footprints",
    "draw_lot",
    "lot_bounds",
    "lot_layout",
    "paint_footprints",
    "paint_graph",
    "paint_labels",
    "paint_lot",
    "paint_portals",
    "save_lot_png",
]
