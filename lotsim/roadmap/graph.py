"""The lot graph: a :class:`networkx.DiGraph` a car can actually drive.

Nodes are poses ``(x, y, theta)`` along the aisle lanes (integers, with
attributes ``pose``, ``kind``, ``lane``, ``station``), plus one node per slot.
Lane nodes carry the lane's ``curvature`` there [1/m] (0 on straights): a car
passing or standing at a node steers for it. Edges are pieces of path
(``path``, a tuple of :class:`~lotsim.core.geometry.Segment`) with ``length`` [m],
``gear`` (+1 forward, -1 reverse), ``speed_limit`` [m/s] and ``kind``:

* ``lane`` — along a lane: one straight, clothoid or arc of it;
* ``turn`` — a continuous-curvature turn (clothoid, arc, clothoid: a car
  turning its wheels at a steady rate as it rolls) from one aisle's lane into
  another's where the aisles meet, sized for a design speed
  (:data:`TURN_SPEEDS`); where that touches a corner slot, one that swings wide
  through the junction's area (:func:`_area_turns`). ``types`` names the vehicle
  types that can drive it (None: all; see :func:`build_graph`);
* ``join`` — a lane that continues as another (zero length);
* ``turnaround`` — a multi-point turn, driven from rest to rest, stopping at each cusp:
  at a dead end onto the opposite lane (:mod:`lotsim.roadmap.turnaround`), or where aisles
  meet in a junction too small for one turn, onto the other aisle's lane
  (:func:`_junction_multipoints`, :mod:`lotsim.roadmap.multipoint`), or a U-turn at a
  junction, turning in the crossing aisle's mouth back onto the opposite lane
  (:func:`_junction_uturns`);
* ``park`` / ``leave`` — from a lane node into a slot node and back, through
  real parking maneuvers: ``maneuvers`` maps each vehicle type that can use
  the link to its :class:`~lotsim.maneuvers.maneuver.Maneuver` (the leave edge
  holds them reversed), ``duration`` maps it to seconds, ``length`` is the
  shortest of them. A lane node sits exactly where each maneuver starts. A park
  edge's ``stays`` (with ``stay_duration`` and ``stay_limit``) holds, per type,
  the lane's own best maneuver where the one in ``maneuvers`` parks the other
  way round so that the car can leave towards every lane: a car that will not
  leave may park with it (it has no leave edge). Built without maneuvers, the
  graph has ``placeholder=True`` links abeam of each
  slot instead, with no geometry (enough to draw and check reachability).

Every edge's geometry but a turnaround's is tangent- and curvature-continuous with
its nodes' headings and curvatures, and every turn, turnaround and lane is swept
with the design vehicle (a turn: with each type it is for) against slots, areas
and the boundary before it is added.
"""

from __future__ import annotations

import contextlib
import itertools
import math
import weakref
from collections import Counter
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import shapely

from lotsim.core.geometry import (
    Segment,
    cc_polyline,
    cc_turn,
    same_pose,
    sample_segments,
    wrap_angle,
)
from lotsim.core.workers import Background, fork_map
from lotsim.errors import ScenarioError
from lotsim.lot.build import SWEEP_STEP, lane_collider
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle, Lane, Lot, Portal, Slot, unit
from lotsim.roadmap.multipoint import plan_onto, segment_to_world, to_local
from lotsim.roadmap.turnaround import STARTS as TURNAROUND_STARTS
from lotsim.roadmap.turnaround import (
    Turnaround,
    plan_turnarounds,
    turnaround_clear,
    turnaround_collider,
)

if TYPE_CHECKING:
    import networkx as nx

TURN_SPEEDS = tuple(k / 3.6 for k in (15.0, 12.5, 10.0, 7.5, 5.0, 3.0, 1.5))
"""Design speeds junction turns try, fastest first [m/s]: a turn for speed ``v`` has an arc
of radius ``max(R, v² / a_lat)`` (or 2 R or 3 R, when wider) and clothoids every type can
steer at ``v``; the fastest and the tightest that are clear of everything are built."""
_EPS = 1e-6


@dataclass(frozen=True, slots=True)
class Turn:
    """A junction turn from ``lane_a`` at ``station_a`` into ``lane_b`` at ``station_b``."""

    lane_a: str
    station_a: float
    lane_b: str
    station_b: float
    segments: tuple[Segment, ...]
    wide: bool = False  # it uses the junction's area (:func:`_area_turns`)


@dataclass(frozen=True, slots=True)
class Reachability:
    """What cannot be driven to.

    ``unreachable[entrance]`` lists the free slots that cannot be reached from
    that entrance; ``stranded[exit]`` the free slots from which that exit cannot
    be reached (a lot with several gates may serve each slot from some of them).
    ``no_way_in`` lists the free slots no entrance reaches; ``no_way_out`` those
    that can be parked in only from where no exit can be reached (empty when
    the lot has no exits). The lot is good (``ok``) when both are empty.
    """

    unreachable: dict[str, list[str]]
    stranded: dict[str, list[str]]
    no_way_in: list[str] = field(default_factory=list)
    no_way_out: list[str] = field(default_factory=list)
    by_type: dict[str, tuple[list[str], list[str]]] = field(default_factory=dict)
    """Vehicle type → (``no_way_in``, ``no_way_out``) for that type's own turns, among the
    free slots it has a parking maneuver for (a type that fits a slot must reach and leave
    it); empty when the graph has no maneuvers."""

    @property
    def ok(self) -> bool:
        return (not self.no_way_in and not self.no_way_out
                and not any(a or b for a, b in self.by_type.values()))


@dataclass(frozen=True, slots=True)
class GraphFacts:
    """What ``lotsim validate`` says of a lot graph and checks traffic against, counted
    once and kept with the lot (in the on-disk cache too: a warm ``validate`` does not
    load the graph's library to read them)."""

    nodes: int
    edges: int
    kinds: dict[str, int]
    """Edges by kind (lane, turn, turnaround, join, park, leave)."""
    park_maneuvers: int
    """Parking maneuvers kept on park edges, one a type."""
    parks: frozenset[str]
    """The vehicle types with a parking maneuver into some slot."""
    leavable: bool
    """Some slot can be left for an exit along the lanes (:meth:`LotGraph.leavable`)."""


