"""Reading OpenStreetMap files: ``.osm`` XML (plain, gzip or bzip2) with the standard
library, ``.osm.pbf`` with pyosmium (the optional extra ``lotsim[osm]``).

Both readers give the same :class:`OsmData`: every node's position in integer units of
10⁻⁷ degrees (the precision OpenStreetMap stores, so that the two readings agree bit for
bit), the tags of tagged nodes, every way (its node ids and tags) and every relation (its
members and tags). Objects a JOSM file marks deleted, or as not visible, are left out. The
file's kind is read from its first bytes, not its name.
"""

from __future__ import annotations

import bz2
import gzip
import os
import xml.etree.ElementTree as ET
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from lotsim.errors import Location, LotsimError, ScenarioError

OSM_EXTRA = "pip install 'lotsim[osm]'"
"""How a user gets the PBF reader."""

E7 = 10_000_000
"""OpenStreetMap's unit of latitude and longitude: 10⁻⁷ degree."""


@dataclass(frozen=True, slots=True)
class OsmWay:
    """A way: its node ids in order and its tags."""

    refs: tuple[int, ...]
    tags: dict[str, str]


@dataclass(frozen=True, slots=True)
class OsmRelation:
    """A relation: its members as ``(type, ref, role)`` (type ``node``, ``way`` or
    ``relation``) and its tags."""

    members: tuple[tuple[str, int, str], ...]
    tags: dict[str, str]


@dataclass
class OsmData:
    """What an OpenStreetMap file holds.

    Attributes
    ----------
    nodes : dict
        Node id -> ``(lat, lon)`` in units of 10⁻⁷ degree (:data:`E7`).
    node_tags : dict
        Node id -> tags, for the nodes that have tags.
    ways, relations : dict
        Id -> :class:`OsmWay` / :class:`OsmRelation`.
    """

    nodes: dict[int, tuple[int, int]] = field(default_factory=dict)
    node_tags: dict[int, dict[str, str]] = field(default_factory=dict)
    ways: dict[int, OsmWay] = field(default_factory=dict)
    relations: dict[int, OsmRelation] = field(default_factory=dict)

    def latlon(self, node: int) -> tuple[float, float]:
        """A node's latitude and longitude [degrees]."""
        lat, lon = self.nodes[node]
        return lat / E7, lon / E7


def read_osm(source: str | os.PathLike, *,
             progress: Callable[[str], None] | None = None) -> OsmData:
    """Read an OpenStreetMap file: XML (``.osm``, also gzip- or bzip2-compressed) or PBF.

    Raises
    ------
    LotsimError
        The file is missing, is neither kind, or the PBF reader is not installed.
    ScenarioError
        The XML is broken (located at its line and column) or holds a value that is not
        what OpenStreetMap writes there.
    """
    path = Path(source)
    if not path.is_file():
        what = "is a folder" if path.is_dir() else "no such file"
        raise LotsimError(f"{path}: {what}")
    with open(path, "rb") as fh:
        head = fh.read(64)
    kind = sniff(head)
    if kind is None:
        raise LotsimError(f"{path}: not an OpenStreetMap file: expected OSM XML (<osm ...>), "
                          "gzip- or bzip2-compressed XML, or PBF")
    if progress is not None:
        progress(f"reading {path.name} ({kind})")
    if kind == "pbf":
        return _read_pbf(path)
    opener = {"xml": open, "xml.gz": gzip.open, "xml.bz2": bz2.open}[kind]
    try:
        with opener(path, "rb") as fh:
            return _read_xml(fh, str(path))
    except (OSError, EOFError) as exc:  # a broken compressed stream
        raise LotsimError(f"{path}: cannot read it: {exc}") from None


def sniff(head: bytes) -> str | None:
    """The kind of file whose first bytes are ``head``: ``xml``, ``xml.gz``, ``xml.bz2``,
    ``pbf`` or None.

    >>> sniff(b'<?xml version="1.0"?><osm>'), sniff(b"\\x00\\x00\\x00\\x0e\\n\\tOSMHeader")
    ('xml', 'pbf')
    """
    if head.startswith(b"\x1f\x8b"):
        return "xml.gz"
    if head.startswith(b"BZh"):
        return "xml.bz2"
    if b"OSMHeader" in head[:32]:
        return "pbf"
    text = head.lstrip(b"\xef\xbb\xbf \t\r\n")
    if text.startswith(b"<"):
        return "xml"
    return None


