"""Junction turns through the junction's area (lotsim.roadmap.area_turns) at the small tee,
where the right turn between the lanes would sweep over a corner bay: checked against a
quarter circle worked out by hand, a step-by-step integration of the kinematic bicycle model
and shapely, and searched again around a post and in a junction walled off."""

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import box
from small_lots import TEE, TEE_LANES, lot_of

from lotsim.lot.build import lane_collider, obstacle_polygons
from lotsim.lot.clearance import Collider
from lotsim.roadmap.area_turns import area_turns
from lotsim.roadmap.junctions import junction_turns
from lotsim.roadmap.lanes import straights
from lotsim.vehicles import CATALOGUE
from oracles.driving import bodies, breaks, curvature_jumps, drive, min_radius, on_line

VALET = CATALOGUE["valet"]


@pytest.fixture(scope="module")
def tee():
    lot = lot_of(TEE)
    return lot, junction_turns(lot, lane_collider(lot))[0]


def _right_turns(turns):
    return [t for t in turns if (t.lane_a, t.lane_b) == ("spur>", "a>")]


def _swept(lot, t):
    _, along, _ = drive(t.segments, t.segments[0].start)
    d = lot.design
    return bodies(np.concatenate(along), d.width, d.front, d.rear)


def test_the_right_turn_by_the_corner_bay_swings_wide_through_the_junction(tee):
    # a quarter circle of the car's radius between the spur's up lane (x = 26.5) and the
    # aisle's east lane (y = 13.5) sweeps over the corner bay E1 (x 28-30.5, y 7-12): the
    # turns found instead use the junction's area, and keep clear of it
    lot, turns = tee
    r = min_radius(VALET)
    cx, cy = 26.5 + r, 13.5 - r  # the arc's centre, right of the spur's up lane
    phi = np.linspace(math.pi, math.pi / 2, 200)
    arc = np.column_stack([cx + r * np.cos(phi), cy + r * np.sin(phi), phi - math.pi / 2])
    d = lot.design
    e1 = lot.slot_by_id["E1"].shape
    assert shapely.intersects(bodies(arc, d.width, d.front, d.rear), e1).any()
    right = _right_turns(turns)
    assert right and all(t.wide for t in right)
    for t in right:
        assert not shapely.intersects(_swept(lot, t), e1).any()
        # wide of the corner: its body reaches across the aisle's centre line (y = 15)
        # or the spur's (x = 25), where the plain turn's does not
        poses = np.concatenate(drive(t.segments, t.segments[0].start)[1])
        assert poses[:, 1].max() > 15.0 or poses[:, 0].min() < 25.0


def test_a_wide_turn_is_drivable_and_lands_on_its_lane(tee):
    lot, turns = tee
    wide = [t for t in turns if t.wide]
    assert len(wide) >= 2
    radius = min_radius(VALET)
    for t in wide:
        start = t.segments[0].start
        assert on_line(start, TEE_LANES[t.lane_a]) == pytest.approx(t.station_a, abs=1e-3)
        at, _, bends = drive(t.segments, start)
        assert on_line(at[-1], TEE_LANES[t.lane_b]) == pytest.approx(t.station_b, abs=1e-3)
        assert breaks(t.segments, start) == []
        assert curvature_jumps(t.segments) == []  # each corner continuous in curvature
        assert np.abs(bends).max() <= 1 / radius + 1e-9
        assert all(s.gear == 1 for s in t.segments)


def _right_turn_search(lot, collider):
    lanes = {lane.id: lane for lane in lot.lanes}
    a, b = lanes["spur>"], lanes["a>"]
    (sa0, pa), = straights(a)
    (sb0, pb), = straights(b)
    return area_turns(a, sa0, pa, b, sb0, pb, lot.design, collider, lot.speed_limit)


def test_a_post_where_the_quickest_wide_turn_runs_moves_the_search_elsewhere(tee):
    # a post on the quickest right turn's path: the turns searched again keep clear of it
    lot, turns = tee
    quick = _right_turns(turns)[0]
    at, along, _ = drive(quick.segments, quick.segments[0].start)
    poses = np.concatenate(along)
    x, y, _ = poses[len(poses) // 2]
    post = shapely.Point(x, y).buffer(0.3)
    base = lane_collider(lot)
    around = [*obstacle_polygons(lot.areas, lot.slots), ("post", post)]
    again = _right_turn_search(lot, Collider(around, base.allowed, edge=lot.edge))
    assert again, "no turn round the post"
    for t in again:
        assert not shapely.intersects(_swept(lot, t), post).any()
        assert not shapely.intersects(_swept(lot, t), lot.slot_by_id["E1"].shape).any()


def test_a_junction_walled_off_has_no_turn_through_its_area(tee):
    lot, _ = tee
    base = lane_collider(lot)
    wall = box(27.0, 13.0, 50.0, 18.0)  # across the aisle's east arm, by the junction
    around = [*obstacle_polygons(lot.areas, lot.slots), ("wall", wall)]
    assert _right_turn_search(lot, Collider(around, base.allowed, edge=lot.edge)) == []
