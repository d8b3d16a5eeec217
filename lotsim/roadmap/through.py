"""Turns through a short stretch of lane between two junctions close together: one path from
the first lane into the last along the stretch, where a turn into it would overrun the start
of the turn out of it."""

from __future__ import annotations

from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle, Lot
from lotsim.roadmap.area_turns import area_turns
from lotsim.roadmap.lanes import EPS, straight_at
from lotsim.roadmap.model import Turn
from lotsim.roadmap.settings import DEFAULTS, RoadmapSettings


def through_chains(lot: Lot, turns: list[Turn], *, settings: RoadmapSettings = DEFAULTS
                   ) -> list[tuple]:
    """The short stretches of lane to turn through: where a turn into lane ``c`` ends past
    where a turn out of it begins, by less than
    :attr:`~lotsim.roadmap.settings.TurnSettings.through_overlap` (two junctions close
    together, one turn swinging wide) and no turn joins the two outer lanes already, none
    back onto the lane it came from.
    For each, the first lane, the start station and straight of it the turn leaves from,
    the last lane and its straight likewise, and the stretch's straight."""
    lanes = {lane.id: lane for lane in lot.lanes}
    into: dict[str, list[Turn]] = {}
    for tn in turns:
        into.setdefault(tn.lane_b, []).append(tn)
    joined = {(tn.lane_a, tn.lane_b) for tn in turns}
    done = set()
    out = []
    most = settings.turns.through_overlap
    for t2 in turns:
        for t1 in into.get(t2.lane_a, ()):
            chain = (t1.lane_a, t2.lane_a, t2.lane_b)
            overlap = t1.station_b - t2.station_a
            if (t1.lane_a == t2.lane_b or chain[::2] in joined or chain in done
                    or not (t1.wide or t2.wide) or not EPS < overlap < most):
                continue
            done.add(chain)
            a, c, b = lanes[t1.lane_a], lanes[t2.lane_a], lanes[t2.lane_b]
            pieces = [straight_at(lane, st) for lane, st in
                      ((a, t1.station_a), (c, (t1.station_b + t2.station_a) / 2),
                       (b, t2.station_b))]
            if any(p is None for p in pieces):
                continue
            (sa0, pa), (_, pc), (sb0, pb) = pieces
            out.append((a, sa0, pa, b, sb0, pb, pc))
    return out


def through_turn(lot: Lot, collider: Collider, design: DesignVehicle | None,
                 chain: tuple, *, settings: RoadmapSettings = DEFAULTS) -> list[Turn]:
    """The turns through one of :func:`through_chains`: from the first lane into the last
    along the stretch (:func:`~lotsim.roadmap.area_turns.area_turns` with ``via``, shifted
    as the area turns are), swept clear with ``design`` (default the lot's design
    vehicle)."""
    a, sa0, pa, b, sb0, pb, pc = chain
    area = settings.area_turns
    return area_turns(a, sa0, pa, b, sb0, pb, design or lot.design, collider,
                      lot.speed_limit, via=(pc,), shifts=area.shifts, settings=area,
                      sweep=lot.settings.sweep)
