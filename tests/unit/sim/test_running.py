"""lotsim.sim.running: prepare a lot, run traffic through it, and what a run's result holds.

A lot small enough to check by eye: one one-way aisle along y = 11 m, three perpendicular
slots P1–P3 on its left (x 12–19.5 m), an entrance at its west end and an exit at its east
end. Each test states its expectation from the scenario (how many slots, who arrives when,
how patient they are), not from an earlier run's numbers.
"""

from __future__ import annotations

import dataclasses
import gc

import pytest
import shapely

from conftest import scenario_from_text
from lotsim.cli import main
from lotsim.core.outcome import Status
from lotsim.errors import ScenarioError, SettingsError
from lotsim.io.result import result_dict
from lotsim.sim import loop as loopmod
from lotsim.sim.loop import EventLoop
from lotsim.sim.preparation import PreparedLot, prepare_graph
from lotsim.sim.results import STATUSES, RunResult
from lotsim.sim.running import RUN_GC_THRESHOLDS, collector_tuned, simulate
from lotsim.sim.settings import RunSettings
from lotsim.traffic.demand import Arrival, StreamSpec, TrafficSpec, UniformDwell, arrivals
from lotsim.traffic.plans import Plan

TINY = """\
name: tiny
seed: 3
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 22], [0, 22]]
  aisles:
    - {id: a, centerline: [[0, 11], [40, 11]], width: 7.0, direction: one-way}
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 12, id_prefix: P}
  entrances:
    - {id: in, x: 3.0, y: 11.0, heading_deg: 0}
  exits:
    - {id: out, x: 34.0, y: 11.0, heading_deg: 0}
"""
SLOTS = ("P1", "P2", "P3")


@pytest.fixture(scope="module")
def tiny():
    sc = scenario_from_text(TINY + "traffic: {vehicles: [{id: x, arrival: 0}]}\n")
    return sc, prepare_graph(sc)


def _with(sc, vehicles=(), *, patience=60.0, stream=None):
    return dataclasses.replace(sc, traffic=TrafficSpec(vehicles=tuple(vehicles),
                                                       streams=(stream,) if stream else (),
                                                       patience=patience))


def _cars(*times, dwell=None):
    return [Arrival(f"c{k}", "valet", "in", float(t), dwell) for k, t in enumerate(times)]


# -- prepare ----------------------------------------------------------------------------------
def test_prepare_builds_the_slots_and_a_way_into_each_for_every_type(tiny):
    sc, lg = tiny
    assert sorted(s.id for s in lg.lot.slots) == list(SLOTS)
    assert lg.infeasible == {"valet": {}}
    parks = {lg.graph.nodes[v]["slot"] for _, v, d in lg.graph.edges(data=True)
             if d["kind"] == "park" and "valet" in d["maneuvers"]}
    assert parks == set(SLOTS)
    assert set(lg.entrances) == {"in"} and set(lg.exits) == {"out"}
    assert lg.reachability().ok


def test_a_type_longer_than_every_slot_can_use_none_and_its_cars_are_turned_away():
    """"Does my limo fit?" is the designer's question, not a broken file: its cars are
    turned away with the reason."""
    limo = "  - {name: limo, width: 2.0, front: 5.5, rear: 1.2, wheelbase: 4.2, max_steer_deg: 30}"
    text = TINY.replace("vehicle_types: [valet]", f"vehicle_types:\n  - valet\n{limo}")
    sc = scenario_from_text(text + "traffic: {vehicles: [{id: x, arrival: 0, type: limo}]}\n")
    lg = prepare_graph(sc)
    assert sorted(lg.infeasible["limo"]) == list(SLOTS)  # 6.7 m of car, 5 m of slot
    (x,) = simulate(sc, lot_graph=lg).vehicles
    assert x.status == "rejected" and "'limo' fits no slot" in x.reason and not x.moves


def test_a_prepared_lot_is_frozen_and_says_what_its_graph_says(tiny):
    sc, lg = tiny
    prepared = PreparedLot(sc, lg)
    assert prepared.lot is lg.lot and prepared.infeasible is lg.infeasible
    with pytest.raises(dataclasses.FrozenInstanceError):
        prepared.scenario = sc


