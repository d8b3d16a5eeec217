"""Reading a result: :func:`read_result`, and the lot and vehicles parsed from it with the
``structure`` rule (a vehicle whose structure is broken is left out of the later rules)."""

from __future__ import annotations

import gzip
import json
import math
import os
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from lotsim.errors import ResultFormatError
from lotsim.verify.report import Violation, _add
from lotsim.verify.tolerances import (
    BAY_USES,
    FORMAT,
    LOT_KEYS,
    MARKS,
    MAX_MAGNITUDE,
    SAMPLE_KEYS,
    SHRINK,
    SLOT_KINDS,
    STATUSES,
    TOP_LEVEL_KEYS,
    TYPE_NUMBERS,
    VEHICLE_KEYS,
    VERSION,
    FloatArray,
    Pose,
)

GZIP_MAGIC = b"\x1f\x8b"
"""The first two bytes of a gzip file: a result in its compact form."""


def read_result(path: str | os.PathLike[str], *, packed: bool = False) -> dict:
    """Read a ``result.json``, or its compact form (``result.json.gz``: gzip-compressed,
    each vehicle's samples encoded as whole numbers, read back to the same numbers).

    Parameters
    ----------
    path : str or path-like
        The file.
    packed : bool, keyword-only
        Each vehicle's sample columns (``samples.t``, ``.x``, …) as numpy float arrays,
        made as the file is read, instead of lists: a list of floats takes four times the
        memory, and a thousand cars' result holds some twelve million of them. What
        :func:`check_result` and a replay read them as; a column that is not a list of
        numbers stays as read.

    Returns
    -------
    dict
        The parsed result, recognised by its ``format``, ``version`` and top-level keys;
        its content is judged by :func:`check_result`.

    Raises
    ------
    ResultFormatError
        The file cannot be read, is not JSON or is not a lotsim result; the message
        names the file and says why.

    Examples
    --------
    >>> read_result("/no/result.json")
    Traceback (most recent call last):
    ...
    lotsim.errors.ResultFormatError: /no/result.json: cannot read it (No such file or directory)
    """
    name = os.fspath(path)
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ResultFormatError(f"{name}: cannot read it ({exc.strerror or exc})") from None
    if raw[:2] == GZIP_MAGIC:  # the compact form (``result.json.gz``)
        try:
            raw = gzip.decompress(raw)
        except (OSError, EOFError, zlib.error) as exc:
            raise ResultFormatError(f"{name}: not a whole gzip file ({exc})") from None
    try:
        data = json.loads(raw, object_hook=_packed if packed else _decoded)
    except _EncodingProblem as exc:
        raise ResultFormatError(f"{name}: a vehicle's samples: {exc}") from None
    except json.JSONDecodeError as exc:
        raise ResultFormatError(
            f"{name}: not JSON (line {exc.lineno}, column {exc.colno}: {exc.msg})") from None
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise ResultFormatError(f"{name}: not JSON ({exc})") from None
    problem = _format_problem(data)
    if problem is not None:
        raise ResultFormatError(f"{name}: {problem}")
    return data


ENCODING_KEYS = ("decimals", "differences")
"""The keys of a vehicle's ``samples.encoding`` in a result's compact form."""


class _EncodingProblem(ValueError):
    """A vehicle's samples say they are encoded but cannot be decoded: why."""


