"""What is paved (``lot.paved``): the pavement's shape against closed forms and shapely,
the scenario key's errors, aisles drawn near one another without joining, and a run on a
paved lot that keeps every car on the pavement (checked by ``lotsim check``, which also
fails a car planted off it)."""

from __future__ import annotations

import copy
import json
import math

import pytest
import shapely
from shapely.geometry import LineString, box

from conftest import position, scenario_from_text
from lotsim.errors import ScenarioError
from lotsim.io.result import result_dict
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.lot.pavement import loose_ends
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import simulate
from lotsim.verify import check_result

T_LOT = """\
name: paved_t
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [60, 0], [60, 40], [0, 40]]
  paved: {PAVED}
  aisles:
    - {id: main, centerline: [[0, 25], [60, 25]], width: 7.0}
    - {id: spur, centerline: [[30, 0], [30, SPUR_END]], width: 7.0}
  rows:
    - {aisle: main, side: left, kind: perpendicular, count: 8, slot_width: 2.5,
       slot_length: 5.0, start: 20}
    - {aisle: spur, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 8}
  entrances: [{id: in, x: 31.75, y: 6, heading_deg: 90}]
  exits: [{id: out, x: 28.25, y: 6, heading_deg: 270}]
"""


def t_lot(paved: str = "{}", spur_end: float = 25.0, traffic: str = ""):
    text = T_LOT.replace("{PAVED}", paved).replace("SPUR_END", f"{spur_end:g}") + traffic
    sc = scenario_from_text(text)
    return sc, build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))


def test_a_lot_without_the_key_is_paved_wall_to_wall():
    sc, lot = t_lot()
    text = T_LOT.replace("  paved: {PAVED}\n", "").replace("SPUR_END", "25")
    whole = build_lot(scenario_from_text(text).lot, lot.design)
    assert whole.pavement is None and whole.ground.equals(whole.boundary)
    assert lot.pavement is not None and lot.ground.area < lot.boundary.area


@pytest.mark.parametrize("radius", [1.5, 3.0, 4.0])
def test_the_kerb_corners_of_a_t_are_two_quarter_circle_fillets(radius):
    """Where the spur meets the main aisle, the pavement beyond the two strips and the slots
    is the two inside corners rounded by the kerb radius: 2 (r² - π r² / 4)."""
    _, lot = t_lot(f"{{corner_radius: {radius:g}}}")
    strips = shapely.union_all([a.polygon for a in lot.aisles.values()]
                               + [s.shape for s in lot.slots])
    extra = lot.pavement.difference(strips).area
    assert extra == pytest.approx(2 * radius ** 2 * (1 - math.pi / 4), rel=0.01)


def test_the_pavement_is_the_aisles_slots_and_areas_within_the_boundary():
    apron = [[40, 0], [60, 0], [60, 10], [40, 10]]
    _, lot = t_lot(f"{{corner_radius: 0, areas: [{{id: apron, polygon: {apron}}}]}}")
    expected = shapely.union_all([
        box(0, 21.5, 60, 28.5), box(26.5, 0, 33.5, 25), box(40, 0, 60, 10),
        *[s.shape for s in lot.slots]])
    assert lot.pavement.symmetric_difference(expected).area < 1e-3
    # without the aisles, only the areas and the slots are paved
    paved_aisles = "[{id: a, polygon: [[0, 21.5], [60, 21.5], [60, 28.5], [0, 28.5]]}, " \
                   "{id: b, polygon: [[26.5, 0], [33.5, 0], [33.5, 21.5], [26.5, 21.5]]}]"
    _, bare = t_lot(f"{{aisles: false, areas: {paved_aisles}}}")
    assert bare.pavement.difference(expected).area < 1e-3
    assert expected.difference(bare.pavement).area == pytest.approx(200.0, rel=1e-3)  # apron


def test_aisles_that_do_not_meet_leave_the_ground_between_unpaved_and_say_so():
    _, lot = t_lot(spur_end=20.0)  # the spur's end, 1.5 m from the main aisle's strip
    gap = box(26.5, 20.0, 33.5, 21.5)
    assert lot.pavement.intersection(gap).area < 1e-6
    (warning,) = loose_ends(lot.aisles, lot.pavement)
    assert "aisle 'spur' ends 1.50 m short of aisle 'main'" in warning
    assert "not paved" in warning
    _, joined = t_lot()
    assert loose_ends(joined.aisles, joined.pavement) == []
    # an end that joins one aisle is not short of another nearby (a spur meeting the first
    # aisle 6.5 m from a cross aisle)
    text = T_LOT.replace("{PAVED}", "{}").replace("SPUR_END", "25").replace(
        "  aisles:\n", "  aisles:\n    - {id: west, centerline: [[23.5, 25], [23.5, 40]], "
        "width: 7.0}\n", 1).replace("slot_length: 5.0, start: 20}", "slot_length: 5.0, "
                                     "start: 30}")
    sc = scenario_from_text(text)
    near = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    assert loose_ends(near.aisles, near.pavement) == []


def test_the_paved_key_is_checked_where_it_is_written():
    with pytest.raises(ScenarioError) as err:
        t_lot("{aisles: false}")
    where = err.value.where
    assert (where.line, where.col, where.key) == (*position(T_LOT, "paved: |{"),
                                                     "lot.paved")
    assert "expected paved areas" in str(err.value)
    with pytest.raises(ScenarioError, match="unknown key 'kerb'"):
        t_lot("{kerb: 2}")
    with pytest.raises(ScenarioError, match="corner_radius"):
        t_lot("{corner_radius: -1}")