@dataclass
class LotGraph:
    """A lot with its drivable graph.

    Attributes
    ----------
    lot : Lot
    graph : networkx.DiGraph
    entrances, exits : dict
        Portal id → node.
    slot_nodes : dict
        Slot id → slot node.
    attachments : dict
        Slot id → lane nodes where its parking maneuver begins.
    skipped_turns : list of str
        Junction turns that no radius could make collision-free, with the reason.
    infeasible : dict
        Vehicle type → {slot id: reason} for slots that type cannot park in.
    maneuver_planner : ManeuverPlanner or None
        The planner (and its cache) the maneuvers came from.
    from_cache : bool
        Whether :func:`~lotsim.sim.preparation.prepare` loaded it from the on-disk cache
        (:mod:`lotsim.core.diskcache`) rather than planning it.
    kept : dict
        What planners work out from the lot alone and keep with it for the next runs in
        this process (the search graph of each vehicle type, with its edge motions:
        :func:`~lotsim.traffic.search.search_graph`). Not pickled.
    """

    lot: Lot
    graph: nx.DiGraph
    entrances: dict[str, int]
    exits: dict[str, int]
    slot_nodes: dict[str, int]
    attachments: dict[str, list[int]] = field(default_factory=dict)
    skipped_turns: list[str] = field(default_factory=list)
    infeasible: dict[str, dict[str, str]] = field(default_factory=dict)
    maneuver_planner: object = None
    from_cache: bool = False
    _reach: Reachability | None = field(default=None, repr=False, compare=False)
    _facts: GraphFacts | None = field(default=None, repr=False, compare=False)
    kept: dict = field(default_factory=dict, repr=False, compare=False)

    def __getstate__(self) -> dict:
        # the graph as its plain dicts (nodes, successors, predecessors, each edge's data
        # dict shared by the two, in their order), not as a networkx object: loading a lot
        # imports networkx only when the graph itself is asked for (:meth:`__getattr__`)
        state = {k: v for k, v in self.__dict__.items() if k not in ("kept", "graph")}
        g = self.__dict__.get("graph")
        if g is not None:
            state["_graph_dicts"] = (g.graph, g._node, g._succ, g._pred)
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self.kept = {}

    def __getattr__(self, name: str):
        # only for attributes not set: the graph of a lot loaded by pickle, made on first use
        dicts = self.__dict__.get("_graph_dicts")
        if name != "graph" or dicts is None:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        import networkx as nx

        g = nx.DiGraph()
        g.graph.update(dicts[0])
        g._node, g._succ, g._pred = dicts[1:]
        g._adj = g._succ
        self.graph = g
        del self._graph_dicts
        return g

    def facts(self) -> GraphFacts:
        """The graph's counts and what traffic is checked against (worked out once and
        kept, in the on-disk cache too)."""
        if self._facts is None:
            edges = [d for _, _, d in self.graph.edges(data=True)]
            parks = [d for d in edges if d["kind"] == "park"]
            self._facts = GraphFacts(
                self.graph.number_of_nodes(), len(edges),
                dict(Counter(d["kind"] for d in edges)),
                sum(len(d["maneuvers"]) for d in parks),
                frozenset(name for d in parks for name in d.get("maneuvers", {})),
                next(self._leavable(None), None) is not None)
        return self._facts

    def _lane_reach(self, vehicle: str | None = None) -> tuple[set[int], set[int]]:
        """Lane nodes reachable from an entrance, and lane nodes that reach an exit (any,
        when the lot has no exits), driving lanes, turns, joins and turnarounds only — never
        through a slot (a car does not turn round in someone's parking space); with
        ``vehicle``, only by the turns that type can make."""
        ahead, back = self._lanes(vehicle)
        come = _spread(ahead, self.entrances.values())
        go = _spread(back, self.exits.values()) if self.exits else set(ahead)
        return come, go

    def _lanes(self, vehicle: str | None = None) -> tuple[dict[int, list[int]],
                                                           dict[int, list[int]]]:
        """Successors and predecessors of each node in the graph without its slot nodes:
        what a car drives between entering and parking (with ``vehicle``, without the turns
        that type cannot make)."""
        nodes = self.graph.nodes
        ahead: dict[int, list[int]] = {}
        back: dict[int, list[int]] = {}
        for u, nbrs in self.graph.adj.items():
            if nodes[u]["kind"] == "slot":
                continue
            ahead.setdefault(u, [])
            back.setdefault(u, [])
            for v, d in nbrs.items():
                if nodes[v]["kind"] == "slot" or (
                        vehicle is not None and d.get("types") is not None
                        and vehicle not in d["types"]):
                    continue
                ahead[u].append(v)
                back.setdefault(v, []).append(u)
        return ahead, back

    def reachable(self) -> dict[str, tuple[float, float]]:
        """Per lane, the station range [m] of the nodes a car can reach from an entrance
        (driving lanes only): where a parking maneuver may start."""
        come, _ = self._lane_reach()
        return self._ranges(come)

    def maneuver_ranges(self) -> dict[str, tuple[tuple[float, float], ...]]:
        """Per lane, the station ranges [m] where a parking maneuver may begin (or a leaving
        one end): that of the nodes a car can reach from an entrance (driving lanes only),
        and, where it does not overlap that one, that of the nodes from which an exit can be
        reached — a car parked from one lane may leave towards another that it could not
        have come along (out of a dead end it cannot turn round in), or along a stretch it
        could not have come to (the lane's start, on a short arm that a car enters only
        near its end). Each slot's maneuver is planned in the range nearest it
        (:class:`~lotsim.maneuvers.planner.ManeuverPlanner`); the two are not joined into
        one, which would reach into the stretch between them where no car comes or leaves
        by."""
        come, go = self._lane_reach()
        reach, leave = self._ranges(come), self._ranges(go)
        out: dict[str, tuple[tuple[float, float], ...]] = {}
        for lid in {**leave, **reach}:
            spans = [reach[lid]] if lid in reach else []
            lo, hi = leave.get(lid, (math.inf, -math.inf))
            if lo <= hi and not any(lo <= b and a <= hi for a, b in spans):
                spans.append((lo, hi))
            out[lid] = tuple(spans)
        return out

    def leave_nodes(self, vehicle: str | None = None) -> frozenset[int]:
        """Lane nodes from which an exit can be reached (all, when the lot has no exits),
        by a ``vehicle`` type's turns if given: a car that will leave again parks only from
        these."""
        return frozenset(self._lane_reach(vehicle)[1])

    def leavable(self, vehicle: str | None = None) -> frozenset[tuple[int, int]]:
        """Park edges ``(lane node, slot node)`` a car that will leave again may park by: its
        maneuver (for ``vehicle``, or for any type) parks it on a pose a leave edge of the
        same type leaves from towards a lane node from which an exit can be reached (any,
        when the lot has no exits). The leave edge need not end where the park edge began: a
        slot parked on one pose from two lanes is left towards either."""
        return frozenset(self._leavable(vehicle))

    def _leavable(self, vehicle: str | None):
        """:meth:`leavable`'s park edges as found, slot by slot (some more than once)."""
        g = self.graph
        go = self._lane_reach(vehicle)[1]
        for node in self.slot_nodes.values():
            leaves = [d for _, w, d in g.out_edges(node, data=True)
                      if d["kind"] == "leave" and w in go]
            away = [(name, m.start) for d in leaves for name, m in d["maneuvers"].items()
                    if vehicle in (None, name)]
            placeholder = any(d.get("placeholder") for d in leaves)  # no poses: any way out
            for u, _, d in g.in_edges(node, data=True):
                if d["kind"] == "park" and ((placeholder and d.get("placeholder")) or any(
                        same_pose(m.end, pose) for name, m in d["maneuvers"].items()
                        for who, pose in away if who == name)):
                    yield u, node

    def _ranges(self, nodes: set[int]) -> dict[str, tuple[float, float]]:
        g = self.graph
        out: dict[str, tuple[float, float]] = {}
        for n in nodes:
            data = g.nodes[n]
            lo, hi = out.get(data["lane"], (math.inf, -math.inf))
            out[data["lane"]] = (min(lo, data["station"]), max(hi, data["station"]))
        return out

    def reachability(self) -> Reachability:
        """Free slots unreachable from each entrance, free slots that cannot reach each
        exit, and free slots that no entrance reaches or that can be parked in only where no
        exit can be reached (driving lanes, turns, joins and turnarounds, into the slot or out
        of it at the end). Cars parked at start never move, so taken slots are not listed.

        Worked out once (the graph does not change) and kept, in the on-disk cache too."""
        if self._reach is None:
            self._reach = self._reachability()
        return self._reach

    def _reachability(self) -> Reachability:
        g = self.graph
        free = [s.id for s in self.lot.free_slots]
        ahead, back = self._lanes()

        def missing(seen: set[int], links) -> list[str]:
            return [sid for sid in free if not any(n in seen for n in links(self.slot_nodes[sid]))]

        unreachable = {name: missing(_spread(ahead, [node]), g.predecessors)
                       for name, node in self.entrances.items()}
        stranded = {name: missing(_spread(back, [node]), g.successors)
                    for name, node in self.exits.items()}
        come, go = self._lane_reach()
        no_way_in = missing(come, g.predecessors)
        def parks_to_leave(out: frozenset[tuple[int, int]], seen: set[int], sid: str) -> bool:
            """Whether a car coming to a node of ``seen`` parks in ``sid`` by a park edge
            in ``out`` (:meth:`leavable`: it leaves from that pose towards an exit)."""
            node = self.slot_nodes[sid]
            return any(u in seen and (u, node) in out for u in g.predecessors(node))

        # a car leaves from the pose it parked on, by any leave edge from there
        out = self.leavable()
        no_way_out = [sid for sid in free
                      if sid not in no_way_in and not parks_to_leave(out, come, sid)]
        by_type = {}
        for name in sorted({v for _, _, d in g.edges(data=True) if d["kind"] == "park"
                            for v in d["maneuvers"]}):
            come, go = self._lane_reach(name)
            fits = {sid for sid in free if any(
                name in g.edges[u, self.slot_nodes[sid]]["maneuvers"]
                for u in g.predecessors(self.slot_nodes[sid]))}

            def parks_from(seen: set[int], sid: str, name: str = name) -> bool:
                node = self.slot_nodes[sid]
                return any(u in seen and name in g.edges[u, node]["maneuvers"]
                           for u in g.predecessors(node))

            no_in = [sid for sid in free if sid in fits and not parks_from(come, sid)]
            out = self.leavable(name)  # only park edges with a maneuver for this type
            no_out = [sid for sid in free if sid in fits and sid not in no_in
                      and not parks_to_leave(out, come, sid)]
            by_type[name] = (no_in, no_out)
        return Reachability(unreachable, stranded, no_way_in, no_way_out, by_type)


def _spread(links: dict[int, list[int]], sources) -> set[int]:
    """``sources`` and every node reached from them by ``links`` (node → next nodes)."""
    seen = set(sources)
    todo = list(seen)
    while todo:
        for n in links.get(todo.pop(), ()):
            if n not in seen:
                seen.add(n)
                todo.append(n)
    return seen