# -- run: what a result holds ------------------------------------------------------------------
def test_a_run_holds_its_inputs_and_every_car_once_in_arrival_order(tiny):
    sc, lg = tiny
    sc = _with(sc, _cars(4, 0, 2))  # listed out of order
    settings = RunSettings(planner="hca")
    rr = simulate(sc, settings, lot_graph=lg)
    assert isinstance(rr, RunResult)
    assert rr.scenario is sc and rr.lot_graph is lg and rr.settings is settings
    assert rr.seed == sc.seed == 3
    assert [v.id for v in rr.vehicles] == ["c1", "c2", "c0"]
    assert [v.arrival.time for v in rr.vehicles] == [0.0, 2.0, 4.0]
    assert all(v.status == "parked" and v.reason == "" for v in rr.vehicles)
    assert sorted(v.slot for v in rr.vehicles) == list(SLOTS)  # three cars, three slots
    assert rr.planning_time > 0 and rr.ordering == {}


def test_each_car_s_moves_follow_on_in_time_and_end_with_it_inside_its_slot(tiny):
    sc, lg = tiny
    rr = simulate(_with(sc, _cars(0, 1)), lot_graph=lg)
    car = sc.vehicle_types[0]
    for v in rr.vehicles:
        assert v.moves[0].t0 >= v.arrival.time
        for a, b in zip(v.moves, v.moves[1:], strict=False):
            assert b.t0 == pytest.approx(a.t1, abs=1e-9) and a.t1 >= a.t0
        assert v.parked_at == pytest.approx(next(m.t1 for m in v.moves if m.kind == "park"))
        slot = shapely.Polygon(lg.lot.slot_by_id[v.slot].polygon).buffer(1e-6)
        body = shapely.Polygon(car.footprints([v.parked_pose])[0])
        assert slot.contains(body), v.id


def test_metrics_count_every_status_and_add_up(tiny):
    sc, lg = tiny
    rr = simulate(_with(sc, _cars(0, 1, dwell=15.0), patience=40), lot_graph=lg)
    m = rr.metrics()
    assert sum(m[s] for s in STATUSES) == m["vehicles"] == 2
    assert m["departed"] == 2  # both leave again through the exit
    ends = [v.moves[-1].t1 for v in rr.vehicles]
    assert m["makespan"] == pytest.approx(max(ends))
    assert m["searches"] == sum(v.searches for v in rr.vehicles) >= 4  # in and out, each




# -- a full lot, and patience -------------------------------------------------------------------
def test_cars_beyond_the_free_slots_are_turned_away_after_their_patience(tiny):
    sc, lg = tiny
    rr = simulate(_with(sc, _cars(0, 1, 2, 3, 4), patience=25), lot_graph=lg)
    by = {v.id: v for v in rr.vehicles}
    # nobody leaves: the first three get the three slots, the other two wait and give up
    assert [by[k].status for k in ("c0", "c1", "c2")] == ["parked"] * 3
    for k in ("c3", "c4"):
        v = by[k]
        assert v.status == "rejected" and v.slot is None
        assert "full" in v.reason and "25" in v.reason
        assert not [m for m in v.moves if m.kind != "outside"]
    # a car turned away waited outside for its whole patience
    assert rr.metrics()["total_waiting"] >= 2 * 25


def test_a_lot_with_every_slot_taken_turns_every_car_away_without_an_error(tiny):
    sc, _ = tiny
    full = scenario_from_text(TINY + "  occupied: [P1, P2, P3]\n"
                              + "traffic: {patience: 10, vehicles: [{id: x, arrival: 0}]}\n")
    rr = simulate(_with(full, _cars(0, 5), patience=10))
    assert [(v.status, "full" in v.reason) for v in rr.vehicles] == [("rejected", True)] * 2
    assert rr.metrics()["total_waiting"] == pytest.approx(20.0)