def _decoded(obj: dict, *, arrays: bool = False) -> dict:
    """A JSON object as read; the samples of the compact form (``"encoding"`` beside the
    columns: whole numbers of each column's last decimal, differenced ``differences``
    times) decoded to the numbers of the plain form: lists of floats (of whole numbers for
    a column of no decimals), or float arrays with ``arrays``. Raises
    :class:`_EncodingProblem` for an encoding it cannot decode."""
    if "encoding" not in obj or not all(key in obj for key in SAMPLE_KEYS):
        return obj
    enc = obj.pop("encoding")
    if not (isinstance(enc, dict) and sorted(enc) == sorted(ENCODING_KEYS)
            and isinstance(enc["decimals"], dict)
            and sorted(enc["decimals"]) == sorted(SAMPLE_KEYS)):
        raise _EncodingProblem(f"'encoding' must be an object of {list(ENCODING_KEYS)}, "
                               f"'decimals' naming each of {list(SAMPLE_KEYS)}")
    times = enc["differences"]
    if type(times) is not int or not 0 <= times <= 3:
        raise _EncodingProblem(f"'differences' must be 0 to 3, not {times!r}")
    for key in SAMPLE_KEYS:
        k, col = enc["decimals"][key], obj[key]
        if type(k) is not int or not 0 <= k <= 9:
            raise _EncodingProblem(f"the decimals of '{key}' must be 0 to 9, not {k!r}")
        if not (isinstance(col, list)
                and all(type(n) is int and abs(n) <= MAX_WHOLE for n in col)):
            raise _EncodingProblem(f"'{key}' must be a list of whole numbers of at most "
                                   f"{MAX_WHOLE} in size")
        if not col:
            continue
        n = np.array(col, dtype=np.int64)
        check = n.astype(float)
        for _ in range(times):
            n, check = np.cumsum(n), np.cumsum(check)
        if np.abs(n - check).max() > 1e-9 * np.abs(check).max() + 1:
            raise _EncodingProblem(f"'{key}' sums beyond the range of whole numbers")
        obj[key] = n / 10.0 ** k if arrays else (n / 10.0 ** k).tolist() if k else n.tolist()
    return obj


MAX_WHOLE = 2 ** 53
"""The largest whole number, in size, of an encoded sample column (a float holds each one
exactly)."""


def _packed(obj: dict) -> dict:
    """A JSON object as read, decoded (:func:`_decoded`), with its sample columns as float
    arrays when it has all of :data:`SAMPLE_KEYS` (the lists of numbers among them, as
    :func:`_samples` makes them): each object is handed over as soon as it is read, so a
    vehicle's lists are let go before the next vehicle is read."""
    if "encoding" in obj:
        return _decoded(obj, arrays=True)
    if all(key in obj for key in SAMPLE_KEYS):
        for key in SAMPLE_KEYS:
            col = obj[key]
            if isinstance(col, list) and col:
                arr = _numbers(col)
                if arr is not None:
                    obj[key] = arr
    return obj


def _numbers(col: list) -> np.ndarray | None:
    """A non-empty list of numbers as a float array; None when it is not one."""
    try:
        arr = np.asarray(col)
    except (ValueError, TypeError):
        return None
    return arr.astype(float) if arr.ndim == 1 and arr.dtype.kind in "iuf" else None


@dataclass(frozen=True, slots=True)
class _Slot:
    id: str
    polygon: shapely.Polygon
    occupied: bool
    use: str = "standard"


@dataclass(slots=True)
class _Lot:
    boundary: shapely.Polygon | None = None
    paved: shapely.MultiPolygon | None = None  # None: all inside the boundary is paved
    slots: dict[str, _Slot] = field(default_factory=dict)
    obstacles: list[shapely.Polygon] = field(default_factory=list)
    access_aisles: list[tuple[str, shapely.Polygon]] = field(default_factory=list)
    parked: list[shapely.Polygon] = field(default_factory=list)
    speed_limit: float = math.inf
    zones: list[tuple[str, shapely.Polygon, float]] = field(default_factory=list)
    entrances: dict[str, Pose] | None = None  # None: unknown, do not cross-check
    exits: dict[str, Pose] = field(default_factory=dict)


