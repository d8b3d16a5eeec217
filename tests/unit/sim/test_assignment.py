"""lotsim.sim.assignment: which slots a car probes, with what budget, and how long an
aisle where a probe ran out is passed over."""

from types import SimpleNamespace

import pytest

from conftest import ROOT
from lotsim.io.scenario_yaml import load_scenario
from lotsim.sim.assignment import SlotAssigner
from lotsim.sim.settings import RunTuning

AISLE = {"A1": "a", "A2": "a", "A3": "a", "B1": "b", "B2": "b", "C1": "c"}
RANKED = ["A1", "A2", "B1", "A3", "B2", "C1"]


def _by_aisles(**tuning) -> SlotAssigner:
    """An assigner over a lot that is only its slots' aisles (no vehicle types)."""
    slots = {k: SimpleNamespace(aisle=v) for k, v in AISLE.items()}
    lot_graph = SimpleNamespace(lot=SimpleNamespace(slot_by_id=slots))
    return SlotAssigner(lot_graph, [], tuning=RunTuning(**tuning))


def test_a_car_that_misses_its_best_slot_tries_the_best_of_other_aisles_next():
    assert _by_aisles().few(RANKED) == ["A1", "B1", "C1"]
    assert _by_aisles(probes=4).few(RANKED) == ["A1", "B1", "C1", "A2"]  # the next best
    assert _by_aisles(probes=1).few(RANKED) == ["A1"]
    assert _by_aisles().few(["A2", "A1"]) == ["A2", "A1"]  # one aisle: in rank order


def test_an_aisle_where_a_look_ran_out_comes_last_for_congested_for_seconds():
    assigner = _by_aisles(congested_for=5.0)
    assert assigner.probes(RANKED, 0.0) == ["A1", "B1", "C1"]
    assigner.ran_out("A2", 10.0)  # aisle a is congested from 10 s to 15 s
    assert assigner.uncongested_first(RANKED, 14.9) == ["B1", "B2", "C1", "A1", "A2", "A3"]
    assert assigner.probes(RANKED, 14.9) == ["B1", "C1", "A1"]
    assert assigner.probes(RANKED, 15.0) == ["A1", "B1", "C1"]
    # with no span, a probe that ran out changes nothing
    never = _by_aisles(congested_for=0.0)
    never.ran_out("A2", 10.0)
    assert never.uncongested_first(RANKED, 10.0) == RANKED


def test_a_probe_gets_its_rate_a_second_of_the_slots_way_and_at_least_its_floor():
    assigner = _by_aisles()
    assert assigner.probe_budget(10.0) == 400  # 80 expansions: the floor
    assert assigner.probe_budget(100.0) == 800
    assert assigner.probe_budget(float("inf")) == 400  # no way: the floor
    tuned = _by_aisles(probe_floor=50, probe_rate=2.0)
    assert (tuned.probe_budget(10.0), tuned.probe_budget(100.0)) == (50, 200)


@pytest.mark.slow  # the large lot is prepared for it
def test_probe_budgets_on_the_large_lot_reach_both_sides_of_the_floor(shipped_graphs):
    # the default rate and floor matter on a real lot: the nearest slot's look gets the
    # floor, the farthest more
    lg = shipped_graphs["large_lot"]
    sc = load_scenario(ROOT / "scenarios" / "large_lot.yaml")
    assigner = SlotAssigner(lg, sc.vehicle_types)
    car, gate = sc.vehicle_types[0].name, next(iter(lg.entrances))
    times = assigner.slot_times(gate, car, False)
    assert set(times) == {s.id for s in lg.lot.slots} - set(lg.infeasible[car])
    near, far = min(times, key=times.get), max(times, key=times.get)
    assert assigner.probe_budget(times[near]) == 400 < 8 * times[far]
    assert assigner.probe_budget(times[far]) == pytest.approx(8 * times[far], abs=0.5)
