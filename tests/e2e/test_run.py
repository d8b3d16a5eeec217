"""lotsim run: every result passes the independent checker; queues, rejections, assignment,
determinism, the expansion limit, and the errors a user can make."""

import dataclasses
import json
import math
import pickle

import numpy as np
import pytest

from conftest import HEAVY, ONE_AISLE, SCENARIOS, position, scenario_from_text, static_times
from lotsim.cli import main
from lotsim.core.outcome import Status
from lotsim.errors import ScenarioError
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import load_scenario
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import simulate
from lotsim.sim.settings import RunSettings, RunTuning
from lotsim.traffic.demand import Arrival, TrafficSpec, arrivals
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.search import Goal, SearchRequest, search
from lotsim.traffic.searchgraph import SearchGraph
from lotsim.traffic.settings import SearchSettings
from lotsim.verify import check_result
from single_track import assert_reproduced

LOT = ONE_AISLE


@pytest.fixture(scope="module")
def small():
    sc = scenario_from_text(LOT + "traffic: {vehicles: [{id: x, arrival: 0}]}\n")
    return sc, prepare_graph(sc)


def test_a_reverse_search_asked_many_things_answers_each_as_a_new_one_would(small):
    # the static times, and how many nodes a new one closes to answer (what sizes a
    # search's expansion limit), whatever the kept one was asked before
    sc, lg = small
    sg = SearchGraph(lg, sc.vehicle_types[0])
    nodes = sorted(sg.pose)
    rng = np.random.default_rng(5)
    reachable = 0
    for goal in sorted(lg.slot_nodes.values()):
        kept = sg.reverse_search({goal: 0.0})
        for start in rng.choice(nodes, size=12).tolist():
            new = sg.reverse_search({goal: 0.0})
            assert kept(start) == new(start)
            if new(start) < math.inf:
                reachable += 1
                assert kept.closed_at(start) == new.closed
    assert reachable >= 20


def _run(sc, lg, vehicles, patience=60.0, **settings):
    sc = dataclasses.replace(sc, traffic=TrafficSpec(vehicles=tuple(vehicles),
                                                     patience=patience))
    return simulate(sc, RunSettings(**settings), lot_graph=lg)


def _checked(rr):
    doc = result_dict(rr)
    report = check_result(doc)
    assert report.ok, [v.message for v in report.violations[:5]]
    assert_reproduced(doc)  # and the vehicle model, integrated, drives every car as planned
    return doc


# the large lot's whole run (100 cars, a minute of planning) only under -m slow; by default
# its first 12 cars (a queue, an expansion limit reached and a second choice among them): the
# same lot and the same code paths; the day's (some 300 cars) the first 8 of each of its streams:
# commuters in the morning, shoppers from 09:00, diners in the evening
_SHORTENED = {"large_lot": 12, "day": 8}


@pytest.mark.parametrize("path,whole", [
    *[pytest.param(p, p.stem not in _SHORTENED, id=p.stem,
                   marks=pytest.mark.slow if p.stem in HEAVY else ()) for p in SCENARIOS],
    *[pytest.param(p, True, id=f"{p.stem}-whole", marks=pytest.mark.slow)
      for p in SCENARIOS if p.stem in _SHORTENED]])
def test_every_shipped_scenario_runs_and_passes_the_independent_check(path, whole,
                                                                        shipped_graphs):
    sc = load_scenario(path)
    if not whole:
        streams = tuple(dataclasses.replace(s, count=_SHORTENED[path.stem])
                        for s in sc.traffic.streams)
        sc = dataclasses.replace(sc, traffic=dataclasses.replace(sc.traffic, streams=streams))
    rr = simulate(sc, lot_graph=shipped_graphs[path.stem])
    doc = _checked(rr)
    m = doc["metrics"]
    # nobody is lost: every vehicle is accounted for, with a reason where it did not park
    assert m["parked"] + m["departed"] + m["waiting"] + m["rejected"] == len(rr.vehicles) > 0
    assert m["parked"] + m["departed"] > 0
    for v in doc["vehicles"]:
        assert (v["status"] in ("waiting", "rejected")) == bool(v["reason"])
    # no stop that serves nothing: every stroke (motion between two stops) is at least
    # 10 cm long — cars no longer creep millimetres from one lane node to the next
    assert min(_stroke_lengths(doc), default=1.0) >= 0.10


