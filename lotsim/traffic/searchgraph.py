"""The lot graph as one vehicle type drives it: :class:`SearchGraph`, the graph the
cooperative space-time search runs on.

Each edge of the lot graph a type may drive becomes an :class:`Edge` with its speed limit
for the type (and, for park and leave edges, the type's maneuver); close lane nodes are
joined by express edges too. A vehicle passes a node at rest or at one of a few speed
levels; an edge driven from one level to another is an :class:`EdgeMotion`: its
jerk-limited profile, duration, end pose and swept hulls, worked out when first asked for
and kept with the graph. Static shortest times over the edges serve slot choice and the
heuristic (:class:`~lotsim.traffic.heuristic.ReverseResumable`).

A graph depends on the lot, the vehicle type and the :class:`~lotsim.traffic.settings.
SearchSettings` alone, so runs on a prepared lot may share one: :func:`search_graph` with a
:class:`SearchGraphMemo` held beside the lot.
"""

from __future__ import annotations

import heapq
import math
import time
from collections import deque
from dataclasses import dataclass

import numpy as np
from shapely.geometry.base import BaseGeometry

from lotsim.core.reusecheck import ReuseCheck, difference
from lotsim.maneuvers.maneuver import Maneuver
from lotsim.roadmap.model import LotGraph
from lotsim.traffic.grid import Cells, cells_of
from lotsim.traffic.heuristic import ReverseResumable
from lotsim.traffic.settings import SearchSettings
from lotsim.traffic.swept import Swept, standing_body, swept_motions
from lotsim.vehicles.model import VehicleType
from lotsim.vehicles.motion import Motion, Piece, Stroke, scurve, speed_cap, timed_path

AT_REST = ("park", "leave", "turnaround")
"""Edges driven from rest to rest (multi-stroke: the car stops at every cusp)."""


KEPT_HULLS = 250_000
"""Swept hulls a :class:`SearchGraph` keeps at most (a hull with its row and cells takes
0.3 to 1.3 kB): past it, those not asked for since it was last full are let go, and worked
out again if asked for (the same hulls: a pure function of the motion). A day of 3000 cars
on a 364-bay lot asks for some 150 000 per type and keeps them all; however long a run, a
graph holds no more than this. (A bound well under what a run asks for costs it more time
working them out again than it saves: most hulls are asked for again within the hour.)"""


class Tally:
    """Seconds spent working out what a search graph keeps (edge motions and their swept
    hulls), so that a search's time can be told from the graph's first-use work; and the
    swept hulls kept, at most ``most`` (:data:`KEPT_HULLS`), the least used let go first.

    The hulls are kept by the edge motions worked out together (a group, see
    :meth:`SearchGraph.variants`), oldest first. Past ``most``, each group in turn is let
    go unless one of its motions was asked for since the last pass, which instead puts it
    last (a second chance, the clock algorithm), until three quarters of ``most`` are
    left.
    """

    __slots__ = ("seconds", "most", "hulls", "_groups", "let_go")

    def __init__(self, most: int = KEPT_HULLS) -> None:
        self.seconds = 0.0
        self.most = most
        self.hulls = 0
        """Hulls kept now."""
        self._groups: deque[list[EdgeMotion]] = deque()
        self.let_go = 0
        """Hulls let go so far (each may have been worked out again since)."""

    def keep(self, group: list[EdgeMotion]) -> None:
        """``group``'s hulls are kept from now (its motions' hulls worked out together)."""
        self._groups.append(group)
        self.hulls += sum(len(em._swept) for em in group)
        if self.hulls > self.most:
            self._let_go()

    def _let_go(self) -> None:
        groups, target = self._groups, 3 * self.most // 4
        while self.hulls > target and len(groups) > 1:
            group = groups.popleft()
            if any(em._asked for em in group):  # asked for since the last pass: kept
                for em in group:
                    em._asked = False
                groups.append(group)
                continue
            for em in group:
                n = len(em._swept)
                self.hulls -= n
                self.let_go += n
                em._swept = None