@dataclass(slots=True)
class _Vehicle:
    index: int
    id: str
    status: str
    slot: str | None
    reason: str
    arrival: float
    width: float
    front: float
    rear: float
    wheelbase: float
    max_steer: float
    max_forward_speed: float
    max_reverse_speed: float
    max_accel: float
    max_brake: float
    max_lateral_accel: float
    max_steer_rate: float
    max_jerk: float
    t: FloatArray
    x: FloatArray
    y: FloatArray
    theta: FloatArray
    v: FloatArray
    steer: FloatArray
    gear: FloatArray
    inside: dict | None = None  # where it stood when it came, in the lot: slot or pose
    marks: frozenset[str] = frozenset()  # what its type is marked as (accessible, ev, ...)

    @property
    def n(self) -> int:
        return len(self.t)

    @property
    def min_radius(self) -> float:
        return self.wheelbase / math.tan(self.max_steer)


def _is_number(value: Any) -> bool:
    """A JSON number (not a boolean) of at most ``MAX_MAGNITUDE`` in size."""
    return (isinstance(value, int | float) and not isinstance(value, bool)
            and abs(value) <= MAX_MAGNITUDE)


def _kind(value: Any) -> str:
    names = {dict: "object", list: "list", str: "string", bool: "boolean", type(None): "null"}
    return names.get(type(value), type(value).__name__)


def _format_problem(data: Any) -> str | None:
    """Why ``data`` is not a lotsim result at all, or None."""
    if not isinstance(data, dict):
        return f"not a lotsim result: expected a JSON object, found {_kind(data)}"
    if data.get("format") != FORMAT:
        return (f"not a lotsim result: 'format' is {data.get('format')!r}, "
                f"expected {FORMAT!r}")
    missing = [k for k in TOP_LEVEL_KEYS if k not in data]
    if missing:
        keys = ", ".join(repr(k) for k in missing)
        return f"not a lotsim result: missing top-level key{'s' if len(missing) > 1 else ''} {keys}"
    version = data.get("version")
    if version != VERSION or isinstance(version, bool):
        return f"unsupported result version {version!r} (this checker reads version {VERSION})"
    return None


def _points(value: Any) -> np.ndarray | None:
    """A list of ``[x, y]`` finite numbers as an (N, 2) array, else None."""
    if not isinstance(value, list):
        return None
    for p in value:
        if not (isinstance(p, list) and len(p) == 2 and _is_number(p[0]) and _is_number(p[1])):
            return None
    return np.array(value, dtype=float).reshape(-1, 2)


def _polygon(value: Any, where: str, out: list[Violation]) -> shapely.Polygon | None:
    pts = _points(value)
    if pts is None or len(pts) < 3:
        _add(out, "structure", None, None,
             f"{where}: expected a polygon [[x, y], ...] of at least 3 finite points")
        return None
    poly = shapely.Polygon(pts)
    if not poly.is_valid or poly.area <= 0:
        _add(out, "structure", None, None,
             f"{where}: not a valid polygon ({shapely.is_valid_reason(poly)})")
        return None
    return poly


def _multipolygon(value: Any, where: str, out: list[Violation]) -> shapely.MultiPolygon | None:
    """GeoJSON MultiPolygon coordinates: polygons, each its outline then its holes."""
    if not isinstance(value, list) or not value:
        _add(out, "structure", None, None, f"{where}: expected a non-empty list of polygons")
        return None
    polys = []
    for i, rings in enumerate(value):
        pts = [_points(r) for r in rings] if isinstance(rings, list) and rings else [None]
        if any(p is None or len(p) < 3 for p in pts):
            _add(out, "structure", None, None, f"{where}[{i}]: expected a list of rings "
                 f"[[x, y], ...] of at least 3 finite points, the outline first")
            return None
        polys.append(shapely.Polygon(pts[0], pts[1:]))
    geom = shapely.MultiPolygon(polys)
    if not geom.is_valid:
        _add(out, "structure", None, None,
             f"{where}: not a valid multipolygon ({shapely.is_valid_reason(geom)})")
        return None
    return geom


def _pose(value: Any) -> Pose | None:
    if isinstance(value, list) and len(value) == 3 and all(_is_number(c) for c in value):
        return (float(value[0]), float(value[1]), float(value[2]))
    return None


