"""The assembler (lotsim.roadmap.assemble) on the small crossing, without maneuvers: lanes cut
into nodes on the lanes' lines worked out by hand, no more than the node spacing apart and
wherever a turn, turnaround or gate begins or ends; every driven edge begins at its first
node's pose and, driven step by step by the kinematic bicycle model, ends at its last's;
each bay hangs off the lane nodes abeam of it by placeholder links; the lanes' graph alone
is the same lanes numbered alike; an aisle that continues as another is joined to it."""

import numpy as np
import pytest
from small_lots import CROSS, CROSS_LANES, lot_of

from lotsim.lot.build import lane_collider
from lotsim.roadmap.assemble import build_graph, lane_graph
from lotsim.roadmap.junctions import junction_turns
from lotsim.roadmap.memo import RoadmapMemo
from oracles.driving import drive, heading_gap, on_line


@pytest.fixture(scope="module")
def cross():
    # the memo carries the turns and turnarounds from one build of the lot to the next
    lot = lot_of(CROSS)
    memo = RoadmapMemo(lot)
    return lot, build_graph(lot, memo=memo), memo


def _lane_nodes(g, lane: str) -> list[tuple[float, int]]:
    return sorted((d["station"], n) for n, d in g.nodes(data=True)
                  if d["kind"] == "lane" and d["lane"] == lane)


def _same_pose(a, b, tol: float = 1e-3) -> bool:
    return float(np.hypot(a[0] - b[0], a[1] - b[1])) <= tol and heading_gap(a[2], b[2]) <= tol


@pytest.mark.parametrize("spacing", [4.0, 2.5])
def test_each_lane_is_cut_into_nodes_on_its_line_no_more_than_the_spacing_apart(
        spacing, cross):
    lot, lg, memo = cross
    g = (lg if spacing == 4.0 else build_graph(lot, node_spacing=spacing, memo=memo)).graph
    for lane, line in CROSS_LANES.items():
        nodes = _lane_nodes(g, lane)
        stations = [s for s, _ in nodes]
        assert stations[0] == 0.0 and stations[-1] == pytest.approx(60.0)
        assert max(np.diff(stations)) <= spacing + 1e-9
        for s, n in nodes:
            assert on_line(g.nodes[n]["pose"], line) == pytest.approx(s, abs=1e-6)
            assert g.nodes[n]["curvature"] == 0.0
        # consecutive nodes joined by a lane edge as long as the stretch between them
        for (s0, u), (s1, v) in zip(nodes, nodes[1:], strict=False):
            d = g.edges[u, v]
            assert d["kind"] == "lane" and d["length"] == pytest.approx(s1 - s0)
            assert not g.has_edge(v, u)  # lanes run one way


def test_every_driven_edge_runs_from_its_first_nodes_pose_to_its_last(cross):
    _, lg, _ = cross
    g = lg.graph
    driven = [(u, v, d) for u, v, d in g.edges(data=True) if d["path"] is not None]
    assert {d["kind"] for _, _, d in driven} == {"lane", "turn", "turnaround"}
    for u, v, d in driven:
        start = g.nodes[u]["pose"]
        assert _same_pose(d["path"][0].start, start), (u, v, d["kind"])
        at, _, _ = drive(d["path"], start)
        assert _same_pose(at[-1], g.nodes[v]["pose"]), (u, v, d["kind"])
        assert d["length"] == pytest.approx(sum(abs(s.distance) for s in d["path"]))


def test_every_junction_turn_is_an_edge_between_the_nodes_where_it_begins_and_lands(cross):
    lot, lg, _ = cross
    g = lg.graph
    turns, _ = junction_turns(lot, lane_collider(lot))
    at = {(d["lane"], round(d["station"], 6)): n for n, d in g.nodes(data=True)
          if d["kind"] == "lane"}
    ends = {(at[t.lane_a, round(t.station_a, 6)], at[t.lane_b, round(t.station_b, 6)])
            for t in turns}
    assert ends == {(u, v) for u, v, d in g.edges(data=True) if d["kind"] == "turn"}


def test_the_gates_stand_on_their_nodes(cross):
    _, lg, _ = cross
    g = lg.graph
    assert _same_pose(g.nodes[lg.entrances["in"]]["pose"], (2.0, 28.25, 0.0))
    assert _same_pose(g.nodes[lg.exits["out"]]["pose"], (6.0, 31.75, np.pi))
    assert g.nodes[lg.entrances["in"]]["entrance"] == "in"
    assert g.nodes[lg.exits["out"]]["exit"] == "out"


