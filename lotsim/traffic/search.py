"""Cooperative space-time A* over the lot graph: CA*, HCA* and WHCA*.

A vehicle's search state is ``(node, speed level, time)``: it stands on a lot
graph node at a time [s], at rest (level 0) or passing through at one of a few
speeds (multiples of 5 km/h up to its top speed). Moves are

* **drive an edge** from speed level ``a`` to ``b``: the fastest jerk-limited
  profile (:func:`~lotsim.vehicles.motion.scurve`) within the edge's speed limit —
  the lowest of the lot's, the vehicle's top speed, and what the edge's curves
  allow for lateral acceleration and steering rate — and the vehicle's
  acceleration, braking and jerk, with zero acceleration at both nodes; so plans
  are the trajectories, with no re-timing afterwards;
* **wait** at a node, at rest, for as long as it needs: from rest a vehicle departs on
  each edge at the earliest time of each stretch of time in which the edge's motion
  meets nobody (safe-interval path planning, SIPP: Phillips & Likhachev 2011), as long
  as its body stands in nobody's way meanwhile;
* **park** (from rest, through the slot's planned maneuver, ending at rest in
  the slot) or **leave** (the same backwards), taking the maneuver's time,
  with the car standing to turn its wheels at cusps and wherever the maneuver's
  curvature still jumps (:func:`~lotsim.vehicles.motion.timed_path`);
* **turn round** (from rest, through a multi-point turn at a dead end, to rest on the
  opposite lane), timed the same way;
* **enter**: a vehicle not yet in the lot waits outside its entrance, taking
  no space, until its first move is free.

Every move is checked against the :class:`~lotsim.traffic.reservation.ReservationTable`
with the hulls of what the vehicle sweeps, chunk by chunk — a cover of its real
footprint at every instant, including the whole of a parking maneuver that
sweeps across the aisle. A goal in a slot is accepted only if the slot stays
free for ever after (the vehicle will stand there).

Heuristics: CA* uses the straight-line distance at top speed; HCA* the true
static time to the goal, from a Reverse Resumable A* (RRA*, Silver 2005) run
backwards from the goal and resumed on demand. WHCA* (in :func:`lotsim.sim.running.run`)
searches like HCA* and replans every half window as it drives, keeping the new
plan when it arrives sooner. The fuse of seed 004 stops a search that
expands more than ``omega`` times the nodes its reverse search closed.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field
from enum import Enum

import numpy as np
from shapely.geometry.base import BaseGeometry

from lotsim.core.geometry import same_pose
from lotsim.maneuvers.maneuver import Maneuver
from lotsim.roadmap.model import LotGraph
from lotsim.sim.settings import OMEGA, PLANNERS
from lotsim.traffic.reservation import (
    ReservationTable,
    Swept,
    cells_of,
    standing_body,
    swept_motions,
)
from lotsim.vehicles.model import KMH, VehicleType
from lotsim.vehicles.motion import Motion, Piece, Stroke, scurve, speed_cap, timed_path

AT_REST = ("park", "leave", "turnaround")
"""Edges driven from rest to rest (multi-stroke: the car stops at every cusp)."""
SPEED_STEP = 5 * KMH
"""Spacing of the speed levels a vehicle may pass a node at [m/s]."""
DEPART_AFTER = 1e-6
"""A vehicle that waits for a body to clear its way departs this long [s] after the last
instant the two would meet."""
MIN_BUDGET = 20000
"""A search may always expand at least this many states before the fuse blows."""
WEIGHT = 1.25
EXPRESS = 6.0
"""Lane nodes closer than this [m] are also joined by one edge through them (see
:meth:`SearchGraph._express`)."""
PASSING = 2.0
"""A vehicle passing a node at a speed level within this long [s] after an earlier state of
the search passed it at that level is taken for that state (see :func:`search`)."""


class Status(Enum):
    """How a search ended."""

    FOUND = "found"
    FUSE = "fuse"
    NO_PATH = "no path"


@dataclass(frozen=True, slots=True)
class Move:
    """One timed step of a plan.

    ``kind`` is ``drive``, ``park``, ``leave``, ``wait``, ``parked`` (standing in
    the slot until leaving) or ``outside`` (waiting to enter, taking no space).
    ``motion`` is set for moving kinds, in time from ``t0``; ``end_pose`` is where
    the move leaves the vehicle (None outside).
    """

    kind: str
    t0: float
    t1: float
    node_from: int
    node_to: int
    level_from: int
    level_to: int
    edge: int = -1
    motion: Motion | None = None
    end_pose: tuple[float, float, float] | None = None
    steer: float = 0.0  # road-wheel angle while standing [rad]


@dataclass
class Plan:
    """A search's answer: the moves, how it ended and what it cost."""

    status: Status
    moves: list[Move] = field(default_factory=list)
    expansions: int = 0

    @property
    def end(self) -> float:
        return self.moves[-1].t1 if self.moves else math.nan


