"""The event loop of a run: cars arrive, look for a slot and a way to it, queue or wait
outside when they find none, park, leave again, and (WHCA*) replan as they drive.

Cars are planned one at a time, each against the reservation table of those planned
before it (cooperative A*, Silver 2005); which slot a car tries is the
:class:`~lotsim.sim.assignment.SlotAssigner`'s choice.
"""

from __future__ import annotations

import dataclasses
import heapq
import math
import time
from collections import OrderedDict
from collections.abc import Callable

from lotsim.core.outcome import Status
from lotsim.roadmap.model import LotGraph
from lotsim.scenario import Scenario
from lotsim.sim import inside, repairs, stalls
from lotsim.sim.assignment import SlotAssigner
from lotsim.sim.limits import takes_three
from lotsim.sim.policies import ASK, SlotRequest, choices
from lotsim.sim.results import VehicleRun
from lotsim.sim.settings import RunSettings
from lotsim.traffic.demand import PATIENCE, Arrival
from lotsim.traffic.disturbances import Closure
from lotsim.traffic.heuristic import ReverseResumable
from lotsim.traffic.plans import Move, Plan, reserve_moves
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.search import Goal, SearchRequest, search
from lotsim.traffic.searchgraph import SearchGraph, SearchGraphMemo
from lotsim.traffic.swept import standing_body


