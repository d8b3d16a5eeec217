"""What lies near an OpenStreetMap lot: the file's ways that matter to lots
(:class:`MapIndex`), a lot's outline (:func:`lot_outline`) and its frame
(:func:`frame_at_centroid`), and, in the lot's local metres, the aisles, roads, mapped
spaces and mapped areas around it (:class:`NearLot`).

Mapped areas inside a lot that cars do not drive on become obstacles (``building=*``,
``barrier=*``) or no-go zones (green ``landuse``, ``natural=*``, green ``leisure``), clipped
to the lot and cut back from its aisles; an area covering more than half the lot is the
land the lot lies in, not a thing in it, and is left out.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from shapely.geometry import LinearRing, LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.ops import unary_union

from lotsim.io.imports.draft import AreaDraft
from lotsim.io.imports.frame import TangentPlane
from lotsim.io.imports.osm_aisles import aisle_ways
from lotsim.io.imports.osm_chains import Chain
from lotsim.io.imports.osm_gates import is_road
from lotsim.io.imports.osm_read import E7, OsmData

NEAR = 150.0
"""Ways this close to a lot [m] are read for it: aisles and roads its gates may use."""
GREEN_LANDUSE = frozenset({"grass", "meadow", "flowerbed", "forest", "village_green",
                           "orchard", "allotments", "plant_nursery", "vineyard", "farmland"})
"""``landuse`` values that are not driven on: no-go zones inside a lot."""
GREEN_LEISURE = frozenset({"park", "garden", "playground", "pitch"})
"""``leisure`` values that are not driven on."""


@dataclass
class MapIndex:
    """The file's ways that matter to lots, each with its extent (:func:`box_of`)."""

    data: OsmData
    aisles: list = field(default_factory=list)  # (way id, way, box)
    roads: dict = field(default_factory=dict)  # way id -> (way, box)
    road_nodes: dict = field(default_factory=dict)  # node id -> road way ids
    features: list = field(default_factory=list)  # (kind, label, "way 5", rings, box)
    spaces: list = field(default_factory=list)  # (way id, refs, box)

    @classmethod
    def of(cls, data: OsmData) -> MapIndex:
        ix = cls(data)
        ix.aisles = [(wid, w, box_of(data, w.refs)) for wid, w in aisle_ways(data)]
        for wid, way in sorted(data.ways.items()):
            tags = way.tags
            if is_road(tags):
                ix.roads[wid] = (way, box_of(data, way.refs))
                for n in way.refs:
                    ix.road_nodes.setdefault(n, []).append(wid)
            elif tags.get("amenity") == "parking_space" and is_closed(way.refs):
                ix.spaces.append((wid, way.refs, box_of(data, way.refs)))
            elif (what := feature_kind(tags)) and is_closed(way.refs) \
                    and tags.get("amenity") != "parking":
                ix.features.append((*what, f"way {wid}", [way.refs], box_of(data, way.refs)))
        for rid, rel in sorted(data.relations.items()):
            what = feature_kind(rel.tags)
            if what and rel.tags.get("type") == "multipolygon" \
                    and rel.tags.get("amenity") != "parking":
                rings = rings_of(data, rel.members, ("outer", ""))
                if not isinstance(rings, str):
                    ix.features.append((*what, f"relation {rid}", rings,
                                        box_of(data, [n for r in rings for n in r])))
        return ix


def box_of(data: OsmData, refs: Sequence[int]) -> tuple[int, int, int, int] | None:
    """The extent of the nodes ``refs`` (those in the file), in 10⁻⁷ degree."""
    pts = [data.nodes[n] for n in refs if n in data.nodes]
    if not pts:
        return None
    lat, lon = zip(*pts, strict=True)
    return min(lat), min(lon), max(lat), max(lon)


def is_closed(refs: Sequence[int]) -> bool:
    """A way that ends where it begins, with at least three corners."""
    return len(refs) >= 4 and refs[0] == refs[-1]


def feature_kind(tags: dict[str, str]) -> tuple[str, str] | None:
    """What a mapped area inside a lot is to lotsim: ``obstacles`` or ``no_go``."""
    if tags.get("building", "no") != "no":
        return "obstacles", f"building={tags['building']}"
    if "barrier" in tags:
        return "obstacles", f"barrier={tags['barrier']}"
    if tags.get("landuse") in GREEN_LANDUSE:
        return "no_go", f"landuse={tags['landuse']}"
    if "natural" in tags:
        return "no_go", f"natural={tags['natural']}"
    if tags.get("leisure") in GREEN_LEISURE:
        return "no_go", f"leisure={tags['leisure']}"
    return None