class EdgeMotion:
    """An edge driven between two speed levels: the motion, its duration [s], end pose,
    and the hulls it sweeps (in its own time; worked out when first asked for: a search
    needs them only where someone else comes near the edge — and then for every speed
    the edge is driven to from the same start speed, so those are worked out together,
    see :meth:`SearchGraph.variants`)."""

    __slots__ = ("motion", "duration", "end", "_vehicle", "_swept", "group")

    def __init__(self, motion: Motion, vehicle: VehicleType):
        self.motion = motion
        self.duration = motion.duration
        self.end = motion.end
        self._vehicle = vehicle
        self._swept: Swept | None = None
        self.group: list[EdgeMotion] = [self]

    @property
    def swept(self) -> Swept:
        if self._swept is None:
            todo = [em for em in self.group if em._swept is None]
            for em, sw in zip(todo, swept_motions([em.motion for em in todo], self._vehicle),
                              strict=True):
                em._swept = sw
        return self._swept


@dataclass(frozen=True, slots=True)
class _Edge:
    u: int
    v: int
    kind: str
    length: float
    cap: float  # speed limit on the edge for this type [m/s]
    data: dict
    maneuver: Maneuver | None = None  # a park or leave edge's, for this type
    duration: float = 0.0  # the maneuver's [s]
    limit: float = math.inf  # speed limit along the maneuver [m/s]
    stay: bool = False  # a park edge only a car that will not leave may take


