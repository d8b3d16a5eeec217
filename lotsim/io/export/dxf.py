"""A built lot as a DXF drawing for CAD (``lotsim export --dxf``, ``docs/export.md``).

The figures of :func:`~lotsim.io.export.cad_drawing.lot_drawing` become model-space
entities, each on its layer of :data:`~lotsim.io.cad_layers.LAYERS` with the layer's
colour and linetype (``BYLAYER``; a reverse stroke of a route's path ``DASHED``; a route's
figures carry its id as extended data, :data:`APPID`): LWPOLYLINE, LINE, POINT, TEXT,
a solid HATCH under each arrow and a HATCH of lines over each access aisle. The drawing is DXF R2010
(AutoCAD 2010 and later read it), in metres or in feet (:data:`DRAWING_UNITS`): in metres
``$INSUNITS`` 6, ``$MEASUREMENT`` 1 (metric), decimal lengths to the millimetre, in lotsim's
own coordinates, unrounded; in feet ``$INSUNITS`` 2, ``$MEASUREMENT`` 0 (imperial), decimal
lengths to the thousandth of a foot, every coordinate and length (texts' heights, arrows,
the hatch's spacing, the linetypes' dashes through ``$LTSCALE``) divided by 0.3048 m, so
the drawing looks on paper as the one in metres does. Its initial view shows the whole lot.

Needs ``ezdxf`` (``pip install 'lotsim[dxf]'``), imported when a drawing is written.
The file is written whole or not at all (:func:`~lotsim.core.atomic.atomic_write`).
"""

from __future__ import annotations

import io
import os
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from lotsim.core.atomic import atomic_write
from lotsim.core.units import LENGTH_UNITS
from lotsim.errors import SettingsError
from lotsim.io.cad_layers import LAYERS
from lotsim.io.export.cad_drawing import CadDrawing, lot_drawing, scaled
from lotsim.io.export.tracks import require
from lotsim.lot.model import Lot
from lotsim.roadmap.service_routes import RouteReport

DXF_VERSION = "R2010"
"""The DXF version written."""
METRES = 6
"""``$INSUNITS`` of metres."""
FEET = 2
"""``$INSUNITS`` of feet."""
DRAWING_UNITS = {"m": (METRES, 1, 3), "ft": (FEET, 0, 3)}
"""The units a drawing is written in (of :data:`~lotsim.core.units.LENGTH_UNITS`) → their
``$INSUNITS``, ``$MEASUREMENT`` (1 metric, 0 imperial) and ``$LUPREC`` (decimals shown: the
millimetre, the thousandth of a foot)."""
BYLAYER = 256
"""The colour index that takes the layer's colour."""
APPID = "LOTSIM"
"""The application name of lotsim's extended data: a route's envelope and path carry the
route's id (group code 1000)."""
HATCH_PATTERN = "ANSI31"
"""The pattern of a hatched figure (an access aisle): lines at 45°."""
HATCH_SPACING = 0.4
"""How far apart its lines are [m]: about as far as the painted lines of an access aisle."""
PATTERN_SPACING = {1: 3.175, 0: 0.125}
"""How far apart ANSI31's lines are at scale 1 [drawing units], by ``$MEASUREMENT``: the
ISO pattern's (metric) and the imperial one's, as CAD programs and ezdxf scale them."""
HATCH_SCALE = HATCH_SPACING / PATTERN_SPACING[1]
"""The pattern's scale in a drawing in metres: lines :data:`HATCH_SPACING` apart."""


@dataclass(frozen=True, slots=True)
class DxfInfo:
    """What :func:`write_dxf` wrote."""

    path: Path
    bays: int
    entities: tuple[tuple[str, int], ...]
    """Entities written on each layer, in the order of :data:`~lotsim.io.cad_layers.LAYERS`
    (layers with none left out)."""
    bytes: int
    units: str = "m"
    """The drawing's units (:data:`DRAWING_UNITS`)."""


def drawing_units(units: str) -> str:
    """``units`` checked: one of :data:`DRAWING_UNITS`, else a :class:`SettingsError`."""
    if units not in DRAWING_UNITS:
        raise SettingsError("units", f"expected one of {', '.join(DRAWING_UNITS)}, found "
                                     f"{units!r}")
    return units


