"""Walks over the paved ground (lotsim.lot.walks), against oracles of their own: a length
worked out by hand round a row of bays, shapely for where the path goes, the straight line
where nothing is in the way, the triangle inequality, and a dense sampled grid's Dijkstra
(a path on it is a walk too, so never shorter, and within a few per cent)."""

from __future__ import annotations

import math

import networkx as nx
import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Point, box

from lotsim import api
from lotsim.lot.walks import shortest_walk, walk_start, walking_ground

BEHIND_A_ROW = """\
name: behind_a_row
seed: 1
vehicle_types:
  - valet
  - {name: blue_badge, width: 1.8, front: 3.7, rear: 1.0, wheelbase: 2.7, max_steer_deg: 33,
     accessible: true}
lot:
  boundary: [[0, 0], [40, 0], [40, 30], [0, 30]]
  aisles:
    - {id: A, centerline: [[0, 10], [40, 10]], width: 7.0}
  rows:
    # the row between the accessible bay and the door: bays x 10..30, y 13.5..18.5
    - {aisle: A, side: left, kind: perpendicular, count: 8, slot_width: 2.5, slot_length: 5.0,
       start: 10.0, id_prefix: N}
    # the accessible bay x 20..22.5, y 1.5..6.5, its access aisle east of it
    - {aisle: A, side: right, kind: perpendicular, count: 1, slot_width: 2.5, slot_length: 5.0,
       start: 20.0, id_prefix: H, use: accessible}
  building_entrances:
    - {id: door, x: 20.0, y: 25.0}
  entrances:
    - {id: west, x: 2.0, y: 8.25, heading_deg: 0}
traffic:
  vehicles: [{id: ann, type: blue_badge, arrival: 0}]
"""


@pytest.fixture(scope="module")
def behind_a_row():
    report = api.validate(BEHIND_A_ROW)
    return report.prepared.lot, report.bays


def test_a_row_in_the_way_is_walked_round_its_nearer_end(behind_a_row):
    lot, bays = behind_a_row
    (w,) = bays.walks
    assert (w.slot, w.entrance) == ("H1", "door")
    # from the middle of the bay's side on its access aisle (x = 22.5), past the row's
    # east end (30, 13.5) to (30, 18.5), then to the door
    start = (22.5, 4.0)
    by_hand = math.dist(start, (30, 13.5)) + 5.0 + math.dist((30, 18.5), (20, 25))
    assert w.distance == pytest.approx(by_hand, abs=1e-3)
    assert w.straight == pytest.approx(math.dist(start, (20, 25)), abs=1e-9)
    assert w.distance > w.straight + 7
    assert tuple(w.path[0]) == start and tuple(w.path[-1]) == (20.0, 25.0)
    assert bays.as_dict()["walks"][0]["distance"] == round(by_hand, 2)


def test_the_path_crosses_no_bay_but_its_own_and_stays_on_the_ground(behind_a_row):
    lot, bays = behind_a_row
    for w in bays.walks:
        free = shapely.difference(lot.ground, shapely.union_all(
            [s.shape for s in lot.slots if s.id != w.slot] + [a.polygon for a in lot.areas]))
        for a, b in zip(w.path[:-1], w.path[1:], strict=True):
            seg = LineString([a, b])
            for s in lot.slots:
                if s.id != w.slot:
                    assert not seg.intersects(s.shape.buffer(-1e-3)), (w.slot, s.id)
            assert free.buffer(1e-5).covers(seg)


def test_with_nothing_in_the_way_the_walk_is_the_straight_line(behind_a_row):
    lot, _ = behind_a_row
    wg = walking_ground(lot.ground, [s.polygon for s in lot.slots])
    h1 = lot.slot_by_id["H1"]
    start = walk_start(h1, [a.polygon for a in lot.access_aisles])
    for door in [(35.0, 3.0), (39.0, 12.0), (5.0, 12.0)]:
        w = shortest_walk(wg, start, door, opened=h1.shape)
        assert w.length == pytest.approx(math.dist(start, door), abs=1e-9)
        assert len(w.points) == 2


def test_an_entrance_off_the_lot_is_reached_straight_from_its_nearest_point(behind_a_row):
    lot, _ = behind_a_row
    wg = walking_ground(lot.ground, [s.polygon for s in lot.slots])
    w = shortest_walk(wg, (35.0, 10.0), (35.0, 32.0))  # 2 m north of the boundary
    assert w.length == pytest.approx(22.0, abs=1e-6)
    assert tuple(w.points[-2]) == pytest.approx((35.0, 30.0))


