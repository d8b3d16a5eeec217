"""The assembler of a lot's drivable graph (:func:`build_graph`): each lane cut into nodes
where something begins or ends on it (turns, turnarounds, gates, speed zones, the start of
each parking maneuver), the junction turns, turnarounds, U-turns and multi-point turns
between them, and each slot's park and leave edges through its planned maneuvers (or
placeholder links abeam of it, for pictures and reachability). The graph's data is
described in :mod:`lotsim.roadmap.model`."""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely

from lotsim.core.geometry import Pose, Segment, sample_segments, wrap_angle
from lotsim.core.workers import fork_map
from lotsim.lot.build import lane_collider
from lotsim.lot.kinds import kind_of
from lotsim.lot.model import DesignVehicle, Lane, Lot, Slot
from lotsim.roadmap.junction_multipoints import junction_multipoints
from lotsim.roadmap.junctions import turns_of
from lotsim.roadmap.lanes import EPS, lane_serves, path_speed_limit, portal_station
from lotsim.roadmap.memo import RoadmapMemo, designs_of, types_key
from lotsim.roadmap.model import LotGraph, ParkingLink, Turn
from lotsim.roadmap.remembered import handed_back, take_back
from lotsim.roadmap.settings import RoadmapSettings, as_settings
from lotsim.roadmap.turnarounds import Turnaround, dead_end_turnarounds
from lotsim.roadmap.uturns import junction_uturns

if TYPE_CHECKING:
    import networkx as nx


Tagged = list[tuple[Turn | Turnaround, "frozenset | None"]]
"""Turns or turnarounds, each with the vehicle types that can drive it (None: every type)."""


def build_graph(lot: Lot, *, node_spacing: float = 4.0,
                links: list[ParkingLink] | None = None, vehicles=(),
                memo: RoadmapMemo | None = None, settings: RoadmapSettings | None = None
                ) -> LotGraph:
    """Build the drivable graph of ``lot``.

    Parameters
    ----------
    lot : Lot
    node_spacing : float, keyword-only
        Largest distance between consecutive nodes along a lane [m].
    links : list of ParkingLink or None, keyword-only
        Each vehicle type's way into each slot from each lane, and out again
        (:func:`lotsim.maneuvers.links.parking_links`), recorded on the park and leave
        edges as they come; a park-only link (no way out) on its park edge's
        ``park_only``. ``None`` links slots by placeholders.
    vehicles : sequence of VehicleType, keyword-only
        The scenario's types: with two or more, junction turns are built for each type's
        own outline and turning radius, and a turn only some types can drive says which
        (edge attribute ``types``, None for all).
    memo : RoadmapMemo or None, keyword-only
        What an earlier build of ``lot``'s graph with the same settings worked out (turns,
        turnarounds); it takes what this one works out. The graph is the same without it.
    settings : RoadmapSettings or None, keyword-only
        The roadmap's tuning (:mod:`lotsim.roadmap.settings`; None: the defaults): the
        design speeds of junction turns, the turns through a junction's area, the
        multi-point search, the turnarounds.

    Returns
    -------
    LotGraph

    Raises
    ------
    SettingsError
        When ``settings`` is not a :class:`~lotsim.roadmap.settings.RoadmapSettings`, or
        ``memo`` is another lot's or was made with other settings.
    """
    settings = as_settings(settings, RoadmapSettings, "settings")
    attach = _attachments(lot) if links is None else _link_attachments(lot, links)
    memo = memo or RoadmapMemo(lot, settings=settings)
    net = _lane_network(lot, attach, node_spacing, vehicles, memo, settings)
    slot_nodes, attachments = _add_slots(lot, net, attach if links is None else None)
    if links is not None:
        _add_links(net, slot_nodes, attachments, links)
    return LotGraph(lot, net.graph, net.entrances, net.exits, slot_nodes, attachments,
                    net.skipped)


def lane_graph(lot: Lot, *, node_spacing: float = 4.0, vehicles=(),
               memo: RoadmapMemo | None = None, settings: RoadmapSettings | None = None
               ) -> LotGraph:
    """The lanes of ``lot``'s graph without its slots: the nodes, lane edges, turns,
    turnarounds and joins that :func:`build_graph` makes without maneuvers (the same nodes,
    numbered alike), with no slot node or placeholder link. Enough to find where a parking
    maneuver may begin (:func:`~lotsim.roadmap.reach.maneuver_ranges`) before any is
    planned. ``settings`` as :func:`build_graph`'s."""
    settings = as_settings(settings, RoadmapSettings, "settings")
    net = _lane_network(lot, _attachments(lot), node_spacing, vehicles,
                        memo or RoadmapMemo(lot, settings=settings), settings)
    return LotGraph(lot, net.graph, net.entrances, net.exits, {}, {}, net.skipped)


