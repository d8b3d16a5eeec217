"""The built lot as plain JSON: ``lot.drawing`` in ``result.json`` (``docs/result.md``).

:func:`lot_to_json` writes a :class:`~lotsim.lot.model.Lot` as a dict of JSON
types; :func:`lot_from_json` rebuilds the model from it, so a lot can be drawn
again from a result file alone, without the scenario.

Encoding
--------
The dict mirrors the model's attributes, with ``"format": "lotsim-lot"`` and
``"version": 1``. Points are ``[x, y]`` lists; a pose is ``[x, y, theta]``;
polygonal geometry (boundary, aisle, area and zone polygons) is a GeoJSON
geometry object, ``{"type": "Polygon" | "MultiPolygon", "coordinates": ...}``,
rings closed (first point repeated), exterior first, then the holes. A lane's
segments are rows ``[x, y, theta, distance, curvature, sharpness]`` (start pose, signed
length, signed curvature at the start, its change per metre); a lane belongs to the aisle
it is listed under.
Source locations (``where``) are not written: the rebuilt model has ``None``.

Lengths, angles and speeds are rounded to 6 decimals (1 µm, 1 µrad, 1 µm/s), except
lane segments, which are written unrounded (Python's shortest round-trip repr, so the
rebuilt lanes are bit-identical): they are few (about 150 numbers in a 1000-slot lot), a
heading error grows along the lane (1 µrad over a 200 m straight is 0.2 mm), and a
rounded ``-pi`` lies outside ``[-pi, pi)`` with a sine of the other sign, which moves
the edge pixels of direction arrows drawn on whole-pixel positions. The output is
deterministic: the same lot gives the same dict, ``occupied`` sorted.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import shapely
from shapely.geometry import LineString, MultiPolygon, Polygon

from lotsim.core.geometry import FloatArray, Segment
from lotsim.errors import LotsimError
from lotsim.lot.model import (
    AccessAisle,
    Aisle,
    Area,
    DesignVehicle,
    Lane,
    Lot,
    Portal,
    Slot,
    SpeedZone,
)
from lotsim.lot.spec import SIDES, SLOT_KINDS
from lotsim.lot.uses import STANDARD, USES

FORMAT = "lotsim-lot"
VERSION = 1
DECIMALS = 6
"""Decimals kept of every number but the lane segments' [m, rad, m/s]: 1 µm, 1 µrad."""
MAX_MAGNITUDE = 1e9
"""Largest size of any number read [m, rad, m/s], as in ``lotsim check``: larger ones
overflow when drawn."""
AREA_KINDS = ("wall", "obstacle", "no_go")
ZONE_SOURCES = ("bump", "zone")

_TOP_KEYS = ("format", "version", "boundary", "aisles", "slots", "areas", "zones",
             "entrances", "exits", "occupied", "speed_limit", "design")
_AISLE_KEYS = ("id", "centerline", "width", "one_way", "bend_radius", "bend_sharpness", "polygon",
               "lanes")
_LANE_KEYS = ("id", "offset", "with_polyline", "segments")
_SLOT_KEYS = ("id", "kind", "polygon", "entry", "heading", "aisle", "side", "station",
              "angle", "width", "length")
_AREA_KEYS = ("id", "kind", "polygon")
_ZONE_KEYS = ("id", "source", "polygon", "limit", "line")
_PORTAL_KEYS = ("id", "pose")
_DESIGN_KEYS = ("width", "front", "rear", "min_radius", "max_curvature_rate", "max_lateral_accel")
_GEOMETRY_KEYS = ("type", "coordinates")


class LotFormatError(LotsimError, ValueError):
    """A ``lotsim-lot`` dict that cannot be read; the message starts with the key path,
    e.g. ``drawing.slots[3].polygon: expected a list of 4 [x, y] points``."""


