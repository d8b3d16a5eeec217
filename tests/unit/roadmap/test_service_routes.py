"""Service routes: a truck that cannot turn round fails and says why; a route that passes
is checked with shapely from its own poses, apart from the planner."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from lotsim.core.outcome import Status
from lotsim.errors import ScenarioError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.roadmap.service_routes import RouteSettings, kerb_circle, plan_route
from lotsim.vehicles.catalogue import SERVICE_VEHICLES

# a 40 m dead-end street 7 m wide, closed at its east end
STREET = """\
name: street
lot:
  boundary: [[0, 0], [40, 0], [40, 7], [0, 7]]
  aisles:
    - {id: A, centerline: [[0, 3.5], [40, 3.5]], width: 7.0}
  entrances: [{id: in, x: 3.0, y: 1.75, heading_deg: 0}]
  exits: [{id: out, x: 3.0, y: 5.25, heading_deg: 180}]
routes:
  - {id: deep, vehicle: fire_pump, from: in, to: {x: 25, y: 1.75, heading_deg: 0},
     leave: out}
"""

# a 44 m x 24 m lot: one aisle, a row of bays on each side, a shop door to the north
SHOP = """\
name: shop
lot:
  boundary: [[0, 0], [44, 0], [44, 24], [0, 24]]
  aisles:
    - {id: A, centerline: [[0, 12], [44, 12]], width: 7.0}
  rows:
    - {aisle: A, side: left, kind: perpendicular, count: 8, slot_width: 2.5,
       slot_length: 5.0, start: 10.0, id_prefix: N}
    - {aisle: A, side: right, kind: perpendicular, count: 8, slot_width: 2.5,
       slot_length: 5.0, start: 10.0, id_prefix: S}
  building_entrances: [{id: door, x: 15.0, y: 23.5}]
  entrances: [{id: west, x: 4.0, y: 10.25, heading_deg: 0}]
  exits: [{id: west_out, x: 4.0, y: 13.75, heading_deg: 180}]
routes:
  - {id: fire, vehicle: fire_pump, from: west, to: {building_entrance: door, within: 18},
     leave: west_out}
"""


def _lot(text: str):
    sc = load_scenario(text)
    return sc, build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))


def test_a_dead_end_too_tight_for_the_appliance_fails_with_the_reason():
    sc, lot = _lot(STREET)
    report = plan_route(lot, sc.routes[0], RouteSettings(budget=3000))
    assert report.status is Status.NO_PATH and not report.passed
    assert "cannot turn round in aisle A (7 m wide)" in report.reason
    assert "exit 'out'" in report.reason and "16.8 m between kerbs" in report.reason
    assert report.envelope is None and math.isnan(report.clearance)


def test_the_same_street_without_leaving_passes():
    sc, lot = _lot(STREET.replace(",\n     leave: out}", "}"))
    report = plan_route(lot, sc.routes[0])
    assert report.passed and report.changes == 0
    assert report.poses[-1, 0] == pytest.approx(25.0, abs=1.0)


@pytest.fixture(scope="module")
def shop():
    sc, lot = _lot(SHOP)
    return sc, lot, plan_route(lot, sc.routes[0])


def test_a_route_it_can_make_passes(shop):
    _, _, report = shop
    assert report.passed, report.reason
    assert report.legs == ("building entrance 'door'", "exit 'west_out'")
    end = report.poses[-1]
    assert math.hypot(end[0] - 4.0, end[1] - 13.75) <= 1.0 + 1e-6
    assert abs(math.remainder(end[2] - math.pi, 2 * math.pi)) < 1e-6


def _prints(report, vehicle):
    """The body's rectangles at the report's poses, made here from the vehicle's sizes."""
    out = []
    for x, y, th in report.poses:
        c, s = math.cos(th), math.sin(th)
        corners = [(-vehicle.rear, -vehicle.width / 2), (vehicle.front, -vehicle.width / 2),
                   (vehicle.front, vehicle.width / 2), (-vehicle.rear, vehicle.width / 2)]
        out.append(Polygon([(x + c * a - s * b, y + s * a + c * b) for a, b in corners]))
    return out


