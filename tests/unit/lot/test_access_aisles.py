"""Access aisles beside accessible bays, checked with shapely on small lots a person can
draw: each lies along its bay's whole long side, is at least as wide as its use asks, two
bays share one, and none meets the vehicular way or another bay; a layout whose aisle would
is refused at the line and column of its row or slot."""

from __future__ import annotations

import pytest
from shapely.geometry import LineString, Polygon

from lotsim.errors import ScenarioError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle

INCH = 0.0254


def lot_text(items: str) -> str:
    """A 50 × 24 m lot: one two-way aisle along y = 12, 7 m wide (the way: 8.5 < y < 15.5),
    and ``items`` (YAML lines under ``lot:``)."""
    return f"""\
name: aisles
lot:
  boundary: [[0, 0], [50, 0], [50, 24], [0, 24]]
  aisles:
    - {{id: A, centerline: [[0, 12], [50, 12]], width: 7.0}}
{items}
  entrances:
    - {{id: in, x: 5.0, y: 10.25, heading_deg: 0}}
"""


def built(items: str):
    sc = load_scenario(lot_text(items))
    return build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))


def shares_long_side(aisle: Polygon, bay, tol=1e-6) -> bool:
    """The aisle and the bay meet along a whole long side of the bay (and overlap by no
    area)."""
    ring = list(bay.shape.exterior.coords)
    sides = [LineString(ring[k:k + 2]) for k in range(4)]
    near = aisle.buffer(tol)
    return (aisle.intersection(bay.shape).area < tol
            and any(abs(e.length - bay.length) < tol and near.covers(e) for e in sides))


def width_of(aisle: Polygon, length: float) -> float:
    return aisle.area / length


WAY = Polygon([(0, 8.5), (50, 8.5), (50, 15.5), (0, 15.5)])


def check_clear(lot) -> None:
    """No access aisle meets the vehicular way, a bay or another aisle but along a line."""
    shapes = [a.shape for a in lot.access_aisles]
    for k, a in enumerate(shapes):
        assert a.intersection(WAY).area < 1e-9
        assert all(a.intersection(s.shape).area < 1e-9 for s in lot.slots)
        assert all(a.intersection(b).area < 1e-9 for b in shapes[:k])


def test_a_row_of_three_accessible_bays_has_two_aisles_the_first_shared():
    lot = built("""  rows:
    - {aisle: A, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 4.0, id_prefix: H, use: accessible}""")
    assert [s.use for s in lot.slots] == ["accessible"] * 3
    assert [a.slots for a in lot.access_aisles] == [("H1", "H2"), ("H3",)]
    by = lot.slot_by_id
    first, last = (a.shape for a in lot.access_aisles)
    assert shares_long_side(first, by["H1"]) and shares_long_side(first, by["H2"])
    assert shares_long_side(last, by["H3"])
    for a in (first, last):
        assert width_of(a, 5.0) == pytest.approx(60 * INCH)
        assert a.bounds[1] == pytest.approx(15.5) and a.bounds[3] == pytest.approx(20.5)
    # bay, aisle, bay, bay, aisle along the aisle edge from x = 4
    assert [round(by[s].shape.bounds[0], 4) for s in ("H1", "H2", "H3")] == \
        [4.0, round(4 + 2.5 + 60 * INCH, 4), round(4 + 5 + 60 * INCH, 4)]
    check_clear(lot)


def test_a_narrow_van_bay_gets_the_wide_aisle_and_a_wide_one_the_narrow():
    lot = built("""  rows:
    - {aisle: A, side: right, kind: perpendicular, count: 1, slot_width: 2.5,
       slot_length: 5.0, start: 4.0, id_prefix: V, use: van_accessible}
    - {aisle: A, side: right, kind: perpendicular, count: 1, slot_width: 3.4,
       slot_length: 5.0, start: 20.0, id_prefix: W, use: van_accessible}""")
    narrow, wide = lot.access_aisles
    assert width_of(narrow.shape, 5.0) == pytest.approx(96 * INCH)
    assert width_of(wide.shape, 5.0) == pytest.approx(60 * INCH)
    check_clear(lot)