# -- writing -----------------------------------------------------------------------------------
def lot_to_json(lot: Lot) -> dict[str, Any]:
    """The lot as a dict of JSON types (dict, list, str, float, int, bool, None).

    Parameters
    ----------
    lot : Lot

    Returns
    -------
    dict
        ``{"format": "lotsim-lot", "version": 1, "boundary": ..., "aisles": [...], ...}``;
        see the module docstring for the encoding.

    Raises
    ------
    ValueError
        If a polygonal attribute is neither a Polygon nor a MultiPolygon.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> lot = Lot(boundary=box(0, 0, 10, 5), aisles={}, slots=(), areas=(), zones=(),
    ...           entrances=(), exits=(), occupied=frozenset(), speed_limit=10 / 3.6,
    ...           design=DesignVehicle(1.8, 3.9, 1.0, 5.0, 0.156, 2.0))
    >>> d = lot_to_json(lot)
    >>> d["format"], d["version"], d["speed_limit"], d["boundary"]["type"]
    ('lotsim-lot', 1, 2.777778, 'Polygon')
    >>> lot_from_json(d).boundary.equals(lot.boundary)
    True
    """
    return {
        "format": FORMAT,
        "version": VERSION,
        "boundary": _geometry_json(lot.boundary),
        "aisles": [_aisle_json(a) for a in lot.aisles.values()],
        "slots": [_slot_json(s) for s in lot.slots],
        "areas": [{"id": a.id, "kind": a.kind, "polygon": _geometry_json(a.polygon)}
                  for a in lot.areas],
        "zones": [{"id": z.id, "source": z.source, "polygon": _geometry_json(z.polygon),
                   "limit": _round(z.limit),
                   "line": None if z.line is None else _points_json(np.asarray(z.line.coords))}
                  for z in lot.zones],
        "entrances": [_portal_json(p) for p in lot.entrances],
        "exits": [_portal_json(p) for p in lot.exits],
        "occupied": sorted(lot.occupied),
        "speed_limit": _round(lot.speed_limit),
        "design": {k: _round(getattr(lot.design, k)) for k in _DESIGN_KEYS},
    } | ({} if lot.pavement is None else {"pavement": _geometry_json(lot.pavement)}) | (
        {"access_aisles": [{"id": a.id, "polygon": _points_json(a.polygon),
                            "slots": list(a.slots), "width": _round(a.width)}
                           for a in lot.access_aisles]} if lot.access_aisles else {})


def _round(x: float) -> float:
    return round(float(x), DECIMALS)


def _points_json(points: FloatArray) -> list[list[float]]:
    return np.round(np.asarray(points, dtype=float)[:, :2], DECIMALS).tolist()


def _polygon_rings(poly: Polygon) -> list[list[list[float]]]:
    if poly.is_empty:
        return []
    return [_points_json(np.asarray(r.coords)) for r in (poly.exterior, *poly.interiors)]


def _geometry_json(geom: Polygon | MultiPolygon) -> dict[str, Any]:
    if geom.geom_type == "Polygon":
        return {"type": "Polygon", "coordinates": _polygon_rings(geom)}
    if geom.geom_type == "MultiPolygon":
        return {"type": "MultiPolygon", "coordinates": [_polygon_rings(p) for p in geom.geoms]}
    raise ValueError(f"cannot write a {geom.geom_type} as a lot polygon")


def _aisle_json(a: Aisle) -> dict[str, Any]:
    lanes = []
    for lane in a.lanes:
        rows = [[float(v) for v in (*s.start, s.distance, s.curvature, s.sharpness)]
                for s in lane.segments]
        lanes.append({"id": lane.id, "offset": _round(lane.offset),
                      "with_polyline": bool(lane.with_polyline), "segments": rows})
    return {"id": a.id, "centerline": _points_json(a.centerline), "width": _round(a.width),
            "one_way": bool(a.one_way), "bend_radius": _round(a.bend_radius),
            "bend_sharpness": float(a.bend_sharpness),
            "polygon": _geometry_json(a.polygon), "lanes": lanes} | (
        {"corner_sharpness": [None if math.isinf(c) else float(c) for c in a.corner_sharpness]}
        if a.corner_sharpness else {})


def _slot_json(s: Slot) -> dict[str, Any]:
    return {"id": s.id, "kind": s.kind, "polygon": _points_json(s.polygon),
            "entry": _points_json(s.entry), "heading": _round(s.heading), "aisle": s.aisle,
            "side": s.side, "station": _round(s.station), "angle": _round(s.angle),
            "width": _round(s.width), "length": _round(s.length)} | (
        {} if s.use == STANDARD else {"use": s.use})


def _portal_json(p: Portal) -> dict[str, Any]:
    return {"id": p.id, "pose": [_round(v) for v in p.pose]}