class EdgeMotion:
    """An edge driven between two speed levels: the motion, its duration [s], end pose,
    and the hulls it sweeps (in its own time; worked out when first asked for: a search
    needs them only where someone else comes near the edge — and then for every speed
    the edge is driven to from the same start speed, so those are worked out together,
    see :meth:`SearchGraph.variants`; kept while they are asked for, see :class:`Tally`)."""

    __slots__ = ("motion", "duration", "end", "_vehicle", "_settings", "_swept", "group",
                 "_tally", "_asked")

    def __init__(self, motion: Motion, vehicle: VehicleType, settings: SearchSettings,
                 tally: Tally | None = None):
        self.motion = motion
        self.duration = motion.duration
        self.end = motion.end
        self._vehicle = vehicle
        self._settings = settings
        self._swept: Swept | None = None
        self.group: list[EdgeMotion] = [self]
        self._tally = tally
        self._asked = False

    @property
    def swept(self) -> Swept:
        """The hulls it sweeps, chunk by chunk (the graph's settings' ``chunk`` and
        ``sample``), in its own time."""
        sw = self._swept
        if sw is None:
            sw = self._work_out()
        self._asked = True
        return sw

    def _work_out(self) -> Swept:
        """Work out the hulls of every motion of its group not kept now."""
        clock = time.perf_counter()
        todo = [em for em in self.group if em._swept is None]
        s = self._settings
        for em, sw in zip(todo, swept_motions([em.motion for em in todo], self._vehicle,
                                              chunk=s.chunk, sample=s.sample),
                          strict=True):
            em._swept = sw
        self._asked = True  # (asked for now: not let go before it is used)
        mine = self._swept
        if self._tally is not None:
            self._tally.keep(todo)
            self._tally.seconds += time.perf_counter() - clock
        return mine


@dataclass(frozen=True, slots=True)
class Edge:
    """An edge of a :class:`SearchGraph`: from node ``u`` to ``v``, of ``kind`` (``lane``,
    ``turn``, ``park``, ``leave``, ``turnaround``, ``join``, ...) and ``length`` [m], with
    its lot-graph edge's ``data``."""

    u: int
    v: int
    kind: str
    length: float
    cap: float  # speed limit on the edge for this type [m/s]
    data: dict
    maneuver: Maneuver | None = None  # a park or leave edge's, for this type
    duration: float = 0.0  # the maneuver's [s]
    limit: float = math.inf  # speed limit along the maneuver [m/s]
    park_only: bool = False  # a park edge only a car that will not leave may take


