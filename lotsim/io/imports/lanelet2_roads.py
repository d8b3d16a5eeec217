"""A Lanelet2 map's lanelets as roads: which ground is driven which way, which pieces
continue into each other, where roads meet.

* A **carriageway** is ground driven as one: two opposite lanelets over the same ground
  (Autoware's valet-parking maps draw a two-way road so), or side by side (sharing a
  bound: a two-way road of their joint width), or one lanelet alone (one-way).
* Carriageways whose ends meet (within :data:`NODE_TOL`) and meet nothing else continue
  into each other: a **road** is such a chain.
* Where three or more ends meet is a **junction**; the short carriageways between junction
  ends (the map's turning and crossing connectors) are dropped, lotsim builds its own turns.
  At each junction the two arms most nearly in line go on through it as one road; the other
  arms end on that road's centre line (a T). Two more arms in line (within
  :data:`THROUGH_DEG`) cross it as a second road (a crossroads).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon

from lotsim.core.geometry import FloatArray
from lotsim.io.imports.lanelet2_lines import end_on
from lotsim.io.imports.lanelet2_map import Lanelet, id_key

NODE_TOL = 1.0
"""Carriageway ends closer than this meet [m]."""
CONNECTOR_MAX = 12.0
"""A carriageway between two junction ends no longer than this is a junction connector [m]."""
THROUGH_DEG = 35.0
"""Arms of a junction within this of a straight line go through it as one road [degrees]."""
SAME_GROUND = 0.5
"""Two opposite lanelets whose polygons overlap by this fraction of their union are one
two-way carriageway."""


@dataclass(frozen=True)
class Carriageway:
    """Ground driven as one: its midline [m] (the first lanelet's way), width [m], lanelets."""

    lanelets: tuple[str, ...]
    line: FloatArray
    width: float
    two_way: bool
    polygon: Polygon

    @property
    def length(self) -> float:
        return float(np.hypot(*np.diff(self.line, axis=0).T).sum())


@dataclass
class Road:
    """A chain of carriageways: its centre line [m], its pieces, and how each end ends:
    ``("open", None)`` (nothing meets it), ``("junction", k)`` or ``("on", road index)``
    once it ends on another road's centre line."""

    line: FloatArray
    parts: list[Carriageway]
    two_way: bool
    ends: list[tuple[str, int | None]] = field(default_factory=lambda: [("open", None)] * 2)

    @property
    def lanelets(self) -> tuple[str, ...]:
        return tuple(i for c in self.parts for i in c.lanelets)

    @property
    def width(self) -> float:
        """The carriageways' width, weighted by length [m]."""
        lengths = np.array([c.length for c in self.parts])
        return float(np.dot(lengths, [c.width for c in self.parts]) / lengths.sum())


@dataclass(frozen=True)
class Network:
    """Roads and junctions of a map; ``connectors`` are the lanelets dropped at junctions."""

    roads: tuple[Road, ...]
    junctions: tuple[FloatArray, ...]
    connectors: tuple[str, ...]


def _resampled(a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Both polylines at the same fractions of their lengths (every vertex of either)."""
    def fractions(p: FloatArray) -> FloatArray:
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
        return s / s[-1] if s[-1] > 0 else np.linspace(0, 1, len(p))
    ta, tb = fractions(a), fractions(b)
    t = np.unique(np.concatenate([ta, tb]))
    return (np.column_stack([np.interp(t, ta, a[:, 0]), np.interp(t, ta, a[:, 1])]),
            np.column_stack([np.interp(t, tb, b[:, 0]), np.interp(t, tb, b[:, 1])]))


def midline(left: FloatArray, right: FloatArray) -> tuple[FloatArray, float]:
    """The line midway between two bounds of one direction, and their mean distance [m]."""
    a, b = _resampled(left, right)
    line = (a + b) / 2
    gaps = np.hypot(*(a - b).T)
    seg = np.hypot(*np.diff(line, axis=0).T)
    weights = np.concatenate([[0.0], seg]) + np.concatenate([seg, [0.0]])
    width = float(np.dot(gaps, weights) / weights.sum()) if weights.sum() > 0 else float(
        gaps.mean())
    return _dedup(line), width


def _dedup(line: FloatArray, tol: float = 1e-6) -> FloatArray:
    keep = np.concatenate([[True], np.hypot(*np.diff(line, axis=0).T) > tol])
    return line[keep]


def _heading(line: FloatArray) -> FloatArray:
    d = line[-1] - line[0]
    return d / max(float(np.hypot(*d)), 1e-12)


def carriageways(lanelets: tuple[Lanelet, ...]) -> list[Carriageway]:
    """Pair opposite lanelets over the same ground or side by side; the rest are one-way."""
    order = sorted(lanelets, key=lambda ll: id_key(ll.id))
    polys = [ll.polygon for ll in order]
    mids = [midline(ll.left, ll.right) for ll in order]
    tree = shapely.STRtree(polys)
    used: set[int] = set()
    out = []
    for i, ll in enumerate(order):
        if i in used:
            continue
        used.add(i)
        line, width = mids[i]
        mate, joint = None, None
        for j in sorted(int(j) for j in tree.query(polys[i].buffer(0.05))):
            if j in used or float(np.dot(_heading(mids[i][0]), _heading(mids[j][0]))) >= 0:
                continue
            inter = polys[i].intersection(polys[j]).area
            union = polys[i].union(polys[j]).area
            if union > 0 and inter / union > SAME_GROUND:
                mate, joint = j, None
                break
            other = order[j]
            shared = np.hypot(*(_resampled(ll.left, other.left[::-1])[0]
                                - _resampled(ll.left, other.left[::-1])[1]).T).max()
            if shared < 0.05 and inter < 0.05 * min(polys[i].area, polys[j].area):
                mate, joint = j, midline(ll.right, other.right[::-1])
                break
        if mate is None:
            out.append(Carriageway((ll.id,), line, width, False, polys[i]))
            continue
        used.add(mate)
        if joint is not None:
            line, width = joint
        out.append(Carriageway((ll.id, order[mate].id), line, width, True,
                               polys[i].union(polys[mate])))
    return out


def network(parts: list[Carriageway]) -> Network:
    """Chain the carriageways into roads, find the junctions, and join the roads there."""
    # ends -> nodes
    nodes: list[FloatArray] = []
    node_of: dict[tuple[int, int], int] = {}
    for k, c in enumerate(parts):
        for e, p in ((0, c.line[0]), (1, c.line[-1])):
            for n, q in enumerate(nodes):
                if float(np.hypot(*(p - q))) < NODE_TOL:
                    node_of[(k, e)] = n
                    break
            else:
                nodes.append(p)
                node_of[(k, e)] = len(nodes) - 1
    at: dict[int, list[tuple[int, int]]] = {n: [] for n in range(len(nodes))}
    for (k, e), n in sorted(node_of.items()):
        at[n].append((k, e))
    junction = {n for n, ends in at.items() if len(ends) >= 3}
    # junction clusters: junction nodes joined by short connectors
    cluster = {n: n for n in junction}

    def find(n: int) -> int:
        while cluster[n] != n:
            n = cluster[n]
        return n

    connectors = set()
    for k, c in enumerate(parts):
        a, b = node_of[(k, 0)], node_of[(k, 1)]
        if a in junction and b in junction and c.length <= CONNECTOR_MAX:
            connectors.add(k)
            ra, rb = find(a), find(b)
            if ra != rb:
                cluster[max(ra, rb)] = min(ra, rb)
    roots = sorted({find(n) for n in junction})
    jid = {n: roots.index(find(n)) for n in junction}
    centres = [np.mean([nodes[n] for n in junction if jid[n] == j], axis=0)
               for j in range(len(roots))]

    # chains through nodes where exactly two carriageway ends meet
    roads: list[Road] = []
    seen: set[int] = set()
    for start in range(len(parts)):
        if start in connectors or start in seen:
            continue
        chain = [(start, False)]  # (part, reversed)
        seen.add(start)
        for direction in (1, 0):  # grow forward from the end, then backward from the start
            while True:
                k, rev = chain[-1] if direction else chain[0]
                tip = (1 - rev) if direction else rev  # the end of part k at this tip
                tip = int(tip)
                n = node_of[(k, tip)]
                others = [(j, e) for j, e in at[n] if j != k]
                if len(at[n]) != 2 or not others or others[0][0] in seen \
                        or others[0][0] in connectors:
                    break
                j, e = others[0]
                if parts[j].two_way != parts[k].two_way:
                    break
                nrev = (e == 1) if direction else (e == 0)
                if not parts[j].two_way and nrev:
                    break  # one-way pieces driven against each other
                seen.add(j)
                if direction:
                    chain.append((j, nrev))
                else:
                    chain.insert(0, (j, nrev))
        pts = [parts[k].line[::-1] if rev else parts[k].line for k, rev in chain]
        line = _dedup(np.vstack(pts))
        road = Road(line, [parts[k] for k, _ in chain], parts[chain[0][0]].two_way)
        first, last = chain[0], chain[-1]
        for e, (k, rev) in ((0, first), (1, last)):
            n = node_of[(k, int(rev) if e == 0 else 1 - int(rev))]
            road.ends[e] = ("junction", jid[n]) if n in junction else ("open", None)
        roads.append(road)
    dropped = tuple(sorted((i for k in connectors for i in parts[k].lanelets), key=id_key))
    return Network(_join(roads, centres), tuple(centres), dropped)


def _arrival(road: Road, end: int) -> tuple[FloatArray, FloatArray]:
    """The end point of ``road`` at ``end`` and the unit direction of arriving there."""
    line = road.line if end == 1 else road.line[::-1]
    d = line[-1] - line[-2]
    return line[-1], d / float(np.hypot(*d))


def _join(roads: list[Road], centres: list[FloatArray]) -> tuple[Road, ...]:
    """At each junction: the arms most in line become one road through it, a second pair
    in line crosses it, the rest end on the nearest road through it."""
    alias: dict[int, int] = {}
    for j in range(len(centres)):
        arms = [(r, e) for r, road in enumerate(roads) for e in (0, 1)
                if road.ends[e] == ("junction", j)]
        pairs = []
        loops = {r for r, e in arms if (r, 1 - e) in arms}
        pairs = []
        for x in range(len(arms)):
            for y in range(x + 1, len(arms)):
                (ra, ea), (rb, eb) = arms[x], arms[y]
                if ra in loops or rb in loops or roads[ra].two_way != roads[rb].two_way:
                    continue
                if not roads[ra].two_way and ea == eb:
                    continue  # one-way roads go through only where one leaves as one arrives
                _, da = _arrival(roads[ra], ea)
                _, db = _arrival(roads[rb], eb)
                turn = float(np.degrees(np.arccos(np.clip(-np.dot(da, db), -1, 1))))
                pairs.append((turn, x, y))
        pairs.sort()
        through: list[int] = []  # the roads going through j
        taken: set[int] = set()
        for turn, x, y in pairs:
            if x in taken or y in taken or (through and turn > THROUGH_DEG):
                continue
            (ra, ea), (rb, eb) = arms[x], arms[y]
            roads[ra] = _merge(roads[ra], ea, roads[rb], eb)
            roads[rb] = Road(np.zeros((0, 2)), [], False, [("gone", None), ("gone", None)])
            alias[rb] = ra
            taken |= {x, y}
            through.append(ra)
        for x, (r, e) in enumerate(arms):
            if x in taken or not through:
                continue
            end, _ = _arrival(roads[r], e)
            host = min(through, key=lambda t: LineString(roads[t].line).distance(Point(end)))
            roads[r] = Road(end_on(roads[r].line, e, roads[host].line), roads[r].parts,
                            roads[r].two_way, list(roads[r].ends))
            roads[r].ends[e] = ("on", host)
    kept = [k for k, r in enumerate(roads) if r.ends[0][0] != "gone"]
    index = {k: i for i, k in enumerate(kept)}

    def live(k: int) -> int:
        while k in alias:
            k = alias[k]
        return index[k]

    for k in kept:
        roads[k].ends = [(kind, live(v)) if kind == "on" else (kind, v)
                         for kind, v in roads[k].ends]
    return tuple(roads[k] for k in kept)


def _merge(a: Road, ea: int, b: Road, eb: int) -> Road:
    """``a`` arriving at its end ``ea``, then ``b`` leaving from its end ``eb``: one road,
    keeping ``a``'s direction where ``a`` is one-way."""
    la = a.line if ea == 1 else a.line[::-1]
    lb = b.line if eb == 0 else b.line[::-1]
    pa = a.parts if ea == 1 else a.parts[::-1]
    pb = b.parts if eb == 0 else b.parts[::-1]
    far_a = a.ends[1 - ea]
    far_b = b.ends[1 - eb]
    road = Road(_dedup(np.vstack([la, lb])), pa + pb, a.two_way, [far_a, far_b])
    if ea == 0:  # keep a one-way road's direction: it was arriving at its start
        road = Road(road.line[::-1], road.parts[::-1], road.two_way, road.ends[::-1])
    return road
