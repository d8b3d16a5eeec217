"""Cars that are inside the lot when they come into a run: one standing in a bay, to be
called out later (a valet's car, a car parked before the run began), or one standing on
a lane (dropped there, or let in by hand), which sets off for a slot.

Either holds its ground from the moment it is there: a car in a bay keeps the bay, a car
on a lane keeps its footprint in the reservation table until it moves — unlike a car
queued outside a gate, which takes no space. A car on a lane stands at a roadmap node
(:func:`lane_node_near` finds the one a pose means).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from lotsim.roadmap.model import LotGraph
from lotsim.sim import repairs
from lotsim.sim.results import VehicleRun
from lotsim.traffic.plans import Move, reserve_moves
from lotsim.traffic.searchgraph import SearchGraph
from lotsim.traffic.swept import standing_body

if TYPE_CHECKING:  # the loop is the caller, passed in
    from lotsim.sim.loop import EventLoop

REACH = 2.5
"""How far a pose given for a car on a lane may lie from the lane node it means [m]: about
half the spacing of a lane's nodes."""

TURN = math.radians(30.0)
"""How far its heading may differ from that node's [rad]."""


def lane_node_near(lg: LotGraph, pose) -> tuple[int | None, str]:
    """The lane node a car standing at ``pose`` ``(x, y, theta)`` [m, rad] means: the
    nearest within :data:`REACH` whose heading is within :data:`TURN` of the pose's; or
    None, with what is nearest (for the error)."""
    x, y, th = (float(c) for c in pose)
    nodes = [(n, d["pose"]) for n, d in lg.graph.nodes(data=True) if d.get("kind") == "lane"]
    if not nodes:
        return None, "the lot has no lane"
    ids = np.array([n for n, _ in nodes])
    xyt = np.array([p for _, p in nodes], dtype=float)
    dist = np.hypot(xyt[:, 0] - x, xyt[:, 1] - y)
    turn = np.abs((xyt[:, 2] - th + math.pi) % (2 * math.pi) - math.pi)
    ok = (dist <= REACH) & (turn <= TURN)
    if ok.any():
        k = int(np.flatnonzero(ok)[np.argmin(dist[ok])])
        return int(ids[k]), ""
    k = int(np.argmin(dist))
    return None, (f"the nearest lane pose is ({xyt[k, 0]:.2f}, {xyt[k, 1]:.2f}, "
                  f"{xyt[k, 2]:.3f}) on lane {lg.graph.nodes[int(ids[k])]['lane']!r}, "
                  f"{dist[k]:.2f} m away and {turn[k]:.3f} rad round (at most {REACH} m "
                  f"and {TURN:.3f} rad)")


def bay_pose(sg: SearchGraph, slot_node: int, leave_set, leaving: bool
             ) -> tuple[float, float, float] | None:
    """Where a car of ``sg``'s type stands in the slot at ``slot_node``: the pose a park
    edge leaves it on that it can leave again by (the one of the quickest way out), or for
    a car that stays (``leaving`` false) any park edge's; None when it has none."""
    best = None
    for ei in sg.into.get(slot_node, ()):
        e = sg.edges[ei]
        if e.kind != "park":
            continue
        if leaving and ((e.u, e.v) not in leave_set or e.park_only):
            continue
        pose = sg.parked_pose(ei)
        out = min((sg.edges[k].duration for k in sg.out.get(slot_node, ())
                   if sg.edges[k].kind == "leave"
                   and _same(sg.parked_pose(k), pose)), default=math.inf)
        key = (out if leaving else 0.0, ei)
        if best is None or key < best[0]:
            best = (key, pose)
    return None if best is None else best[1]


def _same(a, b) -> bool:
    return all(abs(p - q) < 1e-6 for p, q in zip(a, b, strict=True))


def why_not_here(loop: EventLoop, v: VehicleRun, t: float) -> str | None:
    """Why ``v`` (a car inside the lot) cannot be where it says at ``t`` [s], or None."""
    a = v.arrival
    sg = loop.graphs[v.vehicle.name]
    if a.slot is not None:
        if a.slot not in loop.free or a.slot in loop.lg.infeasible.get(v.vehicle.name, {}):
            return f"slot {a.slot!r}: {loop.why_not(v, a.slot, t)}"
        if bay_pose(sg, loop.lg.slot_nodes[a.slot], loop.leave[v.vehicle.name],
                    a.dwell is not None) is None:
            return (f"slot {a.slot!r}: a {v.vehicle.name!r} has no way "
                    + ("out of it to an exit" if a.dwell is not None else "to stand in it"))
        return None
    node = loop.assigner.starts[a.id]
    body = standing_body(v.vehicle, sg.pose[node])
    for r in loop.closures:
        if r.t0 <= t < r.t1 and r.area.intersects(body):
            return f"the {r.closure.kind} {r.closure.id!r} is closed there until {r.t1:g} s"
    for u in loop.vehicles:
        if u is v or not u.moves:
            continue
        k = repairs.under_way(u, t)
        if k is None:
            if _standing_at(u, t) and standing_body(
                    u.vehicle, u.moves[-1].end_pose).intersects(body):
                return f"{u.id!r} is there at {t:g} s"
            continue
        m = u.moves[k]
        # the move a car is making now it makes to its end
        if repairs.meets(loop, u, body, t - repairs.EPS, m.t1, from_move=k):
            return (f"{u.id!r} is there at {t:g} s, or gets there in the move it is making "
                    f"(until {m.t1:.2f} s)")
    return None


