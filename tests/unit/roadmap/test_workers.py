"""The roadmap's searches shared out over forked workers, kept in a memo, or planned ahead on
a background process find exactly what working each out where it is met finds."""

import math

import numpy as np
import pytest

from conftest import ROOT, SCENARIOS
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot, lane_collider
from lotsim.lot.model import DesignVehicle
from lotsim.roadmap import assemble, turnarounds
from lotsim.roadmap.junctions import junction_turns, turns_of, turns_per_design
from lotsim.roadmap.lanes import portal_station
from lotsim.roadmap.memo import RoadmapMemo
from lotsim.roadmap.multipoint import closing_moves
from lotsim.roadmap.through import through_chains, through_turn
from lotsim.sim.preparation import prepare_graph

LOTS = ROOT / "scenarios" / "lots"

pytestmark = pytest.mark.cores  # lotsim's workers on the machine's cores


def _one_by_one(lot, collider, design):
    """A design's junction turns and turns through short stretches, found in one go."""
    turns, skipped = junction_turns(lot, collider, design)
    chains = through_chains(lot, turns)
    return turns + [t for c in chains for t in through_turn(lot, collider, design, c)], skipped


def test_turns_found_on_two_workers_are_those_each_type_finds_on_its_own():
    # the mixed lot's three types: junction turns per type and lane, on forked workers,
    # against each type's junction turns and turns through short stretches found in one go
    sc = load_scenario(SCENARIOS[[p.stem for p in SCENARIOS].index("mixed_lot")])
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    collider = lane_collider(lot)
    designs = [DesignVehicle.envelope([v]) for v in sc.vehicle_types]
    expected = [_one_by_one(lot, collider, design) for design in designs]
    assert sum(len(turns) for turns, _ in expected) > 10
    assert turns_per_design(lot, collider, designs) == expected


@pytest.mark.slow
def test_turns_through_stretches_on_two_workers_are_those_each_type_finds_on_its_own():
    # the gate spur's junctions close together, for two types: each stretch's turn a task
    # on forked workers, against each type's junction and through turns found in one go
    from lotsim.vehicles import CATALOGUE

    sc = load_scenario(LOTS / "gate_spur.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    collider = lane_collider(lot)
    designs = [DesignVehicle.envelope([CATALOGUE[n]]) for n in ("valet", "zoe")]
    for design in designs:
        assert len(through_chains(lot, junction_turns(lot, collider, design)[0])) >= 5
    expected = [_one_by_one(lot, collider, design) for design in designs]
    assert turns_per_design(lot, collider, designs) == expected


@pytest.mark.slow
def test_turnarounds_searched_in_rounds_on_two_workers_are_those_searched_one_by_one(
        monkeypatch):
    # the ladder's dead ends need multi-point turnarounds, some of them searched after
    # another (a car arriving past the first): searched in rounds on forked workers, each
    # once, against each searched where it is met
    from lotsim.roadmap import remembered

    sc = load_scenario(LOTS / "ladder.yaml")
    searched, jobs = [], {}
    real_fork_map, real_reaching_all = remembered.fork_map, turnarounds._reaching_all
    real_onto = turnarounds._reaching_onto

    def recording(lane, back, starts, hi, collider, body, radius, **tuned):
        searched.append((lane.id, back.id, body, tuple(starts), hi))
        return real_onto(lane, back, starts, hi, collider, body, radius, **tuned)

    def turnaround_edges(lg):
        return sorted((u, v, d["path"]) for u, v, d in lg.graph.edges(data=True)
                      if d["kind"] == "turnaround")

    # the searches in this process, to count them
    monkeypatch.setattr(remembered, "fork_map", lambda fn, items, **kw: [fn(x) for x in items])
    monkeypatch.setattr(turnarounds, "_reaching_onto", recording)
    monkeypatch.setattr(turnarounds, "_reaching_all", lambda todo, memo, *rest, **tuned: (
        jobs.update(todo), real_reaching_all(todo, memo, *rest, **tuned))[1])
    found = turnaround_edges(prepare_graph(sc, cache=False))
    assert len(searched) >= 8 and len(set(searched)) == len(searched)
    # a second build whose cars arrive elsewhere on a lane searches only from there
    ends = [job for job in jobs.values() if any(
        (job[0].id, len(starts)) == (lane, len(turnarounds.DEFAULTS.turnarounds.starts))
        for lane, _, _, starts, _ in searched)]
    assert ends
    for job in ends:
        memo, arrive = {}, max(job[6])
        real_reaching_all({0: job}, memo)
        searched.clear()
        real_reaching_all({0: (*job[:6], {arrive - 0.5}, job[7])}, memo)
        assert all(len(starts) == 1 for *_, starts, _ in searched)
    monkeypatch.setattr(remembered, "fork_map", real_fork_map)  # on two workers
    monkeypatch.setattr(turnarounds, "_reaching_onto", real_onto)
    assert turnaround_edges(prepare_graph(sc, cache=False)) == found
    monkeypatch.setattr(turnarounds, "_reaching_all", lambda todo, memo, *rest, **tuned: {
        key: turnarounds._reaching_turnarounds(*job, **tuned) for key, job in todo.items()})
    assert turnaround_edges(prepare_graph(sc, cache=False)) == found


@pytest.mark.slow
def test_junction_multipoints_and_uturns_found_at_once_are_those_found_one_after_another():
    # the ladder's junctions: multi-point turns (none there) and U-turns, worked out
    # together on two forked workers for one lot, against each worked out in this process
    # for another
    from lotsim.roadmap.junction_multipoints import junction_multipoints
    from lotsim.roadmap.uturns import junction_uturns

    sc = load_scenario(LOTS / "ladder.yaml")
    designs = ({v.name: DesignVehicle.envelope([v]) for v in sc.vehicle_types}
               if len(sc.vehicle_types) > 1 else None)
    found = []
    for at_once in (True, False):
        lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
        memo = RoadmapMemo(lot)
        tagged, _ = turns_of(lot, lane_collider(lot), designs, memo)
        exits = {portal_station(lot, p)[0]: portal_station(lot, p)[1] for p in lot.exits}
        found.append(assemble.junction_turnarounds(lot, tagged, designs, exits, memo) if at_once
                     else (junction_multipoints(lot, tagged, designs, exits, memo),
                           junction_uturns(lot, designs, memo)))
        # and again, from what the memo kept
        assert assemble.junction_turnarounds(lot, tagged, designs, exits, memo) == found[-1]
    multis, uturns = found[0]
    assert len(uturns) > 10 and found[0] == found[1]


def test_a_memo_serves_only_its_own_lot():
    sc = load_scenario(next(p for p in SCENARIOS if p.stem == "example"))
    lots = [build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types)) for _ in range(2)]
    memo = RoadmapMemo(lots[0])
    assemble.build_graph(lots[0], memo=memo)
    assert memo.turns
    with pytest.raises(ValueError, match="one lot"):
        assemble.build_graph(lots[1], memo=memo)