class SearchGraph:
    """The lot graph seen by one vehicle type: edges, speed levels, timed motions.

    Motions and their swept hulls are computed on first use and kept (the hulls while they
    are used: at most ``kept_hulls``).

    Parameters
    ----------
    lg : LotGraph
    vehicle : VehicleType
    settings : SearchSettings, optional
        The search's tuning (default ``SearchSettings()``): the graph's speed levels,
        express edges and swept hulls follow it, and every search on the graph reads the
        rest of it from :attr:`settings`.
    kept_hulls : int, optional
        Swept hulls kept at most (:data:`KEPT_HULLS`; :class:`Tally`): the memory the graph
        holds, not its answers (a hull let go is worked out again, the same).

    Notes
    -----
    Nodes sit wherever a maneuver or a turn begins, often half a metre apart, and a car
    passes each node at one of the speed levels: over half a metre it cannot change level,
    so on a stretch of close nodes it could never speed up (and the heuristic, which
    assumes it can, would misjudge every state). So every lane node is also joined to the
    first node at least ``settings.express`` ahead along its lane (or the last before the
    speed limit changes) by an express edge, which the car drives as one speed profile;
    the short edges stay, to stop on a node.
    """

    def __init__(self, lg: LotGraph, vehicle: VehicleType, *,
                 settings: SearchSettings | None = None, kept_hulls: int = KEPT_HULLS):
        self.lg = lg
        self.vehicle = vehicle
        self.settings = settings = settings or SearchSettings()
        g = lg.graph
        top = vehicle.limits.max_forward_speed
        step = settings.speed_step
        n_levels = int(math.floor(top / step + 1e-9))
        levels = [k * step for k in range(n_levels + 1)]
        if top - levels[-1] > 1e-6:
            levels.append(top)
        self.levels = np.array(levels)
        self.edges: list[Edge] = []
        self.out: dict[int, list[int]] = {n: [] for n in g.nodes}
        self.into: dict[int, list[int]] = {n: [] for n in g.nodes}
        name = vehicle.name
        for u, v, d in g.edges(data=True):
            kind = d["kind"]
            if kind in ("park", "leave"):
                # the maneuver a car may leave by again, and (park edges) the lane's own
                # best where that differs, for a car that will not leave
                for m, dur, lim, park_only in (
                        (d["maneuvers"].get(name), d["duration"].get(name, 0.0),
                         d["speed_limit"], False),
                        (d.get("park_only", {}).get(name),
                         d.get("park_only_duration", {}).get(name, 0.0),
                         d.get("park_only_limit", math.inf), True)):
                    if m is not None:
                        self._add(Edge(u, v, kind, float(m.length), min(float(lim), top), d,
                                        m, float(dur), float(lim), park_only))
                continue
            if d.get("placeholder"):
                continue
            if d.get("types") is not None and name not in d["types"]:
                continue  # a turn this type cannot make (too wide, or too tight for it)
            cap = min(float(d["speed_limit"]), top)
            for seg in d.get("path") or ():
                cap = min(cap, speed_cap(seg, vehicle))
            self._add(Edge(u, v, kind, float(d["length"]), cap, d))
        self.base_edges = len(self.edges)
        """How many of :attr:`edges` are the lot graph's; the rest are express edges."""
        self._express()
        self.pose = {n: tuple(map(float, g.nodes[n]["pose"])) for n in g.nodes}
        self.steer = {n: math.atan(g.nodes[n].get("curvature", 0.0) * vehicle.wheelbase)
                      for n in g.nodes}
        self.slot_nodes = set(lg.slot_nodes.values())
        self._motions: dict[tuple[int, int, int], EdgeMotion | None] = {}
        self.tally = Tally(kept_hulls)
        """Seconds spent so far working out edge motions and their hulls (kept for every
        later search on the graph)."""
        self._paths: dict[int, tuple] = {}
        self._variants: dict[tuple[int, int], tuple[list[tuple[int, EdgeMotion]], float]] = {}
        self._bodies: dict[int, BaseGeometry] = {}
        self._cells: dict[int, Cells] = {}
        self._boxes: dict[tuple[int, int], tuple[float, float, float, float]] = {}
        self._standing: dict[int, Swept] = {}
        self._static_time = [self._lower_time(i, e) for i, e in enumerate(self.edges)]
        self._back: dict[int, list[tuple[int, float]]] = {}
        self.passable = {n: self.back(n) for n in g.nodes if n not in self.slot_nodes}
        """:meth:`back` of every node a path may pass through (all but the slots)."""

    def _add(self, e: Edge) -> None:
        self.out[e.u].append(len(self.edges))
        self.into[e.v].append(len(self.edges))
        self.edges.append(e)

    def _express(self) -> None:
        """Add an edge from every lane node along its lane to the first node at least
        ``settings.express`` ahead (or the last before the speed limit changes): see the
        class's notes."""
        express = self.settings.express
        along: dict[int, list[int]] = {}
        for i, e in enumerate(self.edges):
            if e.kind == "lane":
                along.setdefault(e.u, []).append(i)
        for u, first in along.items():
            if len(first) != 1 or self.edges[first[0]].length >= express:
                continue
            head = self.edges[first[0]]
            chain, length, node = [head], head.length, head.v
            while length < express and len(along.get(node, ())) == 1:
                e = self.edges[along[node][0]]
                if e.cap != head.cap or e.data["speed_limit"] != head.data["speed_limit"]:
                    break
                chain.append(e)
                length += e.length
                node = e.v
            if len(chain) < 2:
                continue
            data = {"kind": "lane", "length": length, "speed_limit": head.data["speed_limit"],
                    "path": tuple(seg for e in chain for seg in e.data["path"])}
            self._add(Edge(u, node, "lane", length, head.cap, data))

    # -- motions ------------------------------------------------------------------------------
    def motion(self, ei: int, a: int, b: int) -> EdgeMotion | None:
        """Edge ``ei`` driven from speed level ``a`` to ``b`` (None when the edge cannot join
        those speeds)."""
        key = (ei, a, b)
        if key in self._motions:
            return self._motions[key]
        clock = time.perf_counter()
        e = self.edges[ei]
        out = None
        if e.kind in AT_REST:
            if a == 0 and b == 0:
                segs, limit = ((e.data["path"], e.data["speed_limit"]) if e.maneuver is None
                               else (e.maneuver.segments, e.limit))
                motion = timed_path([Piece(s, limit) for s in segs],
                                    self.vehicle, steer_from=self.steer[e.u],
                                    steer_to=self.steer[e.v])
                out = self._timed(motion)
        elif e.length > 0 and self.crawls(e):
            if a == 0 and b == 0:  # from rest to rest: each piece at the speed it allows
                motion = timed_path([Piece(s, e.data["speed_limit"]) for s in self._path(ei)],
                                    self.vehicle, steer_from=self.steer[e.u],
                                    steer_to=self.steer[e.v])
                out = self._timed(motion)
        elif e.length > 0:
            lim = self.vehicle.limits
            va, vb = self.levels[a], self.levels[b]
            if va <= e.cap + 1e-9 and vb <= e.cap + 1e-9:
                prof = scurve(e.length, va, vb, e.cap, lim.max_accel, lim.max_brake,
                              lim.max_jerk)
                if prof is not None:
                    out = self._timed(Motion((Stroke(self._path(ei), prof),)))
        self._motions[key] = out
        self.tally.seconds += time.perf_counter() - clock
        return out

    def crawls(self, e: Edge) -> bool:
        """Whether edge ``e``'s tightest piece is slower than the lowest speed a car passes a
        node at: it is then driven from rest to rest, each piece as fast as it allows (a
        tight junction turn's sharp clothoids slowly, the arc between them faster), not
        all of it at its tightest piece's speed."""
        return len(self.levels) > 1 and e.cap < self.levels[1] - 1e-9

    def _path(self, ei: int) -> tuple:
        """Edge ``ei``'s path as a tuple, one for all the motions along it (kept)."""
        path = self._paths.get(ei)
        if path is None:
            path = self._paths[ei] = tuple(self.edges[ei].data["path"])
        return path

    def variants(self, ei: int, a: int) -> tuple[list[tuple[int, EdgeMotion]], float]:
        """Edge ``ei`` driven from speed level ``a``: ``(b, motion)`` for every end level
        ``b`` it can reach (only rest for a maneuver, a join or a turnaround), and the
        longest of their durations [s] (kept: a search asks for them at every visit)."""
        out = self._variants.get((ei, a))
        if out is None:
            ends = [0] if self.edges[ei].kind in AT_REST else range(len(self.levels))
            found = [(b, em) for b in ends if (em := self.motion(ei, a, b)) is not None]
            group = [em for _, em in found]
            for em in group:
                em.group = group
            out = self._variants[ei, a] = (found, max((em.duration for _, em in found),
                                                      default=0.0))
        return out

    def sweep_box(self, ei: int, a: int) -> tuple[float, float, float, float]:
        """The box ``(x0, y0, x1, y1)`` [m] holding every hull edge ``ei`` sweeps driven from
        speed level ``a`` to any end level (:meth:`variants`), the lowest and highest of
        their own boxes' sides (kept)."""
        box = self._boxes.get((ei, a))
        if box is None:
            ext = [em.swept.extent for _, em in self.variants(ei, a)[0]]
            box = self._boxes[ei, a] = (min(e[2] for e in ext), min(e[3] for e in ext),
                                        max(e[4] for e in ext), max(e[5] for e in ext))
        return box

    def _timed(self, motion: Motion) -> EdgeMotion:
        return EdgeMotion(motion, self.vehicle, self.settings, self.tally)

    def edge_cells(self, ei: int, em: EdgeMotion) -> Cells:
        """Grid cells of everything edge ``ei`` sweeps (the same at any speed)."""
        cells = self._cells.get(ei)
        if cells is None:
            cells = self._cells[ei] = cells_of(em.swept.extent[2:])
        return cells

    def standing(self, node: int) -> Swept:
        """The footprint at lane node ``node`` at an instant, time 0."""
        sw = self._standing.get(node)
        if sw is None:
            sw = self._standing[node] = Swept.of([(0.0, 0.0, self.body(node))])
        return sw

    def body(self, node: int) -> BaseGeometry:
        """The vehicle's footprint standing at lane node ``node``."""
        if node not in self._bodies:
            self._bodies[node] = standing_body(self.vehicle, self.pose[node])
        return self._bodies[node]

    def parked_pose(self, ei: int) -> tuple[float, float, float]:
        """Where park edge ``ei``'s maneuver leaves the vehicle, or leave edge ``ei``'s
        begins."""
        e = self.edges[ei]
        m = e.maneuver
        return tuple(map(float, m.end if e.kind == "park" else m.start))

    def parked_body(self, ei: int) -> BaseGeometry:
        """The footprint at :meth:`parked_pose`."""
        key = -1 - ei
        if key not in self._bodies:
            self._bodies[key] = standing_body(self.vehicle, self.parked_pose(ei))
        return self._bodies[key]

    def _lower_time(self, i: int, e: Edge) -> float:
        if e.kind in ("park", "leave"):
            return e.duration
        if e.kind == "turnaround" or (e.length > 0 and self.crawls(e)):
            em = self.motion(i, 0, 0)
            return em.duration if em is not None else math.inf
        return e.length / e.cap if e.length > 0 else 0.0

    # -- static distances ---------------------------------------------------------------------
    def back(self, v: int) -> list[tuple[int, float]]:
        """``(u, static time [s])`` of every edge into node ``v`` (kept)."""
        out = self._back.get(v)
        if out is None:
            out = self._back[v] = [(self.edges[ei].u, self._static_time[ei])
                                   for ei in self.into[v]]
        return out

    def back_avoiding(self, v: int, shut: frozenset[int]) -> list[tuple[int, float]]:
        """:meth:`back` less the edges ``shut`` (edge indices)."""
        return [(self.edges[ei].u, self._static_time[ei]) for ei in self.into[v]
                if ei not in shut]

    def reverse_search(self, goals: dict[int, float], *, shut: frozenset[int] = frozenset()
                       ) -> ReverseResumable:
        """An RRA* from ``goals`` (node → extra time at it) over this graph's edges (less
        those ``shut``)."""
        return ReverseResumable(self, goals, shut=shut)

    def forward_times(self, source: int) -> dict[int, float]:
        """Static shortest times [s] from ``source`` to every node it reaches (Dijkstra,
        entering no slot on the way)."""
        return self.forward_tree(source)[0]

    def static_time(self, ei: int) -> float:
        """Least time [s] edge ``ei`` can be driven in (its maneuver's, or its length at its
        speed limit)."""
        return self._static_time[ei]

    def forward_tree(self, source: int, *, express: bool = True
                     ) -> tuple[dict[int, float], dict[int, int]]:
        """:meth:`forward_times` and, for every node reached but ``source``, the edge (by
        index) its shortest way from ``source`` ends with; without ``express`` edges, so
        that a way names every node it passes."""
        return self._tree({source: 0.0}, self.out, lambda e: e.v, express)

    def backward_tree(self, goals, *, express: bool = True
                      ) -> tuple[dict[int, float], dict[int, int]]:
        """Static shortest times [s] from every node to the nearest of ``goals`` (node ids),
        leaving no slot on the way, and for every node but the goals the edge (by index) its
        shortest way there begins with; without ``express`` edges, so that a way names
        every node it passes."""
        return self._tree({n: 0.0 for n in goals}, self.into, lambda e: e.u, express)

    def _tree(self, sources: dict[int, float], step: dict[int, list[int]], far,
              express: bool = True) -> tuple[dict[int, float], dict[int, int]]:
        """Dijkstra from ``sources`` over the edges ``step`` lists at each node (the express
        edges only with ``express``), each edge leading to ``far(edge)``; a slot node is
        reached but not gone on from."""
        last = len(self.edges) if express else self.base_edges
        dist = dict(sources)
        by: dict[int, int] = {}
        heap = [(d, n) for n, d in sorted(sources.items())]
        heapq.heapify(heap)
        done: set[int] = set()
        while heap:
            d, u = heapq.heappop(heap)
            if u in done:
                continue
            done.add(u)
            if u in self.slot_nodes and u not in sources:
                continue
            for ei in step[u]:
                if ei >= last:
                    continue
                n = far(self.edges[ei])
                nd = d + self._static_time[ei]
                if nd < dist.get(n, math.inf):
                    dist[n] = nd
                    by[n] = ei
                    heapq.heappush(heap, (nd, n))
        return dist, by


