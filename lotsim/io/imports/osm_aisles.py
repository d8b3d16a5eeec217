"""The parking aisles of an OpenStreetMap lot.

Aisles are the ``highway=service`` + ``service=parking_aisle`` ways that lie in the lot or
meet it (and the lot's driveways, :meth:`.osm_near.NearLot.driveways`), cut where they leave
the lot grown by :data:`CLIP_GROW`. Their pieces become lotsim aisles (:class:`Chain`): legs
shorter than :data:`MIN_LEG` are merged into their neighbours, pieces that share a node and
run on (same width and direction, turning less than :data:`MAX_CORNER`) are joined into one
polyline, and at a node where several meet the straightest pair runs through (turning less
than :data:`THROUGH_TURN`) and the others end on its centre line (lotsim's junction rule,
``docs/scenario.md``, "How aisles join"). An aisle end that stops short of, or overshoots,
another aisle's centre line by less than half that aisle's width plus 1 m is moved onto it.
Centre lines are simplified within :data:`SIMPLIFY_TOLERANCE`. Where lotsim finds an aisle's
bends too tight for its legs, the importer cuts it at its sharpest corner into two aisles
meeting in an L (:func:`split_chains`). The lot's gates are :mod:`.osm_gates`'.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np
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
SIMPLIFY_TOLERANCE = 0.3
"""Centre lines are simplified within this distance [m] (Douglas-Peucker)."""
MAX_CORNER = math.radians(95)
"""Two pieces that meet at a node and turn more than this are separate aisles."""
THROUGH_TURN = math.radians(45)
"""Where several pieces meet, two that turn less than this run through as one aisle."""
JOIN_REACH = 1.0
"""An aisle end within half another's width plus this [m] of its centre line joins it."""
ROAD_SEARCH = 100.0
"""How far an aisle way is followed outside the lot to a road [m]."""
MIN_AISLE = 3.0
"""A piece of aisle shorter than this that joins no other is dropped [m]."""

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


@dataclass
class Chain:
    """One lotsim aisle: its centre line, the OSM ways it comes from, its width;
    ``attached``: its ends (0, -1) moved onto another aisle's centre line."""

    id: str
    keys: list[int]
    pts: list[tuple[float, float]]
    ways: list[int]
    width: float
    one_way: bool
    note: str = ""
    attached: set[int] = field(default_factory=set)

    def free(self, end: int, counts: dict[int, int]) -> bool:
        """Whether the end (0 or -1) joins no other aisle (``counts``: :func:`end_counts`)."""
        return counts[self.keys[end]] == 1 and end not in self.attached

    @property
    def line(self) -> LineString:
        return LineString(self.pts)

    @property
    def polygon(self) -> Polygon:
        """What lotsim builds as the aisle's surface."""
        return self.line.buffer(self.width / 2, cap_style="flat", join_style="round")


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


# -- chains -----------------------------------------------------------------------------------
def _direction(vertices, at: int, e: Edge) -> np.ndarray:
    other = e.b if e.a == at else e.a
    d = np.subtract(vertices[other].xy, vertices[at].xy)
    return d / np.hypot(*d)


def _turn(vertices, at: int, e1: Edge, e2: Edge) -> float:
    """How much a car turns going from ``e1`` through ``at`` onto ``e2`` [rad]."""
    into = -_direction(vertices, at, e1)
    out = _direction(vertices, at, e2)
    return math.acos(max(-1.0, min(1.0, float(np.dot(into, out)))))


def _runs_on(at: int, e1: Edge, e2: Edge) -> bool:
    if e1.width != e2.width or e1.one_way != e2.one_way:
        return False
    if not e1.one_way:
        return True
    return (e1.b == at and e2.a == at) or (e1.a == at and e2.b == at)


