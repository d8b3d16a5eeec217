"""Slot kinds: a closed registry, and what each kind decides, on a three-bay hand-built lot."""

import math

import pytest

from conftest import scenario_from_text
from lotsim.lot.build import build_lot
from lotsim.lot.kinds import KINDS, kind_of
from lotsim.lot.model import DesignVehicle

LOT = """
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 24], [0, 24]]
  aisles: [{id: a, centerline: [[0, 12], [40, 12]], width: 7.0}]
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 1, slot_width: 2.5,
       slot_length: 5.0, start: 4}
    - {aisle: a, side: left, kind: angled, angle_deg: 60, count: 1, slot_width: 2.5,
       slot_length: 5.0, start: 14, id_prefix: g}
    - {aisle: a, side: right, kind: parallel, count: 1, slot_width: 2.2,
       slot_length: 6.0, start: 4}
  entrances: [{id: in, x: 2, y: 10.25, heading_deg: 0}]
traffic: {vehicles: [{id: x, arrival: 0}]}
"""


def _slots():
    sc = scenario_from_text(LOT)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    return {s.kind: s for s in lot.slots}


def test_the_registry_is_closed():
    assert list(KINDS) == ["perpendicular", "parallel", "angled"]

    class Odd:
        kind = "diagonal"

    with pytest.raises(KeyError):
        kind_of(Odd())


def test_each_kind_decides_its_lanes_gear_and_parked_zone():
    slots = _slots()
    perp, angled, par = slots["perpendicular"], slots["angled"], slots["parallel"]
    # a perpendicular bay is served both ways; an angled one only by traffic heading its way
    assert kind_of(perp).serves(perp, 0.0) and kind_of(perp).serves(perp, math.pi)
    assert kind_of(angled).serves(angled, 0.0) != kind_of(angled).serves(angled, math.pi)
    assert (kind_of(angled).entry_gear, kind_of(perp).entry_gear) == (1, -1)
    assert kind_of(par).parks_along and not kind_of(perp).parks_along
    # a bay's parked car keeps others out of a strip as wide as the car, grown by the margin;
    # a parallel slot's out of the whole slot, not past its entry line
    strip = kind_of(perp).taken(perp, 1.8, 0.1)
    assert strip.area == pytest.approx((1.8 + 0.2) * (5.0 + 0.2))
    whole = kind_of(par).taken(par, 1.8, 0.1)
    assert whole.area == pytest.approx((6.0 + 0.2) * (2.2 + 0.1))
    assert whole.covers(par.shape.buffer(-1e-6))
