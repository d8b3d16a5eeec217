"""Multi-point turns onto a lane (lotsim.roadmap.multipoint): checked against an independent
integration of the path and against shapely, and used where a junction is too small for one
turn."""

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import box
from small_lots import TINY_TEE

from lotsim.core.geometry import Segment
from lotsim.io.result import result_dict
from lotsim.lot.build import build_lot
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle
from lotsim.maneuvers.planner import ManeuverPlanner
from lotsim.roadmap.multipoint import plan_onto
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import simulate
from lotsim.vehicles import CATALOGUE
from lotsim.verify import check_result

CAR = DesignVehicle(width=1.9, front=3.6, rear=0.9, min_radius=5.0, max_curvature_rate=0.15,
                    max_lateral_accel=2.0)


def _integrate(seg: Segment, ds: float = 1e-3) -> np.ndarray:
    """Poses along ``seg`` by small explicit steps of the kinematic model (x' = cos θ,
    y' = sin θ, θ' = κ), independent of the exact arcs the planner uses."""
    n = max(1, math.ceil(seg.length / ds))
    h = seg.distance / n
    x, y, th = seg.start
    out = [(x, y, th)]
    for k in range(n):
        kappa = seg.curvature + seg.sharpness * abs(h) * (k + 0.5)
        mid = th + 0.5 * h * kappa
        x, y, th = x + h * math.cos(mid), y + h * math.sin(mid), th + h * kappa
        out.append((x, y, th))
    return np.array(out)


def _bodies(poses: np.ndarray, car: DesignVehicle) -> np.ndarray:
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    corners = [(-car.rear, -car.width / 2), (car.front, -car.width / 2),
               (car.front, car.width / 2), (-car.rear, car.width / 2)]
    rings = np.stack([np.column_stack([poses[:, 0] + c * a - s * b, poses[:, 1] + s * a + c * b])
                      for a, b in corners], axis=1)
    return shapely.polygons(rings)


@pytest.mark.parametrize(("start", "frame", "lo", "hi"), [
    # right into a short arm: no single turn fits
    ((8.5, -8.0, math.pi / 2), (0.0, 1.5, 0.0), 9.0, 11.5),
    # left into the other arm, landing near its closed end
    ((8.5, -2.0, math.pi / 2), (16.0, 4.5, math.pi), 9.0, 12.0),
    # turn round across the street, onto the east-bound lane
    ((13.0, 4.5, math.pi), (0.0, 1.5, 0.0), 5.0, 9.0),
])
def test_a_multi_point_path_lands_on_the_lane_within_its_stretch_clear_of_everything(
        start, frame, lo, hi):
    """A spur 6 m wide meeting a 6 m street 16 m long: the path is continuous (each piece,
    integrated step by step, ends where the next begins), no tighter than the car's radius,
    ends on the lane's line heading along it inside [lo, hi], driven forward at the end,
    and every footprint along it lies inside the lot (shapely, 1 cm apart)."""
    lot = box(4, -12, 10, 0).union(box(0, 0, 16, 6))
    found = plan_onto([start], frame, lo, hi, Collider([], lot), CAR, 5.0)
    assert found.found, found.reason
    path = found.value[1]
    pose = np.array(start)
    poses = []
    for seg in path:
        assert np.allclose(seg.start[:2], pose[:2], atol=1e-3)
        assert math.remainder(seg.start[2] - pose[2], math.tau) == pytest.approx(0, abs=1e-3)
        assert abs(seg.curvature) <= 1 / 5.0 + 1e-9 and seg.sharpness == 0.0
        walk = _integrate(seg)
        poses.append(walk[:: 10])
        pose = walk[-1]
    c, s = math.cos(frame[2]), math.sin(frame[2])
    along = c * (pose[0] - frame[0]) + s * (pose[1] - frame[1])
    across = -s * (pose[0] - frame[0]) + c * (pose[1] - frame[1])
    assert across == pytest.approx(0.0, abs=1e-3)
    assert math.remainder(pose[2] - frame[2], math.tau) == pytest.approx(0.0, abs=1e-3)
    assert lo - 1e-3 <= along <= hi + 1e-3
    assert path[-1].gear == 1
    assert shapely.covers(lot, _bodies(np.concatenate(poses), CAR)).all()


