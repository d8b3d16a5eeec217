"""The ``priced`` slot choice (``SlotAssigner.prices``): the share of the slots whose
shortest way passes each lane node, against networkx's shortest paths; the flows seen at
the gate; the price of a slot every way passes in closed form; the ranking against brute
force; and a run at real demand that checks and repeats."""

from __future__ import annotations

import networkx as nx
import pytest

from conftest import ONE_AISLE, ROOT
from lotsim.io.scenario_yaml import load_scenario
from lotsim.sim.assignment import SlotAssigner
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.settings import RunTuning
from lotsim.traffic.demand import Arrival

GATE_SPUR = ROOT / "scenarios" / "lots" / "gate_spur.yaml"


pytestmark = pytest.mark.slow  # preparing the gate spur lot for them outweighs the rest

@pytest.fixture(scope="module")
def gate_spur():
    sc = load_scenario(GATE_SPUR)
    return sc, prepare_graph(sc)


def _assigner(gate_spur, **tuning) -> SlotAssigner:
    sc, lg = gate_spur
    return SlotAssigner(lg, sc.vehicle_types, policy="priced", tuning=RunTuning(**tuning))


def _lanes(sg) -> nx.DiGraph:
    """The type's graph of the lot graph's edges between lane nodes (no slot, no express
    edge), each weighted by its static time (the least of parallel ones)."""
    g = nx.DiGraph()
    for ei, e in enumerate(sg.edges[:sg.base_edges]):
        if e.u in sg.slot_nodes or e.v in sg.slot_nodes:
            continue
        w = sg.static_time(ei)
        if not g.has_edge(e.u, e.v) or g[e.u][e.v]["weight"] > w:
            g.add_edge(e.u, e.v, weight=w)
    return g


def test_route_shares_count_shortest_ways_networkx_agrees_with(gate_spur):
    """Each slot's way in (from the entrance to where its maneuver begins) and way out
    (from where its leaving ends to the exit), walked node by node, is as short as
    networkx's Dijkstra finds; the shares are the counts of those walks over the slots."""
    sc, lg = gate_spur
    assigner = _assigner(gate_spur)
    car = sc.vehicle_types[0].name
    sg = assigner.graphs[car]
    g = _lanes(sg)
    gate, exit_ = lg.entrances["gate-in"], lg.exits["gate-out"]
    dist_in, by_in = sg.forward_tree(gate, express=False)
    dist_out, by_out = sg.backward_tree([exit_], express=False)
    shortest_in = nx.single_source_dijkstra_path_length(g, gate)
    shortest_out = nx.single_source_dijkstra_path_length(g.reverse(copy=False), exit_)

    def walk(n: int, by: dict, end) -> list[int]:
        way = [n]
        while way[-1] in by:
            way.append(end(sg.edges[by[way[-1]]]))
        return way

    cases = (
        ("gate-in", [sg.edges[p].u for _, p, _ in assigner.slot_ways("gate-in", car, False)
                     .values()], by_in, lambda e: e.u, shortest_in, gate),
        (None, [sg.edges[lv].v for _, _, lv in assigner.slot_ways("gate-in", car, True)
                .values()], by_out, lambda e: e.v, shortest_out, exit_))
    for key, ends, by, end, shortest, root in cases:
        expected: dict[int, float] = {}
        for n in ends:
            way = walk(n, by, end)
            assert way[-1] == root
            length = sum(sg.static_time(by[m]) for m in way[:-1])
            assert length == pytest.approx(shortest[n], abs=1e-9)
            for m in way:
                expected[m] = expected.get(m, 0) + 1 / len(ends)
        got = assigner.route_shares(car, key)
        assert got == pytest.approx(expected)
        assert got[root] == pytest.approx(1.0)  # the gate: every way passes it


def test_flows_are_the_cars_seen_over_the_window(gate_spur):
    assigner = _assigner(gate_spur, flow_window=100.0)
    assert assigner.flows(50.0) == {}
    for t in (10.0, 30.0, 95.0, 120.0):
        assigner.saw("gate-in", t)
    assigner.saw(None, 60.0)
    assert assigner.flows(100.0) == {"gate-in": 0.03, None: 0.01}
    assert assigner.flows(125.0) == {"gate-in": 0.03, None: 0.01}  # 10 s fell out
    assert assigner.flows(170.0) == {"gate-in": 0.02, None: 0.0}


def test_without_traffic_priced_ranks_as_shortest(gate_spur):
    sc, lg = gate_spur
    free = {s.id for s in lg.lot.free_slots}
    car = Arrival("a", sc.vehicle_types[0].name, "gate-in", 0.0, 600.0)
    priced = _assigner(gate_spur).ranked(car, free, 0.0)
    shortest = SlotAssigner(lg, sc.vehicle_types, policy="shortest").ranked(car, free)
    assert priced == shortest


