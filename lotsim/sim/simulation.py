"""The simulation pipeline, scenario in, results out.

:func:`prepare` builds a scenario's lot, plans every slot's maneuvers and the
drivable graph; :func:`run` plans the scenario's traffic through it.
"""

from __future__ import annotations

import dataclasses
import gc
import heapq
import math
import time
from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np

from lotsim.core.geometry import same_pose
from lotsim.core.outcome import Status
from lotsim.errors import Location, ScenarioError, SettingsError
from lotsim.roadmap.graph import LotGraph, Reachability
from lotsim.scenario import Scenario
from lotsim.sim.preparation import prepare
from lotsim.sim.settings import RunSettings
from lotsim.traffic.demand import Arrival, arrivals
from lotsim.traffic.heuristic import ReverseResumable
from lotsim.traffic.plans import Move, Plan, reserve_moves
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.search import Goal, SearchRequest, search
from lotsim.traffic.searchgraph import SearchGraph, search_graph
from lotsim.traffic.swept import standing_body
from lotsim.vehicles.model import VehicleType
from lotsim.vehicles.motion import Trajectory

# -- running traffic -------------------------------------------------------------------------
SAMPLE_DT = 0.05
"""Interval of the samples of a moving vehicle in a run's result [s]."""
STATUSES = ("parked", "departed", "waiting", "rejected")
FIRST_LOOK = 400
"""Fewest expansions a car's first look at each of its few best slots gets, before the full
searches (see :data:`FIRST_LOOK_RATE`)."""
FIRST_LOOK_RATE = 8.0
"""Expansions a first look gets per second of the slot's static time from the entrance
(at least :data:`FIRST_LOOK`). A slot the car can reach without a long wait is found well
within this, so a car does not queue behind cars parking in its best slot's aisle while a
slot in another aisle is free to reach; a far slot gets a budget as long as its way.
Measured on the large lot with HCA*, against a fixed 1000 expansions: 1000 cars at 1200/h
staying 10–30 min planned in 51 s against 66 s and parked after 60.9 s against 64.0 s on
average; 300 such cars 17 s against 31 s, parked after 51.6 s against 60.1 s; the
``large_lot_load`` suite (150 cars that stay, 300 to 2400/h, two seeds) parked 0.2–2.8 %
sooner on each of its 12 runs with as many expansions in all. A fixed budget did worse somewhere:
1000 wasted a third of the 1000-car planning on looks that ran out, and 250 (or 250 plus 5
per second) parked the load suite's cars up to 4.8 % later at 1000–1200/h."""

JAMMED_FOR = 5.0
"""How long [s] an aisle counts as jammed after a car's first look at a slot in it ran out:
meanwhile the next cars look first at their best slots in the other aisles
(:meth:`_Simulation.unjammed_first`), and at its slots only after those. With 1000 cars at
1200/h into the large lot, staying 10-30 min, a first look into an aisle where one had run
out less than 5 s before ran out 71 % of the time, against 23 % elsewhere, and the looks
that ran out took a third of the planning. Measured against no such rule: those 1000 cars
planned in 26.7 s against 34.9 s and parked after 58.8 s against 60.9 s on average; with
other seeds and rates (300 cars at 1200/h, three seeds; 300 at 2400/h; 1000 at 1200/h,
another seed) they parked 1.9-4.1 % sooner on every run, with 0.45-0.69 of the
expansions; the ``large_lot_load`` suite (150 cars that stay, 300 to 2400/h, two seeds)
took 0.69 of the expansions and 0.75 of the planning time in all, its runs parking 0.8 %
sooner to 1.4 % later (later by over 0.1 % only at 1200/h and over, where cars queue
at the gate).
Longer spans saved no more and parked the cars that stay later: up to 3.2 % with 10 s,
7 % with 20 s."""

RUN_GC_THRESHOLDS = (20_000, 20, 1000)
"""The cycle collector's thresholds while a run plans (Python's are 700, 10, 10): it still
collects, in larger batches, and seldom scans everything. A run makes millions of objects
and almost no cycles: 1000 cars into the large lot made 855 objects in cycles in all, and
Python's collector passed 5278 times to find them (27 of those over everything, finding
none), 10-14 % of the run's time (planning 56.6 and 57.0 s against 49.8 s with these; the
same peak memory, 408 MB, and the same plans)."""

