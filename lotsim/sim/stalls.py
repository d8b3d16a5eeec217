"""A car that stalls while a run is stepped (:meth:`lotsim.Live.stall`): it stops where its
plan next brings it to rest on the lanes, stands there for the stall, and is then planned
again from where it stands; the cars whose plans pass where it stands are planned round it
at once (a repair each), rather than queuing behind it.

Where a car that must pass comes at speed with no way round and no stop before it, the
stall moves to the stalled car's next place of rest; where none is left, it is not had
(recorded with the reason).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING

from lotsim.sim import repairs
from lotsim.sim.results import VehicleRun
from lotsim.traffic.plans import Move, reserve_moves
from lotsim.traffic.swept import standing_body

if TYPE_CHECKING:  # the loop is the caller, passed in
    from lotsim.sim.loop import EventLoop


@dataclass(frozen=True)
class StallRecord:
    """A stall met in a stepped run: ``car`` stood still from ``t0`` to ``t1`` [s] for a
    stall asked for at ``at``; or, with ``refused``, it was not had, and why."""

    car: str
    at: float
    duration: float
    t0: float = math.nan
    t1: float = math.nan
    refused: str = ""

    def as_dict(self) -> dict:
        """As ``result.json``'s ``disturbances.stalls`` holds a stall (``refused`` ones
        are not there: see :attr:`repairs.LotChanges.stalls_refused`)."""
        return {"car": self.car, "t0": round(self.t0, 6), "t1": round(self.t1, 6),
                "at": round(self.at, 6)}


def stall(loop: EventLoop, i: int, v: VehicleRun, t: float, duration: float) -> StallRecord:
    """``v`` stalls at ``t`` [s] for ``duration`` [s]: what came of it."""
    if not v.moves or not repairs.entered(v, t) or v.left_at is not None and v.left_at <= t:
        return StallRecord(v.id, t, duration, refused="it is not in the lot then")
    k = repairs.under_way(v, t)
    if k is None:  # its plan is done: it is parked, or stands for good
        return StallRecord(v.id, t, duration, refused="its plan has no way left to drive")
    rests = _rests(v, k, t)
    for j in rests:
        rec = _try(loop, i, v, t, j, duration)
        if rec is not None:
            return rec
    return StallRecord(v.id, t, duration, refused=(
        "the cars coming could not go round it where its plan next brings it to rest"
        if rests else "its plan brings it to rest on the lanes no more before it parks"))


def _rests(v: VehicleRun, k: int, t: float) -> list[int]:
    """The indices of ``v``'s moves from ``k`` on after which it is at rest on the lanes
    (after a drive, a multi-point turn, out of its slot, or a wait), before it parks."""
    out = []
    for j in range(k, len(v.moves)):
        if v.moves[j].kind in ("park", "parked"):  # it stalls on its way, not after it
            break
        if v.moves[j].level_to == 0 and v.moves[j].kind in ("drive", "wait", "turnaround",
                                                              "leave"):
            out.append(j)
    return out


def _try(loop: EventLoop, i: int, v: VehicleRun, t: float, j: int, duration: float
         ) -> StallRecord | None:
    """``v`` stands after its move ``j`` for ``duration``, the cars that would meet it there
    planned round it; None (and nothing changed) when one of them cannot be."""
    m = v.moves[j]
    t0 = t if m.kind == "wait" and m.t0 < t else m.t1  # standing now: it stalls from now
    sg = loop.graphs[v.vehicle.name]
    pose = m.end_pose if m.end_pose is not None else sg.pose[m.node_to]
    body = standing_body(v.vehicle, pose)
    keep = v.moves[:j] + [replace(m, t1=t0) if m.kind == "wait" else m]
    stand = Move("wait", t0, t0 + duration, m.node_to, m.node_to, 0, 0, end_pose=pose,
                 steer=m.steer if m.motion is None else float(sg.steer[m.node_to]))
    # the others planned over that ground while it stands (or after, until it has a plan)
    crossing = []
    for c, u in enumerate(loop.vehicles):
        ku = repairs.under_way(u, t)
        if u is v or ku is None or not repairs.meets(loop, u, body, t0, math.inf,
                                                     from_move=ku):
            continue
        if repairs.meets(loop, u, body, t0, u.moves[ku].t1, from_move=ku):
            return None  # it is on that ground then, in the move it is making
        crossing.append((c, u, ku))
    kept = {id(u): _snapshot(u) for _, u, _ in crossing} | {id(v): _snapshot(v)}
    free, mark = set(loop.free), len(loop.replans)
    loop.table.release(v.id, after=t0)
    v.moves = [*keep, stand]
    repairs.unsettle(v, "stalled")
    reserve_moves(loop.table, v.id, sg, [stand], hold_end=True)
    for c, u, ku in crossing:
        if repairs.entered(u, t):
            loop.table.release(u.id, after=u.moves[ku].t1)
        rec = repairs.repair(loop, c, u, t, f"{v.id!r} stalled in its way")
        if rec is not None and rec.outcome.startswith("none found") and repairs.entered(u, t):
            # it comes at speed with no way round: put every plan back as it was
            for w in (v, *(u for _, u, _ in crossing)):
                loop.table.release(w.id, after=t)
                _restore(w, kept[id(w)])
                _reserve_from(loop, w, t)
            loop.free.clear()
            loop.free.update(free)
            del loop.replans[mark:]
            return None
    loop.at(stand.t1, "repair", i)
    return StallRecord(v.id, t, duration, t0, stand.t1)


def _snapshot(v: VehicleRun) -> dict:
    return {f.name: getattr(v, f.name) for f in fields(v)} | {"moves": list(v.moves)}


def _restore(v: VehicleRun, kept: dict) -> None:
    for name, value in kept.items():
        setattr(v, name, value)


def _reserve_from(loop: EventLoop, u: VehicleRun, t: float) -> None:
    """Reserve again ``u``'s moves from the one under way at ``t`` [s] (its plan put back
    after its reservations from ``t`` on were released)."""
    k = repairs.under_way(u, t)
    if k is None:
        return
    reserve_moves(loop.table, u.id, loop.graphs[u.vehicle.name], u.moves[k:],
                  hold_end=u.left_at is None and u.moves[-1].kind != "outside")
