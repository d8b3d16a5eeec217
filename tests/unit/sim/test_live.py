"""lotsim.sim.live and lotsim.sim.policies: a run stepped from outside, and slot choices
taken by a policy of the caller's.

The lot is checked by eye: one one-way aisle along y = 10 m, four perpendicular slots on
each side (N1–N4 left, S1–S4 right, x 8–18 m), N2 and S3 taken at the start, an entrance at
x = 3 m and an exit at x = 24 m. A stepped run is compared with the same run planned in one
go; a policy's choices with what each car got; a refused choice with the lot's state.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import shapely

import lotsim
from lotsim.errors import DecisionError, SettingsError
from lotsim.io.result import result_dict
from lotsim.sim.live import Live
from lotsim.sim.policies import ASK, Ranked

ROOT = Path(__file__).resolve().parents[3]
TRAFFIC = """\
traffic:
  vehicles:
    - {id: ada, arrival: 0}
    - {id: bob, arrival: 3, dwell: 20}
    - {id: cy, arrival: 6}
    - {id: dee, arrival: 8, dwell: 5}
    - {id: eve, arrival: 9}
"""


@pytest.fixture(scope="module")
def prepared():
    text = lotsim.EXAMPLE.split("traffic:")[0] + TRAFFIC
    return lotsim.prepare(text)


def _doc(rr):
    doc = result_dict(rr)
    doc["settings"].pop("lotsim_version")
    return doc


def test_a_run_stepped_in_small_steps_is_the_run_planned_in_one_go(prepared):
    whole = lotsim.run(prepared)
    live = Live(prepared)
    t = 0.0
    while not live.done:
        t += 1.7
        live.advance(t)
        assert live.now == pytest.approx(t)
    assert _doc(live.finish()) == _doc(whole)


def test_the_built_in_rankings_are_policies_of_the_same_kind(prepared):
    for by in ("shortest", "nearest", "priced"):
        own = Live(prepared, lotsim.RunSettings(assignment=by)).finish()
        given = Live(prepared, lotsim.RunSettings(assignment=by), policy=Ranked(by)).finish()
        assert [(v.slot, v.moves) for v in given.vehicles] == \
            [(v.slot, v.moves) for v in own.vehicles]
    # another ranking than the run's own: what that assignment gives
    nearest = lotsim.run(prepared, assignment="nearest")
    ranked = Live(prepared, policy=Ranked("nearest")).finish()
    assert [v.slot for v in ranked.vehicles] == [v.slot for v in nearest.vehicles]


def test_each_car_parks_in_the_slot_its_policy_chose_and_the_run_checks(prepared):
    asked = []

    def farthest(request):
        asked.append(request)
        return max(request.slots, key=lambda s: (request.static_times[s], s))

    rr = Live(prepared, policy=farthest).finish()
    assert lotsim.check(rr).ok
    chose = {}
    for r in asked:
        chose.setdefault(r.car, max(r.slots, key=lambda s: (r.static_times[s], s)))
    assert {v.id: v.slot for v in rr.vehicles} == chose
    # every request lists free slots only, and never one a car holds at that time
    for r in asked:
        assert not {"N2", "S3"} & set(r.slots)
        assert r.slots == tuple(sorted(r.slots, key=lambda s: (r.static_times[s], s)))


def test_a_choice_the_lot_cannot_honour_is_refused_with_the_slot_and_why(prepared):
    with pytest.raises(DecisionError, match=r"car 'ada' cannot take slot 'N2': it is occupied"):
        Live(prepared, policy=lambda r: "N2").finish()
    with pytest.raises(DecisionError, match=r"cannot take slot 'Z9': there is no such slot"):
        Live(prepared, policy=lambda r: "Z9").finish()
    with pytest.raises(DecisionError, match=r"car 'bob' cannot take slot 'N1': it is taken "
                                            r"by 'ada'"):
        Live(prepared, policy=lambda r: "N1").finish()
    with pytest.raises(DecisionError, match="expected a slot id"):
        Live(prepared, policy=lambda r: 7).finish()


def test_a_car_whose_policy_waits_asks_again_after_the_retry_time(prepared):
    seen = []

    def patient(request):
        seen.append((request.car, request.time))
        if request.car == "ada" and request.time < 10:
            return None
        return request.slots[0]

    rr = Live(prepared, policy=patient).finish()
    ada = rr.vehicles[0]
    times = [t for car, t in seen if car == "ada"]
    retry = rr.settings.retry
    assert times[:3] == pytest.approx([0.0, retry, 2 * retry])
    assert ada.status == "parked"
    first = next(m for m in ada.moves if m.kind != "outside")
    assert first.t0 >= 10 - 1e-9


def test_asking_the_caller_gives_the_run_a_policy_of_the_same_choices_gives(prepared):
    def last(request):
        return request.slots[-1]

    by_policy = Live(prepared, policy=last).finish()
    live = Live(prepared, policy=ASK)
    cars = []
    while (request := live.next_decision()) is not None:
        assert live.pending == request and live.now == pytest.approx(request.time)
        cars.append(request.car)
        live.decide(request.slots[-1])
    assert cars == [v.id for v in by_policy.vehicles]
    assert _doc(live.finish()) == _doc(by_policy)
    with pytest.raises(DecisionError, match="no car waits"):
        Live(prepared, policy=ASK).decide("N1")


def test_a_refused_answer_leaves_the_choice_pending(prepared):
    live = Live(prepared, policy=ASK)
    request = live.next_decision()
    with pytest.raises(DecisionError, match="occupied"):
        live.decide("S3")
    assert live.pending == request
    live.decide(request.slots[0])
    assert live.pending is None


def test_the_state_says_where_each_car_is_and_what_each_aisle_and_gate_holds(prepared):
    live = Live(prepared, traffic=False)
    # six free slots and six cars that stay, then a seventh that finds the lot full
    for k in range(7):
        live.add(f"c{k}", "valet", "in", at=60.0 * k)
    live.advance(60.0 * 6 + 1.0)
    state = live.state()
    by = {c["id"]: c for c in state["cars"]}
    assert [by[f"c{k}"]["phase"] for k in range(6)] == ["parked"] * 6
    assert by["c6"]["phase"] == "queued" and by["c6"]["pose"] is None
    assert state["queues"] == {"in": ["c6"]}
    taken = {s: c for s, c in state["occupancy"].items() if c is not None}
    assert taken == {"N2": "occupied", "S3": "occupied",
                     **{by[f"c{k}"]["slot"]: f"c{k}" for k in range(6)}}
    assert None not in state["occupancy"].values()
    # a parked car stands inside its slot; the aisle holds no one
    slots = prepared.lot.slot_by_id
    for k in range(6):
        x, y, _ = by[f"c{k}"]["pose"]
        assert shapely.Polygon(slots[by[f"c{k}"]["slot"]].polygon).contains(
            shapely.Point(x, y))
    assert state["aisles"] == {"main": []}
    # where and when each came, and when each came to stand in its slot
    assert [(by[f"c{k}"]["entrance"], by[f"c{k}"]["arrival"]) for k in range(7)] == \
        [("in", 60.0 * k) for k in range(7)]
    parked = [by[f"c{k}"]["parked_at"] for k in range(6)]
    assert all(60.0 * k < parked[k] < 60.0 * (k + 1) for k in range(6))
    assert by["c6"]["parked_at"] is None
    rr = live.finish()
    assert parked == [v.parked_at for v in rr.vehicles[:6]]


def test_a_car_has_no_parking_time_before_it_stands_in_its_slot(prepared):
    live = Live(prepared, traffic=False)
    live.add("van", "valet", "in", at=0.0)
    live.advance(1.0)
    assert live.state()["cars"][0]["parked_at"] is None
    parked_at = live.snapshot().vehicles[0].parked_at  # planned, not reached
    live.advance(parked_at)
    assert live.state()["cars"][0]["parked_at"] == parked_at


def test_a_car_on_its_way_is_on_the_aisle_at_the_pose_and_speed_its_plan_gives(prepared):
    live = Live(prepared, traffic=False)
    live.add("van", "valet", "in", at=0.0)
    live.advance(1.5)
    state = live.state()
    car = state["cars"][0]
    assert car["phase"] == "driving" and state["aisles"] == {"main": ["van"]}
    # on the aisle's centreline, heading east, moving: between the entrance and the slots
    x, y, theta = car["pose"]
    assert 3.0 < x < 18.0 and y == pytest.approx(10.0, abs=1e-6)
    assert math.cos(theta) > 0.99 and car["speed"] > 0
    rr = live.finish()
    samples = result_dict(rr)["vehicles"][0]["samples"]
    k = samples["t"].index(1.5)
    assert [samples["x"][k], samples["y"][k]] == pytest.approx([x, y], abs=1e-3)


def test_cars_added_from_outside_are_refused_with_what_was_expected(prepared):
    live = Live(prepared, traffic=False)
    with pytest.raises(SettingsError, match=r"vehicle: expected one of the scenario's "
                                            r"vehicle types \(valet\), found 'van'"):
        live.add("a", "van", "in")
    with pytest.raises(SettingsError, match=r"entrance: .*\(in\), found 'west'"):
        live.add("a", "valet", "west")
    live.add("a", "valet", "in", at=5.0)
    with pytest.raises(SettingsError, match="already in the run"):
        live.add("a", "valet", "in", at=6.0)
    live.advance(10.0)
    with pytest.raises(SettingsError, match=r"at: expected a time from now \(10 s\) on"):
        live.add("b", "valet", "in", at=2.0)
    live.finish()
    with pytest.raises(SettingsError, match="the run has ended"):
        live.add("c", "valet", "in")


def test_a_car_added_while_the_run_goes_takes_its_place_in_arrival_order(prepared):
    live = Live(prepared)
    live.advance(4.0)
    live.add("early", "valet", "in", at=5.0, dwell=2.0)
    rr = live.finish()
    assert [v.id for v in rr.vehicles] == ["ada", "bob", "early", "cy", "dee", "eve"]
    early = rr.vehicles[2]
    assert early.status == "departed" and lotsim.check(rr).ok


def test_a_snapshot_is_the_run_so_far_and_stays_as_it_was_taken(prepared):
    live = Live(prepared)
    live.advance(4.0)
    shot = live.snapshot()
    before = _doc(shot)
    assert [(v.id, v.status) for v in shot.vehicles] == \
        [("ada", "parked"), ("bob", "parked"), ("cy", "waiting"), ("dee", "waiting"),
         ("eve", "waiting")]
    assert not shot.vehicles[2].moves  # cy comes at 6 s
    rr = live.finish()
    assert _doc(shot) == before  # stepping on left it as it was
    # ada's plan was whole by then; bob's was still to leave
    assert shot.vehicles[0].moves == rr.vehicles[0].moves
    assert shot.vehicles[1].moves == rr.vehicles[1].moves[:len(shot.vehicles[1].moves)]
    assert len(rr.vehicles[1].moves) > len(shot.vehicles[1].moves)
    assert live.snapshot() is rr


def test_the_choice_asked_for_leaves_out_the_slots_a_closure_cuts_off():
    prepared = lotsim.prepare(ROOT / "scenarios" / "mixed_lot.yaml")
    live = Live(prepared, policy=ASK)
    live.close("aisle", "south", 3600.0)  # the parallel bays L1-L6 lie along it
    first = live.next_decision()  # asked at 0 s, before the closure came
    assert "L1" in first.slots
    live.decide(first.slots[0])
    request = live.next_decision()
    assert request.slots and not [s for s in request.slots if s.startswith("L")]
    with pytest.raises(DecisionError, match=r"cannot take slot 'L1': it is closed off now"):
        live.decide("L1")
    assert live.pending == request
    live.decide(request.slots[0])
    while (more := live.next_decision()) is not None:
        assert not [s for s in more.slots if s.startswith("L")] or more.time >= 3600.0
        live.decide(more.slots[0])
    rr = live.finish()
    got = {v.id: v.slot for v in rr.vehicles}
    assert got[request.car] == request.slots[0] and lotsim.check(rr).ok
