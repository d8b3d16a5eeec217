"""Slot choice: which free slot a car tries first, and which next.

The policy (:data:`lotsim.sim.settings.ASSIGNMENTS`) ranks the free slots a car can use:
``nearest`` by straight-line distance from its entrance, ``shortest`` by static travel time
along the graph plus the maneuver (and, for a car that will leave, the way out to the
nearest exit), ``priced`` by that time plus the delay the car's maneuvers are expected to
cause the cars that pass the slot (:meth:`SlotAssigner.prices`: the slots at a lot's
throat, which every car passes, cost the more the busier the gate). A car then looks
first at a few of them (:class:`~lotsim.sim.settings.RunTuning`): its best, then the
best in each other aisle, those in aisles where a probe just ran out last. The event loop
(:mod:`lotsim.sim.loop`) and the shortest-first planning order
(:func:`lotsim.sim.orders.shortest_first`) share one :class:`SlotAssigner`'s timings.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Iterable, Sequence

import numpy as np

from lotsim.core.geometry import same_pose
from lotsim.roadmap.model import LotGraph
from lotsim.sim.settings import RunTuning
from lotsim.traffic.demand import Arrival
from lotsim.traffic.searchgraph import SearchGraph, SearchGraphMemo, search_graph
from lotsim.traffic.settings import SearchSettings
from lotsim.vehicles.model import VehicleType


class SlotAssigner:
    """Slot choice for the cars of one run in ``lot_graph``.

    Parameters
    ----------
    lot_graph : LotGraph
        The prepared lot.
    vehicle_types : sequence of VehicleType
        The types that drive in it (each gets its search graph and the park edges it can
        leave again by).
    policy : {"nearest", "shortest", "priced"}
        How slots are ranked.
    tuning : RunTuning
        How many slots a car probes, their budgets, how long an aisle where a probe
        ran out stays congested, and over how long a ``priced`` ranking sees the flows.

    Attributes
    ----------
    graphs : dict of str to SearchGraph
        Each type's search graph, by type name.
    leave : dict of str to set
        Each type's park edges it can leave the slot by for an exit, by type name.
    """

    def __init__(self, lot_graph: LotGraph, vehicle_types: Sequence[VehicleType], *,
                 policy: str = "shortest", tuning: RunTuning | None = None,
                 search: SearchSettings | None = None,
                 memo: SearchGraphMemo | None = None) -> None:
        self.lg = lot_graph
        self.policy = policy
        self.tuning = tuning or RunTuning()
        self.graphs = {t.name: search_graph(lot_graph, t, memo, settings=search)
                       for t in vehicle_types}
        self.leave = {t.name: lot_graph.leavable(t.name) for t in vehicle_types}
        self._times: dict[tuple[str, str, bool], dict[str, float]] = {}
        self._ways: dict[tuple[str, str, bool], dict[str, tuple[float, int, int | None]]] = {}
        self._congested: dict[str, float] = {}  # aisle → when a probe there last ran out
        self._seen: dict[str | None, list[float]] = {}  # entrance (None: out) → times
        self._terms: dict[tuple[str, str, bool], dict[str, dict[str | None, float]]] = {}
        self._share: dict[tuple[str, str | None], dict[int, float]] = {}
        self.starts: dict[str, int] = {}  # car id → the lane node a car on a lane sets off from

    # -- ranking ------------------------------------------------------------------------------
    def ranked(self, arrival: Arrival, free: Iterable[str], t: float | None = None, *,
               by: str | None = None) -> list[str]:
        """The slots of ``free`` that ``arrival``'s car can park in (and leave again, if it
        will), best first by the policy ``by`` (the assigner's, if None) at time ``t`` [s]
        (the arrival's, if None), ties by slot id."""
        leaving = arrival.dwell is not None
        start = self.origin(arrival)
        times = self.slot_times(start, arrival.vehicle, leaving)
        usable = [s for s in free if s in times]
        by = by or self.policy
        if by == "shortest":
            return sorted(usable, key=lambda s: (times[s], s))
        if by == "priced":
            price = self.prices(start, arrival.vehicle, leaving,
                                arrival.time if t is None else t)
            return sorted(usable, key=lambda s: (times[s] + price.get(s, 0.0), s))
        x, y, _ = self.lg.graph.nodes[self.node_of(start)]["pose"]
        slots = self.lg.lot.slot_by_id
        return sorted(usable, key=lambda s: (math.dist((x, y), slots[s].center), s))

    def origin(self, arrival: Arrival) -> str | int:
        """Where ``arrival``'s car sets off for a slot: its entrance, or (a car already on a
        lane) the lane node it stands at (:attr:`starts`)."""
        return self.starts.get(arrival.id, arrival.entrance)

    def node_of(self, start: str | int) -> int:
        """The graph node of ``start``: an entrance's name, or a node."""
        return start if isinstance(start, int) else self.lg.entrances[start]

    def slot_times(self, gate: str | int, vname: str, leaving: bool) -> dict[str, float]:
        """Static time [s] from entrance ``gate`` (or from lane node ``gate``) into each
        slot a ``vname`` can use and, if
        ``leaving``, out of it again (by any way out from the pose it parks on) to the
        nearest exit: a car that will leave counts the way out as well as the way in."""
        key = (gate, vname, leaving)
        if key not in self._times:  # asked at every arrival: kept
            self._times[key] = {sid: tt for sid, (tt, _, _)
                                in self.slot_ways(gate, vname, leaving).items()}
        return self._times[key]

    def slot_ways(self, gate: str | int, vname: str, leaving: bool
                  ) -> dict[str, tuple[float, int, int | None]]:
        """For each slot a ``vname`` from entrance ``gate`` can use, :meth:`slot_times`'s
        time [s] with the park edge and (if ``leaving``) the leave edge of that way, as
        edge indices of the type's search graph (the first in edge order of equal time)."""
        key = (gate, vname, leaving)
        if key not in self._ways:
            sg = self.graphs[vname]
            dist = sg.forward_times(self.node_of(gate))
            to_exit = (sg.reverse_search({n: 0.0 for n in self.lg.exits.values()})
                       if leaving else None)
            out: dict[str, tuple[float, int, int | None]] = {}
            for i, e in enumerate(sg.edges):
                if e.kind == "park" and e.u in dist and (
                        not leaving or ((e.u, e.v) in self.leave[vname] and not e.park_only)):
                    sid = self.lg.graph.nodes[e.v]["slot"]
                    tt, way_out = dist[e.u] + e.duration, None
                    if to_exit is not None:
                        t_out, way_out = _way_out(sg, i, to_exit)
                        tt += t_out
                    if tt < out.get(sid, (math.inf,))[0]:
                        out[sid] = (tt, i, way_out)
            self._ways[key] = out
        return self._ways[key]

    # -- the price of a slot to the others ----------------------------------------------------
    def saw(self, gate: str | None, t: float) -> None:
        """A car came in at entrance ``gate`` (None: one set off out) at ``t`` [s]: the flows
        :meth:`prices` reckons with are those seen over the last ``tuning.flow_window``."""
        bisect.insort(self._seen.setdefault(gate, []), t)

    def flows(self, t: float) -> dict[str | None, float]:
        """Cars a second seen at each entrance (None: setting off out) over the
        ``tuning.flow_window`` seconds up to ``t`` [s]."""
        w = self.tuning.flow_window
        return {g: (bisect.bisect_right(ts, t) - bisect.bisect_right(ts, t - w)) / w
                for g, ts in self._seen.items()}

    def prices(self, gate: str | int, vname: str, leaving: bool, t: float) -> dict[str, float]:
        """The delay [s] a ``vname`` from ``gate`` is expected to cause the other cars by
        parking in each slot (and leaving it again, if ``leaving``), at time ``t`` [s].

        While a maneuver of ``d`` seconds holds a stretch of lane, the cars that come by
        at a rate ``f`` wait for it, ``d / 2`` on average: ``f d² / 2`` seconds in all.
        The rate past a lane node is the flow seen at each entrance (:meth:`flows`) times
        the share of the slots whose shortest way in from there passes the node, plus the
        flow seen setting off out times the share of the slots whose shortest way out does;
        a maneuver's stretch is every lane node within half the car's length of its path's
        box, and its rate the highest of theirs. Slots are counted alike (each as likely a
        goal): a prior, not the run's own choices."""
        flows = self.flows(t)
        if not any(flows.values()):
            return {}
        terms = self._price_terms(gate, vname, leaving)
        out: dict[str, float] = {}
        for sid, by in terms.items():
            out[sid] = sum(flows.get(g, 0.0) * c for g, c in by.items())
        return out

    def _price_terms(self, gate: str | int, vname: str, leaving: bool
                     ) -> dict[str, dict[str | None, float]]:
        """For each slot, :meth:`prices`' sum of ``share × d² / 2`` over the slot's
        maneuvers, by the flow (entrance, or None for the way out) it is multiplied by."""
        key = (gate, vname, leaving)
        if key not in self._terms:
            sg = self.graphs[vname]
            shares = {g: self.route_shares(vname, g) for g in self.lg.entrances}
            shares[None] = self.route_shares(vname, None)
            ids = np.array(sorted(set().union(*shares.values())), dtype=int)
            xy = np.array([sg.pose[n][:2] for n in ids]).reshape(-1, 2)
            table = {g: np.array([sh.get(n, 0.0) for n in ids]) for g, sh in shares.items()}
            reach = sg.vehicle.length / 2
            out: dict[str, dict[str | None, float]] = {}
            for sid, (_, park, leave) in self.slot_ways(gate, vname, leaving).items():
                terms: dict[str | None, float] = dict.fromkeys(table, 0.0)
                for ei in (park, leave):
                    if ei is None:
                        continue  # a car that stays: no way out
                    e = sg.edges[ei]
                    pts = np.array([p[:2] for p in _path_points(e.maneuver)])
                    lo, hi = pts.min(axis=0) - reach, pts.max(axis=0) + reach
                    held = np.all((xy >= lo) & (xy <= hi), axis=1)
                    if held.any():
                        for g, sh in table.items():
                            terms[g] += float(sh[held].max()) * e.duration ** 2 / 2
                out[sid] = terms
            self._terms[key] = out
        return self._terms[key]

    def route_shares(self, vname: str, gate: str | None) -> dict[int, float]:
        """Share of the slots a ``vname`` can use whose shortest way in from entrance
        ``gate`` (None: whose shortest way out to the nearest exit) passes each lane node."""
        key = (vname, gate)
        if key not in self._share:
            sg = self.graphs[vname]
            lg = self.lg
            if gate is not None:
                dist, by = sg.forward_tree(lg.entrances[gate], express=False)
                ends = {sid: sg.edges[p].u
                        for sid, (_, p, _) in self.slot_ways(gate, vname, False).items()}
                nxt = {n: sg.edges[ei].u for n, ei in by.items()}
            else:
                dist, by = sg.backward_tree(lg.exits.values(), express=False)
                ends = {}
                for sid, (_, _, leave) in self.slot_ways(
                        min(lg.entrances), vname, True).items():
                    if leave is not None:
                        ends[sid] = sg.edges[leave].v
                nxt = {n: sg.edges[ei].v for n, ei in by.items()}
            count: dict[int, float] = {}
            for n in ends.values():
                count[n] = count.get(n, 0.0) + 1.0
            for n in _leaves_first(nxt):  # each route's count passed on towards its root
                if n in count:
                    count[nxt[n]] = count.get(nxt[n], 0.0) + count[n]
            total = max(len(ends), 1)
            self._share[key] = {n: c / total for n, c in count.items()
                                if n not in sg.slot_nodes}
        return self._share[key]

    # -- the probes ---------------------------------------------------------------------------
    def probes(self, ranked: list[str], t: float) -> list[str]:
        """The slots of ``ranked`` a car probes at time ``t`` [s]: the few best
        (:meth:`few`), those in congested aisles (:meth:`uncongested_first`) after the others."""
        return self.few(self.uncongested_first(ranked, t))

    def probe_budget(self, static: float) -> int:
        """Expansions of a probe into a slot ``static`` seconds of static time from the
        car: ``probe_rate`` a second, at least ``probe_floor``."""
        tuning = self.tuning
        if math.isinf(static):
            return tuning.probe_floor
        return max(tuning.probe_floor, round(tuning.probe_rate * static))

    def ran_out(self, sid: str, t: float) -> None:
        """A probe into slot ``sid`` ran out at ``t`` [s]: its aisle is congested for
        ``congested_for`` seconds."""
        self._congested[self.lg.lot.slot_by_id[sid].aisle] = t

    def uncongested_first(self, options: list[str], t: float) -> list[str]:
        """``options`` (a ranked slot list) with the slots in aisles congested at ``t`` [s]
        (a probe there ran out less than ``congested_for`` before) moved after the others,
        each part in rank order."""
        slots = self.lg.lot.slot_by_id
        late = {aisle for aisle, when in self._congested.items()
                if t - when < self.tuning.congested_for}
        if not late:
            return options
        return ([sid for sid in options if slots[sid].aisle not in late]
                + [sid for sid in options if slots[sid].aisle in late])

    def few(self, options: list[str]) -> list[str]:
        """The best of ``options`` (a ranked slot list), then the best in each other aisle,
        then the next best, ``probes`` in all: when the best cannot be reached in time
        (its aisle is busy with cars parking), its neighbours seldom can, and another aisle
        often can."""
        n = self.tuning.probes
        slots = self.lg.lot.slot_by_id
        out, seen = [], set()
        for sid in options:
            if slots[sid].aisle not in seen:
                seen.add(slots[sid].aisle)
                out.append(sid)
                if len(out) == n:
                    return out
        return out + [sid for sid in options if sid not in out][:n - len(out)]


def _way_out(sg: SearchGraph, park: int, to_exit) -> tuple[float, int | None]:
    """Static time [s] from the pose park edge ``park`` leaves the car on, by a leave edge
    that begins there, to the nearest exit, and that leave edge (the first of equal time;
    None if there is none)."""
    pose = sg.parked_pose(park)
    best, by = math.inf, None
    for j in sg.out[sg.edges[park].v]:
        e = sg.edges[j]
        if e.kind == "leave" and same_pose(sg.parked_pose(j), pose):
            tt = e.duration + to_exit(e.v)
            if tt < best:
                best, by = tt, j
    return best, by


def _leaves_first(nxt: dict[int, int]) -> list[int]:
    """The nodes of the tree ``nxt`` (node → the next towards its root), each before the
    one it leads to."""
    depth: dict[int, int] = {}
    for n in nxt:
        path = []
        while n in nxt and n not in depth:
            path.append(n)
            n = nxt[n]
        d = depth.get(n, 0)
        for m in reversed(path):
            d += 1
            depth[m] = d
    return sorted(nxt, key=lambda n: (-depth[n], n))


def _path_points(maneuver) -> list:
    """The poses a maneuver's pieces begin and end at."""
    return [seg.start for seg in maneuver.segments] + [maneuver.end]