@pytest.mark.slow
def test_checking_states_ahead_in_one_batch_finds_what_checking_one_at_a_time_does():
    """The search checks the state it expands and the next few on its heap in one batch
    (``ahead``, :data:`lotsim.roadmap.multipoint.AHEAD` by default); the paths found, to the
    last bit, are those of checking each state as it is expanded, on the spur and street
    above, bare and with posts and a kerb in it (many moves blocked, many last moves
    refused)."""
    lot = box(4, -12, 10, 0).union(box(0, 0, 16, 6))
    def posts(*at):
        return [("post", shapely.Point(x, y).buffer(0.3)) for x, y in at]

    kerb = [("kerb", box(4.0, -12.0, 4.4, -6.0))]
    problems = [((8.5, -8.0, math.pi / 2), (0.0, 1.5, 0.0), 9.0, 11.5),
                ((8.5, -2.0, math.pi / 2), (16.0, 4.5, math.pi), 9.0, 12.0),
                ((13.0, 4.5, math.pi), (0.0, 1.5, 0.0), 5.0, 9.0)]
    found = {}
    ahead = 6
    for n in (1, ahead):
        found[n] = [plan_onto([start], frame, lo, hi, Collider(obstacles, lot), CAR, 5.0,
                              budget=600, ahead=n)
                    for obstacles in ([], posts((1.0, 5.0), (15.0, 5.5)),
                                      posts((0.5, 0.5), (15.5, 5.5), (12.5, 0.4)) + kerb)
                    for start, frame, lo, hi in problems]
    assert sum(x.found for x in found[1]) == 7  # the posts leave two unreachable
    assert found[ahead] == found[1]


def test_a_multi_point_path_is_not_found_when_the_lane_cannot_be_reached():
    """A car facing a wall it cannot turn in front of, with the lane behind the wall: the
    outcome says so, with a reason, and holds no path."""
    lot = box(0, 0, 6, 6)
    got = plan_onto([(3.0, 1.0, math.pi / 2)], (0.0, 20.0, 0.0), 0.0, 10.0,
                    Collider([], lot), CAR, 5.0, budget=500)
    assert not got.found and got.value is None and got.reason


@pytest.mark.slow
def test_a_spur_meeting_a_short_arm_is_turned_into_in_a_few_strokes_and_every_bay_used():
    """A gate spur meets a 7.4 m aisle at a T; its east arm is too short past the corner bay
    for one right turn (it touches E1). Before, no car reached E2; now the turn is made in
    a few strokes, every bay is reached and left, and a run through it passes the
    checker with every car departed."""
    from conftest import scenario_from_text

    sc = scenario_from_text(TINY_TEE)
    lg = prepare_graph(sc, cache=False)
    g = lg.graph
    multi = [d["path"] for u, v, d in g.edges(data=True) if d["kind"] == "turnaround"
             and (g.nodes[u]["lane"], g.nodes[v]["lane"]) == ("spur>", "a0>")]
    assert multi
    for path in multi:
        assert {s.gear for s in path} == {1, -1}
        assert max(s.max_curvature for s in path) <= 1 / lg.lot.design.min_radius + 1e-9
        poses = np.concatenate([s.sample(0.05) for s in path])
        bodies = shapely.polygons(lg.lot.design.footprints(poses))
        assert shapely.covers(lg.lot.boundary.buffer(-0.099), bodies).all()
        slots = shapely.union_all([s.shape for s in lg.lot.slots])
        assert shapely.distance(bodies, slots).min() >= 0.099
    _every_bay_served_and_every_car_departs(sc, lg, "vw")


def _every_bay_served_and_every_car_departs(sc, lg, vehicle: str) -> None:
    """Every free bay reached, parked in and left by ``vehicle``; a run through the lot
    passes the independent checker and every car departs."""
    reach = lg.reachability()
    assert reach.ok and not reach.no_way_in and not reach.no_way_out, reach
    assert reach.by_type[vehicle] == ([], []), reach
    assert not lg.infeasible.get(vehicle), lg.infeasible
    doc = result_dict(simulate(sc, lot_graph=lg))
    report = check_result(doc)
    assert report.ok, [v.message for v in report.violations[:5]]
    assert {v["status"] for v in doc["vehicles"]} == {"departed"}


SMALL_TEE = """
name: small-tee
seed: 0
vehicle_types: [altis]
lot:
  boundary: [[0, 0], [21.2, 0], [21.2, 15.6], [0, 15.6]]
  aisles:
    - {id: spur, centerline: [[10.8, 0], [10.8, 7.8]], width: 6.0}
    - {id: a0, centerline: [[1.0, 7.8], [20.2, 7.8]], width: 6.0}
  rows:
    - {aisle: a0, side: right, kind: perpendicular, count: 2, slot_width: 2.4,
       slot_length: 4.8, start: 0.0, id_prefix: W}
    - {aisle: a0, side: right, kind: perpendicular, count: 2, slot_width: 2.4,
       slot_length: 4.8, start: 13.3, id_prefix: E}
    - {aisle: a0, side: left, kind: perpendicular, count: 2, slot_width: 2.4,
       slot_length: 4.8, start: 0.0, id_prefix: N}
  entrances:
    - {id: gate-in, x: 12.3, y: 1.5, heading_deg: 90}
  exits:
    - {id: gate-out, x: 9.3, y: 4.5, heading_deg: -90}
traffic:
  patience: 600
  stream: {count: 4, rate_per_hour: 60, dwell: [30, 30]}
"""