def _stroke_lengths(doc):
    for v in doc["vehicles"]:
        x, y, speed = (np.array(v["samples"][k]) for k in ("x", "y", "v"))
        edges = np.flatnonzero(np.diff(np.concatenate([[0], (speed != 0).astype(int), [0]])))
        for a, b in zip(edges[::2], edges[1::2], strict=True):
            a, b = max(a - 1, 0), min(b, len(x) - 1)  # from the stop before to the one after
            yield float(np.sum(np.hypot(np.diff(x[a:b + 1]), np.diff(y[a:b + 1]))))


@pytest.mark.parametrize(("name", "planner"), [
    (name, planner) for name in ("quickstart", "street", "two_rows")
    for planner in ("ca", "hca", "whca")
    if (name, planner) != ("street", "ca")])  # CA* on the street: 15 s for no new case
def test_every_planner_and_policy_gives_a_checked_result(planner, name, shipped_graphs):
    sc = load_scenario(next(p for p in SCENARIOS if p.stem == name))
    assign = "nearest" if planner == "ca" else "shortest"
    rr = simulate(sc, RunSettings(planner=planner, assignment=assign, window=6.0),
             lot_graph=shipped_graphs[name])
    _checked(rr)


def test_samples_respect_speed_and_acceleration_limits(mixed_lot_doc):
    sc = load_scenario(next(p for p in SCENARIOS if p.stem == "mixed_lot"))
    doc = mixed_lot_doc
    lim = sc.vehicle_types[0].limits
    for v in doc["vehicles"]:
        s = {k: np.array(a) for k, a in v["samples"].items()}
        dt = np.diff(s["t"])
        moving = dt <= 0.05 + 1e-6
        acc = np.diff(s["v"])[moving] / dt[moving]
        # within a stroke speed changes no faster than the car accelerates or brakes
        # (forward: +accel / -brake; in reverse the signs swap); 2 % for rounding
        assert np.all(np.abs(acc) <= max(lim.max_accel, lim.max_brake) * 1.02 + 0.01)
        assert s["v"].max() <= lim.max_forward_speed + 1e-4  # written to 0.1 mm/s
        assert s["v"].min() >= -lim.max_reverse_speed - 1e-4
        step = np.hypot(np.diff(s["x"]), np.diff(s["y"]))
        assert step.max() <= 0.5


def test_a_full_lot_queues_then_rejects_with_a_reason_and_loses_nobody(small):
    sc, lg = small
    cars = [Arrival(f"c{k}", "valet", "in", float(2 * k)) for k in range(6)]
    rr = _run(sc, lg, cars, patience=30.0)
    status = {v.id: v.status for v in rr.vehicles}
    assert sorted(status.values()) == ["parked"] * 3 + ["rejected"] * 3
    for v in rr.vehicles:
        if v.status == "rejected":
            assert "full" in v.reason and "30" in v.reason
            assert v.moves == []
    _checked(rr)


def test_a_lot_with_every_slot_taken_turns_its_cars_away_and_validate_says_so():
    # not bad input: the cars are turned away as they are when the one free slot is taken
    # (run refused it with "no route from entrance 'in' to a free slot", exit 2)
    import lotsim

    text = (LOT.replace("occupied: [N1, N2, N3, N4, N5, S1, S2, S3, S4]",
                        "occupied: {fraction: 1.0, seed: 0, min_free: 0}")
            + "traffic:\n  patience: 20\n  vehicles: [{id: x, arrival: 0}, "
              "{id: y, arrival: 1, dwell: 5}]\n")
    report = lotsim.validate(text)
    assert any("every car will be turned away" in w for w in report.warnings)
    rr = lotsim.run(report.prepared)
    assert [(v.status, "full" in v.reason) for v in rr.vehicles] == [("rejected", True)] * 2
    assert lotsim.check(rr).ok


