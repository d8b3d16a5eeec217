"""Turns through a short stretch of lane between two junctions close together
(lotsim.roadmap.through), on the ladder: two aisles joined by a 17.8 m cross aisle, where a
car from the first into the second turns twice in the stretch. Checked against the lanes'
lines worked out by hand, a step-by-step integration of the kinematic bicycle model and
shapely."""

import dataclasses
import math

import numpy as np
import pytest
import shapely
from small_lots import LADDER, LADDER_LANES, lot_of

from lotsim.lot.build import lane_collider
from lotsim.roadmap.junctions import junction_turns
from lotsim.roadmap.through import through_chains, through_turn
from lotsim.vehicles import CATALOGUE
from oracles.driving import (
    bodies,
    breaks,
    curvature_jumps,
    drive,
    heading_gap,
    min_radius,
    on_line,
)


@pytest.fixture(scope="module")
def ladder():
    lot = lot_of(LADDER)
    collider = lane_collider(lot)
    turns, _ = junction_turns(lot, collider)
    return lot, collider, turns


def _chain(lot, turns, first: str, last: str):
    return next(c for c in through_chains(lot, turns) if (c[0].id, c[3].id) == (first, last))


def test_the_stretches_to_turn_through_are_those_where_a_wide_turn_overruns_the_next(ladder):
    # into the cross aisle from a1 and out of it into a2 (the two turns overlap on it), and
    # from the gate spur along a1 into the cross aisle; no stretch joins two lanes that a
    # turn joins already, or runs back onto the lane it came from
    lot, _, turns = ladder
    chains = through_chains(lot, turns)
    assert {(c[0].id, c[3].id) for c in chains} == {("a1<", "a2>"), ("spur>", "west>")}
    joined = {(t.lane_a, t.lane_b) for t in turns}
    for c in chains:
        assert (c[0].id, c[3].id) not in joined
        into = [t for t in turns if t.lane_a == c[0].id]
        out = [t for t in turns if t.lane_b == c[3].id]
        # a turn into the stretch ends past where one out of it begins
        assert any(t1.lane_b == t2.lane_a and t1.station_b > t2.station_a
                   for t1 in into for t2 in out)


def test_without_a_wide_turn_no_stretch_is_turned_through(ladder):
    # the overlap of two plain turns is left to them: only a wide one makes a stretch
    lot, _, turns = ladder
    plain = [dataclasses.replace(t, wide=False) for t in turns]
    assert through_chains(lot, plain) == []


def test_the_turn_from_one_aisle_into_the_next_runs_along_the_cross_aisle(ladder):
    lot, collider, turns = ladder
    got = through_turn(lot, collider, None, _chain(lot, turns, "a1<", "a2>"))
    assert got
    west = lot.aisles["west"].line.buffer(3.5)
    radius = min_radius(CATALOGUE["valet"])
    bays = shapely.union_all([s.shape for s in lot.slots])
    d = lot.design
    for t in got:
        assert (t.lane_a, t.lane_b) == ("a1<", "a2>")
        start = t.segments[0].start
        assert on_line(start, LADDER_LANES["a1<"]) == pytest.approx(t.station_a, abs=1e-3)
        at, along, bends = drive(t.segments, start)
        assert on_line(at[-1], LADDER_LANES["a2>"]) == pytest.approx(t.station_b, abs=1e-3)
        assert breaks(t.segments, start) == [] and curvature_jumps(t.segments) == []
        assert np.abs(bends).max() <= 1 / radius + 1e-9
        poses = np.concatenate(along)
        # from heading west to heading east, through heading north on the way
        assert heading_gap(poses[-1, 2], poses[0, 2]) == pytest.approx(math.pi, abs=1e-3)
        assert min(heading_gap(h, math.pi / 2) for h in poses[:, 2]) < 1e-2
        # half way along, it drives in the cross aisle
        assert west.contains(shapely.Point(poses[len(poses) // 2][:2]))
        swept = bodies(poses, d.width, d.front, d.rear)
        assert shapely.covers(lot.boundary, swept).all()
        assert not shapely.intersects(swept, bays).any()
