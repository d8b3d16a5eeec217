"""The lot graph is drivable: curvature, continuity, directions, limits, clearance, reach."""

import math

import numpy as np
import pytest
import shapely
from small_lots import DISCONNECTED

from conftest import (
    ONE_AISLE,
    ROOT,
    SCENARIOS,
    SHIPPED,
    graph_from_text,
    position,
    scenario_from_text,
    shipped,
)
from lotsim.core.geometry import wrap_angle
from lotsim.errors import ScenarioError
from lotsim.sim.preparation import prepare_graph
from lotsim.vehicles import KMH


def driven_edges(lg):
    return [(u, v, d) for u, v, d in lg.graph.edges(data=True) if d["path"] is not None]


def path_poses(path, step):
    return np.concatenate([s.sample(step) for s in path])


def driven_length(path, step: float = 0.05) -> float:
    """How far a car drives along ``path`` [m]: the chords between its poses ``step``
    apart, piece by piece (a cusp turns back without a chord across it)."""
    return float(sum(np.hypot(*np.diff(s.sample(step)[:, :2], axis=0).T).sum() for s in path))


@pytest.mark.parametrize("name", SHIPPED)
def test_every_edge_starts_and_ends_at_its_nodes_poses(shipped_graphs, name):
    lg = shipped_graphs[name]
    g = lg.graph
    for u, v, d in driven_edges(lg):
        path = d["path"]
        for pose, node in ((path[0].start, u), (path[-1].end, v)):
            ref = g.nodes[node]["pose"]
            assert math.dist(pose[:2], ref[:2]) < 1e-6, (name, u, v)
            assert abs(wrap_angle(pose[2] - ref[2])) < 1e-6, (name, u, v)
        # its length is the distance driven along it, measured on its poses 5 cm apart
        assert d["length"] == pytest.approx(driven_length(path), rel=1e-4, abs=1e-3)
        if d["kind"] == "lane":  # and a lane edge's, the stretch of lane between
            gap = g.nodes[v]["station"] - g.nodes[u]["station"]
            assert d["length"] == pytest.approx(gap, abs=1e-6), (name, u, v)
        if d["kind"] == "turnaround":  # strokes: the car stops (and steers) at each cusp
            for a, b in zip(path[:-1], path[1:], strict=True):
                assert np.allclose(a.end[:2], b.start[:2], atol=1e-9)
            continue
        # and the curvature is the nodes' at both ends, continuous in between
        assert path[0].curvature == pytest.approx(g.nodes[u]["curvature"], abs=1e-9)
        assert path[-1].end_curvature == pytest.approx(g.nodes[v]["curvature"], abs=1e-9)
        for a, b in zip(path[:-1], path[1:], strict=True):
            assert np.allclose(a.end[:2], b.start[:2], atol=1e-9)
            assert abs(wrap_angle(a.end[2] - b.start[2])) < 1e-9
            assert b.curvature == pytest.approx(a.end_curvature, abs=1e-9)


@pytest.mark.parametrize("name", SHIPPED)
def test_heading_is_continuous_through_every_lane_node(shipped_graphs, name):
    lg = shipped_graphs[name]
    g = lg.graph
    for n, data in g.nodes(data=True):
        if data["kind"] != "lane":
            continue
        ins = [d["path"][-1].end[2] for _, _, d in g.in_edges(n, data=True) if d["path"]]
        outs = [d["path"][0].start[2] for _, _, d in g.out_edges(n, data=True)
                if d["path"]]
        for a in ins:
            for b in outs:
                assert abs(wrap_angle(a - b)) < 1e-6


@pytest.mark.parametrize("name", SHIPPED)
def test_curvature_never_exceeds_the_limit_of_the_vehicles_that_drive_it(shipped_graphs, name):
    from lotsim.io.scenario_yaml import load_scenario

    path = ROOT / "scenarios" / f"{name}.yaml"
    lg = shipped_graphs[path.stem]
    radius = {v.name: v.min_turning_radius for v in load_scenario(path).vehicle_types}
    for _, _, d in driven_edges(lg):
        # an edge built for some types only (a small car's turnaround) is theirs
        limit = 1 / (min(radius[t] for t in d["types"]) if d.get("types")
                     else lg.lot.design.min_radius)
        assert all(seg.max_curvature <= limit + 1e-9 for seg in d["path"])
        if d["kind"] != "turnaround":
            assert d["gear"] == 1  # lanes and turns are driven forward


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_lots_reach_every_free_slot_and_exit(shipped_graphs, name):
    lg = shipped_graphs[name]
    reach = lg.reachability()
    assert reach.ok, (name, reach)
    assert lg.entrances and lg.exits


