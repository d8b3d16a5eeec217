"""The reservation table never lets two bodies touch at any instant (checked densely)."""

import numpy as np
import pytest
import shapely
from shapely.geometry import box

from lotsim.geometry import Segment
from lotsim.planners.reservation import ReservationTable, bodies_at_rest, swept_by_step
from lotsim.trajectory import Piece, drive, standing
from lotsim.vehicles import CATALOGUE

CAR = CATALOGUE["valet"]


def _random_trajectory(rng, t0):
    x, y = rng.uniform(-10, 10, size=2)
    th = rng.uniform(-np.pi, np.pi)
    pieces, pose = [], (float(x), float(y), float(th))
    for _ in range(rng.integers(1, 4)):
        seg = Segment(pose, float(rng.uniform(2, 12)) * rng.choice([1, 1, -1]),
                      float(rng.uniform(-1, 1) * CAR.max_curvature))
        pieces.append(Piece(seg))
        pose = seg.end
    return drive(pieces, CAR, t0=t0)


def _dense_overlap(a, b):
    """Whether the two vehicles' footprints overlap at some common instant (every 10 ms)."""
    lo, hi = max(a.start_time, b.start_time), min(a.end_time, b.end_time)
    if hi <= lo:
        return False
    t = np.arange(lo, hi, 0.01)

    def at(tr):
        th = np.interp(t, tr.t, np.unwrap(tr.theta))
        return CAR.footprints(np.column_stack([np.interp(t, tr.t, tr.x),
                                               np.interp(t, tr.t, tr.y), th]))

    return bool(shapely.intersects(shapely.polygons(at(a)), shapely.polygons(at(b))).any())


def test_random_crossings_that_touch_at_an_instant_are_always_caught():
    rng = np.random.default_rng(11)
    caught = touching = 0
    for _ in range(150):
        a = _random_trajectory(rng, float(rng.uniform(0, 3)))
        b = _random_trajectory(rng, float(rng.uniform(0, 3)))
        table = ReservationTable(dt=0.5)
        table.reserve_trajectory("a", a, CAR)
        conflict = table.first_conflict(swept_by_step(b, CAR, 0.5))
        if _dense_overlap(a, b):
            touching += 1
            assert conflict is not None and conflict.owner == "a"
        caught += conflict is not None
    assert touching >= 10  # the sample exercises real clashes
    assert caught >= touching


def test_a_parked_car_blocks_only_from_when_it_parks_and_not_its_owner():
    table = ReservationTable(dt=0.5)
    table.reserve_parked("p", box(0, 0, 2, 5), since=10.0)
    probe = box(1, 1, 3, 3)
    assert table.is_free({19: probe})
    assert table.first_conflict({20: probe}).owner == "p"
    assert table.is_free({25: probe}, ignore="p")


def test_release_after_a_time_keeps_the_past_and_the_parked_car_until_then():
    table = ReservationTable(dt=1.0)
    tr = drive([Piece(Segment((0.0, 0.0, 0.0), 10.0, 0.0))], CAR)
    table.reserve_trajectory("v", tr, CAR, park=True)
    end = bodies_at_rest(CAR, tr.poses[-1], [int(tr.end_time) + 5])
    assert not table.is_free(end)
    table.release("v", after=tr.end_time + 3)
    assert table.is_free(end)
    assert not table.is_free(bodies_at_rest(CAR, tr.poses[-1], [int(tr.end_time) + 1]))
    assert not table.is_free(bodies_at_rest(CAR, tr.poses[0], [0]))
    table.release("v")
    assert table.owners() == set()


def test_a_standing_vehicle_reserves_every_step_it_stands():
    table = ReservationTable(dt=0.5)
    table.reserve_trajectory("w", standing((0.0, 0.0, 0.0), 2.0, 3.0), CAR)
    body = shapely.Polygon(CAR.footprints([[0.0, 0.0, 0.0]])[0])
    for k in range(4, 10):
        assert table.first_conflict({k: body}).step == k
    assert table.is_free({3: body}) and table.is_free({11: body})


def test_bad_step_length_is_refused():
    with pytest.raises(ValueError):
        ReservationTable(dt=0)