def build_graph(lot: Lot, *, node_spacing: float = 4.0, maneuvers=None,
                vehicles=(), stays=None) -> LotGraph:
    """Build the drivable graph of ``lot``.

    Parameters
    ----------
    lot : Lot
    node_spacing : float, keyword-only
        Largest distance between consecutive nodes along a lane [m].
    maneuvers : dict or None, keyword-only
        ``(vehicle name, slot id, lane id)`` → parking Maneuver, from
        :func:`lotsim.maneuvers.batch.plan_lot`; ``None`` links slots by placeholders.
    vehicles : sequence of VehicleType, keyword-only
        The scenario's types: the maneuvers' durations; with two or more, junction turns
        are built for each type's own outline and turning radius, and a turn only some
        types can drive says which (edge attribute ``types``, None for all).

    Returns
    -------
    LotGraph
    """
    lanes = {lane.id: lane for lane in lot.lanes}
    collider = lane_collider(lot)
    designs = _designs_of(vehicles)
    tagged, skipped = _turns_of(lot, collider, designs)
    # turns for more types first: two that join the same nodes keep the one more can drive
    tagged.sort(key=lambda c: -len(designs or ()) if c[1] is None else -len(c[1]))
    turns = [t for t, _ in tagged]
    joins = _joins(lot)
    exits = {}
    for p in lot.exits:
        lid, st = _portal_station(lot, p)
        exits[lid] = max(exits.get(lid, -math.inf), st)
    multis, uturns = _junction_backs(lot, tagged, designs, exits)
    stays = {} if maneuvers is None else (stays or {})
    attach = (_attachments(lot) if maneuvers is None
              else _maneuver_attachments(lot, [*maneuvers.items(), *stays.items()]))
    stops: dict[str, float] = {}  # per lane, the last station a car parks or unparks at
    for links in attach.values():
        for lid, st in links:
            stops[lid] = max(stops.get(lid, -math.inf), st)
    backs, no_back = _turnarounds_of(lot, turns, joins, exits, designs, stops,
                                     [t for t, _ in multis])
    backs += multis + uturns
    # turnarounds for more types first: two that join the same nodes keep the one more can
    # drive
    backs.sort(key=lambda c: -len(designs or ()) if c[1] is None else -len(c[1]))
    skipped += no_back

    stations: dict[str, list[float]] = {lid: [0.0, lane.length] for lid, lane in lanes.items()}
    for lid, lane in lanes.items():
        stations[lid] += [float(s) for s in lane.starts]
        stations[lid] += _zone_crossings(lot, lane)
    for t in (*turns, *(t for t, _ in backs)):
        stations[t.lane_a].append(t.station_a)
        stations[t.lane_b].append(t.station_b)
    portals = {p: _portal_station(lot, p) for p in (*lot.entrances, *lot.exits)}
    for lid, s in portals.values():
        stations[lid].append(s)
    for links in attach.values():
        for lid, s in links:
            stations[lid].append(s)

    import networkx as nx  # (here: a lot loaded from the cache may never need it)

    g = nx.DiGraph()
    index: dict[str, np.ndarray] = {}
    first: dict[str, int] = {}
    for lid, lane in lanes.items():
        st = _spaced(np.array(stations[lid]), lane.length, node_spacing)
        index[lid] = st
        first[lid] = g.number_of_nodes()
        for k, s in enumerate(st):
            g.add_node(first[lid] + k, pose=lane.pose_at(float(s)), kind="lane", lane=lid,
                       station=float(s), curvature=lane.curvature_at(float(s)))
        for k in range(len(st) - 1):
            seg = _lane_piece(lane, float(st[k]), float(st[k + 1]))
            _add_edge(g, lot, first[lid] + k, first[lid] + k + 1, (seg,), "lane")

    def node_at(lid: str, s: float) -> int:
        st = index[lid]
        k = int(np.argmin(np.abs(st - s)))
        return first[lid] + k

    for t, types in tagged:
        u, v = node_at(t.lane_a, t.station_a), node_at(t.lane_b, t.station_b)
        if not g.has_edge(u, v):
            _add_edge(g, lot, u, v, t.segments, "turn")
            g.edges[u, v]["types"] = types
    for t, types in backs:
        u, v = node_at(t.lane_a, t.station_a), node_at(t.lane_b, t.station_b)
        if not g.has_edge(u, v):
            _add_edge(g, lot, u, v, t.segments, "turnaround")
            g.edges[u, v]["types"] = types
    for a, b in joins:
        g.add_edge(node_at(a, lanes[a].length), node_at(b, 0.0), kind="join", length=0.0,
                   gear=1, path=None, speed_limit=lot.speed_limit, placeholder=False)

    entrances = {p.id: node_at(*portals[p]) for p in lot.entrances}
    exits = {p.id: node_at(*portals[p]) for p in lot.exits}
    for name, node in entrances.items():
        g.nodes[node]["entrance"] = name
    for name, node in exits.items():
        g.nodes[node]["exit"] = name

    slot_nodes: dict[str, int] = {}
    attachments: dict[str, list[int]] = {}
    for slot in lot.slots:
        node = g.number_of_nodes()
        slot_nodes[slot.id] = node
        cx, cy = slot.center
        g.add_node(node, pose=(cx, cy, slot.heading), kind="slot", slot=slot.id,
                   occupied=slot.id in lot.occupied, curvature=0.0)
        attachments[slot.id] = []
        if maneuvers is None:
            for lid, s in attach[slot.id]:
                _add_placeholder(g, lot, node_at(lid, s), node, slot)
                attachments[slot.id].append(node_at(lid, s))
    if maneuvers is not None:
        types = {v.name: v for v in vehicles}

        def shape(path, vname: str, limit: float) -> tuple:
            """What the maneuver's time depends on: its pieces' shapes, not where they lie."""
            return vname, limit, tuple((s.distance, s.curvature, s.sharpness)
                                       for s in path.segments)

        leaving = {key: m.reversed() for key, m in maneuvers.items()}  # each way out
        # a lot's maneuvers repeat a few shapes: each timed once, on both cores
        todo: dict[tuple, tuple] = {}
        for kept, both in ((maneuvers, True), (stays, False)):
            for key, m in kept.items():
                if key[0] in types:
                    limit = _path_limit(lot, m)
                    for path in (m, leaving[key]) if both else (m,):
                        todo.setdefault(shape(path, key[0], limit), (path, key[0], limit))
        jobs = list(todo.values())
        parts = [jobs[k::8] for k in range(8)] if len(jobs) >= 64 else [jobs]
        times = fork_map(lambda part: [p.duration(types[v], lim) for p, v, lim in part], parts)
        timed = {shape(*job): t for part, ts in zip(parts, times, strict=True)
                 for job, t in zip(part, ts, strict=True)}

        def duration(path, vname: str, limit: float) -> float:
            return timed[shape(path, vname, limit)]

        for (vname, sid, lid), m in sorted(maneuvers.items(), key=lambda kv: kv[0]):
            a, node = node_at(lid, m.station), slot_nodes[sid]
            if a not in attachments[sid]:
                attachments[sid].append(a)
            limit = _path_limit(lot, m)
            back = leaving[vname, sid, lid]
            for u, v, kind, path in ((a, node, "park", m), (node, a, "leave", back)):
                e = _link(g, u, v, kind, path, limit)
                e["maneuvers"][vname] = path
                if vname in types:
                    e["duration"][vname] = duration(path, vname, limit)
                e["length"] = min(e["length"], path.length)
        for (vname, sid, lid), m in sorted(stays.items(), key=lambda kv: kv[0]):
            a, node = node_at(lid, m.station), slot_nodes[sid]
            limit = _path_limit(lot, m)
            e = _link(g, a, node, "park", m, limit)
            e.setdefault("stays", {})[vname] = m
            e["stay_limit"] = min(e.get("stay_limit", math.inf), limit)
            if vname in types:
                e.setdefault("stay_duration", {})[vname] = duration(m, vname, limit)
            e["length"] = min(e["length"], m.length)
    return LotGraph(lot, g, entrances, exits, slot_nodes, attachments, skipped)


# -- helpers -----------------------------------------------------------------------------------
def _link(g: nx.DiGraph, u: int, v: int, kind: str, path, limit: float) -> dict:
    """The park or leave edge ``u`` → ``v``'s attributes, made (with no maneuver yet) if
    new."""
    if not g.has_edge(u, v):
        g.add_edge(u, v, kind=kind, maneuvers={}, duration={}, length=math.inf,
                   gear=path.segments[0].gear, path=None, speed_limit=limit,
                   placeholder=False)
    return g.edges[u, v]


def _add_placeholder(g: nx.DiGraph, lot: Lot, a: int, node: int, slot: Slot) -> None:
    ax, ay, _ = g.nodes[a]["pose"]
    cx, cy = slot.center
    reach = math.hypot(cx - ax, cy - ay)
    gear = 1 if slot.kind == "angled" else -1
    for u, v, kind in ((a, node, "park"), (node, a, "leave")):
        g.add_edge(u, v, kind=kind, length=reach, gear=gear if kind == "park" else -gear,
                   path=None, speed_limit=lot.speed_limit, placeholder=True,
                   maneuvers={}, duration={})


def _maneuver_attachments(lot: Lot, maneuvers) -> dict[str, list[tuple[str, float]]]:
    """Lane and station where each planned maneuver starts (``maneuvers``: pairs of
    ``(vehicle name, slot id, lane id)`` and Maneuver)."""
    out: dict[str, list[tuple[str, float]]] = {s.id: [] for s in lot.slots}
    for (_, sid, lid), m in maneuvers:
        out[sid].append((lid, m.station))
    return out


def _spaced(stations: np.ndarray, length: float, spacing: float) -> np.ndarray:
    """Sorted unique stations within [0, length], with extra ones so no gap exceeds spacing."""
    st = np.unique(np.clip(stations, 0.0, length))
    st = st[np.concatenate([[True], np.diff(st) > _EPS])]
    out = [st[:1]]
    for a, b in zip(st[:-1], st[1:], strict=True):
        n = max(1, math.ceil((b - a) / spacing - 1e-9))
        out.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(out)


def _lane_piece(lane: Lane, s0: float, s1: float) -> Segment:
    i, d0 = lane.locate(s0)
    seg = lane.segments[i]
    # A piece ending exactly on the next segment's start still belongs to segment i.
    d1 = min(s1 - float(lane.starts[i]), seg.length)
    return seg.piece(d0, d1)


def _path_limit(lot: Lot, path) -> float:
    """Speed limit along ``path`` (segments, or a maneuver): the lowest zone it runs in
    [m/s] (:func:`_zone_limit` of points 0.25 m apart; the lot's limit, unsampled, when the
    lot has no zones)."""
    if not lot.zones:
        return lot.speed_limit
    points = path.sample(0.25)[0] if hasattr(path, "sample") else sample_segments(path, 0.25)[0]
    return _zone_limit(lot, points[:, :2])


def _zone_limit(lot: Lot, points: np.ndarray) -> float:
    """Speed limit along a path through ``points`` (N, 2): the lowest zone it runs in [m/s]."""
    limit = lot.speed_limit
    line = shapely.LineString(points) if lot.zones else None
    for zone in lot.zones:
        if zone.polygon.intersects(line) and zone.polygon.intersection(line).length > _EPS:
            limit = min(limit, zone.limit)
    return limit


def _add_edge(g: nx.DiGraph, lot: Lot, u: int, v: int, path: tuple[Segment, ...],
              kind: str) -> None:
    g.add_edge(u, v, kind=kind, length=sum(s.length for s in path), gear=path[0].gear,
               path=path, speed_limit=_path_limit(lot, path),
               placeholder=False)


def _zone_crossings(lot: Lot, lane: Lane) -> list[float]:
    """Stations where the lane enters or leaves a speed zone, so limits change at nodes."""
    out: list[float] = []
    for zone in lot.zones:
        cut = lane.line.intersection(zone.polygon.boundary)
        if cut.is_empty:
            continue
        pts = shapely.get_coordinates(cut)
        out += [float(lane.line.project(shapely.Point(p))) for p in pts]
    return out


PORTAL_HEADING_TOLERANCE = math.radians(15)
"""How far a portal's heading may differ from its lane's there [rad]: the car stands on
the lane, heading its way; more is refused rather than turned without a word."""


def _portal_station(lot: Lot, portal: Portal) -> tuple[str, float]:
    """The lane (and station on it) a portal pose stands on: nearest lane heading its way."""
    pose = portal.pose
    best = None
    near = None  # the nearest lane the portal stands on, whichever way it heads
    for aisle in lot.aisles.values():
        for lane in aisle.lanes:
            s, dist = lane.project(pose[:2])
            if dist > aisle.width / 2 + 0.01:
                continue
            heading = lane.pose_at(s)[2]
            off = abs(wrap_angle(heading - pose[2]))
            if near is None or (off, dist) < near[:2]:
                near = (off, dist, lane.id, heading)
            if off <= PORTAL_HEADING_TOLERANCE and (best is None or dist < best[0]):
                best = (dist, lane.id, s)
    if best is None:
        there = (f"; lane {near[2]!r} there heads {math.degrees(near[3]) % 360:.0f}° (give "
                 f"heading_deg within {math.degrees(PORTAL_HEADING_TOLERANCE):.0f}° of it)"
                 if near is not None else "")
        raise ScenarioError(
            portal.where,
            f"{portal.id!r} at ({pose[0]:g}, {pose[1]:g}) heading "
            f"{math.degrees(pose[2]):.0f}° is on no lane driven that way{there}",
        )
    lane = next(ln for ln in lot.lanes if ln.id == best[1])
    body = shapely.Polygon(lot.design.footprints(np.array([lane.pose_at(best[2])]))[0])
    out = body.difference(lot.boundary).area
    if out > 1e-6:
        raise ScenarioError(
            portal.where,
            f"a car standing at {portal.id!r} sticks out of the lot boundary "
            f"({out:.2f} m²); cars appear and vanish at portals, so move it inward",
        )
    return best[1], best[2]