def test_validate_warns_of_the_cars_run_turns_away_for_any_seed_of_the_stream(tmp_path):
    # the scenario's seed draws no limo, a seed of run's may: validate judges every type the
    # stream can draw, with run's reason
    import lotsim

    path = tmp_path / "mix.yaml"
    path.write_text(LOT.replace("vehicle_types: [valet]", """vehicle_types:
  - valet
  - {name: limo, width: 2.0, front: 5.5, rear: 1.2, wheelbase: 4.2, max_steer_deg: 30}""")
        + "traffic:\n  stream: {count: 2, rate_per_hour: 60, mix: {valet: 9, limo: 1}}\n")
    sc = load_scenario(path)
    assert {a.vehicle for a in arrivals(sc.traffic, sc.seed)} == {"valet"}
    seed = next(s for s in range(100) if "limo" in {a.vehicle for a in arrivals(sc.traffic, s)})
    prepared = lotsim.prepare(path)
    away = [v for v in lotsim.run(prepared, seed=seed).vehicles if v.vehicle.name == "limo"]
    assert away and all(v.status == "rejected" for v in away)
    report = lotsim.validate(path)
    assert report.turned_away == {"limo": away[0].reason} and not report.complete
    assert "'limo' fits no slot" in away[0].reason
    assert f"warning: {away[0].reason}: its cars" in report.summary()


def test_a_queued_vehicle_gets_the_next_freed_slot(small):
    sc, lg = small
    cars = [Arrival("a", "valet", "in", 0.0, dwell=20.0), Arrival("b", "valet", "in", 1.0),
            Arrival("c", "valet", "in", 2.0), Arrival("d", "valet", "in", 3.0)]
    rr = _run(sc, lg, cars, patience=300.0)
    by = {v.id: v for v in rr.vehicles}
    assert by["a"].status == "departed"
    assert by["d"].status == "parked" and by["d"].slot == by["a"].slot
    # it parked only after the first car had driven out of the slot
    a_out = next(m.t1 for m in by["a"].moves if m.kind == "leave")
    assert by["d"].parked_at > a_out
    assert by["d"].moves[0].t0 > by["a"].parked_at + 20.0 - 1e-6
    _checked(rr)


def test_a_later_vehicle_waits_for_an_earlier_one_instead_of_overlapping(small):
    sc, lg = small
    alone = _run(sc, lg, [Arrival("b", "valet", "in", 0.0)])
    t_alone = alone.vehicles[0].parked_at
    # two cars at once: the second is planned around the first
    rr = _run(sc, lg, [Arrival("a", "valet", "in", 0.0), Arrival("b", "valet", "in", 0.0)])
    a, b = rr.vehicles
    assert a.parked_at == pytest.approx(t_alone)
    assert b.parked_at > t_alone + 1.0
    assert {a.slot, b.slot} <= {"N6", "S5", "S6"} and a.slot != b.slot
    _checked(rr)


@pytest.mark.parametrize("policy", ["nearest", "shortest", "priced"])
def test_the_first_vehicle_gets_the_best_slot_by_each_policy(policy, shipped_graphs):
    sc = load_scenario(next(p for p in SCENARIOS if p.stem == "mixed_lot"))
    lg = shipped_graphs["mixed_lot"]
    car = sc.vehicle_types[0]
    rr = _run(sc, lg, [Arrival("x", car.name, "gate-in", 0.0)], assignment=policy)
    got = rr.vehicles[0].slot
    gate = lg.entrances["gate-in"]
    x, y, _ = lg.graph.nodes[gate]["pose"]
    if policy == "nearest":
        score = {s.id: math.dist((x, y), s.center) for s in lg.lot.free_slots}
    else:
        dist = static_times(lg, car, gate)
        score = {}
        for u, v, d in lg.graph.edges(data=True):
            if d["kind"] == "park" and car.name in d["duration"] and u in dist:
                sid = lg.graph.nodes[v]["slot"]
                score[sid] = min(score.get(sid, math.inf), dist[u] + d["duration"][car.name])
    best = min(score.values())
    assert score[got] == pytest.approx(best, abs=1e-6)