def test_a_slot_every_way_passes_costs_the_flow_times_its_maneuvers_squared():
    """On a one-way aisle, every way in passes where the slot nearest the entrance is
    parked from, and every way out where the slot nearest the exit is left to: with cars
    seen only coming in (only going out), that slot's price is ``f (d_park² + d_leave²) /
    2``, the most any slot's maneuvers can cost (no stretch of lane sees more than the whole
    flow). Prices follow the flow seen."""
    sc = load_scenario(ONE_AISLE)
    lg = prepare_graph(sc)
    assigner = SlotAssigner(lg, sc.vehicle_types, policy="priced")
    car = sc.vehicle_types[0].name
    sg = assigner.graphs[car]
    ways = assigner.slot_ways("in", car, True)
    dist_in = sg.forward_times(lg.entrances["in"])
    dist_out, _ = sg.backward_tree([lg.exits["out"]])

    def held(sid: str) -> float:
        _, park, leave = ways[sid]
        return (sg.edges[park].duration ** 2 + sg.edges[leave].duration ** 2) / 2

    first_in = min(ways, key=lambda sid: dist_in[sg.edges[ways[sid][1]].u])
    last_out = min(ways, key=lambda sid: dist_out[sg.edges[ways[sid][2]].v])
    for k in range(6):  # 6 in in ten minutes
        assigner.saw("in", 100.0 * k)
    price = assigner.prices("in", car, True, 599.0)
    assert price[first_in] == pytest.approx(0.01 * held(first_in))
    assert all(p <= 0.01 * held(sid) * (1 + 1e-9) for sid, p in price.items())
    last_in = max(ways, key=lambda sid: dist_in[sg.edges[ways[sid][1]].u])
    assert price[last_in] < 0.7 * 0.01 * held(last_in)  # fewer ways go past the farthest
    assigner.saw("in", 599.0)  # one more car in: a sixth dearer
    more = assigner.prices("in", car, True, 599.0)
    assert more == pytest.approx({s: p * 7 / 6 for s, p in price.items()})
    going = SlotAssigner(lg, sc.vehicle_types, policy="priced")
    for k in range(3):  # 3 out in ten minutes
        going.saw(None, 100.0 * k)
    out = going.prices("in", car, True, 599.0)
    assert out[last_out] == pytest.approx(0.005 * held(last_out))
    assert all(p <= 0.005 * held(sid) * (1 + 1e-9) for sid, p in out.items())


def test_with_traffic_seen_priced_takes_the_cheapest_slot_all_told(gate_spur):
    """At 350 cars an hour in and out, a car's slots are ranked by static time plus price
    (its first the least, by brute force over the free slots): the slots shortest ranks,
    in another order."""
    sc, lg = gate_spur
    assigner = _assigner(gate_spur)
    for k in range(58):
        assigner.saw("gate-in", 600.0 * k / 58)
        assigner.saw(None, 600.0 * k / 58)
    free = {s.id for s in lg.lot.free_slots}
    car = Arrival("a", sc.vehicle_types[0].name, "gate-in", 600.0, 600.0)
    times = assigner.slot_times("gate-in", car.vehicle, True)
    price = assigner.prices("gate-in", car.vehicle, True, 600.0)
    best = min((s for s in free if s in times), key=lambda s: (times[s] + price[s], s))
    got = assigner.ranked(car, free, 600.0)
    assert got[0] == best
    assert got == sorted(got, key=lambda s: (times[s] + price[s], s))
    shortest = SlotAssigner(lg, sc.vehicle_types, policy="shortest").ranked(car, free)
    assert sorted(got) == sorted(shortest) and got != shortest  # the same, reordered


def test_a_priced_run_at_real_demand_serves_every_car_checks_and_repeats(gate_spur):
    """30 cars at 350 an hour through the gate spur, slots priced: every car is served,
    the result passes the checker, and the same seed plans the same run."""
    import dataclasses

    import lotsim
    from lotsim.io.result import result_dict
    from lotsim.sim.running import simulate
    from lotsim.sim.settings import RunSettings

    sc, lg = gate_spur
    stream = dataclasses.replace(sc.traffic.streams[0], count=30, rate=350 / 3600)
    sc = dataclasses.replace(sc, traffic=dataclasses.replace(sc.traffic, streams=(stream,)))
    runs = [simulate(sc, RunSettings(seed=1, assignment="priced"), lot_graph=lg)
            for _ in range(2)]
    assert runs[0].metrics()["served"] == 30
    assert lotsim.check(runs[0]).ok
    assert result_dict(runs[0]) == result_dict(runs[1])