class SearchGraphMemo:
    """The search graphs of one lot, one per vehicle type and settings, for
    :func:`search_graph`: held by whoever holds the lot (a prepared lot) and passed in by
    every run on it.

    A graph's edge motions and their swept hulls depend on the lot, the type and the
    settings alone, so runs after the first on a prepared lot (a suite's planners and seeds,
    a notebook's runs) drive the edges the first has worked out without working them out
    again, and plan the same. A memo serves one lot graph (another is refused), lives in
    its process and is not pickled (a copy starts empty).

    With a reuse check (``check``, :class:`~lotsim.core.reusecheck.ReuseCheck`), a graph
    handed out again is compared with one made afresh: its edges, their static times and
    every edge motion (and swept hulls) worked out so far (:func:`same_graph`).

    Examples
    --------
    >>> memo = SearchGraphMemo()
    >>> len(memo)
    0
    """

    __slots__ = ("_lot_graph", "_graphs", "check", "kept_hulls")

    def __init__(self, check: ReuseCheck | None = None, *,
                 kept_hulls: int = KEPT_HULLS) -> None:
        self._lot_graph: LotGraph | None = None
        self._graphs: dict[tuple[VehicleType, SearchSettings], SearchGraph] = {}
        self.check = check
        self.kept_hulls = kept_hulls
        """Swept hulls each graph keeps at most (:class:`SearchGraph`'s ``kept_hulls``)."""

    def __len__(self) -> int:
        return len(self._graphs)

    def __reduce__(self):
        return (SearchGraphMemo, (None,), {"kept_hulls": self.kept_hulls})

    def __setstate__(self, state: dict) -> None:
        self.kept_hulls = state["kept_hulls"]

    def graph(self, lg: LotGraph, vehicle: VehicleType, settings: SearchSettings
              ) -> SearchGraph:
        """``lg`` as seen by ``vehicle`` with ``settings``, made on first use."""
        if self._lot_graph is None:
            self._lot_graph = lg
        elif self._lot_graph is not lg:
            raise ValueError("a SearchGraphMemo holds the search graphs of one lot graph")
        key = (vehicle, settings)
        sg = self._graphs.get(key)
        if sg is None:
            sg = self._graphs[key] = SearchGraph(lg, vehicle, settings=settings,
                                                 kept_hulls=self.kept_hulls)
        elif self.check is not None:
            self.check.compare("search graphs", (vehicle.name, settings), sg,
                               SearchGraph(lg, vehicle, settings=settings), differ=same_graph)
        return sg


