"""The roadmap's searches answer with an Outcome: found with the value, or a status and a
reason a user can read — on hand-built streets a person can check by eye."""

from __future__ import annotations

import math

from shapely.geometry import box

from lotsim.core.geometry import Segment
from lotsim.core.outcome import Outcome, Status
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle, Lane
from lotsim.roadmap.multipoint import plan_onto
from lotsim.roadmap.settings import RoadmapSettings, TurnaroundSettings
from lotsim.roadmap.turnarounds import _reaching_onto, plan_turnaround, plan_turnarounds

CAR = DesignVehicle(1.8, 3.7, 1.0, 4.97, 0.15, 2.0)  # 4.7 m long, radius 4.97 m


def _street(width: float) -> tuple[Collider, Lane, Lane]:
    """A dead-end street ``width`` m wide, closed at x = 40: its east-bound lane a quarter of
    the width up, the west-bound one three quarters up."""
    q = width / 4
    east = Lane("e", "a", (Segment((0.0, q, 0.0), 36.0, 0.0),), q, True)
    west = Lane("w", "a", (Segment((36.0, 3 * q, math.pi), 36.0, 0.0),), q, False)
    return Collider([], box(0, 0, 40, width)), east, west


def test_a_turnaround_in_a_wide_enough_street_is_found_and_lands_on_the_opposite_lane():
    collider, east, west = _street(9.0)
    got = plan_turnaround(east, west, collider, CAR, CAR.min_radius)
    assert isinstance(got, Outcome) and got.found and got.reason == ""
    t = got.value
    assert (t.lane_a, t.lane_b) == ("e", "w")
    assert t.changes >= 1  # 9 m is less than a full-lock U-turn's 2 × 4.97 m
    end = t.segments[-1].end
    assert math.isclose(end[1], 6.75, abs_tol=1e-6)  # on the west-bound lane's line


def test_a_street_narrower_than_the_car_has_no_turnaround_and_says_with_what_it_searched():
    # 4 m: the 4.7 m car cannot stand across it, let alone turn
    collider, east, west = _street(4.0)
    settings = RoadmapSettings(turnarounds=TurnaroundSettings(max_changes=4, margin=0.2))
    got = plan_turnaround(east, west, collider, CAR, CAR.min_radius, settings=settings)
    assert not got.found and got.value is None
    assert got.status is Status.NO_PATH
    assert "up to 4 direction changes" in got.reason and "0.2 m" in got.reason
    both = plan_turnarounds(east, west, collider, CAR, CAR.min_radius, settings=settings)
    assert (both.status, both.reason) == (got.status, got.reason)


def test_an_opposite_lane_that_bends_where_it_begins_cannot_be_turned_onto():
    collider, east, _ = _street(9.0)
    bent = Lane("w", "a", (Segment((36.0, 6.75, math.pi), 10.0, 0.05),), 2.25, False)
    got = plan_turnaround(east, bent, collider, CAR, CAR.min_radius)
    assert got.status is Status.INFEASIBLE and "bends" in got.reason


def test_a_multi_point_search_stopped_by_its_expansion_limit_says_so():
    """A car coming north up a 6 m spur into a 6 m street whose east arm is too short for
    one right turn: it takes a few strokes, more than two states' worth of search; with
    room to search it is found."""
    lot = box(4, -12, 10, 0).union(box(0, 0, 16, 6))
    args = ([(8.5, -8.0, math.pi / 2)], (0.0, 1.5, 0.0), 9.0, 11.5, Collider([], lot), CAR,
            5.0)
    assert plan_onto(*args).found
    got = plan_onto(*args, budget=2)
    assert got.status is Status.OUT_OF_BUDGET and "2 states" in got.reason


def test_a_landing_stretch_that_ends_before_it_begins_is_infeasible():
    got = plan_onto([(1.0, 1.0, 0.0)], (0.0, 0.0, 0.0), 5.0, 4.0, Collider([], box(0, 0, 9, 9)),
                    CAR, 5.0)
    assert got.status is Status.INFEASIBLE


def test_a_turnaround_reaching_the_opposite_lane_by_search_is_an_outcome_too():
    collider, east, west = _street(9.0)
    got = _reaching_onto(east, west, [36.0], 30.0, collider, CAR, CAR.min_radius)
    assert got.found and got.value.lane_b == "w" and got.value.station_b <= 30.0 + 1e-6
    none = _reaching_onto(*_street(4.0)[1:], [36.0], 30.0, _street(4.0)[0], CAR,
                          CAR.min_radius)
    assert not none.found and none.reason