class SearchGraph:
    """The lot graph seen by one vehicle type: edges, speed levels, timed motions.

    Motions and their swept hulls are computed on first use and kept.
    """

    def __init__(self, lg: LotGraph, vehicle: VehicleType):
        self.lg = lg
        self.vehicle = vehicle
        g = lg.graph
        top = vehicle.limits.max_forward_speed
        n_levels = int(math.floor(top / SPEED_STEP + 1e-9))
        levels = [k * SPEED_STEP for k in range(n_levels + 1)]
        if top - levels[-1] > 1e-6:
            levels.append(top)
        self.levels = np.array(levels)
        self.edges: list[_Edge] = []
        self.out: dict[int, list[int]] = {n: [] for n in g.nodes}
        self.into: dict[int, list[int]] = {n: [] for n in g.nodes}
        name = vehicle.name
        for u, v, d in g.edges(data=True):
            kind = d["kind"]
            if kind in ("park", "leave"):
                # the maneuver a car may leave by again, and (park edges) the lane's own
                # best where that differs, for a car that will not leave
                for m, dur, lim, stay in (
                        (d["maneuvers"].get(name), d["duration"].get(name, 0.0),
                         d["speed_limit"], False),
                        (d.get("stays", {}).get(name), d.get("stay_duration", {}).get(name, 0.0),
                         d.get("stay_limit", math.inf), True)):
                    if m is not None:
                        self._add(_Edge(u, v, kind, float(m.length), min(float(lim), top), d,
                                        m, float(dur), float(lim), stay))
                continue
            if d.get("placeholder"):
                continue
            if d.get("types") is not None and name not in d["types"]:
                continue  # a turn this type cannot make (too wide, or too tight for it)
            cap = min(float(d["speed_limit"]), top)
            for seg in d.get("path") or ():
                cap = min(cap, speed_cap(seg, vehicle))
            self._add(_Edge(u, v, kind, float(d["length"]), cap, d))
        self._express()
        self.pose = {n: tuple(map(float, g.nodes[n]["pose"])) for n in g.nodes}
        self.steer = {n: math.atan(g.nodes[n].get("curvature", 0.0) * vehicle.wheelbase)
                      for n in g.nodes}
        self.slot_nodes = set(lg.slot_nodes.values())
        self._motions: dict[tuple[int, int, int], EdgeMotion | None] = {}
        self._paths: dict[int, tuple] = {}
        self._variants: dict[tuple[int, int], tuple[list[tuple[int, EdgeMotion]], float]] = {}
        self._bodies: dict[int, BaseGeometry] = {}
        self._cells: dict[int, tuple[tuple[int, int], ...]] = {}
        self._boxes: dict[tuple[int, int], tuple[float, float, float, float]] = {}
        self._standing: dict[int, Swept] = {}
        self._static_time = [self._lower_time(i, e) for i, e in enumerate(self.edges)]
        self._back: dict[int, list[tuple[int, float]]] = {}
        self.passable = {n: self.back(n) for n in g.nodes if n not in self.slot_nodes}
        """:meth:`back` of every node a path may pass through (all but the slots)."""

    def _add(self, e: _Edge) -> None:
        self.out[e.u].append(len(self.edges))
        self.into[e.v].append(len(self.edges))
        self.edges.append(e)

    def _express(self) -> None:
        """Add an edge from every lane node along its lane to the first node at least
        :data:`EXPRESS` ahead (or the last before the speed limit changes).

        Nodes sit wherever a maneuver or a turn begins, often half a metre apart, and a car
        passes each node at one of the speed levels: over half a metre it cannot change
        level, so on a stretch of close nodes it could never speed up (and the heuristic,
        which assumes it can, would misjudge every state). An express edge lets the car
        drive the stretch as one speed profile; the short edges stay, to stop on a node.
        """
        along: dict[int, list[int]] = {}
        for i, e in enumerate(self.edges):
            if e.kind == "lane":
                along.setdefault(e.u, []).append(i)
        for u, first in along.items():
            if len(first) != 1 or self.edges[first[0]].length >= EXPRESS:
                continue
            head = self.edges[first[0]]
            chain, length, node = [head], head.length, head.v
            while length < EXPRESS and len(along.get(node, ())) == 1:
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
            self._add(_Edge(u, node, "lane", length, head.cap, data))

    # -- motions ------------------------------------------------------------------------------
    def motion(self, ei: int, a: int, b: int) -> EdgeMotion | None:
        """Edge ``ei`` driven from speed level ``a`` to ``b`` (None when the edge cannot join
        those speeds)."""
        key = (ei, a, b)
        if key in self._motions:
            return self._motions[key]
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
        elif e.length > 0:
            lim = self.vehicle.limits
            va, vb = self.levels[a], self.levels[b]
            if va <= e.cap + 1e-9 and vb <= e.cap + 1e-9:
                prof = scurve(e.length, va, vb, e.cap, lim.max_accel, lim.max_brake,
                              lim.max_jerk)
                if prof is not None:
                    out = self._timed(Motion((Stroke(self._path(ei), prof),)))
        self._motions[key] = out
        return out

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
        return EdgeMotion(motion, self.vehicle)

    def edge_cells(self, ei: int, em: EdgeMotion) -> tuple[tuple[int, int], ...]:
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

    def _lower_time(self, i: int, e: _Edge) -> float:
        if e.kind in ("park", "leave"):
            return e.duration
        if e.kind == "turnaround":
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

    def reverse_search(self, goals: dict[int, float]) -> ReverseResumable:
        """An RRA* from ``goals`` (node → extra time at it) over this graph's edges."""
        return ReverseResumable(self, goals)

    def forward_times(self, source: int) -> dict[int, float]:
        """Static shortest times [s] from ``source`` to every node it reaches (Dijkstra,
        entering no slot on the way)."""
        dist = {source: 0.0}
        heap = [(0.0, source)]
        done: set[int] = set()
        slots = self.lg.graph.nodes
        while heap:
            d, u = heapq.heappop(heap)
            if u in done:
                continue
            done.add(u)
            if slots[u]["kind"] == "slot":
                continue
            for ei in self.out[u]:
                e = self.edges[ei]
                nd = d + self._static_time[ei]
                if nd < dist.get(e.v, math.inf):
                    dist[e.v] = nd
                    heapq.heappush(heap, (nd, e.v))
        return dist


