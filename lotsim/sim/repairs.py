"""When the lot changes under a run: an aisle or gate closes for a while, a car the plan
does not know takes a bay. The cars whose plans the change breaks are planned again from
where they are (a repair), not the whole run; each repair is recorded.

A closure is a body held in the reservation table over its interval, so every later
search keeps out of it; the cars already in the closed ground (or driving into it) when it
closes go on as planned. A bay taken is held for ever from its time, as a parked car is.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from lotsim.core.outcome import Status
from lotsim.errors import ScenarioError
from lotsim.roadmap.model import LotGraph
from lotsim.sim.results import VehicleRun
from lotsim.traffic.disturbances import Closure, Disturbances, TakenBay
from lotsim.traffic.plans import Move, reserve_moves
from lotsim.traffic.swept import standing_body

if TYPE_CHECKING:  # the loop is the caller, passed in
    from lotsim.sim.loop import EventLoop

EPS = 1e-9


@dataclass
class ClosureRecord:
    """A closure as the run met it: the ground closed (``area``), from ``t0`` to ``t1``
    [s], the cars ``inside`` it (or driving into it) when it closed, which went on."""

    closure: Closure
    area: BaseGeometry
    t0: float
    t1: float
    inside: list[str] = field(default_factory=list)


@dataclass
class TakenRecord:
    """A bay taken: ``slot`` from ``t`` [s], the body of the car in it, and what it did:
    the car it was taken from (``moved``), or why it was not taken (``refused``)."""

    bay: TakenBay
    body: BaseGeometry | None
    moved: str | None = None
    refused: str = ""
    t: float = math.nan  # when the car stands there: the bay's time, or when the cars
    # planned past it before then have passed, in a run driven late

    def __post_init__(self) -> None:
        if math.isnan(self.t):
            self.t = self.bay.at


@dataclass(frozen=True)
class Replan:
    """A car planned again at ``t`` [s]: why, and what came of it."""

    car: str
    t: float
    why: str
    outcome: str


def lot_event_problem(lg: LotGraph, event: Closure | TakenBay) -> tuple[str, str] | None:
    """``(key, what is wrong)`` when ``event`` names what the lot does not have (a slot,
    an aisle, a gate), else None."""
    if isinstance(event, TakenBay):
        if event.slot in lg.lot.slot_by_id:
            return None
        return "slot", (f"expected a slot id, found {event.slot!r}: the lot has no slot "
                        f"{event.slot!r}")
    names = (lg.lot.aisles if event.kind == "aisle" else
             {lane.id: lane for lane in lg.lot.lanes} if event.kind == "lane" else
             {**lg.entrances, **lg.exits})
    if event.id in names:
        return None
    return event.kind, (f"expected one of the lot's {event.kind}s "
                        f"({', '.join(sorted(names))}), found {event.id!r}")


def check_lot_events(lg: LotGraph, spec: Disturbances | None) -> None:
    """Refuse closures and bays taken that name what the lot does not have.

    Raises
    ------
    ScenarioError
        Located where the scenario names it.
    """
    for event in () if spec is None else (*spec.taken, *spec.closures):
        problem = lot_event_problem(lg, event)
        if problem is not None:
            raise ScenarioError(event.where, problem[1])


def closure_area(lg: LotGraph, closure: Closure, vehicles) -> BaseGeometry:
    """The ground ``closure`` closes: an aisle's polygon; a lane's side of its aisle (the
    half right of the centre line in the lane's direction; a one-way aisle's whole width);
    or the ground every one of ``vehicles`` (types) stands on at a gate."""
    if closure.kind == "aisle":
        return lg.lot.aisles[closure.id].polygon
    if closure.kind == "lane":
        lane = next(lane for lane in lg.lot.lanes if lane.id == closure.id)
        aisle = lg.lot.aisles[lane.aisle]
        if len(aisle.lanes) == 1:
            return aisle.polygon
        # a single-sided buffer lies left of the line for a positive distance
        reach = 2 * aisle.width
        half = aisle.line.buffer(-reach if lane.with_polyline else reach, single_sided=True)
        side = shapely.intersection(half, aisle.polygon)
        # one polygon, as result.json writes it (its largest piece, should the lane's
        # strip leave slivers of the aisle's ends)
        return max(getattr(side, "geoms", [side]), key=lambda g: g.area)
    node = lg.entrances.get(closure.id, lg.exits.get(closure.id))
    pose = lg.graph.nodes[node]["pose"]
    return shapely.union_all([standing_body(t, pose) for t in vehicles])


def meets(loop: EventLoop, v: VehicleRun, area: BaseGeometry, t0: float, t1: float,
          *, from_move: int = 0) -> bool:
    """Whether ``v``'s moves from ``from_move`` on sweep ``area`` between ``t0`` and ``t1``
    [s] (standing in its slot aside)."""
    sg = loop.graphs[v.vehicle.name]
    for m in v.moves[from_move:]:
        if m.t1 <= t0 + EPS or m.t0 >= t1 - EPS or m.kind in ("outside", "parked"):
            continue
        if m.motion is None:
            if standing_body(v.vehicle, m.end_pose).intersects(area):
                return True
            continue
        sw = sg.motion(m.edge, m.level_from, m.level_to).swept
        t = sw.t + m.t0
        when = (t[:, 1] > t0 + EPS) & (t[:, 0] < t1 - EPS)
        if when.any() and shapely.intersects(sw.geoms[when], area).any():
            return True
    return False


def under_way(v: VehicleRun, t: float) -> int | None:
    """The index of ``v``'s move under way at ``t`` [s] (the first ending after it), None
    when its moves are all done by then."""
    return next((k for k, m in enumerate(v.moves) if m.t1 > t + EPS), None)


def entered(v: VehicleRun, t: float) -> bool:
    """Whether ``v`` is in the lot at ``t`` [s] by its plan (it set off by then)."""
    first = next((m for m in v.moves if m.kind != "outside"), None)
    return first is not None and first.t0 < t - EPS


def close(loop: EventLoop, closure: Closure, t: float) -> ClosureRecord:
    """``closure`` begins at ``t`` [s]: hold its ground, and plan again every car that
    would pass it while it lasts (not those in it, or driving into it, now)."""
    types = {v.vehicle.name: v.vehicle for v in loop.vehicles} | loop.types
    area = closure_area(loop.lg, closure, types.values())
    rec = ClosureRecord(closure, area, t, closure.end)
    for v in loop.vehicles:
        k = under_way(v, t)
        if k is None or not v.moves:
            continue
        if entered(v, t) and _in_it(loop, v, k, t, area):
            rec.inside.append(v.id)
    loop.table.reserve(f"closed:{closure.kind}:{closure.id}", [(t, closure.end, area)])
    for i, v in enumerate(loop.vehicles):
        k = under_way(v, t)
        if v.id in rec.inside or k is None:
            continue
        if meets(loop, v, area, t, closure.end, from_move=k + (entered(v, t))):
            repair(loop, i, v, t, f"{closure.kind} {closure.id!r} closed")
    return rec


def _in_it(loop: EventLoop, v: VehicleRun, k: int, t: float, area: BaseGeometry) -> bool:
    """Whether ``v`` stands in ``area`` at ``t`` or its move under way then reaches it."""
    m = v.moves[k]
    if m.motion is None:
        return m.kind != "outside" and standing_body(v.vehicle, m.end_pose).intersects(area)
    return meets(loop, dataclasses.replace(v, moves=[m]), area, t, m.t1)


def take(loop: EventLoop, bay: TakenBay, t: float) -> TakenRecord:
    """A car the plan does not know parks in ``bay.slot`` at ``t`` [s], unless a car is in
    or parking in it then; a car that was to park there is given another slot."""
    lot = loop.lg.lot
    slot = lot.slot_by_id.get(bay.slot)
    if slot is None:
        return TakenRecord(bay, None, refused="no such slot")
    if bay.slot in lot.occupied:
        return TakenRecord(bay, None, refused="it was occupied at the start")
    holder = next((i for i, v in enumerate(loop.vehicles)
                   if v.slot == bay.slot and not _left(v, t)), None)
    if holder is not None:
        v = loop.vehicles[holder]
        park = next((m for m in v.moves if m.kind == "park"), None)
        if park is not None and park.t0 < t + EPS:
            return TakenRecord(bay, None, refused=f"{v.id!r} was in it or parking in it")
    stranger = loop.scenario_parked
    body = standing_body(stranger, slot.centered_pose(stranger.front, stranger.rear))
    loop.table.reserve_standing(f"taken:{bay.slot}", body, t, in_slot=True)
    loop.free.discard(bay.slot)
    loop.taken.add(bay.slot)
    rec = TakenRecord(bay, body)
    if holder is not None:
        rec.moved = loop.vehicles[holder].id
        repair(loop, holder, loop.vehicles[holder], t, f"its bay {bay.slot!r} was taken")
    return rec


def _left(v: VehicleRun, t: float) -> bool:
    """Whether ``v`` has set off out of its slot by ``t`` [s]."""
    leave = next((m for m in v.moves if m.kind == "leave"), None)
    return leave is not None and leave.t0 < t + EPS


KEPT = "none found: it keeps its plan"
"""A repair's outcome when a car driving at speed found no other way and no stop: it drives
its plan on."""


def repair(loop: EventLoop, i: int, v: VehicleRun, t: float, why: str) -> Replan | None:
    """Plan ``v`` again from where it is at ``t`` [s]: a car not in the lot yet from its
    gate (its slot chosen anew), one on its way from the end of its move under way (to its
    slot, or another if that one can no longer be had; or to an exit). When no way is
    found, it stands there and tries again a little later. The repair's record (None when
    there was nothing to plan)."""
    if not entered(v, t):
        loop.table.release(v.id)
        _give_back(loop, v)
        v.moves, v.parked_at, v.parked_pose, v.depart_at = [], None, None, None
        v.status, v.done, v.reason = "waiting", False, why
        loop.replans.append(Replan(v.id, t, why, "to choose its slot again at its gate"))
        loop.at(t, "retry", i)
        return loop.replans[-1]
    k = under_way(v, t)
    if k is None and v.moves and v.moves[-1].kind == "wait":
        k = len(v.moves) - 1  # it stood until now (to try again)
    if k is None:
        return None
    last = v.moves[k]
    if last.kind == "parked":
        return None  # it plans its way out when it leaves
    if last.motion is None and last.t0 < t - EPS:
        last = dataclasses.replace(last, t1=t)
    kept = [*v.moves[:k], last]
    sg = loop.graphs[v.vehicle.name]
    v.done = False
    slots = [] if v.leaving else _slots_for(loop, v, t, last.node_to)
    in_slot = last.node_to == loop.lg.slot_nodes.get(v.slot)
    for sid in ([None] if v.leaving else slots):
        goal = (loop.exit_goal() if sid is None else loop.park_goal(v, sid))
        plan = loop.plan(v, sg, start=last.node_to, t0=last.t1, level=last.level_to,
                         goal=goal, start_pose=v.parked_pose if in_slot else None,
                         key=("exit", v.vehicle.name) if sid is None else ("slot", sid))
        if plan.status is Status.FOUND:
            loop.table.release(v.id, after=last.t1)
            old = v.slot
            if sid is not None and sid != old:
                _give_back(loop, v)
                loop.free.discard(sid)
                v.slot = sid
            v.moves = kept
            loop.commit(i, v, sg, plan)
            outcome = ("out to an exit" if sid is None else
                       f"to slot {sid!r}" + ("" if sid == old else f" (not {old!r})"))
            loop.replans.append(Replan(v.id, t, why, outcome))
            return loop.replans[-1]
    # no way now: it stands where its move under way ends (or, driving on, where its plan
    # first comes to rest), and tries again
    wait = loop.backoff(v)
    if last.level_to != 0:
        j = standstill(v, k)
        if j is None or not _free_to_stand(loop, v, v.moves[j], v.moves[j].t1 + wait):
            loop.replans.append(Replan(v.id, t, why, KEPT))
            return loop.replans[-1]
        last, kept = v.moves[j], v.moves[: j + 1]
    loop.table.release(v.id, after=last.t1)
    stand = Move("wait", last.t1, last.t1 + wait, last.node_to, last.node_to, 0, 0,
                 end_pose=last.end_pose if last.end_pose is not None else sg.pose[last.node_to],
                 steer=last.steer if last.motion is None else float(sg.steer[last.node_to]))
    v.moves = [*kept, stand]
    unsettle(v, why)
    # it holds its ground until it moves again (the next try, or a later one)
    reserve_moves(loop.table, v.id, sg, [stand], hold_end=True)
    loop.replans.append(Replan(v.id, t, why, f"none found: it stands and tries again at "
                                                f"{stand.t1:.1f} s"))
    loop.at(stand.t1, "repair", i)
    return loop.replans[-1]


def unsettle(v: VehicleRun, why: str) -> None:
    """``v`` stands on the lanes with no plan on from there yet (it will be planned again):
    it has not parked (or, on its way out, not left) yet, whatever its old plan said."""
    v.done, v.reason = False, why
    if v.leaving:
        v.left_at = None
    else:
        v.parked_at = v.parked_pose = v.depart_at = None
        v.status = "waiting"


def standstill(v: VehicleRun, k: int) -> int | None:
    """The index of the first of ``v``'s moves from ``k`` on that ends at rest on a lane
    (not in a slot, nor out of the lot): where a car driving on can next stand; None when
    its plan has none."""
    return next((j for j in range(k, len(v.moves)) if v.moves[j].level_to == 0
                 and v.moves[j].kind in ("drive", "wait")), None)


def _free_to_stand(loop: EventLoop, v: VehicleRun, m: Move, until: float) -> bool:
    """Whether ``v`` can stand where move ``m`` leaves it, from its end to ``until`` [s],
    as far as the others' reservations go."""
    body = standing_body(v.vehicle, m.end_pose)
    return loop.table.is_free([(m.t1, until, body)], ignore=v.id)


