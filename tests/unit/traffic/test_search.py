"""lotsim.traffic.search.search on a hand-built straight lane: when a car waits, for
how long, and that what it plans meets nobody (checked with shapely, not the table)."""

import dataclasses
import math

import networkx as nx
import numpy as np
import pytest
import shapely
from shapely.geometry import box

from lotsim.core.geometry import Segment
from lotsim.core.outcome import Status
from lotsim.roadmap.model import LotGraph
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.search import Goal, SearchRequest, search
from lotsim.traffic.searchgraph import SearchGraph
from lotsim.traffic.settings import SearchSettings
from lotsim.vehicles import CATALOGUE

CAR = CATALOGUE["valet"]  # 1.0 m behind the rear axle, 3.9 m in front, 1.8 m wide
LIMIT = 20 / 3.6


def _lane(xs, settings=None):
    """A one-way lane along the x axis with nodes at ``xs`` [m], one edge between each two
    neighbours (the last node is the exit)."""
    g = nx.DiGraph()
    for k, x in enumerate(xs):
        g.add_node(k, pose=(float(x), 0.0, 0.0), kind="lane")
    for k in range(len(xs) - 1):
        length = float(xs[k + 1] - xs[k])
        g.add_edge(k, k + 1, kind="lane", length=length, gear=1, speed_limit=LIMIT,
                   path=(Segment((float(xs[k]), 0.0, 0.0), length, 0.0),), placeholder=False)
    return SearchGraph(LotGraph(None, g, {}, {}, {}), CAR, settings=settings)


def _front_meets(x_rear_axle, x0, x1):
    """Whether the car, rear axle at ``x_rear_axle`` on the x axis, overlaps [x0, x1]."""
    return x_rear_axle + CAR.front >= x0 and x_rear_axle - CAR.rear <= x1


@pytest.mark.parametrize("outside", [False, True])
def test_a_car_departs_exactly_when_its_motion_clears_a_body_crossing_its_way(outside):
    # a 30 m lane; a thin body lies across it at x = 15 m from t = 0 to 6.3 s. The car
    # starts at rest at x = 0 (or outside the lane's first node, taking no space). Its
    # drive's swept hull over chunk [a, z] of its motion meets the body iff the car
    # overlaps the body at some time of the chunk (along a straight the hull of the
    # chunk's end footprints is what it sweeps); that chunk may not overlap the body's
    # time, so the car can depart at 6.3 - a for the first such chunk, and no sooner
    sg = _lane([0.0, 30.0])
    x0, x1, t1 = 15.0, 15.5, 6.3
    table = ReservationTable()
    table.reserve("other", [(0.0, t1, box(x0, -3.0, x1, 3.0))])
    plan = search(sg, table, SearchRequest(owner="me", start=0, t0=0.0, goal=Goal(exits=(1,)),
                                           outside=outside))
    assert plan.status is Status.FOUND
    *waits, drive = plan.moves
    assert waits and {w.kind for w in waits} == {"outside" if outside else "wait"}
    assert drive.kind == "drive" and drive.t0 == waits[-1].t1
    em = sg.motion(drive.edge, 0, drive.level_to)
    first = None
    for a, z in em.swept.t:  # the chunks the table holds, in the motion's own time
        xa, xz = em.motion.at(np.array([a, z]), wheelbase=CAR.wheelbase)[0][:, 0]
        if _front_meets(xa, x0, x1) or _front_meets(xz, x0, x1) or xa <= x0 <= xz:
            first = a
            break
    assert first is not None and first > 0
    assert drive.t0 == pytest.approx(t1 - first, abs=1e-5)
    assert drive.t0 > t1 - first  # not one instant too soon


def test_a_way_blocked_for_ever_is_no_path_after_a_few_expansions():
    # with 1 s waits the car would wait, expanding the edge again, until the horizon
    sg = _lane([0.0, 10.0, 30.0])
    table = ReservationTable()
    table.reserve_standing("wall", box(20.0, -3.0, 20.5, 3.0), 0.0)
    plan = search(sg, table, SearchRequest(owner="me", start=0, t0=0.0, goal=Goal(exits=(2,))))
    assert plan.status is Status.NO_PATH
    assert plan.expansions <= 10


