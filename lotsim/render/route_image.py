"""Service routes drawn over their lot (``lotsim show --routes``).

Each route's swept envelope is a translucent fill in the route's colour
(:data:`ROUTE_COLOURS`, in the scenario's order), outlined in it; its path, the line of
the rear-axle centre, is drawn over it blue where the vehicle drives forward and orange
in reverse, as ``lotsim maneuver`` draws a maneuver; a ring marks where the route comes
closest to what it must keep off, with the clearance written beside it. The legend names
each route, its vehicle and whether it passes. A route that fails draws what its report
holds (a report of a failure holds no path), and its row of the legend says it fails.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from PIL import Image, ImageDraw

from lotsim.core.geometry import sample_segments
from lotsim.render.lot_image import (
    TEXT,
    LotCanvas,
    _flat,
    draw_lot,
    draw_text,
    font,
    text_size,
)
from lotsim.render.lot_image.canvas import fill_geometry
from lotsim.render.lot_image.legend import _Entry
from lotsim.render.lot_image.theme import Color
from lotsim.render.maneuver_image import FORWARD, REVERSE
from lotsim.roadmap.service_routes import RouteReport

ROUTE_COLOURS: tuple[Color, ...] = (
    (200, 30, 170), (0, 160, 140), (140, 200, 0), (120, 70, 220), (170, 100, 40),
    (230, 60, 90),
)
"""The colour of each route's envelope, in the scenario's order (then again from the first):
none the blue or orange of a path's strokes."""
ENVELOPE_ALPHA = 80
"""Opacity of an envelope's fill (0 to 255): the bays and aisles under it stay readable."""
CLEARANCE_RING: Color = (20, 20, 20)


def route_colour(k: int) -> Color:
    """The colour of the ``k``-th route (:data:`ROUTE_COLOURS`)."""
    return ROUTE_COLOURS[k % len(ROUTE_COLOURS)]


def route_label(report: RouteReport) -> str:
    """A route's row of the legend: ``fire_front (fire_pump): passes, 0.30 m clear``, or
    ``bins (refuse_26t): FAILS``."""
    if not report.passed:
        return f"{report.id} ({report.vehicle}): FAILS"
    return f"{report.id} ({report.vehicle}): passes, {report.clearance:.2f} m clear"


class RouteOverlay:
    """The routes of ``reports`` as a picture's :class:`~lotsim.render.lot_image.Overlay`
    (module docstring)."""

    def __init__(self, reports: Sequence[RouteReport]):
        self.reports = tuple(reports)

    def bounds(self) -> tuple[float, float, float, float] | None:
        """The envelopes' rectangle [m]: at an entrance or exit they reach past the lot."""
        boxes = [r.envelope.bounds for r in self.reports
                 if r.envelope is not None and not r.envelope.is_empty]
        if not boxes:
            return None
        b = np.array(boxes, dtype=float)
        return (b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max())

    def entries(self) -> list[_Entry]:
        out = [_Entry(route_label(r), _swatch_envelope(route_colour(k), r.passed))
               for k, r in enumerate(self.reports)]
        if any(r.segments for r in self.reports):
            out += [_Entry("route forward", _swatch_line(FORWARD)),
                    _Entry("route reverse", _swatch_line(REVERSE))]
        if any(r.clearance_at is not None for r in self.reports):
            out.append(_Entry("tightest clearance", _swatch_ring))
        return out

    def paint(self, img: Image.Image, canvas: LotCanvas) -> None:
        for k, r in enumerate(self.reports):
            if r.envelope is not None and not r.envelope.is_empty:
                colour = route_colour(k)
                fill_geometry(img, canvas, r.envelope, colour + (ENVELOPE_ALPHA,),
                              outline=colour, width=2)
        for r in self.reports:
            paint_path(img, canvas, r)
        for k, r in enumerate(self.reports):
            paint_clearance(img, canvas, r, route_colour(k))


def paint_path(img: Image.Image, canvas: LotCanvas, report: RouteReport) -> None:
    """The route's rear-axle line, each stroke coloured by its gear."""
    if not report.segments:
        return
    poses, owner = sample_segments(report.segments, max(0.05, 1.0 / canvas.scale))
    gears = np.array([s.gear for s in report.segments])[owner]
    d = ImageDraw.Draw(img)
    w = max(2, int(round(canvas.px(0.15))))
    px = canvas.to_px(poses[:, :2])
    cuts = np.flatnonzero(np.diff(owner)) + 1  # a stroke per segment, ends shared
    for a, b in zip(np.concatenate([[0], cuts]), np.concatenate([cuts, [len(px)]]),
                    strict=True):
        piece = px[max(a - 1, 0):b]
        if len(piece) >= 2:
            d.line(_flat(piece), fill=FORWARD if gears[a] > 0 else REVERSE, width=w,
                   joint="curve")