def _parse_lot(raw: Any, out: list[Violation]) -> _Lot:
    lot = _Lot()
    if not isinstance(raw, dict):
        _add(out, "structure", None, None, f"lot: expected an object, found {_kind(raw)}")
        return lot
    for key in LOT_KEYS:
        if key not in raw:
            _add(out, "structure", None, None, f"lot: missing key {key!r}")
    if "boundary" in raw:
        lot.boundary = _polygon(raw["boundary"], "lot.boundary", out)
    if "paved" in raw:
        lot.paved = _multipolygon(raw["paved"], "lot.paved", out)

    slots = raw.get("slots", [])
    if not isinstance(slots, list):
        _add(out, "structure", None, None, "lot.slots: expected a list")
        slots = []
    occupied = 0
    for i, s in enumerate(slots):
        where = f"lot.slots[{i}]"
        if not isinstance(s, dict):
            _add(out, "structure", None, None, f"{where}: expected an object")
            continue
        sid = s.get("id")
        if not isinstance(sid, str) or not sid:
            _add(out, "structure", None, None, f"{where}.id: expected a non-empty string")
            continue
        where = f"slot {sid}"
        if sid in lot.slots:
            _add(out, "structure", None, None, f"{where}: the id is used twice")
        if s.get("kind") not in SLOT_KINDS:
            _add(out, "structure", None, None,
                 f"{where}: kind {s.get('kind')!r} is not one of {', '.join(SLOT_KINDS)}")
        if not isinstance(s.get("occupied"), bool):
            _add(out, "structure", None, None, f"{where}: 'occupied' must be true or false")
        use = s.get("use", "standard")
        if use not in BAY_USES:
            _add(out, "structure", None, None,
                 f"{where}: use {use!r} is not one of {', '.join(BAY_USES)}")
        poly = _polygon(s.get("polygon"), f"{where}.polygon", out)
        if poly is not None:
            lot.slots[sid] = _Slot(sid, poly, s.get("occupied") is True,
                                   use if use in BAY_USES else "standard")
        occupied += s.get("occupied") is True

    for key in ("obstacles", "parked"):
        polys = raw.get(key, [])
        if not isinstance(polys, list):
            _add(out, "structure", None, None, f"lot.{key}: expected a list of polygons")
            continue
        for i, p in enumerate(polys):
            poly = _polygon(p, f"lot.{key}[{i}]", out)
            if poly is not None:
                getattr(lot, key).append(poly)
        if key == "parked" and len(polys) != occupied:
            _add(out, "structure", None, None,
                 f"lot.parked holds {len(polys)} cars but {occupied} slots are occupied")

    aisles = raw.get("access_aisles", [])  # optional: a lot without accessible bays
    if not isinstance(aisles, list):
        _add(out, "structure", None, None, "lot.access_aisles: expected a list")
        aisles = []
    for i, a in enumerate(aisles):
        where = f"lot.access_aisles[{i}]"
        if not (isinstance(a, dict) and isinstance(a.get("id"), str)):
            _add(out, "structure", None, None, f"{where}: expected {{\"id\": ..., "
                 f"\"polygon\": [[x, y], ...]}}")
            continue
        poly = _polygon(a.get("polygon"), f"{where}.polygon", out)
        if poly is not None:
            lot.access_aisles.append((a["id"], poly))

    if "speed_limit" in raw:
        if _is_number(raw["speed_limit"]) and raw["speed_limit"] > 0:
            lot.speed_limit = float(raw["speed_limit"])
        else:
            _add(out, "structure", None, None,
                 f"lot.speed_limit: expected a positive number, found {raw['speed_limit']!r}")

    zones = raw.get("speed_zones", [])
    if not isinstance(zones, list):
        _add(out, "structure", None, None, "lot.speed_zones: expected a list")
        zones = []
    for i, z in enumerate(zones):
        where = f"lot.speed_zones[{i}]"
        if not isinstance(z, dict):
            _add(out, "structure", None, None, f"{where}: expected an object")
            continue
        zid = z.get("id")
        if not isinstance(zid, str):
            _add(out, "structure", None, None, f"{where}.id: expected a string, found {zid!r}")
        limit = z.get("limit")
        if not (_is_number(limit) and limit > 0):
            _add(out, "structure", None, None,
                 f"{where}.limit: expected a positive number, found {limit!r}")
            continue
        poly = _polygon(z.get("polygon"), f"{where}.polygon", out)
        if poly is not None:
            lot.zones.append((str(zid), poly, float(limit)))

    for key in ("entrances", "exits"):
        portals = raw.get(key, [])
        found: dict[str, Pose] = {}
        if not isinstance(portals, list):
            _add(out, "structure", None, None, f"lot.{key}: expected a list")
            portals = []
        for i, p in enumerate(portals):
            pid = p.get("id") if isinstance(p, dict) else None
            pose = _pose(p.get("pose")) if isinstance(p, dict) else None
            if not isinstance(pid, str) or pose is None:
                _add(out, "structure", None, None,
                     f"lot.{key}[{i}]: expected {{\"id\": ..., \"pose\": [x, y, theta]}}")
                continue
            found[pid] = pose
        if key == "entrances":
            lot.entrances = found if isinstance(raw.get(key), list) else None
        else:
            lot.exits = found
    return lot


