"""What a car can drive to (lotsim.roadmap.reach), against a breadth-first search of our own
over the graph's lanes: on the small crossing whole and with lanes and turns taken out at
random (a fixed seed), on two aisles that do not meet, with a turn only one type drives,
and on a graph of a few nodes built by hand whose maneuvers park on a pose that cannot be
left from."""

import random
from collections import deque
from types import SimpleNamespace

import networkx as nx
import pytest
from small_lots import CROSS, DISCONNECTED, lot_of

from lotsim.roadmap.assemble import build_graph
from lotsim.roadmap.model import LotGraph
from lotsim.roadmap.reach import find_reachability, lane_reach, reachable_ranges


def _search(links: dict, sources) -> set:
    """Every node reached from ``sources`` by ``links`` (node → next nodes), breadth first."""
    seen, todo = set(sources), deque(sources)
    while todo:
        for n in links.get(todo.popleft(), ()):
            if n not in seen:
                seen.add(n)
                todo.append(n)
    return seen


def _lanes(lg, vehicle=None) -> tuple[dict, dict]:
    """Successors and predecessors over the graph without its slot nodes (with ``vehicle``,
    leaving out the edges only other types drive)."""
    g = lg.graph
    ahead: dict = {}
    back: dict = {}
    for u, v, d in g.edges(data=True):
        if "slot" in (g.nodes[u]["kind"], g.nodes[v]["kind"]):
            continue
        types = d.get("types")
        if types is not None and vehicle is not None and vehicle not in types:
            continue
        ahead.setdefault(u, []).append(v)
        back.setdefault(v, []).append(u)
    return ahead, back


def _expected(lg) -> dict:
    """What a placeholder graph's reachability must say, searched here: a free bay is
    reached from a gate when a lane node linked into it is, left for an exit when a lane
    node it is linked out to reaches the exit, and a car parks to leave when it reaches
    a node linked in and the bay is linked out to a node that reaches an exit."""
    g = lg.graph
    ahead, back = _lanes(lg)
    free = [s.id for s in lg.lot.free_slots]
    into = {sid: list(g.predecessors(lg.slot_nodes[sid])) for sid in free}
    out = {sid: list(g.successors(lg.slot_nodes[sid])) for sid in free}
    come = _search(ahead, lg.entrances.values())
    lane_nodes = {n for n, d in g.nodes(data=True) if d["kind"] != "slot"}
    go = _search(back, lg.exits.values()) if lg.exits else lane_nodes
    no_in = [sid for sid in free if not set(into[sid]) & come]
    return {
        "unreachable": {e: [sid for sid in free if not set(into[sid]) & _search(ahead, [n])]
                        for e, n in lg.entrances.items()},
        "stranded": {x: [sid for sid in free if not set(out[sid]) & _search(back, [n])]
                     for x, n in lg.exits.items()},
        "no_way_in": no_in,
        "no_way_out": [sid for sid in free if sid not in no_in and not set(out[sid]) & go],
        "come": come, "go": go,
    }


def _agrees(lg) -> dict:
    want = _expected(lg)
    got = find_reachability(lg)
    assert got.unreachable == want["unreachable"]
    assert got.stranded == want["stranded"]
    assert (got.no_way_in, got.no_way_out) == (want["no_way_in"], want["no_way_out"])
    assert lane_reach(lg) == (want["come"], want["go"])
    return want


@pytest.fixture(scope="module")
def cross():
    return build_graph(lot_of(CROSS))


def test_on_the_whole_crossing_every_bay_is_reached_and_left(cross):
    want = _agrees(cross)
    assert not want["no_way_in"] and not want["no_way_out"]
    assert find_reachability(cross).ok
    # a maneuver may begin where a car can come: a> from the entrance on, the others
    # from where the first turn or turnaround lands on them
    g = cross.graph
    spans = {}
    for n in want["come"]:
        lane, s = g.nodes[n]["lane"], g.nodes[n]["station"]
        lo, hi = spans.get(lane, (s, s))
        spans[lane] = (min(lo, s), max(hi, s))
    assert reachable_ranges(cross) == spans
    assert spans["a>"] == (2.0, pytest.approx(60.0))