def search_graph(lg: LotGraph, vehicle: VehicleType) -> SearchGraph:
    """``lg`` as seen by ``vehicle``: one :class:`SearchGraph` a type, kept with the lot
    (``lg.kept``) for every run on it in this process.

    Its edge motions and their swept hulls depend on the lot and the type alone, so runs
    after the first on a prepared lot (a suite's planners and seeds, a notebook's runs)
    drive the edges the first has worked out without working them out again, and plan the
    same."""
    graphs = lg.kept.setdefault("search_graphs", {})
    sg = graphs.get(vehicle)
    if sg is None:
        sg = graphs[vehicle] = SearchGraph(lg, vehicle)
    return sg


class ReverseResumable:
    """Reverse Resumable A*: true static time [s] from any node to the goals, computed
    backwards from the goals and resumed only as far as each query needs.

    Slot nodes other than the goals are not passed through.
    """

    def __init__(self, sg: SearchGraph, goals: dict[int, float]):
        self.sg = sg
        self.dist: dict[int, float] = {}
        self.best = dict(goals)
        self.heap = [(c, n) for n, c in goals.items()]
        heapq.heapify(self.heap)
        self.goals = set(goals)

    @property
    def closed(self) -> int:
        return len(self.dist)

    def closed_at(self, node: int) -> int:
        """How many nodes a new RRA* towards the same goals closes to answer ``node`` (one
        that has answered it; its answers do not depend on what it was asked before, only
        how far it has got): ``node``'s place in the order nodes were closed, from 1."""
        d = self.dist.get(node)
        if d is None or d == math.inf:
            return self.closed
        # nodes are closed in the order of dist's keys (unreachable ones asked for come last)
        return next(k for k, n in enumerate(self.dist, 1) if n == node)

    def __call__(self, node: int) -> float:
        dist = self.dist
        d = dist.get(node)
        if d is not None:
            return d
        heap, best, goals, passable = self.heap, self.best, self.goals, self.sg.passable
        pop, push, inf = heapq.heappop, heapq.heappush, math.inf
        while heap:
            d, v = pop(heap)
            if v in dist:
                continue
            dist[v] = d
            into = passable.get(v)
            if into is None and v in goals:
                into = self.sg.back(v)
            if into:
                for u, w in into:
                    nd = d + w
                    if nd < best.get(u, inf) and u not in dist:
                        best[u] = nd
                        push(heap, (nd, u))
            if v == node:
                return d
        dist.setdefault(node, inf)
        return dist[node]


@dataclass(frozen=True, slots=True)
class Goal:
    """Where a search ends: in ``slot`` (a slot node, for ever) or at any of ``exits``.

    A car that will leave again (``park_by`` given) parks only by the park edges
    ``(lane node, slot node)`` in ``park_by``, those that park it on a pose it can leave
    by (:meth:`~lotsim.roadmap.model.LotGraph.leavable`), and never with a maneuver the lot
    graph keeps for cars that stay (a park edge's ``stays``)."""

    slot: int | None = None
    exits: tuple[int, ...] = ()
    park_by: frozenset[tuple[int, int]] | None = None