def rings_of(data: OsmData, members: Sequence[tuple[str, int, str]],
             roles: tuple[str, ...]) -> list[list[int]] | str:
    """The closed rings the member ways of ``roles`` make, or why they make none."""
    ways = []
    for kind, ref, role in members:
        if kind != "way" or role not in roles:
            continue
        if ref not in data.ways:
            return f"clipped by the extract: member way {ref} is not in the file"
        ways.append(list(data.ways[ref].refs))
    rings = []
    while ways:
        ring = ways.pop(0)
        while ring[0] != ring[-1]:
            for i, w in enumerate(ways):
                if w[0] == ring[-1]:
                    ring += w[1:]
                elif w[-1] == ring[-1]:
                    ring += w[-2::-1]
                else:
                    continue
                ways.pop(i)
                break
            else:
                return "its member ways do not close into rings"
        rings.append(ring)
    return rings


def lot_outline(kind: str, oid: int, data: OsmData) -> tuple[list[int], list[list[int]]] | str:
    """The lot's outer ring and inner rings (node ids), or why it has none."""
    if kind == "node":
        return "a point, not an area: lotsim needs the lot's outline"
    if kind == "way":
        refs = list(data.ways[oid].refs)
        if not is_closed(refs):
            return "an open way, not an area"
        rings: list[list[int]] = [refs]
        outers, inners = rings, []
    else:
        rel = data.relations[oid]
        if rel.tags.get("type") != "multipolygon":
            return f"a relation of type {rel.tags.get('type', '(none)')}, not a multipolygon"
        outers = rings_of(data, rel.members, ("outer", ""))
        if isinstance(outers, str):
            return outers
        inners = rings_of(data, rel.members, ("inner",))
        if isinstance(inners, str):
            return inners
        if len(outers) != 1:
            return (f"{len(outers)} outer rings: lotsim takes one lot per outline "
                    "(map each as its own lot)")
        rings = outers + inners
    missing = sorted({n for r in rings for n in r if n not in data.nodes})
    if missing:
        total = len({n for r in rings for n in r})
        return (f"clipped by the extract: {len(missing)} of its {total} nodes "
                f"{'is' if len(missing) == 1 else 'are'} not in the file "
                f"(node {missing[0]}{', ...' if len(missing) > 1 else ''})")
    return outers[0], inners


def frame_at_centroid(data: OsmData, ring: list[int]) -> TangentPlane:
    """The tangent plane at the centroid of the ring, to 10⁻⁷ degree."""
    lat = np.array([data.nodes[n][0] for n in ring], dtype=float) / E7
    lon = np.array([data.nodes[n][1] for n in ring], dtype=float) / E7
    k = math.cos(math.radians(float(lat.mean())))
    c = Polygon(np.column_stack([lon * k, lat])).centroid
    return TangentPlane(round(c.y, 7), round(c.x / k, 7))