def test_same_scenario_and_seed_give_the_same_file_byte_for_byte(tmp_path, shipped_graphs):
    import lotsim

    path = next(p for p in SCENARIOS if p.stem == "street")
    lg = shipped_graphs["street"]
    prepared = lotsim.PreparedLot(load_scenario(path), lg)
    outs = [lotsim.write_result(lotsim.run(prepared), tmp_path / f"r{k}.json").read_bytes()
            for k in range(2)]
    assert outs[0] == outs[1]
    # after another planner's run on the same lot, and on a copy of the lot: the same file
    lotsim.run(prepared, lotsim.RunSettings(planner="whca", seed=7))
    # its runs drive one search graph a vehicle type, made by the first
    assert len(prepared.search_graphs) == len(prepared.scenario.vehicle_types)
    copy = pickle.loads(pickle.dumps(lg))
    for k, held in enumerate((prepared, lotsim.PreparedLot(prepared.scenario, copy))):
        again = lotsim.run(held)
        assert lotsim.write_result(again, tmp_path / f"again{k}.json").read_bytes() == outs[0]
    # another seed draws other arrivals (that a run takes its seed's:
    # tests/unit/sim/test_running.py)
    sc = prepared.scenario
    assert [a.time for a in arrivals(sc.traffic, 99)] != [
        v["arrival"] for v in json.loads(outs[0])["vehicles"]]


def test_an_expansion_limit_reached_makes_the_car_wait_then_leaves_it_rejected_saying_so(
        small):
    sc, lg = small
    rr = _run(sc, lg, [Arrival("x", "valet", "in", 0.0)], patience=20.0, omega=1.0,
              search=SearchSettings(min_budget=3))
    v = rr.vehicles[0]
    assert v.status == "rejected" and "expansion limit" in v.reason
    assert v.searches >= 3  # it tried again while it waited
    _checked(rr)


def test_run_cli_writes_a_result_that_check_accepts_and_a_corrupted_one_it_refuses(
        tmp_path, capsys):
    path = next(p for p in SCENARIOS if p.stem == "quickstart")
    out = tmp_path / "out"
    assert main(["run", str(path), "-o", str(out), "--no-gif"]) == 0
    text = capsys.readouterr().out
    assert "parked" in text and "the last move ends at" in text and "result.json" in text
    assert [p.name for p in out.iterdir()] == ["result.json"]  # nothing half-written
    assert main(["check", str(out / "result.json")]) == 0
    said = capsys.readouterr().out
    assert "ok — 6 vehicles checked" in said and "footprint" not in said  # no internals
    assert main(["check", str(out / "result.json"), "--verbose"]) == 0
    assert "footprint tests" in capsys.readouterr().out
    doc = json.loads((out / "result.json").read_text())
    a, b = doc["vehicles"][0], doc["vehicles"][2]
    # drive the third car along the first one's path at the first one's time
    b["samples"] = json.loads(json.dumps(a["samples"]))
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    assert main(["check", str(bad)]) == 1
    assert "overlap" in capsys.readouterr().out


# -- bad input -------------------------------------------------------------------------------
@pytest.mark.parametrize("traffic, needle, words", [
    ("traffic: {vehicles: [{id: x, arrival: 0, type: bus}]}", "|bus", "vehicle type"),
    ("traffic: {stream: {count: 5, rate_per_hour: 0}}", "rate_per_hour: |0", "positive"),
    ("traffic: {stream: {count: 5, rate_per_hour: -3}}", "rate_per_hour: |-3", "positive"),
    ("traffic: {vehicles: [{id: x, arrival: 0, entrance: gate}]}", "|gate}", "in"),
    ("traffic: {vehicles: [{id: x, arrival: 0}, {id: x, arrival: 1}]}", "id: |x, arrival: 1",
     "twice"),
    ("traffic: {stream: {count: 5, rate_per_hour: 30, dwell: [90, 10]}}", "|[90", "min"),
    ("traffic: {stream: {count: 5, rate_per_hour: 30, mix: {valet: 1, van: 2}}}", "|van",
     "unknown key"),
    ("traffic: {}", "|{}", "vehicles"),
])
def test_traffic_errors_point_at_the_value(traffic, needle, words):
    text = LOT + traffic + "\n"
    with pytest.raises(ScenarioError) as err:
        scenario_from_text(text)
    line, col = position(text, needle)
    assert err.value.where.line == line and err.value.where.col == col
    assert words in err.value.message


def test_a_type_that_fits_no_slot_is_turned_away_and_the_others_park(small):
    sc = scenario_from_text(LOT.replace("vehicle_types: [valet]", """vehicle_types:
  - valet
  - {name: limo, width: 2.0, front: 5.5, rear: 1.2, wheelbase: 4.2, max_steer_deg: 30}""")
        + "traffic: {vehicles: [{id: x, arrival: 0}, {id: long, arrival: 1, type: limo}]}\n")
    x, long = simulate(sc).vehicles
    assert x.status == "parked"
    assert long.status == "rejected" and "'limo' fits no slot" in long.reason