def test_a_queued_car_gets_the_freed_slot_only_if_it_waits_long_enough(tiny):
    sc, lg = tiny
    # three cars fill the lot, one of them leaves after 30 s; the fourth arrives at once
    cars = [*_cars(0, 0.5), Arrival("goes", "valet", "in", 1.0, 30.0),
            Arrival("late", "valet", "in", 2.0)]
    rr = simulate(_with(sc, cars, patience=600), lot_graph=lg)
    by = {v.id: v for v in rr.vehicles}
    late, goes = by["late"], by["goes"]
    assert late.status == "parked" and late.slot == goes.slot
    way_in = next(m.t0 for m in late.moves if m.kind != "outside")
    assert way_in >= next(m.t0 for m in goes.moves if m.kind == "leave")  # once it was free
    # a little less patient, it gives up before the slot is free
    patience = 0.8 * (way_in - late.arrival.time)
    late = simulate(_with(sc, cars, patience=patience), lot_graph=lg).vehicles[-1]
    assert late.status == "rejected" and f"waited {patience:g} s" in late.reason


def test_a_car_that_can_never_leave_ends_waiting_with_its_reason_and_run_exits_1(
        tiny, tmp_path, monkeypatch):
    # every search for a way out fails (as when the aisle stays blocked): the car tries
    # again and again, backing off, and is not reported parked when the run ends
    real = loopmod.search

    def no_way_out(sg, table, request, **kw):
        if request.goal.slot is None:  # towards the exits
            return Plan(Status.NO_PATH, expansions=1)
        return real(sg, table, request, **kw)

    monkeypatch.setattr(loopmod, "search", no_way_out)
    sc, lg = tiny
    rr = simulate(_with(sc, [Arrival("stuck", "valet", "in", 0.0, 20.0), *_cars(1)]), lot_graph=lg)
    stuck, other = rr.vehicles
    assert other.status == "parked" and other.reason == ""
    assert stuck.status == "waiting" and stuck.slot is not None
    assert stuck.reason.startswith("could not leave yet (no path)")
    assert "when the run ended" in stuck.reason
    assert stuck.searches > 3  # parked once, then tried to leave again and again
    assert rr.metrics()["waiting"] == 1
    assert result_dict(rr)["vehicles"][0]["status"] == "waiting"
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY + "traffic:\n  vehicles:\n"
                    "    - {id: stuck, type: valet, entrance: in, arrival: 0, dwell: 20}\n")
    assert main(["run", str(path), "-o", str(tmp_path / "o"), "--no-gif"]) == 1
    monkeypatch.setattr(loopmod, "search", real)
    assert main(["run", str(path), "-o", str(tmp_path / "p"), "--no-gif"]) == 0


# -- determinism and errors ----------------------------------------------------------------------
def test_a_seeded_stream_runs_the_same_twice_and_its_seed_draws_its_arrivals(tiny):
    sc, lg = tiny
    stream = StreamSpec(count=4, rate=240.0, mix=(("valet", 1.0),), entrances=("in",),
                        dwell=UniformDwell(10.0, 20.0))
    sc = _with(sc, stream=stream, patience=60)
    a, b = (result_dict(simulate(sc, lot_graph=lg)) for _ in range(2))
    assert a["vehicles"] == b["vehicles"] and a["settings"] == b["settings"]
    for seed in (3, 4):
        rr = simulate(sc, RunSettings(seed=seed), lot_graph=lg)
        drawn = arrivals(sc.traffic, seed)
        assert rr.seed == seed and len(drawn) == 4
        assert [(v.id, v.arrival.time, v.arrival.dwell) for v in rr.vehicles] == [
            (d.id, d.time, d.dwell) for d in drawn]
    assert [d.time for d in arrivals(sc.traffic, 3)] != [d.time for d in arrivals(sc.traffic, 4)]


def test_progress_counts_every_trip_in_and_out_once(tiny):
    sc, lg = tiny
    calls = []
    simulate(_with(sc, [*_cars(0, 1), Arrival("goes", "valet", "in", 2.0, 10.0)]), lot_graph=lg,
        progress=lambda done, total: calls.append((done, total)))
    total = 2 + 2  # two cars in, one car in and out
    assert {t for _, t in calls} == {total}
    done = [d for d, _ in calls]
    assert done == sorted(done) and done[-1] == total and len(set(done)) == len(done)


def test_a_scenario_without_traffic_is_refused_at_its_first_line():
    sc = scenario_from_text(TINY, file="lot.yaml")
    with pytest.raises(ScenarioError) as err:
        simulate(sc)
    assert (err.value.where.file, err.value.where.line, err.value.where.col) == ("lot.yaml", 1, 1)
    assert "no 'traffic' section" in err.value.message