def _attachments(lot: Lot) -> dict[str, list[tuple[str, float]]]:
    """Lane and station where each slot's parking maneuver begins (placeholder: abeam)."""
    out: dict[str, list[tuple[str, float]]] = {}
    for slot in lot.slots:
        aisle = lot.aisles[slot.aisle]
        mid = slot.entry.mean(axis=0)
        links = []
        for lane in aisle.lanes:
            s, _ = lane.project((float(mid[0]), float(mid[1])))
            if lane_serves(lane, s, slot):
                links.append((lane.id, s))
        out[slot.id] = links
    return out


def lane_serves(lane: Lane, station: float, slot: Slot) -> bool:
    """Whether a car on ``lane`` can begin this slot's maneuver: by kind and direction."""
    if slot.kind == "perpendicular":
        return True
    heading = lane.pose_at(station)[2]
    return float(np.dot(unit(heading), unit(slot.heading))) > 1e-9


def _joins(lot: Lot) -> list[tuple[str, str]]:
    """Pairs of lanes where one ends exactly where the next begins, heading the same way."""
    lanes = lot.lanes
    ends = [(lane, lane.pose_at(lane.length)) for lane in lanes]
    out = []
    for a, (x, y, t) in ends:
        for b in lanes:
            if b.aisle == a.aisle:
                continue
            bx, by, bt = b.pose_at(0.0)
            if math.hypot(bx - x, by - y) < 0.05 and abs(wrap_angle(bt - t)) < math.radians(1):
                out.append((a.id, b.id))
    return out


def _straights(lane: Lane) -> list[tuple[float, Segment]]:
    return [(float(s0), seg) for s0, seg in zip(lane.starts, lane.segments, strict=True)
            if seg.curvature == 0.0 and seg.sharpness == 0.0]


_TURNS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _types_key(designs: dict[str, DesignVehicle] | None) -> tuple | None:
    """What the per-lot caches of this module key a set of vehicle types by (None: the
    lot's design vehicle for every type)."""
    return tuple(sorted(designs.items())) if designs else None


def _turns_of(lot: Lot, collider: Collider, designs: dict[str, DesignVehicle] | None = None
              ) -> tuple[list[tuple[Turn, frozenset | None]], list[str]]:
    """The lot's junction turns (:func:`_junction_turns`, :func:`_through_turns`), each with
    the vehicle types that can drive it (None: every type), and the reasons of those
    skipped; worked out once per lot and set of types.

    With ``designs`` (vehicle type → its own outline and limits, for two types or more)
    turns are built for each type on its own — a small car turns where the envelope of all
    the types could not — and a turn built for several types is kept once; without, for
    the lot's design vehicle (the envelope), for every type.
    """
    key = _types_key(designs)
    cache = _TURNS.setdefault(lot, {})
    if key not in cache:
        per = _turns_per_design(lot, collider, list(designs.values()) if designs else [None])
        if not designs:
            turns, skipped = per[0]
            cache[key] = ([(t, None) for t in turns], skipped)
        else:
            found: dict[Turn, None] = {}
            why: dict[str, list[str]] = {}
            for name, (turns, skipped) in zip(designs, per, strict=True):
                found.update(dict.fromkeys(turns))
                for reason in skipped:
                    why.setdefault(reason, []).append(name)
            # every turn for every type it suits: no tighter than its radius, swept clear
            tagged: dict[Turn, set[str]] = {}
            for t in found:
                poses = sample_segments(t.segments, SWEEP_STEP)[0]
                bend = max(seg.max_curvature for seg in t.segments)
                for name, design in designs.items():
                    if bend <= 1 / design.min_radius + 1e-9 and collider.sweep_hit(
                            design.footprints(poses)) is None:
                        tagged.setdefault(t, set()).add(name)
            every = len(designs)
            notes = [reason if len(names) == every else f"{reason} (for {', '.join(names)})"
                     for reason, names in why.items()]
            cache[key] = ([(t, None if len(n) == every else frozenset(n))
                           for t, n in tagged.items()], notes)
    turns, skipped = cache[key]
    return list(turns), list(skipped)


def _turns_per_design(lot: Lot, collider: Collider, designs: list
                      ) -> list[tuple[list[Turn], list[str]]]:
    """:func:`_junction_turns` and :func:`_through_turns` for each of ``designs`` (None: the
    lot's design vehicle), as each would find them on its own: the junction turns out of
    each lane, then each design's turns through short stretches, on both cores
    (:func:`~lotsim.core.workers.fork_map`; the same answers in the same order)."""
    jobs = [(design, a) for design in designs for a in lot.lanes]
    found = fork_map(lambda job: _junction_turns(lot, collider, job[0], lanes_a=(job[1],)),
                     jobs)
    per = []
    for k in range(len(designs)):
        mine = found[k * len(lot.lanes):(k + 1) * len(lot.lanes)]
        per.append(([t for turns, _ in mine for t in turns], [r for _, why in mine for r in why]))
    # then each design's turns through short stretches, a stretch a task (a large type's
    # take longest)
    chains = [(k, chain) for k in range(len(designs)) for chain in _through_chains(lot, per[k][0])]
    got = fork_map(lambda job: _through_turn(lot, collider, designs[job[0]], job[1]), chains)
    through: list[list[Turn]] = [[] for _ in designs]
    for (k, _), turns in zip(chains, got, strict=True):
        through[k] += turns
    return [(turns + extra, why) for (turns, why), extra in zip(per, through, strict=True)]


DEAD_END = 15.0
"""A lane whose last turn off it begins more than this before its end [m], and which does
not continue as another, ends in a dead end: a car turns round there (a turnaround); so
does one a car parks or unparks on past its last turn (:func:`_turnarounds_of`)."""
_BACKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # lot → {(types, ends): result}
_BACK_PLANS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # lot → {(lane, design): plan}


def _turnarounds_of(lot: Lot, turns: list[Turn], joins: list[tuple[str, str]],
                    exits: dict[str, float], designs: dict[str, DesignVehicle] | None = None,
                    stops: dict[str, float] | None = None, multis: list[Turnaround] = ()
                    ) -> tuple[list[tuple[Turnaround, frozenset | None]], list[str]]:
    """Turnarounds at the dead ends of two-way aisles, each with the vehicle types that can
    drive it (None: every type), and a note for each dead end where none fits (naming the
    types, when only some have none); each planned once per lot, lane and type.

    A lane that does not continue as another ends in a dead end when its last turn off it
    begins more than :data:`DEAD_END` before its end and it leads to no exit past that turn,
    or when a car parks or unparks on it past its last turn and exit (``stops``: lane → the
    last such station; a corner bay): a car there could not get on otherwise. ``exits`` maps a
    lane to its last exit's station.

    With ``designs`` (vehicle type → its own outline and limits, for two types or more)
    turnarounds are planned for each type on its own — a small car turns round where the
    envelope of all the types, or a van that fits no bay, could not — and each is tagged
    with every type it suits: no tighter than its radius, clear for its body and margin.

    Where every turnaround found lands past the last place the opposite lane can be left
    (a turn off it, an exit, its continuation), or begins before where a car arrives on the
    lane (a turn or a multi-point junction turn, ``multis``, landing near its end, or a
    car unparking onto it: ``stops``), one is also looked for by multi-point search
    (:func:`_reaching_turnarounds`).
    """
    stops = stops or {}
    last = {lane.id: exits.get(lane.id, -math.inf) + DEAD_END for lane in lot.lanes}
    turned = {lane.id: exits.get(lane.id, -math.inf) for lane in lot.lanes}  # last way off
    for t in turns:
        last[t.lane_a] = max(last[t.lane_a], t.station_a)
        turned[t.lane_a] = max(turned[t.lane_a], t.station_a)
    joined = {a for a, _ in joins}
    ends = [(lane, back) for lane, back in _two_way_lanes(lot)
            if lane.id not in joined and (last[lane.id] < lane.length - DEAD_END
                                          or stops.get(lane.id, -math.inf) > turned[lane.id])]
    # where a car arrives on each lane, and the last place it can leave each lane from
    arrive: dict[str, set[float]] = {}
    go_on = {lane.id: (lane.length if lane.id in joined else turned[lane.id])
             for lane in lot.lanes}
    for x in [*turns, *multis]:
        arrive.setdefault(x.lane_b, set()).add(x.station_b)
        go_on[x.lane_a] = max(go_on[x.lane_a], x.station_a)
    for lid, st in stops.items():  # a car unparks onto the lane there
        arrive.setdefault(lid, set()).add(st)
    key = (_types_key(designs),
           tuple((lane.id, tuple(sorted(arrive.get(lane.id, ()))), go_on[back.id])
                 for lane, back in ends))
    cache = _BACKS.setdefault(lot, {})
    if key not in cache:
        per = designs or {"": lot.design}
        bodies = {name: turnaround_collider(lot, design) for name, design in per.items()}
        tagged: dict[Turnaround, set[str]] = {}  # each with the types it was planned for
        why: dict[tuple[str, str], str] = {}  # (lane, type) → why it has none
        planned = _BACK_PLANS.setdefault(lot, {})  # (lane, design) → plan_turnarounds
        if lot in _AHEAD:  # those planned ahead so far (plan_turnarounds_ahead)
            keys, ahead = _AHEAD[lot]
            for k, plan in ahead.take().items():
                planned.setdefault(keys[k], plan)
        # the searches not planned before (by an earlier build of this lot's graph, or
        # ahead), on both cores: each is a function of its arguments alone, so the same
        # answers
        todo = {key: job for key, job in _turnaround_plans(per, bodies, ends).items()
                if key not in planned}
        planned.update(zip(todo, fork_map(lambda job: plan_turnarounds(*job),
                                          list(todo.values())), strict=True))
        reach = {}  # reach key → (lane, back, found, collider, body, radius, arrive, go on)

        def reach_key(lane: Lane, back: Lane, design: DesignVehicle) -> tuple:
            # what _reaching_turnarounds depends on: of the arrivals, only the last
            return (lane.id, design, max(arrive.get(lane.id, ()), default=-math.inf),
                    go_on[back.id], "reach")

        for name, design in per.items():
            for lane, back in ends:
                t = planned[lane.id, design]
                if reach_key(lane, back, design) not in planned and _fits_a_slot(lot, design):
                    reach[reach_key(lane, back, design)] = (
                        lane, back, [] if isinstance(t, str) else t, *bodies[name],
                        design.min_radius, arrive.get(lane.id, ()), go_on[back.id])
        planned.update(_reaching_all(reach, planned))
        for name, design in per.items():
            for lane, back in ends:
                t = planned[lane.id, design]
                more = planned.get(reach_key(lane, back, design), [])
                if isinstance(t, str) and not more:
                    why[lane.id, name] = t
                for x in ([] if isinstance(t, str) else t) + more:
                    tagged.setdefault(x, set()).add(name)
        for t, names in tagged.items():  # and every other type it suits
            names.update(n for n in per if n not in names and _suits(t, per[n], bodies[n]))
        notes = []
        for lane, _ in ends:
            lacking = [name for name in per if not any(
                t.lane_a == lane.id and name in names for t, names in tagged.items())]
            if lacking:
                x, y, _ = lane.pose_at(lane.length)
                reason = next((why[lane.id, n] for n in lacking if (lane.id, n) in why),
                              "none clear for it")
                some = f" (for {', '.join(lacking)})" if len(lacking) < len(per) else ""
                notes.append(f"dead end of lane {lane.id} at ({x:.1f}, {y:.1f}): no "
                             f"turnaround{some}: {reason}")
        cache[key] = ([(t, None if len(n) == len(per) else frozenset(n))
                       for t, n in tagged.items()], notes)
    found, notes = cache[key]
    return list(found), list(notes)