def test_an_aisle_off_the_pavement_is_refused_saying_so():
    text = T_LOT.replace("{PAVED}", "{aisles: false, areas: [{id: a, polygon: "
                         "[[0, 21.5], [60, 21.5], [60, 28.5], [0, 28.5]]}]}")
    with pytest.raises(ScenarioError, match="pavement|paved"):
        sc = scenario_from_text(text.replace("SPUR_END", "25"))
        build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))


@pytest.fixture(scope="module")
def paved_run():
    traffic = "traffic:\n  stream: {count: 6, rate_per_hour: 300, dwell: [20, 60]}\n"
    sc, _ = t_lot(traffic=traffic)
    return result_dict(simulate(sc, lot_graph=prepare_graph(sc)))


def test_a_run_on_a_paved_lot_keeps_every_car_on_the_pavement(paved_run):
    doc = paved_run
    assert doc["lot"]["paved"], "the result says what is paved"
    assert {v["status"] for v in doc["vehicles"]} == {"departed"}
    report = check_result(json.loads(json.dumps(doc)))
    assert report.ok, report.violations


def test_the_checker_fails_a_car_that_leaves_the_pavement(paved_run):
    """Planted fault: the pavement shrunk to the main aisle, where the cars come in by the
    spur: every car leaves it on its way in."""
    doc = copy.deepcopy(paved_run)
    doc["lot"]["paved"] = [[[[0, 21.5], [60, 21.5], [60, 28.5], [0, 28.5]]]]
    report = check_result(doc)
    rules = {v.rule for v in report.violations}
    assert rules == {"pavement"}
    assert len(report.violations) == len(doc["vehicles"])


def test_the_checker_reads_a_malformed_pavement_as_a_structure_error(paved_run):
    doc = copy.deepcopy(paved_run)
    doc["lot"]["paved"] = [[[[0, 0], [1, 1]]]]
    report = check_result(doc)
    assert [v.rule for v in report.violations] == ["structure"]
    assert "lot.paved" in report.violations[0].message


def test_the_drawing_carries_the_pavement(paved_run):
    from lotsim.io.lot_json import lot_from_json

    lot = lot_from_json(paved_run["lot"]["drawing"])
    line = LineString([(30, 0), (30, 25)]).buffer(3.5, cap_style="flat")
    assert lot.pavement is not None and lot.pavement.covers(line.buffer(-0.01))
    assert not lot.pavement.covers(box(0, 0, 5, 5))


@pytest.mark.slow
def test_the_same_traffic_on_the_lot_paved_wall_to_wall_crosses_that_ground(paved_run):
    """The test above can fail: planned on the lot paved wall to wall, the same cars cut
    the kerb corners, which the checker sees against the paved lot's pavement."""
    traffic = "traffic:\n  stream: {count: 6, rate_per_hour: 300, dwell: [20, 60]}\n"
    text = T_LOT.replace("  paved: {PAVED}\n", "").replace("SPUR_END", "25") + traffic
    sc = scenario_from_text(text)
    doc = result_dict(simulate(sc, lot_graph=prepare_graph(sc)))
    doc["lot"]["paved"] = paved_run["lot"]["paved"]
    report = check_result(json.loads(json.dumps(doc)))
    assert "pavement" in {v.rule for v in report.violations}


@pytest.mark.slow
def test_a_parallel_slot_on_a_paved_lot_is_parked_in_up_to_the_kerb():
    """A car backing into a free-standing parallel bay swings its corner up to the
    pavement's edge: the margin it keeps to walls is not kept to the kerb."""
    import lotsim
    from conftest import ROOT

    text = (ROOT / "scenarios" / "example.yaml").read_text().replace(
        "  speed_limit_kmh: 20           # optional, default 20\n",
        "  speed_limit_kmh: 20           # optional, default 20\n  paved: {aisles: true}\n", 1)
    report = lotsim.validate(text)
    assert report.prepared.lot_graph.lot.pavement is not None
    assert "X2" in report.usable()["valet"] and "X2" in report.usable()["van"]


def test_the_inside_of_an_aisles_bends_is_paved_where_its_lanes_run():
    """A lane rounds the corners of its aisle's centre line, and a car on the inner lane
    of a two-way aisle cuts inside the strip's corner: that ground is the aisle's too."""
    text = """\
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [60, 0], [60, 60], [0, 60]]
  paved: {}
  aisles:
    - {id: bend, centerline: [[0, 10], [40, 10], [40, 60]], width: 7.0}
  entrances: [{id: in, x: 3, y: 8.25, heading_deg: 0}]
"""
    sc = scenario_from_text(text)
    lot = build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))
    strip = lot.aisles["bend"].polygon
    cut = False
    for lane in lot.lanes:
        bodies = shapely.polygons(lot.design.footprints(lane.sample(0.2)))
        bodies = shapely.intersection(bodies, lot.boundary)  # a gate pokes out of the lot
        assert shapely.covers(lot.pavement.buffer(1e-6), bodies).all(), lane.id
        cut |= not shapely.covers(strip.buffer(1e-6), bodies).all()
    assert cut, "the strip alone holds the lanes: this lot tests nothing"
