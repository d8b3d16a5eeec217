"""U-turns at junctions (lotsim.roadmap.uturns) on the small crossing: each lane of a two-way
aisle turns back onto its aisle's other lane in the crossing aisle's mouth, ending on that
lane's line heading the way it runs (the reverse of where it began); checked against the
lanes' lines worked out by hand, a step-by-step integration of the kinematic bicycle model
and shapely."""

import math

import numpy as np
import pytest
import shapely
from small_lots import CROSS, CROSS_LANES, lot_of

from lotsim.roadmap.memo import RoadmapMemo
from lotsim.roadmap.uturns import junction_uturns
from lotsim.vehicles import CATALOGUE
from oracles.driving import bodies, breaks, drive, heading_gap, min_radius, on_line

MARGIN = 0.1
"""The clearance a multi-point turn keeps to bays and the boundary [m]."""

BACK = {"a>": "a<", "a<": "a>", "b>": "b<", "b<": "b>"}
"""Each lane of the crossing and its aisle's other lane."""

CROSSING = 28.25
"""Station [m] on each lane where it first meets a lane of the other aisle (the lanes lie
1.75 m either side of the centre lines, and every lane begins 30 m from the centre)."""
MEET = 31.75
"""Station [m] abeam of that point on the aisle's other lane, which runs the other way."""


@pytest.fixture(scope="module")
def cross():
    lot = lot_of(CROSS)
    return lot, junction_uturns(lot, None, RoadmapMemo(lot))


def test_each_lane_turns_back_onto_its_aisles_other_lane_once(cross):
    _, found = cross
    assert sorted((t.lane_a, t.lane_b) for t, _ in found) == sorted(BACK.items())
    assert all(types is None for _, types in found)  # the one type drives them all


def test_a_uturn_ends_on_the_other_lane_heading_its_way_the_reverse_of_its_start(cross):
    _, found = cross
    for t, _ in found:
        start = t.segments[0].start
        assert on_line(start, CROSS_LANES[t.lane_a]) == pytest.approx(t.station_a, abs=1e-3)
        at, _, _ = drive(t.segments, start)
        assert on_line(at[-1], CROSS_LANES[t.lane_b]) == pytest.approx(t.station_b, abs=1e-3)
        assert heading_gap(at[-1][2], start[2] + math.pi) < 1e-3
        # it begins at most 6 m before the crossing, and lands from 2 m before the point
        # abeam of it on the lane it joins to 8 m past
        assert CROSSING - 6 - 1e-6 <= t.station_a <= CROSSING + 1e-6
        assert MEET - 2 - 1e-6 <= t.station_b <= MEET + 8 + 1e-6


def test_a_uturn_is_a_few_strokes_no_tighter_than_the_car_steers(cross):
    _, found = cross
    radius = min_radius(CATALOGUE["valet"])
    for t, _ in found:
        gears = [s.gear for s in t.segments]
        assert {1, -1} <= set(gears) and gears[-1] == 1  # forward and back, forward last
        assert t.changes == sum(a != b for a, b in zip(gears, gears[1:], strict=False))
        _, _, bends = drive(t.segments, t.segments[0].start)
        assert np.abs(bends).max() <= 1 / radius + 1e-9
        assert breaks(t.segments, t.segments[0].start) == []


def test_a_uturn_keeps_its_margin_to_the_boundary_and_the_bays(cross):
    lot, found = cross
    d = lot.design
    bays = shapely.union_all([s.shape for s in lot.slots])
    inside = lot.boundary.buffer(-MARGIN + 0.01)
    for t, _ in found:
        swept = bodies(np.concatenate(drive(t.segments, t.segments[0].start)[1]), d.width,
                       d.front, d.rear)
        assert shapely.covers(inside, swept).all()
        assert shapely.distance(swept, bays).min() >= MARGIN - 0.01


def test_one_way_aisles_have_no_uturns():
    one_way = CROSS.replace("width: 7.0}", "width: 7.0, direction: one-way}")
    one_way = one_way.replace("y: 28.25", "y: 30").replace("x: 6, y: 31.75, heading_deg: 180",
                                                           "x: 54, y: 30, heading_deg: 0")
    lot = lot_of(one_way)
    assert all(aisle.one_way for aisle in lot.aisles.values())
    assert junction_uturns(lot, None, RoadmapMemo(lot)) == []
