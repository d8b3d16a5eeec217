"""The drivable graph of a built lot as data (:class:`LotGraph`) and the junction turn
(:class:`Turn`) its turn edges are made of.

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
  (:mod:`lotsim.roadmap.junctions`); where that touches a corner slot, one that swings
  wide through the junction's area (:mod:`lotsim.roadmap.area_turns`). ``types`` names
  the vehicle types that can drive it (None: all);
* ``join`` — a lane that continues as another (zero length);
* ``turnaround`` — a multi-point turn, driven from rest to rest, stopping at each cusp:
  at a dead end onto the opposite lane (:mod:`lotsim.roadmap.turnarounds`), or where
  aisles meet in a junction too small for one turn, onto the other aisle's lane
  (:mod:`lotsim.roadmap.junction_multipoints`), or a U-turn at a junction, turning in the
  crossing aisle's mouth back onto the opposite lane (:mod:`lotsim.roadmap.uturns`);
* ``park`` / ``leave`` — from a lane node into a slot node and back, through
  real parking maneuvers: ``maneuvers`` maps each vehicle type that can use
  the link to its :class:`~lotsim.maneuvers.maneuver.Maneuver` (the leave edge
  holds them reversed), ``duration`` maps it to seconds, ``length`` is the
  shortest of them. A lane node sits exactly where each maneuver starts. A park
  edge's ``park_only`` (with ``park_only_duration`` and ``park_only_limit``) holds, per type,
  the lane's own best maneuver where the one in ``maneuvers`` parks the other
  way round so that the car can leave towards every lane: a car that will not
  leave may park with it (it has no leave edge). Built without maneuvers, the
  graph has ``placeholder=True`` links abeam of each
  slot instead, with no geometry (enough to draw and check reachability).

Every edge's geometry but a turnaround's is tangent- and curvature-continuous with
its nodes' headings and curvatures, and every turn, turnaround and lane is swept
with the design vehicle (a turn: with each type it is for) against slots, areas
and the boundary before it is added (:mod:`lotsim.roadmap.assemble`).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from lotsim.core.geometry import Segment
from lotsim.core.lazy import LoadedBy
from lotsim.core.packed import pack, unpack
from lotsim.lot.model import Lot
from lotsim.roadmap.reach import Reachability, find_reachability, leavable_edges

if TYPE_CHECKING:
    import networkx as nx


@dataclass(frozen=True, slots=True)
class Turn:
    """A junction turn from ``lane_a`` at ``station_a`` into ``lane_b`` at ``station_b``."""

    lane_a: str
    station_a: float
    lane_b: str
    station_b: float
    segments: tuple[Segment, ...]
    wide: bool = False  # it uses the junction's area (:mod:`lotsim.roadmap.area_turns`)


@dataclass(frozen=True, slots=True)
class ParkingLink:
    """One vehicle type's way into one slot from one lane, and out again, as the maneuvers
    hand it to the roadmap (:func:`lotsim.maneuvers.links.parking_links`): plain numbers
    the roadmap reads, and the maneuvers themselves, which it only records on the park and
    leave edges for the runs to drive.

    Attributes
    ----------
    vehicle, slot, lane : str
        The vehicle type's name, the slot's id and the lane's id.
    station : float
        Where along the lane the maneuver begins (and the way out ends) [m].
    speed_limit : float
        The lowest speed limit along it [m/s].
    park : object
        The maneuver into the slot (a :class:`~lotsim.maneuvers.maneuver.Maneuver`).
    park_gear, park_length, park_time
        Its first gear (+1 forward, -1 reverse), length [m] and time for the type [s]
        (None: not timed, for a type the graph is not built for).
    leave : object or None
        The way out, the maneuver driven backwards (None: a park-only link, for cars that
        will not leave: the lane's own best where the shared pose parks the other way).
    leave_gear, leave_length, leave_time
        The way out's first gear, length [m] and time [s], as for ``park``.
    """

    vehicle: str
    slot: str
    lane: str
    station: float
    speed_limit: float
    park: object
    park_gear: int
    park_length: float
    park_time: float | None
    leave: object | None = None
    leave_gear: int = 0
    leave_length: float = 0.0
    leave_time: float | None = None


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


def pack_graph(g: nx.DiGraph) -> bytes:
    """``g`` packed (:func:`~lotsim.core.packed.pack`) as its graph attributes, its nodes
    with their data and its edges with theirs, the edges in an order that adds each node's
    successors and its predecessors in the order ``g`` holds them (a topological order of
    those two orders): :func:`unpack_graph` makes it again through networkx's public API
    with every node, successor and predecessor in the same order, so that whatever walks
    the graph walks it as it walked ``g``."""
    from graphlib import TopologicalSorter

    order: TopologicalSorter = TopologicalSorter()
    for u, nbrs in g.adj.items():
        prev = None
        for v in nbrs:
            order.add((u, v), *(() if prev is None else (prev,)))
            prev = (u, v)
    for v, nbrs in g.pred.items():
        prev = None
        for u in nbrs:
            if prev is not None:
                order.add((u, v), prev)
            prev = (u, v)
    edges = [(u, v, g.adj[u][v]) for u, v in order.static_order()]
    return pack((g.graph, list(g.nodes(data=True)), edges))


def unpack_graph(packed: bytes) -> nx.DiGraph:
    """The graph :func:`pack_graph` packed, made through networkx's public API."""
    import networkx as nx

    attrs, nodes, edges = unpack(packed)
    g = nx.DiGraph()
    g.graph.update(attrs)
    g.add_nodes_from(nodes)
    g.add_edges_from(edges)
    return g


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
    from_cache : bool
        Whether :func:`~lotsim.sim.preparation.prepare_graph` loaded it from the on-disk cache
        (:mod:`lotsim.core.diskcache`) rather than planning it.
    """

    lot: Lot
    graph: nx.DiGraph = LoadedBy("load_graph")  # type: ignore[assignment]
    entrances: dict[str, int]
    exits: dict[str, int]
    slot_nodes: dict[str, int]
    attachments: dict[str, list[int]] = field(default_factory=dict)
    skipped_turns: list[str] = field(default_factory=list)
    infeasible: dict[str, dict[str, str]] = field(default_factory=dict)
    from_cache: bool = False
    _reach: Reachability | None = field(default=None, repr=False, compare=False)
    _facts: GraphFacts | None = field(default=None, repr=False, compare=False)

    def __getstate__(self) -> dict:
        # the graph packed apart (:meth:`packed_graph`): loading a lot unpacks it, and
        # imports networkx, only when the graph itself is read (:meth:`load_graph`);
        # a lot whose graph was never asked for passes it on as it came
        state = {k: v for k, v in self.__dict__.items() if k != "graph"}
        if "graph" in self.__dict__:
            state["_graph_packed"] = self.packed_graph()
        return state

    def packed_graph(self) -> bytes:
        """Its graph as pickling it packs it (:meth:`with_graph_packed`)."""
        return pack_graph(self.graph)

    def with_graph_packed(self, packed: bytes) -> LotGraph:
        """It as pickled with its graph packed already (:meth:`packed_graph`, made elsewhere
        meanwhile): what pickling it writes, without packing the graph again. The copy
        reads that graph when first asked for, as a lot loaded from the cache does."""
        out = object.__new__(LotGraph)
        out.__dict__.update({k: v for k, v in self.__dict__.items() if k != "graph"},
                            _graph_packed=packed)
        return out

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)

    def load_graph(self) -> None:
        """Unpack the graph of a lot loaded from pickle (:func:`unpack_graph`), if it is
        still packed: what reading :attr:`graph` does first."""
        packed = self.__dict__.pop("_graph_packed", None)
        if packed is not None:
            self.graph = unpack_graph(packed)

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
                next(leavable_edges(self), None) is not None)
        return self._facts

    def leavable(self, vehicle: str | None = None) -> frozenset[tuple[int, int]]:
        """Park edges ``(lane node, slot node)`` a car that will leave again may park by
        (:func:`~lotsim.roadmap.reach.leavable_edges`; for ``vehicle``, or for any type)."""
        return frozenset(leavable_edges(self, vehicle))

    def reachability(self) -> Reachability:
        """Free slots unreachable from each entrance, free slots that cannot reach each
        exit, and free slots that no entrance reaches or that can be parked in only where no
        exit can be reached (:func:`~lotsim.roadmap.reach.find_reachability`).

        Worked out once (the graph does not change) and kept, in the on-disk cache too."""
        if self._reach is None:
            self._reach = find_reachability(self)
        return self._reach