def paint_clearance(img: Image.Image, canvas: LotCanvas, report: RouteReport,
                    colour: Color) -> None:
    """A ring at the point the route comes closest to, and the clearance [m] beside it on a
    white tag edged in the route's colour."""
    if report.clearance_at is None or math.isnan(report.clearance):
        return
    d = ImageDraw.Draw(img)
    cx, cy = canvas.to_px(np.array(report.clearance_at, dtype=float))
    r = max(5, int(round(canvas.px(0.5))))
    d.ellipse((cx - r, cy - r, cx + r, cy + r), outline=(255, 255, 255), width=5)
    d.ellipse((cx - r, cy - r, cx + r, cy + r), outline=CLEARANCE_RING, width=2)
    f = font(12)
    label = f"{report.clearance:.2f} m"
    tw, th = text_size(label, f)
    x0 = min(max(cx + r + 4, 0), img.width - tw - 10)
    y0 = min(max(cy - th / 2 - 3, 0), img.height - th - 6)
    d.rectangle((x0, y0, x0 + tw + 8, y0 + th + 6), fill=(255, 255, 255), outline=colour,
                width=2)
    draw_text(d, (x0 + 4 + tw / 2, y0 + 3 + th / 2), label, f, anchor="mm", fill=TEXT)


def _swatch_envelope(colour: Color, passed: bool):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        d = ImageDraw.Draw(img, "RGBA")
        d.rectangle(box, fill=(255, 255, 255))
        d.rectangle(box, fill=colour + (ENVELOPE_ALPHA,), outline=colour, width=2)
        if not passed:  # crossed out
            d.line((box[0], box[1], box[2], box[3]), fill=colour, width=2)
            d.line((box[0], box[3], box[2], box[1]), fill=colour, width=2)

    return paint


def _swatch_line(colour: Color):
    def paint(img: Image.Image, box: tuple[int, int, int, int]) -> None:
        y = (box[1] + box[3]) / 2
        ImageDraw.Draw(img).rectangle((box[0], y - 2, box[2], y + 2), fill=colour)

    return paint


def _swatch_ring(img: Image.Image, box: tuple[int, int, int, int]) -> None:
    cx, cy = (box[0] + box[2]) / 2, (box[1] + box[3]) / 2
    r = min(box[2] - box[0], box[3] - box[1]) / 2
    ImageDraw.Draw(img).ellipse((cx - r, cy - r, cx + r, cy + r), outline=CLEARANCE_RING,
                                width=2)


def draw_routes(lot_graph, reports: Sequence[RouteReport], *,
                size: tuple[int, int] = (1200, 900), show_graph: bool = False,
                parked_vehicle=None, title: str | None = None) -> Image.Image:
    """Draw the lot with its service routes over it (module docstring).

    Parameters
    ----------
    lot_graph : LotGraph or Lot
        As :func:`~lotsim.render.lot_image.draw_lot` takes it.
    reports : sequence of RouteReport
        The routes as planned (:func:`lotsim.roadmap.service_routes.plan_routes`).
    size, show_graph, parked_vehicle, title
        As :func:`~lotsim.render.lot_image.draw_lot`.

    Returns
    -------
    PIL.Image.Image

    Examples
    --------
    >>> from pathlib import Path
    >>> import lotsim
    >>> from lotsim.io.scenario_yaml import load_scenario
    >>> from lotsim.lot.build import build_lot
    >>> from lotsim.lot.model import DesignVehicle
    >>> from lotsim.roadmap.service_routes import plan_routes
    >>> sc = load_scenario(Path(lotsim.__file__).parents[1] / "scenarios/lots/storefront.yaml")
    >>> lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    >>> draw_routes(lot, plan_routes(lot, sc.routes), size=(400, 300)).size
    (400, 300)
    """
    return draw_lot(lot_graph, size=size, show_graph=show_graph, parked_vehicle=parked_vehicle,
                    title=title, overlay=RouteOverlay(reports))


__all__ = ["ROUTE_COLOURS", "RouteOverlay", "draw_routes", "paint_clearance", "paint_path",
           "route_colour", "route_label"]
