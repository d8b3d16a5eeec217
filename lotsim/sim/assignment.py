"""Slot choice: which free slot a car tries first, and which next.

The policy (:data:`lotsim.sim.settings.ASSIGNMENTS`) ranks the free slots a car can use:
``nearest`` by straight-line distance from its entrance, ``shortest`` by static travel time
along the graph plus the maneuver (and, for a car that will leave, the way out to the
nearest exit). A car then looks first at a few of them (:class:`~lotsim.sim.settings.RunTuning`):
its best, then the best in each other aisle, those in aisles where a look just ran out last.
The event loop (:mod:`lotsim.sim.loop`) and the shortest-first planning order
(:func:`lotsim.sim.orders.shortest_first`) share one :class:`SlotAssigner`'s timings.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

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
    policy : {"nearest", "shortest"}
        How slots are ranked.
    tuning : RunTuning
        How many slots a car first looks at, their budgets and how long an aisle where a
        look ran out stays jammed.

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
        self._jammed: dict[str, float] = {}  # aisle → when a first look there last ran out

    # -- ranking ------------------------------------------------------------------------------
    def ranked(self, arrival: Arrival, free: Iterable[str]) -> list[str]:
        """The slots of ``free`` that ``arrival``'s car can park in (and leave again, if it
        will), best first by the policy, ties by slot id."""
        times = self.slot_times(arrival.entrance, arrival.vehicle, arrival.dwell is not None)
        usable = [s for s in free if s in times]
        if self.policy == "shortest":
            return sorted(usable, key=lambda s: (times[s], s))
        x, y, _ = self.lg.graph.nodes[self.lg.entrances[arrival.entrance]]["pose"]
        slots = self.lg.lot.slot_by_id
        return sorted(usable, key=lambda s: (math.dist((x, y), slots[s].center), s))

    def slot_times(self, gate: str, vname: str, leaving: bool) -> dict[str, float]:
        """Static time [s] from entrance ``gate`` into each slot a ``vname`` can use and, if
        ``leaving``, out of it again (by any way out from the pose it parks on) to the
        nearest exit: a car that will leave counts the way out as well as the way in."""
        key = (gate, vname, leaving)
        if key not in self._times:
            sg = self.graphs[vname]
            dist = sg.forward_times(self.lg.entrances[gate])
            to_exit = (sg.reverse_search({n: 0.0 for n in self.lg.exits.values()})
                       if leaving else None)
            out: dict[str, float] = {}
            for i, e in enumerate(sg.edges):
                if e.kind == "park" and e.u in dist and (
                        not leaving or ((e.u, e.v) in self.leave[vname] and not e.stay)):
                    sid = self.lg.graph.nodes[e.v]["slot"]
                    tt = dist[e.u] + e.duration
                    if to_exit is not None:
                        tt += _way_out(sg, i, to_exit)
                    out[sid] = min(out.get(sid, math.inf), tt)
            self._times[key] = out
        return self._times[key]

    # -- the first looks ----------------------------------------------------------------------
    def first_looks(self, ranked: list[str], t: float) -> list[str]:
        """The slots of ``ranked`` a car looks at first at time ``t`` [s]: the few best
        (:meth:`few`), those in jammed aisles (:meth:`unjammed_first`) after the others."""
        return self.few(self.unjammed_first(ranked, t))

    def look_budget(self, static: float) -> int:
        """Expansions of a first look into a slot ``static`` seconds of static time from the
        car: ``first_look_rate`` a second, at least ``first_look``."""
        tuning = self.tuning
        if math.isinf(static):
            return tuning.first_look
        return max(tuning.first_look, round(tuning.first_look_rate * static))

    def ran_out(self, sid: str, t: float) -> None:
        """A first look into slot ``sid`` ran out at ``t`` [s]: its aisle is jammed for
        ``jammed_for`` seconds."""
        self._jammed[self.lg.lot.slot_by_id[sid].aisle] = t

    def unjammed_first(self, options: list[str], t: float) -> list[str]:
        """``options`` (a ranked slot list) with the slots in aisles jammed at ``t`` [s] (a
        first look there ran out less than ``jammed_for`` before) moved after the others,
        each part in rank order."""
        slots = self.lg.lot.slot_by_id
        late = {aisle for aisle, when in self._jammed.items()
                if t - when < self.tuning.jammed_for}
        if not late:
            return options
        return ([sid for sid in options if slots[sid].aisle not in late]
                + [sid for sid in options if slots[sid].aisle in late])

    def few(self, options: list[str]) -> list[str]:
        """The best of ``options`` (a ranked slot list), then the best in each other aisle,
        then the next best, ``first_looks`` in all: when the best cannot be reached in time
        (its aisle is busy with cars parking), its neighbours seldom can, and another aisle
        often can."""
        n = self.tuning.first_looks
        slots = self.lg.lot.slot_by_id
        out, seen = [], set()
        for sid in options:
            if slots[sid].aisle not in seen:
                seen.add(slots[sid].aisle)
                out.append(sid)
                if len(out) == n:
                    return out
        return out + [sid for sid in options if sid not in out][:n - len(out)]


def _way_out(sg: SearchGraph, park: int, to_exit) -> float:
    """Static time [s] from the pose park edge ``park`` leaves the car on, by a leave edge
    that begins there, to the nearest exit."""
    pose = sg.parked_pose(park)
    best = math.inf
    for j in sg.out[sg.edges[park].v]:
        e = sg.edges[j]
        if e.kind == "leave" and same_pose(sg.parked_pose(j), pose):
            best = min(best, e.duration + to_exit(e.v))
    return best
