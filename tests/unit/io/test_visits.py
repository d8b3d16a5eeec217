"""The one reader of a car's visit in a result document (:func:`lotsim.io.visits.visits`,
read by the replay and every export): on runs, it tells the moment each car came to rest
in its bay and moved off again as the run itself recorded them; on documents made by hand,
the longest stand in the bay, at one pose, with the body's centre inside it."""

from __future__ import annotations

import pytest

import lotsim
from lotsim.io.result import result_dict
from lotsim.io.visits import visits
from lotsim.render.replay import Replay

TOL = 1.5e-6  # the file's clock is written to 1 µs


@pytest.fixture(scope="module")
def runs():
    return [lotsim.run("scenarios/mixed_lot.yaml"),
            lotsim.run("scenarios/mixed_lot.yaml",
                       disturbances=lotsim.Disturbances(stall_rate=60.0,
                                                        stall_duration=(30.0, 60.0), seed=1)),
            lotsim.run("scenarios/lots/storefront.yaml")]


@pytest.mark.slow
def test_each_car_parks_and_moves_off_when_the_run_says(runs):
    seen = 0
    for rr in runs:
        vs = visits(result_dict(rr))
        for v in rr.vehicles:
            visit = vs[v.id]
            if v.parked_at is None:
                assert visit.park is None, v.id
                continue
            seen += 1
            assert visit.park == pytest.approx(v.parked_at, abs=TOL), v.id
            if v.status == "departed":  # it began to leave: its first move after parking
                k = max(i for i, m in enumerate(v.moves) if m.kind == "parked")
                off = next(m for m in v.moves[k:] if m.motion is not None)
                assert visit.leave == pytest.approx(off.t0, abs=TOL), v.id
                assert visit.end == pytest.approx(v.moves[-1].t1, abs=TOL)
            else:
                assert visit.leave is None, v.id
    assert seen > 60


def test_the_replay_reads_the_same_visits(runs):
    doc = result_dict(runs[1])
    vs = visits(doc)
    for tr in Replay(doc).tracks:
        visit = vs[tr.id]
        assert (tr.parked_from if visit.park is not None else None) == visit.park
        assert (tr.parked_until if visit.leave is not None else None) == visit.leave


CAR = {"name": "car", "width": 1.8, "front": 3.9, "rear": 1.0, "wheelbase": 2.8}
BAY = {"id": "B", "polygon": [[10, -1.25], [15, -1.25], [15, 1.25], [10, 1.25]]}


def _doc(t, x, v, status="departed", theta=None, patience=None, steer=None):
    n = len(t)
    gear = [0 if s == 0 else 1 for s in v]
    return {"lot": {"slots": [BAY], "exits": [{"id": "out", "pose": [0.0, 0.0, 0.0]}]},
            "settings": {"patience": patience},
            "vehicles": [{"id": "a", "slot": "B", "status": status, "arrival": 0.0,
                          "entrance": "in", "type": CAR,
                          "samples": {"t": t, "x": x, "y": [0.0] * n,
                                      "theta": theta or [0.0] * n, "v": v,
                                      "steer": steer or [0.0] * n, "gear": gear}}]}


def test_the_longest_stand_with_the_body_centre_in_the_bay_is_the_dwell():
    # rear axle at 9.0: the body's centre (1.45 m ahead) at 10.45 m, inside the bay, though
    # the rear axle is not; a first short stand there, a longer one after a shuffle
    doc = _doc(t=[0.0, 5.0, 6.0, 7.0, 8.0, 30.0, 35.0],
               x=[0.0, 9.0, 9.0, 9.5, 9.2, 9.2, 0.0],
               v=[1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0])
    visit = visits(doc)["a"]
    assert (visit.start, visit.park, visit.leave, visit.end) == (0.0, 8.0, 30.0, 35.0)
    assert visit.exit == "out"


def test_a_stand_outside_the_bay_or_moving_is_no_dwell():
    # the body's centre at 8.45 m: short of the bay; then rolling through it
    doc = _doc(t=[0.0, 5.0, 20.0, 21.0, 22.0], x=[0.0, 7.0, 7.0, 12.0, 20.0],
               v=[1.0, 0.0, 0.0, 1.0, 1.0])
    assert visits(doc)["a"].park is None


def test_a_pose_that_drifts_by_more_than_the_rounding_ends_the_stand():
    doc = _doc(t=[0.0, 5.0, 10.0, 12.0, 20.0], x=[0.0, 11.0, 11.0, 11.001, 11.001],
               v=[1.0, 0.0, 0.0, 0.0, 0.0], status="parked")
    visit = visits(doc)["a"]
    assert (visit.park, visit.leave) == (12.0, None)  # the stand to the end: it stays


def test_a_turned_away_car_gives_up_after_the_patience():
    doc = _doc(t=[], x=[], v=[], status="rejected", patience=90.0)
    doc["vehicles"][0]["arrival"] = 12.0
    visit = visits(doc)["a"]
    assert (visit.start, visit.park, visit.rejected) == (None, None, 102.0)


def test_a_car_that_straightens_its_wheels_standing_parks_when_they_are_straight():
    # stops in the bay at 5 s with its wheels turned, straightens them by 6 s; turns them
    # again standing from 20 s before it rolls out at 21 s
    doc = _doc(t=[0.0, 5.0, 5.5, 6.0, 20.0, 20.5, 21.0, 25.0],
               x=[0.0, 11.0, 11.0, 11.0, 11.0, 11.0, 11.0, 0.0],
               v=[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0],
               steer=[0.4, 0.4, 0.2, 0.0, 0.0, -0.2, -0.4, -0.4])
    visit = visits(doc)["a"]
    assert (visit.park, visit.leave) == (6.0, 20.0)