@pytest.mark.parametrize("name", SHIPPED)
def test_every_slot_is_linked_through_real_maneuvers_that_start_at_their_lane_node(
        shipped_graphs, name):
    lg = shipped_graphs[name]
    g = lg.graph
    for slot in lg.lot.slots:
        node = lg.slot_nodes[slot.id]
        parks = list(g.in_edges(node, data=True))
        assert parks, (name, slot.id)
        ends = {}  # type → where the maneuvers a car can leave by park it
        for _, _, d in parks:
            for v, m in d["maneuvers"].items():
                ends.setdefault(v, []).append(m.end)
        for u, _, d in parks:
            assert d["kind"] == "park" and not d["placeholder"]
            assert d["maneuvers"] or d["park_only"]
            pose = g.nodes[u]["pose"]
            ms = [*d["maneuvers"].values(), *d.get("park_only", {}).values()]
            for m in ms:
                assert math.dist(m.start[:2], pose[:2]) < 1e-6, (name, slot.id)
                assert abs(wrap_angle(m.start[2] - pose[2])) < 1e-6, (name, slot.id)
            assert d["length"] == pytest.approx(min(m.length for m in ms))
            if d["maneuvers"]:
                leave = g.edges[node, u]
                assert (leave["kind"] == "leave"
                        and set(leave["maneuvers"]) == set(d["maneuvers"]))
            else:  # a maneuver for cars that stay only is never left by
                assert not g.has_edge(node, u) or not g.edges[node, u]["maneuvers"]
            for v, m in d.get("park_only", {}).items():
                # the lane's own best parks the other way round than the shared pose
                assert all(abs(abs(wrap_angle(m.end[2] - e[2])) - math.pi) < 0.1
                           for e in ends[v]), (name, slot.id, v)


def test_without_maneuvers_slots_hang_off_marked_placeholders():
    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.sim.preparation import prepare_graph

    path = next(p for p in SCENARIOS if p.stem == "quickstart")
    lg = prepare_graph(load_scenario(path), maneuvers=False)
    for slot in lg.lot.slots:
        parks = [d for _, _, d in lg.graph.in_edges(lg.slot_nodes[slot.id], data=True)]
        assert parks and all(d["kind"] == "park" and d["placeholder"] for d in parks)


# (the large lot's lanes and turns are the other lots' over again)
@pytest.mark.parametrize("name", shipped("large_lot"))
def test_lane_and_turn_sweeps_touch_no_slot_or_area(shipped_graphs, name):
    """Independent of the builder's checker: real vehicle footprints every 5 cm, via shapely."""
    from lotsim.io.scenario_yaml import load_scenario

    path = ROOT / "scenarios" / f"{name}.yaml"
    lg = shipped_graphs[name]
    lot = lg.lot
    blockers = [s.shape for s in lot.slots] + [a.polygon for a in lot.areas]
    tree = shapely.STRtree(blockers)
    for vehicle in load_scenario(path).vehicle_types:
        for _, _, d in driven_edges(lg):
            if d.get("types") and vehicle.name not in d["types"]:
                continue  # built for other types only: this one never drives it
            polys = shapely.polygons(vehicle.footprints(path_poses(d["path"], 0.05)))
            left, right = tree.query(polys, predicate="intersects")
            if left.size:
                area = shapely.area(shapely.intersection(polys[left],
                                                         np.array(blockers)[right]))
                assert area.max() < 1e-6


def test_one_way_aisles_carry_one_direction_and_two_way_both(shipped_graphs):
    lot = shipped_graphs["mixed_lot"].lot
    for aisle in lot.aisles.values():
        heading = math.atan2(*(aisle.centerline[-1] - aisle.centerline[0])[::-1])
        dirs = sorted(round(math.cos(wrap_angle(lane.segments[0].start[2] - heading)))
                      for lane in aisle.lanes)
        assert dirs == ([1] if aisle.one_way else [-1, 1])


