"""The built lot's settings (lotsim.lot.settings.LotSettings): each checked on
construction, each changing what it says when the lot is built (the lanes' clearance, the
crawl speed of bends, the sweeps of lanes and junction turns), read from a scenario's
``lot.build`` in the file's units, and part of the prepared lot's cache key."""

from __future__ import annotations

import dataclasses
import math

import pytest
import shapely
from small_lots import CROSS, SHORT_LEGS, lot_of

from conftest import position, scenario_from_text
from lotsim.core.diskcache import key
from lotsim.core.geometry import sample_segments
from lotsim.errors import ScenarioError, SettingsError
from lotsim.lot.build import build_lot, lane_collider, obstacle_polygons
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle
from lotsim.lot.settings import LotSettings
from lotsim.roadmap.junctions import junction_turns
from lotsim.roadmap.remembered import lot_key
from lotsim.sim.preparation import PreparedFrom


def _built(text: str, **settings):
    sc = scenario_from_text(text)
    spec = dataclasses.replace(sc.lot, settings=LotSettings(**settings)) if settings else sc.lot
    return build_lot(spec, DesignVehicle.envelope(sc.vehicle_types))


# -- checked on construction ------------------------------------------------------------------
@pytest.mark.parametrize(("name", "bad", "told"), [
    ("lane_clearance", -0.01, "expected 0 to 1 m, found -0.01"),
    ("lane_clearance", 1.5, "expected 0 to 1 m, found 1.5"),
    ("lane_clearance", "0.2", "expected a number"),
    ("sweep", 0.0, "expected 0.01 to 1 m, found 0"),
    ("sweep", 2.0, "expected 0.01 to 1 m, found 2"),
    ("sweep", math.nan, "expected 0.01 to 1 m"),
    ("sweep", True, "expected a number"),
    ("crawl_speed", 0.0, "expected 0.05 to 5 m/s (0.18 to 18 km/h), found 0 m/s (0 km/h)"),
    ("crawl_speed", 10.0, "found 10 m/s (36 km/h)"),
    ("crawl_speed", math.inf, "expected 0.05 to 5 m/s"),
    ("crawl_speed", None, "found None"),
])
def test_a_value_out_of_range_is_refused_with_its_name(name, bad, told):
    with pytest.raises(SettingsError) as got:
        LotSettings(**{name: bad})
    assert got.value.name == name
    assert told in got.value.message


def test_the_ranges_ends_are_taken():
    assert LotSettings(lane_clearance=0.0, sweep=0.01, crawl_speed=0.05)
    assert LotSettings(lane_clearance=1.0, sweep=1.0, crawl_speed=5.0)


def test_a_lot_spec_refuses_settings_of_another_kind():
    sc = scenario_from_text(AISLE.replace("WIDTH", "3.0"))
    with pytest.raises(SettingsError, match="settings: expected LotSettings, found dict"):
        dataclasses.replace(sc.lot, settings={"sweep": 0.1})


# -- each changes what it says ------------------------------------------------------------------
AISLE = """\
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 20], [0, 20]]
  aisles:
    - {id: a, direction: one-way, width: WIDTH, centerline: [[0, 10], [40, 10]]}
  entrances: [{id: in, x: 3, y: 10, heading_deg: 0}]
"""
"""A one-way aisle across a bare lot, for the valet (1.8 m wide)."""


def test_the_built_lot_keeps_the_settings_it_was_built_with():
    settings = LotSettings(lane_clearance=0.2, sweep=0.1, crawl_speed=0.5)
    assert _built(AISLE.replace("WIDTH", "3.0")).settings == LotSettings()
    assert _built(AISLE.replace("WIDTH", "3.0"), **dataclasses.asdict(settings)).settings \
        == settings


def test_a_wider_lane_clearance_refuses_an_aisle_the_default_takes():
    text = AISLE.replace("WIDTH", "2.15")  # 1.8 m + 2 × 0.15 m = 2.10 m: it fits
    assert _built(text).aisles["a"].width == 2.15
    with pytest.raises(ScenarioError) as got:
        _built(text, lane_clearance=0.2)  # 1.8 m + 2 × 0.2 m = 2.20 m
    assert got.value.where.key == "lot.aisles[0]"
    assert "2 × 0.20 m lane clearance) = 2.20 m, found 2.15 m" in str(got.value)
    assert _built(text, lane_clearance=0.0).aisles["a"].width == 2.15




