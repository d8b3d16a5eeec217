"""OpenStreetMap aisle legs joined into lotsim aisles (:class:`Chain`).

Pieces that share a node and run on (same width and direction, turning less than
:data:`MAX_CORNER`) are joined into one polyline, and at a node where several meet the
straightest pair runs through (turning less than :data:`THROUGH_TURN`) and the others end on
its centre line (lotsim's junction rule, ``docs/scenario.md``, "How aisles join"). A loop
is cut in the middle of its longest legs, so that its pieces run on into each other (a
lotsim lane continues into the next aisle's where that begins heading the same way); a
polyline that crosses itself is cut too. Centre lines are simplified within
:data:`SIMPLIFY_TOLERANCE`. An aisle end that stops short of, or overshoots, another
aisle's centre line by less than half that aisle's width plus :data:`JOIN_REACH` is moved
onto it. Where lotsim finds an aisle's bends too tight for its legs, the importer cuts it at
its sharpest corner into two aisles meeting in an L (:func:`split_chains`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from shapely.geometry import LineString, Point, Polygon

from lotsim.io.imports.osm_aisles import MIN_LEG, Edge, Vertex

SIMPLIFY_TOLERANCE = 0.3
"""Centre lines are simplified within this distance [m] (Douglas-Peucker)."""
MAX_CORNER = math.radians(95)
"""Two pieces that meet at a node and turn more than this are separate aisles."""
THROUGH_TURN = math.radians(45)
"""Where several pieces meet, two that turn less than this run through as one aisle."""
JOIN_REACH = 1.0
"""An aisle end within half another's width plus this [m] of its centre line joins it."""
MIN_AISLE = 3.0
"""A piece of aisle shorter than this that joins no other is dropped [m]."""


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