def _give_back(loop: EventLoop, v: VehicleRun) -> None:
    """``v``'s slot is free again (unless a car the plan does not know took it)."""
    if v.slot is not None and v.slot not in loop.taken:
        loop.free.add(v.slot)
    v.slot = None if not v.leaving else v.slot


def _slots_for(loop: EventLoop, v: VehicleRun, t: float, start: int) -> list[str]:
    """The slots ``v`` tries when planned again from node ``start``: its own while it can
    still have it, then the free ones it can use, best first (none it cannot reach while
    the closures last)."""
    away, _ = cut_off(loop, v.vehicle.name, start, t)
    own = [v.slot] if v.slot is not None and v.slot not in loop.taken \
        and v.slot not in away else []
    ranked = [s for s in loop.assigner.ranked(v.arrival, loop.free, t) if s not in away]
    return own + loop.assigner.probes(ranked, t)


def closed_slots(loop: EventLoop, t: float) -> set[str]:
    """The slots on aisles closed at ``t`` [s]."""
    aisles = {r.closure.id for r in loop.closures
              if r.closure.kind == "aisle" and r.t0 <= t < r.t1}
    if not aisles:
        return set()
    return {s.id for s in loop.lg.lot.slots if s.aisle in aisles}


def cut_off(loop: EventLoop, vname: str, start: int, t: float) -> tuple[set[str], bool]:
    """What a ``vname`` at node ``start`` cannot reach while the closures of ``t`` [s]
    last, along the lanes that keep clear of the closed ground: the slots (those on a
    closed aisle among them), and whether every exit. Kept for the run, by the closures
    open then."""
    active = tuple(k for k, r in enumerate(loop.closures) if r.t0 <= t < r.t1)
    if not active:
        return set(), False
    key = (active, vname, start)
    hit = loop.cut_cache.get(key)
    if hit is None:
        sg = loop.graphs[vname]
        shut = _shut_edges(loop, vname, active)
        seen, todo = {start}, [start]
        while todo:
            u = todo.pop()
            for ei in sg.out.get(u, ()):
                w = sg.edges[ei].v
                if w not in seen and ei not in shut:
                    seen.add(w)
                    todo.append(w)
        slots = {sid for sid, n in loop.lg.slot_nodes.items() if n not in seen}
        hit = loop.cut_cache[key] = (slots | closed_slots(loop, t),
                                     not any(n in seen for n in loop.lg.exits.values()))
    return hit