def test_angled_bays_share_a_parallelogram_aisle_as_wide_as_asked():
    lot = built("""  rows:
    - {aisle: A, side: left, kind: angled, angle_deg: 60, count: 2, slot_width: 2.6,
       slot_length: 5.0, start: 4.0, id_prefix: H, use: accessible,
       access_aisle_width: 1.8}""")
    (aisle,) = lot.access_aisles
    for s in lot.slots:
        assert shares_long_side(aisle.shape, s)
    assert width_of(aisle.shape, 5.0) == pytest.approx(1.8)
    check_clear(lot)


def test_a_parallel_bay_has_its_aisle_behind_it_away_from_the_way():
    lot = built("""  rows:
    - {aisle: A, side: left, kind: parallel, count: 2, slot_width: 2.5, slot_length: 6.5,
       start: 4.0, id_prefix: P, use: accessible}""")
    assert [a.slots for a in lot.access_aisles] == [("P1",), ("P2",)]
    for a, s in zip(lot.access_aisles, lot.slots, strict=True):
        assert shares_long_side(a.shape, s)
        assert a.shape.bounds[1] == pytest.approx(18.0)  # behind the bay: 15.5 + 2.5
    check_clear(lot)


def test_a_single_slot_has_its_aisle_on_the_side_it_names():
    lot = built("""  slots:
    - {id: H, kind: perpendicular, width: 2.5, length: 5.0, aisle: A, side: left, at: 10,
       use: accessible, access_side: left}""")
    (aisle,) = lot.access_aisles
    slot = lot.slots[0]
    assert shares_long_side(aisle.shape, slot)
    # facing into the bay (north), left is west
    assert aisle.shape.centroid.x < slot.shape.centroid.x


def error_of(items: str) -> ScenarioError:
    with pytest.raises(ScenarioError) as info:
        built(items)
    return info.value


def test_an_aisle_over_a_neighbouring_bay_is_refused_at_the_slot():
    err = error_of("""  slots:
    - {id: N, kind: perpendicular, width: 2.5, length: 5.0, aisle: A, side: left, at: 12.5}
    - {id: H, kind: perpendicular, width: 2.5, length: 5.0, aisle: A, side: left, at: 10,
       use: accessible, access_side: right}""")
    assert (err.where.line, err.where.col) == (8, 7)
    assert "access aisle of slot 'H' overlaps slot 'N'" in str(err)


def test_an_aisle_on_the_way_is_refused_at_the_slot():
    # a parallel bay left of a two-way aisle faces its near lane's way, west: its left is
    # the way
    err = error_of("""  slots:
    - {id: P, kind: parallel, width: 2.5, length: 6.5, aisle: A, side: left, at: 10,
       use: accessible, access_side: left}""")
    assert (err.where.line, err.where.col) == (7, 7)
    assert "overlaps aisle 'A' (the vehicular way)" in str(err)


@pytest.mark.parametrize("row, at, words", [
    ("{aisle: A, side: left, kind: perpendicular, count: 1, slot_width: 2.3, "
     "slot_length: 5.0, start: 4, use: accessible}", None, "at least 2.44 m wide"),
    ("{aisle: A, side: left, kind: perpendicular, count: 1, slot_width: 2.5, "
     "slot_length: 5.0, start: 4, use: van_accessible, access_aisle_width: 1.6}",
     None, "at least 2.44 m (96 in)"),
    ("{aisle: A, side: left, kind: perpendicular, count: 1, slot_width: 2.5, "
     "slot_length: 5.0, start: 4, access_aisle_width: 1.6}", "1.6}",
     "for accessible and van-accessible bays"),
    ("{aisle: A, side: left, kind: perpendicular, count: 1, slot_width: 2.5, "
     "slot_length: 5.0, start: 4, use: disabled}", "disabled", "expected one of standard"),
])
def test_a_bay_or_aisle_its_use_refuses_is_a_located_error(row, at, words):
    """At the row (``at`` None) or at the value ``at`` names, on line 7 of the file."""
    line = f"    - {row}"
    err = error_of(f"  rows:\n{line}")
    col = 7 if at is None else line.index(at) + 1
    assert (err.where.line, err.where.col) == (7, col), str(err)
    assert words in str(err)