def dxf_document(drawing: CadDrawing, *, units: str = "m"):
    """The ezdxf document of ``drawing`` (its figures in metres), written in ``units``
    (module docstring)."""
    ezdxf = require("ezdxf", "dxf")
    from ezdxf.enums import TextEntityAlignment

    code, measurement, places = DRAWING_UNITS[drawing_units(units)]
    size = LENGTH_UNITS[units]  # [m] per drawing unit
    if units != "m":  # a metric drawing keeps lotsim's own numbers, not a product with 1
        drawing = scaled(drawing, 1.0 / size)
    hatch_scale = HATCH_SPACING / size / PATTERN_SPACING[measurement]
    doc = ezdxf.new(DXF_VERSION, setup=True)
    doc.header["$INSUNITS"] = code
    doc.header["$MEASUREMENT"] = measurement
    doc.header["$LUNITS"] = 2  # decimal
    doc.header["$LUPREC"] = places
    if units != "m":  # the linetypes' dashes as long on paper as in metres
        doc.header["$LTSCALE"] = 1.0 / size
    for layer in LAYERS:
        doc.layers.add(layer.name, color=layer.color, linetype=layer.linetype)
    doc.appids.add(APPID)
    msp = doc.modelspace()
    for p in drawing.polylines:
        attribs = {"layer": p.layer} | ({"linetype": p.linetype} if p.linetype else {})
        line = msp.add_lwpolyline(p.points, format="xy", close=p.closed, dxfattribs=attribs)
        if p.of:
            line.set_xdata(APPID, [(1000, p.of)])
        if p.fill:
            hatch = msp.add_hatch(color=BYLAYER, dxfattribs={"layer": p.layer})
            hatch.paths.add_polyline_path(p.points, is_closed=True)
        if p.hatch:
            hatch = msp.add_hatch(color=BYLAYER, dxfattribs={"layer": p.layer})
            hatch.set_pattern_fill(HATCH_PATTERN, scale=hatch_scale)
            hatch.paths.add_polyline_path(p.points, is_closed=True)
    for s in drawing.segments:
        msp.add_line(s.start, s.end, dxfattribs={"layer": s.layer})
    for m in drawing.marks:
        msp.add_point(m.at, dxfattribs={"layer": m.layer})
    for t in drawing.labels:
        msp.add_text(t.text, height=t.height, rotation=t.rotation,
                     dxfattribs={"layer": t.layer}).set_placement(
            t.at, align=TextEntityAlignment.MIDDLE_CENTER)
    x0, y0, x1, y1 = drawing.bounds
    doc.set_modelspace_vport(height=max(y1 - y0, (x1 - x0) * 0.75, 1.0) * 1.1,
                             center=((x0 + x1) / 2, (y0 + y1) / 2))
    return doc


def write_dxf(lot: Lot, path: str | os.PathLike, *, routes: Sequence[RouteReport] = (),
              units: str = "m") -> DxfInfo:
    """Write ``lot`` as a DXF drawing at ``path`` in ``units`` (module docstring), with the
    envelopes and paths of its service routes' ``routes`` (their reports).

    Parameters
    ----------
    lot : Lot
        A built lot (a scenario's, or a result's ``lot.drawing`` read back).
    path : path-like
        The file to write; its folder must exist.
    routes : sequence of RouteReport, keyword-only
        The scenario's service routes as planned
        (:func:`~lotsim.roadmap.service_routes.plan_routes`), drawn on their layers.
    units : str, keyword-only
        The drawing's units, ``m`` or ``ft`` (:data:`DRAWING_UNITS`).

    Returns
    -------
    DxfInfo

    Raises
    ------
    ExportUnavailable
        Without ``ezdxf`` (``pip install 'lotsim[dxf]'``).
    SettingsError
        ``units`` neither ``m`` nor ``ft``.
    """
    drawing_units(units)
    drawing = lot_drawing(lot, routes)
    doc = dxf_document(drawing, units=units)
    text = io.StringIO()
    doc.write(text)
    data = doc.encode(text.getvalue())
    target = Path(path)
    with atomic_write(target, "wb") as fh:
        fh.write(data)
    counts = Counter(e.dxf.layer for e in doc.modelspace())
    order = [layer.name for layer in LAYERS]
    return DxfInfo(path=target, bays=len(lot.slots),
                   entities=tuple((n, counts[n]) for n in order if counts[n]),
                   bytes=len(data), units=units)
