"""What a lot's traffic costs its cars (``RunResult.trip_figures``, ``standing``): the
standing split by where it happens, on trips laid out by hand, and the figures of a run
against the numbers worked out again from its cars."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import ROOT
from lotsim.sim.results import VehicleRun, standing_times
from lotsim.traffic.demand import Arrival
from lotsim.traffic.plans import Move
from lotsim.vehicles.catalogue import CATALOGUE


def move(kind: str, t0: float, t1: float) -> Move:
    return Move(kind, t0, t1, 0, 0, 0, 0)


def car(arrival: float, dwell: float | None, moves: list[Move], parked_at: float | None,
        left_at: float | None = None) -> VehicleRun:
    v = VehicleRun(Arrival("x", "valet", "in", arrival, dwell), CATALOGUE["valet"])
    v.moves, v.parked_at, v.left_at = moves, parked_at, left_at
    return v


def test_standing_is_split_into_outside_the_way_in_and_the_way_out():
    # arrives at 10, queued outside until 13, drives, waits 2 s on the way in, parks at
    # 30; dwell 100 so it wants out at 130; its way out starts at 134 and waits 5 s
    moves = [move("drive", 13, 20), move("wait", 20, 22), move("drive", 22, 25),
             move("park", 25, 30), move("parked", 30, 134), move("leave", 134, 140),
             move("wait", 140, 145), move("drive", 145, 150)]
    assert standing_times(car(10, 100, moves, parked_at=30, left_at=150)) == (3, 2, 4 + 5)


def test_a_wait_in_the_slot_before_leaving_is_counted_once():
    # wants out at 130; its way out waits in the slot until 140, leaves, waits 3 s later
    moves = [move("drive", 10, 25), move("park", 25, 30), move("parked", 30, 130),
             move("wait", 130, 140), move("leave", 140, 146), move("wait", 146, 149),
             move("drive", 149, 155)]
    assert standing_times(car(10, 100, moves, parked_at=30, left_at=155)) == (0, 0, 10 + 3)


def test_a_car_that_never_got_out_stood_from_the_end_of_its_dwell_to_the_end():
    moves = [move("drive", 0, 10), move("park", 10, 15), move("parked", 15, 400)]
    assert standing_times(car(0, 60, moves, parked_at=15)) == (0, 0, 400 - 75)


def test_a_car_rejected_after_waiting_stood_outside_for_it():
    v = car(5, None, [], parked_at=None)
    v.waited_outside = 600.0
    assert standing_times(v) == (600, 0, 0)


@pytest.fixture(scope="module")
def culdesac_run():
    import lotsim

    return lotsim.run(ROOT / "scenarios" / "lots" / "culdesac.yaml")


def test_the_figures_of_a_run_are_its_cars(culdesac_run):
    rr = culdesac_run
    f = rr.trip_figures()
    park = [v.parked_at - v.arrival.time for v in rr.vehicles if v.parked_at is not None]
    leave = [v.left_at - v.parked_at - v.arrival.dwell for v in rr.vehicles
             if v.left_at is not None]
    assert park and leave
    assert f["median_time_to_park"] == pytest.approx(np.median(park))
    assert f["p90_time_to_park"] == pytest.approx(np.percentile(park, 90))
    assert f["median_time_to_leave"] == pytest.approx(np.median(leave))
    parts = f["standing_outside_per_car"] + f["standing_in_per_car"] + \
        f["standing_out_per_car"]
    assert f["standing_per_car"] == pytest.approx(parts)
    # the standing the run's metrics count (waits and queueing), plus the way out's start
    waited = rr.metrics()["total_waiting"] / len(rr.vehicles)
    assert f["standing_per_car"] >= waited - 1e-9
    for v in rr.vehicles:  # nobody stands longer than its trips take
        outside, way_in, way_out = standing_times(v)
        assert outside + way_in <= v.parked_at - v.arrival.time + 1e-9
        if v.left_at is not None:
            assert way_out <= v.left_at - v.parked_at - v.arrival.dwell + 1e-9


def test_each_car_counts_in_the_hour_it_came_and_an_empty_hour_reads_zero():
    from lotsim.sim.results import RunResult

    # three cars in hour 1 (3600–7200 s), none in hour 2, one in hour 3; one of hour 1's
    # turned away (it never parks)
    cars = [car(3700, None, [move("drive", 3700, 3720), move("park", 3720, 3730)], 3730),
            car(4000, None, [move("outside", 4000, 4010), move("drive", 4010, 4050),
                             move("park", 4050, 4060)], 4060),
            car(7100, None, [], None),
            car(11000, None, [move("drive", 11000, 11005), move("park", 11005, 11010)],
                11010)]
    cars[2].status = "rejected"
    rr = RunResult.__new__(RunResult)
    rr.vehicles = cars
    hours = rr.hourly()
    assert [h["hour"] for h in hours] == [1, 2, 3]
    one, two, three = hours
    assert (one["arrivals"], one["parked"], one["rejected"]) == (3, 2, 1)
    assert one["median_time_to_park"] == pytest.approx(np.median([30, 60]))
    assert one["standing_per_car"] == pytest.approx(10 / 3)  # the one queued outside
    assert two == {"hour": 2, "arrivals": 0, "parked": 0, "rejected": 0,
                   "median_time_to_park": 0.0, "p90_time_to_park": 0.0,
                   "standing_per_car": 0.0}
    assert three["p90_time_to_park"] == pytest.approx(10.0)