def shut_at(loop: EventLoop, vname: str, t: float) -> tuple[tuple[int, ...], frozenset[int]]:
    """The closures open at ``t`` [s] (indices into the run's) and the edges of ``vname``'s
    search graph they shut (:func:`_shut_edges`); both empty when none is."""
    active = tuple(k for k, r in enumerate(loop.closures) if r.t0 <= t < r.t1)
    if not active:
        return (), frozenset()
    return active, frozenset(_shut_edges(loop, vname, active))


def _shut_edges(loop: EventLoop, vname: str, active: tuple[int, ...]) -> set[int]:
    """The edges of ``vname``'s search graph whose path (through its pieces' ends) meets
    the ground of the closures ``active`` (indices into the run's closures); kept."""
    key = (active, vname)
    hit = loop.cut_cache.get(key)
    if hit is None:
        sg = loop.graphs[vname]
        lines = []
        for e in sg.edges:
            segs = e.maneuver.segments if e.maneuver is not None else e.data.get("path", ())
            pts = [seg.start[:2] for seg in segs] + ([segs[-1].end[:2]] if segs else [])
            if len(pts) < 2:
                pts = [sg.pose[e.u][:2], sg.pose[e.v][:2]]
            lines.append(shapely.LineString(pts))
        area = shapely.union_all([loop.closures[k].area for k in active])
        meet = shapely.intersects(np.array(lines, dtype=object), area)
        hit = loop.cut_cache[key] = set(np.flatnonzero(meet).tolist())
    return hit

