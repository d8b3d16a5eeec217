"""Slot corners of each kind against values worked out by hand, and occupancy rules."""

import math

import numpy as np
import pytest
import shapely

from conftest import ROOT, SHIPPED, scenario_from_text
from lotsim.errors import ScenarioError
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle

S45, C45 = math.sin(math.radians(45)), math.cos(math.radians(45))
S60, C60 = math.sin(math.radians(60)), math.cos(math.radians(60))

LOT = """
vehicle_types: [valet]
lot:
  boundary: [[-5, -20], [60, -20], [60, 20], [-5, 20]]
  aisles:
    - {{id: a, centerline: [[0, 0], [50, 0]], width: 6.0}}
  rows:
    - {row}
  entrances:
    - {{id: in, x: 1.0, y: -1.5, heading_deg: 0}}
"""


def lot_from_text(text: str):
    """The built lot alone: slots, occupancy (no maneuvers, no graph)."""
    sc = scenario_from_text(text)
    return build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))


def slots_of(row: str):
    return lot_from_text(LOT.format(row=row)).slots


def same_corners(poly, expected):
    got = {(round(x, 6), round(y, 6)) for x, y in poly}
    want = {(round(x, 6), round(y, 6)) for x, y in expected}
    return got == want


def test_perpendicular_row_corners():
    slots = slots_of("{aisle: a, side: left, kind: perpendicular, count: 3, slot_width: 2.5, "
                     "slot_length: 5.0, start: 10.0, id_prefix: P}")
    assert [s.id for s in slots] == ["P1", "P2", "P3"]
    assert same_corners(slots[0].polygon, [(10, 3), (12.5, 3), (12.5, 8), (10, 8)])
    assert same_corners(slots[2].polygon, [(15, 3), (17.5, 3), (17.5, 8), (15, 8)])
    assert slots[0].heading == pytest.approx(math.pi / 2)  # nose-in faces north
    assert same_corners(slots[0].entry, [(10, 3), (12.5, 3)])


def test_parallel_row_on_the_right_corners():
    slots = slots_of("{aisle: a, side: right, kind: parallel, count: 2, slot_width: 2.5, "
                     "slot_length: 6.0, start: 10.0, gap: 0.5}")
    assert same_corners(slots[0].polygon, [(10, -3), (16, -3), (16, -5.5), (10, -5.5)])
    assert same_corners(slots[1].polygon, [(16.5, -3), (22.5, -3), (22.5, -5.5), (16.5, -5.5)])
    assert same_corners(slots[0].entry, [(10, -3), (16, -3)])
    assert slots[0].heading == pytest.approx(0.0)  # with the traffic of the right-hand lane


@pytest.mark.parametrize(
    ("deg", "s", "c"), [(45, S45, C45), (60, S60, C60)], ids=["45deg", "60deg"]
)
def test_angled_row_corners(deg, s, c):
    w, length = 2.5, 5.0
    slots = slots_of(f"{{aisle: a, side: left, kind: angled, angle_deg: {deg}, count: 2, "
                     f"slot_width: {w}, slot_length: {length}, start: 10.0}}")
    # back entry corner recessed by w·cos, front entry corner on the aisle edge (y = 3)
    b = np.array([10.0, 3.0 + w * c])
    a = np.array([10.0 + w * s, 3.0])
    d = np.array([c, s])
    assert same_corners(slots[0].polygon, [a, b, b + length * d, a + length * d])
    pitch = w / s
    assert same_corners(slots[1].polygon - [pitch, 0], slots[0].polygon)
    assert slots[0].heading == pytest.approx(math.radians(deg))
    assert slots[0].angle == pytest.approx(math.radians(deg))
    # neighbours share a long side and do not overlap
    p0, p1 = shapely.Polygon(slots[0].polygon), shapely.Polygon(slots[1].polygon)
    assert p0.intersection(p1).area < 1e-9 and p0.distance(p1) < 1e-9


def test_angled_row_on_the_right_mirrors_the_left():
    left = slots_of("{aisle: a, side: left, kind: angled, angle_deg: 60, count: 1, "
                    "slot_width: 2.5, slot_length: 5.0, start: 10.0}")[0]
    right = slots_of("{aisle: a, side: right, kind: angled, angle_deg: 60, count: 1, "
                     "slot_width: 2.5, slot_length: 5.0, start: 10.0}")[0]
    assert same_corners(right.polygon, left.polygon * [1, -1])
    assert right.heading == pytest.approx(-left.heading)


