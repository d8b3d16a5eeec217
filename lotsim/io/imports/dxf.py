"""A plot drawn in CAD, from DXF (``lotsim import dxf``, ``docs/import.md``): its boundary,
islands, gates and building entrances, each read from the layers the user names, as a plot
file for ``lotsim layout`` (``docs/layout.md``).

What is read, from model space (layer names as CAD compares them, ignoring case):

* **the boundary**: the one closed outline on its layer: a closed LWPOLYLINE or POLYLINE
  (its arcs followed within :data:`FLATTEN` [m]), a CIRCLE, an ELLIPSE or a closed SPLINE;
* **islands**: every closed outline on the island layers, each inside the boundary, named
  by a TEXT or MTEXT of those layers inside it (else ``island-1``, ``island-2``, ...);
* **gates**: every POINT, INSERT (its insertion point), CIRCLE (its centre) or LINE (its
  middle) on the gate layers, each on the boundary within :data:`GATE_TOLERANCE`, named by
  the nearest TEXT or MTEXT of those layers within :data:`LABEL_REACH` (else by the compass
  point of the boundary's edge it is on, as an OpenStreetMap plot's gates are);
* **building entrances**: the same kinds of entity on the entrance layers, named by a text
  near each as gates are (else ``entrance-1``, ...).

Coordinates are the drawing's, times its units in metres: ``$INSUNITS`` 4 (mm), 5 (cm),
6 (m), 1 (in) or 2 (ft), or the units the user gives, which win; the plot file states its
unit as the drawing's (``units: ft`` for a drawing in feet or inches, :data:`FILE_UNITS`)
and gives its lengths in it. A drawing without units (``$INSUNITS`` 0, or none), or in
units lotsim does not read, is an error that asks for them. So is everything a plot file
cannot hold: no closed outline on the boundary layer, several, a boundary that crosses
itself, an island outside it or open, a gate off the boundary, none at all. Every problem
is found and said at once, each naming its layer and its entity (``LWPOLYLINE #2B``) and
what was expected; nothing is written.

Needs ``ezdxf`` (``pip install 'lotsim[dxf]'``).
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from shapely.geometry import Point, Polygon
from shapely.validation import explain_validity

from lotsim.core.units import LENGTH_UNITS
from lotsim.errors import LotsimError
from lotsim.io.cad_layers import LAYER_NAMES
from lotsim.io.imports.draft import AreaDraft, PlotDraft
from lotsim.io.imports.osm_gates import _side

UNITS: dict[str, tuple[int, float]] = {
    "mm": (4, 0.001),
    "cm": (5, 0.01),
    "m": (6, 1.0),
    "in": (1, 0.0254),
    "ft": (2, 0.3048),
}
"""The units lotsim reads → their ``$INSUNITS`` code and length in metres (the
international inch and foot)."""
INSUNITS_NAMES = {0: "unitless", 3: "miles", 7: "kilometres", 8: "microinches", 9: "mils",
                  10: "yards", 11: "ångströms", 12: "nanometres", 13: "microns",
                  14: "decimetres", 15: "decametres", 16: "hectometres", 17: "gigametres",
                  18: "astronomical units", 19: "light years", 20: "parsecs",
                  21: "US survey feet", 22: "US survey inches", 23: "US survey yards",
                  24: "US survey miles"}
"""The other ``$INSUNITS`` codes, named for the error that refuses them."""
GATE_TOLERANCE = 0.5
"""A gate lies on the boundary within this distance [m], as a plot file allows."""
LABEL_REACH = 5.0
"""A text names the gate or building entrance nearest it within this distance [m]."""
FLATTEN = 0.01
"""Arcs, circles and splines are followed within this distance [m]."""
MAX_SPAN = 2000.0
"""Largest plot, across [m], as a plot file allows."""
PLACES = 3
"""Decimals of the lengths written: the millimetre, or the thousandth of a foot."""
FILE_UNITS = {"mm": "m", "cm": "m", "m": "m", "in": "ft", "ft": "ft"}
"""The drawing's units → the unit the plot file states and gives its lengths in
(:data:`~lotsim.core.units.LENGTH_UNITS`): feet for a drawing in feet or inches, else
metres."""

OUTLINES = ("LWPOLYLINE", "POLYLINE", "CIRCLE", "ELLIPSE", "SPLINE")
"""Entities that may draw a closed outline."""
OPEN_LINES = ("LINE", "ARC")
"""Entities that draw only part of an outline."""
POINTS = ("POINT", "INSERT", "CIRCLE", "LINE")
"""Entities that mark a gate or an entrance."""
TEXTS = ("TEXT", "MTEXT")


class DxfImportError(LotsimError, ValueError):
    """A drawing that cannot be read as a plot; ``errors`` holds every problem found, each
    naming the file, the layer and the entity."""

    def __init__(self, errors: list[str]) -> None:
        self.errors = tuple(errors)
        super().__init__("\n".join(self.errors))


@dataclass(frozen=True, slots=True)
class DxfLayers:
    """The layers a plot is read from (module docstring): the boundary's, and those of
    islands, gates and building entrances (none: not read)."""

    boundary: str = LAYER_NAMES["boundary"]
    islands: tuple[str, ...] = (LAYER_NAMES["island"],)
    gates: tuple[str, ...] = (LAYER_NAMES["gate"],)
    entrances: tuple[str, ...] = (LAYER_NAMES["building_entrance"],)


@dataclass(frozen=True, slots=True)
class DxfPlot:
    """A plot read from a drawing.

    Attributes
    ----------
    draft : PlotDraft
        The plot, in metres, ready to be written: in feet (``units: ft``) for a drawing in
        feet or inches, else in metres (``units: m``; :data:`FILE_UNITS`).
    units : str
        The drawing's units (of :data:`UNITS`), and ``scale`` their length [m].
    units_from : str
        Where they came from: ``$INSUNITS 2``, or ``--units``.
    boundary : str
        The boundary's entity (``LWPOLYLINE #2B``).
    area : float
        The boundary's area [m²].
    ignored : tuple of str
        What the named layers hold that a plot does not read (``3 HATCH on C-PRKG-ISLD``).
    """

    draft: PlotDraft
    units: str
    scale: float
    units_from: str
    boundary: str
    area: float
    ignored: tuple[str, ...] = ()
    path: Path | None = None
    """The plot file written (None: not yet)."""

    def line(self) -> str:
        """One line for the command's summary."""
        d = self.draft
        counts = (f"{len(d.islands)} island{'s' * (len(d.islands) != 1)}, "
                  f"{len(d.gates)} gate{'s' * (len(d.gates) != 1)}, "
                  f"{len(d.building_entrances)} building entrance"
                  f"{'s' * (len(d.building_entrances) != 1)}")
        return (f"boundary {self.area:.0f} m² ({self.boundary}), {counts}; drawn in "
                f"{self.units} ({self.units_from})")


