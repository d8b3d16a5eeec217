"""Priority orders: booked traffic planned in a given order, shortest first, and the GA."""

import dataclasses
import math
import time

import numpy as np
import pytest

from conftest import ONE_AISLE, ROOT, scenario_from_text, static_times
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import load_scenario
from lotsim.roadmap.reach import lane_reach
from lotsim.sim.orders import (
    _order_crossover,
    fitness,
    genetic_order,
    plan_run,
    shortest_first,
)
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import simulate
from lotsim.sim.settings import GASettings, RunSettings
from lotsim.traffic.demand import Arrival, TrafficSpec, arrivals
from lotsim.verify import check_result

BURST = ONE_AISLE.replace("occupied: [N1, N2, N3, N4, N5, S1, S2, S3, S4]",
                          "occupied: [N1, N3, N5, S2, S4, S6]") + \
    "traffic: {vehicles: [{id: x, arrival: 0}]}\n"


@pytest.fixture(scope="module")
def burst():
    sc = scenario_from_text(BURST)
    return sc, prepare_graph(sc)


def _with(sc, cars, patience=120.0):
    return dataclasses.replace(sc, traffic=TrafficSpec(vehicles=tuple(cars), patience=patience))


def _checked(rr):
    report = check_result(result_dict(rr))
    assert report.ok, [v.message for v in report.violations[:5]]
    return rr


CARS = [Arrival(f"c{k}", "valet", "in", 2.0 * k) for k in range(5)]


def test_the_vehicle_planned_first_parks_as_fast_as_it_would_alone(burst):
    sc, lg = burst
    busy = _with(sc, CARS)
    for first in ("c4", "c2", "c0"):
        order = (first,) + tuple(c.id for c in CARS if c.id != first)
        rr = _checked(simulate(busy, RunSettings(order=order), lot_graph=lg))
        got = next(v for v in rr.vehicles if v.id == first)
        alone = simulate(_with(sc, [c for c in CARS if c.id == first]), RunSettings(),
                    lot_graph=lg).vehicles[0]
        assert got.slot == alone.slot
        assert got.parked_at == pytest.approx(alone.parked_at, abs=1e-9)


def test_booked_runs_pass_the_checker_and_start_no_vehicle_before_it_arrives(burst):
    sc, lg = burst
    cars = CARS + [Arrival(f"d{k}", "valet", "in", 30.0 + 7 * k, dwell=40.0) for k in range(4)]
    busy = _with(sc, cars)
    rng = np.random.default_rng(3)
    ids = [c.id for c in cars]
    for horizon in (5.0, 30.0, math.inf):
        order = tuple(rng.permutation(ids).tolist())
        rr = _checked(simulate(busy, RunSettings(order=order, horizon=horizon), lot_graph=lg))
        for v in rr.vehicles:
            assert all(m.t0 >= v.arrival.time - 1e-9 for m in v.moves)
            # turned away after its patience exactly when it never got a plan in
            assert (v.status == "rejected") == (v.moves == [])


def test_an_order_must_name_every_vehicle_once(burst):
    sc, lg = burst
    busy = _with(sc, CARS)
    for bad in (("c0", "c1"), ("c0", "c0", "c1", "c2", "c3"), ("c0", "c1", "c2", "c3", "zz")):
        with pytest.raises(ValueError, match="every vehicle id"):
            simulate(busy, RunSettings(order=bad), lot_graph=lg)


def test_fitness_is_the_total_time_to_park_with_a_penalty_for_the_unparked(burst):
    sc, lg = burst
    rr = simulate(_with(sc, CARS), RunSettings(), lot_graph=lg)
    m = rr.metrics()
    assert m["parked"] == 5
    assert fitness(rr) == pytest.approx(m["mean_time_to_park"] * 5)
    # 8 cars for 6 free slots, nobody leaves: two are turned away after 30 s
    full = simulate(_with(sc, [Arrival(f"f{k}", "valet", "in", 2.0 * k) for k in range(8)], 30.0),
               RunSettings(), lot_graph=lg)
    parked = [v.parked_at - v.arrival.time for v in full.vehicles if v.parked_at is not None]
    assert len(parked) == 6
    assert fitness(full) == pytest.approx(sum(parked) + 2 * (30.0 + 600.0))
    # the penalty is the run's GA setting
    milder = dataclasses.replace(full, settings=RunSettings(ga=GASettings(unparked_penalty=50)))
    assert fitness(milder) == pytest.approx(sum(parked) + 2 * (30.0 + 50.0))


