"""The parking-aisle network of an OpenStreetMap lot, in its local metres.

Aisles are the ``highway=service`` + ``service=parking_aisle`` ways that lie in the lot or
meet it (and the lot's driveways, :meth:`.osm_near.NearLot.driveways`), cut where they leave
the lot grown by :data:`CLIP_GROW` (:func:`clip_network`), with the road each cut end leads
to outside; legs shorter than :data:`MIN_LEG` are merged into their neighbours
(:func:`merge_short_legs`). Widths come from the ``width`` tag, else the defaults
:data:`TWO_WAY_WIDTH` and :data:`ONE_WAY_WIDTH`; ``oneway`` is honoured. :mod:`.osm_chains`
joins the legs into lotsim aisles.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from shapely.geometry import LineString, Point, Polygon
from shapely.prepared import prep

from lotsim.io.imports.osm_read import OsmData, OsmWay

TWO_WAY_WIDTH = 7.0
"""Width of a two-way aisle without a ``width`` tag [m]: the aisle of the two-way,
double-loaded 90° module of 5.0 + 7.0 + 5.0 m (US codes ask 22–24 ft, 6.7–7.3 m)."""
ONE_WAY_WIDTH = 6.0
"""Width of a one-way aisle without a ``width`` tag [m]: bays are inferred at 90°, and a
car backing into one needs nearly the room of a two-way aisle (US codes ask 18–24 ft,
5.5–7.3 m, for one-way aisles serving 90° stalls)."""
CLIP_GROW = 3.0
"""Aisles are kept where they lie within this distance of the lot [m]."""
MIN_LEG = 1.0
"""Shorter legs are merged into their neighbours [m]."""
ROAD_SEARCH = 100.0
"""How far an aisle way is followed outside the lot to a road [m]."""

_WIDTH = re.compile(r"\s*(\d+(?:[.,]\d+)?)\s*(m|metres|meters)?\s*")
_FEET = re.compile(r"\s*(\d+)\s*'\s*(?:(\d+)\s*\")?\s*")


def is_aisle(tags: dict[str, str]) -> bool:
    """A ``service=parking_aisle`` way."""
    return tags.get("highway") == "service" and tags.get("service") == "parking_aisle"


def width_tag(value: str | None) -> float | None:
    """A ``width`` tag in metres (``6``, ``6.5 m``, ``6,5``, ``20'6"``); None when absent or
    unreadable.

    >>> width_tag("6.5"), width_tag("7 m"), width_tag("20'"), width_tag("wide")
    (6.5, 7.0, 6.096, None)
    """
    if value is None:
        return None
    if m := _WIDTH.fullmatch(value):
        w = float(m.group(1).replace(",", "."))
    elif m := _FEET.fullmatch(value):
        w = round(int(m.group(1)) * 0.3048 + int(m.group(2) or 0) * 0.0254, 3)
    else:
        return None
    return w if 0 < w < 100 else None


def oneway_of(tags: dict[str, str]) -> int:
    """1: one-way along the way; -1: one-way against it; 0: two-way.

    >>> oneway_of({"oneway": "yes"}), oneway_of({"oneway": "-1"}), oneway_of({})
    (1, -1, 0)
    """
    value = tags.get("oneway", "")
    if value in ("yes", "true", "1"):
        return 1
    if value in ("-1", "reverse"):
        return -1
    return 0


@dataclass(frozen=True)
class AisleRules:
    """The widths an import gives aisles: the defaults, and the least lotsim's lanes need
    for the scenario's widest vehicle [m]."""

    two_way: float = TWO_WAY_WIDTH
    one_way: float = ONE_WAY_WIDTH
    least_two_way: float = 0.0
    least_one_way: float = 0.0


@dataclass
class Vertex:
    """A point of the aisle network in local metres: an OSM node, where a way leaves the
    clip region (``cut``), or where a loop is cut into aisles that run on into each other
    (``seam``). ``roads``: road ways reached from it; ``ways``: the aisle ways through it."""

    key: int
    xy: tuple[float, float]
    node: int | None
    cut: bool = False
    roads: set[int] = field(default_factory=set)
    seam: bool = False
    ways: set[int] = field(default_factory=set)


@dataclass
class Edge:
    """A leg of an aisle way between two vertices; ``one_way`` runs from ``a`` to ``b``."""

    a: int
    b: int
    way: int
    width: float
    tagged: bool
    one_way: bool


# -- the network ------------------------------------------------------------------------------
def aisle_ways(data: OsmData) -> list[tuple[int, OsmWay]]:
    """Every parking-aisle way of the file, by id."""
    return sorted((wid, w) for wid, w in data.ways.items() if is_aisle(w.tags))


def clip_network(ways: list[tuple[int, OsmWay]], xy: dict[int, tuple[float, float]],
                 region: Polygon, rules: AisleRules, road_nodes: dict[int, list[int]],
                 notes: list[str]) -> tuple[dict[int, Vertex], list[Edge]]:
    """The aisle ways' legs within ``region``, cut where they leave it.

    ``xy`` holds the local position of every node known near the lot (a way's nodes missing
    from the file are left out: it is cut there); ``road_nodes`` the road ways through each
    node.
    """
    vertices: dict[int, Vertex] = {}
    edges: list[Edge] = []
    graph = _way_graph(ways, xy)
    next_cut = -1
    prepared = prep(region)
    for wid, way in ways:
        width, tagged, one_way = _way_width(wid, way, rules, notes)
        direction = oneway_of(way.tags)
        refs = way.refs if direction >= 0 else way.refs[::-1]
        for i in range(len(refs) - 1):
            u, v = refs[i], refs[i + 1]
            if u not in xy or v not in xy or u == v:
                continue
            seg = LineString([xy[u], xy[v]])
            if not prepared.intersects(seg):
                continue
            pieces = seg.intersection(region)
            for piece in getattr(pieces, "geoms", [pieces]):
                if not isinstance(piece, LineString) or piece.length < 1e-6:
                    continue
                keys = []
                for end in (piece.coords[0], piece.coords[-1]):
                    node = u if math.dist(end, xy[u]) < 1e-6 else \
                        v if math.dist(end, xy[v]) < 1e-6 else None
                    if node is not None:
                        if node not in vertices:
                            vertices[node] = Vertex(node, xy[node], node,
                                                    roads=set(road_nodes.get(node, ())))
                        keys.append(node)
                    else:
                        beyond = _beyond(end, u, v, xy, region)
                        vertices[next_cut] = Vertex(
                            next_cut, (float(end[0]), float(end[1])), None, cut=True,
                            roads=_roads_beyond(beyond, graph, xy, region, road_nodes))
                        keys.append(next_cut)
                        next_cut -= 1
                for k in keys:
                    vertices[k].ways.add(wid)
                edges.append(Edge(keys[0], keys[1], wid, width, tagged, one_way))
    return vertices, edges


def _beyond(cut, u: int, v: int, xy, region: Polygon) -> int:
    """Of a leg's two nodes, the one outside ``region`` on the side of ``cut``."""
    out = [n for n in (u, v) if not region.covers(Point(xy[n]))]
    return min(out or [u, v], key=lambda n: math.dist(cut, xy[n]))


def _way_width(wid: int, way: OsmWay, rules: AisleRules,
               notes: list[str]) -> tuple[float, bool, bool]:
    one_way = oneway_of(way.tags) != 0
    least = rules.least_one_way if one_way else rules.least_two_way
    tag = width_tag(way.tags.get("width"))
    if tag is None:
        if "width" in way.tags:
            notes.append(f"way {wid}: width={way.tags['width']!r} not read as metres; "
                         "the default used")
        return (rules.one_way if one_way else rules.two_way), False, one_way
    if tag < least:
        notes.append(f"way {wid}: width {tag:g} m is narrower than lotsim's lanes need "
                     f"({least:.2f} m): widened")
        return least, True, one_way
    return tag, True, one_way


def _way_graph(ways: list[tuple[int, OsmWay]], xy) -> dict[int, list[int]]:
    """Node -> neighbouring nodes along the aisle ways (both ways)."""
    graph: dict[int, list[int]] = {}
    for _, way in ways:
        for u, v in zip(way.refs, way.refs[1:], strict=False):
            if u in xy and v in xy and u != v:
                graph.setdefault(u, []).append(v)
                graph.setdefault(v, []).append(u)
    return graph


def _roads_beyond(start: int, graph, xy, region: Polygon, road_nodes) -> set[int]:
    """The roads reached from node ``start`` along aisle ways outside ``region``, within
    :data:`ROAD_SEARCH` metres."""
    best: dict[int, float] = {start: 0.0}
    todo = [(0.0, start)]
    found: set[int] = set()
    while todo:
        todo.sort(reverse=True)
        dist, node = todo.pop()
        if dist > best.get(node, math.inf):
            continue
        if node in road_nodes:
            found.update(road_nodes[node])
            continue
        for nxt in graph.get(node, ()):
            d = dist + math.dist(xy[node], xy[nxt])
            if d <= ROAD_SEARCH and d < best.get(nxt, math.inf) and \
                    not region.contains(Point(xy[nxt])):
                best[nxt] = d
                todo.append((d, nxt))
    return found


def merge_short_legs(vertices: dict[int, Vertex], edges: list[Edge]) -> list[Edge]:
    """Merge the two ends of every leg shorter than :data:`MIN_LEG` into one vertex (the
    junction, the road end or the cut, where one of them is)."""
    degree: dict[int, int] = {}
    for e in edges:
        degree[e.a] = degree.get(e.a, 0) + 1
        degree[e.b] = degree.get(e.b, 0) + 1
    parent = {k: k for k in vertices}

    def find(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    def rank(k: int) -> tuple:
        v = vertices[k]
        return (degree.get(k, 0) >= 3, bool(v.roads), v.cut, degree.get(k, 0) == 1, -k)

    for e in edges:
        if math.dist(vertices[e.a].xy, vertices[e.b].xy) < MIN_LEG:
            ra, rb = find(e.a), find(e.b)
            if ra != rb:
                keep, drop = (ra, rb) if rank(ra) >= rank(rb) else (rb, ra)
                parent[drop] = keep
                vertices[keep].roads |= vertices[drop].roads
                vertices[keep].ways |= vertices[drop].ways
                vertices[keep].cut |= vertices[drop].cut
    out: list[Edge] = []
    seen: set[tuple[int, int]] = set()
    for e in edges:
        a, b = find(e.a), find(e.b)
        if a == b or (min(a, b), max(a, b)) in seen:
            continue
        seen.add((min(a, b), max(a, b)))
        out.append(Edge(a, b, e.way, e.width, e.tagged, e.one_way))
    for k in list(vertices):
        if find(k) != k:
            del vertices[k]
    return out
