"""lotsim.sim.repairs: aisles, lanes and gates closed for a while, bays taken by cars the plan does
not know, and the cars planned again for them.

The lot is the example's, checked by eye: one one-way aisle ``main`` along y = 10 m, four
perpendicular slots on each side (N1–N4, S1–S4), N2 and S3 taken at the start, the entrance
``in`` at x = 3 m, the exit ``out`` at x = 24 m; ada comes at 0 s, bob at 3 s (and leaves
20 s after parking), cy at 6 s. Each expectation follows from that, and the independent
checker judges every run.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import shapely

import lotsim
from lotsim.errors import ScenarioError, SettingsError
from lotsim.io.result import result_dict
from lotsim.traffic.disturbances import Closure, Disturbances, TakenBay

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def prepared():
    return lotsim.prepare(lotsim.EXAMPLE)


def _first_sample(doc, car):
    v = next(v for v in doc["vehicles"] if v["id"] == car)
    return v["samples"]["t"][0]


def test_a_bay_taken_before_its_car_parks_sends_the_car_to_another(prepared):
    plan = lotsim.run(prepared)
    ada = plan.vehicles[0]
    park = next(m for m in ada.moves if m.kind == "park")
    rr = lotsim.run(prepared, disturbances=Disturbances(taken=(TakenBay(ada.slot,
                                                                        park.t0 - 1.0),)))
    assert lotsim.check(rr).ok
    again = rr.vehicles[0]
    assert again.status == "parked" and again.slot not in (ada.slot, "N2", "S3")
    doc = result_dict(rr)["disturbances"]
    assert doc["taken"][0]["moved"] == "ada" and doc["taken"][0]["polygon"]
    assert [(r["car"], r["why"]) for r in doc["replans"]] == \
        [("ada", f"its bay {ada.slot!r} was taken")]
    assert all(v.slot != ada.slot for v in rr.vehicles)


def test_a_bay_is_not_taken_from_a_car_parking_in_it(prepared):
    plan = lotsim.run(prepared)
    ada = plan.vehicles[0]
    park = next(m for m in ada.moves if m.kind == "park")
    rr = lotsim.run(prepared, disturbances=Disturbances(
        taken=(TakenBay(ada.slot, (park.t0 + park.t1) / 2),)))
    (taken,) = result_dict(rr)["disturbances"]["taken"]
    assert taken["refused"] == "'ada' was in it or parking in it" and taken["polygon"] is None
    assert rr.vehicles[0].slot == ada.slot and lotsim.check(rr).ok


def test_the_checker_sees_a_car_that_meets_the_car_in_a_taken_bay(prepared):
    # the plan parks ada in N1; the record of N1 taken at 0.5 s, put beside the plan, must
    # fail (beside the run that gave ada another bay, it passes)
    plan = lotsim.run(prepared)
    assert plan.vehicles[0].slot == "N1"
    taken = lotsim.run(prepared, disturbances=Disturbances(taken=(TakenBay("N1", 0.5),)))
    record = result_dict(taken)["disturbances"]["taken"][0]
    assert record["moved"] == "ada" and lotsim.check(taken).ok
    doc = result_dict(plan)
    doc["disturbances"] = {"taken": [record]}
    violations = lotsim.check(doc).violations
    assert violations and {v.rule for v in violations} == {"taken"}
    assert {v.vehicle for v in violations} == {"ada"}


def test_an_aisle_closed_holds_the_cars_that_would_use_it_until_it_opens(prepared):
    rr = lotsim.run(prepared, disturbances=Disturbances(closures=(Closure("aisle", "main",
                                                                          5.0, 60.0),)))
    assert lotsim.check(rr).ok
    doc = result_dict(rr)
    (closure,) = doc["disturbances"]["closures"]
    assert closure["inside"] == ["ada"]  # in the aisle when it closed: she parks
    assert [v.status for v in rr.vehicles] == ["parked", "departed", "parked"]
    # bob (planned, not yet in) and cy enter only once it opens
    assert _first_sample(doc, "bob") >= 60.0 and _first_sample(doc, "cy") >= 60.0
    assert ("bob", "aisle 'main' closed") in [(r["car"], r["why"])
                                              for r in doc["disturbances"]["replans"]]
    # the same record with ada taken out of `inside` is a violation: she was on it
    closure["inside"] = []
    assert {v.rule for v in lotsim.check(doc).violations} == {"closure"}


def test_a_gate_closed_keeps_cars_out_and_an_exit_closed_keeps_them_in(prepared):
    rr = lotsim.run(prepared, disturbances=Disturbances(closures=(
        Closure("gate", "in", 0.0, 30.0), Closure("gate", "out", 20.0, 90.0))))
    assert lotsim.check(rr).ok
    doc = result_dict(rr)
    assert min(_first_sample(doc, c) for c in ("ada", "bob", "cy")) >= 30.0
    bob = rr.vehicles[1]
    assert bob.status == "departed" and bob.left_at >= 90.0


def test_the_live_run_closes_and_takes_from_outside_and_refuses_what_the_lot_lacks(prepared):
    live = lotsim.Live(prepared)
    live.advance(4.0)
    live.close("aisle", "main", 40.0)
    live.take_bay("S4", at=10.0)
    rr = live.finish()
    assert lotsim.check(rr).ok and all(v.slot != "S4" for v in rr.vehicles)
    live = lotsim.Live(prepared)
    with pytest.raises(SettingsError, match=r"expected one of the lot's aisles \(main\), "
                                            r"found 'side'"):
        live.close("aisle", "side", 9.0)
    with pytest.raises(SettingsError, match="no slot 'Z1'"):
        live.take_bay("Z1")
    with pytest.raises(SettingsError, match="closures.end: expected a time after start"):
        live.close("gate", "in", 0.0, at=5.0)


def test_the_scenario_names_what_it_closes_and_takes_where_it_says_so():
    text = lotsim.EXAMPLE + ("disturbances:\n  closures: [{aisle: main, from: 5, to: 60}]\n"
                             "  taken: [{slot: S1, time: 2}]\n")
    d = lotsim.load_scenario(text).disturbances
    assert d.closures == (Closure("aisle", "main", 5.0, 60.0),)
    assert d.taken == (TakenBay("S1", 2.0),)
    bad = text.replace("slot: S1", "slot: Q9")
    lines = bad.splitlines()
    line = next(k for k, x in enumerate(lines) if "Q9" in x)
    col = lines[line].index("Q9") + 1
    with pytest.raises(ScenarioError, match=rf"<scenario>:{line + 1}:{col}: disturbances"
                                            r".taken\[0\].slot: expected a slot id, found "
                                            r"'Q9'"):
        lotsim.run(bad)
    with pytest.raises(ScenarioError, match="expected one of aisle or lane or gate"):
        lotsim.load_scenario(lotsim.EXAMPLE + "disturbances: {closures: [{from: 1, to: 2}]}\n")
    with pytest.raises(ScenarioError, match=r"to: expected a time after 'from' \(5 s\)"):
        lotsim.load_scenario(lotsim.EXAMPLE + "disturbances: {closures: [{gate: in, from: 5, "
                                              "to: 1}]}\n")


def test_a_car_whose_ways_out_are_all_closed_waits_in_its_slot_without_searching(prepared):
    plan = lotsim.run(prepared)
    bob = plan.vehicles[1]
    rr = lotsim.run(prepared, disturbances=Disturbances(closures=(
        Closure("gate", "out", bob.depart_at - 1.0, bob.depart_at + 60.0),)))
    late = rr.vehicles[1]
    assert lotsim.check(rr).ok and late.status == "departed"
    leave = next(m for m in late.moves if m.kind == "leave")
    assert leave.t0 >= bob.depart_at + 60.0 - 1e-9
    # it asked for no way out while none was open: as many searches as when none closed
    assert late.searches == bob.searches


def test_a_lane_closed_closes_its_side_of_a_two_way_aisle_only():
    """scenarios/example.yaml: the two-way aisle ``main`` along y = 10 m, 7 m wide, its
    lanes ``main>`` (eastbound, south half) and ``main<`` (westbound, north half, the exit's
    lane); the ten N slots open onto the north half."""
    prepared = lotsim.prepare(ROOT / "scenarios" / "example.yaml")
    aisle = prepared.lot_graph.lot.aisles["main"].polygon
    north = shapely.intersection(aisle, shapely.box(-1, 10.0, 41, 21))
    spec = Disturbances(closures=(Closure("lane", "main<", 0.0, 120.0),))
    rr = lotsim.run(prepared, disturbances=spec)
    doc = result_dict(rr)
    (closure,) = doc["disturbances"]["closures"]
    ground = shapely.Polygon(closure["polygon"])
    assert ground.symmetric_difference(north).area < 1e-6  # that half, not the aisle
    report = lotsim.check(doc)
    assert report.ok, report.summary()
    # no N slot is entered while its side is closed (every maneuver into one sweeps it)
    assert all(v.parked_at is None or v.slot[0] != "N" or v.parked_at > 120.0
               for v in rr.vehicles)
    # the plan made without the closure puts a car on that half during it: the checker,
    # given the same closure beside it, finds it
    plain = result_dict(lotsim.run(prepared))
    plain["disturbances"] = {"closures": [{**closure, "inside": []}]}
    assert "closure" in {v.rule for v in lotsim.check(plain).violations}
    live = lotsim.Live(prepared)
    with pytest.raises(SettingsError, match=r"expected one of the lot's lanes \(main<, "
                                            r"main>\), found 'main'"):
        live.close("lane", "main", 9.0)