def test_speed_bump_lowers_the_limit_within_5_m(shipped_graphs):
    lg = shipped_graphs["mixed_lot"]
    bump = shapely.LineString([(40, 26.5), (40, 33.5)])
    slow = fast = 0
    for _, _, d in driven_edges(lg):
        line = shapely.LineString(path_poses(d["path"], 0.25)[:, :2])
        gap = line.distance(bump)
        if gap > 5.0 + 1e-6:
            assert d["speed_limit"] == pytest.approx(20 * KMH)
            fast += 1
        elif shapely.Point(line.interpolate(0.5, normalized=True)).distance(bump) < 5.0 - 1e-6:
            assert d["speed_limit"] == pytest.approx(10 * KMH)
            slow += 1
    assert slow >= 2 and fast > slow


def test_unreachable_slots_are_reported_not_dropped():
    import lotsim

    lg = graph_from_text(DISCONNECTED)
    reach = lg.reachability()
    assert not reach.ok
    assert reach.unreachable["in"] == ["B1", "B2", "B3"]
    # A slots can be entered but not left for the exit; B slots could be left for it (a
    # maneuver out of them ends on aisle b, which leads there), but no car gets to them
    assert reach.stranded["out"] == ["A1", "A2", "A3"]
    assert len(lg.lot.slots) == 6
    assert (reach.no_way_in, reach.no_way_out) == (["B1", "B2", "B3"], ["A1", "A2", "A3"])
    report = lotsim.validate(DISCONNECTED)
    out = report.summary()
    assert "3 free slots cannot be reached from any entrance: B1, B2, B3" in out
    assert "from 3 free slots no exit can be reached: A1, A2, A3" in out
    assert not report.complete  # what --strict refuses


def test_junction_turns_join_aisles_with_feasible_arcs():
    lg = graph_from_text("""
        lot:
          boundary: [[0, 0], [60, 0], [60, 60], [0, 60]]
          aisles:
            - {id: a, centerline: [[0, 10], [60, 10]], width: 7.0}
            - {id: b, centerline: [[30, 10], [30, 60]], width: 7.0}
          rows:
            - {aisle: b, side: left, kind: perpendicular, count: 4, slot_width: 2.5,
               slot_length: 5.0, start: 20, id_prefix: B}
          entrances:
            - {id: in, x: 2, y: 8.25, heading_deg: 0}
          exits:
            - {id: out, x: 5, y: 11.75, heading_deg: 180}
        """)
    turns = [d for _, _, d in lg.graph.edges(data=True) if d["kind"] == "turn"]
    # a T: from both lanes of a into b's up lane, and from b's down lane into both of a's
    assert len(turns) == 8  # the fastest clear turn and the tightest, for each pair
    for d in turns:
        path = d["path"]
        assert min(seg.radius for seg in path) >= lg.lot.design.min_radius - 1e-9
        assert abs(path[-1].end[2] - path[0].start[2]) == pytest.approx(math.pi / 2)
        # clothoid in, arc, clothoid out: the wheels turn while the car rolls
        assert path[0].sharpness != 0 and path[-1].sharpness != 0
        assert path[0].curvature == 0 and abs(path[-1].end_curvature) < 1e-12
    # b is a dead end: cars reach its slots up its right lane and turn round at its end (a
    # multi-point turn onto its down lane) to leave; so does a's east end. At the T a car
    # can also turn back, on a either way in b's mouth, and on b coming down in a's
    g = lg.graph
    turnarounds: dict[tuple[str, str], list] = {}
    for u, v, d in g.edges(data=True):
        if d["kind"] == "turnaround":
            turnarounds.setdefault((g.nodes[u]["lane"], g.nodes[v]["lane"]), []).append(d["path"])
    assert {pair: len(paths) for pair, paths in turnarounds.items()} == {
        ("b>", "b<"): 1, ("a>", "a<"): 2, ("a<", "a>"): 1, ("b<", "b>"): 1}
    t_uturns = [*turnarounds["a<", "a>"], *turnarounds["b<", "b>"],
                *(p for p in turnarounds["a>", "a<"] if p[0].start[0] < 40)]
    for p in t_uturns:  # each begins at most 6 m before the crossing and ends near it
        x, y = p[0].start[:2]
        ex, ey = p[-1].end[:2]
        assert math.hypot(x - 30, y - 10) <= 3.5 + 6 + 1e-6
        assert math.hypot(ex - 30, ey - 10) <= 3.5 + 8 + 1e-6
    path = turnarounds["b>", "b<"][0]
    assert {seg.gear for seg in path} == {1, -1}  # forward and back
    assert abs(wrap_angle(path[-1].end[2] - path[0].start[2])) == pytest.approx(math.pi)
    reach = lg.reachability()
    assert reach.unreachable["in"] == [] and reach.stranded["out"] == []