@dataclass
class _Network:
    """A lot's lanes cut into nodes (numbered lane after lane, ``first[lane]`` on; the
    stations of each lane's nodes in ``index``), with the edges between them."""

    graph: nx.DiGraph
    index: dict[str, np.ndarray]
    first: dict[str, int]
    entrances: dict[str, int]
    exits: dict[str, int]
    skipped: list[str]

    def node_at(self, lid: str, s: float) -> int:
        """The node of lane ``lid`` nearest station ``s`` [m]."""
        return self.first[lid] + int(np.argmin(np.abs(self.index[lid] - s)))


def _turns_and_turnarounds(lot: Lot, attach: dict[str, list[tuple[str, float]]], vehicles,
                     memo: RoadmapMemo, settings: RoadmapSettings
                     ) -> tuple[Tagged, Tagged, list[tuple[str, str]], list[str]]:
    """The junction turns and the turnarounds (at dead ends, multi-point junction turns,
    U-turns) of ``lot``, each with the types that can drive it, for more types first (two
    that join the same nodes keep the one more can drive); the lane joins; the notes of
    turns and turnarounds skipped. ``attach``: where cars park and unpark on each lane."""
    designs = designs_of(vehicles)
    tagged, skipped = turns_of(lot, lane_collider(lot), designs, memo, settings=settings)
    tagged.sort(key=lambda c: -len(designs or ()) if c[1] is None else -len(c[1]))
    turns = [t for t, _ in tagged]
    joins = _joins(lot)
    exits = {}
    for p in lot.exits:
        lid, st = portal_station(lot, p)
        exits[lid] = max(exits.get(lid, -math.inf), st)
    multis, uturns = junction_turnarounds(lot, tagged, designs, exits, memo, settings=settings)
    stops: dict[str, float] = {}  # per lane, the last station a car parks or unparks at
    for links in attach.values():
        for lid, st in links:
            stops[lid] = max(stops.get(lid, -math.inf), st)
    turnarounds, no_turnaround = dead_end_turnarounds(lot, turns, joins, exits, designs, stops,
                                          [t for t, _ in multis], memo, settings=settings)
    turnarounds += multis + uturns
    turnarounds.sort(key=lambda c: -len(designs or ()) if c[1] is None else -len(c[1]))
    return tagged, turnarounds, joins, skipped + no_turnaround


def _lane_network(lot: Lot, attach: dict[str, list[tuple[str, float]]], node_spacing: float,
                  vehicles, memo: RoadmapMemo, settings: RoadmapSettings) -> _Network:
    """The lanes cut into nodes no more than ``node_spacing`` apart and wherever a turn,
    turnaround, gate, speed zone or (``attach``) parking maneuver begins or ends, with the
    lane edges, turns, turnarounds and joins between them, and the gates' nodes."""
    memo.check(lot, settings)
    tagged, turnarounds, joins, skipped = _turns_and_turnarounds(lot, attach, vehicles, memo,
                                                                 settings)
    lanes = {lane.id: lane for lane in lot.lanes}
    stations: dict[str, list[float]] = {lid: [0.0, lane.length] for lid, lane in lanes.items()}
    for lid, lane in lanes.items():
        stations[lid] += [float(s) for s in lane.starts]
        stations[lid] += _zone_crossings(lot, lane)
    for t in (*(t for t, _ in tagged), *(t for t, _ in turnarounds)):
        stations[t.lane_a].append(t.station_a)
        stations[t.lane_b].append(t.station_b)
    portals = {p: portal_station(lot, p) for p in (*lot.entrances, *lot.exits)}
    for lid, s in portals.values():
        stations[lid].append(s)
    for links in attach.values():
        for lid, s in links:
            stations[lid].append(s)

    import networkx as nx  # (here: a lot loaded from the cache may never need it)

    g = nx.DiGraph()
    net = _Network(g, {}, {}, {}, {}, skipped)
    for lid, lane in lanes.items():
        st = _spaced(np.array(stations[lid]), lane.length, node_spacing)
        net.index[lid] = st
        net.first[lid] = first = g.number_of_nodes()
        poses = lane.poses_at(st)
        at, into = (a.tolist() for a in lane.locate_all(st))
        for k, s in enumerate(st):
            seg = lane.segments[at[k]]
            g.add_node(first + k, pose=poses[k], kind="lane", lane=lid, station=float(s),
                       curvature=float(seg.curvature_at(into[k])))
        for k in range(len(st) - 1):
            piece = _lane_piece(lane, at[k], into[k], float(st[k + 1]), poses[k])
            _add_edge(g, lot, first + k, first + k + 1, (piece,), "lane")
    for kind, links in (("turn", tagged), ("turnaround", turnarounds)):
        for t, types in links:
            u, v = net.node_at(t.lane_a, t.station_a), net.node_at(t.lane_b, t.station_b)
            if not g.has_edge(u, v):
                _add_edge(g, lot, u, v, t.segments, kind)
                g.edges[u, v]["types"] = types
    for a, b in joins:
        g.add_edge(net.node_at(a, lanes[a].length), net.node_at(b, 0.0), kind="join",
                   length=0.0, gear=1, path=None, speed_limit=lot.speed_limit,
                   placeholder=False)
    for gates, which, attr in ((lot.entrances, net.entrances, "entrance"),
                               (lot.exits, net.exits, "exit")):
        for p in gates:
            which[p.id] = net.node_at(*portals[p])
        for name, node in which.items():
            g.nodes[node][attr] = name
    return net