def _samples(raw: Any, problems: list[str]) -> dict[str, np.ndarray] | None:
    if not isinstance(raw, dict):
        problems.append(f"samples: expected an object, found {_kind(raw)}")
        return None
    cols: dict[str, np.ndarray] = {}
    for key in SAMPLE_KEYS:
        col = raw.get(key)
        if isinstance(col, np.ndarray) and col.ndim == 1 and col.dtype == float:
            arr = col  # read packed (:func:`read_result`)
        elif not isinstance(col, list):
            problems.append(f"samples.{key}: expected a list of numbers, found {_kind(col)}")
            continue
        else:
            arr = _numbers(col) if col else np.zeros(0)
            if arr is None:
                problems.append(f"samples.{key}: expected a list of numbers")
                continue
        bad = np.flatnonzero(~(np.abs(arr) <= MAX_MAGNITUDE))
        if bad.size:
            problems.append(f"samples.{key}[{bad[0]}] is {arr[bad[0]]}, not a finite number"
                            + ("" if not np.isfinite(arr[bad[0]]) else
                               f" of at most {MAX_MAGNITUDE:g}"))
            continue
        cols[key] = arr
    if len(cols) < len(SAMPLE_KEYS):
        return None
    lengths = {key: len(arr) for key, arr in cols.items()}
    if len(set(lengths.values())) > 1:
        problems.append("samples: arrays of unequal length ("
                        + ", ".join(f"{k} {n}" for k, n in lengths.items()) + ")")
        return None
    t = cols["t"]
    step = np.flatnonzero(np.diff(t) <= 0)
    if step.size:
        i = int(step[0])
        problems.append(f"samples.t is not strictly increasing at index {i + 1} "
                        f"({t[i]:.6g} s, then {t[i + 1]:.6g} s)")
    gear = np.flatnonzero(~np.isin(cols["gear"], (-1.0, 0.0, 1.0)))
    if gear.size:
        problems.append(f"samples.gear[{gear[0]}] is {cols['gear'][gear[0]]:g}, "
                        "not -1, 0 or 1")
    return None if step.size or gear.size else cols


