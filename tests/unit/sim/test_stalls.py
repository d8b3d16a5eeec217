"""lotsim.sim.stalls: a car that stalls in a stepped run (Live.stall) stands at its next
place of rest on the lanes for the stall, and the cars whose plans pass there are planned
round it.

The lot is the quickstart's (scenarios/quickstart.yaml), checked by eye: one one-way aisle
along y = 10 m, ten slots each side from x = 8 m, the entrance at x = 3 m; cy comes at 8 s
and, planned on its own, comes to rest on the lane at about 15 s before parking. Whether a
car stood still, and whether another met it, is read from the result's samples with numpy
and shapely, and judged by lotsim check.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

import lotsim
from lotsim.errors import SettingsError
from lotsim.io.result import result_dict
from lotsim.sim.live import Live
from oracles.sampled import footprints

QUICKSTART = Path(__file__).resolve().parents[3] / "scenarios" / "quickstart.yaml"


@pytest.fixture(scope="module")
def prepared():
    return lotsim.prepare(QUICKSTART)


def _car(doc: dict, car: str) -> dict:
    return next(v for v in doc["vehicles"] if v["id"] == car)


def _stalled(prepared, car: str = "cy", at: float = 12.0, duration: float = 30.0):
    live = Live(prepared)
    live.advance(at)
    live.stall(car, duration)
    return live.finish()


def test_a_stalled_car_stands_at_its_next_rest_for_the_stall_and_the_others_go_round(
        prepared):
    doc = result_dict(_stalled(prepared))
    report = lotsim.check(doc)
    assert report.ok, report.summary()
    (st,) = doc["disturbances"]["stalls"]
    assert st["car"] == "cy" and st["at"] == 12.0
    assert st["t0"] >= 12.0 and st["t1"] - st["t0"] == pytest.approx(30.0)
    cy = _car(doc, "cy")
    t = np.asarray(cy["samples"]["t"])
    during = (t >= st["t0"]) & (t <= st["t1"])
    assert during.sum() >= 2  # samples at both ends of the stand
    for k in ("x", "y", "theta", "v"):
        col = np.asarray(cy["samples"][k])[during]
        assert np.ptp(col) < 1e-9 and (k != "v" or np.all(col == 0))
    assert cy["status"] == "parked" and t[-1] > st["t1"]  # it went on and parked
    # every car planned over where it stood was planned again, and none meets that ground
    # while it stands
    ground = footprints(cy)[np.flatnonzero(during)[0]]
    for other in doc["vehicles"]:
        if other["id"] == "cy" or not other["samples"]["t"]:
            continue
        to = np.asarray(other["samples"]["t"])
        near = (to >= st["t0"]) & (to <= st["t1"])
        assert not shapely.intersects(footprints(other)[near], ground).any(), other["id"]
    assert {r["car"] for r in doc["disturbances"]["replans"]
            if r["why"] == "'cy' stalled in its way"} == {"dee"}


def test_the_checker_finds_a_stall_the_car_did_not_stand_through(prepared):
    stalled = result_dict(_stalled(prepared))
    (st,) = stalled["disturbances"]["stalls"]
    plain = result_dict(lotsim.run(prepared))  # cy never stood 30 s there
    plain["disturbances"] = {"stalls": [st]}
    assert "stall" in {v.rule for v in lotsim.check(plain).violations}


def test_a_stall_that_cannot_be_had_is_recorded_with_the_reason(prepared):
    doc = result_dict(_stalled(prepared, "cy", at=6.0))  # cy comes at 8 s
    assert doc["disturbances"]["stalls"] == []
    assert doc["disturbances"]["stalls_refused"] == [
        {"car": "cy", "at": 6.0, "why": "it is not in the lot then"}]
    doc = result_dict(_stalled(prepared, "cy", at=20.0))  # backing into its slot then
    assert doc["disturbances"]["stalls_refused"][0]["why"] == (
        "its plan brings it to rest on the lanes no more before it parks")
    assert lotsim.check(doc).ok
    live = Live(prepared)
    live.advance(5.0)
    with pytest.raises(SettingsError, match="expected a car of the run, found 'zed'"):
        live.stall("zed", 10.0)
    with pytest.raises(SettingsError, match="duration: expected seconds"):
        live.stall("cy", 0.0)
    with pytest.raises(SettingsError, match=r"expected a time from now \(5 s\) on"):
        live.stall("cy", 10.0, at=2.0)


def test_a_stepped_run_driven_late_and_slow_keeps_each_stall_whole(prepared):
    stalled = _stalled(prepared)
    for seed in range(3):
        driven = lotsim.execute(stalled, lotsim.Disturbances(
            late_probability=0.5, late_max=8.0, speed=(0.7, 1.0), seed=seed),
            memo=prepared.search_graphs)
        doc = result_dict(driven)
        report = lotsim.check(doc)
        assert report.ok, report.summary()
        (st,) = doc["disturbances"]["stalls"]
        assert st["car"] == "cy" and st["t1"] - st["t0"] == pytest.approx(30.0)
