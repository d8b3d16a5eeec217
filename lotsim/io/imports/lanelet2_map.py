"""A Lanelet2 map as the importer reads it: its OSM XML parsed with the standard library
(:mod:`xml.parsers.expat`, which gives every element's line), projected into local metres.

:func:`read_lanelet2` returns a :class:`Lanelet2Map`: the lanelets (their bounds oriented
the way they are driven, the left bound on the left), the areas of Autoware's valet-parking
convention (``parking_spot`` and ``parking_access`` as ``type=multipolygon`` relations or
closed ways, assembled into polygons), and the line features of the building (walls,
kerbs, columns, ...) by their ``subtype``. Every problem is a
:class:`~lotsim.errors.ScenarioError` at the element's line.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

import numpy as np
import yaml
from shapely.geometry import Polygon

from lotsim.core.geometry import FloatArray
from lotsim.errors import Location, ScenarioError
from lotsim.io.imports.frame import TangentPlane

AREA_KINDS = ("parking_spot", "parking_access")
"""The ``subtype`` values of the areas the importer reads as spots and as access ground."""


@dataclass
class _Element:
    """One ``node``, ``way`` or ``relation`` of the file."""

    kind: str
    id: str
    line: int
    col: int
    attrs: dict[str, str]
    tags: dict[str, str] = field(default_factory=dict)
    refs: list[str] = field(default_factory=list)  # a way's nodes
    members: list[tuple[str, str, str]] = field(default_factory=list)  # (type, ref, role)


@dataclass(frozen=True)
class Lanelet:
    """A lanelet: its bounds [m] as driven (both in the direction of travel, ``left`` on the
    left), its tags and where it is in the file."""

    id: str
    left: FloatArray
    right: FloatArray
    tags: dict[str, str]
    where: Location

    @property
    def polygon(self) -> Polygon:
        """The ground between the bounds."""
        return Polygon(np.vstack([self.left, self.right[::-1]])).buffer(0)


@dataclass(frozen=True)
class MapArea:
    """A ``parking_spot`` or ``parking_access`` area: its outline [m], its tags."""

    id: str
    subtype: str
    polygon: Polygon
    tags: dict[str, str]
    where: Location


@dataclass(frozen=True)
class MapLine:
    """A way that draws part of the building (``subtype`` Walls, Kerbs, Columns, ...)."""

    id: str
    subtype: str
    points: FloatArray
    closed: bool
    where: Location


@dataclass(frozen=True)
class Lanelet2Map:
    """What the importer takes from a Lanelet2 file.

    Attributes
    ----------
    frame : TangentPlane
        The local plane its points are in.
    origin_source : str
        Where the frame's origin comes from (given, the map's ``map_config``, the centroid).
    error : float
        Bound of the projection's error over the map's nodes [m].
    points : ndarray, shape (N, 2)
        Every node [m], for the map's extent.
    lanelets, spots, accesses, lines
        In the order of the file.
    """

    source: Path
    frame: TangentPlane
    origin_source: str
    error: float
    points: FloatArray
    lanelets: tuple[Lanelet, ...]
    spots: tuple[MapArea, ...]
    accesses: tuple[MapArea, ...]
    lines: tuple[MapLine, ...]


def read_lanelet2(source: str | os.PathLike, *,
                  origin: tuple[float, float] | None = None) -> Lanelet2Map:
    """Read a Lanelet2 OSM XML file.

    Parameters
    ----------
    source : path
        The ``.osm`` file.
    origin : (lat, lon) or None
        Origin of the local frame [degrees]; None: the ``map_config`` yaml beside the file
        with the same stem (Autoware's ``latitude``, ``longitude``), else the centroid of
        the map's nodes.

    Raises
    ------
    ScenarioError
        The file is missing, is not XML or not OSM, or an element refers to one the file
        does not hold.
    """
    path = Path(source)
    elements = _parse(path)
    nodes = {e.id: e for e in elements if e.kind == "node"}
    ways = {e.id: e for e in elements if e.kind == "way"}
    if not nodes:
        raise ScenarioError(None, f"{path}: expected OSM nodes, found none")
    ids = list(nodes)
    lat = np.array([_coord(nodes[i], "lat", 90.0, path) for i in ids])
    lon = np.array([_coord(nodes[i], "lon", 180.0, path) for i in ids])
    frame, origin_source = _frame(path, origin, lat, lon)
    x, y = frame.to_local(lat, lon)
    pts = np.column_stack([x, y])
    where_of = {i: k for k, i in enumerate(ids)}

    def way_points(w: _Element) -> FloatArray:
        missing = [r for r in w.refs if r not in where_of]
        if missing:
            raise ScenarioError(_loc(path, w), f"way {w.id} refers to node {missing[0]}, "
                                               "which the file does not hold")
        if len(w.refs) < 2:
            raise ScenarioError(_loc(path, w), f"way {w.id} has fewer than two nodes")
        return pts[[where_of[r] for r in w.refs]]

    def member_way(rel: _Element, ref: str) -> _Element:
        if ref not in ways:
            raise ScenarioError(_loc(path, rel), f"relation {rel.id} refers to way {ref}, "
                                                 "which the file does not hold")
        return ways[ref]

    lanelets, spots, accesses = [], [], []
    in_relation: set[str] = set()
    for e in elements:
        if e.kind != "relation":
            continue
        kind, subtype = e.tags.get("type"), e.tags.get("subtype")
        if kind == "lanelet":
            if subtype not in (None, "lane", "road"):
                continue
            left = [r for t, r, role in e.members if t == "way" and role == "left"]
            right = [r for t, r, role in e.members if t == "way" and role == "right"]
            if len(left) != 1 or len(right) != 1:
                raise ScenarioError(_loc(path, e), f"lanelet {e.id} needs one left and one "
                                                   f"right bound, found {len(left)} and "
                                                   f"{len(right)}")
            lanelets.append(_lanelet(e, way_points(member_way(e, left[0])),
                                     way_points(member_way(e, right[0])), path))
        elif kind == "multipolygon" and subtype in AREA_KINDS:
            outer = [member_way(e, r) for t, r, role in e.members
                     if t == "way" and role in ("outer", "")]
            in_relation.update(w.id for w in outer)
            poly = _assemble(e, outer, way_points, path)
            (spots if subtype == "parking_spot" else accesses).append(
                MapArea(e.id, subtype, poly, e.tags, _loc(path, e)))
    lines = []
    for w in ways.values():
        subtype = w.tags.get("subtype")
        closed = len(w.refs) > 3 and w.refs[0] == w.refs[-1]
        if subtype in AREA_KINDS:
            if closed and w.id not in in_relation and w.tags.get("type") in ("area", None):
                poly = _ring(w, way_points(w), path)
                (spots if subtype == "parking_spot" else accesses).append(
                    MapArea(w.id, subtype, poly, w.tags, _loc(path, w)))
        elif subtype is not None and w.tags.get("type") == "area":
            lines.append(MapLine(w.id, subtype, way_points(w), closed, _loc(path, w)))
    error = frame.error_over(x, y)
    return Lanelet2Map(path, frame, origin_source, error, pts, tuple(lanelets), tuple(spots),
                       tuple(accesses), tuple(lines))


def id_key(ident: str) -> tuple[int, int | str]:
    """Order of OSM ids: numbers by value (negative ones, of elements not yet uploaded,
    too), then any other text."""
    return (0, int(ident)) if ident.lstrip("-").isdigit() else (1, ident)


# -- the file ---------------------------------------------------------------------------------
def _parse(path: Path) -> list[_Element]:
    """The file's nodes, ways and relations, with their lines."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise ScenarioError(None, f"{path}: no such file") from None
    except OSError as exc:
        raise ScenarioError(None, f"{path}: cannot read it: {exc.strerror or exc}") from None
    elements: list[_Element] = []
    stack: list[str] = []
    root: list[str] = []
    parser = expat.ParserCreate()

    def start(name: str, attrs: dict[str, str]) -> None:
        if not stack:
            root.append(name)
        if len(stack) == 1 and name in ("node", "way", "relation"):
            if "id" not in attrs:
                raise ScenarioError(Location(str(path), parser.CurrentLineNumber,
                                             parser.CurrentColumnNumber + 1),
                                    f"expected an id on this {name}")
            elements.append(_Element(name, attrs["id"], parser.CurrentLineNumber,
                                     parser.CurrentColumnNumber + 1, attrs))
        elif len(stack) == 2 and stack[1] in ("node", "way", "relation") and elements:
            e = elements[-1]
            if name == "tag" and "k" in attrs:
                e.tags[attrs["k"]] = attrs.get("v", "")
            elif name == "nd" and "ref" in attrs:
                e.refs.append(attrs["ref"])
            elif name == "member" and "ref" in attrs:
                e.members.append((attrs.get("type", ""), attrs["ref"], attrs.get("role", "")))
        stack.append(name)

    def end(name: str) -> None:
        stack.pop()

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        raise ScenarioError(Location(str(path), exc.lineno, exc.offset + 1),
                            f"not well-formed XML: {expat.ErrorString(exc.code)}") from None
    if root != ["osm"]:
        raise ScenarioError(None, f"{path}: expected an OSM XML file (<osm> at the top), "
                                  f"found <{root[0] if root else ''}>")
    return elements


def _loc(path: Path, e: _Element) -> Location:
    return Location(str(path), e.line, e.col, f"{e.kind}/{e.id}")


def _coord(e: _Element, key: str, limit: float, path: Path) -> float:
    try:
        value = float(e.attrs[key])
    except (KeyError, ValueError):
        raise ScenarioError(_loc(path, e), f"expected a number as {key}, found "
                                           f"{e.attrs.get(key)!r}") from None
    if not math.isfinite(value) or abs(value) > limit:
        raise ScenarioError(_loc(path, e), f"expected {key} within ±{limit:g}, found {value}")
    return value


def _frame(path: Path, origin: tuple[float, float] | None, lat: FloatArray,
           lon: FloatArray) -> tuple[TangentPlane, str]:
    """The local frame and a line saying where its origin comes from."""
    if origin is not None:
        la, lo = (float(v) for v in origin)
        if not (abs(la) <= 90 and abs(lo) <= 180):
            raise ScenarioError(None, f"origin ({la}, {lo}): expected lat within ±90 and lon "
                                      "within ±180 degrees")
        return TangentPlane(la, lo), "origin given"
    config = path.with_suffix(".yaml")
    if config.is_file():
        la, lo = _map_config(config)
        return TangentPlane(la, lo), f"origin from the map's {config.name} (map_config)"
    # the mean of the nodes' unit vectors: right across the date line too
    la, lo = np.radians(lat), np.radians(lon)
    v = np.array([np.cos(la) * np.cos(lo), np.cos(la) * np.sin(lo), np.sin(la)]).mean(axis=1)
    c_lat = math.degrees(math.atan2(v[2], math.hypot(v[0], v[1])))
    c_lon = math.degrees(math.atan2(v[1], v[0]))
    return TangentPlane(c_lat, c_lon), "origin at the centroid of the map's nodes"


def _map_config(config: Path) -> tuple[float, float]:
    """Autoware's map origin: ``map_config: {latitude, longitude}`` (or the keys at top)."""
    try:
        doc = yaml.safe_load(config.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise ScenarioError(None, f"{config}: cannot read the map's origin: {exc}") from None
    body = doc.get("map_config", doc) if isinstance(doc, dict) else None
    try:
        la, lo = float(body["latitude"]), float(body["longitude"])
    except (TypeError, KeyError, ValueError):
        raise ScenarioError(None, f"{config}: expected map_config with latitude and "
                                  "longitude") from None
    if not (abs(la) <= 90 and abs(lo) <= 180):
        raise ScenarioError(None, f"{config}: latitude {la}, longitude {lo} out of range")
    return la, lo


# -- geometry ---------------------------------------------------------------------------------
def _lanelet(e: _Element, left: FloatArray, right: FloatArray, path: Path) -> Lanelet:
    """Orient the bounds: both one way (a bound drawn the other way is turned), and that way
    the one with the left bound on its left (Lanelet2's rule; a map's ``direction`` tags are
    not needed)."""
    same = np.hypot(*(left[0] - right[0])) + np.hypot(*(left[-1] - right[-1]))
    crossed = np.hypot(*(left[0] - right[-1])) + np.hypot(*(left[-1] - right[0]))
    if crossed < same:
        right = right[::-1]
    mid = (left[-1] + right[-1]) / 2 - (left[0] + right[0]) / 2
    across = _mean_point(left) - _mean_point(right)
    if float(np.hypot(*mid)) < 1e-6:
        raise ScenarioError(_loc(path, e), f"lanelet {e.id} has no length")
    if mid[0] * across[1] - mid[1] * across[0] < 0:  # drawn against the way it is driven
        left, right = left[::-1], right[::-1]
    return Lanelet(e.id, left, right, e.tags, _loc(path, e))


def _mean_point(line: FloatArray) -> FloatArray:
    """The mean of a polyline's points, weighted by length."""
    seg = np.hypot(*np.diff(line, axis=0).T)
    if seg.sum() <= 0:
        return line.mean(axis=0)
    mids = (line[1:] + line[:-1]) / 2
    return (mids * seg[:, None]).sum(axis=0) / seg.sum()


def _ring(w: _Element, pts: FloatArray, path: Path) -> Polygon:
    poly = Polygon(pts)
    if not poly.is_valid or poly.area <= 1e-6:
        raise ScenarioError(_loc(path, w), f"way {w.id} is not a simple polygon")
    return poly


def _assemble(rel: _Element, outer: list[_Element], way_points, path: Path) -> Polygon:
    """A multipolygon's one outer ring, joined from its ways end to end by node ids."""
    if not outer:
        raise ScenarioError(_loc(path, rel), f"relation {rel.id} has no outer way")
    pieces = [list(w.refs) for w in outer]
    for w in outer:
        way_points(w)  # every node known
    ring = pieces.pop(0)
    while pieces:
        for k, p in enumerate(pieces):
            if p[0] == ring[-1]:
                ring += p[1:]
            elif p[-1] == ring[-1]:
                ring += p[::-1][1:]
            else:
                continue
            pieces.pop(k)
            break
        else:
            raise ScenarioError(_loc(path, rel), f"relation {rel.id}: its outer ways do not "
                                                 "join into one closed ring")
    if ring[0] != ring[-1] or len(ring) < 4:
        raise ScenarioError(_loc(path, rel), f"relation {rel.id}: its outer ring is not closed")
    members = {r: p for w in outer for r, p in zip(w.refs, way_points(w), strict=True)}
    poly = Polygon([members[r] for r in ring])
    if not poly.is_valid or poly.area <= 1e-6:
        raise ScenarioError(_loc(path, rel), f"relation {rel.id}: its outer ring is not a "
                                             "simple polygon")
    return poly