class NearLot:
    """What lies near one lot, in its local metres."""

    def __init__(self, data: OsmData, index: MapIndex, frame: TangentPlane, ring: list[int],
                 inners: list[list[int]]):
        self.data, self.index, self.frame = data, index, frame
        lat = [data.nodes[n][0] for n in ring]
        lon = [data.nodes[n][1] for n in ring]
        dlat = NEAR / 111_000 * E7
        dlon = dlat / max(0.05, math.cos(math.radians(sum(lat) / len(lat) / E7)))
        self.box = (min(lat) - dlat, min(lon) - dlon, max(lat) + dlat, max(lon) + dlon)
        self.aisles = [(wid, w) for wid, w, box in index.aisles if self._near(box)]
        self.roads = {wid: w for wid, (w, box) in index.roads.items() if self._near(box)}
        nodes = set(ring).union(*inners)
        for _, w in self.aisles:
            nodes.update(w.refs)
        for w in self.roads.values():
            nodes.update(w.refs)
        self._features = [f[:4] for f in index.features if self._near(f[4])]
        self._spaces = [(wid, refs) for wid, refs, box in index.spaces if self._near(box)]
        for f in self._features:
            nodes.update(n for r in f[3] for n in r)
        for _, refs in self._spaces:
            nodes.update(refs)
        known = sorted(n for n in nodes if n in data.nodes)
        lat_lon = np.array([data.nodes[n] for n in known], dtype=float).reshape(-1, 2) / E7
        x, y = frame.to_local(lat_lon[:, 0], lat_lon[:, 1])
        self.xy = {n: (float(a), float(b)) for n, a, b in zip(known, x, y, strict=True)}

    def _near(self, b) -> bool:
        return b is not None and not (b[2] < self.box[0] or b[0] > self.box[2]
                                      or b[3] < self.box[1] or b[1] > self.box[3])

    def xy_of(self, refs) -> list[tuple[float, float]]:
        return [self.xy[n] for n in refs]

    def driveways(self, lot: Polygon) -> list:
        """The service roads that meet an aisle inside the lot: the lot's driveways, driven
        as aisles up to where they leave it."""
        inside = {n for _, w in self.aisles for n in w.refs
                  if n in self.xy and lot.covers(Point(self.xy[n]))}
        return [(wid, w) for wid, w in sorted(self.roads.items())
                if w.tags.get("highway") == "service" and inside.intersection(w.refs)]

    def road_lines(self) -> dict[int, LineString]:
        out = {}
        for wid, w in self.roads.items():
            pts = [self.xy[n] for n in w.refs if n in self.xy]
            if len(pts) >= 2:
                out[wid] = LineString(pts)
        return out

    def road_name(self, wid: int) -> str:
        tags = self.roads[wid].tags if wid in self.roads else self.data.ways[wid].tags
        name = f" {tags['name']!r}" if "name" in tags else ""
        return f"highway={tags.get('highway')} way {wid}{name}"

    def spaces(self, lot: Polygon) -> list[tuple[int, Polygon, str]]:
        """The mapped spaces whose centre lies in the lot: way id, outline [m] and its
        ``parking:orientation`` tag ("" without one)."""
        out = []
        for wid, refs in self._spaces:
            if all(n in self.xy for n in refs):
                poly = Polygon(self.xy_of(refs))
                if poly.is_valid and lot.buffer(1.0).contains(poly.centroid):
                    tags = self.data.ways[wid].tags
                    out.append((wid, poly, tags.get("parking:orientation", "")))
        return out

    def areas(self, lot: Polygon, chains: list[Chain], own: int | None
              ) -> tuple[list[AreaDraft], list[AreaDraft]]:
        """Mapped areas inside the lot that are not driven on: obstacles and no-go zones,
        clipped to the lot, less the aisles."""
        aisles = unary_union([c.polygon for c in chains]).buffer(0.1)
        out: dict[str, list[AreaDraft]] = {"obstacles": [], "no_go": []}
        for kind, label, name, rings in self._features:
            if name == f"way {own}":
                continue
            for ring in rings:
                if not all(n in self.xy for n in ring):
                    continue
                poly = Polygon(self.xy_of(ring))
                if not poly.is_valid:
                    poly = poly.buffer(0)
                inside = poly.intersection(lot)
                if inside.area < 0.5 or inside.area > 0.5 * lot.area:
                    continue  # next to the lot, or the land the lot lies in
                pieces = [ring_points(p.exterior)
                          for p in polygons_of(inside.difference(aisles)) if p.area >= 0.5]
                pieces = [p for p in pieces if len(p) >= 3 and Polygon(p).is_valid]
                for j, p in enumerate(pieces):
                    ident = name.replace(" ", "") + (f"-{j + 1}" if len(pieces) > 1 else "")
                    out[kind].append(AreaDraft(ident, p, note=f"{label} ({name})"))
        return out["obstacles"], out["no_go"]


def polygons_of(geom: BaseGeometry) -> list[Polygon]:
    """The non-empty polygons of a geometry."""
    if isinstance(geom, Polygon):
        return [geom] if not geom.is_empty else []
    return [g for g in getattr(geom, "geoms", []) if isinstance(g, Polygon) and not g.is_empty]


def ring_points(ring: LinearRing) -> list[tuple[float, float]]:
    """A ring's points, rounded to the centimetre, without the closing repeat."""
    pts = [(round(x, 2), round(y, 2)) for x, y in list(ring.coords)[:-1]]
    return [p for i, p in enumerate(pts) if p != pts[i - 1]]