def _blocks():
    """A small lot with two rows of bays and an island, the rows' ends not aligned."""
    ground = box(0, 0, 30, 24)
    bays = ([box(4 + 2.5 * k, 6, 6.5 + 2.5 * k, 11) for k in range(6)]
            + [box(9 + 2.5 * k, 15, 11.5 + 2.5 * k, 20) for k in range(6)])
    island = shapely.Polygon([(22, 3), (26, 5), (24, 9)])
    return ground, bays, [island]


def test_the_walk_obeys_the_triangle_inequality_and_is_never_shorter_than_straight():
    ground, bays, islands = _blocks()
    wg = walking_ground(ground, bays, islands)
    rng = np.random.default_rng(7)
    points = []
    while len(points) < 12:
        p = rng.uniform((0, 0), (30, 24))
        if wg.region.buffer(-0.01).contains(Point(p)):
            points.append((float(p[0]), float(p[1])))
    for a, b, c in zip(points[0::3], points[1::3], points[2::3], strict=True):
        ab, bc, ac = (shortest_walk(wg, a, b).length, shortest_walk(wg, b, c).length,
                      shortest_walk(wg, a, c).length)
        assert ac <= ab + bc + 1e-9
        assert ac >= math.dist(a, c) - 1e-9
        assert shortest_walk(wg, c, a).length == pytest.approx(ac, abs=1e-6)


def _grid_walk(region, start, goal, step: float) -> float:
    """Dijkstra over a dense grid of points of ``region``, each joined to those a king's or
    a knight's move away (16 directions) where the segment lies on ``region``; the start
    and goal joined to the grid points within two steps that they see."""
    x0, y0, x1, y1 = region.bounds
    xs, ys = np.meshgrid(np.arange(x0, x1 + 1e-9, step), np.arange(y0, y1 + 1e-9, step))
    pts = np.stack([xs.ravel(), ys.ravel()], axis=1)
    pts = pts[shapely.covered_by(shapely.points(pts), region)]
    pts = np.concatenate([pts, [start, goal]])
    index = {(round(x / step), round(y / step)): i for i, (x, y) in enumerate(pts[:-2])}
    moves = [(1, 0), (0, 1), (1, 1), (1, -1), (2, 1), (1, 2), (2, -1), (1, -2)]
    pairs = [(i, index[(gx + dx, gy + dy)]) for (gx, gy), i in index.items()
             for dx, dy in moves if (gx + dx, gy + dy) in index]
    n = len(pts)
    for end in (n - 2, n - 1):
        near = np.flatnonzero(np.hypot(*(pts[:-2] - pts[end]).T) <= 2 * step)
        pairs += [(end, int(i)) for i in near]
    pairs = np.asarray(pairs)
    ok = shapely.covered_by(shapely.linestrings(np.stack([pts[pairs[:, 0]],
                                                          pts[pairs[:, 1]]], axis=1)), region)
    g = nx.Graph()
    for i, j in pairs[ok].tolist():
        g.add_edge(i, j, weight=math.dist(pts[i], pts[j]))
    return nx.dijkstra_path_length(g, n - 2, n - 1)


@pytest.mark.slow
def test_a_dense_grid_walk_is_a_little_longer_never_shorter():
    ground, bays, islands = _blocks()
    wg = walking_ground(ground, bays, islands)
    for start, goal in [((8.0, 2.0), (14.0, 22.0)), ((6.0, 22.0), (14.0, 2.0)),
                        ((24.0, 1.0), (10.0, 13.0))]:
        exact = shortest_walk(wg, start, goal).length
        grid = _grid_walk(wg.region, start, goal, 0.25)
        assert exact > math.dist(start, goal) + 0.5  # something is in the way
        assert exact - 1e-6 <= grid <= 1.04 * exact, (start, goal, exact, grid)


def test_a_walk_shut_in_by_bays_has_no_length():
    ring = [box(x, y, x + 2, y + 2) for x in (4, 6, 8) for y in (4, 6, 8) if (x, y) != (6, 6)]
    wg = walking_ground(box(0, 0, 14, 14), ring)
    assert math.isinf(shortest_walk(wg, (7.0, 7.0), (1.0, 1.0)).length)