def test_a_higher_crawl_speed_refuses_a_bend_the_default_takes():
    text = SHORT_LEGS.replace("LEG", "16")  # an 11 m leg: its corners are driven at 0.80 m/s
    aisle = _built(text).aisles["ring"]
    design = _built(text).design
    speed = design.max_curvature_rate / max(aisle.corners)
    assert 0.25 < speed < 0.85
    assert _built(text, crawl_speed=0.75).aisles["ring"].corners == pytest.approx(
        aisle.corners, rel=1e-9)
    with pytest.raises(ScenarioError, match="even at a crawl of 3.1 km/h"):
        _built(text, crawl_speed=0.85)


def test_a_lower_crawl_speed_takes_a_bend_the_default_refuses():
    text = SHORT_LEGS.replace("LEG", "15.1")  # a 10.1 m leg: corners at about 0.12 m/s
    with pytest.raises(ScenarioError, match="even at a crawl of 0.9 km/h"):
        _built(text)
    aisle = _built(text, crawl_speed=0.05).aisles["ring"]
    assert aisle.corners and max(aisle.corners) > aisle.bend_sharpness


DEAD_END = """\
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 20], [0, 20]]
  aisles:
    - {id: a, direction: one-way, width: 4.0, centerline: [[0, 10], [30, 10]]}
  walls: [{id: end, polygon: [[30, 5], [31, 5], [31, 15], [30, 15]]}]
  entrances: [{id: in, x: 3, y: 10, heading_deg: 0}]
"""
"""A one-way lane 30 m long into a wall: the valet (3.9 m ahead of its rear axle) touches
it past station 26.1 m."""


@pytest.mark.parametrize(("sweep", "length"), [(0.2, 26.0), (0.7, 37 * 30 / 43), (1.0, 26.0)])
def test_a_lane_into_a_wall_is_cut_back_to_its_last_clear_footprint_of_the_sweep(sweep,
                                                                                length):
    # the lane is swept with footprints `sweep` apart (30 m in equal steps of at most it)
    # and ends at the last one before the body meets the wall: within a step of 26.1 m
    (lane,) = _built(DEAD_END, sweep=sweep).lanes
    assert lane.length == pytest.approx(length, abs=1e-9)
    assert 26.1 - sweep < lane.length < 26.1


def _swept(lot, turn, step: float):
    bodies = Collider.sweeps(lot.design.footprints(sample_segments(turn.segments, step)[0]))
    return shapely.union_all(shapely.convex_hull(shapely.multipoints(bodies)))


def test_the_junction_turns_are_swept_with_the_lots_sweep():
    # a post of 2 mm where the default sweep of a turn's body reaches and a sweep with
    # footprints 1 m apart (whose hulls cut the corners of the curve) does not: the lot
    # built with the coarse sweep keeps the turn, the default refuses it
    lot = lot_of(CROSS)
    turns, _ = junction_turns(lot, lane_collider(lot))
    turn = turns[0]
    gap = _swept(lot, turn, 0.2).difference(_swept(lot, turn, 1.0)).buffer(-0.002)
    post = gap.representative_point().buffer(0.001)
    collider = Collider([*obstacle_polygons(lot.areas, lot.slots), ("post", post)],
                        lane_collider(lot).allowed, edge=lot.edge)
    fine, _ = junction_turns(lot, collider)
    coarse, _ = junction_turns(dataclasses.replace(lot, settings=LotSettings(sweep=1.0)),
                               collider)
    assert turn not in fine and turn in coarse
    assert len(fine) == len(coarse)  # the default takes another design of that turn