def same_graph(held: SearchGraph, fresh: SearchGraph) -> str | None:
    """Where search graph ``held`` (made earlier, driven since) differs from ``fresh``
    (the same lot, type and settings, made now), or None: their edges and static times, and
    each edge motion ``held`` has worked out — its motion, duration and end, and its swept
    hulls where ``held`` has swept it — worked out again in ``fresh``."""
    got = difference((held.edges, held._static_time, held.pose),
                     (fresh.edges, fresh._static_time, fresh.pose))
    if got is not None:
        return f"edges: {got}"
    for (ei, a, b), em in held._motions.items():
        again = fresh.motion(ei, a, b)
        parts = [(x.motion, x.duration, x.end) if x is not None else None for x in (em, again)]
        if em is not None and again is not None and em._swept is not None:
            parts = [(*parts[0], em._swept), (*parts[1], again.swept)]
        got = difference(*parts)
        if got is not None:
            return f"edge {ei} from speed level {a} to {b}: {got}"
    return None


def search_graph(lg: LotGraph, vehicle: VehicleType, memo: SearchGraphMemo | None = None, *,
                 settings: SearchSettings | None = None) -> SearchGraph:
    """``lg`` as seen by ``vehicle``: the :class:`SearchGraph` kept in ``memo`` (made there
    on first use), or, without one, a new one.

    Parameters
    ----------
    lg : LotGraph
    vehicle : VehicleType
    memo : SearchGraphMemo, optional
        The lot's search graphs, shared by the runs on it (see :class:`SearchGraphMemo`).
    settings : SearchSettings, optional
        The search's tuning (default ``SearchSettings()``).
    """
    settings = settings or SearchSettings()
    if memo is None:
        return SearchGraph(lg, vehicle, settings=settings)
    return memo.graph(lg, vehicle, settings)