HEURISTICS_KEPT = 16
"""Reverse searches towards a slot a run keeps for later searches there (each holds up to a
few hundred kB on the large lot). With 300 cars into the large lot, staying 10-30 min, 16
kept closed 1 035 114 nodes in all, as few as 64 kept did, against 1 536 370 with none."""


@dataclass
class VehicleRun:
    """One vehicle's part of a run."""

    arrival: Arrival
    vehicle: VehicleType
    slot: str | None = None
    status: str = "waiting"
    reason: str = ""
    moves: list[Move] = field(default_factory=list)
    parked_at: float | None = None
    parked_pose: tuple[float, float, float] | None = None
    depart_at: float | None = None
    leaving: bool = False
    left_at: float | None = None
    searches: int = 0
    failures: int = 0  # failed searches in a row
    expansions: int = 0
    planning_time: float = 0.0
    done: bool = False  # nothing more will happen to it
    seen: int = 0  # the reservation table's releases when it last searched

    @property
    def id(self) -> str:
        return self.arrival.id


@dataclass
class RunResult:
    """What :func:`run` returns: the lot, the settings and every vehicle's story."""

    scenario: Scenario
    lot_graph: LotGraph
    settings: RunSettings
    seed: int
    vehicles: list[VehicleRun]
    planning_time: float
    ordering: dict = field(default_factory=dict)
    """How the planning order was chosen (:func:`lotsim.sim.orders.plan_run`); empty when
    :func:`run` was called directly."""

    def metrics(self) -> dict[str, float]:
        """Counts by status and the timing figures of ``docs/result.md``."""
        out: dict[str, float] = {s: 0 for s in STATUSES}
        for v in self.vehicles:
            out[v.status] += 1
        out["vehicles"] = len(self.vehicles)
        park = [v.parked_at - v.arrival.time for v in self.vehicles if v.parked_at is not None]
        out["mean_time_to_park"] = float(np.mean(park)) if park else 0.0
        out["max_time_to_park"] = float(np.max(park)) if park else 0.0
        out["total_waiting"] = float(sum(m.t1 - m.t0 for v in self.vehicles for m in v.moves
                                         if m.kind in ("wait", "outside"))
                                     + sum(_queued(v) for v in self.vehicles)
                                     + sum(self.scenario.traffic.patience  # turned away
                                           for v in self.vehicles if v.status == "rejected"))
        ends = [v.moves[-1].t1 for v in self.vehicles if v.moves]
        out["makespan"] = float(max(ends)) if ends else 0.0
        out["planning_time"] = self.planning_time
        out["expansions"] = int(sum(v.expansions for v in self.vehicles))
        out["searches"] = int(sum(v.searches for v in self.vehicles))
        per = [v.planning_time for v in self.vehicles if v.searches]
        out["planning_time_median"] = float(np.median(per)) if per else 0.0
        out["planning_time_p95"] = float(np.percentile(per, 95)) if per else 0.0
        return out


def _queued(v: VehicleRun) -> float:
    """Time spent queued outside before the plan that brought it in began [s]."""
    start = next((m.t0 for m in v.moves), None)
    if start is None:
        return 0.0
    return max(0.0, start - v.arrival.time)