def test_two_aisles_that_never_meet_strand_the_bays_of_each():
    lg = build_graph(lot_of(DISCONNECTED))
    want = _agrees(lg)
    # by eye: the south bays are reached but cannot be left for the exit; the north ones
    # could be left for it, but no car gets to them
    assert want["unreachable"] == {"in": ["B1", "B2", "B3"]}
    assert want["stranded"] == {"out": ["A1", "A2", "A3"]}
    assert not find_reachability(lg).ok


def test_with_lanes_and_turns_cut_at_random_the_answers_match_a_breadth_first_search(cross):
    rng = random.Random(12)
    g = cross.graph
    driven = [(u, v) for u, v, d in g.edges(data=True) if d["kind"] not in ("park", "leave")]
    told = set()
    for _ in range(40):
        cut = nx.DiGraph(g)
        cut.remove_edges_from(rng.sample(driven, rng.randint(1, 6)))
        lg = LotGraph(cross.lot, cut, cross.entrances, cross.exits, cross.slot_nodes,
                      cross.attachments)
        want = _agrees(lg)
        told.add((bool(want["no_way_in"]), bool(want["no_way_out"])))
    # the cuts left bays unreached, bays reached but not left, and all well
    assert {(False, False), (True, False), (False, True)} <= told, told


def test_a_turn_only_one_type_drives_is_the_way_in_for_that_type_alone(cross):
    # every turn and turnaround onto b's up lane is for the small car only: the other
    # types cannot get onto that lane at all
    cut = nx.DiGraph(cross.graph)
    for u, v, d in cut.edges(data=True):
        if cut.nodes[v].get("lane") == "b>" != cut.nodes[u].get("lane"):
            d["types"] = frozenset({"zoe"})
    lg = LotGraph(cross.lot, cut, cross.entrances, cross.exits, cross.slot_nodes,
                  cross.attachments)
    for vehicle in ("zoe", "valet"):
        ahead, back = _lanes(lg, vehicle)
        want = (_search(ahead, lg.entrances.values()), _search(back, lg.exits.values()))
        assert lane_reach(lg, vehicle) == want
    zoe, valet = lane_reach(lg, "zoe")[0], lane_reach(lg, "valet")[0]
    up = {n for n in zoe if cut.nodes[n]["lane"] == "b>"}
    assert up and not up & valet


def _hand_built():
    """Lane nodes 0 → 1 → 2 → 3 (the entrance at 0, the exit at 3) and 4 → 5 apart from
    them; bay N1 parked from 1 and left to 2 on the same pose, N2 parked from 1 on a pose
    it is left from by no maneuver, N3 parked from 5 alone (a valet's maneuvers)."""
    lot = lot_of(CROSS)
    g = nx.DiGraph()
    for n in range(6):
        g.add_node(n, kind="lane", lane="x", station=float(n), pose=(float(n), 0.0, 0.0))
    for u, v in ((0, 1), (1, 2), (2, 3), (4, 5)):
        g.add_edge(u, v, kind="lane")
    slots = {"N1": 10, "N2": 11, "N3": 12}
    for sid, node in slots.items():
        g.add_node(node, kind="slot", slot=sid)

    def link(u, node, w, park_end, leave_start):
        g.add_edge(u, node, kind="park", maneuvers={"valet": SimpleNamespace(end=park_end)})
        g.add_edge(node, w, kind="leave",
                   maneuvers={"valet": SimpleNamespace(start=leave_start)})

    link(1, 10, 2, (1.0, 5.0, 1.57), (1.0, 5.0, 1.57))
    link(1, 11, 2, (2.0, 5.0, 1.57), (2.0, 5.0, -1.57))  # parks nose in, leaves nose out
    link(5, 12, 2, (3.0, 5.0, 1.57), (3.0, 5.0, 1.57))
    return LotGraph(lot, g, {"in": 0}, {"out": 3}, slots, {})


def test_a_bay_parked_on_a_pose_no_maneuver_leaves_from_cannot_be_left():
    lg = _hand_built()
    got = find_reachability(lg)
    assert got.unreachable == {"in": ["N3"]}
    assert got.stranded == {"out": []}  # every bay's leave edge ends on a way out
    assert (got.no_way_in, got.no_way_out) == (["N3"], ["N2"])
    assert got.by_type == {"valet": (["N3"], ["N2"])}
    assert lg.leavable() == {(1, 10), (5, 12)}
    assert not got.ok