def _two_way_lanes(lot: Lot) -> list[tuple[Lane, Lane]]:
    """Each lane of a two-way aisle with the aisle's other lane, the one a car turning back
    lands on."""
    return [(lane, back) for aisle in lot.aisles.values()
            if not aisle.one_way and len(aisle.lanes) == 2
            for lane, back in (aisle.lanes, aisle.lanes[::-1])]


def _designs_of(vehicles) -> dict[str, DesignVehicle] | None:
    """Vehicle type → its own outline and limits, for two types or more (None: the lot's
    design vehicle serves every type): what :func:`build_graph` plans turns and
    turnarounds for."""
    names = sorted({v.name for v in vehicles})
    return ({v.name: DesignVehicle.envelope([v]) for v in vehicles} if len(names) > 1
            else None)


def _turnaround_plans(per: dict[str, DesignVehicle], bodies: dict[str, tuple],
                      ends: list[tuple[Lane, Lane]]) -> dict[tuple[str, DesignVehicle], tuple]:
    """(lane id, design) → the arguments of :func:`plan_turnarounds` for each of ``ends``
    (lane, opposite lane) and each type's design in ``per`` (``bodies``: its
    :func:`turnaround_collider`)."""
    return {(lane.id, per[name]): (lane, back, *bodies[name], per[name].min_radius)
            for name in per for lane, back in ends}


_AHEAD: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # lot → (keys, Background)


def plan_turnarounds_ahead(lot: Lot, vehicles=()) -> Background:
    """Begin planning the turnaround at the end of every lane of a two-way aisle of ``lot``
    (for ``vehicles``' designs, as :func:`build_graph` will want them), on a background
    process that takes only CPU time nothing else wants (:class:`~lotsim.core.workers.Background`):
    the lanes that turn out to be dead ends are then planned already when a graph of the
    lot is built. Each plan is a function of its arguments alone, so the graph is the same
    with it as without; one it has not finished is planned when needed, as without. Close
    it (or use it as a context manager) when the lot is built."""
    per = _designs_of(vehicles) or {"": lot.design}
    bodies = {name: turnaround_collider(lot, design) for name, design in per.items()}
    jobs = _turnaround_plans(per, bodies, _two_way_lanes(lot))
    done = _BACK_PLANS.get(lot, {})
    keys = [key for key in jobs if key not in done]
    ahead = Background(lambda key: plan_turnarounds(*jobs[key]), keys)
    _AHEAD[lot] = (keys, ahead)
    return ahead


def _fits_a_slot(lot: Lot, design: DesignVehicle) -> bool:
    """Whether a car of outline ``design`` fits some slot of ``lot`` (length and width)."""
    return any(design.front + design.rear <= s.length + _EPS and design.width <= s.width + _EPS
               for s in lot.slots)


def _reaching_all(jobs: dict, memo: dict) -> dict:
    """:func:`_reaching_turnarounds` of each of ``jobs`` (key → its arguments), by key; its
    multi-point searches on both cores, each once: ``memo`` holds (and is given) those
    done before, by lane, design and arguments (an earlier build of the lot's graph made
    some). A job's second search waits for its first (whether it is made depends on what
    the first found), so the searches go in rounds, each round's on both cores."""
    wanted: dict[tuple, tuple] = {}  # the searches the jobs need that are not done

    def onto(lane, back, starts, hi, collider, body, radius):
        key = (lane.id, back.id, body, radius, tuple(starts), hi, "onto")
        if key not in memo:
            wanted[key] = (lane, back, starts, hi, collider, body, radius)
            raise _Pending
        return memo[key]

    while True:
        wanted.clear()
        out = {}
        for key, job in jobs.items():
            with contextlib.suppress(_Pending):
                out[key] = _reaching_turnarounds(*job, onto=onto)
        if not wanted:
            return out
        memo.update(zip(wanted, fork_map(lambda job: _reaching_onto(*job),
                                         list(wanted.values())), strict=True))


class _Pending(Exception):
    """A search :func:`_reaching_all` has not made yet."""


def _reaching_onto(lane: Lane, back: Lane, starts: list[float], hi: float,
                   collider: Collider, body: DesignVehicle, radius: float
                   ) -> Turnaround | None:
    """A turnaround from ``lane`` (from the first of ``starts`` that has one, [m]) onto the
    straight beginning ``back``, landing at or before ``hi`` along it
    (:func:`~lotsim.roadmap.multipoint.plan_onto`), or None."""
    seg = back.segments[0]
    got = plan_onto([lane.pose_at(st) for st in starts], seg.start, 0.0, hi, collider, body,
                    radius)
    if got is None:
        return None
    k, segs = got
    return Turnaround(lane.id, starts[k], back.id, _along(seg, segs[-1].end), segs)


def _reaching_turnarounds(lane: Lane, back: Lane, found: list[Turnaround],
                          collider: Collider, body: DesignVehicle, radius: float,
                          arrive, go_on: float, *, onto=_reaching_onto) -> list[Turnaround]:
    """Turnarounds from ``lane`` onto ``back`` by multi-point search
    (:func:`~lotsim.roadmap.multipoint.plan_onto`) that land at or before ``go_on`` (the last
    station ``back`` can be left from), where those ``found`` leave a car stranded: one from
    as near the lane's end as there is room when every one found lands past ``go_on`` (or
    none was found), and one from the last station in ``arrive`` (where turns land on
    ``lane`` and cars unpark onto it) when that is past where every one found begins (a car
    arriving earlier drives on to it). ``onto`` makes each search
    (:func:`_reaching_onto`'s arguments and answer)."""
    seg = back.segments[0]
    if seg.curvature != 0.0 or seg.sharpness != 0.0 or go_on < 0:
        return []
    hi = min(go_on, seg.length)
    out: list[Turnaround] = []

    def plan(starts) -> None:
        starts = [st for st in starts if st >= 0 and _on_straight(lane, st)]
        got = onto(lane, back, starts, hi, collider, body, radius) if starts else None
        if got is not None:
            out.append(got)

    if all(t.station_b > go_on + _EPS for t in found):
        plan([lane.length - k for k in TURNAROUND_STARTS])
    # a car arriving past every start drives on to the last arrival and turns there
    latest = max((t.station_a for t in [*found, *out]), default=-math.inf)
    last = max(arrive, default=-math.inf)
    if last > latest + _EPS:
        plan([last])
    return out


def _on_straight(lane: Lane, station: float) -> bool:
    seg = lane.segments[lane.locate(station)[0]]
    return seg.curvature == 0.0 and seg.sharpness == 0.0


def _along(seg: Segment, pose) -> float:
    """How far along straight ``seg``'s line ``pose`` lies from its start [m]."""
    return float(np.dot(np.subtract(pose[:2], seg.start[:2]), unit(seg.start[2])))


def _junction_turns(lot: Lot, collider: Collider, design: DesignVehicle | None = None, *,
                    lanes_a=None) -> tuple[list[Turn], list[str]]:
    """Arcs between lanes of aisles that meet, each swept clear with ``design`` (default
    the lot's design vehicle): out of ``lanes_a`` (default every lane)."""
    design = design or lot.design
    turns: list[Turn] = []
    skipped: list[str] = []
    lanes = lot.lanes
    for a in lanes if lanes_a is None else lanes_a:
        for b in lanes:
            if a.aisle == b.aisle:
                continue
            aisle_a, aisle_b = lot.aisles[a.aisle], lot.aisles[b.aisle]
            reach = max(aisle_a.width, aisle_b.width) / 2 + 1.0
            for sa0, pa in _straights(a):
                for sb0, pb in _straights(b):
                    turn = _fillet_between(a, sa0, pa, b, sb0, pb, aisle_a, aisle_b, reach,
                                           design, collider, lot.speed_limit)
                    if isinstance(turn, list):
                        turns.extend(turn)
                    elif turn:
                        skipped.append(turn)
    return turns, skipped