@pytest.mark.parametrize("name", SHIPPED)
def test_every_slot_polygon_is_counter_clockwise_with_its_size(shipped_graphs, name):
    for slot in shipped_graphs[name].lot.slots:
        poly = shapely.Polygon(slot.polygon)
        assert poly.exterior.is_ccw
        assert poly.area == pytest.approx(slot.width * slot.length)


def test_free_standing_slot_finds_its_aisle():
    lot = lot_from_text("""
        lot:
          boundary: [[0, -10], [40, -10], [40, 10], [0, 10]]
          aisles:
            - {id: a, centerline: [[0, 0], [40, 0]], width: 6.0}
          slots:
            - {id: X, kind: perpendicular, width: 2.5, length: 5.0, center: [20, -5.5],
               heading_deg: -90}
          entrances:
            - {id: in, x: 1.0, y: -1.5, heading_deg: 0}
        """)
    slot = lot.slot_by_id["X"]
    assert slot.aisle == "a" and slot.side == "right"
    assert same_corners(slot.entry, [(18.75, -3), (21.25, -3)])
    assert slot.station == pytest.approx(20.0)


@pytest.mark.parametrize("deg, side", [(45, "left"), (60, "left"), (60, "right")])
def test_a_free_standing_angled_slot_is_the_angled_rows_slot_at_its_place(deg, side):
    """Placed by the centre and heading of a row's angled slot, a free-standing one is that
    slot: its entry slants away from the aisle (front corner on the edge, back corner
    width·cos α behind, here 0.88 or 0.63 m), so it opens onto the aisle by its nearer end."""
    (row,) = slots_of(f"{{aisle: a, side: {side}, kind: angled, angle_deg: {deg}, count: 1, "
                      "slot_width: 2.5, slot_length: 5.0, start: 20.0}")
    lot = lot_from_text(f"""
        lot:
          boundary: [[-5, -20], [60, -20], [60, 20], [-5, 20]]
          aisles:
            - {{id: a, centerline: [[0, 0], [50, 0]], width: 6.0}}
          slots:
            - {{id: X, kind: angled, angle_deg: {deg}, width: 2.5, length: 5.0,
               center: [{row.center[0]!r}, {row.center[1]!r}],
               heading_deg: {math.degrees(row.heading)!r}}}
          entrances:
            - {{id: in, x: 1.0, y: -1.5, heading_deg: 0}}
        """)
    free = lot.slot_by_id["X"]
    assert (free.aisle, free.side, free.kind) == ("a", side, "angled")
    assert free.angle == pytest.approx(math.radians(deg))
    assert free.heading == pytest.approx(row.heading)
    assert free.station == pytest.approx(row.station)
    assert same_corners(free.entry, row.entry) and same_corners(free.polygon, row.polygon)


def test_a_free_standing_angled_slot_whose_angle_its_heading_belies_is_refused():
    with pytest.raises(ScenarioError, match=r"slot 'X': angle_deg is 60, but its heading "
                                            r"makes 45.0° with aisle 'a'"):
        lot_from_text("""
            lot:
              boundary: [[-5, -20], [60, -20], [60, 20], [-5, 20]]
              aisles:
                - {id: a, centerline: [[0, 0], [50, 0]], width: 6.0}
              slots:
                - {id: X, kind: angled, angle_deg: 60, width: 2.5, length: 5.0,
                   center: [22.65, 5.65], heading_deg: 45}
              entrances:
                - {id: in, x: 1.0, y: -1.5, heading_deg: 0}
            """)


def test_a_free_standing_angled_slot_recessed_past_reach_opens_onto_no_aisle():
    """0.3 m of reach counts from the entry's nearer end: 0.35 m off, it is refused."""
    c, s = math.cos(math.radians(45)), math.sin(math.radians(45))
    front = np.array([20.0, 3.35])  # the nearer corner, 0.35 m off the edge at y = 3
    d, n = np.array([c, s]), np.array([-s, c])
    center = [float(v) for v in front + n * 1.25 + d * 2.5]
    with pytest.raises(ScenarioError, match="opens onto no aisle: its entry side is 0.35 m"):
        lot_from_text(f"""
            lot:
              boundary: [[-5, -20], [60, -20], [60, 20], [-5, 20]]
              aisles:
                - {{id: a, centerline: [[0, 0], [50, 0]], width: 6.0}}
              slots:
                - {{id: X, kind: angled, angle_deg: 45, width: 2.5, length: 5.0,
                   center: [{center[0]!r}, {center[1]!r}], heading_deg: 45}}
              entrances:
                - {{id: in, x: 1.0, y: -1.5, heading_deg: 0}}
            """)