def test_an_entrance_with_no_route_is_refused(small):
    sc, lg = small
    # an entrance past the last slot: no slot can be reached from it
    text = LOT.replace("    - {id: in, x: 3.0, y: 11.0, heading_deg: 0}",
                       "    - {id: in, x: 3.0, y: 11.0, heading_deg: 0}\n"
                       "    - {id: late, x: 43.0, y: 11.0, heading_deg: 0}")
    sc = scenario_from_text(text + "traffic: {vehicles: [{id: x, arrival: 0, entrance: late}]}\n")
    with pytest.raises(ScenarioError, match="no route from entrance 'late'"):
        simulate(sc)


def test_cli_run_errors_are_clean(tmp_path, capsys):
    bare = tmp_path / "bare.yaml"
    bare.write_text(LOT)
    assert main(["run", str(bare), "-o", str(tmp_path / "o")]) == 2
    assert "no 'traffic' section" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["run", str(bare), "--planner", "dijkstra"])
    assert exc.value.code == 2
    assert "invalid choice" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
    junk = tmp_path / "junk.json"
    junk.write_text("{not json")
    assert main(["check", str(junk)]) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_a_portal_where_a_car_would_stick_out_of_the_lot_is_refused():
    text = LOT.replace("{id: out, x: 44.0, y: 11.0, heading_deg: 0}",
                       "{id: out, x: 48.0, y: 11.0, heading_deg: 0}")
    with pytest.raises(ScenarioError) as err:
        prepare_graph(scenario_from_text(text))
    assert "sticks out of the lot boundary" in err.value.message
    assert (err.value.where.line, err.value.where.col) == position(text, "|{id: out")


def test_a_car_speeds_up_across_closely_spaced_nodes():
    # a straight 60 m lane cut into half-metre edges (nodes where maneuvers begin are often
    # that close): from rest, the car must reach the far end about as fast as over one
    # 60 m edge (the closed-form jerk-limited profile), not crawl at the speed it could
    # reach within half a metre
    import networkx as nx

    from lotsim.core.geometry import Segment
    from lotsim.roadmap.model import LotGraph
    from lotsim.vehicles import CATALOGUE
    from lotsim.vehicles.motion import scurve

    car = CATALOGUE["valet"]
    g = nx.DiGraph()
    step, n = 0.5, 121
    for k in range(n):
        g.add_node(k, pose=(k * step, 0.0, 0.0), kind="lane")
    for k in range(n - 1):
        g.add_edge(k, k + 1, kind="lane", length=step, gear=1, speed_limit=20 / 3.6,
                   path=(Segment((k * step, 0.0, 0.0), step, 0.0),), placeholder=False)
    sg = SearchGraph(LotGraph(None, g, {}, {}, {}), car)
    table, goal = ReservationTable(), Goal(exits=(n - 1,))
    plan = search(sg, table, SearchRequest(owner="x", start=0, t0=0.0, goal=goal))
    assert plan.status is Status.FOUND
    # a probe with a budget smaller than the search needs reaches the expansion limit there
    look = search(sg, table, SearchRequest(owner="x", start=0, t0=0.0, goal=goal,
                                           budget=plan.expansions - 2))
    assert look.status is Status.OUT_OF_BUDGET and look.expansions == plan.expansions - 1
    lim = car.limits
    best = min(p.duration for v in sg.levels
               if (p := scurve(60.0, 0.0, float(v), min(20 / 3.6, lim.max_forward_speed),
                               lim.max_accel, lim.max_brake, lim.max_jerk)) is not None)
    assert best <= plan.end <= 1.1 * best