def _add_slots(lot: Lot, net: _Network, placeholders: dict[str, list[tuple[str, float]]] | None
               ) -> tuple[dict[str, int], dict[str, list[int]]]:
    """A node for each slot (slot id → node) and, with ``placeholders`` (slot id → lanes and
    stations abeam of it), its placeholder links (slot id → the lane nodes linked)."""
    g = net.graph
    slot_nodes: dict[str, int] = {}
    attachments: dict[str, list[int]] = {}
    for slot in lot.slots:
        node = g.number_of_nodes()
        slot_nodes[slot.id] = node
        cx, cy = slot.center
        g.add_node(node, pose=(cx, cy, slot.heading), kind="slot", slot=slot.id,
                   occupied=slot.id in lot.occupied, curvature=0.0)
        attachments[slot.id] = []
        if placeholders is not None:
            for lid, s in placeholders[slot.id]:
                _add_placeholder(g, lot, net.node_at(lid, s), node, slot)
                attachments[slot.id].append(net.node_at(lid, s))
    return slot_nodes, attachments


def _add_links(net: _Network, slot_nodes: dict[str, int], attachments: dict[str, list[int]],
               links: list[ParkingLink]) -> None:
    """Each slot's park and leave edges through ``links`` (a park-only link: a park edge's
    ``park_only`` maneuver, for cars that will not leave), as :func:`build_graph` records
    them."""
    g = net.graph
    order = sorted(range(len(links)), key=lambda k: (links[k].leave is None, links[k].vehicle,
                                                     links[k].slot, links[k].lane))
    for link in (links[k] for k in order):
        a, node = net.node_at(link.lane, link.station), slot_nodes[link.slot]
        if link.leave is None:
            e = _link(g, a, node, "park", link.park_gear, link.speed_limit)
            e.setdefault("park_only", {})[link.vehicle] = link.park
            e["park_only_limit"] = min(e.get("park_only_limit", math.inf), link.speed_limit)
            if link.park_time is not None:
                e.setdefault("park_only_duration", {})[link.vehicle] = link.park_time
            e["length"] = min(e["length"], link.park_length)
            continue
        if a not in attachments[link.slot]:
            attachments[link.slot].append(a)
        for u, v, kind, path, gear, length, time in (
                (a, node, "park", link.park, link.park_gear, link.park_length, link.park_time),
                (node, a, "leave", link.leave, link.leave_gear, link.leave_length,
                 link.leave_time)):
            e = _link(g, u, v, kind, gear, link.speed_limit)
            e["maneuvers"][link.vehicle] = path
            if time is not None:
                e["duration"][link.vehicle] = time
            e["length"] = min(e["length"], length)