def entity_name(e: Any) -> str:
    """``LWPOLYLINE #2B``: an entity's type and handle, as CAD lists them."""
    return f"{e.dxftype()} #{e.dxf.handle}"


def _require_ezdxf():
    try:
        import ezdxf
    except ImportError:
        raise LotsimError("the dxf import needs the ezdxf package: pip install "
                          "'lotsim[dxf]'") from None
    return ezdxf


def read_drawing(path: Path):
    """The ezdxf document of ``path``, or a :class:`DxfImportError` saying why not."""
    ezdxf = _require_ezdxf()
    try:
        path.open("rb").close()
    except OSError as exc:
        raise DxfImportError([f"{path}: cannot read: {exc.strerror or exc}"]) from None
    try:
        return ezdxf.readfile(str(path))
    except (OSError, ezdxf.DXFError, UnicodeDecodeError, ValueError) as exc:
        raise DxfImportError([f"{path}: not a DXF drawing ezdxf can read ({exc})"]) from None


def units_of(doc, path: Path, units: str | None) -> tuple[str, float, str]:
    """The drawing's units (name, metres per unit, where they came from)."""
    code = int(doc.header.get("$INSUNITS", 0) or 0)
    said = next((n for n, (c, _) in UNITS.items() if c == code), None)
    if units is not None:
        if units not in UNITS:
            raise DxfImportError([f"--units: expected one of {', '.join(UNITS)}, found "
                                  f"{units!r}"])
        where = "--units" + (f"; the drawing says {said}" if said and said != units else "")
        return units, UNITS[units][1], where
    if said is not None:
        return said, UNITS[said][1], f"$INSUNITS {code}"
    what = INSUNITS_NAMES.get(code, "a code DXF does not define")
    if code == 0:
        raise DxfImportError([f"{path}: $INSUNITS is 0 (unitless): the drawing does not say "
                              f"its units; give them with --units "
                              f"{'|'.join(UNITS)}"])
    raise DxfImportError([f"{path}: $INSUNITS is {code} ({what}): lotsim reads drawings in "
                          f"{', '.join(UNITS)}; give the drawing's units with --units "
                          f"{'|'.join(UNITS)}"])