def check_traffic(lg: LotGraph, traffic: list[Arrival], reach: Reachability | None = None
                  ) -> None:
    """Refuse traffic the lot cannot serve at all: a type that fits no slot, an
    entrance with no route to a slot, dwell times in a lot with no exit. ``reach`` is
    ``lg.reachability()`` when the caller has it already.

    Raises
    ------
    ScenarioError
        Located at the vehicle or stream that asks for it.
    """
    facts = lg.facts()
    for name in sorted({a.vehicle for a in traffic}):
        who = next(a for a in traffic if a.vehicle == name)
        if name not in facts.parks:
            reasons = sorted(set(lg.infeasible.get(name, {}).values()))
            why = f" ({reasons[0]})" if reasons else ""
            raise ScenarioError(who.where, f"vehicle type {name!r} fits no slot of this "
                                           f"lot{why}")
    reach = reach or lg.reachability()
    for name in sorted({a.vehicle for a in traffic}):
        no_in, no_out = reach.by_type.get(name, ([], []))
        fits = {sid for sid in (s.id for s in lg.lot.free_slots)
                if sid not in lg.infeasible.get(name, {})}
        mine = [a for a in traffic if a.vehicle == name]
        if fits and fits <= set(no_in):
            raise ScenarioError(mine[0].where, f"vehicle type {name!r} can reach none of the "
                                               f"free slots it fits (no turns it can make "
                                               f"lead there)")
        leaving = [a for a in mine if a.dwell is not None]
        if leaving and lg.exits and fits and fits <= set(no_in) | set(no_out):
            raise ScenarioError(leaving[0].where, f"vehicle type {name!r} can leave none of "
                                                  f"the free slots it reaches for an exit")
    unreachable = reach.unreachable
    free = len(lg.lot.free_slots)
    for gate in sorted({a.entrance for a in traffic}):
        # a full lot is no bad input: its cars are turned away ("the lot is full")
        if free and len(unreachable[gate]) == free:
            who = next(a for a in traffic if a.entrance == gate)
            raise ScenarioError(who.where, f"no route from entrance {gate!r} to a free slot")
    leaving = [a for a in traffic if a.dwell is not None]
    if leaving and not lg.exits:
        raise ScenarioError(leaving[0].where, "vehicles have dwell times but the lot has no "
                                              "exit to leave by")
    if leaving and not facts.leavable:
        raise ScenarioError(leaving[0].where, "vehicles have dwell times but no slot can "
                                              "be left for an exit along the lanes")


def require_traffic(scenario: Scenario) -> None:
    """Refuse to run a scenario that only describes a lot.

    Raises
    ------
    ScenarioError
        At the top of its file, when the scenario has no ``traffic`` section.
    """
    if scenario.traffic is None:
        raise ScenarioError(Location(scenario.source, 1, 1), "the scenario has no 'traffic' "
                                                              "section to run (see "
                                                              "docs/scenario.md)")


def run(scenario: Scenario, settings: RunSettings | None = None, *, lot_graph=None,
        progress=None) -> RunResult:
    """Plan the scenario's traffic: assign slots, plan every vehicle in, and out again.

    Vehicles are planned one after another in arrival order (their priority),
    or in ``settings.order`` when the traffic is booked in advance, each against
    the reservations of those before it. A vehicle that finds no
    free slot queues at its entrance and gets the next slot freed; one whose
    search fails (fuse, no path) waits outside and tries again. After the
    traffic's patience it is turned away, with the reason. Nothing is dropped:
    every vehicle ends parked, departed, waiting or rejected.

    Parameters
    ----------
    scenario : Scenario
        Must have ``traffic``.
    settings : RunSettings, optional
    lot_graph : LotGraph, optional
        The prepared lot (made with :func:`prepare` if not given).
    progress : callable, optional
        Called as ``progress(done, total)`` as trips are dealt with: a vehicle's way in when
        it is planned, its way out (if it has a dwell) when that is, or both when it is
        turned away or the run ends. It may raise (e.g.
        :class:`lotsim.sim.limits.LimitExceeded`) to stop the run.

    Raises
    ------
    ScenarioError
        For a scenario without traffic, or traffic the lot cannot serve at all (see
        :func:`check_traffic`).
    SettingsError
        For an ``order`` that does not hold every vehicle of the traffic once.
    """
    settings = settings or RunSettings()
    require_traffic(scenario)
    lg = lot_graph or prepare(scenario)
    seed = scenario.seed if settings.seed is None else settings.seed
    traffic = arrivals(scenario.traffic, seed)
    if settings.order is not None and sorted(settings.order) != sorted(a.id for a in traffic):
        raise SettingsError("order", "expected every vehicle id of the traffic exactly once")
    check_traffic(lg, traffic)
    sim = _Simulation(scenario, lg, settings, traffic, progress)
    clock = time.perf_counter()
    # what the process held before (the prepared lot, other runs' results) is left out of
    # the run's garbage collections: a full one scans every object it tracks, and one
    # that fell in a short run of a process holding several lots took longer than the
    # run's own work (the planning times it skews are the figures runs are compared by)
    # and collections come less often: planning makes millions of objects and almost no
    # cycles (see RUN_GC_THRESHOLDS)
    thresholds = gc.get_threshold()
    gc.freeze()
    gc.set_threshold(*RUN_GC_THRESHOLDS)
    try:
        sim.go()
    finally:
        gc.set_threshold(*thresholds)
        gc.unfreeze()
    return RunResult(scenario, lg, settings, seed, sim.vehicles, time.perf_counter() - clock)