@pytest.mark.slow
def test_whca_replans_only_when_space_was_freed_and_that_changes_next_to_nothing(
        shipped_graphs):
    """A replan with nothing freed since the car's last search could only find what its
    optimal search missed by its time lattice: the street's cars end as with every replan,
    park within 0.1 s of it, with fewer than half the searches."""
    sc = load_scenario(SCENARIOS[[p.stem for p in SCENARIOS].index("street")])
    runs = {}
    for skip in (True, False):
        settings = RunSettings(planner="whca", tuning=RunTuning(skip_fruitless=skip))
        runs[skip] = simulate(sc, settings, lot_graph=shipped_graphs["street"])
    fast, full = runs[True], runs[False]
    assert check_result(result_dict(fast)).ok
    assert 2 * fast.metrics()["searches"] < full.metrics()["searches"]
    for a, b in zip(fast.vehicles, full.vehicles, strict=True):
        assert (a.status, a.slot) == (b.status, b.slot)
        for ta, tb in ((a.parked_at, b.parked_at), (a.left_at, b.left_at)):
            assert (ta is None) == (tb is None)
            assert ta is None or abs(ta - tb) < 0.1, (a.id, ta, tb)


def test_the_run_summary_counts_what_became_of_each_car_as_the_result_does(tmp_path, capsys):
    # it read "parked 0, departed 30" (as if nothing parked), "total waiting 0.0 s;
    # makespan 8.5 s" when every car was turned away after waiting, and "1 searches"
    path = tmp_path / "s.yaml"
    path.write_text(LOT + "traffic:\n  patience: 25\n  vehicles: [{id: a, arrival: 0, dwell: 5},"
                    " {id: b, arrival: 1}, {id: c, arrival: 2}, {id: d, arrival: 3},"
                    " {id: e, arrival: 4}]\n")
    assert main(["run", str(path), "-o", str(tmp_path / "o"), "--no-gif"]) == 0
    out = capsys.readouterr().out
    doc = json.loads((tmp_path / "o" / "result.json").read_text())
    status = [v["status"] for v in doc["vehicles"]]
    away = status.count("rejected")
    assert status.count("departed") == 1 and away >= 1  # three slots for five cars
    served = len(status) - away
    assert (f"{served} served ({served - 1} parked at the end, 1 departed), 0 waiting, "
            f"{away} rejected") in out
    assert doc["metrics"]["served"] == served  # the same word in the result
    # a car turned away queued outside for the whole patience
    assert doc["metrics"]["total_waiting"] >= 25 * away
    assert out.count(": rejected: waited 25 s outside") == away
    searches = doc["metrics"]["searches"]
    assert f"({searches} searches, " in out and searches > 1

    path.write_text(LOT.replace("occupied: [N1, N2, N3, N4, N5, S1, S2, S3, S4]",
                                "occupied: [N1, N2, N3, N4, N5, N6, S1, S2, S3, S4, S5]")
                    + "traffic:\n  patience: 25\n  vehicles: [{id: a, arrival: 0}]\n")
    assert main(["run", str(path), "-o", str(tmp_path / "o"), "--no-gif"]) == 0
    out = capsys.readouterr().out
    assert "1 served (1 parked at the end, 0 departed), 0 waiting, 0 rejected" in out
    assert "(1 search, " in out

    path.write_text(LOT.replace("occupied: [N1, N2, N3, N4, N5, S1, S2, S3, S4]",
                                "occupied: {fraction: 1, seed: 0, min_free: 0}")
                    + "traffic:\n  patience: 25\n  vehicles: [{id: a, arrival: 0},"
                    " {id: b, arrival: 3}]\n")
    assert main(["run", str(path), "-o", str(tmp_path / "o"), "--no-gif"]) == 0
    out = capsys.readouterr().out
    doc = json.loads((tmp_path / "o" / "result.json").read_text())
    assert doc["metrics"]["total_waiting"] == pytest.approx(50.0)
    assert "time to park: no car parked; total waiting 50.0 s" in out and "no car moved" in out


def test_validate_lists_slot_ids_in_natural_order(capsys):
    from lotsim.api import validate

    text = LOT.replace("count: 6", "count: 12").replace("vehicle_types: [valet]", """\
vehicle_types:
  - valet
  - {name: limo, width: 2.0, front: 5.5, rear: 1.2, wheelbase: 4.2, max_steer_deg: 30}""")
    warning = next(w for w in validate(text).warnings if w.startswith("limo cannot park"))
    ids = warning.split(": ")[1].split(", ")
    # the free slots (N1-N5, S1-S4 are taken), N9 before N10 (it read N10, N11, N12, N6)
    assert ids[:12] == [f"N{k}" for k in range(6, 13)] + [f"S{k}" for k in range(5, 10)]
