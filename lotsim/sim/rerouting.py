"""Planning again a car whose wait grows long while a run is driven through its
disturbances (:func:`lotsim.sim.execution.execute`).

Driven in the plan's order, a car that the plan has pass somewhere after a car held up (a
stall ahead of it, a car come late) waits for that car however long it is held. An
operator would not leave it there: once it has stood
:attr:`~lotsim.traffic.disturbances.Disturbances.repair_after` seconds past the moment
its plan had it set off, it is planned again from where it stands, against where every
other car is as driven, the lot's closures and the bays taken from outside (a search like
any of the run's, with a probe's budget). The new way is taken when it brings the
car to its slot, or out of the lot, sooner than waiting its turn would; the plan, with
that car's new way in it, is then driven again (still in the order of every car's pass,
so a car slower than planned stays safe), and the next long wait looked for. Each
attempt is a repair in the result's ``replans``.

Only cars at rest on the lanes are planned again: a car queued at its gate takes no
space and waits no differently on another way, and one waiting in its slot to leave
holds no one up.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import TYPE_CHECKING

from lotsim.core.outcome import Status
from lotsim.sim.loop import EventLoop
from lotsim.sim.repairs import LotChanges, Replan
from lotsim.sim.results import RunResult, VehicleRun
from lotsim.sim.standstills import Driven, Run, runs_of, stop_after, stretch
from lotsim.traffic.plans import Move
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.swept import standing_body

if TYPE_CHECKING:  # the driver is the caller; these are its types
    from lotsim.traffic.searchgraph import SearchGraph, SearchGraphMemo

EPS = 1e-9
"""Times closer than this are the same instant [s]."""
MAX_REPAIRS = 500
"""Most long waits a run's driving tries to repair; the cars of any later ones wait their
turn."""
POSE_TOL = 1e-6
"""A car's slot pose after a new way in is the one its way out leaves from, within this
[m, rad]."""
MIN_GAIN = 1.0
"""A new way is taken when it has the car there at least this much sooner [s]."""
NONE_FOUND = "none found: it waits its turn"
"""A repair's outcome when no sooner way was found."""


def repair_waits(driven: Driven, after: float, replans: list[Replan],
                 drive: Callable[[list[VehicleRun], list[list[Run]], Driven, int], Driven],
                 context: Context) -> Driven:
    """``driven`` with every wait longer than ``after`` [s] repaired where a sooner way
    was found, earliest first; each attempt appended to ``replans``. ``drive`` drives a
    plan again: the cars as a drive executed them, but for one planned again."""
    tried: set[tuple[str, int]] = set()
    dropped: list = []
    done = 0
    for _ in range(MAX_REPAIRS):
        wait = _first_long_wait(driven, after, tried)
        if wait is None:
            break
        c, j, t_rest, t_star = wait
        v = driven.executed[c]
        tried.add((v.id, j))
        why = f"it had stood {after:g} s past its plan, waiting for the cars before it"
        new = _plan_again(driven, c, runs_of(v, c)[j - 1].last, t_star, context)
        if new is None:
            replans.append(Replan(v.id, t_star, why, NONE_FOUND))
            continue
        moves, outcome = new
        replans.append(Replan(v.id, t_star, why, outcome))
        plan = list(driven.executed)
        plan[c] = dataclasses.replace(v, moves=moves)
        runs = [_carried(runs_of(u, k), driven.runs[k], k == c, j, t_rest,
                         context.speed.get(v.id, 1.0), dropped)
                for k, u in enumerate(plan)]
        driven = drive(plan, runs, driven, c)
        done += 1
    return dataclasses.replace(driven, repaired=done, stalls_dropped=len(dropped))


