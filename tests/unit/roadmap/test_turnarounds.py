"""Turnarounds at dead ends (lotsim.roadmap.turnarounds) on the small street: the multi-point
turn from the end of the east-bound lane ends on the west-bound lane's line heading west
(the reverse of the lane it left), in strokes no tighter than the car's lock, keeping its
margin to the walls and bays (a step-by-step integration of the kinematic bicycle model and
shapely); a street narrower than the car is long has none; the graph turns round where the
street is a dead end and nowhere else."""

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import box
from small_lots import STREET, STREET_LANES, lot_of

from lotsim.core.geometry import Segment
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle, Lane
from lotsim.roadmap.assemble import build_graph
from lotsim.roadmap.turnarounds import plan_turnarounds, turnaround_collider
from lotsim.vehicles import CATALOGUE
from oracles.driving import bodies, breaks, drive, heading_gap, min_radius, on_line

MARGIN = 0.1
"""The clearance a turnaround keeps to walls, bays and the boundary [m]."""


@pytest.fixture(scope="module")
def street():
    lot = lot_of(STREET)
    lanes = {lane.id: lane for lane in lot.lanes}
    found = plan_turnarounds(lanes["e>"], lanes["e<"], *turnaround_collider(lot),
                             lot.design.min_radius)
    return lot, found.value


def test_the_turnaround_ends_on_the_opposite_lane_heading_back(street):
    lot, found = street
    assert isinstance(found, list) and found, found
    for t in found:
        assert (t.lane_a, t.lane_b) == ("e>", "e<")
        start = t.segments[0].start
        # it begins on the lane at most 6 m before its end (x = 36)
        assert on_line(start, STREET_LANES["e>"]) == pytest.approx(t.station_a, abs=1e-3)
        assert 30.0 - 1e-6 <= t.station_a <= 36.0 + 1e-6
        at, _, _ = drive(t.segments, start)
        assert on_line(at[-1], STREET_LANES["e<"]) == pytest.approx(t.station_b, abs=1e-3)
        assert heading_gap(at[-1][2], start[2]) == pytest.approx(math.pi, abs=1e-3)
        assert breaks(t.segments, start) == []


def test_the_turnaround_is_a_few_strokes_no_tighter_than_the_car_steers(street):
    _, found = street
    radius = min_radius(CATALOGUE["valet"])
    for t in found:
        gears = [s.gear for s in t.segments]
        assert {1, -1} <= set(gears) and gears[-1] == 1
        assert 1 <= t.changes == sum(a != b for a, b in zip(gears, gears[1:], strict=False))
        assert t.changes <= 8
        _, _, bends = drive(t.segments, t.segments[0].start)
        assert np.abs(bends).max() <= 1 / radius + 1e-9


def test_the_turnaround_keeps_its_margin_to_the_walls_and_bays(street):
    lot, found = street
    d = lot.design
    bays = shapely.union_all([s.shape for s in lot.slots])
    inside = lot.boundary.buffer(-MARGIN + 0.01)
    for t in found:
        swept = bodies(np.concatenate(drive(t.segments, t.segments[0].start)[1]), d.width,
                       d.front, d.rear)
        assert shapely.covers(inside, swept).all()
        assert shapely.distance(swept, bays).min() >= MARGIN - 0.01
        # it uses the street's end: within a car's length of the closed east end
        assert shapely.bounds(swept)[:, 2].max() > 40 - MARGIN - 0.5


def test_a_street_narrower_than_the_car_is_long_has_no_turnaround():
    # heading from east to west the car heads north at some instant, when it spans its
    # length (4.9 m) across a 4.5 m street: no turnaround exists, and none is claimed
    car = DesignVehicle(1.8, 3.9, 1.0, 4.97, 0.15, 2.0)
    east = Lane("e", "a", (Segment((0.0, 1.125, 0.0), 36.0, 0.0),), 1.125, True)
    west = Lane("w", "a", (Segment((36.0, 3.375, math.pi), 36.0, 0.0),), 1.125, False)
    assert car.front + car.rear > 4.5
    got = plan_turnarounds(east, west, Collider([], box(0, 0, 40, 4.5)), car, 4.97)
    assert not got.found and "no multi-point turn" in got.reason


def _turnarounds(lot):
    g = build_graph(lot).graph
    return [(g.nodes[u]["lane"], g.nodes[v]["lane"], d["path"])
            for u, v, d in g.edges(data=True) if d["kind"] == "turnaround"]


def test_the_graph_turns_round_at_the_dead_end_and_nowhere_else():
    # the one gate pair is at the west end: a car that came down e> turns round at its end
    got = _turnarounds(lot_of(STREET))
    assert [(a, b) for a, b, _ in got] == [("e>", "e<")] * len(got) and got
    for _, _, path in got:
        assert path[0].start[0] >= 30.0 - 1e-6
    # with an exit on e> near its end the street is no dead end: a car leaves by it
    through = STREET.replace("exits:\n", "exits:\n    - {id: far, x: 30, y: 2.25, "
                             "heading_deg: 0}\n")
    assert _turnarounds(lot_of(through)) == []