def test_the_expansion_limit_is_omega_times_the_reverse_search_and_a_long_wait_fits():
    # a car waiting 100 s for its way is found in a few expansions, within an expansion
    # limit of 4 times the reverse search's 2 nodes; a smaller budget still reaches it, then
    sg = _lane([0.0, 30.0], SearchSettings(min_budget=0))
    table = ReservationTable()
    table.reserve("other", [(0.0, 100.0, box(15.0, -3.0, 15.5, 3.0))])
    ask = SearchRequest(owner="me", start=0, t0=0.0, goal=Goal(exits=(1,)))
    plan = search(sg, table, ask, omega=4)
    assert plan.status is Status.FOUND and plan.moves[0].t1 > 90
    stopped = search(sg, table, ask, omega=0.5)
    assert stopped.status is Status.OUT_OF_BUDGET and not stopped.found
    assert stopped.reason == "expansion limit"
    look = search(sg, table, dataclasses.replace(ask, budget=1))
    assert look.status is Status.OUT_OF_BUDGET and look.expansions == 2
    # the same search with the default floor of expansions finds it
    assert search(_lane([0.0, 30.0]), table, ask, omega=0.5).found


def test_a_reverse_search_kept_from_other_searches_sizes_the_expansion_limit_as_a_new_one():
    # the RRA* from the exit has closed all 4 nodes for an earlier search from node 0; a
    # search from node 1 with it, shared, reaches its expansion limit (omega 0.5) where one
    # with a new RRA* (3 nodes closed to reach node 1) does, not a step later
    sg = _lane([0.0, 10.0, 20.0, 30.0], SearchSettings(min_budget=0))
    table = ReservationTable()
    table.reserve("other", [(0.0, 100.0, box(25.0, -3.0, 25.5, 3.0))])
    ask = SearchRequest(owner="me", start=1, t0=0.0, goal=Goal(exits=(3,)))
    used = sg.reverse_search({3: 0.0})
    assert used(0) < math.inf and used.closed == 4
    new = search(sg, table, ask, heuristic=sg.reverse_search({3: 0.0}), omega=0.5)
    kept = search(sg, table, ask, heuristic=used, shared=True, omega=0.5)
    assert new.status is kept.status is Status.OUT_OF_BUDGET
    assert kept.expansions == new.expansions == 2
    # sized by all it closed
    assert search(sg, table, ask, heuristic=used, omega=0.5).expansions == 3


def _footprint(pose):
    return shapely.Polygon(CAR.footprints(np.asarray(pose, dtype=float)[None, :])[0])


def _meets(moves, bodies, dt=0.01):
    """The first (time, body index) at which the planned car overlaps a body, sampling
    every ``dt`` [s] and each move's ends; None if never."""
    for m in moves:
        if m.kind == "outside":
            continue
        tau = np.union1d(np.arange(0.0, m.t1 - m.t0, dt), [m.t1 - m.t0])
        if m.motion is None:
            poses = np.repeat(np.asarray(m.end_pose, dtype=float)[None, :], len(tau), axis=0)
        else:
            poses = m.motion.at(tau, wheelbase=CAR.wheelbase)[0]
        polys = shapely.polygons(CAR.footprints(poses))
        for k, (t0, t1, body) in enumerate(bodies):
            now = (m.t0 + tau >= t0) & (m.t0 + tau <= t1)
            if now.any():
                hit = shapely.intersects(polys[now], body)
                if hit.any():
                    return float((m.t0 + tau[now])[np.argmax(hit)]), k
    return None


def test_a_planned_car_meets_no_reserved_body_at_any_instant():
    # bodies cross the lane at random places and times, half of them where the car would
    # stand at a node; whatever the car does, its footprint (from its moves, not the
    # table's hulls) never overlaps a body held at that instant, and the same search gives
    # the same plan
    waited = 0
    for seed in range(8):
        rng = np.random.default_rng(seed)
        sg = _lane([0.0, 6.0, 12.0, 18.0, 24.0, 30.0, 45.0])
        table = ReservationTable()
        bodies = []
        for k in range(10):
            x = float(rng.uniform(4.0, 40.0) if k % 2 else rng.choice([6.0, 12.0, 18.0, 24.0])
                      + rng.uniform(-1.5, 3.5))
            t0 = float(rng.uniform(0.0, 12.0))
            t1 = t0 + float(rng.uniform(0.5, 6.0))
            body = box(x, -3.0, x + float(rng.uniform(0.3, 2.0)), 3.0)
            bodies.append((t0, t1, body))
            table.reserve(f"o{k}", [(t0, t1, body)])
        ask = SearchRequest(owner="me", start=0, t0=0.0, goal=Goal(exits=(6,)))
        plan = search(sg, table, ask)
        assert plan.status is Status.FOUND
        assert _meets(plan.moves, bodies) is None, seed
        again = search(sg, table, ask)
        assert again.moves == plan.moves
        assert plan.moves[0].t0 == 0.0 and plan.moves[-1].node_to == 6
        for a, b in zip(plan.moves, plan.moves[1:], strict=False):
            assert b.t0 == a.t1 and b.node_from == a.node_to
        waited += any(m.kind == "wait" for m in plan.moves)
    assert waited >= 5  # most had to wait somewhere
