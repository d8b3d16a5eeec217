"""lotsim.sim.loop: the event loop's probes, with a stand-in search where the real one
would take too long to run out."""

import pytest

from conftest import ROOT
from lotsim.core.outcome import Status
from lotsim.io.scenario_yaml import load_scenario
from lotsim.sim import loop as loopmod
from lotsim.sim.loop import EventLoop
from lotsim.sim.settings import RunSettings, RunTuning
from lotsim.traffic.demand import Arrival
from lotsim.traffic.plans import Plan

pytestmark = pytest.mark.slow  # the large lot is prepared for them


@pytest.fixture(scope="module")
def large(shipped_graphs):
    return load_scenario(ROOT / "scenarios" / "large_lot.yaml"), shipped_graphs["large_lot"]


@pytest.mark.parametrize("congested_for", [5.0, 12.0])
def test_after_a_probe_runs_out_the_next_cars_probe_other_aisles_first_for_a_while(
        large, monkeypatch, congested_for):
    """Every probe runs out (a stand-in search): the next car, within ``congested_for``,
    probes first the best slot outside the aisles those probes were in, and at its own
    best again once the span is over."""
    sc, lg = large
    car, gate = sc.vehicle_types[0].name, next(iter(lg.entrances))
    cars = [Arrival(f"c{k}", car, gate, 0.0) for k in range(3)]
    settings = RunSettings(tuning=RunTuning(congested_for=congested_for))
    loop = EventLoop(sc, lg, settings, cars, None)
    looks: list[tuple[str, str, float]] = []  # (car, slot, start time) of each probe
    slot_of = {node: sid for sid, node in lg.slot_nodes.items()}

    def runs_out(sg, table, ask, **kw):
        if ask.budget is not None:
            looks.append((ask.owner, slot_of[ask.goal.slot], ask.t0))
            return Plan(Status.OUT_OF_BUDGET, expansions=ask.budget + 1)
        return Plan(Status.NO_PATH)

    monkeypatch.setattr(loopmod, "search", runs_out)
    aisle = {s.id: s.aisle for s in lg.lot.slots}
    assigner = loop.assigner
    ranked = assigner.ranked(cars[0], loop.free)
    loop.on_retry(0, loop.vehicles[0], 0.0)
    first = [sid for who, sid, _ in looks if who == "c0"]
    assert first == assigner.few(ranked) and len({aisle[s] for s in first}) == 3
    assert all(v.reason.startswith("no conflict-free route") for v in loop.vehicles[:1])
    congested = {aisle[s] for s in first}
    loop.on_retry(1, loop.vehicles[1], congested_for - 0.5)
    second = [sid for who, sid, _ in looks if who == "c1"]
    assert second[0] == next(s for s in ranked if aisle[s] not in congested)
    assert not congested & {aisle[s] for s in second}
    # congested_for after c0's probes their aisles are free again; c1's are still congested
    loop.on_retry(2, loop.vehicles[2], congested_for)
    third = [sid for who, sid, _ in looks if who == "c2"]
    assert third == assigner.few([s for s in ranked if aisle[s] not in {aisle[x] for x in second}])
    assert third[0] == ranked[0]


def test_a_probe_is_budgeted_by_the_static_time_its_reverse_search_reads(large):
    # the loop reads the slot's static time off the RRA* the search asks anyway: the same
    # time as the forward search from the gate that ranks the slots
    sc, lg = large
    loop = EventLoop(sc, lg, RunSettings(), [], None)
    car, gate = sc.vehicle_types[0].name, next(iter(lg.entrances))
    times = loop.assigner.slot_times(gate, car, False)
    for sid in (min(times, key=times.get), max(times, key=times.get)):
        budget = loop.probe_budget(loop.graphs[car], lg.entrances[gate], lg.slot_nodes[sid])
        assert budget == loop.assigner.probe_budget(times[sid])


def test_a_run_keeps_at_most_heuristics_kept_reverse_searches(large):
    sc, lg = large
    car, gate = sc.vehicle_types[0].name, next(iter(lg.entrances))
    loop = EventLoop(sc, lg, RunSettings(tuning=RunTuning(heuristics_kept=2)), [], None)
    sg = loop.graphs[car]
    nodes = sorted(lg.slot_nodes.values())[:5]
    for node in nodes:
        loop.probe_budget(sg, lg.entrances[gate], node)
    assert [key[1] for key in loop._heuristics] == nodes[-2:]  # the last two asked