@dataclass
class LotChanges:
    """What changed the lot in a run, and the repairs it took (a run's
    :attr:`~lotsim.sim.results.RunResult.lot_changes`)."""

    closures: list[ClosureRecord]
    taken: list[TakenRecord]
    replans: list[Replan]
    stalls: list = field(default_factory=list)  # asked for in a stepped run (StallRecord)

    def as_dict(self) -> dict:
        """As ``result.json``'s ``disturbances`` holds them (``docs/result.md``)."""
        def ring(g) -> list:
            geom = g if g.geom_type == "Polygon" else g.convex_hull
            return np.round(np.asarray(geom.exterior.coords)[:-1], 4).tolist()

        return {
            "closures": [{"kind": r.closure.kind, "id": r.closure.id, "t0": round(r.t0, 6),
                          "t1": round(r.t1, 6), "polygon": ring(r.area), "inside": r.inside}
                         for r in self.closures],
            "taken": [{"slot": r.bay.slot, "t": round(r.t, 6), "moved": r.moved,
                       "refused": r.refused,
                       "polygon": None if r.body is None else ring(r.body)}
                      for r in self.taken],
            "replans": [{"car": p.car, "t": round(p.t, 6), "why": p.why,
                         "outcome": p.outcome} for p in self.replans],
            **({"stalls": [r.as_dict() for r in self.stalls if not r.refused],
                "stalls_refused": [{"car": r.car, "at": round(r.at, 6), "why": r.refused}
                                   for r in self.stalls if r.refused]}
               if self.stalls else {}),
        }