# -- reading -----------------------------------------------------------------------------------
def lot_from_json(d: Any, *, root: str = "drawing") -> Lot:
    """Rebuild a :class:`~lotsim.lot.model.Lot` from :func:`lot_to_json`'s dict.

    Parameters
    ----------
    d : dict
        The dict, e.g. ``json.load(f)["lot"]["drawing"]``.
    root : str, keyword-only
        Key path of ``d`` used in error messages.

    Returns
    -------
    Lot
        Every ``where`` is ``None``.

    Raises
    ------
    LotFormatError
        On the first missing or unknown key, wrong type or shape, non-finite number or
        one beyond :data:`MAX_MAGNITUDE`, invalid polygon, unknown kind, or broken
        reference (a slot's aisle, an occupied slot); the message starts with the key path.

    Examples
    --------
    >>> lot_from_json({"format": "lotsim-lot", "version": 1})
    Traceback (most recent call last):
    ...
    lotsim.io.lot_json.LotFormatError: drawing: missing key 'boundary'
    >>> lot_from_json([], root="lot.drawing")
    Traceback (most recent call last):
    ...
    lotsim.io.lot_json.LotFormatError: lot.drawing: expected an object, found an empty list
    """
    if not isinstance(d, dict):
        raise LotFormatError(f"{root}: expected an object, found {_found(d)}")
    # format and version first: a newer version may hold keys this one does not know
    for key, want in (("format", FORMAT), ("version", VERSION)):
        if key not in d:
            raise LotFormatError(f"{root}: missing key {key!r}")
        if type(d[key]) is not type(want) or d[key] != want:
            raise LotFormatError(f"{root}.{key}: expected {want!r}, found {_found(d[key])}")
    raw_pavement = d.get("pavement")  # optional: absent, the lot is paved wall to wall
    raw_access = d.get("access_aisles", [])  # optional: absent, the lot has none
    d = _object({k: v for k, v in d.items() if k not in ("pavement", "access_aisles")}, root,
                _TOP_KEYS)
    geoms: list[tuple[str, Any]] = []  # checked for validity at once, at the end

    def geometry(value: Any, path: str) -> Polygon | MultiPolygon:
        g = _geometry(value, path)
        geoms.append((path, g))
        return g

    boundary = geometry(d["boundary"], f"{root}.boundary")
    aisles: dict[str, Aisle] = {}
    for i, raw in enumerate(_list(d["aisles"], f"{root}.aisles")):
        a = _aisle(raw, f"{root}.aisles[{i}]", geometry)
        if a.id in aisles:
            raise LotFormatError(f"{root}.aisles[{i}].id: aisle id {a.id!r} is used twice")
        aisles[a.id] = a
    slots = _slots(_list(d["slots"], f"{root}.slots"), f"{root}.slots", aisles)
    areas = []
    for i, raw in enumerate(_list(d["areas"], f"{root}.areas")):
        path = f"{root}.areas[{i}]"
        o = _object(raw, path, _AREA_KEYS)
        areas.append(Area(_str(o, "id", path), _choice(o, "kind", path, AREA_KINDS),
                          geometry(o["polygon"], f"{path}.polygon")))
    zones = []
    for i, raw in enumerate(_list(d["zones"], f"{root}.zones")):
        path = f"{root}.zones[{i}]"
        o = _object(raw, path, _ZONE_KEYS)
        line = None
        if o["line"] is not None:
            line = LineString(_array(o["line"], f"{path}.line", (None, 2), min_rows=2,
                                     what="null or a list of at least 2 [x, y] points"))
        zones.append(SpeedZone(_str(o, "id", path), _choice(o, "source", path, ZONE_SOURCES),
                               geometry(o["polygon"], f"{path}.polygon"),
                               _number(o, "limit", path), line))
    entrances = _portals(d["entrances"], f"{root}.entrances")
    exits = _portals(d["exits"], f"{root}.exits")
    occupied = _occupied(d["occupied"], f"{root}.occupied", slots)
    design = _object(d["design"], f"{root}.design", _DESIGN_KEYS)
    design_vehicle = DesignVehicle(*(_number(design, k, f"{root}.design") for k in _DESIGN_KEYS))
    pavement = None if raw_pavement is None else geometry(raw_pavement, f"{root}.pavement")
    access = _access_aisles(raw_access, f"{root}.access_aisles", {s.id for s in slots})
    valid = shapely.is_valid(np.array([g for _, g in geoms], dtype=object))
    if not valid.all():
        path, g = geoms[int(np.argmin(valid))]
        raise LotFormatError(f"{path}: expected a valid polygon, but "
                             f"{shapely.is_valid_reason(g)}")
    return Lot(boundary=boundary, aisles=aisles, slots=slots, areas=tuple(areas),
               zones=tuple(zones), entrances=entrances, exits=exits, occupied=occupied,
               speed_limit=_number(d, "speed_limit", root), design=design_vehicle,
               pavement=pavement, access_aisles=access)