def junction_turnarounds(lot: Lot, tagged: Tagged, designs: dict[str, DesignVehicle] | None,
                   exits: dict[str, float], memo: RoadmapMemo, *,
                   settings: RoadmapSettings | None = None) -> tuple[Tagged, Tagged]:
    """:func:`~lotsim.roadmap.junction_multipoints.junction_multipoints` and
    :func:`~lotsim.roadmap.uturns.junction_uturns`; the two at once, on the workers, when
    neither is in ``memo`` for this set of types (each is a function of its arguments: the
    same answers, kept in the memo as each keeps its own), networkx (for the graph next)
    imported meanwhile."""
    settings = as_settings(settings, RoadmapSettings, "settings")
    key = types_key(designs)
    if key not in memo.multipoints and key not in memo.uturns:
        # each kept as it keeps its own: what the workers kept went with them, but for the
        # searches they added to the memo's store, handed back
        memo.multipoints[key], memo.uturns[key] = (take_back(memo, got) for got in fork_map(
            lambda job: job(), [
                handed_back(memo, lambda: junction_multipoints(lot, tagged, designs, exits,
                                                               memo, settings=settings)),
                handed_back(memo, lambda: junction_uturns(lot, designs, memo,
                                                          settings=settings))],
            meanwhile=lambda: importlib.import_module("networkx")))  # the graph's, next
    return (junction_multipoints(lot, tagged, designs, exits, memo, settings=settings),
            junction_uturns(lot, designs, memo, settings=settings))


def _link(g: nx.DiGraph, u: int, v: int, kind: str, gear: int, limit: float) -> dict:
    """The park or leave edge ``u`` → ``v``'s attributes, made (with no maneuver yet, first
    in ``gear``) if new."""
    if not g.has_edge(u, v):
        g.add_edge(u, v, kind=kind, maneuvers={}, duration={}, length=math.inf,
                   gear=gear, path=None, speed_limit=limit,
                   placeholder=False)
    return g.edges[u, v]


def _add_placeholder(g: nx.DiGraph, lot: Lot, a: int, node: int, slot: Slot) -> None:
    ax, ay, _ = g.nodes[a]["pose"]
    cx, cy = slot.center
    reach = math.hypot(cx - ax, cy - ay)
    gear = kind_of(slot).entry_gear
    for u, v, kind in ((a, node, "park"), (node, a, "leave")):
        g.add_edge(u, v, kind=kind, length=reach, gear=gear if kind == "park" else -gear,
                   path=None, speed_limit=lot.speed_limit, placeholder=True,
                   maneuvers={}, duration={})


def _link_attachments(lot: Lot, links: list[ParkingLink]
                      ) -> dict[str, list[tuple[str, float]]]:
    """Lane and station where each link's maneuver starts, by slot."""
    out: dict[str, list[tuple[str, float]]] = {s.id: [] for s in lot.slots}
    for link in links:
        out[link.slot].append((link.lane, link.station))
    return out


def _spaced(stations: np.ndarray, length: float, spacing: float) -> np.ndarray:
    """Sorted unique stations within [0, length], with extra ones so no gap exceeds spacing."""
    st = np.unique(np.clip(stations, 0.0, length))
    st = st[np.concatenate([[True], np.diff(st) > EPS])]
    out = [st[:1]]
    for a, b in zip(st[:-1], st[1:], strict=True):
        n = max(1, math.ceil((b - a) / spacing - 1e-9))
        out.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(out)


def _lane_piece(lane: Lane, i: int, d0: float, s1: float, start: Pose) -> Segment:
    """The lane from ``d0`` into its segment ``i`` (where a station ``s0`` lies,
    :meth:`~lotsim.lot.model.Lane.locate`; ``start``: the lane's pose there) to station
    ``s1 > s0``: :meth:`~lotsim.core.geometry.Segment.piece` of that segment."""
    seg = lane.segments[i]
    # A piece ending exactly on the next segment's start still belongs to segment i.
    d1 = min(s1 - float(lane.starts[i]), seg.length)
    return Segment(start, seg.gear * (d1 - d0), seg.curvature + seg.sharpness * d0,
                   seg.sharpness)


def _path_limit(lot: Lot, path: tuple[Segment, ...]) -> float:
    """Speed limit along ``path``: the lowest zone it runs in [m/s]
    (:func:`~lotsim.roadmap.lanes.path_speed_limit`)."""
    return path_speed_limit(lot, lambda step: sample_segments(path, step)[0])


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