OCC = """
seed: 1
lot:
  boundary: [[0, -10], [60, -10], [60, 10], [0, 10]]
  aisles:
    - {{id: a, centerline: [[0, 0], [60, 0]], width: 6.0}}
  rows:
    - {{aisle: a, side: left, kind: perpendicular, count: 20, slot_width: 2.5,
       slot_length: 5.0, start: 5.0, id_prefix: P}}
  entrances:
    - {{id: in, x: 1.0, y: -1.5, heading_deg: 0}}
  occupied: {occ}
"""


def test_random_occupancy_is_the_seeded_draw():
    lot = lot_from_text(OCC.format(occ="{fraction: 0.5, seed: 42, min_free: 1}"))
    draw = np.random.default_rng(42).random(20) < 0.5
    assert lot.occupied == {f"P{i + 1}" for i in np.flatnonzero(draw)}


def test_random_occupancy_keeps_min_free():
    lot = lot_from_text(OCC.format(occ="{fraction: 1.0, seed: 3, min_free: 4}"))
    assert len(lot.occupied) == 16
    again = lot_from_text(OCC.format(occ="{fraction: 1.0, seed: 3, min_free: 4}"))
    assert again.occupied == lot.occupied


def test_listed_occupancy():
    lot = lot_from_text(OCC.format(occ="[P1, P7]"))
    assert lot.occupied == {"P1", "P7"}
    assert len(lot.free_slots) == 18


@pytest.mark.parametrize("name", ["lots/short_loop", "lots/ring"])
def test_a_lanes_poses_at_many_stations_are_each_stations_own_to_the_bit(name):
    """:meth:`Lane.poses_at` takes a segment's stations at once: each pose is the one
    :meth:`Lane.pose_at` gives, to the bit, on straights, arcs and clothoids, at the lane's
    ends, its segments' joins and past its ends."""
    from lotsim.io.scenario_yaml import load_scenario

    sc = load_scenario(ROOT / "scenarios" / f"{name}.yaml")
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    kinds = set()
    for lane in lot.lanes:
        kinds |= {(s.curvature != 0.0, s.sharpness != 0.0) for s in lane.segments}
        stations = np.concatenate([np.linspace(-1.0, lane.length + 1.0, 97), lane.starts,
                                   [lane.length]])
        assert lane.poses_at(stations) == [lane.pose_at(float(s)) for s in stations]
    assert (False, False) in kinds
    assert any(sharp for _, sharp in kinds) == (name == "lots/short_loop")  # its bends
    # a long clothoid, turning by 4.5 rad: its quadrature takes more cells farther along
    from lotsim.core.geometry import Segment
    from lotsim.lot.model import Lane

    spiral = Lane("spiral", "a", (Segment((1.0, 2.0, 0.3), 30.0, 0.0, 0.01),), 0.0, True)
    stations = np.linspace(0.0, 30.0, 61)
    assert spiral.poses_at(stations) == [spiral.pose_at(float(s)) for s in stations]


def test_a_slot_through_pickle_makes_its_shape_again_and_a_frame_comes_back_equal():
    """A prepared lot is kept without its slots' shapes (made again from the corners when
    asked for) and a problem's frame by its fields: both come back equal."""
    import pickle

    from lotsim.maneuvers.problem import LocalFrame

    lot = lot_from_text(LOT.format(row="{aisle: a, side: left, kind: perpendicular, "
                                       "count: 3, slot_width: 2.5, slot_length: 5.0, "
                                       "start: 5}"))
    slot = lot.slots[0]
    shape = slot.shape
    back = pickle.loads(pickle.dumps(slot))
    assert "shape" in slot.__dict__ and b"shape" not in pickle.dumps(slot)
    assert "shape" not in back.__dict__
    assert back.shape.equals(shape) and back.id == slot.id
    assert np.array_equal(back.polygon, slot.polygon)
    frame = LocalFrame(1.5, -2.0, 0.7, True)
    assert pickle.loads(pickle.dumps(frame)) == frame