def _access_aisles(raw: Any, path: str, slot_ids: set[str]) -> tuple[AccessAisle, ...]:
    out = []
    for i, item in enumerate(_list(raw, path)):
        p = f"{path}[{i}]"
        o = _object(item, p, ("id", "polygon", "slots", "width"))
        served = _list(o["slots"], f"{p}.slots")
        for k, sid in enumerate(served):
            if sid not in slot_ids:
                raise LotFormatError(f"{p}.slots[{k}]: expected the id of a slot, found "
                                     f"{_found(sid)}")
        out.append(AccessAisle(_str(o, "id", p), _array(o["polygon"], f"{p}.polygon", (4, 2),
                                                        what="a list of 4 [x, y] points"),
                               tuple(served), _number(o, "width", p)))
    return tuple(out)


def _aisle(raw: Any, path: str, geometry: Callable[[Any, str], Any]) -> Aisle:
    # optional: written only for aisles whose corners are too close for bend_sharpness
    corners = raw.get("corner_sharpness") if isinstance(raw, dict) else None
    if isinstance(raw, dict):
        raw = {k: v for k, v in raw.items() if k != "corner_sharpness"}
    o = _object(raw, path, _AISLE_KEYS)
    aid = _str(o, "id", path)
    lanes = []
    for j, lraw in enumerate(_list(o["lanes"], f"{path}.lanes")):
        lpath = f"{path}.lanes[{j}]"
        lo = _object(lraw, lpath, _LANE_KEYS)
        rows = _array(lo["segments"], f"{lpath}.segments", (None, 6), min_rows=1,
                      what="a list of at least one [x, y, theta, distance, curvature, "
                           "sharpness] row")
        segments = tuple(Segment((x, y, t), s, k, g) for x, y, t, s, k, g in rows.tolist())
        lanes.append(Lane(_str(lo, "id", lpath), aid, segments, _number(lo, "offset", lpath),
                          _bool(lo, "with_polyline", lpath)))
    centerline = _array(o["centerline"], f"{path}.centerline", (None, 2), min_rows=2,
                        what="a list of at least 2 [x, y] points")
    return Aisle(aid, centerline, _number(o, "width", path), _bool(o, "one_way", path),
                 _number(o, "bend_radius", path), _number(o, "bend_sharpness", path),
                 geometry(o["polygon"], f"{path}.polygon"),
                 tuple(lanes), corner_sharpness=_corners(corners, f"{path}.corner_sharpness",
                                                         len(centerline) - 2))


def _corners(value: Any, path: str, n: int) -> tuple[float, ...]:
    """Each corner's sharpness, ``null`` for a plain arc (``inf``); () when not given."""
    if value is None:
        return ()
    if not isinstance(value, list) or len(value) != n or not all(
            v is None or (type(v) in (int, float) and math.isfinite(v) and v > 0)
            for v in value):
        raise LotFormatError(f"{path}: expected a list of {n} positive numbers or nulls, "
                             f"one per corner of the centre line")
    return tuple(math.inf if v is None else float(v) for v in value)