@dataclasses.dataclass(frozen=True)
class Context:
    """What planning a car again needs besides the drive: the run as planned (its
    scenario, lot and settings), the lot's search graphs and each car's speed factor."""

    planned: RunResult
    memo: SearchGraphMemo | None
    speed: dict[str, float]
    loops: list = dataclasses.field(default_factory=list)  # the one loop searched in

    def loop(self) -> EventLoop:
        """An event loop of the run's lot and settings, with an empty reservation table
        (made once: its slot assigner's tables are the lot's)."""
        if not self.loops:
            rr = self.planned
            self.loops.append(EventLoop(rr.scenario, rr.lot_graph, rr.settings, [], None,
                                        self.memo))
        loop = self.loops[0]
        loop.table = ReservationTable()
        loop.reserve_parked()
        loop.closures, loop.cut_cache = [], {}
        return loop


def _first_long_wait(driven: Driven, after: float, tried: set[tuple[str, int]]
                     ) -> tuple[int, int, float, float] | None:
    """The wait that grows past ``after`` [s] first: the car, the index of the run it
    waits to set off on, when it came to rest and when the wait grew too long [s]."""
    best = None
    for c, rs in enumerate(driven.runs):
        vid = driven.executed[c].id
        for r in rs[1:]:
            if r.in_slot or (vid, r.index) in tried:
                continue
            prev = rs[r.index - 1]
            rest = driven.starts[id(prev)] + prev.duration
            due = rest + r.gap + r.stall + r.late_by
            if driven.starts[id(r)] > due + after + EPS:
                t_star = due + after
                if best is None or t_star < best[3] - EPS:
                    best = (c, r.index, rest, t_star)
    return best


def _carried(new: list[Run], old: list[Run], replanned: bool, j: int, t_rest: float,
             factor: float, dropped: list) -> list[Run]:
    """The runs of a plan driven before (``new``), given what their drive had (``old``):
    each had its speed factor and late start driven already, and keeps its stall and how
    long the first plan had the car stand before it. A car planned again from its run
    ``j`` (``replanned``) drives its new runs with its own ``factor``, the first of them
    due when its new way sets off from where it came to rest at ``t_rest`` [s]; a stall
    still to come that its new way has no place of rest for goes to ``dropped``."""
    keep = len(new) if not replanned else j
    if not replanned and len(new) != len(old):
        raise RuntimeError("a car's plan driven again has other standstills")
    for r, o in zip(new[:keep], old[:keep], strict=True):
        r.factor, r.late, r.late_by = 1.0, 0.0, o.late_by
        r.stall, r.stalls, r.gap = o.stall, list(o.stalls), o.gap
    if replanned:
        for r in new[keep:]:
            r.factor = factor
        if keep < len(new):
            first = new[keep]
            if keep < len(old):  # a stall it stood there is still its own
                first.stall, first.stalls = old[keep].stall, list(old[keep].stalls)
            first.gap = first.t0 - t_rest - first.stall
        # its stalls still to come fall where its new way next brings it to rest
        for st in (st for o in old[keep + 1:] for st in o.stalls):
            r = stop_after(new, st.at)
            if r is None:
                dropped.append(st)
            else:
                r.stall += st.duration
                r.stalls.append(st)
    return new