def search(sg: SearchGraph, table: ReservationTable, *, owner: str, start: int, t0: float,
           goal: Goal, level: int = 0, outside: bool = False,
           start_pose: tuple[float, float, float] | None = None, planner: str = "hca",
           heuristic: ReverseResumable | None = None, shared: bool = False,
           omega: float = OMEGA, horizon: float = 3600.0, budget: int | None = None) -> Plan:
    """Plan one vehicle against the reservations of those planned before it.

    Parameters
    ----------
    sg : SearchGraph
        The lot graph for this vehicle's type.
    table : ReservationTable
        Everyone else's reservations (``owner``'s own are ignored).
    owner : str
    start : int
        Start node; ``level`` its speed level (0: at rest).
    t0 : float
        Start time [s].
    goal : Goal
    outside : bool, keyword-only
        The vehicle is not in the lot yet: it may wait outside ``start`` (an
        entrance) for free, and appears there at rest.
    start_pose : tuple, keyword-only
        The parked pose, when ``start`` is a slot: only the leave maneuver that
        begins there is driven, and waiting there holds this footprint.
    planner : {"ca", "hca", "whca"}
    heuristic : ReverseResumable, optional
        The RRA* towards ``goal`` (made here if not given); also sizes the fuse.
    shared : bool, keyword-only
        ``heuristic`` serves other searches too: the fuse is sized by what a new one would
        have closed to answer ``start`` (:meth:`ReverseResumable.closed_at`), not by all it
        has closed for them, so a search blows its fuse where it would with its own.
    omega : float
        The fuse factor.
    horizon : float
        Give up on states later than ``t0 + horizon`` [s].
    budget : int, optional
        Blow the fuse after this many expansions at the latest (a first look).

    Returns
    -------
    Plan
        ``FOUND`` with the moves; ``FUSE`` or ``NO_PATH`` with none.
    """
    if planner not in PLANNERS:
        raise ValueError(f"unknown planner {planner!r}; expected one of {PLANNERS}")
    goals = ({goal.slot: 0.0} if goal.slot is not None else {n: 0.0 for n in goal.exits})
    rra = heuristic or sg.reverse_search(goals)
    top = float(sg.levels[-1])
    goal_xy = np.array([sg.pose[n][:2] for n in goals])

    if planner == "ca":
        def h(n: int) -> float:
            x, y, _ = sg.pose[n]
            return float(np.min(np.hypot(goal_xy[:, 0] - x, goal_xy[:, 1] - y))) / top
        # the reverse search still runs, for the fuse and to prune dead ends
    else:
        h = rra

    exits = set(goal.exits)
    if rra(start) == math.inf:
        return Plan(Status.NO_PATH)

    # a car leaving its slot stands there first (other nodes' bodies are the graph's)
    start_stand = (Swept.of([(0.0, 0.0, standing_body(sg.vehicle, start_pose))])
                   if start_pose is not None else None)
    end = t0 + horizon

    # state: (node, level, time, outside); parents keyed by an integer id, each with the
    # step that led there (see moves_of), made into moves only for the plan found
    heap: list[tuple[float, float, int]] = []
    states: list[tuple[int, int, float, bool]] = []
    parent: list[tuple[int, tuple | None]] = []
    closed: set[tuple[int, bool, float]] = set()  # at rest: node, outside, free till
    passed: dict[tuple[int, int], float] = {}  # moving: (node, level) → last time expanded

    lim = sg.vehicle.limits
    # time lost reaching top speed from each level, and braking to rest before parking:
    # exact on long runs, an overestimate on the last few metres (plans are near-optimal)
    stop = top / (2 * lim.max_brake) if goal.slot is not None else 0.0
    loss = [(top - v) ** 2 / (2 * lim.max_accel * top) + stop for v in sg.levels]
    parked_until: dict[int, float] = {}  # park edge → till when its pose is taken [s]
    in_way: dict[int, list[tuple[float, float]]] = {}  # node → when standing there is not
    h_of: dict[int, float] = {}  # node → WEIGHT × its heuristic, inf: the goal out of reach
    inf = math.inf
    heappush, heappop = heapq.heappush, heapq.heappop

    def weighted(node: int) -> float:
        """WEIGHT × ``node``'s heuristic (inf where the goal is out of reach), kept."""
        hv = h(node)
        if h is not rra and hv != inf and rra(node) == inf:
            hv = inf
        wh = h_of[node] = WEIGHT * hv
        return wh

    def push(node: int, lvl: int, t: float, out: bool, par: int, step: tuple | None) -> None:
        if lvl:
            # a state passing a node soon after one already expanded there would be
            # dropped when popped (the times expanded at a node and level only grow)
            last = passed.get((node, lvl))
            if last is not None and t - last < PASSING:
                return
        wh = h_of.get(node)
        if wh is None:
            wh = weighted(node)
        if wh == inf:
            return
        states.append((node, lvl, t, out))
        parent.append((par, step))
        heappush(heap, (t + (wh + loss[lvl]), -t, len(states) - 1))  # ties: deepest

    def moves_of(step: tuple | None) -> tuple[Move, ...]:
        """The moves of a step: from ``node`` (at ``lvl``, at ``t``) along edge ``ei`` from
        time ``d`` (waiting there before, from rest, when ``d`` is later), to level ``b``."""
        if step is None:
            return ()
        kind, t, d, em, node, lvl, b, ei, out = step
        drive = Move(kind, d, d + em.duration, node, sg.edges[ei].v, lvl, b, ei, em.motion,
                     em.end)
        if d <= t:
            return (drive,)
        here = start_pose if node == start and start_pose is not None else sg.pose[node]
        wait = (Move("outside", t, d, node, node, 0, 0) if out else
                Move("wait", t, d, node, node, 0, 0, end_pose=here, steer=sg.steer[node]))
        return (wait, drive)

    def found(sid: int) -> Plan:
        moves: list[Move] = []
        while sid >= 0:
            sid, step = parent[sid]
            moves.extend(reversed(moves_of(step)))
        moves.reverse()
        return Plan(Status.FOUND, moves, expansions)

    push(start, level, t0, outside, -1, None)
    expansions = 0
    sized_by = rra.closed
    if shared and omega * sized_by > MIN_BUDGET:  # (otherwise the fuse is the same either way)
        sized_by = rra.closed_at(start)
    fuse = max(MIN_BUDGET, omega * sized_by)
    if budget is not None:
        fuse = min(fuse, budget)
    out_edges, edges, variants_kept, boxes = sg.out, sg.edges, sg._variants, sg._boxes
    cells_kept = sg._cells
    nearby, blocked, is_free = table.nearby, table.blocked, table.is_free
    blocked_standing = table.blocked_standing
    gathered: dict = {}  # what the table holds near each edge, by time buckets (see nearby)
    while heap:
        _, _, sid = heappop(heap)
        node, lvl, t, out = states[sid]
        if lvl == 0:
            # at rest: it may stand here until its body is first in someone's way (outside,
            # for ever); an earlier arrival within that same free stretch could have waited
            # till now, so the state is the node and the stretch's end (SIPP)
            if out:
                free_till = inf
            else:
                hit = in_way.get(node)
                if hit is None:  # once per node: the table does not change meanwhile
                    if node == start and start_stand is not None:
                        hit = blocked(start_stand, t0, end, ignore=owner)
                    else:  # (what the body meets kept with it, for the next searches)
                        hit = blocked_standing(sg.standing(node), t0, end, ignore=owner)
                    in_way[node] = hit
                free_till = _free_till(hit, t)
            # (standing where it is already in someone's way, it may only drive on)
            key = (node, out, free_till) if free_till > t else (node, out, t)
            if key in closed:
                continue
            closed.add(key)
        else:
            # passing at speed it cannot wait, so a later state is no worse in every way;
            # but one soon after an earlier is taken for it, or every way of stopping
            # before a queue and going on again would be searched (a plan that needs the
            # later one waits on the way instead, at rest)
            last = passed.get((node, lvl))
            if last is not None and t - last < PASSING:
                continue
            passed[node, lvl] = t
        expansions += 1
        if expansions > fuse:
            return Plan(Status.FUSE, expansions=expansions)
        if t > end:
            continue
        if not out and (node in exits or node == goal.slot):
            return found(sid)
        # from rest it departs when the way is free, waiting for it where it stands
        latest = min(free_till, end) if lvl == 0 else t
        for ei in out_edges[node]:
            e = edges[ei]
            ek = e.kind
            if ek == "leave" and (node != start or out or not same_pose(
                    sg.parked_pose(ei), start_pose)):
                continue
            if ek == "park" and (e.v != goal.slot or (
                    goal.park_by is not None and (e.stay or (node, e.v) not in goal.park_by))):
                continue
            if ek == "join":
                if not out:
                    push(e.v, lvl, t, out, sid, None)
                continue
            variants, longest = variants_kept.get((ei, lvl)) or sg.variants(ei, lvl)
            if not variants:
                continue
            cells = cells_kept.get(ei) or sg.edge_cells(ei, variants[0][1])
            # who is near the edge while any variant drives it (nobody: no exact test needed)
            near = nearby(cells, t, latest + longest, ignore=owner, memo=gathered)
            if near.ids:  # only those near what it sweeps (worked out only now: when needed)
                near = near.within(boxes.get((ei, lvl)) or sg.sweep_box(ei, lvl))
            kind = ek if ek in ("park", "leave") else "drive"
            for b, em in variants:
                after = -inf  # a parked vehicle must be able to stay for ever
                if ek == "park":
                    taken = parked_until.get(ei)
                    if taken is None:
                        taken = parked_until[ei] = table.taken_until(sg.parked_body(ei),
                                                                     ignore=owner)
                    after = taken - em.duration
                if lvl > 0 or latest <= t:
                    if t <= after or (near.ids and not is_free(em.swept, offset=t, among=near)):
                        continue
                    departs: list[float] | tuple[float] = (t,)
                else:
                    hit = blocked(em.swept, t, latest, among=near) if near.ids else []
                    if after >= t:
                        hit = _merged_with(hit, (-inf, after))
                    departs = _departures(hit, t, latest)
                v = e.v
                for d in departs:
                    # push(v, b, d + duration, False, sid, step) written out: the search's
                    # most frequent call (some 2 million pushes for 300 cars into the large lot)
                    tv = d + em.duration
                    if b:
                        last = passed.get((v, b))
                        if last is not None and tv - last < PASSING:
                            continue
                    wh = h_of.get(v)
                    if wh is None:
                        wh = weighted(v)
                    if wh == inf:
                        continue
                    states.append((v, b, tv, False))
                    parent.append((sid, (kind, t, d, em, node, lvl, b, ei, out)))
                    heappush(heap, (tv + (wh + loss[b]), -tv, len(states) - 1))
    return Plan(Status.NO_PATH, expansions=expansions)


