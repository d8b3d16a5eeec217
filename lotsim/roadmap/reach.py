"""What a car can drive to in a lot graph, as functions of the graph: the lane nodes
reachable from an entrance and those that reach an exit, the station ranges where parking
maneuvers may begin, the park edges a car that will leave may park by, and the free slots
that cannot be reached or left (:class:`Reachability`).

Driving here means lanes, turns, joins and turnarounds only — never through a slot (a car
does not turn round in someone's parking space)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from lotsim.core.geometry import same_pose

if TYPE_CHECKING:
    from collections.abc import Iterable, Iterator

    from lotsim.roadmap.model import LotGraph


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


def spread(links: dict[int, list[int]], sources) -> set[int]:
    """``sources`` and every node reached from them by ``links`` (node → next nodes)."""
    seen = set(sources)
    todo = list(seen)
    while todo:
        for n in links.get(todo.pop(), ()):
            if n not in seen:
                seen.add(n)
                todo.append(n)
    return seen


def lane_links(lg: LotGraph, vehicle: str | None = None
               ) -> tuple[dict[int, list[int]], dict[int, list[int]]]:
    """Successors and predecessors of each node in the graph without its slot nodes:
    what a car drives between entering and parking (with ``vehicle``, without the turns
    that type cannot make)."""
    return _typed(_links(lg), vehicle)


def lane_reach(lg: LotGraph, vehicle: str | None = None, links: tuple | None = None
               ) -> tuple[set[int], set[int]]:
    """Lane nodes reachable from an entrance, and lane nodes that reach an exit (any, when
    the lot has no exits); with ``vehicle``, only by the turns that type can make
    (``links``: its :func:`lane_links`, when the caller has them)."""
    ahead, back = lane_links(lg, vehicle) if links is None else links
    come = spread(ahead, lg.entrances.values())
    go = spread(back, lg.exits.values()) if lg.exits else set(ahead)
    return come, go


def station_ranges(lg: LotGraph, nodes: set[int]) -> dict[str, tuple[float, float]]:
    """Per lane, the range of stations [m] of ``nodes`` on it."""
    g = lg.graph
    out: dict[str, tuple[float, float]] = {}
    for n in nodes:
        data = g.nodes[n]
        lo, hi = out.get(data["lane"], (math.inf, -math.inf))
        out[data["lane"]] = (min(lo, data["station"]), max(hi, data["station"]))
    return out


def reachable_ranges(lg: LotGraph) -> dict[str, tuple[float, float]]:
    """Per lane, the station range [m] of the nodes a car can reach from an entrance
    (driving lanes only): where a parking maneuver may start."""
    return station_ranges(lg, lane_reach(lg)[0])


def maneuver_ranges(lg: LotGraph) -> dict[str, tuple[tuple[float, float], ...]]:
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
    come, go = lane_reach(lg)
    reach, leave = station_ranges(lg, come), station_ranges(lg, go)
    out: dict[str, tuple[tuple[float, float], ...]] = {}
    for lid in {**leave, **reach}:
        spans = [reach[lid]] if lid in reach else []
        lo, hi = leave.get(lid, (math.inf, -math.inf))
        if lo <= hi and not any(lo <= b and a <= hi for a, b in spans):
            spans.append((lo, hi))
        out[lid] = tuple(spans)
    return out


def leavable_edges(lg: LotGraph, vehicle: str | None = None, go: set[int] | None = None
                   ) -> Iterator[tuple[int, int]]:
    """Park edges ``(lane node, slot node)`` a car that will leave again may park by, as
    found slot by slot (some more than once): its maneuver (for ``vehicle``, or for any
    type) parks it on a pose a leave edge of the same type leaves from towards a lane node
    from which an exit can be reached (any, when the lot has no exits). The leave edge need
    not end where the park edge began: a slot parked on one pose from two lanes is left
    towards either. ``go``: the lane nodes that reach an exit (:func:`lane_reach`), when
    the caller has them."""
    go = lane_reach(lg, vehicle)[1] if go is None else go
    return _leavable(_slot_poses(lg), vehicle, go)


def _slot_poses(lg: LotGraph) -> Iterator[tuple[int, list, list]]:
    """Each slot node with its park edges (lane node, type → the pose its maneuver parks
    on, whether it is a placeholder) and its leave edges (lane node, type → the pose its
    maneuver leaves from, whether it is a placeholder), slot by slot."""
    g = lg.graph
    for node in lg.slot_nodes.values():
        parks = [(u, {name: m.end for name, m in d["maneuvers"].items()},
                  bool(d.get("placeholder")))
                 for u, _, d in g.in_edges(node, data=True) if d["kind"] == "park"]
        leaves = [(w, {name: m.start for name, m in d["maneuvers"].items()},
                   bool(d.get("placeholder")))
                  for _, w, d in g.out_edges(node, data=True) if d["kind"] == "leave"]
        yield node, parks, leaves


def _leavable(slots: Iterable[tuple[int, list, list]], vehicle: str | None, go: set[int]
              ) -> Iterator[tuple[int, int]]:
    """:func:`leavable_edges` of the slots of :func:`_slot_poses`."""
    for node, parks, leaves in slots:
        leaves = [x for x in leaves if x[0] in go]
        away = [(name, pose) for _, starts, _ in leaves for name, pose in starts.items()
                if vehicle in (None, name)]
        placeholder = any(ph for *_, ph in leaves)  # no poses: any way out
        for u, ends, ph in parks:
            if (placeholder and ph) or any(
                    same_pose(ends[who], pose) for who, pose in away if who in ends):
                yield u, node


def _links(lg: LotGraph) -> tuple[dict[int, list[int]], dict[int, list[int]],
                                  list[tuple[int, int, frozenset[str]]]]:
    """:func:`lane_links` by the edges every type drives, and the edges only some types
    drive (from, to, those types), in one pass over the graph."""
    nodes = lg.graph.nodes
    ahead: dict[int, list[int]] = {}
    back: dict[int, list[int]] = {}
    some = []
    for u, nbrs in lg.graph.adj.items():
        if nodes[u]["kind"] == "slot":
            continue
        ahead.setdefault(u, [])
        back.setdefault(u, [])
        for v, d in nbrs.items():
            if nodes[v]["kind"] == "slot":
                continue
            if d.get("types") is not None:
                some.append((u, v, d["types"]))
            else:
                ahead[u].append(v)
                back.setdefault(v, []).append(u)
    return ahead, back, some


def _typed(links: tuple, vehicle: str | None) -> tuple[dict[int, list[int]],
                                                       dict[int, list[int]]]:
    """:func:`lane_links` from :func:`_links`' ``links``: the links every type drives and,
    of the edges only some types drive, those ``vehicle`` drives (all of them for None)."""
    ahead, back, some = links
    own = [(u, v) for u, v, types in some if vehicle is None or vehicle in types]
    return _with(ahead, own), _with(back, ((v, u) for u, v in own))


def _with(links: dict[int, list[int]], more: Iterable[tuple[int, int]]
          ) -> dict[int, list[int]]:
    """``links`` (node → next nodes) with the links ``more`` (node, next node) too."""
    out = dict(links)
    for u, v in more:
        out[u] = [*out.get(u, ()), v]
    return out


def find_reachability(lg: LotGraph) -> Reachability:
    """Free slots unreachable from each entrance, free slots that cannot reach each exit,
    and free slots that no entrance reaches or that can be parked in only where no exit
    can be reached (driving lanes, turns, joins and turnarounds, into the slot or out of it
    at the end); the same for each vehicle type with its own turns. Cars parked at start
    never move, so taken slots are not listed."""
    g = lg.graph
    free = [s.id for s in lg.lot.free_slots]
    # the links every type drives, and a type's own turns and turnarounds (its links are
    # every type's where no turn or turnaround is for some only)
    links = _links(lg)
    ahead, back = _typed(links, None)
    reaches: dict[str | None, tuple[set[int], set[int]]] = {}

    def reach(vehicle: str | None) -> tuple[set[int], set[int]]:
        key = vehicle if links[2] else None
        if key not in reaches:
            reaches[key] = lane_reach(lg, key, (ahead, back) if key is None
                                      else _typed(links, key))
        return reaches[key]

    def missing(seen: set[int], links) -> list[str]:
        return [sid for sid in free if not any(n in seen for n in links(lg.slot_nodes[sid]))]

    unreachable = {name: missing(spread(ahead, [node]), g.predecessors)
                   for name, node in lg.entrances.items()}
    stranded = {name: missing(spread(back, [node]), g.successors)
                for name, node in lg.exits.items()}
    come, go = reach(None)
    no_way_in = missing(come, g.predecessors)

    def parks_to_leave(out: frozenset[tuple[int, int]], seen: set[int], sid: str) -> bool:
        """Whether a car coming to a node of ``seen`` parks in ``sid`` by a park edge
        in ``out`` (:func:`leavable_edges`: it leaves from that pose towards an exit)."""
        node = lg.slot_nodes[sid]
        return any(u in seen and (u, node) in out for u in g.predecessors(node))

    # a car leaves from the pose it parked on, by any leave edge from there
    slots = list(_slot_poses(lg))  # each pose read once
    out = frozenset(_leavable(slots, None, go))
    no_way_out = [sid for sid in free
                  if sid not in no_way_in and not parks_to_leave(out, come, sid)]
    by_type = {}
    for name in sorted({v for _, _, d in g.edges(data=True) if d["kind"] == "park"
                        for v in d["maneuvers"]}):
        come, go = reach(name)
        fits = {sid for sid in free if any(
            name in g.edges[u, lg.slot_nodes[sid]]["maneuvers"]
            for u in g.predecessors(lg.slot_nodes[sid]))}

        def parks_from(seen: set[int], sid: str, name: str = name) -> bool:
            node = lg.slot_nodes[sid]
            return any(u in seen and name in g.edges[u, node]["maneuvers"]
                       for u in g.predecessors(node))

        no_in = [sid for sid in free if sid in fits and not parks_from(come, sid)]
        out = frozenset(_leavable(slots, name, go))  # park edges with a maneuver for it
        no_out = [sid for sid in free if sid in fits and sid not in no_in
                  and not parks_to_leave(out, come, sid)]
        by_type[name] = (no_in, no_out)
    return Reachability(unreachable, stranded, no_way_in, no_way_out, by_type)
