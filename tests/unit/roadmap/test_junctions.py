"""Junction turns (lotsim.roadmap.junctions) on two small lots: they join exactly the lanes
that meet, leave and land on the lanes' lines as worked out by hand, are drivable by the
kinematic bicycle model integrated step by step (no tighter than the car's lock, heading
and curvature continuous), and sweep a body that shapely finds on the pavement and clear
of the bays."""

import math

import numpy as np
import pytest
import shapely
from small_lots import CROSS, CROSS_LANES, TEE, TEE_LANES, lot_of

from lotsim.lot.build import lane_collider
from lotsim.roadmap.junctions import junction_turns
from lotsim.vehicles import CATALOGUE
from oracles.driving import bodies, breaks, curvature_jumps, drive, min_radius, on_line

VALET = CATALOGUE["valet"]


@pytest.fixture(scope="module")
def cross():
    lot = lot_of(CROSS)
    return lot, junction_turns(lot, lane_collider(lot))


@pytest.fixture(scope="module")
def tee():
    lot = lot_of(TEE)
    return lot, junction_turns(lot, lane_collider(lot))


def test_at_a_crossing_every_lane_turns_into_both_lanes_of_the_other_aisle(cross):
    # four lanes reach the crossing; each turns left and right into the other aisle, and
    # never into its own aisle's lanes
    _, (turns, skipped) = cross
    assert skipped == []
    ours = {"a": ("a>", "a<"), "b": ("b>", "b<")}
    expected = {(x, y) for mine, other in (("a", "b"), ("b", "a"))
                for x in ours[mine] for y in ours[other]}
    assert {(t.lane_a, t.lane_b) for t in turns} == expected


def test_at_a_tee_only_the_lanes_that_lead_into_the_junction_turn_out_of_it(tee):
    # the spur's up lane turns either way onto the aisle, and either lane of the aisle
    # turns down the spur's down lane; no turn runs into the spur's up lane (it leads
    # towards the junction) or out of its down lane (it leads away)
    _, (turns, _) = tee
    assert {(t.lane_a, t.lane_b) for t in turns} == {
        ("spur>", "a>"), ("spur>", "a<"), ("a>", "spur<"), ("a<", "spur<")}


@pytest.mark.parametrize("which", ["cross", "tee"])
def test_each_turn_leaves_its_lane_and_lands_on_the_other_heading_along_it(which, request):
    lot, (turns, _) = request.getfixturevalue(which)
    lines = {"cross": CROSS_LANES, "tee": TEE_LANES}[which]
    for t in turns:
        start = t.segments[0].start
        # it begins on its lane's line, at its station, heading along it
        assert on_line(start, lines[t.lane_a]) == pytest.approx(t.station_a, abs=1e-3)
        at, _, _ = drive(t.segments, start)
        # and, driven piece by piece, ends on the other lane's line at its station
        assert on_line(at[-1], lines[t.lane_b]) == pytest.approx(t.station_b, abs=1e-3), t
        assert breaks(t.segments, start) == []


@pytest.mark.parametrize("which", ["cross", "tee"])
def test_each_turn_is_no_tighter_than_the_car_steers_and_turns_its_wheels_smoothly(
        which, request):
    lot, (turns, _) = request.getfixturevalue(which)
    radius = min_radius(VALET)
    for t in turns:
        _, _, bends = drive(t.segments, t.segments[0].start)
        assert np.abs(bends).max() <= 1 / radius + 1e-9
        assert curvature_jumps(t.segments) == []
        # straight on the lanes at either end: the wheels straight as it leaves and lands
        assert t.segments[0].curvature == 0.0
        last = t.segments[-1]
        assert abs(last.curvature + last.sharpness * last.length) < 1e-9
        if not t.wide:  # a plain turn: clothoid, arc, clothoid through a right angle
            assert len(t.segments) == 3
            assert t.segments[1].sharpness == 0.0 and t.segments[1].curvature != 0.0
            turned = sum(s.curvature * s.length + s.sharpness * s.length ** 2 / 2
                         for s in t.segments)
            assert abs(turned) == pytest.approx(math.pi / 2, abs=1e-6)


@pytest.mark.parametrize("which", ["cross", "tee"])
def test_each_turn_sweeps_a_body_on_the_pavement_and_clear_of_every_bay(which, request):
    lot, (turns, _) = request.getfixturevalue(which)
    bays = shapely.union_all([s.shape for s in lot.slots])
    d = lot.design
    for t in turns:
        _, along, _ = drive(t.segments, t.segments[0].start)
        swept = bodies(np.concatenate(along), d.width, d.front, d.rear)
        assert shapely.covers(lot.boundary, swept).all(), t
        assert not shapely.intersects(swept, bays).any(), t