# -- the scenario file ----------------------------------------------------------------------------
def test_lot_build_is_read_in_the_files_units():
    sc = scenario_from_text(AISLE.replace("WIDTH", "3.0").replace(
        "  entrances:", "  build: {lane_clearance: 0.2, sweep: 0.1, crawl_speed_kmh: 1.8}\n"
                        "  entrances:"))
    assert sc.lot.settings == LotSettings(lane_clearance=0.2, sweep=0.1, crawl_speed=0.5)
    feet = scenario_from_text("units: ft\n" + AISLE.replace(
        "[[0, 0], [40, 0], [40, 20], [0, 20]]", "[[0, 0], [130, 0], [130, 66], [0, 66]]")
        .replace("width: WIDTH, centerline: [[0, 10], [40, 10]]",
                 "width: 10, centerline: [[0, 33], [130, 33]]")
        .replace("x: 3, y: 10", "x: 10, y: 33")
        .replace("  entrances:", "  build: {lane_clearance: 0.5, sweep: 0.25, "
                                 "crawl_speed_kmh: 1.8}\n  entrances:"))
    assert feet.lot.settings.lane_clearance == pytest.approx(0.5 * 0.3048, abs=1e-9)
    assert feet.lot.settings.sweep == pytest.approx(0.25 * 0.3048, abs=1e-9)
    assert feet.lot.settings.crawl_speed == 0.5  # km/h in any file
    assert scenario_from_text(AISLE.replace("WIDTH", "3.0")).lot.settings == LotSettings()


@pytest.mark.parametrize(("build", "needle", "told"), [
    ("  build: {sweeep: 0.1}\n", "|sweeep", "unknown key 'sweeep' (did you mean 'sweep'?)"),
    ("  build: {crawl_speed: 0.5}\n", "|crawl_speed", "unknown key 'crawl_speed'"),
    ("  build: {sweep: 2}\n", "sweep: |2", "lot.build.sweep: expected 0.01 to 1 m, found 2"),
    ("  build: {lane_clearance: -1}\n", "lane_clearance: |-1",
     "lot.build.lane_clearance: expected 0 to 1 m"),
    ("  build: {crawl_speed_kmh: 36}\n", "crawl_speed_kmh: |36",
     "lot.build.crawl_speed_kmh: expected 0.05 to 5 m/s (0.18 to 18 km/h), found 10 m/s "
     "(36 km/h)"),
    ("  build: {sweep: abc}\n", "sweep: |abc", "expected a number"),
    ("  build: [0.1]\n", "build: |[", "expected a mapping"),
])
def test_a_wrong_key_or_value_under_lot_build_is_refused_where_it_stands(build, needle, told):
    text = AISLE.replace("WIDTH", "3.0").replace("  entrances:", build + "  entrances:")
    with pytest.raises(ScenarioError) as got:
        scenario_from_text(text)
    assert (got.value.where.line, got.value.where.col) == position(text, needle)
    assert told in str(got.value)


@pytest.mark.parametrize(("section", "needle"), [
    ("build: {sweep: 0.1}\n", "|build"),  # at the top, not under lot
    ("roadmap: {build: {sweep: 0.1}}\n", "|build"),
    ("maneuvers: {lane_clearance: 0.2}\n", "|lane_clearance"),
])
def test_a_lot_setting_out_of_its_place_is_an_unknown_key_where_it_stands(section, needle):
    text = AISLE.replace("WIDTH", "3.0") + section
    with pytest.raises(ScenarioError) as got:
        scenario_from_text(text)
    assert (got.value.where.line, got.value.where.col) == position(text, needle)
    assert "unknown key" in str(got.value)


# -- the cache key --------------------------------------------------------------------------------
@pytest.mark.parametrize("change", [{"lane_clearance": 0.2}, {"sweep": 0.1},
                                    {"crawl_speed": 0.3}])
def test_the_prepared_lots_and_the_roadmap_stores_keys_change_with_a_lot_setting(change):
    sc = scenario_from_text(AISLE.replace("WIDTH", "3.0"))

    def prepared(spec):
        return key("prepared", PreparedFrom(spec, tuple(sc.vehicle_types), sc.parked_vehicle,
                                            (False,), 4.0, sc.maneuvers, sc.roadmap))

    other = dataclasses.replace(sc.lot, settings=LotSettings(**change))
    same = dataclasses.replace(sc.lot, settings=LotSettings())
    assert prepared(same) == prepared(sc.lot)
    assert prepared(other) != prepared(sc.lot)
    design = DesignVehicle.envelope(sc.vehicle_types)
    assert lot_key(build_lot(other, design)) != lot_key(build_lot(sc.lot, design))