def test_an_order_must_hold_every_vehicle_once(tiny):
    sc, lg = tiny
    sc = _with(sc, _cars(0, 1))
    for order in (("c0",), ("c0", "c0"), ("c0", "c1", "zz")):
        with pytest.raises(SettingsError, match="every vehicle id"):
            simulate(sc, RunSettings(order=order), lot_graph=lg)
    rr = simulate(sc, RunSettings(order=("c1", "c0")), lot_graph=lg)
    assert {v.id: v.status for v in rr.vehicles} == {"c0": "parked", "c1": "parked"}


# -- the garbage collector ---------------------------------------------------------------------
def test_a_run_leaves_the_garbage_collector_as_it_found_it(tiny, monkeypatch):
    sc, lg = tiny
    seen = []
    go = EventLoop.go

    def spy(self, *args):
        seen.append((gc.get_freeze_count(), gc.get_threshold()))
        go(self, *args)

    monkeypatch.setattr(EventLoop, "go", spy)
    before = (gc.get_freeze_count(), gc.get_threshold())
    simulate(_with(sc, _cars(0)), lot_graph=lg)
    assert seen == [before] and (gc.get_freeze_count(), gc.get_threshold()) == before


def test_collector_tuned_freezes_what_the_process_held_and_restores_it_even_on_an_error(
        tiny, monkeypatch):
    # frozen while it plans (the prepared lot is not scanned by its collections), collected
    # in larger batches; back to normal after it, also when planning raises
    sc, lg = tiny
    seen = []
    go = EventLoop.go

    def spy(self, *args):
        seen.append((gc.get_freeze_count(), gc.get_threshold()))
        go(self, *args)

    monkeypatch.setattr(EventLoop, "go", spy)
    before = (gc.get_freeze_count(), gc.get_threshold())
    assert before[1] != RUN_GC_THRESHOLDS
    with collector_tuned():
        simulate(_with(sc, _cars(0)), lot_graph=lg)
    assert seen[0][0] > before[0] and seen[0][1] == RUN_GC_THRESHOLDS
    assert (gc.get_freeze_count(), gc.get_threshold()) == before

    def boom(self, *args):
        raise KeyboardInterrupt

    monkeypatch.setattr(EventLoop, "go", boom)
    with pytest.raises(KeyboardInterrupt), collector_tuned():
        simulate(_with(sc, _cars(0)), lot_graph=lg)
    assert (gc.get_freeze_count(), gc.get_threshold()) == before


def test_collector_tuned_leaves_what_was_frozen_before_it_frozen():
    """An object frozen before stays out of the collector's generations (where
    ``gc.get_objects`` finds what is not frozen) inside and after: the count of frozen
    objects is no measure, as other tests' frozen objects may be freed meanwhile."""

    def frozen(x) -> bool:
        return not any(o is x for o in gc.get_objects())

    held = [object()]
    assert not frozen(held)
    gc.freeze()
    try:
        assert frozen(held)
        with collector_tuned():
            assert frozen(held)
        assert frozen(held)
    finally:
        gc.unfreeze()
    assert not frozen(held)


def test_runs_on_a_lot_are_timed_alike_whatever_ran_before_them(tiny):
    """The edge motions a lot's first run works out are kept (the lot's search graphs) for
    its later runs: that work is counted apart (``motion_time``), out of the planning
    times, so the first run's planning is not charged for it."""
    from lotsim.traffic.searchgraph import SearchGraphMemo

    sc, lg = tiny
    sc = _with(sc, _cars(0, 20, 40, dwell=60.0))
    memo = SearchGraphMemo()
    first, second = (simulate(sc, RunSettings(), lot_graph=lg, memo=memo) for _ in range(2))
    assert result_dict(first) == result_dict(second)  # the same plans
    assert first.motion_time > 0 and second.motion_time < first.motion_time / 10
    for rr in (first, second):
        assert rr.planning_time > 0  # every car's search took some time
        assert rr.metrics()["planning_time_motions"] == rr.motion_time
        assert sum(v.planning_time for v in rr.vehicles) <= rr.planning_time + 1e-9
    fresh = simulate(sc, RunSettings(), lot_graph=lg, memo=SearchGraphMemo())
    assert fresh.motion_time > second.motion_time  # a new memo works them out again