def _standing_at(u: VehicleRun, t: float) -> bool:
    """Whether ``u`` stands where its last move left it at ``t`` [s] (its moves done, and
    it has not left the lot)."""
    return (u.moves[-1].t1 <= t + repairs.EPS and u.left_at is None
            and u.moves[-1].end_pose is not None)


def place(loop: EventLoop, i: int, v: VehicleRun, t: float) -> None:
    """``v``, inside the lot, is there from ``t`` [s]: in its bay (called out after its
    dwell), or on its lane, where it looks for a slot and, finding no way yet, stands,
    the cars planned through its ground planned again. It is turned away, with the reason,
    when it is found where another car is, or where one drives at speed with no way round
    it and no stop before it."""
    why = why_not_here(loop, v, t)
    if why is not None:
        loop.finish(v, "rejected", f"could not be placed: {why}")
        return
    a = v.arrival
    sg = loop.graphs[v.vehicle.name]
    if a.slot is not None:
        node = loop.lg.slot_nodes[a.slot]
        pose = bay_pose(sg, node, loop.leave[v.vehicle.name], a.dwell is not None)
        loop.free.discard(a.slot)
        v.slot, v.parked_at, v.parked_pose = a.slot, t, pose
        v.moves = [Move("parked", t, t, node, node, 0, 0, end_pose=pose)]
        loop.table.reserve_standing(v.id, standing_body(v.vehicle, pose), t, in_slot=True)
        v.status, v.reason = "parked", ""
        loop.handled(v, 1)
        if a.dwell is None:
            loop.finish(v, "parked")
        else:
            v.depart_at = t + a.dwell
            loop.at(v.depart_at, "depart", i)
        return
    node = loop.assigner.starts[a.id]
    pose = sg.pose[node]
    v.moves = [Move("wait", t, t, node, node, 0, 0, end_pose=pose,
                    steer=float(sg.steer[node]))]
    body = standing_body(v.vehicle, pose)
    # it is there: it goes first. The cars planned through its ground give up their plans
    # from the end of the move each is making, it looks for its way, then they look for
    # theirs round it.
    crossing = []
    for j, u in enumerate(loop.vehicles):
        k = repairs.under_way(u, t)
        if u is not v and k is not None and repairs.meets(
                loop, u, body, t, math.inf, from_move=k + repairs.entered(u, t)):
            crossing.append((j, u, k))
            if repairs.entered(u, t):
                loop.table.release(u.id, after=u.moves[k].t1)
    loop.table.reserve_standing(v.id, body, t)
    loop.on_retry(i, v, t)
    for j, u, k in crossing:
        before = (list(u.moves), u.reason, len(loop.replans))
        rec = repairs.repair(loop, j, u, t, f"{v.id!r} stands in its way")
        if rec is not None and rec.outcome.startswith("none found") and repairs.entered(u, t):
            # no way round it: the car there first drives its plan on as it was, and the
            # one on the lane is turned away
            loop.table.release(u.id, after=u.moves[k].t1)
            u.moves, u.reason = before[0], before[1]
            del loop.replans[before[2]:]
            reserve_moves(loop.table, u.id, loop.graphs[u.vehicle.name], u.moves[k + 1:],
                          hold_end=u.left_at is None)
            _turn_away(loop, i, v, f"could not stand there: {u.id!r} comes there with no "
                                   f"way round it")
            return


def _turn_away(loop: EventLoop, i: int, v: VehicleRun, why: str) -> None:
    """Take ``v`` (a car on a lane) out of the run again, rejected for ``why``."""
    loop.table.release(v.id)
    if i in loop.queue:
        loop.queue.remove(i)
    if v.slot is not None and v.slot not in loop.taken:
        loop.free.add(v.slot)
    v.moves, v.slot, v.parked_at, v.parked_pose, v.depart_at = [], None, None, None, None
    loop.finish(v, "rejected", why)


def set_off(loop: EventLoop, v: VehicleRun, t: float) -> tuple[int, bool]:
    """Where ``v`` sets off for a slot at ``t`` [s] and whether from outside: its entrance,
    or (a car on a lane) its node, its standing stretched to ``t``."""
    a = v.arrival
    if not a.inside:
        return loop.lg.entrances[a.entrance], True
    last = v.moves[-1]
    if last.t1 < t:
        v.moves[-1] = Move(last.kind, last.t0, t, last.node_from, last.node_to, 0, 0,
                           end_pose=last.end_pose, steer=last.steer)
    return last.node_to, False