class _Reader:
    """One drawing's entities by layer, in metres, and the problems found."""

    def __init__(self, doc, path: Path, scale: float) -> None:
        self.path, self.scale = path, scale
        self.by_layer: dict[str, list] = {}
        for e in doc.modelspace():
            self.by_layer.setdefault(e.dxf.layer.upper(), []).append(e)
        self.layer_names = {layer.dxf.name.upper(): layer.dxf.name for layer in doc.layers}
        self.problems: list[str] = []
        self.ignored: list[str] = []

    def on(self, layers: tuple[str, ...] | str) -> list:
        names = (layers,) if isinstance(layers, str) else layers
        return [e for n in names for e in self.by_layer.get(n.upper(), [])]

    def fail(self, layer: str, message: str) -> None:
        self.problems.append(f"{self.path}: layer {layer!r}: {message}")

    def known(self, layer: str, option: str) -> bool:
        """Whether the drawing has ``layer``; if not, a problem naming its layers."""
        if layer.upper() in self.layer_names or layer.upper() in self.by_layer:
            return True
        names = {**{k: e[0].dxf.layer for k, e in self.by_layer.items()}, **self.layer_names}
        there = ", ".join(sorted(names.values(), key=str.upper)) or "none"
        self.problems.append(f"{self.path}: no layer {layer!r} in the drawing (its layers: "
                             f"{there}); name the layer with {option}")
        return False

    def metres(self, pts) -> np.ndarray:
        return np.asarray([(p[0], p[1]) for p in pts], dtype=float) * self.scale

    def outline(self, e) -> np.ndarray | None:
        """The closed outline an entity draws [m] (its last point not repeated); None when
        it draws none."""
        from ezdxf import path as dxf_path

        if e.dxftype() == "POLYLINE" and not e.is_2d_polyline:
            return None
        try:
            p = dxf_path.make_path(e)
        except (TypeError, ValueError):
            return None
        if not len(p) or not p.is_closed:
            return None
        pts = self.metres(p.flattening(FLATTEN / self.scale))
        keep = np.concatenate([[True], np.any(np.abs(np.diff(pts, axis=0)) > 1e-9, axis=1)])
        pts = pts[keep]
        if len(pts) > 1 and np.allclose(pts[0], pts[-1], atol=1e-9):
            pts = pts[:-1]
        return pts

    def mark(self, e) -> np.ndarray | None:
        """The point a gate or entrance entity marks [m] (module docstring)."""
        kind = e.dxftype()
        if kind == "POINT":
            v = e.dxf.location
        elif kind in ("INSERT", "CIRCLE"):
            v = e.ocs().to_wcs(e.dxf.insert if kind == "INSERT" else e.dxf.center)
        elif kind == "LINE":
            v = (e.dxf.start + e.dxf.end) / 2
        else:
            return None
        return self.metres([(v.x, v.y)])[0]

    def labels(self, layers: tuple[str, ...]) -> list[tuple[str, np.ndarray]]:
        """The texts on ``layers``: (text, where [m])."""
        out = []
        for e in self.on(layers):
            if e.dxftype() == "TEXT":
                aligned = e.dxf.halign or e.dxf.valign
                v = e.ocs().to_wcs(e.dxf.align_point if aligned else e.dxf.insert)
                words = e.dxf.text
            elif e.dxftype() == "MTEXT":
                v, words = e.dxf.insert, e.plain_text()
            else:
                continue
            name = " ".join(str(words).split())[:100]
            if name:
                out.append((name, self.metres([(v.x, v.y)])[0]))
        return out

    def note_ignored(self, layers: tuple[str, ...], read: tuple[str, ...]) -> None:
        counts: dict[tuple[str, str], int] = {}
        for e in self.on(layers):
            if e.dxftype() not in read + TEXTS:
                key = (e.dxftype(), e.dxf.layer)
                counts[key] = counts.get(key, 0) + 1
        self.ignored += [f"{n} {kind} on {layer}" for (kind, layer), n in sorted(counts.items())]