# -- XML -------------------------------------------------------------------------------------
def _read_xml(fh, file: str) -> OsmData:
    data = OsmData()
    tags: dict[str, str] = {}
    refs: list[int] = []
    members: list[tuple[str, int, str]] = []
    root_seen = False
    try:
        for event, elem in ET.iterparse(fh, events=("start", "end")):
            if not root_seen:
                root_seen = True
                if elem.tag != "osm":
                    raise LotsimError(f"{file}: not an OpenStreetMap XML file: its root "
                                      f"element is <{elem.tag}>, expected <osm>")
                continue
            if event == "start":
                if elem.tag in ("node", "way", "relation"):
                    tags, refs, members = {}, [], []
                continue
            tag = elem.tag
            if tag == "tag":
                tags[_attr(elem, "k", file)] = elem.get("v", "")
            elif tag == "nd":
                refs.append(_int(elem, "ref", file))
            elif tag == "member":
                members.append((_attr(elem, "type", file), _int(elem, "ref", file),
                                elem.get("role", "")))
            elif tag in ("node", "way", "relation"):
                if elem.get("action") != "delete" and elem.get("visible") != "false":
                    _add(data, elem, tags, refs, members, file)
                elem.clear()
    except ET.ParseError as exc:
        line, col = exc.position
        raise ScenarioError(Location(file, line, col + 1),
                            f"not well-formed XML: {_xml_reason(exc)}") from None
    if not root_seen:
        raise LotsimError(f"{file}: not an OpenStreetMap XML file: it is empty")
    return data


def _xml_reason(exc: ET.ParseError) -> str:
    """expat's message without its own ``line n, column m`` (the location says it)."""
    return str(exc).split(": line ")[0]


def _add(data: OsmData, elem, tags, refs, members, file: str) -> None:
    oid = _int(elem, "id", file)
    if elem.tag == "node":
        if elem.get("lat") is None and elem.get("lon") is None:
            return  # a node of a history file without a position
        data.nodes[oid] = (_e7(elem, "lat", file), _e7(elem, "lon", file))
        if tags:
            data.node_tags[oid] = tags
    elif elem.tag == "way":
        data.ways[oid] = OsmWay(tuple(refs), tags)
    else:
        data.relations[oid] = OsmRelation(tuple(members), tags)


def _attr(elem, name: str, file: str) -> str:
    value = elem.get(name)
    if value is None:
        raise ScenarioError(None, f"{file}: <{elem.tag}> without its {name!r} attribute")
    return value


def _int(elem, name: str, file: str) -> int:
    value = _attr(elem, name, file)
    try:
        return int(value)
    except ValueError:
        raise ScenarioError(None, f"{file}: <{elem.tag}> {name}={value!r}: expected a whole "
                            "number") from None


def _e7(elem, name: str, file: str) -> int:
    value = _attr(elem, name, file)
    try:
        degrees = float(value)
    except ValueError:
        degrees = float("nan")
    limit = 90 if name == "lat" else 180
    if not abs(degrees) <= limit:
        raise ScenarioError(None, f"{file}: node {elem.get('id')} {name}={value!r}: expected "
                            f"degrees from -{limit} to {limit}")
    return round(degrees * E7)


# -- PBF ------------------------------------------------------------------------------------
def _read_pbf(path: Path) -> OsmData:
    try:
        import osmium
    except ImportError:
        raise LotsimError(f"{path}: reading .osm.pbf files needs pyosmium: "
                          f"{OSM_EXTRA}") from None
    data = OsmData()
    try:
        for obj in osmium.FileProcessor(osmium.io.File(str(path), "pbf")):
            tags = {t.k: t.v for t in obj.tags}
            if obj.is_node():
                loc = obj.location
                if not loc.valid():
                    continue
                data.nodes[obj.id] = (loc.y, loc.x)
                if tags:
                    data.node_tags[obj.id] = tags
            elif obj.is_way():
                data.ways[obj.id] = OsmWay(tuple(n.ref for n in obj.nodes), tags)
            elif obj.is_relation():
                kinds = {"n": "node", "w": "way", "r": "relation"}
                data.relations[obj.id] = OsmRelation(
                    tuple((kinds[m.type], m.ref, m.role) for m in obj.members), tags)
    except (RuntimeError, ValueError, OSError) as exc:
        raise LotsimError(f"{path}: not a readable OSM PBF file: {exc}") from None
    return data
