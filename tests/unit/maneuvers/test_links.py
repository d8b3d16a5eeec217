"""The parking links the maneuvers hand the roadmap (lotsim.maneuvers.links): each is its
maneuver, where it begins, its way out driven backwards, and their times for the link's
vehicle type as the maneuver itself times them; a maneuver shared by two types is timed
for each; a slow zone on the way lowers the link's limit and lengthens its time."""

import dataclasses

import pytest

from conftest import ONE_AISLE, scenario_from_text
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.maneuvers.batch import plan_lot
from lotsim.maneuvers.links import parking_links
from lotsim.sim.preparation import maneuver_planner

# the same aisle with a 5 km/h zone over its first bays
ZONED = ONE_AISLE.replace("  entrances:", """\
  speed_zones:
    - {id: slow, polygon: [[10, 4], [22, 4], [22, 18], [10, 18]], limit_kmh: 5}
  entrances:""")


def _planned(text: str):
    sc = scenario_from_text(text)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    planned, _, park_only = plan_lot(maneuver_planner(sc, lot), sc.vehicle_types,
                                     workers=1)
    return sc, lot, planned, park_only


@pytest.fixture(scope="module")
def plain():
    return _planned(ONE_AISLE)


def test_each_link_is_its_maneuver_and_way_out_timed_as_they_time_themselves(plain):
    sc, lot, planned, park_only = plain
    links = parking_links(lot, planned, park_only, sc.vehicle_types)
    assert len(links) == len(planned) + len(park_only) > 0
    types = {v.name: v for v in sc.vehicle_types}
    for link, ((vname, sid, lid), m) in zip(links, planned.items(), strict=False):
        assert (link.vehicle, link.slot, link.lane, link.station) == (vname, sid, lid,
                                                                     m.station)
        assert link.park is m and link.leave == m.reversed()
        assert (link.park_gear, link.leave_gear) == (m.gears[0], m.reversed().gears[0])
        assert link.speed_limit == lot.speed_limit  # no zone
        assert link.park_time == m.duration(types[vname], lot.speed_limit)
        assert link.leave_time == m.reversed().duration(types[vname], lot.speed_limit)
    for link in links[len(planned):]:
        assert link.leave is None and link.park_time is not None


def test_a_maneuver_shared_by_two_types_is_timed_for_each(plain):
    sc, lot, planned, _ = plain
    car = sc.vehicle_types[0]
    slow = dataclasses.replace(car, name="slow", limits=dataclasses.replace(
        car.limits, max_forward_speed=car.limits.max_forward_speed / 3,
        max_reverse_speed=car.limits.max_reverse_speed / 3))
    (key, m), = list(planned.items())[:1]
    shared = {key: m, ("slow", key[1], key[2]): m}
    fast_link, slow_link = parking_links(lot, shared, None, [car, slow])
    assert fast_link.park_time == m.duration(car, lot.speed_limit)
    assert slow_link.park_time == m.duration(slow, lot.speed_limit)
    assert slow_link.park_time > fast_link.park_time
    # a type the links are not timed for: no time
    (untimed,) = parking_links(lot, {key: m}, None, [])
    assert untimed.park_time is None and untimed.leave_time is None


def test_a_slow_zone_lowers_the_limit_of_the_links_through_it_and_lengthens_them(plain):
    sc, lot, planned, park_only = plain
    _, zoned_lot, zoned, zoned_only = _planned(ZONED)
    plain_links = {(k.vehicle, k.slot, k.lane): k
                   for k in parking_links(lot, planned, park_only, sc.vehicle_types)}
    slowed = 0
    for link in parking_links(zoned_lot, zoned, zoned_only, sc.vehicle_types):
        before = plain_links[link.vehicle, link.slot, link.lane]
        if link.speed_limit < zoned_lot.speed_limit:
            assert link.speed_limit == pytest.approx(5 / 3.6)
            assert link.park_time > before.park_time
            slowed += 1
        else:
            assert link.park_time == before.park_time
    assert slowed > 0