def _slots(raws: list, path: str, aisles: dict[str, Aisle]) -> tuple[Slot, ...]:
    # a bay's use is written only when it is not standard
    uses = [raw.get("use", STANDARD) if isinstance(raw, dict) else STANDARD for raw in raws]
    objs = [_object({k: v for k, v in raw.items() if k != "use"} if isinstance(raw, dict)
                    else raw, f"{path}[{i}]", _SLOT_KEYS) for i, raw in enumerate(raws)]
    # every polygon and entry converted in one numpy call each; only a bad one costs a loop
    polygons = _stacked(objs, path, "polygon", (4, 2), "a list of 4 [x, y] points")
    entries = _stacked(objs, path, "entry", (2, 2), "a list of 2 [x, y] points")
    out = []
    seen: set[str] = set()
    for i, o in enumerate(objs):
        p = f"{path}[{i}]"
        sid = _str(o, "id", p)
        if sid in seen:
            raise LotFormatError(f"{p}.id: slot id {sid!r} is used twice")
        seen.add(sid)
        aisle = _str(o, "aisle", p)
        if aisle not in aisles:
            raise LotFormatError(f"{p}.aisle: expected the id of an aisle, found {aisle!r}")
        out.append(Slot(
            id=sid, kind=_choice(o, "kind", p, SLOT_KINDS), polygon=polygons[i],
            entry=entries[i], heading=_number(o, "heading", p), aisle=aisle,
            side=_choice(o, "side", p, SIDES), station=_number(o, "station", p),
            angle=_number(o, "angle", p), width=_number(o, "width", p),
            length=_number(o, "length", p),
            use=_choice({"use": uses[i]}, "use", p, tuple(USES)),
        ))
    return tuple(out)


def _portals(raw: Any, path: str) -> tuple[Portal, ...]:
    out = []
    for i, item in enumerate(_list(raw, path)):
        p = f"{path}[{i}]"
        o = _object(item, p, _PORTAL_KEYS)
        x, y, t = _array(o["pose"], f"{p}.pose", (3,), what="[x, y, theta]").tolist()
        out.append(Portal(_str(o, "id", p), (x, y, t)))
    return tuple(out)


def _occupied(raw: Any, path: str, slots: tuple[Slot, ...]) -> frozenset[str]:
    ids = {s.id for s in slots}
    seen: set[str] = set()
    for i, sid in enumerate(_list(raw, path)):
        if not isinstance(sid, str) or sid not in ids:
            raise LotFormatError(f"{path}[{i}]: expected the id of a slot, found {_found(sid)}")
        if sid in seen:
            raise LotFormatError(f"{path}[{i}]: slot {sid!r} is listed twice")
        seen.add(sid)
    return frozenset(seen)


def _geometry(raw: Any, path: str) -> Polygon | MultiPolygon:
    o = _object(raw, path, _GEOMETRY_KEYS)
    kind = o["type"]
    coords = f"{path}.coordinates"
    if kind == "Polygon":
        return _polygon(o["coordinates"], coords)
    if kind == "MultiPolygon":
        parts = [_polygon(p, f"{coords}[{i}]") for i, p in enumerate(_list(o["coordinates"],
                                                                            coords))]
        for i, p in enumerate(parts):
            if p.is_empty:
                raise LotFormatError(f"{coords}[{i}]: expected at least one ring, found none")
        return MultiPolygon(parts)
    raise LotFormatError(f"{path}.type: expected 'Polygon' or 'MultiPolygon', "
                         f"found {_found(kind)}")


def _polygon(raw: Any, path: str) -> Polygon:
    rings = [_array(r, f"{path}[{k}]", (None, 2), min_rows=4,
                    what="a closed ring of at least 4 [x, y] points")
             for k, r in enumerate(_list(raw, path))]
    for k, r in enumerate(rings):
        if not np.array_equal(r[0], r[-1]):
            raise LotFormatError(f"{path}[{k}]: expected a closed ring (last point equal to "
                                 f"the first), found {r[0].tolist()} … {r[-1].tolist()}")
    if not rings:
        return Polygon()
    return Polygon(rings[0], rings[1:])