MULTI_STARTS = (0.0, 3.0, 6.0)
"""How far before the crossing of two lanes [m] a multi-point junction turn may begin
(:func:`_junction_multipoints`); and it may begin where the lane's straight ends."""
MULTI_ROOM = 3.0
"""Lane a multi-point junction turn needs before the crossing on the lane it leaves, and
after it on the lane it joins [m]: where a lane begins or ends at the crossing, a car
comes from or goes on to another turn instead."""
_MULTIS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # lot → {types: multis}


def _junction_multipoints(lot: Lot, tagged: list[tuple[Turn, frozenset | None]],
                          designs: dict[str, DesignVehicle] | None = None,
                          exits: dict[str, float] | None = None
                          ) -> list[tuple[Turnaround, frozenset | None]]:
    """Multi-point turns between lanes of aisles that meet, where no turn joins them for
    some vehicle type (``tagged``: the junction turns, each with the types that can drive
    it, None for all): a junction too small to turn in at one go — a short arm, a spur
    meeting a narrow aisle — is turned in as a driver does, in a few strokes
    (:func:`~lotsim.roadmap.multipoint.plan_onto`), beginning at or a little before the
    crossing and landing on the other lane past it, driven from rest to rest like a
    turnaround. So too where every turn lands past an exit on the other lane (``exits``:
    lane → its last exit's station) that the crossing is before: an exit close to the
    junction, which the multi-point turn lands before. Each is tagged with the types it
    suits (None: all); worked out once per lot and set of types."""
    exits = exits or {}
    key = _types_key(designs)
    cache = _MULTIS.setdefault(lot, {})
    if key in cache:
        return list(cache[key])
    per = designs or {"": lot.design}
    every = frozenset(per)
    lands: dict[tuple[str, str], dict[str, float]] = {}  # (a, b) → type → first landing
    for t, types in tagged:
        pair = lands.setdefault((t.lane_a, t.lane_b), {})
        for name in every if types is None else types:
            pair[name] = min(pair.get(name, math.inf), t.station_b)
    bodies = {name: turnaround_collider(lot, design) for name, design in per.items()}
    found: dict[Turnaround, set[str]] = {}
    parks = [n for n, design in per.items() if _fits_a_slot(lot, design)]  # others never park
    for a in lot.lanes:
        for b in lot.lanes:
            if a.aisle == b.aisle:
                continue
            landed = lands.get((a.id, b.id), {})
            out_at = exits.get(b.id, math.inf)
            lacking = [n for n in parks if n not in landed or landed[n] > out_at + _EPS]
            if not lacking:
                continue
            aisle_a, aisle_b = lot.aisles[a.aisle], lot.aisles[b.aisle]
            reach = max(aisle_a.width, aisle_b.width) / 2 + 1.0
            for sa0, pa in _straights(a):
                for sb0, pb in _straights(b):
                    corner = _corner(pa, pb, aisle_a, aisle_b, reach)
                    if corner is None:
                        continue
                    _, ta, tb, _ = corner
                    hi = min(pb.length, out_at - sb0)  # land before the exit, if any
                    if sa0 + ta < MULTI_ROOM or hi - tb < MULTI_ROOM:
                        continue  # a lane that begins, or one that ends, at the crossing
                    end = min(ta, pa.length)
                    starts = sorted({max(end - k, 0.0) for k in MULTI_STARTS} | {pa.length},
                                    reverse=True)
                    for name in lacking:
                        if any(name in n for t, n in found.items()
                               if (t.lane_a, t.lane_b) == (a.id, b.id)):
                            continue
                        got = plan_onto(list(pa.poses_at(starts)), pb.start, max(tb - 1.0, 0.0),
                                        hi, *bodies[name], per[name].min_radius)
                        if got is not None:
                            k, segs = got
                            t = Turnaround(a.id, sa0 + starts[k], b.id,
                                           sb0 + _along(pb, segs[-1].end), segs)
                            found.setdefault(t, set()).add(name)
    for t, names in found.items():  # and every other type it suits
        names.update(n for n in per if n not in names and _suits(t, per[n], bodies[n]))
    out = [(t, None if len(n) == len(per) else frozenset(n)) for t, n in found.items()]
    cache[key] = out
    return list(out)


def _junction_backs(lot: Lot, tagged: list[tuple[Turn, frozenset | None]],
                    designs: dict[str, DesignVehicle] | None, exits: dict[str, float]
                    ) -> tuple[list[tuple[Turnaround, frozenset | None]],
                               list[tuple[Turnaround, frozenset | None]]]:
    """:func:`_junction_multipoints` and :func:`_junction_uturns`; the two at once, on both
    cores, when neither was worked out before for this lot and set of types (each is a
    function of its arguments: the same answers, kept as each keeps its own)."""
    key = _types_key(designs)
    if key not in _MULTIS.get(lot, {}) and key not in _UTURNS.get(lot, {}):
        # each kept as it keeps its own: what the workers kept went with them
        _MULTIS.setdefault(lot, {})[key], _UTURNS.setdefault(lot, {})[key] = fork_map(
            lambda job: job(), [lambda: _junction_multipoints(lot, tagged, designs, exits),
                                lambda: _junction_uturns(lot, designs)])
    return _junction_multipoints(lot, tagged, designs, exits), _junction_uturns(lot, designs)


UTURN_LAND = (2.0, 8.0)
"""Where a U-turn at a junction (:func:`_junction_uturns`) may land on the opposite lane:
from this much before the crossing to this much past it [m]."""
_UTURNS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # lot → {types: uturns}


def _junction_uturns(lot: Lot, designs: dict[str, DesignVehicle] | None = None
                     ) -> list[tuple[Turnaround, frozenset | None]]:
    """U-turns at junctions: from a lane of a two-way aisle, where another aisle crosses
    or meets it, back onto its opposite lane, in a few strokes that use the other aisle's
    mouth (:func:`~lotsim.roadmap.multipoint.plan_onto`) — how a driver turns back whose way
    is blocked, or who leaves the way they came. Each begins at or up to 6 m
    (:data:`MULTI_STARTS`) before the crossing and lands within :data:`UTURN_LAND` of it;
    it needs :data:`MULTI_ROOM` of lane before the crossing on the lane it leaves and past
    it on the one it joins. Each is tagged with the vehicle types it suits (None: all);
    only types that fit a slot are planned for, largest first.

    Junctions of one shape share a plan: one found at a junction is moved onto the next
    (the same place relative to the crossing) and kept when it lands on that junction's
    opposite lane and is clear there, so a lot of many alike junctions plans a few.
    Worked out once per lot and set of types."""
    key = _types_key(designs)
    cache = _UTURNS.setdefault(lot, {})
    if key in cache:
        return list(cache[key])
    per = designs or {"": lot.design}
    bodies = {name: turnaround_collider(lot, design) for name, design in per.items()}
    parks = sorted((n for n, d in per.items() if _fits_a_slot(lot, d)),
                   key=lambda n: (-per[n].min_radius, -(per[n].front + per[n].rear), n))
    known: list[tuple[str, tuple[Segment, ...]]] = []  # (type, path relative to a crossing)
    found: dict[Turnaround, set[str]] = {}
    for aisle in lot.aisles.values():
        if aisle.one_way or len(aisle.lanes) != 2:
            continue
        for a, back in (aisle.lanes, aisle.lanes[::-1]):
            for sa0, pa, x in _crossings(lot, a):
                ta = _along(pa, x)
                sb, _ = back.project((float(x[0]), float(x[1])))
                got = _straight_at(back, sb)
                if got is None or sa0 + ta < MULTI_ROOM:
                    continue
                sb0, pb = got
                tb = sb - sb0
                lo, hi = max(tb - UTURN_LAND[0], 0.0), min(tb + UTURN_LAND[1], pb.length)
                if hi - tb < MULTI_ROOM:
                    continue
                frame = np.array(pa.start, dtype=float)
                frame[:2] = x
                end = min(ta, pa.length)
                mine: list[Turnaround] = []
                for name in parks:
                    fitting = [t for t in mine if _suits(t, per[name], bodies[name])]
                    if fitting:  # one planned for a larger type here serves this one
                        found[fitting[0]].add(name)
                        continue
                    t = _moved_uturn(known, name, frame, a, sa0, pa, end, back, sb0, pb,
                                     lo, hi, bodies[name])
                    if t is None:
                        starts = sorted({max(end - k, 0.0) for k in MULTI_STARTS},
                                        reverse=True)
                        plan = plan_onto(list(pa.poses_at(starts)), pb.start, lo, hi,
                                         *bodies[name], per[name].min_radius)
                        if plan is None:
                            continue
                        k, segs = plan
                        t = Turnaround(a.id, sa0 + starts[k], back.id,
                                       sb0 + _along(pb, segs[-1].end), segs)
                        known.append((name, tuple(_segment_to_local(frame, g) for g in segs)))
                    found.setdefault(t, set()).add(name)
                    mine.append(t)
    for t, names in found.items():  # and every other type it suits
        names.update(n for n in per if n not in names and _suits(t, per[n], bodies[n]))
    out = [(t, None if len(n) == len(per) else frozenset(n)) for t, n in found.items()]
    cache[key] = out
    return list(out)


def _suits(t: Turnaround, design: DesignVehicle, checks: tuple[Collider, DesignVehicle]
           ) -> bool:
    """Whether a car of ``design`` can drive ``t``: no tighter than its radius, and clear
    (``checks``: collider and grown body, :func:`turnaround_collider`)."""
    bend = max(seg.max_curvature for seg in t.segments)
    return bend <= 1 / design.min_radius + 1e-9 and turnaround_clear(t, *checks)


def _crossings(lot: Lot, lane: Lane) -> list[tuple[float, Segment, np.ndarray]]:
    """Where other aisles cross or meet ``lane``'s straights: (the straight's start
    station, the straight, the crossing point with the nearest of the other aisle's lanes'
    lines), once per other aisle and straight."""
    out = []
    aisle = lot.aisles[lane.aisle]
    for sa0, pa in _straights(lane):
        for other in lot.aisles.values():
            if other.id == aisle.id:
                continue
            reach = max(aisle.width, other.width) / 2 + 1.0
            hits = [corner[3] for c in other.lanes for _, pc in _straights(c)
                    if (corner := _corner(pa, pc, aisle, other, reach)) is not None]
            if hits:
                out.append((sa0, pa, min(hits, key=lambda h: _along(pa, h))))
    return out