class _Simulation:
    def __init__(self, scenario: Scenario, lg: LotGraph, settings: RunSettings,
                 traffic: list[Arrival], progress) -> None:
        self.lg = lg
        self.s = settings
        self.patience = scenario.traffic.patience
        self.table = ReservationTable()
        self.graphs = {t.name: search_graph(lg, t) for t in scenario.vehicle_types}
        types = {t.name: t for t in scenario.vehicle_types}
        self.vehicles = [VehicleRun(a, types[a.vehicle]) for a in traffic]
        self.by_id = {v.id: v for v in self.vehicles}
        self.free = {s.id for s in lg.lot.free_slots}
        self.queue: list[int] = []
        self.events: list[tuple[float, int, str, int]] = []
        self.seq = 0
        self.progress = progress
        self._trips = sum(1 + (v.arrival.dwell is not None) for v in self.vehicles)
        self._trips_done = 0
        self._counted: dict[str, int] = {}
        self._slot_times: dict[tuple[str, str, bool], dict[str, float]] = {}
        self.leave = {t.name: lg.leavable(t.name) for t in scenario.vehicle_types}
        self._exits: dict[str, ReverseResumable] = {}
        self._heuristics: OrderedDict[tuple, ReverseResumable] = OrderedDict()
        self.jammed: dict[str, float] = {}  # aisle → when a first look there last ran out
        parked = scenario.parked_vehicle
        for sid in sorted(lg.lot.occupied):
            slot = lg.lot.slot_by_id[sid]
            pose = slot.centered_pose(parked.front, parked.rear)
            self.table.reserve_standing(f"parked:{sid}", standing_body(parked, pose), -math.inf,
                                        in_slot=True)
        last = max((a.time for a in traffic), default=0.0)
        longest = max((a.dwell or 0.0 for a in traffic), default=0.0)
        self.end_time = last + self.patience + longest + 3600.0
        if settings.order is None:
            for i, a in enumerate(traffic):
                self.at(a.time, "arrive", i)
        else:  # booked: each batch is planned at its start, in this order
            index = {a.id: i for i, a in enumerate(traffic)}
            first = min((a.time for a in traffic), default=0.0)
            h = settings.horizon
            for vid in settings.order:
                a = traffic[index[vid]]
                batch = first if math.isinf(h) else first + math.floor((a.time - first) / h) * h
                self.at(batch, "arrive", index[vid])

    def at(self, t: float, kind: str, i: int) -> None:
        self.seq += 1
        heapq.heappush(self.events, (t, self.seq, kind, i))

    def go(self) -> None:
        while self.events:
            t, _, kind, i = heapq.heappop(self.events)
            # events come in time order and every search and release starts at its event's
            # time or later: what ended before is no use to any of them
            self.table.forget_before(t)
            v = self.vehicles[i]
            if v.done:
                continue
            if t > self.end_time:
                # a parked car that has not left yet is still parked (no reason: it is fine),
                # unless it should have left and could not: it is waiting to get out
                if v.status == "parked" and v.reason.startswith("could not leave"):
                    self.finish(v, "waiting", f"{v.reason} when the run ended at "
                                              f"{self.end_time:.0f} s")
                elif v.status == "parked":
                    self.finish(v, "parked")
                else:
                    self.finish(v, "waiting", f"the run ended at {self.end_time:.0f} s first")
                continue
            getattr(self, f"on_{kind}")(i, v, t)
        for v in self.vehicles:
            if not v.done:
                unsettled = v.status in ("waiting", "rejected")
                self.finish(v, v.status, (v.reason or "the run ended") if unsettled else "")

    def backoff(self, v: VehicleRun) -> float:
        """Wait before the next try after a failed search: ``retry``, doubling with each
        failure in a row, at most a minute [s]."""
        v.failures += 1
        return min(60.0, self.s.retry * 2 ** (v.failures - 1))

    def finish(self, v: VehicleRun, status: str, reason: str = "") -> None:
        v.status, v.reason, v.done = status, reason, True
        self.handled(v, 2)

    def handled(self, v: VehicleRun, trips: int) -> None:
        """Count ``v``'s first ``trips`` trips (1: in, 2: in and out, if it leaves) as dealt
        with, for ``progress``."""
        trips = min(trips, 1 + (v.arrival.dwell is not None))
        more = trips - self._counted.get(v.arrival.id, 0)
        if more > 0:
            self._counted[v.arrival.id] = trips
            self._trips_done += more
            if self.progress is not None:
                self.progress(self._trips_done, self._trips)

    # -- arriving -----------------------------------------------------------------------------
    def on_arrive(self, i: int, v: VehicleRun, t: float) -> None:
        if self.patience > 0:
            self.at(v.arrival.time + self.patience, "timeout", i)
        self.on_retry(i, v, t)

    def on_timeout(self, i: int, v: VehicleRun, t: float) -> None:
        if v.moves:  # it got in
            return
        if i in self.queue:
            self.queue.remove(i)
        why = v.reason or "no slot was freed"
        self.finish(v, "rejected", f"waited {self.patience:g} s outside: {why}")

    def on_retry(self, i: int, v: VehicleRun, t: float) -> None:
        if v.moves or v.done:
            return
        t = max(t, v.arrival.time)  # a booked vehicle is planned before it arrives
        sg = self.graphs[v.vehicle.name]
        options = self.slot_choice(v)
        if not options:
            v.reason = "the lot is full"
            if i not in self.queue:
                self.queue.append(i)
            if self.patience == 0:
                self.on_timeout(i, v, t)
            return
        # a first look at each of the few best slots (those in jammed aisles last), then a
        # full search where that ran out
        start = self.lg.entrances[v.arrival.entrance]
        tries = [(sid, True) for sid in self.few(self.unjammed_first(options, t))]
        while tries:
            sid, first = tries.pop(0)
            goal = self.park_goal(v, sid)
            budget = self.first_look(sg, start, goal.slot) if first else None
            plan = self.plan(v, sg, start=start, t0=t, goal=goal, outside=True,
                             key=("slot", sid), budget=budget)
            if plan.status is Status.FOUND:
                if i in self.queue:
                    self.queue.remove(i)
                self.free.discard(sid)
                v.slot = sid
                self.commit(i, v, sg, plan)
                return
            if plan.status is Status.OUT_OF_BUDGET and first:
                tries.append((sid, False))
                self.jammed[self.lg.lot.slot_by_id[sid].aisle] = t
        v.reason = f"no conflict-free route found ({plan.reason})"
        if self.patience == 0:
            self.on_timeout(i, v, t)
            return
        self.at(t + self.backoff(v), "retry", i)

    def first_look(self, sg: SearchGraph, start: int, slot: int) -> int:
        """The budget of a first look from ``start`` into slot node ``slot`` (see
        :data:`FIRST_LOOK_RATE`), from the RRA* the search asks anyway."""
        static = self.heuristic(sg, {slot: 0.0})(start)
        if math.isinf(static):
            return FIRST_LOOK
        return max(FIRST_LOOK, round(FIRST_LOOK_RATE * static))

    def unjammed_first(self, options: list[str], t: float) -> list[str]:
        """``options`` (a ranked slot list) with the slots in aisles jammed at ``t`` [s] (a
        first look there ran out less than :data:`JAMMED_FOR` before) moved after the
        others, each part in rank order."""
        slots, jammed = self.lg.lot.slot_by_id, self.jammed
        late = {aisle for aisle, when in jammed.items() if t - when < JAMMED_FOR}
        if not late:
            return options
        return ([sid for sid in options if slots[sid].aisle not in late]
                + [sid for sid in options if slots[sid].aisle in late])

    def few(self, options: list[str], n: int = 3) -> list[str]:
        """The best of ``options`` (a ranked slot list), then the best in each other aisle,
        then the next best, ``n`` in all: when the best cannot be reached in time (its aisle
        is busy with cars parking), its neighbours seldom can, and another aisle often can."""
        slots = self.lg.lot.slot_by_id
        out, seen = [], set()
        for sid in options:
            if slots[sid].aisle not in seen:
                seen.add(slots[sid].aisle)
                out.append(sid)
                if len(out) == n:
                    return out
        return out + [sid for sid in options if sid not in out][:n - len(out)]

    def park_goal(self, v: VehicleRun, sid: str) -> Goal:
        """Slot ``sid``, entered from where ``v`` can later leave if it will."""
        return Goal(slot=self.lg.slot_nodes[sid],
                    park_by=(self.leave[v.vehicle.name] if v.arrival.dwell is not None
                             else None))

    def slot_choice(self, v: VehicleRun) -> list[str]:
        """Free slots this vehicle can park in, best first by the assignment policy."""
        times = self.slot_times(v.arrival.entrance, v.vehicle.name, v.arrival.dwell is not None)
        usable = [s for s in self.free if s in times]
        if self.s.assignment == "shortest":
            return sorted(usable, key=lambda s: (times[s], s))
        x, y, _ = self.lg.graph.nodes[self.lg.entrances[v.arrival.entrance]]["pose"]
        slots = self.lg.lot.slot_by_id
        return sorted(usable, key=lambda s: (math.dist((x, y), slots[s].center), s))

    def slot_times(self, gate: str, vname: str, leaving: bool) -> dict[str, float]:
        """Static time [s] from entrance ``gate`` into each slot a ``vname`` can use and, if
        ``leaving``, out of it again (by any way out from the pose it parks on) to the
        nearest exit: a car that will leave counts the way out as well as the way in."""
        key = (gate, vname, leaving)
        if key not in self._slot_times:
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
                        tt += self._way_out(sg, i, to_exit)
                    out[sid] = min(out.get(sid, math.inf), tt)
            self._slot_times[key] = out
        return self._slot_times[key]

    @staticmethod
    def _way_out(sg: SearchGraph, park: int, to_exit) -> float:
        """Static time [s] from the pose park edge ``park`` leaves the car on, by a leave
        edge that begins there, to the nearest exit."""
        pose = sg.parked_pose(park)
        best = math.inf
        for j in sg.out[sg.edges[park].v]:
            e = sg.edges[j]
            if e.kind == "leave" and same_pose(sg.parked_pose(j), pose):
                best = min(best, e.duration + to_exit(e.v))
        return best

    # -- planning -----------------------------------------------------------------------------
    def plan(self, v: VehicleRun, sg: SearchGraph, *, key: tuple[str, str], **kw) -> Plan:
        goal = kw["goal"]
        goals = ({goal.slot: 0.0} if goal.slot is not None else {n: 0.0 for n in goal.exits})
        if key[0] == "exit" and self.s.planner != "ca":
            # one for every way out of a type, its fuse sized by all it has closed so far
            rra, shared = self._exits.get(key[1]), False
            if rra is None:
                rra = self._exits[key[1]] = sg.reverse_search(goals)
        else:
            rra, shared = self.heuristic(sg, goals), True
        v.seen = len(self.table.releases)
        clock = time.perf_counter()
        plan = search(sg, self.table, SearchRequest(owner=v.id, **kw), planner=self.s.planner,
                      heuristic=rra, shared=shared, omega=self.s.omega)
        v.planning_time += time.perf_counter() - clock
        v.searches += 1
        v.expansions += plan.expansions
        return plan

    def heuristic(self, sg: SearchGraph, goals: dict[int, float]) -> ReverseResumable:
        """The RRA* towards ``goals`` for ``sg``'s type, kept for the next search there (the
        same slot is searched for again and again: a first look, then a full search, by the
        car's next try and by the next cars); the :data:`HEURISTICS_KEPT` last used."""
        key = (sg.vehicle.name, *goals)
        kept = self._heuristics
        rra = kept.get(key)
        if rra is None:
            rra = kept[key] = sg.reverse_search(goals)
            if len(kept) > HEURISTICS_KEPT:
                kept.popitem(last=False)
        else:
            kept.move_to_end(key)
        return rra

    def commit(self, i: int, v: VehicleRun, sg: SearchGraph, plan: Plan) -> None:
        """Take ``plan`` (appended to ``v``'s moves) and reserve it; WHCA* replans it half a
        window on, while there is more than that left to drive."""
        v.failures = 0
        exit_ = self.is_exit(plan)
        reserve_moves(self.table, v.id, sg, plan.moves, hold_end=not exit_)
        v.moves.extend(plan.moves)
        t_end = plan.end
        now = plan.moves[0].t0
        if exit_:
            v.left_at = t_end
        else:
            v.parked_at = t_end
            v.parked_pose = plan.moves[-1].end_pose
            v.status, v.reason = "parked", ""
            self.handled(v, 1)
            if v.arrival.dwell is not None:
                v.depart_at = t_end + v.arrival.dwell
                self.at(v.depart_at, "depart", i)
        half = self.s.window / 2
        if self.s.planner == "whca" and t_end > now + half:
            self.at(now + half, "replan", i)
        else:
            self.settle(v)

    def settle(self, v: VehicleRun) -> None:
        """``v``'s plan is final: it departs, or parks for good."""
        if v.left_at is not None:
            self.finish(v, "departed")
        elif v.arrival.dwell is None:
            self.finish(v, "parked")

    def is_exit(self, plan: Plan) -> bool:
        return bool(plan.moves) and plan.moves[-1].node_to in self.lg.exits.values()

    # -- leaving ------------------------------------------------------------------------------
    def on_depart(self, i: int, v: VehicleRun, t: float) -> None:
        if v.depart_at is None or abs(t - v.depart_at) > 1e-9 or v.leaving:
            return  # superseded (a WHCA* replan moved the parking time)
        sg = self.graphs[v.vehicle.name]
        plan = self.plan(v, sg, start=self.lg.slot_nodes[v.slot], t0=t,
                         start_pose=v.parked_pose, goal=Goal(exits=tuple(self.lg.exits.values())),
                         key=("exit", v.vehicle.name))
        if plan.status is not Status.FOUND:
            v.reason = f"could not leave yet ({plan.reason})"
            v.depart_at = t + self.backoff(v)
            self.at(v.depart_at, "depart", i)
            return
        self.table.release(v.id, after=t)
        self.commit_departure(i, v, sg, plan, t)

    def commit_departure(self, i: int, v: VehicleRun, sg: SearchGraph, plan: Plan,
                         t: float) -> None:
        v.leaving = True  # from now on its plans lead out
        # the parked stretch until the departure's first move (already reserved until t)
        if plan.moves[0].t0 > v.moves[-1].t1:
            node = v.moves[-1].node_to
            v.moves.append(Move("parked", v.moves[-1].t1, plan.moves[0].t0, node, node, 0, 0,
                                end_pose=v.parked_pose))
        self.commit(i, v, sg, plan)
        self.free.add(v.slot)
        self.wake(t)

    def wake(self, t: float) -> None:
        """Give freed slots to the queue, first come first served."""
        for j in list(self.queue):
            if not self.free:
                break
            self.on_retry(j, self.vehicles[j], t)

    # -- WHCA* --------------------------------------------------------------------------------
    def on_replan(self, i: int, v: VehicleRun, t: float) -> None:
        """Replan from the end of the move under way at ``t``; keep the new plan if it gets
        there sooner (the old one stays valid: nobody planned over it)."""
        sg = self.graphs[v.vehicle.name]
        k = next((k for k, m in enumerate(v.moves) if m.t1 > t), len(v.moves) - 1)
        kept, last = v.moves[: k + 1], v.moves[k]
        if last.kind in ("wait", "outside") and last.t0 < t < last.t1:
            # waiting (for as long as its search found it must): from now, it may go sooner
            last = dataclasses.replace(last, t1=t)
            kept = [*v.moves[:k], last]
        t_end = v.moves[-1].t1
        if k < len(v.moves) - 1 and self.may_be_sooner(v, t_end):
            goal = (Goal(exits=tuple(self.lg.exits.values())) if v.leaving
                    else self.park_goal(v, v.slot))
            in_slot = last.node_to == self.lg.slot_nodes.get(v.slot)
            plan = self.plan(v, sg, start=last.node_to, t0=last.t1, level=last.level_to,
                             goal=goal, outside=last.kind == "outside",
                             start_pose=v.parked_pose if in_slot else None,
                             key=("exit", v.vehicle.name) if v.leaving else ("slot", v.slot))
            if plan.status is Status.FOUND and plan.end < t_end - 1e-6:
                self.table.release(v.id, after=last.t1)
                v.moves = kept
                self.commit(i, v, sg, plan)
                return
        if t_end > t + self.s.window / 2:
            self.at(t + self.s.window / 2, "replan", i)
        else:
            self.settle(v)


    def may_be_sooner(self, v: VehicleRun, t_end: float) -> bool:
        """Whether a replan of ``v``, whose plan ends at ``t_end``, is worth searching:
        only if someone else's reservations were dropped or cut short before ``t_end``
        since it last searched — or, for reservations that stood in a slot (a parked car
        that leaves), in its own slot (a car's search meets a body in a slot only there).
        Otherwise the table only grew meanwhile and the replan
        starts on the car's own plan, which its last search chose over every other way
        from there; a sooner one could only be what that search passed over, its heuristic
        being weighted (1.25) and states passing a node at speed within
        :attr:`~lotsim.traffic.settings.SearchSettings.passing` of one another taken as one —
        milliseconds in practice (a test bounds it at 0.1 s a car on the street's
        run)."""
        return not SKIP_FRUITLESS or any(
            who != v.id and after < t_end
            and (not in_slot or getattr(self.by_id.get(who), "slot", None) == v.slot)
            for after, who, in_slot in self.table.releases[v.seen:])