def build_chains(vertices: dict[int, Vertex], edges: list[Edge]) -> list[Chain]:
    """Join the legs into aisles (:class:`Chain`), each a simple polyline."""
    incident: dict[int, list[int]] = {}
    for i, e in enumerate(edges):
        incident.setdefault(e.a, []).append(i)
        incident.setdefault(e.b, []).append(i)
    partner: dict[tuple[int, int], int] = {}
    for at in sorted(incident):
        inc = incident[at]
        limit = MAX_CORNER if len(inc) == 2 else THROUGH_TURN
        pairs = sorted((_turn(vertices, at, edges[i], edges[j]), i, j)
                       for k, i in enumerate(inc) for j in inc[k + 1:]
                       if _runs_on(at, edges[i], edges[j]))
        used: set[int] = set()
        for turn, i, j in pairs:
            if turn <= limit and i not in used and j not in used:
                used |= {i, j}
                partner[(at, i)], partner[(at, j)] = j, i
    done: set[int] = set()
    sequences: list[tuple[list[int], list[int]]] = []
    for start in range(len(edges)):
        if start in done:
            continue
        done.add(start)
        keys, legs = [edges[start].a, edges[start].b], [start]
        closed = False
        for forward in (True, False):
            at, cur = (keys[-1] if forward else keys[0]), start
            while (at, cur) in partner:
                nxt = partner[(at, cur)]
                if nxt == start:
                    closed = True
                    break
                done.add(nxt)
                e = edges[nxt]
                at, cur = (e.b if e.a == at else e.a), nxt
                if forward:
                    keys.append(at)
                    legs.append(nxt)
                else:
                    keys.insert(0, at)
                    legs.insert(0, nxt)
            if closed:
                break
        for piece in _cut_loops(keys, legs, vertices):
            sequences += _simple(*piece, vertices)
    chains = []
    for keys, legs in sequences:
        e0 = edges[legs[0]]
        run = np.subtract(vertices[keys[1]].xy, vertices[keys[0]].xy)
        way = np.subtract(vertices[e0.b].xy, vertices[e0.a].xy)
        if e0.one_way and float(np.dot(run, way)) < 0:
            keys, legs = keys[::-1], legs[::-1]
        ways = sorted({edges[i].way for i in legs})
        chains.append(Chain("", keys, [vertices[k].xy for k in keys], ways, e0.width,
                            e0.one_way, "width from the tag" if e0.tagged else ""))
    return chains