@pytest.mark.slow
def test_a_car_reaches_the_exit_of_a_short_spur_at_driving_speed_not_a_crawl():
    """A gate spur 12 m long meets an aisle at a T, its exit 4.5 m in from the boundary.
    The fastest turns into the spur's outbound lane end past the exit (they need a long
    tangent), the tightest is designed for 1.5 km/h; the fastest turn that ends before the
    exit is built too: a car coming along the aisle's far lane turns out at 10 km/h or
    more, one on the near lane (a right turn, with 5.75 m from the lanes' crossing to the
    exit) at 3 km/h, not at a crawl."""
    from lotsim.vehicles.catalogue import CATALOGUE
    from lotsim.vehicles.motion import speed_cap

    lg = graph_from_text("""
        lot:
          boundary: [[0, 0], [80, 0], [80, 40], [0, 40]]
          aisles:
            - {id: spur, centerline: [[40.5, 0], [40.5, 12.0]], width: 7.0}
            - {id: a, centerline: [[3.5, 12.0], [79, 12.0]], width: 7.0}
          rows:
            - {aisle: a, side: left, kind: perpendicular, count: 20, slot_width: 2.6,
               slot_length: 5.4, start: 14, id_prefix: N}
          entrances:
            - {id: in, x: 42.25, y: 1.5, heading_deg: 90}
          exits:
            - {id: out, x: 38.75, y: 4.5, heading_deg: -90}
        """)
    g = lg.graph
    car = CATALOGUE["valet"]
    out_lane = g.nodes[lg.exits["out"]]["lane"]
    fastest: dict[str, float] = {}  # by the lane the turn comes from
    for u, v, d in g.edges(data=True):
        if d["kind"] == "turn" and g.nodes[v]["lane"] == out_lane \
                and g.nodes[v]["pose"][1] >= 4.5 - 1e-6:  # it ends before the exit
            cap = min(speed_cap(seg, car) for seg in d["path"])
            lane = g.nodes[u]["lane"]
            fastest[lane] = max(fastest.get(lane, 0.0), cap)
    assert fastest["a<"] >= 10 * KMH - 1e-9
    assert fastest["a>"] >= 3 * KMH - 1e-9
    assert lg.reachability().stranded["out"] == []


def test_a_portal_heading_off_its_lane_is_refused_not_turned_without_a_word():
    # 45° on a lane running at 0° was snapped to 0° silently; a few degrees are fine
    for heading, ok in ((45, False), (-30, False), (10, True)):
        text = ONE_AISLE.replace("{id: in, x: 3.0, y: 11.0, heading_deg: 0}",
                                 f"{{id: in, x: 3.0, y: 11.0, heading_deg: {heading}}}")
        sc = scenario_from_text(text)
        if ok:
            assert prepare_graph(sc, maneuvers=False).entrances["in"] is not None
            continue
        with pytest.raises(ScenarioError) as err:
            prepare_graph(sc, maneuvers=False)
        assert (err.value.where.line, err.value.where.col) == position(text, "|{id: in")
        assert "lane 'a>' there heads 0°" in err.value.message


def test_a_portal_heading_the_other_lanes_way_is_told_the_heading_not_the_boundary():
    """Heading 180° on the eastbound lane of a two-way aisle is a heading off its lane, not
    a car for the westbound lane 3.5 m away."""
    text = (ONE_AISLE.replace("direction: one-way", "direction: two-way")
            .replace("{id: in, x: 3.0, y: 11.0, heading_deg: 0}",
                     "{id: in, x: 3.0, y: 9.25, heading_deg: 180}")
            .replace("{id: out, x: 44.0, y: 11.0,", "{id: out, x: 44.0, y: 9.25,"))
    with pytest.raises(ScenarioError) as err:
        prepare_graph(scenario_from_text(text), maneuvers=False)
    assert (err.value.where.line, err.value.where.col) == position(text, "|{id: in")
    assert "stands on lane 'a>', which heads 0°" in err.value.message
    assert "boundary" not in err.value.message