SKIP_FRUITLESS = True
"""WHCA*: skip the replans :meth:`_Simulation.may_be_sooner` finds not worth searching (off
only in the test that bounds what skipping them changes)."""


def samples(v: VehicleRun, *, dt: float = SAMPLE_DT) -> Trajectory | None:
    """``v``'s motion sampled for a result: every ``dt`` [s] on a common clock (``k·dt``)
    while it moves, plus every start, stop and cusp; standing stretches only at their ends
    (gear 0). None when it never entered the lot."""
    moves = [m for m in v.moves if m.kind != "outside"]
    if not moves:
        return None
    parts: list[tuple[np.ndarray, ...]] = []
    for m in moves:
        if m.motion is None:  # standing
            pose = m.end_pose
            t = np.array([m.t0, m.t1])
            z = np.zeros(2)
            parts.append((t, z + pose[0], z + pose[1], z + pose[2], z, z + m.steer,
                          np.zeros(2, int)))
            continue
        grid = np.arange(math.floor(m.t0 / dt) + 1, math.ceil(m.t1 / dt)) * dt
        tau = np.unique(np.concatenate([[0.0], grid - m.t0, m.motion.cusps,
                                        [m.motion.duration]]))
        tau = tau[(tau >= 0) & (tau <= m.motion.duration)]
        p, speed, steer, gear = m.motion.at(tau, wheelbase=v.vehicle.wheelbase)
        parts.append((m.t0 + tau, p[:, 0], p[:, 1], p[:, 2], speed, steer, gear))
    cols = [np.concatenate([p[k] for p in parts]) for k in range(7)]
    # one sample per instant: where moves meet the later move's first sample stays; two
    # samples microseconds apart (written to 1 µs) are one, at the earlier time
    # (a sample that stands for one at rest is at rest: a drive that sets off 2 µs before
    # a grid instant has rolled 1e-12 m/s by then, and the car stood until it set off)
    t = cols[0]
    near = np.append(np.diff(t) <= 2e-6, False)
    later = np.flatnonzero(near) + 1
    t[later] = t[later - 1]
    keep = ~near
    group = np.concatenate([[0], np.cumsum(keep[:-1])])  # the kept sample each one is
    rest = np.zeros(int(keep.sum()), dtype=bool)
    np.logical_or.at(rest, group, np.abs(cols[4]) < 1e-12)
    cols = [c[keep] for c in cols]
    # a sample at rest (a start, a stop, a cusp) is standing: gear 0
    cols[4] = np.where(rest, 0.0, cols[4])
    cols[6] = np.where(rest, 0, cols[6])
    return Trajectory(*cols)