def _free_till(in_way: list[tuple[float, float]], t: float) -> float:
    """Till when [s] a body standing from ``t`` [s] is free, given when it is in somebody's
    way (:meth:`~lotsim.traffic.reservation.ReservationTable.blocked` from any time up to
    ``t``): the start of the first stretch reaching past ``t`` — as from a query from
    ``t`` on, or, where the body is in the way at ``t`` already, a time before ``t`` both
    ways (a stretch that began before ``t`` may only have merged with earlier ones)."""
    return next((lo for lo, hi in in_way if hi >= t), math.inf)


def _departures(hit: list[tuple[float, float]], t: float, latest: float) -> list[float]:
    """The earliest time [s] of each stretch of ``[t, latest]`` (``latest`` itself
    excluded when it is after ``t``: the first instant the waiting body is in the way)
    outside the sorted, disjoint closed intervals ``hit``."""
    out = []
    d = t
    for lo, hi in hit:
        if hi < d:
            continue
        if lo > d:
            out.append(d)
        d = hi + DEPART_AFTER
        if d >= latest:
            return out
    if d < latest or d == t:
        out.append(d)
    return out


def _merged_with(hit: list[tuple[float, float]], extra: tuple[float, float]
                 ) -> list[tuple[float, float]]:
    """``hit`` (sorted, disjoint closed intervals) with ``extra`` added."""
    out: list[tuple[float, float]] = []
    for lo, hi in sorted([*hit, extra]):
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(hi, out[-1][1]))
        else:
            out.append((lo, hi))
    return out


def reserve_moves(table: ReservationTable, owner: str, sg: SearchGraph, moves: list[Move], *,
                  hold_end: bool) -> None:
    """Reserve everything ``moves`` sweep for ``owner``; with ``hold_end``, also the last
    pose from the end on, for ever (a parked car)."""
    slots = sg.slot_nodes
    for m in moves:
        if m.kind == "outside":
            continue
        if m.motion is None:
            table.reserve_standing(owner, standing_body(sg.vehicle, m.end_pose), m.t0, m.t1,
                                   in_slot=m.node_to in slots)
        else:
            em = sg.motion(m.edge, m.level_from, m.level_to)
            assert em is not None  # it was found by the search
            table.reserve(owner, em.swept, offset=m.t0)
    if hold_end and moves and moves[-1].end_pose is not None:
        table.reserve_standing(owner, standing_body(sg.vehicle, moves[-1].end_pose),
                               moves[-1].t1, in_slot=moves[-1].node_to in slots)