def _plan_again(driven: Driven, c: int, stop: int, t_star: float, context: Context
                ) -> tuple[list[Move], str] | None:
    """Car ``c``'s executed moves with a new way on from where its move ``stop`` brought
    it to rest, set off from ``t_star`` [s], and the repair's outcome; None when no way
    brings it to its slot, or out, sooner."""
    v = driven.executed[c]
    rest = v.moves[stop]
    park = next((k for k in range(stop + 1, len(v.moves)) if v.moves[k].kind == "park"),
                None)
    if park is None and v.left_at is None:
        return None  # it stays where it is: nothing to reach sooner
    old_end = v.moves[park].t1 if park is not None else v.moves[-1].t1
    loop = context.loop()
    for u in driven.executed:
        if u is not v:
            _reserve_driven(loop.table, u, loop.graphs[u.vehicle.name], t_star)
    _hold_changes(loop, driven.changes)
    sg = loop.graphs[v.vehicle.name]
    me = dataclasses.replace(v, moves=[])
    if park is not None:
        goal, key = loop.park_goal(v, v.slot), ("slot", v.slot)
        goals = {goal.slot: 0.0}
    else:
        goal, key = loop.exit_goal(), ("exit", v.vehicle.name)
        goals = {n: 0.0 for n in goal.exits}
    budget = loop.assigner.probe_budget(loop.heuristic(sg, goals)(rest.node_to))
    plan = loop.plan(me, sg, start=rest.node_to, t0=t_star, level=0, goal=goal, key=key,
                     budget=budget)
    v.searches += me.searches
    v.expansions += me.expansions
    v.planning_time += me.planning_time
    if plan.status is not Status.FOUND or not plan.moves:
        return None
    factor = context.speed.get(v.id, 1.0)
    if t_star + (plan.end - t_star) / factor > old_end - MIN_GAIN:
        return None  # no sooner than waiting its turn
    tail: list[Move] = []
    if park is not None:
        end_pose = plan.moves[-1].end_pose
        if end_pose is None or max(abs(a - b) for a, b in zip(
                end_pose, v.moves[park].end_pose, strict=True)) > POSE_TOL:
            return None  # its way out leaves from the pose it parked in before
        tail = list(v.moves[park + 1:])
        if tail:
            if tail[0].motion is not None:
                return None
            tail[0] = dataclasses.replace(tail[0], t0=plan.end)
    pose = rest.end_pose if rest.end_pose is not None else sg.pose[rest.node_to]
    steer = rest.steer if rest.motion is None else float(sg.steer[rest.node_to])
    stand = ([Move("wait", rest.t1, t_star, rest.node_to, rest.node_to, 0, 0, end_pose=pose,
                   steer=steer)] if t_star > rest.t1 + EPS else [])
    outcome = ("out to an exit" if park is None else f"to slot {v.slot!r}") + (
        f", there at {plan.end:.1f} s where waiting would have had it there at "
        f"{old_end:.1f} s")
    return [*v.moves[:stop + 1], *stand, *plan.moves, *tail], outcome


def _reserve_driven(table: ReservationTable, u: VehicleRun, sg: SearchGraph,
                    since: float) -> None:
    """Hold what ``u``'s executed moves sweep from ``since`` [s] on (a move driven slower
    than its edge's motion over times stretched alike), and its last pose for ever when it
    stays."""
    slots = sg.slot_nodes
    for m in u.moves:
        if m.kind == "outside" or m.t1 < since - EPS:
            continue
        if m.motion is None:
            table.reserve_standing(u.id, standing_body(sg.vehicle, m.end_pose), m.t0, m.t1,
                                   in_slot=m.node_to in slots)
            continue
        em = sg.motion(m.edge, m.level_from, m.level_to)
        k = stretch(em, m)
        if k == 1.0:
            table.reserve(u.id, em.swept, offset=m.t0)
        else:
            table.reserve(u.id, [(m.t0 + a * k, m.t0 + b * k, g) for (a, b, *_), g
                                 in zip(em.swept.rows, em.swept.geoms, strict=True)])
    last = u.moves[-1] if u.moves else None
    if u.left_at is None and last is not None and last.end_pose is not None \
            and last.kind != "outside":
        table.reserve_standing(u.id, standing_body(sg.vehicle, last.end_pose), last.t1,
                               in_slot=last.node_to in slots)


def _hold_changes(loop: EventLoop, changes: LotChanges | None) -> None:
    """Hold the closures and the bays taken from outside, as the drive met them."""
    if changes is None:
        return
    for rec in changes.closures:
        loop.table.reserve(f"closed:{rec.closure.kind}:{rec.closure.id}",
                           [(rec.t0, rec.t1, rec.area)])
    loop.closures = list(changes.closures)
    for rec in changes.taken:
        if rec.body is not None:
            loop.table.reserve_standing(f"taken:{rec.bay.slot}", rec.body, rec.t,
                                        in_slot=True)