def _parse_vehicle(i: int, raw: Any, lot: _Lot, out: list[Violation]) -> _Vehicle | None:
    """The vehicle, or None (after reporting why) when its structure is broken."""
    if not isinstance(raw, dict):
        _add(out, "structure", None, None, f"vehicles[{i}]: expected an object")
        return None
    vid = raw.get("id")
    name = vid if isinstance(vid, str) and vid else f"vehicles[{i}]"
    problems: list[str] = [f"missing key {k!r}" for k in VEHICLE_KEYS if k not in raw]
    if "id" in raw and not (isinstance(vid, str) and vid):
        problems.append(f"id: expected a non-empty string, found {vid!r}")
    vtype = raw.get("type")
    dims: dict[str, float] = {}
    if isinstance(vtype, dict):
        if not isinstance(vtype.get("name"), str):
            problems.append("type.name: expected a string")
        for key in TYPE_NUMBERS:
            value = vtype.get(key)
            if not _is_number(value):
                problems.append(f"type.{key}: expected a number, found {value!r}")
            else:
                dims[key] = float(value)
        if len(dims) == len(TYPE_NUMBERS):
            if not 0 < dims["max_steer"] < math.pi / 2:
                problems.append(f"type.max_steer {dims['max_steer']} is not in (0, pi/2)")
            if dims["width"] <= 2 * SHRINK or dims["front"] + dims["rear"] <= 2 * SHRINK:
                problems.append("type: the footprint is empty")
            for key in TYPE_NUMBERS[3:]:
                if key != "max_steer" and dims[key] <= 0:
                    problems.append(f"type.{key} must be positive")
        marks = vtype.get("marks", [])
        if not (isinstance(marks, list) and all(m in MARKS for m in marks)):
            problems.append(f"type.marks: expected a list of {', '.join(MARKS)}, found "
                            f"{marks!r}")
    elif "type" in raw:
        problems.append(f"type: expected an object, found {_kind(vtype)}")
    arrival = raw.get("arrival")
    if "arrival" in raw and not _is_number(arrival):
        problems.append(f"arrival: expected a number, found {arrival!r}")
    entrance = raw.get("entrance")
    inside = _inside(raw, lot, problems)
    if "entrance" in raw:
        if entrance is None and inside is not None:
            pass  # in the lot when it came
        elif not isinstance(entrance, str):
            problems.append(f"entrance: expected a string (or null for a car with "
                            f"'inside'), found {entrance!r}")
        elif inside is not None:
            problems.append(f"entrance {entrance!r}: a car inside the lot when it came has "
                            f"none (null)")
        elif lot.entrances is not None and entrance not in lot.entrances:
            problems.append(f"entrance {entrance!r} is not an entrance of the lot")
    slot = raw.get("slot")
    if "slot" in raw and slot is not None and not isinstance(slot, str):
        problems.append(f"slot: expected a string or null, found {slot!r}")
    status = raw.get("status")
    if "status" in raw and status not in STATUSES:
        problems.append(f"status {status!r} is not one of {', '.join(STATUSES)}")
    reason = raw.get("reason")
    if "reason" in raw and not isinstance(reason, str):
        problems.append(f"reason: expected a string, found {reason!r}")
    cols = _samples(raw["samples"], problems) if "samples" in raw else None
    for p in problems:
        _add(out, "structure", name, None, f"{name}: {p}")
    if problems or cols is None:
        return None
    return _Vehicle(i, name, status, slot, reason, float(arrival),
                    **{key: dims[key] for key in TYPE_NUMBERS}, **cols, inside=inside,
                    marks=frozenset(vtype.get("marks", [])))


def _inside(raw: dict, lot: _Lot, problems: list[str]) -> dict | None:
    """A vehicle's ``inside`` (where it stood when it came into the run, in the lot): a
    slot of the lot, or a pose; None when it came by a gate."""
    if "inside" not in raw:
        return None
    got = raw["inside"]
    if isinstance(got, dict) and set(got) == {"slot"} and isinstance(got["slot"], str):
        if got["slot"] not in lot.slots:
            problems.append(f"inside.slot {got['slot']!r} is not a slot of the lot")
        return {"slot": got["slot"]}
    if (isinstance(got, dict) and set(got) == {"pose"} and isinstance(got["pose"], list)
            and len(got["pose"]) == 3 and all(_is_number(c) for c in got["pose"])):
        return {"pose": tuple(float(c) for c in got["pose"])}
    problems.append(f"inside: expected {{'slot': id}} or {{'pose': [x, y, theta]}}, found "
                    f"{got!r}")
    return None
