"""Small lots for the roadmap's unit tests, each built in well under a second and small
enough to check by eye, with the lines of their lanes worked out by hand (a two-way aisle
7 m wide carries a lane 1.75 m either side of its centre line, cars keeping right; a 6 m
one, 1.5 m).

``CROSS`` (60 × 60 m)::

         b< | b>                   two two-way aisles crossing at (30, 30):
            |[N1 N2 N3]            a along y = 30, b along x = 30; three bays
    --------+-------------         north of a's east arm from the corner,
     a<     |                      x 33.5-41; gate in at the west end of a>,
     a>     |                      out on a<

``TEE`` (50 × 30 m): a 6 m spur from the south (x = 25) meets a 6 m aisle along y = 15 at
a T; three bays south of the aisle on each side of the spur, the inner ones at its corners
(W3 ends at x = 22, E1 begins at x = 28): a right turn between the lanes sweeps over E1.

``LADDER`` (40 × 38.5 m): aisles a1 (y = 12) and a2 (y = 29.8) joined at their west ends by
a 17.8 m cross aisle ``west`` (x = 3.5), bays north of a1 and south of a2 from the corner;
a gate spur from the south meets a1 at x = 20. A car from a1 into a2 turns twice in the
short cross aisle.

``STREET`` (40 × 11 m): a two-way street 9 m wide along y = 4.5, its lanes ending at
x = 36, 4 m short of the closed east end; a gate in and one out at its west end, two
parallel bays 6 × 2 m along its north side (x 8-20, y 9-11): cars turn round at the dead
end.
"""

from __future__ import annotations

import textwrap

from lotsim.io.scenario_yaml import parse_scenario
from lotsim.io.yamlnodes import parse_text
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle, Lot

CROSS = """\
name: cross
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [60, 0], [60, 60], [0, 60]]
  aisles:
    - {id: a, centerline: [[0, 30], [60, 30]], width: 7.0}
    - {id: b, centerline: [[30, 0], [30, 60]], width: 7.0}
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 33.5, id_prefix: N}
  entrances:
    - {id: in, x: 2, y: 28.25, heading_deg: 0}
  exits:
    - {id: out, x: 6, y: 31.75, heading_deg: 180}
"""
CROSS_LANES = {"a>": (0.0, 28.25, 0.0), "a<": (60.0, 31.75, 3.141592653589793),
               "b>": (31.75, 0.0, 1.5707963267948966),
               "b<": (28.25, 60.0, -1.5707963267948966)}
"""Lane → the pose it begins at (its line: that point and heading)."""

TEE = """\
name: tee
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [50, 0], [50, 30], [0, 30]]
  aisles:
    - {id: spur, centerline: [[25, 0], [25, 15]], width: 6.0}
    - {id: a, centerline: [[1, 15], [49, 15]], width: 6.0}
  rows:
    - {aisle: a, side: right, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 13.5, id_prefix: W}
    - {aisle: a, side: right, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 27.0, id_prefix: E}
  entrances:
    - {id: in, x: 26.5, y: 1.5, heading_deg: 90}
  exits:
    - {id: out, x: 23.5, y: 4.5, heading_deg: -90}
"""
TEE_LANES = {"spur>": (26.5, 0.0, 1.5707963267948966),
             "spur<": (23.5, 15.0, -1.5707963267948966),
             "a>": (1.0, 13.5, 0.0), "a<": (49.0, 16.5, 3.141592653589793)}