def _moved_uturn(known, name: str, frame: np.ndarray, a: Lane, sa0: float, pa: Segment,
                 end: float, back: Lane, sb0: float, pb: Segment, lo: float, hi: float,
                 checks: tuple[Collider, DesignVehicle]) -> Turnaround | None:
    """The first U-turn found earlier for type ``name`` (``known``: paths relative to
    their crossing) that, moved to the crossing ``frame``, begins on straight ``pa`` at
    most at ``end``, lands on ``pb``'s line heading along it between ``lo`` and ``hi``,
    and is clear (``checks``: collider and body); None when none is."""
    for owner, local in known:
        if owner != name:
            continue
        segs = tuple(segment_to_world(frame, g) for g in local)
        start = _along(pa, segs[0].start)
        if not 0.0 <= start <= end + _EPS:
            continue
        ex, ey, eh = segs[-1].end
        off = to_local(np.array(pb.start, dtype=float), np.array([ex, ey, eh]))
        at = float(off[0])
        if (abs(off[1]) > 1e-6 or abs(wrap_angle(off[2])) > 1e-6
                or not lo - _EPS <= at <= hi + _EPS):
            continue
        t = Turnaround(a.id, sa0 + start, back.id, sb0 + at, segs)
        if turnaround_clear(t, *checks):
            return t
    return None


def _segment_to_local(frame: np.ndarray, seg: Segment) -> Segment:
    x, y, t = to_local(frame, np.array(seg.start, dtype=float))
    return Segment((float(x), float(y), float(t)), seg.distance, seg.curvature, seg.sharpness)


THROUGH_OVERLAP = 15.0
"""Longest stretch of lane [m] by which a turn into it may overrun the start of a turn out of
it for the two to be joined into one turn through the stretch."""


def _through_turns(lot: Lot, turns: list[Turn], collider: Collider,
                   design: DesignVehicle | None = None) -> list[Turn]:
    """Turns through a short stretch of lane: where a turn into lane ``c`` ends past where
    a turn out of it begins (two junctions close together, one turn swinging wide), one
    path from the first lane into the last along the stretch (:func:`_area_turns` with
    ``via``), if no turn joins the two lanes there already. None back onto the lane it
    came from."""
    return [t for chain in _through_chains(lot, turns)
            for t in _through_turn(lot, collider, design, chain)]


def _through_chains(lot: Lot, turns: list[Turn]) -> list[tuple]:
    """The stretches :func:`_through_turns` turns through, in its order: for each, the
    first lane, the start station and straight of it the turn leaves from, the last lane
    and its straight likewise, and the stretch's straight."""
    lanes = {lane.id: lane for lane in lot.lanes}
    into: dict[str, list[Turn]] = {}
    for tn in turns:
        into.setdefault(tn.lane_b, []).append(tn)
    joined = {(tn.lane_a, tn.lane_b) for tn in turns}
    done = set()
    out = []
    for t2 in turns:
        for t1 in into.get(t2.lane_a, ()):
            chain = (t1.lane_a, t2.lane_a, t2.lane_b)
            overlap = t1.station_b - t2.station_a
            if (t1.lane_a == t2.lane_b or chain[::2] in joined or chain in done
                    or not (t1.wide or t2.wide) or not _EPS < overlap < THROUGH_OVERLAP):
                continue
            done.add(chain)
            a, c, b = lanes[t1.lane_a], lanes[t2.lane_a], lanes[t2.lane_b]
            pieces = [_straight_at(lane, st) for lane, st in
                      ((a, t1.station_a), (c, (t1.station_b + t2.station_a) / 2),
                       (b, t2.station_b))]
            if any(p is None for p in pieces):
                continue
            (sa0, pa), (_, pc), (sb0, pb) = pieces
            out.append((a, sa0, pa, b, sb0, pb, pc))
    return out


def _through_turn(lot: Lot, collider: Collider, design: DesignVehicle | None,
                  chain: tuple) -> list[Turn]:
    """:func:`_through_turns` through one of :func:`_through_chains`."""
    a, sa0, pa, b, sb0, pb, pc = chain
    return _area_turns(a, sa0, pa, b, sb0, pb, design or lot.design, collider,
                       lot.speed_limit, via=(pc,), shifts=AREA_SHIFTS)


def _straight_at(lane: Lane, station: float) -> tuple[float, Segment] | None:
    """The straight of ``lane`` that holds ``station`` (its start station and itself)."""
    for s0, seg in _straights(lane):
        if s0 - _EPS <= station <= s0 + seg.length + _EPS:
            return s0, seg
    return None


def _turn_designs(design, lot_speed: float) -> list[tuple[float, float]]:
    """(design speed [m/s], arc radius [m]) of the junction turns to try, fastest first,
    tightest first at each speed: the tightest arc the speed allows, and twice and three
    times the design radius (a wide arc clears a corner that a tight one's body sweeps
    over)."""
    out = []
    for speed in TURN_SPEEDS:
        if speed > lot_speed + 1e-9 and speed != TURN_SPEEDS[-1]:
            continue
        least = max(design.min_radius, speed * speed / design.max_lateral_accel)
        for r in sorted({least, 2 * design.min_radius, 3 * design.min_radius}):
            if r >= least:
                out.append((speed, r))
    return out


def _corner(pa: Segment, pb: Segment, aisle_a, aisle_b, reach: float
            ) -> tuple[float, float, float, np.ndarray] | None:
    """Where straights ``pa`` and ``pb`` (of lanes of two aisles) meet, if they cross at
    10° to 170° within ``reach`` of both aisles' centre lines: the turn's deflection [rad],
    the distances along each to the crossing [m], and the crossing point."""
    ta, tb = pa.start[2], pb.start[2]
    delta = float(wrap_angle(tb - ta))
    if abs(math.sin(delta)) < math.sin(math.radians(10)) or abs(delta) > math.radians(170):
        return None
    ua, ub = unit(ta), unit(tb)
    pa_xy, pb_xy = np.array(pa.start[:2]), np.array(pb.start[:2])
    # pa_xy + t ua = pb_xy + s ub
    t, s = np.linalg.solve(np.column_stack([ua, -ub]), pb_xy - pa_xy)
    x = pa_xy + t * ua
    pt = shapely.Point(x)
    if aisle_a.line.distance(pt) > reach or aisle_b.line.distance(pt) > reach:
        return None
    return delta, float(t), float(s), x


def _fillet_between(a, sa0, pa, b, sb0, pb, aisle_a, aisle_b, reach, design,
                    collider: Collider, lot_speed: float) -> list[Turn] | str | None:
    """The turns from straight ``pa`` of lane ``a`` into straight ``pb`` of lane ``b``: the
    fastest that is clear and, when it is another, the tightest that is clear (the shortest
    tangent: it starts later and ends sooner, so it can reach a node the wide one passes
    by).

    Returns the turns, a reason string when the aisles meet but no turn is clear,
    or None when the two straights do not meet.
    """
    corner = _corner(pa, pb, aisle_a, aisle_b, reach)
    if corner is None:
        return None
    delta, t, s, x = corner
    reason = None
    fits = []  # (speed, radius, tangent) of the turns with room on both lanes
    for speed, r in _turn_designs(design, lot_speed):
        _, tangent = cc_turn(delta, 1 / r, design.sharpness(speed))
        da, db = t - tangent, s + tangent  # distances into pa and pb
        if -_EPS <= da <= pa.length + _EPS and -_EPS <= db <= pb.length + _EPS:
            fits.append((speed, r, tangent))
        else:
            reason = reason or f"no room for a turn at {speed * 3.6:.1f} km/h"
    clear: dict[int, Turn | None] = {}

    def sweep(k: int) -> Turn | None:
        """The k-th fitting turn if its swept body touches nothing (each swept once)."""
        nonlocal reason
        if k not in clear:
            speed, r, tangent = fits[k]
            da = t - tangent
            start = tuple(float(v) for v in pa.poses_at(min(max(da, 0.0), pa.length))[0])
            segs, _ = cc_turn(delta, 1 / r, design.sharpness(speed), start)
            hit = collider.sweep_hit(design.footprints(sample_segments(segs, SWEEP_STEP)[0]))
            if hit is not None:
                reason = f"touches {hit.what}"
            clear[k] = None if hit is not None else Turn(a.id, sa0 + da, b.id,
                                                          sb0 + s + tangent, tuple(segs))
        return clear[k]

    # the fastest clear turn, and the tightest (shortest tangent: starts latest, ends soonest)
    fastest = next((tn for k in range(len(fits)) if (tn := sweep(k)) is not None), None)
    tight = sorted(range(len(fits)), key=lambda k: fits[k][2])
    tightest = next((tn for k in tight if (tn := sweep(k)) is not None), None)
    found = [tn for tn in (fastest, tightest) if tn is not None]
    if found:
        return found if found[0] is not found[-1] else found[:1]
    wide = _area_turns(a, sa0, pa, b, sb0, pb, design, collider, lot_speed)
    if wide:
        return wide
    return (f"turn {a.id} → {b.id} near ({x[0]:.1f}, {x[1]:.1f}) skipped: {reason}"
            if reason and "touches" in reason else None)


AREA_SHIFTS = (0.0, 1.0, -1.0, 2.0, -2.0, 3.0, -3.0, 4.0)
"""Sideways shifts [m] of the corner of a junction turn that uses the junction's area, from
each lane's line (positive: to the lane's left, across the oncoming lane)."""
AREA_LEADS = (1.5, 3.0, 4.5, 6.0, 9.0, 12.0)
"""Lengths [m] of the drift from a lane to the shifted corner's line, and back."""
AREA_RADII = (1.0, 1.5)
"""Multiples of the design radius the corner of such a turn tries."""
AREA_SPEEDS = (5.0 / 3.6, 3.0 / 3.6, 1.5 / 3.6)
"""Design speeds [m/s] such a turn tries below the fastest its arc allows: a slower turn has
shorter clothoids (the wheels turn at the same rate over less path), so it fits a tighter
corner."""