def test_a_graph_built_with_a_memo_is_the_one_built_without():
    # the lanes' graph first, then the graph through placeholder links, with one memo
    # (as preparing does) and each afresh: the same nodes and edges, in the same order
    sc = load_scenario(LOTS / "culdesac.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    memo = RoadmapMemo(lot)
    lanes = assemble.lane_graph(lot, vehicles=sc.vehicle_types, memo=memo)
    kept = assemble.build_graph(lot, vehicles=sc.vehicle_types, memo=memo)
    fresh = assemble.build_graph(lot, vehicles=sc.vehicle_types)
    assert list(kept.graph.edges(data=True)) == list(fresh.graph.edges(data=True))
    assert list(kept.graph.nodes(data=True)) == list(fresh.graph.nodes(data=True))
    # the lanes' graph is the placeholder graph without its slots, numbered alike
    lane_nodes = [(n, d) for n, d in fresh.graph.nodes(data=True) if d["kind"] != "slot"]
    assert list(lanes.graph.nodes(data=True)) == lane_nodes
    assert list(lanes.graph.edges(data=True)) == [
        (u, v, d) for u, v, d in fresh.graph.edges(data=True)
        if d["kind"] not in ("park", "leave")]


def test_closings_checked_in_batches_find_what_checking_each_finds():
    """A turnaround's last moves, from every probe along a stroke, are checked together,
    the k-th of each at once (turnarounds._first_clear): each probe gets the first closing
    that checking them one by one finds clear (turnarounds._blocked), or none."""
    sc = load_scenario(LOTS / "culdesac.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    collider, body = turnarounds.turnaround_collider(lot)
    rng = np.random.default_rng(7)
    aisle = next(a for a in lot.aisles.values() if not a.one_way and len(a.lanes) == 2)
    lane, back = aisle.lanes
    frame = np.array(back.segments[0].start)
    length = back.segments[0].length
    # poses across the lane's end, turned part of the way round: some closing_moves clear, some
    # through a slot or the boundary, some poses with none clear
    x = rng.uniform(length - 25.0, length, 300)
    y = rng.uniform(0.0, 9.0, 300)
    th = rng.uniform(math.pi, 2 * math.pi, 300)
    options = [closing_moves(q, length, lot.design.min_radius) for q in np.column_stack([x, y, th])]
    each = [next((k for k, path in enumerate(paths)
                  if not turnarounds._blocked(frame, path, collider, body)), None)
            for paths in options]
    assert turnarounds._first_clear(frame, options, collider, body) == each
    assert {0, None} <= set(each) and any(k not in (0, None) for k in each)


def test_turnarounds_planned_ahead_make_the_same_graph_and_are_used(monkeypatch):
    """prepare plans every two-way lane's turnaround ahead, in CPU time nothing else wants
    (turnarounds.plan_turnarounds_ahead, handed to the memo): a graph built with those
    plans is the one built without, and the build plans none itself when they are all in."""
    sc = load_scenario(LOTS / "culdesac.yaml")

    def built(ahead: bool):
        lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
        if not ahead:
            return assemble.build_graph(lot, vehicles=sc.vehicle_types)
        memo = RoadmapMemo(lot)
        with turnarounds.plan_turnarounds_ahead(memo, sc.vehicle_types) as bg:
            keys, *_ = memo.ahead
            bg._proc.join(60)
            assert len(bg.take()) == len(keys) > 0
            with monkeypatch.context() as m:  # (the background process has its own copy)
                m.setattr(turnarounds, "plan_turnarounds", lambda *a: 1 / 0)
                return assemble.build_graph(lot, vehicles=sc.vehicle_types, memo=memo)

    def edges(lg):
        return sorted((u, v, d["kind"], d.get("types"), d["path"])
                      for u, v, d in lg.graph.edges(data=True) if d["kind"] == "turnaround")

    plain, ahead = built(False), built(True)
    assert edges(plain) and edges(ahead) == edges(plain)
    assert ahead.skipped_turns == plain.skipped_turns


@pytest.mark.slow
@pytest.mark.parametrize("cores", [None, 1])
def test_roadmap_pieces_remembered_from_an_earlier_lot_are_taken_only_where_unchanged(
        cores, monkeypatch):
    """Pieces of a lot's roadmap (junction turns out of each lane, the dead ends' plans and
    multi-point searches) kept with what each read: the same lot again takes every one of
    them; the lot with one bay fewer at the end of a row takes those whose checks never
    reached it and works out the rest; each graph is the one built without the store. On
    every core, or on one (as in a worker of the bench: each piece counted once)."""
    import yaml

    import lotsim.core.workers

    if cores is not None:
        monkeypatch.setattr(lotsim.core.workers, "_default_workers", lambda: cores)

    from conftest import scenario_from_text

    doc = yaml.safe_load((LOTS / "ladder.yaml").read_text(encoding="utf-8"))

    def graph(document, known):
        sc = scenario_from_text(yaml.safe_dump(document))
        lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
        memo = RoadmapMemo(lot, known)
        lg = assemble.lane_graph(lot, vehicles=sc.vehicle_types, memo=memo)
        edges = sorted((u, v, d["kind"], d.get("types"), d["path"])
                       for u, v, d in lg.graph.edges(data=True))
        return edges, memo

    known: dict = {}
    cold, first = graph(doc, known)
    assert first.worked > 0 and first.recalled == 0
    assert sum(len(versions) for versions in known.values()) == first.worked  # each once
    again, second = graph(doc, known)
    assert again == cold and second.worked == 0 and second.recalled == first.worked
    row = doc["lot"]["rows"][0]
    row["count"] -= 1  # a bay fewer at the row's far end
    plain, _ = graph(doc, None)
    edited, third = graph(doc, known)
    assert edited == plain
    assert third.recalled > 0 and third.worked > 0


@pytest.mark.slow
@pytest.mark.parametrize("lot_name", ["large_lot", "lots/gate_spur"])
def test_junctions_alike_share_a_search_through_their_area_and_find_what_each_finds(
        lot_name, monkeypatch):
    """The turns through a junction's area are searched once per shape of candidates
    and obstacles about them: the junction turns are those found with every junction
    searched on its own, in fewer searches (the large lot's junctions are mostly alike;
    the gate spur's, irregular, some)."""
    from lotsim.roadmap import junctions

    sc = load_scenario(ROOT / "scenarios" / f"{lot_name}.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    collider = lane_collider(lot)
    searches = []
    real_search = junctions.area_turns

    def counted(*args, **kwargs):
        searches.append(args[1:3])
        return real_search(*args, **kwargs)

    monkeypatch.setattr(junctions, "area_turns", counted)
    shared = junction_turns(lot, collider)
    alike = len(searches)
    searches.clear()
    each = iter(range(10**6))  # every junction a shape of its own
    monkeypatch.setattr(junctions, "candidates_shape",
                        lambda *a, **kw: next(each).to_bytes(4, "big"))
    assert junction_turns(lot, collider) == shared
    assert alike < len(searches)
    if lot_name == "large_lot":
        assert len(searches) > 10 * alike


def test_obstacles_seen_from_a_place_are_digested_where_they_lie_about_it():
    """:meth:`Collider.local_digest`: a lot moved and turned holds the same about the
    same place; an obstacle moved inside the box is seen, one outside it is not."""
    import shapely

    from lotsim.lot.clearance import Collider

    def collider(shift, turn, extra):
        def place(g):
            return shapely.affinity.translate(shapely.affinity.rotate(
                g, turn, origin=(0, 0), use_radians=True), *shift)
        obstacles = [("a", shapely.box(2, 1, 4, 3)), ("b", shapely.box(-5, -1, -3, 0)),
                     ("far", shapely.box(*extra))]
        return Collider([(k, place(g)) for k, g in obstacles],
                        place(shapely.box(-20, -20, 20, 20)))

    def frame(shift, turn, x, y, heading):
        c, s = math.cos(turn), math.sin(turn)
        return (shift[0] + c * x - s * y, shift[1] + s * x + c * y, heading + turn)

    box = (-6.0, -2.0, 6.0, 4.0)
    here = collider((0, 0), 0.0, (30, 30, 31, 31)).local_digest((0.5, 0.5, 0.2), box)
    moved = collider((123.4, -56.7), 1.1, (30, 30, 31, 31))
    assert moved.local_digest(frame((123.4, -56.7), 1.1, 0.5, 0.5, 0.2), box) == here
    outside = collider((0, 0), 0.0, (8.5, 8.5, 9.0, 9.0))  # beyond the box, turned 0.2 rad
    assert outside.local_digest((0.5, 0.5, 0.2), box) == here
    inside = collider((0, 0), 0.0, (0.0, 3.0, 0.5, 3.5))
    assert inside.local_digest((0.5, 0.5, 0.2), box) != here
    assert collider((0, 0), 0.0, (30, 30, 31, 31)).local_digest((0.5, 0.5, 0.2),
                                                                (-6.0, -2.0, 6.0, 2.0)) != here


@pytest.mark.slow
def test_a_round_that_would_leave_a_core_idle_makes_the_next_search_it_may_want(monkeypatch):
    # a dead end whose cars arrive past where its first turnaround begins wants a second
    # search, from there: on two cores it is made with the first, in one round, and the
    # turnarounds found are those found a round each on one core
    import lotsim.core.workers
    from lotsim.roadmap import remembered

    sc = load_scenario(LOTS / "ladder.yaml")
    jobs, rounds = {}, []
    real_reaching_all, real_worked_out = turnarounds._reaching_all, turnarounds.worked_out
    monkeypatch.setattr(turnarounds, "_reaching_all", lambda todo, memo, *rest, **tuned: (
        jobs.update(todo), real_reaching_all(todo, memo, *rest, **tuned))[1])
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    assemble.lane_graph(lot, vehicles=sc.vehicle_types)  # (where parking may begin)
    monkeypatch.setattr(remembered, "fork_map", lambda fn, items, **kw: [fn(x) for x in items])
    monkeypatch.setattr(turnarounds, "worked_out", lambda memo, keys, *rest: (
        rounds.append(len(keys)), real_worked_out(memo, keys, *rest))[1])
    twice = 0
    for job in jobs.values():
        found = {}
        for cores in (1, 2):
            monkeypatch.setattr(lotsim.core.workers, "_default_workers", lambda c=cores: c)
            rounds.clear()
            found[cores] = real_reaching_all({0: job}, {})
            if cores == 1:
                alone = list(rounds)
        assert found[2] == found[1]
        if alone == [1, 1]:  # the second search waited for the first
            twice += 1
            assert rounds == [2]
    assert twice