def _plain(text: str) -> str:
    """A plot's name from a file name: letters, digits, ``_ - .``."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", text).strip("-.") or "plot"


def _boundary(r: _Reader, layer: str) -> tuple[Polygon, str] | None:
    found = [(e, pts) for e in r.on(layer) if e.dxftype() in OUTLINES
             for pts in [r.outline(e)] if pts is not None]
    if len(found) > 1:
        r.fail(layer, f"expected one closed boundary, found {len(found)}: "
                      f"{', '.join(entity_name(e) for e, _ in found)} (keep one on this layer, "
                      f"or name the layer of the one to read with --boundary-layer)")
        return None
    if not found:
        pieces = [e for e in r.on(layer) if e.dxftype() in OUTLINES + OPEN_LINES]
        what = (f"found only open lines: {', '.join(entity_name(e) for e in pieces[:6])}"
                f"{' ...' if len(pieces) > 6 else ''} (join them into one closed polyline)"
                if pieces else "found none")
        r.fail(layer, f"expected a closed boundary (a closed LWPOLYLINE or POLYLINE, a "
                      f"CIRCLE, an ELLIPSE or a closed SPLINE), {what}")
        return None
    e, pts = found[0]
    poly = Polygon(pts) if len(pts) >= 3 else Polygon()
    if len(pts) >= 3 and not poly.is_valid:
        r.fail(layer, f"{entity_name(e)}: expected a simple polygon, but "
                      f"{explain_validity(poly)} (coordinates in metres)")
        return None
    if poly.area <= 0:
        r.fail(layer, f"{entity_name(e)}: expected a boundary with an area, found none")
        return None
    x0, y0, x1, y1 = poly.bounds
    span = max(x1 - x0, y1 - y0)
    if span > MAX_SPAN:
        r.fail(layer, f"{entity_name(e)}: expected a plot at most {MAX_SPAN:g} m across, "
                      f"found {span:.0f} m (are the drawing's units right? --units sets them)")
        return None
    return poly, entity_name(e)


def _islands(r: _Reader, layers: tuple[str, ...], outline: Polygon | None) -> list:
    shapes = []
    for e in r.on(layers):
        if e.dxftype() not in OUTLINES + OPEN_LINES:
            continue
        pts = r.outline(e) if e.dxftype() in OUTLINES else None
        if pts is None:
            r.fail(e.dxf.layer, f"{entity_name(e)} is open: expected the closed outline of "
                                f"an island (close it)")
            continue
        poly = Polygon(pts) if len(pts) >= 3 else Polygon()
        if not poly.is_valid or poly.area <= 0:
            why = explain_validity(poly) if not poly.is_valid else "it has no area"
            r.fail(e.dxf.layer, f"{entity_name(e)}: expected an island to be a simple "
                                f"polygon, but {why}")
        elif outline is not None and not outline.contains(poly):
            r.fail(e.dxf.layer, f"{entity_name(e)}: expected an island inside the boundary, "
                                f"found one reaching {poly.difference(outline).area:.2f} m² "
                                f"outside it")
        else:
            shapes.append((e, pts, poly))
    labels = r.labels(layers)
    taken: set[str] = set()
    out = []
    for k, (e, pts, poly) in enumerate(shapes):
        named = next((t for t, at in labels if t not in taken and poly.contains(Point(at))),
                     None)
        ident = named or f"island-{k + 1}"
        taken.add(ident)
        out.append((ident, pts, f"{entity_name(e)} on layer {e.dxf.layer}"))
    r.note_ignored(layers, OUTLINES + OPEN_LINES)
    return out


def _marks(r: _Reader, layers: tuple[str, ...]) -> list[tuple[Any, np.ndarray]]:
    out = [(e, at) for e in r.on(layers) if e.dxftype() in POINTS
           for at in [r.mark(e)] if at is not None]
    r.note_ignored(layers, POINTS)
    return out


def _named(r: _Reader, layers: tuple[str, ...], marks: list, fallback) -> list[str]:
    """A name for each mark: the nearest text within :data:`LABEL_REACH` (each text names
    one, nearest pairs first), else ``fallback(k, at)``; made unique with ``-2``, ``-3``."""
    labels = r.labels(layers)
    pairs = sorted((float(np.hypot(*(at - where))), k, j)
                   for k, (_, at) in enumerate(marks) for j, (_, where) in enumerate(labels))
    names: dict[int, str] = {}
    used: set[int] = set()
    for d, k, j in pairs:
        if d <= LABEL_REACH and k not in names and j not in used:
            names[k] = labels[j][0]
            used.add(j)
    out: list[str] = []
    for k, (_, at) in enumerate(marks):
        base = names.get(k) or fallback(k, at)
        name, n = base, 1
        while name in out:
            n += 1
            name = f"{base}-{n}"
        out.append(name)
    return out


def read_dxf_plot(source: str | os.PathLike, *, layers: DxfLayers = DxfLayers(),
                  units: str | None = None) -> DxfPlot:
    """Read the plot of a DXF drawing (module docstring).

    Parameters
    ----------
    source : path-like
        The drawing.
    layers : DxfLayers
        The layers to read each part from.
    units : str, optional
        The drawing's units (of :data:`UNITS`), over its ``$INSUNITS``.

    Raises
    ------
    DxfImportError
        Every problem found, each naming its layer and entity.
    LotsimError
        Without ``ezdxf``.
    """
    path = Path(source)
    doc = read_drawing(path)
    unit, scale, units_from = units_of(doc, path, units)
    r = _Reader(doc, path, scale)
    found = r.known(layers.boundary, "--boundary-layer") and _boundary(r, layers.boundary)
    outline, boundary = found if found else (None, "")
    default = DxfLayers()
    for names, usual, option in ((layers.islands, default.islands, "--island-layer"),
                                 (layers.gates, default.gates, "--gate-layer"),
                                 (layers.entrances, default.entrances, "--entrance-layer")):
        if names != usual:  # a layer the user named must be there
            for name in names:
                r.known(name, option)
    islands = _islands(r, layers.islands, outline)
    gate_marks = _marks(r, layers.gates)
    if not gate_marks:
        r.fail(", ".join(layers.gates), "expected at least one gate where a road meets "
               "the boundary (a POINT, INSERT, CIRCLE or LINE), found none (name the gates' "
               "layer with --gate-layer)")
    if outline is not None:
        edge = outline.exterior
        for e, at in gate_marks:
            d = edge.distance(Point(at))
            if d > GATE_TOLERANCE:
                r.fail(e.dxf.layer, f"{entity_name(e)} at ({at[0]:.2f}, {at[1]:.2f}) m is "
                                    f"{d:.2f} m from the boundary ({boundary}): expected a "
                                    f"gate on the boundary (within {GATE_TOLERANCE:g} m)")
    entrance_marks = _marks(r, layers.entrances)
    if r.problems:
        raise DxfImportError(r.problems)
    assert outline is not None

    def compass(k: int, at) -> str:
        return _side((float(at[0]), float(at[1])), outline)

    gate_names = _named(r, layers.gates, gate_marks, compass)
    entrance_names = _named(r, layers.entrances, entrance_marks,
                            lambda k, at: f"entrance-{k + 1}")

    size = LENGTH_UNITS[FILE_UNITS[unit]]  # the plot file's unit [m]

    def xy(at) -> tuple[float, float]:  # to the file's thousandth of its unit
        return (round(float(at[0]) / size, PLACES) * size,
                round(float(at[1]) / size, PLACES) * size)

    def ring(pts) -> list[tuple[float, float]]:  # to the millimetre, no point twice running
        out: list[tuple[float, float]] = []
        for p in map(xy, pts):
            if not out or p != out[-1]:
                out.append(p)
        return out[:-1] if len(out) > 1 and out[0] == out[-1] else out

    def note(e) -> str:
        return f"{entity_name(e)} on layer {e.dxf.layer}"

    header = [f"Read from {path.name} by lotsim import dxf, drawn in {unit} ({units_from}); "
              f"in {'feet' if FILE_UNITS[unit] == 'ft' else 'metres'} here.",
              f"Boundary: {boundary} on layer {layers.boundary}."]
    if r.ignored:
        header.append(f"Not read: {', '.join(r.ignored)}.")
    draft = PlotDraft(
        name=_plain(path.stem), description=f"A plot read from {path.name}.",
        boundary=ring(ring_of(outline)),
        gates=[(n, xy(at), note(e)) for n, (e, at) in zip(gate_names, gate_marks,
                                                           strict=True)],
        islands=[AreaDraft(ident, ring(pts), note=where)
                 for ident, pts, where in islands],
        header=header,
        building_entrances=[(n, xy(at), note(e)) for n, (e, at)
                            in zip(entrance_names, entrance_marks, strict=True)],
        places=PLACES, units=FILE_UNITS[unit])
    return DxfPlot(draft=draft, units=unit, scale=scale, units_from=units_from,
                   boundary=boundary, area=float(outline.area), ignored=tuple(r.ignored))


def ring_of(poly: Polygon) -> list[tuple[float, float]]:
    """The polygon's exterior, its last point not repeated."""
    return [(float(x), float(y)) for x, y in list(poly.exterior.coords)[:-1]]


__all__ = ["DxfImportError", "DxfLayers", "DxfPlot", "GATE_TOLERANCE", "UNITS",
           "read_dxf_plot"]