def _cut_loops(keys: list[int], legs: list[int], vertices: dict[int, Vertex]
               ) -> list[tuple[list[int], list[int]]]:
    """A sequence that comes back to a vertex (a loop) is cut in the middle of the loop's
    longest leg (a closed loop also in the middle of the leg across from it), so that the
    pieces run on into each other (lotsim's lanes continue where one aisle ends and the next
    begins heading the same way)."""
    for i in range(len(keys)):
        for j in range(i + 1, len(keys)):
            if keys[j] != keys[i]:
                continue
            length = [math.dist(vertices[keys[p]].xy, vertices[keys[p + 1]].xy)
                      for p in range(len(legs))]
            first = max(range(i, j), key=lambda p: (length[p], -p))
            closed = i == 0 and j == len(keys) - 1
            at = {first, (first + j // 2) % j} if closed else {first}
            pieces = _cut_at(keys, legs, at, vertices)
            if closed:  # the last piece runs on into the first through keys[0]
                last = pieces.pop()
                pieces[0] = (last[0] + pieces[0][0][1:], last[1] + pieces[0][1])
            return [q for piece in pieces for q in _cut_loops(*piece, vertices)]
    return [(keys, legs)] if len(keys) >= 2 else []


def _cut_at(keys: list[int], legs: list[int], at: set[int], vertices: dict[int, Vertex]
            ) -> list[tuple[list[int], list[int]]]:
    """The sequence cut in the middle of the legs at positions ``at`` (a seam vertex each)."""
    pieces = []
    cur_keys, cur_legs = [keys[0]], []
    for p, leg in enumerate(legs):
        if p in at:
            mid = min(min(vertices), 0) - 1
            a, b = vertices[keys[p]].xy, vertices[keys[p + 1]].xy
            vertices[mid] = Vertex(mid, ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2), None,
                                   seam=True)
            pieces.append((cur_keys + [mid], cur_legs + [leg]))
            cur_keys, cur_legs = [mid], []
        cur_keys.append(keys[p + 1])
        cur_legs.append(leg)
    pieces.append((cur_keys, cur_legs))
    return pieces


def _simple(keys: list[int], legs: list[int], vertices: dict[int, Vertex]
            ) -> list[tuple[list[int], list[int]]]:
    """A sequence whose polyline crosses itself is cut in the middle until it does not."""
    if len(keys) <= 2 or LineString([vertices[k].xy for k in keys]).is_simple:
        return [(keys, legs)]
    return [q for piece in _cut_at(keys, legs, {len(legs) // 2}, vertices)
            for q in _simple(*piece, vertices)]


def tidy_chains(chains: list[Chain], vertices: dict[int, Vertex]) -> list[Chain]:
    """Simplify the centre lines (keeping the points other aisles meet), drop short
    legs, number the aisles ``a1, a2, ...`` in the order of their OSM ways, and drop
    stray short pieces."""
    count: dict[int, int] = {}
    for c in chains:
        for k in set(c.keys):
            count[k] = count.get(k, 0) + 1
    out = []
    for c in chains:
        pinned = {0, len(c.keys) - 1} | {i for i, k in enumerate(c.keys)
                                         if count[k] > 1 or vertices[k].roads}
        keep = _simplified(c.pts, sorted(pinned))
        keep = _without_short_legs(c.pts, keep, pinned)
        c.keys = [c.keys[i] for i in keep]
        c.pts = [c.pts[i] for i in keep]
        joined = any(count[k] > 1 for k in c.keys)
        if len(c.pts) < 2 or (c.line.length < MIN_AISLE and not joined):
            continue
        out.append(c)
    out.sort(key=lambda c: (c.ways, c.keys))
    for i, c in enumerate(out):
        c.id = f"a{i + 1}"
    return out


def _simplified(pts, pinned: list[int]) -> list[int]:
    keep = [pinned[0]]
    for i, j in zip(pinned, pinned[1:], strict=False):
        if j - i > 1:
            part = LineString(pts[i:j + 1]).simplify(SIMPLIFY_TOLERANCE, preserve_topology=False)
            coords = [tuple(p) for p in part.coords]
            keep += [k for k in range(i + 1, j) if tuple(pts[k]) in coords]
        keep.append(j)
    return keep


def _without_short_legs(pts, keep: list[int], pinned: set[int]) -> list[int]:
    changed = True
    while changed and len(keep) > 2:
        changed = False
        for n in range(len(keep) - 1):
            i, j = keep[n], keep[n + 1]
            if math.dist(pts[i], pts[j]) < MIN_LEG:
                drop = j if j not in pinned else i if i not in pinned else None
                if drop is not None:
                    keep.remove(drop)
                    changed = True
                    break
    return keep


def join_ends(chains: list[Chain], vertices: dict[int, Vertex]) -> list[str]:
    """Move each aisle end that stops near another aisle's centre line (not already on it)
    onto it, at its vertex when one is within 0.5 m. Returns what was moved."""
    moved = []
    shared = {}
    for c in chains:
        for k in c.keys:
            shared[k] = shared.get(k, 0) + 1
    for c in chains:
        for end in (0, -1):
            k = c.keys[end]
            if shared[k] > 1 or vertices[k].cut or len(c.pts) < 2:
                continue
            e = Point(c.pts[end])
            prev = np.asarray(c.pts[1 if end == 0 else -2])
            best = None
            for d in chains:
                if d is c:
                    continue
                gap = d.line.distance(e)
                if gap <= d.width / 2 + JOIN_REACH and (best is None or gap < best[0]):
                    best = (gap, d)
            if best is None or best[0] < 1e-9:
                continue
            gap, d = best
            q = d.line.interpolate(d.line.project(e))
            target, key = (float(q.x), float(q.y)), k
            for i, p in enumerate(d.pts):
                if math.dist(p, target) < 0.5:
                    target, key = p, d.keys[i]
                    break
            leg = np.subtract(target, prev)
            if np.hypot(*leg) < MIN_LEG or _crossing_angle(leg, d, target) < math.radians(20):
                continue
            c.pts[end] = target
            c.keys[end] = key
            c.attached.add(end)
            shared[key] = shared.get(key, 0) + 1
            moved.append(f"{c.id} end moved {gap:.2f} m onto {d.id}'s centre line")
    return moved


def _crossing_angle(leg: np.ndarray, d: Chain, at: tuple[float, float]) -> float:
    s = d.line.project(Point(at))
    a = d.line.interpolate(max(0.0, s - 0.5))
    b = d.line.interpolate(min(d.line.length, s + 0.5))
    v = np.array([b.x - a.x, b.y - a.y])
    cos = abs(float(np.dot(leg, v))) / (np.hypot(*leg) * np.hypot(*v) + 1e-12)
    return math.acos(min(1.0, cos))


def junctions(chains: list[Chain], vertices: dict[int, Vertex]
              ) -> dict[str, list[tuple[float, float]]]:
    """Per aisle, the stations [m] where another aisle meets or crosses it, with that
    aisle's half width [m]; not where one runs on into the next (a seam)."""
    seams = [Point(v.xy) for v in vertices.values() if v.seam]
    out: dict[str, list[tuple[float, float]]] = {c.id: [] for c in chains}
    for c in chains:
        for d in chains:
            if d is c:
                continue
            hit = c.line.intersection(d.line.buffer(0.05))
            for part in getattr(hit, "geoms", [hit]):
                if part.is_empty or any(part.distance(m) < 0.1 for m in seams):
                    continue
                s = c.line.project(part.centroid)
                out[c.id].append((s, d.width / 2))
    return {k: sorted(v) for k, v in out.items()}


def end_counts(chains: list[Chain]) -> dict[int, int]:
    """How many aisles pass through or end at each vertex."""
    count: dict[int, int] = {}
    for c in chains:
        for k in c.keys:
            count[k] = count.get(k, 0) + 1
    return count


def sharpest_corner(c: Chain) -> int:
    """The key of the aisle's vertex where it turns most."""
    pts = np.asarray(c.pts, dtype=float)
    d = np.diff(pts, axis=0)
    heading = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs(np.angle(np.exp(1j * np.diff(heading))))
    return c.keys[int(np.argmax(turn)) + 1]


def split_chains(chains: list[Chain], at: set[int], vertices: dict[int, Vertex]
                 ) -> list[Chain]:
    """Cut aisles in two at the vertices ``at`` (an L where they met as a bend; a piece
    shorter than :data:`MIN_AISLE` at an aisle's end is dropped, its end's roads going to
    the new end), and number the aisles again."""
    out = []
    for c in chains:
        cuts = [i for i, k in enumerate(c.keys[1:-1], start=1) if k in at]
        bounds = [0, *cuts, len(c.keys) - 1]
        pieces = [Chain("", c.keys[i:j + 1], c.pts[i:j + 1], c.ways, c.width, c.one_way,
                        c.note) for i, j in zip(bounds, bounds[1:], strict=False)]
        pieces[0].attached |= c.attached & {0}
        pieces[-1].attached |= c.attached & {-1}
        while len(pieces) > 1 and pieces[0].line.length < MIN_AISLE:
            gone = pieces.pop(0)
            _inherit(vertices[pieces[0].keys[0]], vertices[gone.keys[0]])
        while len(pieces) > 1 and pieces[-1].line.length < MIN_AISLE:
            gone = pieces.pop()
            _inherit(vertices[pieces[-1].keys[-1]], vertices[gone.keys[-1]])
        out += pieces
    for i, c in enumerate(out):
        c.id = f"a{i + 1}"
    return out


def _inherit(end: Vertex, gone: Vertex) -> None:
    end.roads |= gone.roads
    end.ways |= gone.ways
    end.cut |= gone.cut and bool(gone.roads)