def test_shortest_first_orders_by_static_time_to_a_slot():
    sc = load_scenario(ROOT / "scenarios" / "street.yaml")
    lg = prepare_graph(sc)
    order = shortest_first(sc, lg)
    traffic = arrivals(sc.traffic, sc.seed)
    assert sorted(order) == sorted(a.id for a in traffic)
    # independent: networkx Dijkstra over the lanes at each type's top speed, plus the
    # quickest maneuver into a free slot it can leave again (if it will leave)
    leave = lane_reach(lg)[1]  # lane nodes from which an exit can be reached
    best = {}
    for a in traffic:
        car = sc.vehicle_type(a.vehicle)
        dist = static_times(lg, car, lg.entrances[a.entrance])
        best[a.id] = min(dist[u] + d["duration"][car.name]
                         for u, v, d in lg.graph.edges(data=True)
                         if d["kind"] == "park" and car.name in d["duration"] and u in dist
                         and lg.graph.nodes[v]["slot"] not in lg.lot.occupied
                         and (a.dwell is None or u in leave))
    times = [best[vid] for vid in order]
    assert times == sorted(times)
    assert list(order) != [a.id for a in traffic]  # three types: not the arrival order


def test_order_crossover_gives_permutations_keeping_a_slice_of_the_first_parent():
    rng = np.random.default_rng(0)
    for n in (1, 2, 5, 12):
        for _ in range(30):
            a, b = rng.permutation(n), rng.permutation(n)
            c = _order_crossover(a, b, rng)
            assert sorted(c.tolist()) == list(range(n))
            same = c == a
            assert same.any() or n == 0


@pytest.mark.slow
def test_the_ga_never_does_worse_than_arrival_order_or_shortest_first(burst):
    sc, lg = burst
    cars = [Arrival(f"c{k}", "valet", "in", 1.0 * k) for k in range(5)]
    busy = _with(sc, cars)
    ga = GASettings(population=4, generations=2, seed=1)  # small: the claims hold at any size
    order, found = genetic_order(busy, RunSettings(), lot_graph=lg, ga=ga)
    assert sorted(order) == sorted(c.id for c in cars)
    assert found["fitness"] <= found["fitness_arrival"] + 1e-9
    assert found["fitness"] <= found["fitness_shortest_first"] + 1e-9
    assert all(b <= a + 1e-9 for a, b in zip(found["history"], found["history"][1:],
                                             strict=False))
    assert found["evaluations"] <= ga.population * (ga.generations + 1)
    # the order found gives that fitness when planned again (independent run)
    rr = _checked(simulate(busy, RunSettings(order=order), lot_graph=lg))
    assert fitness(rr) == pytest.approx(found["fitness"])
    # same GA seed, same answer
    again, _ = genetic_order(busy, RunSettings(), lot_graph=lg, ga=ga)
    assert again == order


def test_plan_run_records_how_the_order_was_chosen(burst):
    sc, lg = burst
    busy = _with(sc, CARS)
    for priority in ("arrival", "shortest_first", "ga"):
        settings = RunSettings(priority=priority, ga=GASettings(population=4, generations=1))
        clock = time.perf_counter()
        rr = _checked(plan_run(busy, settings, lot_graph=lg))
        wall = time.perf_counter() - clock
        extra = rr.ordering
        assert extra["fitness"] == pytest.approx(fitness(rr))
        # chosen before the run planned in that order, within the call's time
        assert 0 <= extra["order_time"] <= wall - rr.planning_time
        assert (extra["evaluations"] > 0) == (priority == "ga")
        assert (rr.settings.order is None) == (priority == "arrival")
        if priority == "shortest_first":
            assert rr.settings.order == shortest_first(busy, lg)


def test_run_plans_booked_traffic_in_the_order_asked(tmp_path, capsys):
    import lotsim
    from lotsim.cli import main

    path = ROOT / "scenarios" / "street.yaml"
    sc = load_scenario(path)
    prepared = lotsim.PreparedLot(sc, prepare_graph(sc))
    rr = lotsim.run(prepared, priority="shortest_first", horizon=120)
    assert rr.settings.order == shortest_first(sc, prepared.lot_graph)
    doc = lotsim.result_dict(rr)
    assert tuple(doc["settings"]["order"]) == rr.settings.order
    assert doc["settings"]["horizon"] == 120
    assert check_result(doc).ok
    # the command line takes the same settings, and refuses a horizon the library refuses
    with pytest.raises(lotsim.SettingsError, match="horizon: expected a positive"):
        lotsim.run(prepared, priority="ga", horizon=0)
    assert main(["run", str(path), "--priority", "ga", "--horizon", "0"]) == 2
    assert "--horizon: expected a positive" in capsys.readouterr().err
    # and says what the order it chose is worth
    assert main(["run", str(ROOT / "scenarios" / "quickstart.yaml"), "-o", str(tmp_path),
                 "--no-gif", "--priority", "shortest_first"]) == 0
    assert "priority shortest_first: total time to park" in capsys.readouterr().out