def test_each_bay_hangs_off_the_lane_nodes_abeam_of_it_by_placeholder_links(cross):
    lot, lg, _ = cross
    g = lg.graph
    assert set(lg.slot_nodes) == {"N1", "N2", "N3"}
    for sid, node in lg.slot_nodes.items():
        slot = lot.slot_by_id[sid]
        assert g.nodes[node]["kind"] == "slot"
        assert np.allclose(g.nodes[node]["pose"][:2], slot.center)
        parks = [u for u in g.predecessors(node)]
        leaves = [w for w in g.successors(node)]
        assert sorted(parks) == sorted(leaves) == sorted(lg.attachments[sid])
        assert parks
        for u in parks:
            assert g.edges[u, node]["kind"] == "park" and g.edges[u, node]["placeholder"]
            assert g.edges[node, u]["kind"] == "leave" and g.edges[node, u]["placeholder"]
            # on the aisle the bay opens onto, abeam of the bay's middle
            assert g.nodes[u]["lane"] in ("a>", "a<")
            assert g.nodes[u]["pose"][0] == pytest.approx(slot.center[0], abs=1e-6)


def test_the_lanes_graph_is_the_same_lanes_numbered_alike_without_the_bays(cross):
    lot, lg, memo = cross
    lanes = lane_graph(lot, memo=memo).graph
    g = lg.graph
    assert not any(d["kind"] == "slot" for _, d in lanes.nodes(data=True))
    assert all(d["kind"] in ("lane", "turn", "turnaround") for _, _, d in lanes.edges(data=True))
    ours = [n for n, d in g.nodes(data=True) if d["kind"] == "lane"]
    assert sorted(lanes.nodes) == sorted(ours)
    for n in ours:
        assert lanes.nodes[n]["pose"] == g.nodes[n]["pose"]
    assert set(lanes.edges) == {(u, v) for u, v, d in g.edges(data=True)
                                if d["kind"] not in ("park", "leave")}


def test_an_aisle_that_continues_as_another_is_joined_to_it():
    # aisle a ends where aisle c begins, heading the same way: a car drives from one to the
    # other by a join (of no length), each way
    text = (CROSS.replace("    - {id: b, centerline: [[30, 0], [30, 60]], width: 7.0}\n",
                          "    - {id: c, centerline: [[30, 30], [60, 30]], width: 7.0}\n")
            .replace("[[0, 30], [60, 30]]", "[[0, 30], [30, 30]]")
            .replace("aisle: a, side: left", "aisle: c, side: left")
            .replace("start: 33.5", "start: 3.5"))
    g = build_graph(lot_of(text)).graph
    joins = [(u, v) for u, v, d in g.edges(data=True) if d["kind"] == "join"]
    assert sorted((g.nodes[u]["lane"], g.nodes[v]["lane"]) for u, v in joins) == [
        ("a>", "c>"), ("c<", "a<")]
    for u, v in joins:
        assert _same_pose(g.nodes[u]["pose"], g.nodes[v]["pose"])
        assert g.edges[u, v]["length"] == 0.0


def test_parking_links_are_recorded_as_they_come_and_their_maneuvers_never_driven():
    """The roadmap reads a link's numbers and only keeps its maneuvers: here bare objects,
    which any use would break. A link with a way out gives a park edge and a leave edge from
    the lane node at its station; a park-only link a park edge's ``park_only``; a bay with
    no link no edge."""
    from lotsim.roadmap.model import ParkingLink

    lot = lot_of(CROSS)
    park, leave, only = object(), object(), object()
    links = [ParkingLink("valet", "N1", "a<", 22.0, 4.0, park, -1, 9.5, 12.0,
                         leave, 1, 9.25, 10.0),
             ParkingLink("valet", "N2", "a<", 18.0, 3.0, only, 1, 8.0, 9.0)]
    lg = build_graph(lot, links=links)
    g = lg.graph
    at = {(d["lane"], round(d["station"], 9)): n for n, d in g.nodes(data=True)
          if d["kind"] == "lane"}
    a, b = at["a<", 22.0], at["a<", 18.0]
    assert _same_pose(g.nodes[a]["pose"], (60.0 - 22.0, 31.75, np.pi), 1e-9)
    n1, n2, n3 = (lg.slot_nodes[s] for s in ("N1", "N2", "N3"))
    into, out = g.edges[a, n1], g.edges[n1, a]
    assert (into["kind"], into["maneuvers"], into["duration"], into["gear"], into["length"],
            into["speed_limit"]) == ("park", {"valet": park}, {"valet": 12.0}, -1, 9.5, 4.0)
    assert (out["kind"], out["maneuvers"], out["duration"], out["gear"], out["length"]) == (
        "leave", {"valet": leave}, {"valet": 10.0}, 1, 9.25)
    only_edge = g.edges[b, n2]
    assert (only_edge["park_only"], only_edge["park_only_duration"],
            only_edge["park_only_limit"], only_edge["maneuvers"]) == (
        {"valet": only}, {"valet": 9.0}, 3.0, {})
    assert not g.has_edge(n2, b)  # a car that will not leave has no way out
    assert g.degree(n3) == 0
    assert a in lg.attachments["N1"]