def clock_line(now: float, served: int) -> str:
    """A run's clock as a time of day (its clock starts at midnight; past the first day,
    ``day N``) and the cars served so far (come to stand in their slot): ``"08:42, 512
    served"``, ``"day 2 07:05, 3120 served"``.

    Examples
    --------
    >>> clock_line(31_330.0, 512)
    '08:42, 512 served'
    >>> clock_line(86_400.0 + 25_500.0, 3120)
    'day 2 07:05, 3120 served'
    """
    minutes = int(max(now, 0.0) // 60.0)
    day, minutes = divmod(minutes, 24 * 60)
    clock = f"{minutes // 60:02d}:{minutes % 60:02d}"
    return f"{f'day {day + 1} ' if day else ''}{clock}, {served} served"


class EventLoop:
    """One run's events in time order: arrivals, retries after a failed search, timeouts,
    departures and WHCA* replans, each planned against the reservations of those before.

    Parameters
    ----------
    scenario : Scenario
        Its traffic's patience, vehicle types and the car parked in occupied slots.
    lg : LotGraph
        The prepared lot.
    settings : RunSettings
    traffic : list of Arrival
        The vehicles, in arrival order.
    progress : callable or None
        Called as ``progress(done, total)`` as trips are dealt with; one that takes a third
        argument is given the run's clock and the cars served so far as text
        (:func:`clock_line`: ``"08:42, 512 served"``).
    policy : callable, optional
        Chooses the slots a car tries, as ``policy(request)`` (a
        :class:`~lotsim.sim.policies.SlotRequest`): a slot id, slot ids to try in order, or
        None to wait; without one, ``settings.assignment`` ranks them. :data:`ASK` leaves
        each choice to the caller (:meth:`decide`), the loop pausing at it.
    """

    def __init__(self, scenario: Scenario, lg: LotGraph, settings: RunSettings,
                 traffic: list[Arrival], progress, memo: SearchGraphMemo | None = None,
                 *, turned_away: dict[str, str] | None = None, policy=None) -> None:
        self.lg = lg
        self.on_done: Callable[[VehicleRun], None] | None = None
        """Called with each vehicle as it is done (nothing more will happen to it)."""
        self.turned_away = turned_away or {}  # vehicle id → why the lot cannot serve it
        self.s = settings
        self.patience = scenario.traffic.patience if scenario.traffic else PATIENCE
        self.table = ReservationTable()
        self.assigner = SlotAssigner(lg, scenario.vehicle_types, policy=settings.assignment,
                                     tuning=settings.tuning, search=settings.search,
                                     memo=memo)
        self.graphs = self.assigner.graphs
        self.leave = self.assigner.leave
        self.types = {t.name: t for t in scenario.vehicle_types}
        self.vehicles: list[VehicleRun] = []
        self.by_id: dict[str, VehicleRun] = {}
        self.free = {s.id for s in lg.lot.free_slots}
        self.queue: list[int] = []
        self.events: list[tuple[float, int, str, int]] = []
        self.seq = 0
        self.now = -math.inf  # the time of the event dealt with last [s]
        self.progress = progress
        self._says_clock = takes_three(progress)
        self.served = 0  # cars that came to stand in their slot
        self.policy = policy
        self.pending: tuple[int, float] | None = None  # a car waiting for a decision, when
        self.answer: tuple[int, object] | None = None  # the caller's to it
        self.asked: SlotRequest | None = None  # what the pending car was asked
        self.state_of = lambda loop: {}  # the run's state as plain data (set by its Live)
        self.scenario_parked = scenario.parked_vehicle  # a car in a bay taken from outside
        self.closures: list = []  # closures met (repairs.ClosureRecord), in time order
        self.taken_records: list = []  # bays taken from outside (repairs.TakenRecord)
        self.taken: set[str] = set()  # the slots those took
        self.replans: list = []  # every repair (repairs.Replan), in time order
        self.lot_events: list = []  # closures and bays taken, by the index their events hold
        self.stall_asks: list[tuple[int, float]] = []  # (car, duration) of stalls asked for
        self.stalls: list = []  # what came of them (stalls.StallRecord), in time order
        self.cut_cache: dict = {}  # what closures cut off (repairs.cut_off), by closures open
        self._trips = 0
        self._trips_done = 0
        self._counted: dict[str, int] = {}
        self._exits: dict[tuple, ReverseResumable] = {}  # by type and closures open
        self._heuristics: OrderedDict[tuple, ReverseResumable] = OrderedDict()
        self.reserve_parked()
        self._last: float | None = None  # the latest arrival [s]
        self._longest = 0.0  # the longest dwell [s]
        self.end_time = self.patience + 3600.0
        for a in traffic:
            self.enter(a)
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

    def reserve_parked(self) -> None:
        """Hold the cars parked in the lot's occupied slots, from the start for ever."""
        parked = self.scenario_parked
        for sid in sorted(self.lg.lot.occupied):
            slot = self.lg.lot.slot_by_id[sid]
            pose = slot.centered_pose(parked.front, parked.rear)
            self.table.reserve_standing(f"parked:{sid}", standing_body(parked, pose), -math.inf,
                                        in_slot=True)

    def enter(self, a: Arrival) -> int:
        """Take ``a`` into the run (its arrival event is the caller's to schedule); its
        index among the run's vehicles."""
        v = VehicleRun(a, self.types[a.vehicle])
        self.vehicles.append(v)
        self.by_id[v.id] = v
        if v.id not in self.turned_away:
            self._trips += 1 + (a.dwell is not None)
        # the run ends an hour after the last car could be done: the last arrival, the
        # patience and the longest dwell
        self._last = a.time if self._last is None else max(self._last, a.time)
        self._longest = max(self._longest, a.dwell or 0.0)
        self.end_time = self._last + self.patience + self._longest + 3600.0
        return len(self.vehicles) - 1

    def at(self, t: float, kind: str, i: int) -> None:
        self.seq += 1
        heapq.heappush(self.events, (t, self.seq, kind, i))

    def go(self, until: float = math.inf) -> None:
        """Deal with every event up to ``until`` [s] (or until a car waits for a decision,
        :attr:`pending`)."""
        while self.events and self.pending is None and self.events[0][0] <= until:
            self.step()

    def step(self) -> None:
        """Deal with the next event."""
        t, _, kind, i = heapq.heappop(self.events)
        self.now = max(self.now, t)
        # events come in time order and every search and release starts at its event's
        # time or later: what ended before is no use to any of them
        self.table.forget_before(t)
        if kind == "close":
            self.closures.append(repairs.close(self, self.lot_events[i], t))
            self.at(self.lot_events[i].end, "open", i)
            return
        if kind == "open":  # the cars queued meanwhile try the slots it gives back
            self.wake(t)
            return
        if kind == "take":
            self.taken_records.append(repairs.take(self, self.lot_events[i], t))
            return
        if kind == "stall":  # asked for from outside (Live.stall)
            car, duration = self.stall_asks[i]
            self.stalls.append(stalls.stall(self, car, self.vehicles[car], t, duration))
            return
        v = self.vehicles[i]
        if v.done:
            return
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
            return
        getattr(self, f"on_{kind}")(i, v, t)

    def close(self) -> None:
        """End the run: every vehicle not done yet ends as it stands."""
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
        if self.on_done is not None:
            self.on_done(v)

    def handled(self, v: VehicleRun, trips: int) -> None:
        """Count ``v``'s first ``trips`` trips (1: in, 2: in and out, if it leaves) as dealt
        with, for ``progress``."""
        trips = min(trips, 1 + (v.arrival.dwell is not None))
        more = trips - self._counted.get(v.arrival.id, 0)
        if more > 0:
            self._counted[v.arrival.id] = trips
            self._trips_done += more
            if self._says_clock:
                self.progress(self._trips_done, self._trips, clock_line(self.now, self.served))
            elif self.progress is not None:
                self.progress(self._trips_done, self._trips)

    # -- arriving -----------------------------------------------------------------------------
    def on_arrive(self, i: int, v: VehicleRun, t: float) -> None:
        if v.id in self.turned_away:  # a type the lot cannot serve: turned away at once
            self.finish(v, "rejected", self.turned_away[v.id])
            return
        if v.arrival.inside:  # in a bay or on a lane: it holds its ground from now
            inside.place(self, i, v, t)
            return
        self.assigner.saw(v.arrival.entrance, v.arrival.time)
        if self.patience > 0:
            self.at(v.arrival.time + self.patience, "timeout", i)
        self.on_retry(i, v, t)

    def on_timeout(self, i: int, v: VehicleRun, t: float) -> None:
        if v.moves:  # it got in
            return
        if i in self.queue:
            self.queue.remove(i)
        why = v.reason or "no slot was freed"
        v.waited_outside = self.patience
        self.finish(v, "rejected", f"waited {self.patience:g} s outside: {why}")

    def on_retry(self, i: int, v: VehicleRun, t: float) -> None:
        if v.done or (v.moves and not (v.arrival.inside and v.slot is None)):
            return  # it is on its way (a car on a lane that has no slot yet looks again)
        t = max(t, v.arrival.time)  # a booked vehicle is planned before it arrives
        sg = self.graphs[v.vehicle.name]
        start, outside = inside.set_off(self, v, t)
        options = self.assigner.ranked(v.arrival, self.free, t)
        full = ("the lot is full" if not v.arrival.inside
                else "no free slot it can reach from where it stands")
        if self.closures and options:
            away, _ = repairs.cut_off(self, v.vehicle.name, start, t)
            options = [sid for sid in options if sid not in away]
            full = ("the lot is full" if options
                    else "its free slots are closed off (on or beyond a closed aisle)")
        if not options:
            v.reason = full
            if i not in self.queue:
                self.queue.append(i)
            if self.patience == 0:
                self.on_timeout(i, v, t)
            return
        tries = self.tries(i, v, t, options)
        if tries is None:  # the policy chose to wait, or has yet to choose
            return
        while tries:
            sid, first = tries.pop(0)
            goal = self.park_goal(v, sid)
            budget = self.probe_budget(sg, start, goal.slot) if first else None
            plan = self.plan(v, sg, start=start, t0=t, goal=goal, outside=outside,
                             key=("slot", sid), budget=budget)
            if plan.status is Status.FOUND:
                if i in self.queue:
                    self.queue.remove(i)
                self.free.discard(sid)
                v.slot = sid
                if not outside:  # it stood on its lane until now
                    self.table.release(v.id, after=t)
                self.commit(i, v, sg, plan)
                return
            if plan.status is Status.OUT_OF_BUDGET and first:
                tries.append((sid, False))
                self.assigner.ran_out(sid, t)
        v.reason = f"no conflict-free route found ({plan.reason})"
        if self.patience == 0 and not v.arrival.inside:
            self.on_timeout(i, v, t)
            return
        self.at(t + self.backoff(v), "retry", i)

    def on_repair(self, i: int, v: VehicleRun, t: float) -> None:
        """A car that stood where a repair found no way tries again."""
        if v.moves and v.moves[-1].kind == "wait" and abs(v.moves[-1].t1 - t) < 1e-9:
            repairs.repair(self, i, v, t, v.reason)

    def add_lot_event(self, event) -> None:
        """A closure or a bay taken (:mod:`lotsim.traffic.disturbances`), at its time."""
        self.lot_events.append(event)
        closes = isinstance(event, Closure)
        self.at(event.start if closes else event.at, "close" if closes else "take",
                len(self.lot_events) - 1)

    def exit_goal(self) -> Goal:
        """Any of the lot's exits."""
        return Goal(exits=tuple(self.lg.exits.values()))

    def tries(self, i: int, v: VehicleRun, t: float, options: list[str]
              ) -> list[tuple[str, bool]] | None:
        """The slots ``v`` tries at ``t`` [s], each with whether it is a probe (a small
        budget, then a full search where it ran out): a probe of each of the few best of
        ``options`` (those in congested aisles last), or as the policy chooses. None
        when the car waits: its policy chose to, or (:data:`ASK`) the caller has yet to
        decide (:attr:`pending`)."""
        if self.policy is None:
            return [(sid, True) for sid in self.assigner.probes(options, t)]
        request = self.request(v, t, options)
        if self.policy == ASK:
            if self.answer is None or self.answer[0] != i:
                self.pending, self.asked = (i, t), request
                return None
            answer = self.answer[1]
            self.answer = None
        else:
            answer = self.policy(request)
        picked = choices(answer, request, lambda sid: self.why_not(v, sid, t))
        if picked is None:
            v.reason = "its policy chose to wait"
            if self.patience == 0 and not v.arrival.inside:
                self.on_timeout(i, v, t)
            else:
                self.at(t + self.s.retry, "retry", i)
            return None
        if len(picked) > 1:  # a ranking: looked at as the run's own are
            picked = self.assigner.probes(picked, t)
        return [(sid, True) for sid in picked]

    def request(self, v: VehicleRun, t: float, options: list[str]) -> SlotRequest:
        """What a policy is asked for ``v`` at ``t`` [s], ``options`` its usable free
        slots, ranked."""
        a = v.arrival
        times = self.assigner.slot_times(self.assigner.origin(a), a.vehicle,
                                         a.dwell is not None)
        return SlotRequest(a.id, a.vehicle, a.entrance, t, a.dwell is not None,
                           tuple(options), {sid: times[sid] for sid in options},
                           lambda by: self.assigner.ranked(a, options, t, by=by),
                           lambda: self.state_of(self))

    def why_not(self, v: VehicleRun, sid: str, t: float) -> str:
        """Why ``v`` cannot take slot ``sid`` at ``t`` [s] (a policy chose it)."""
        lot = self.lg.lot
        if sid not in lot.slot_by_id:
            return "there is no such slot"
        if sid in lot.occupied:
            return "it is occupied (taken when the run began)"
        if sid not in self.free:
            holder = next((u.id for u in self.vehicles if u.slot == sid and not u.leaving),
                          None)
            return f"it is taken by {holder!r}" if holder else "it is taken"
        why = self.lg.infeasible.get(v.vehicle.name, {}).get(sid)
        if why:
            return f"a {v.vehicle.name!r} cannot use it ({why})"
        if self.closures and not v.arrival.inside:
            gate = self.lg.entrances[v.arrival.entrance]
            if sid in repairs.cut_off(self, v.vehicle.name, gate, t)[0]:
                return "it is closed off now (on or beyond a closed aisle, lane or gate)"
        where = (f"entrance {v.arrival.entrance!r}" if not v.arrival.inside
                 else "where it stands")
        return (f"a {v.vehicle.name!r} cannot reach it from {where}"
                + (" and leave it for an exit" if v.arrival.dwell is not None else ""))

    def probe_budget(self, sg: SearchGraph, start: int, slot: int) -> int:
        """The budget of a probe from ``start`` into slot node ``slot``
        (:meth:`SlotAssigner.probe_budget`), from the RRA* the search asks anyway."""
        return self.assigner.probe_budget(self.heuristic(sg, {slot: 0.0})(start))

    def park_goal(self, v: VehicleRun, sid: str) -> Goal:
        """Slot ``sid``, entered from where ``v`` can later leave if it will."""
        return Goal(slot=self.lg.slot_nodes[sid],
                    park_by=(self.leave[v.vehicle.name] if v.arrival.dwell is not None
                             else None))

    # -- planning -----------------------------------------------------------------------------
    def plan(self, v: VehicleRun, sg: SearchGraph, *, key: tuple[str, str], **kw) -> Plan:
        """Search for ``v`` (``kw``: :func:`~lotsim.traffic.search.search`'s), with the
        heuristic kept for ``key`` (``("slot", id)`` or ``("exit", type)``); counted in
        ``v``'s searches, expansions and planning time."""
        goal = kw["goal"]
        goals = ({goal.slot: 0.0} if goal.slot is not None else {n: 0.0 for n in goal.exits})
        # while closures last, the static times go round what they shut
        active, shut = repairs.shut_at(self, sg.vehicle.name, kw["t0"])
        if key[0] == "exit" and self.s.planner != "ca":
            # one for every way out of a type, its expansion limit sized by all it has closed so far
            rra, shared = self._exits.get((key[1], active)), False
            if rra is None:
                rra = self._exits[key[1], active] = sg.reverse_search(goals, shut=shut)
        else:
            rra, shared = self.heuristic(sg, goals, active, shut), True
        v.seen = len(self.table.releases)
        worked = sg.tally.seconds
        clock = time.perf_counter()
        plan = search(sg, self.table, SearchRequest(owner=v.id, **kw), planner=self.s.planner,
                      heuristic=rra, shared=shared, omega=self.s.omega)
        # the edge motions this search worked out first are kept for the lot's later runs:
        # counted apart (the graph's tally), so that a run is timed alike whatever ran on
        # the lot before it
        v.planning_time += time.perf_counter() - clock - (sg.tally.seconds - worked)
        v.searches += 1
        v.expansions += plan.expansions
        return plan

    def heuristic(self, sg: SearchGraph, goals: dict[int, float], active: tuple = (),
                  shut: frozenset[int] = frozenset()) -> ReverseResumable:
        """The RRA* towards ``goals`` for ``sg``'s type, kept for the next search there (the
        same slot is searched for again and again: a probe, then a full search, by the
        car's next try and by the next cars); the ``heuristics_kept`` last used. While
        closures are open (``active``), one that goes round the edges they ``shut``."""
        key = (sg.vehicle.name, *goals) if not active else (sg.vehicle.name, active, *goals)
        kept = self._heuristics
        rra = kept.get(key)
        if rra is None:
            rra = kept[key] = sg.reverse_search(goals, shut=shut)
            if len(kept) > self.s.tuning.heuristics_kept:
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
            self.served += v.parked_at is None
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
        if self.closures and repairs.cut_off(self, v.vehicle.name, self.lg.slot_nodes[v.slot],
                                             t)[1]:
            # every way out is closed: it leaves once the first closure ends
            reopen = min(r.t1 for r in self.closures if r.t0 <= t < r.t1)
            v.reason = "could not leave yet (the ways out are closed)"
            v.depart_at = reopen
            self.at(reopen, "depart", i)
            return
        plan = self.plan(v, sg, start=self.lg.slot_nodes[v.slot], t0=t,
                         start_pose=v.parked_pose, goal=self.exit_goal(),
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
        self.assigner.saw(None, t)
        # the parked stretch until the departure's first move (already reserved until t)
        if plan.moves[0].t0 > v.moves[-1].t1:
            node, t0 = v.moves[-1].node_to, v.moves[-1].t1
            if v.moves[-1].kind == "parked":  # one that stood in its bay when it came
                t0 = v.moves.pop().t0
            v.moves.append(Move("parked", t0, plan.moves[0].t0, node, node, 0, 0,
                                end_pose=v.parked_pose))
        self.commit(i, v, sg, plan)
        self.free.add(v.slot)
        self.wake(t)

    def wake(self, t: float) -> None:
        """Give freed slots to the queue, first come first served."""
        for j in list(self.queue):
            if not self.free:
                break
            if self.policy == ASK:  # one choice at a time: each is the caller's
                self.at(t, "retry", j)
            else:
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
            goal = self.exit_goal() if v.leaving else self.park_goal(v, v.slot)
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
        :attr:`~lotsim.traffic.settings.SearchSettings.passing` of one another taken as one:
        milliseconds in practice. Every replan is searched when the run's
        ``tuning.skip_fruitless`` is off."""
        return not self.s.tuning.skip_fruitless or any(
            who != v.id and after < t_end
            and (not in_slot or getattr(self.by_id.get(who), "slot", None) == v.slot)
            for after, who, in_slot in self.table.releases[v.seen:])