@pytest.mark.slow
def test_a_6_m_tee_whose_exit_is_close_to_the_junction_is_left_by_a_multi_point_turn():
    """Everything tight: 6 m aisles, arms of 9 m, the exit 3.3 m down the spur. Every
    turn onto the outbound lane lands past the exit, and every turnaround at the end of
    an arm lands past the turn it needs. Before, every bay was stranded ("can leave none
    of the free slots it reaches" and the run refused); now a multi-point turn lands
    before the exit, a turnaround from where a car arrives in the east arm lands before
    its turn out, and every car departs, checked."""
    from conftest import scenario_from_text

    sc = scenario_from_text(SMALL_TEE)
    lg = prepare_graph(sc, cache=False)
    g = lg.graph
    exit_station = g.nodes[lg.exits["gate-out"]]["station"]
    into_exit = [g.nodes[v]["station"] for u, v, d in g.edges(data=True)
                 if g.nodes[v].get("lane") == "spur<" and d["kind"] in ("turn", "turnaround")]
    assert min(into_exit) < exit_station
    _every_bay_served_and_every_car_departs(sc, lg, "altis")


CLOSED_CORNER = """
name: closed-corner
vehicle_types: [msv]
lot:
  boundary: [[0, 0], [27.3, 0], [27.3, 33.66], [0, 33.66]]
  aisles:
    - {id: spur, centerline: [[11.415, 0], [11.415, 8.415]], width: 6.47}
    - {id: a0, centerline: [[1.0, 8.415], [24.065, 8.415]], width: 6.47}
  rows:
    - {aisle: a0, side: right, kind: perpendicular, count: 2, slot_width: 2.59,
       slot_length: 5.18, start: 0.0, id_prefix: S}
    - {aisle: a0, side: left, kind: perpendicular, count: 2, slot_width: 2.59,
       slot_length: 5.18, start: 0.0, id_prefix: N}
  entrances:
    - {id: gate-in, x: 13.032, y: 1.5, heading_deg: 90}
  occupied: [S1, S2]
"""


def test_a_corner_bay_at_a_closed_end_is_left_towards_the_end_in_a_few_strokes():
    """N1 sits in the closed west corner of a 6.5 m aisle. Leaving it towards the west-bound
    lane, the full-lock shuffle finds no way (it was infeasible); strokes that are not all
    at full lock do. The maneuver ends on the lane heading along it, is no tighter than
    the car's radius, and keeps the margin to the boundary and to a car of the lot's
    design width parked centred in every other bay (shapely, footprints 5 cm apart)."""
    from conftest import scenario_from_text

    sc = scenario_from_text(CLOSED_CORNER)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    planner = ManeuverPlanner(lot)
    slot, lane = lot.slot_by_id["N1"], next(x for x in lot.lanes if x.id == "a0<")
    msv = CATALOGUE["msv"]
    result = planner.solve(msv, slot, lane)
    assert result.found, result.reason
    m = result.value
    assert max(s.max_curvature for s in m.segments) <= 1 / msv.min_turning_radius + 1e-9
    start = lane.pose_at(m.station)
    assert np.allclose(m.start[:2], start[:2], atol=1e-6)
    assert math.remainder(m.start[2] - start[2], math.tau) == pytest.approx(0.0, abs=1e-6)
    poses = np.concatenate([s.sample(0.05) for s in m.segments])
    bodies = shapely.polygons(msv.footprints(poses))
    assert shapely.covers(lot.boundary.buffer(-0.099), bodies).all()
    parked = []
    for s in lot.slots:
        if s.id != "N1":
            u = np.array([math.cos(s.heading), math.sin(s.heading)])
            n = np.array([-u[1], u[0]]) * lot.design.width / 2
            c, h = np.asarray(s.center), u * s.length / 2
            parked.append(shapely.Polygon([c - h - n, c + h - n, c + h + n, c - h + n]))
    assert shapely.distance(bodies, shapely.union_all(parked)).min() >= 0.099