# -- checked access ----------------------------------------------------------------------------
def _found(value: Any) -> str:
    """A short description of a JSON value for a message."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, dict):
        return "an object"
    if isinstance(value, list):
        return f"a list of {len(value)}" if value else "an empty list"
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _object(value: Any, path: str, keys: tuple[str, ...]) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise LotFormatError(f"{path}: expected an object, found {_found(value)}")
    if len(value) != len(keys) or any(k not in value for k in keys):
        missing = [k for k in keys if k not in value]
        if missing:
            raise LotFormatError(f"{path}: missing key {missing[0]!r}")
        extra = sorted(str(k) for k in value if k not in keys)
        raise LotFormatError(f"{path}: unknown key {extra[0]!r}; expected only "
                             f"{', '.join(keys)}")
    return value


def _list(value: Any, path: str) -> list:
    if not isinstance(value, list):
        raise LotFormatError(f"{path}: expected a list, found {_found(value)}")
    return value


def _str(o: dict, key: str, path: str) -> str:
    v = o[key]
    if not isinstance(v, str):
        raise LotFormatError(f"{path}.{key}: expected a string, found {_found(v)}")
    return v


def _choice(o: dict, key: str, path: str, choices: tuple[str, ...]) -> str:
    v = o[key]
    if not isinstance(v, str) or v not in choices:
        raise LotFormatError(f"{path}.{key}: expected one of {', '.join(choices)}, "
                             f"found {_found(v)}")
    return v


def _bool(o: dict, key: str, path: str) -> bool:
    v = o[key]
    if not isinstance(v, bool):
        raise LotFormatError(f"{path}.{key}: expected true or false, found {_found(v)}")
    return v


def _number(o: dict, key: str, path: str) -> float:
    v = o[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise LotFormatError(f"{path}.{key}: expected a number, found {_found(v)}")
    if isinstance(v, float) and not math.isfinite(v):
        raise LotFormatError(f"{path}.{key}: expected a finite number, found {_found(v)}")
    if abs(v) > MAX_MAGNITUDE:  # also an int too large for a float
        raise LotFormatError(f"{path}.{key}: expected a number of at most {MAX_MAGNITUDE:g} "
                             f"in size, found {_found(v)}")
    return float(v)


def _array(value: Any, path: str, shape: tuple[int | None, ...], *, what: str,
           min_rows: int = 0) -> FloatArray:
    """``value`` as a float array of ``shape`` (``None``: any length, at least ``min_rows``)."""
    a = _try_array(value)
    if a is None:
        found = _found(value)
        if isinstance(value, list):
            found += " whose items differ in shape or type"
        raise LotFormatError(f"{path}: expected {what}, found {found}")
    if a.dtype.kind not in "iuf":
        raise LotFormatError(f"{path}: expected {what}, found {_found(value)} holding "
                             "something other than numbers")
    if (a.ndim != len(shape) or (shape[0] is None and a.shape[0] < min_rows)
            or any(n is not None and n != m for n, m in zip(shape, a.shape, strict=True))):
        raise LotFormatError(f"{path}: expected {what}, found {_shape(a)}")
    if not np.isfinite(a).all():
        raise LotFormatError(f"{path}: expected {what}, found a non-finite number")
    if a.size and np.abs(a).max() > MAX_MAGNITUDE:
        raise LotFormatError(f"{path}: expected {what}, found a number larger than "
                             f"{MAX_MAGNITUDE:g} in size")
    return a.astype(float, copy=False)


def _shape(a: np.ndarray) -> str:
    if a.size == 0 and a.ndim == 1:
        return "an empty list"
    if a.ndim == 1:
        return f"a list of {a.shape[0]} numbers"
    if a.ndim == 2:
        return f"a list of {a.shape[0]} lists of {a.shape[1]} numbers"
    return f"nested lists of shape {a.shape}"


def _stacked(objs: list[dict], path: str, key: str, shape: tuple[int, ...],
             what: str) -> FloatArray:
    """``o[key]`` of every object as one (N, *shape) array, converted in one numpy call;
    a bad item is found (and named by its path) only when the whole does not convert."""
    if not objs:
        return np.zeros((0, *shape))
    values = [o[key] for o in objs]
    a = _try_array(values)
    if (a is not None and a.shape == (len(values), *shape) and a.dtype.kind in "iuf"
            and np.isfinite(a).all() and np.abs(a).max() <= MAX_MAGNITUDE):
        return a.astype(float, copy=False)
    for i, v in enumerate(values):
        _array(v, f"{path}[{i}].{key}", shape, what=what)
    raise LotFormatError(f"{path}: expected {what} as every item's {key}")  # not reached


def _try_array(value: Any) -> np.ndarray | None:
    """``value`` through ``np.asarray`` if it is a list that converts (not ragged)."""
    if not isinstance(value, list):
        return None
    try:
        return np.asarray(value)
    except (ValueError, TypeError, OverflowError):
        return None