def _approx_tangent(deflection, radius: float, sharpness: float):
    """The tangent length of a continuous-curvature turn (:func:`cc_turn`) by the road
    designers' formula, ``(R + p) tan(Δ/2) + L/2`` with the clothoids' shift ``p = L² / 24R``
    (within 0.1 % of the exact one for the turns built here); ``deflection`` [rad] may be an
    array."""
    d = np.asarray(deflection, dtype=float)
    peak = np.minimum(1 / radius, np.sqrt(d * sharpness))
    ramp = peak / sharpness
    with np.errstate(divide="ignore", invalid="ignore"):
        out = (1 / peak + ramp * ramp * peak / 24) * np.tan(d / 2) + ramp / 2
    return np.where(d > 1e-12, out, 0.0)


def _area_designs(design, lot_speed: float) -> list[tuple[float, float]]:
    """(radius multiple, design speed [m/s]) of the junction-area turns to try."""
    out = []
    for f in AREA_RADII:
        top = min(lot_speed, math.sqrt(design.max_lateral_accel * f * design.min_radius))
        out += [(f, v) for v in sorted({top, *(v for v in AREA_SPEEDS if v < top)},
                                       reverse=True)]
    return out


def _area_turns(a, sa0, pa, b, sb0, pb, design, collider: Collider,
                lot_speed: float, via: tuple[Segment, ...] = (),
                shifts: tuple[float, ...] = ()) -> list[Turn]:
    """Turns from ``pa`` into ``pb`` that use the junction's whole area, as a driver does
    where the turn between the lanes themselves touches a corner slot: drift sideways from
    the lane (wide of the corner, across the oncoming lane where need be), turn, drift back
    onto the other lane. Each line is shifted sideways by :data:`AREA_SHIFTS` (positive:
    to the lane's left), the drifts take :data:`AREA_LEADS`, the corners' arcs
    :data:`AREA_RADII`; every corner is continuous-curvature, sized for the arc's speed.
    With ``via`` (a lane's straight between two junctions close together) the path runs
    along that straight, shifted by ``shifts``, from one turn into the next without
    drifting back to its lane between them.

    The quickest clear one (length over design speed) is built and, when it is another,
    the most compact clear one (the least lane used before and after: it starts latest and
    ends soonest, so it fits between two turns close together); none when none is clear.
    """
    lines = (pa, *via, pb)
    dirs = np.array([unit(seg.start[2]) for seg in lines])  # (L, 2)
    normals = np.column_stack([-dirs[:, 1], dirs[:, 0]])
    origins = np.array([seg.start[:2] for seg in lines])
    heads = np.array([seg.start[2] for seg in lines])
    bends = np.abs(np.asarray(wrap_angle(np.diff(heads)), dtype=float))  # (L-1,)
    grids = [AREA_SHIFTS, *([shifts or (0.0,)] * len(via)), AREA_SHIFTS]
    offs = np.array(list(itertools.product(*grids)))  # (N, L)
    if not via:
        offs = offs[np.any(offs != 0.0, axis=1)]  # (0, 0) is the plain turn, already tried
    # corner k: where line k shifted by offs[:, k] meets line k+1 shifted by offs[:, k+1]
    corners, params = [], []
    for k in range(len(lines) - 1):
        inv = np.linalg.inv(np.column_stack([dirs[k], -dirs[k + 1]]))
        rhs = (origins[k + 1] - origins[k] + offs[:, k + 1, None] * normals[k + 1]
               - offs[:, k, None] * normals[k])  # (N, 2)
        ts = rhs @ inv.T  # (N, 2): along line k, along line k+1
        corners.append(origins[k] + offs[:, k, None] * normals[k] + ts[:, :1] * dirs[k])
        params.append(ts)
    ta, tb = params[0][:, 0], params[-1][:, 1]
    # leads (la, lb) for every shift: index arrays over (N × leads²)
    leads = np.array(list(itertools.product(AREA_LEADS, AREA_LEADS)))
    n_off, n_lead = len(offs), len(leads)
    oi = np.repeat(np.arange(n_off), n_lead)
    la, lb = np.tile(leads[:, 0], n_off), np.tile(leads[:, 1], n_off)
    u, w = offs[oi, 0], offs[oi, -1]
    a1 = origins[0] + (ta[oi] - la)[:, None] * dirs[0]
    b1 = origins[-1] + (tb[oi] + lb)[:, None] * dirs[-1]
    c_first, c_last = corners[0][oi], corners[-1][oi]
    h1 = np.arctan2(*(c_first - a1).T[::-1])
    h2 = np.arctan2(*(b1 - c_last).T[::-1])
    first_turn = np.abs(np.asarray(wrap_angle((heads[1] if via else h2) - h1), dtype=float))
    last_turn = np.abs(np.asarray(wrap_angle(h2 - (heads[-2] if via else h1)), dtype=float))
    legs = [np.hypot(la, u), np.hypot(lb, w)]
    blocks = []  # per design and shape: (points (M, P, 2), time, lane used, da, db, r, sharp)

    def add(ok, points, speed, da, db, r, sharp) -> None:
        rows = np.flatnonzero(ok)
        if len(rows):
            pts = np.stack([p[rows] for p in points], axis=1)
            rough = np.hypot(*np.diff(pts, axis=1).transpose(2, 0, 1)).sum(axis=1)
            blocks.append((pts, rough / speed, db[rows] - da[rows], da[rows], db[rows], r,
                           sharp))

    corners_n = [c[oi] for c in corners]
    for f, speed in _area_designs(design, lot_speed):
        r = f * design.min_radius
        sharp = design.sharpness(speed)
        pre = np.where(u != 0.0, _approx_tangent(np.arctan2(np.abs(u), la), r, sharp) + 0.05,
                       0.0)
        post = np.where(w != 0.0, _approx_tangent(np.arctan2(np.abs(w), lb), r, sharp) + 0.05,
                        0.0)
        da, db = ta[oi] - la - pre, tb[oi] + lb + post
        ok = ((da >= -_EPS) & (da <= pa.length + _EPS) & (db >= -_EPS)
              & (db <= pb.length + _EPS)
              # the corners' turns must leave room for the drifts' (road designers'
              # estimate of the tangents; cc_polyline checks exactly)
              & (_approx_tangent(first_turn, r, sharp) + pre <= legs[0] * 1.01)
              & (_approx_tangent(last_turn, r, sharp) + post <= legs[1] * 1.01))
        if via:  # the corners on the stretch in order, with room for both turns
            gap = params[1][oi, 0] - params[0][oi, 1]
            ok &= gap >= float(_approx_tangent(bends[0], r, sharp)
                               + _approx_tangent(bends[1], r, sharp))
        add(ok, [a1 - dirs[0] * pre[:, None], a1, *corners_n, b1, b1 + dirs[-1] * post[:, None]],
            speed, da, db, r, sharp)
        if via:
            continue
        # or: drift onto the shifted line, run along it, turn the corner, run along the
        # other shifted line, drift back (the drift ends before the corner's turn begins, so
        # a wide shift does not sharpen the corner: a big car's way round a corner slot)
        corner = _approx_tangent(bends[0], r, sharp)
        g1 = np.where(u != 0.0, corner + pre + 0.05, 0.0)
        g2 = np.where(w != 0.0, corner + post + 0.05, 0.0)
        da, db = ta[oi] - g1 - la - pre, tb[oi] + g2 + lb + post
        ok = (((u != 0.0) | (w != 0.0)) & (da >= -_EPS) & (da <= pa.length + _EPS)
              & (db >= -_EPS) & (db <= pb.length + _EPS)
              & (2 * pre <= legs[0] * 1.01) & (2 * post <= legs[1] * 1.01))
        on_a = origins[0] + (ta[oi] - g1 - la)[:, None] * dirs[0]
        on_b = origins[-1] + (tb[oi] + g2 + lb)[:, None] * dirs[-1]
        add(ok, [on_a - dirs[0] * pre[:, None], on_a, c_first - dirs[0] * g1[:, None], c_first,
                 c_last + dirs[-1] * g2[:, None], on_b, on_b + dirs[-1] * post[:, None]],
            speed, da, db, r, sharp)
    if not blocks:
        return []
    times, used, starts, ends = (np.concatenate([b[k] for b in blocks]) for k in range(1, 5))
    offsets = np.cumsum([0] + [len(b[1]) for b in blocks])

    def candidate(k: int) -> tuple[np.ndarray, float, float]:
        """Candidate ``k``'s polyline without repeated points, corner radius, sharpness."""
        j = int(np.searchsorted(offsets, k, side="right")) - 1
        i = k - int(offsets[j])
        pts, *_, r, sharp = blocks[j]
        row = pts[i]
        keep = np.ones(len(row), dtype=bool)
        keep[1:] = np.hypot(*np.diff(row, axis=0).T) > 1e-6
        return row[keep], r, sharp

    clear: dict[int, bool] = {}
    paths: dict[int, list[Segment]] = {}

    def first(order: list[int], chunk: int = 24) -> int | None:
        """The first clear candidate of ``order``: a rough pass over footprints 1 m apart
        drops most blocked ones a chunk at a time, then the sweep, in order."""
        for c0 in range(0, len(order), chunk):
            part = [k for k in order[c0 : c0 + chunk] if k not in clear]
            built = []
            for k in part:
                pts, r, sharp = candidate(k)
                try:
                    built.append((k, cc_polyline(pts, r, sharp)))
                except ValueError:  # no room for a corner's turn on a leg
                    clear[k] = False
            if built:
                poses, of = sample_segments([sg for _, path in built for sg in path], 1.0)
                owner = np.repeat(np.arange(len(built)), [len(path) for _, path in built])[of]
                bad = collider.blocked(design.footprints(poses))
                rough = np.bincount(owner[bad], minlength=len(built)) > 0
                for (k, path), hit in zip(built, rough, strict=True):
                    if hit:
                        clear[k] = False
                    else:
                        paths[k] = path
            for k in order[c0 : c0 + chunk]:
                if k not in clear:
                    clear[k] = collider.sweep_hit(
                        design.footprints(sample_segments(paths[k], SWEEP_STEP)[0])) is None
                if clear[k]:
                    return k
        return None

    quick = first(np.lexsort((used, times)).tolist())
    if quick is None:
        return []
    compact = first(np.lexsort((times, used)).tolist())
    return [Turn(a.id, sa0 + float(starts[k]), b.id, sb0 + float(ends[k]), tuple(paths[k]),
                 True) for k in dict.fromkeys((quick, compact))]