LADDER = """\
name: ladder
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 38.5], [0, 38.5]]
  aisles:
    - {id: a1, centerline: [[3.5, 12.0], [39, 12.0]], width: 7.0}
    - {id: a2, centerline: [[3.5, 29.8], [39, 29.8]], width: 7.0}
    - {id: west, centerline: [[3.5, 12.0], [3.5, 29.8]], width: 7.0}
    - {id: spur, centerline: [[20, 0], [20, 12.0]], width: 7.0}
  rows:
    - {aisle: a1, side: left, kind: perpendicular, count: 10, slot_width: 2.6,
       slot_length: 5.4, start: 3.5, id_prefix: N}
    - {aisle: a2, side: right, kind: perpendicular, count: 10, slot_width: 2.6,
       slot_length: 5.4, start: 3.5, id_prefix: S}
  entrances:
    - {id: gate-in, x: 21.75, y: 1.5, heading_deg: 90}
  exits:
    - {id: gate-out, x: 18.25, y: 4.5, heading_deg: -90}
"""
LADDER_LANES = {"a1<": (39.0, 13.75, 3.141592653589793), "a2>": (3.5, 28.05, 0.0),
                "west>": (5.25, 12.0, 1.5707963267948966),
                "spur>": (21.75, 0.0, 1.5707963267948966)}

STREET = """\
name: street
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 11], [0, 11]]
  aisles:
    - {id: e, centerline: [[0, 4.5], [36, 4.5]], width: 9.0}
  rows:
    - {aisle: e, side: left, kind: parallel, count: 2, slot_width: 2.0,
       slot_length: 6.0, start: 8, id_prefix: P}
  entrances:
    - {id: in, x: 2, y: 2.25, heading_deg: 0}
  exits:
    - {id: out, x: 6, y: 6.75, heading_deg: 180}
"""
STREET_LANES = {"e>": (0.0, 2.25, 0.0), "e<": (36.0, 6.75, 3.141592653589793)}


def lot_of(text: str) -> Lot:
    """The lot of a scenario's text, built for the envelope of its vehicle types."""
    sc = parse_scenario(parse_text(textwrap.dedent(text), "small.yaml"))
    return build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))


# A gate spur meeting a 7.4 m aisle at a T, whose east arm is too short past the corner bay
# for one right turn: the turn from the spur onto the east-bound lane is a multi-point turn.
TINY_TEE = """
name: tiny-tee
seed: 9
vehicle_types: [vw]
lot:
  boundary: [[0, 0], [22.59, 0], [22.59, 18.25], [0, 18.25]]
  aisles:
    - {id: spur, centerline: [[11.495, 0], [11.495, 9.125]], width: 7.39}
    - {id: a0, centerline: [[1.0, 9.125], [21.59, 9.125]], width: 7.39}
  rows:
    - {aisle: a0, side: right, kind: perpendicular, count: 2, slot_width: 2.4,
       slot_length: 5.43, start: 0.0, id_prefix: W}
    - {aisle: a0, side: right, kind: perpendicular, count: 2, slot_width: 2.4,
       slot_length: 5.43, start: 14.69, id_prefix: E}
    - {aisle: a0, side: left, kind: perpendicular, count: 2, slot_width: 2.4,
       slot_length: 5.43, start: 0.0, id_prefix: N}
  entrances:
    - {id: gate-in, x: 13.342, y: 1.5, heading_deg: 90}
  exits:
    - {id: gate-out, x: 9.647, y: 4.5, heading_deg: -90}
traffic:
  patience: 600
  stream: {count: 6, rate_per_hour: 60, dwell: [30, 64]}
"""


DISCONNECTED = """\
name: apart
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [60, 0], [60, 60], [0, 60]]
  aisles:
    - {id: a, centerline: [[0, 10], [60, 10]], width: 7.0, direction: one-way}
    - {id: b, centerline: [[0, 45], [60, 45]], width: 7.0, direction: one-way}
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 10, id_prefix: A}
    - {aisle: b, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 10, id_prefix: B}
  entrances:
    - {id: in, x: 2, y: 10, heading_deg: 0}
  exits:
    - {id: out, x: 54, y: 45, heading_deg: 0}
"""
"""Two one-way aisles that never meet: the entrance on the south one, the exit on the
north one."""

SHORT_LEGS = """\
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 30], [0, 30]]
  aisles:
    - {id: ring, direction: one-way, width: 5.0,
       centerline: [[3, 5], [30, 5], [30, LEG], [3, LEG]]}
  entrances: [{id: in, x: 5, y: 5, heading_deg: 0}]
"""
"""A one-way aisle turning twice on a short leg (LEG - 5 m, LEG given by the test): as
plain arcs its corners need 9.95 m of it."""