def test_its_envelope_stays_on_the_ground_and_clear_of_the_bays(shop):
    sc, lot, report = shop
    v = SERVICE_VEHICLES["fire_pump"]
    ground = Polygon([(0, 0), (44, 0), (44, 24), (0, 24)])
    bays = shapely.union_all([s.shape for s in lot.slots])
    prints = _prints(report, v)
    # on the ground but where it drives out through the exit's mouth, beyond the boundary
    mouth = shapely.box(-30.0, 13.75 - 2.25, 0.0, 13.75 + 2.25)
    assert all(ground.union(mouth).buffer(1e-6).covers(p) for p in prints)
    assert prints[0].within(ground) and not prints[-1].within(ground)
    assert min(p.distance(bays) for p in prints) >= 0.1 - 1e-3
    # the reported envelope holds every footprint and has their union's area
    union = shapely.union_all(prints)
    assert report.envelope.buffer(1e-6).covers(union)
    assert report.area == pytest.approx(union.area, rel=0.02)


def test_its_steering_never_exceeds_the_vehicles_lock(shop):
    _, _, report = shop
    v = SERVICE_VEHICLES["fire_pump"]
    kmax = math.tan(v.max_steer) / v.wheelbase
    assert all(abs(s.curvature) <= kmax * (1 + 1e-9) for s in report.segments)
    p = report.poses
    step = np.hypot(np.diff(p[:, 0]), np.diff(p[:, 1]))
    turn = np.abs(np.remainder(np.diff(p[:, 2]) + math.pi, 2 * math.pi) - math.pi)
    moving = step > 1e-6
    assert (turn[moving] / step[moving]).max() <= kmax * 1.01


def test_its_clearance_matches_a_brute_force_distance(shop):
    _, lot, report = shop
    v = SERVICE_VEHICLES["fire_pump"]
    prints = _prints(report, v)
    # the bays, and the lot's edge but the exit's mouth it leaves through
    edge = Polygon([(0, 0), (44, 0), (44, 24), (0, 24)]).exterior.difference(
        shapely.box(-1.0, 13.75 - 2.3, 1.0, 13.75 + 2.3))
    things = [s.shape for s in lot.slots] + [edge]
    brute = min(p.distance(t) for p in prints for t in things)
    assert report.clearance == pytest.approx(brute, abs=0.02)
    x, y = report.clearance_at
    assert min(t.distance(shapely.Point(x, y)) for t in things) < 1e-6


def test_the_catalogue_turning_circles_are_the_published_ones():
    assert kerb_circle(SERVICE_VEHICLES["fire_pump"]) == pytest.approx(16.8)
    assert kerb_circle(SERVICE_VEHICLES["refuse_26t"]) == pytest.approx(17.0)


@pytest.mark.parametrize("old, new, where", [
    ("vehicle: fire_pump", "vehicle: fire_pmp", "9:25: routes[0].vehicle"),
    ("from: in", "from: gate", "9:42: routes[0].from"),
    ("leave: out", "leave: [out, nowhere]", "10:19: routes[0].leave[1]"),
    ("{x: 25, y: 1.75, heading_deg: 0}", "{x: 25, y: 1.75}", "9:50: routes[0].to"),
    ("{x: 25, y: 1.75, heading_deg: 0}", "{building_entrance: door}",
     "9:70: routes[0].to.building_entrance"),
    ("{x: 25, y: 1.75, heading_deg: 0}", "{exit: out}", "10:13: routes[0].leave"),
])
def test_bad_routes_are_refused_where_they_are_written(old, new, where):
    with pytest.raises(ScenarioError) as err:
        load_scenario(STREET.replace(old, new))
    assert f"<scenario>:{where}:" in str(err.value), str(err.value)
