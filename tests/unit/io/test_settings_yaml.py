"""A scenario file's ``roadmap`` and ``maneuvers`` sections (and its lot's ``build``, the
rest of whose tests are in tests/unit/lot/test_lot_settings.py): read as what each key
measures, refused at the key that is wrong with the settings' own message, and every
setting has a key."""

from __future__ import annotations

import dataclasses
import math

import pytest

from conftest import position, scenario_from_text
from lotsim.errors import ScenarioError
from lotsim.io.settings_yaml import KEYS, WAY_OUT_KEYS
from lotsim.lot.settings import LotSettings
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.roadmap.settings import RoadmapSettings

LOT = """\
lot:
  boundary: [[0, 0], [30, 0], [30, 20], [0, 20]]
  aisles:
    - {id: main, centerline: [[0, 10], [30, 10]], width: 7.0, direction: one-way}
  rows:
    - {aisle: main, side: left, kind: perpendicular, count: 4, slot_width: 2.5,
       slot_length: 5.0, start: 8.0}
  entrances: [{id: in, x: 3.0, y: 10.0, heading_deg: 0}]
  exits: [{id: out, x: 24.0, y: 10.0, heading_deg: 0}]
"""


def test_a_scenario_without_the_sections_has_the_default_settings():
    sc = scenario_from_text(LOT)
    assert sc.roadmap == RoadmapSettings() and sc.maneuvers == ManeuverSettings()


def test_the_sections_are_read_in_the_units_of_their_keys():
    sc = scenario_from_text(LOT + """\
roadmap:
  turns: {speeds_kmh: [9, 3.6], through_overlap: 12}
  multipoint: {expansion_limit: 800, uturn_land: [1, 6]}
  turnarounds: {margin: 0.25, starts: [0, 3]}
maneuvers:
  margin: 0.15
  first_turn_deg: 30
  ease_ramps: [2.0, 1.0]
  way_out: {weight: 2, cell: 0.25}
""")
    assert sc.roadmap.turns.speeds == (2.5, 1.0)  # km/h → m/s
    assert sc.roadmap.turns.through_overlap == 12.0
    assert sc.roadmap.multipoint.expansion_limit == 800
    assert sc.roadmap.multipoint.uturn_land == (1.0, 6.0)
    assert sc.roadmap.turnarounds == dataclasses.replace(
        RoadmapSettings().turnarounds, margin=0.25, starts=(0.0, 3.0))
    assert sc.roadmap.area_turns == RoadmapSettings().area_turns  # not given: the default
    assert sc.maneuvers.margin == 0.15
    assert math.isclose(sc.maneuvers.first_turn, math.pi / 6)
    assert sc.maneuvers.ease_ramps == (2.0, 1.0)
    # the way out's own search: what is given over its defaults (1500 states, not 3000)
    assert sc.maneuvers.way_out == dataclasses.replace(
        ManeuverSettings().way_out, weight=2.0, cell=0.25)
    assert sc.maneuvers.way_out.expansion_limit == 1500


def test_lengths_in_a_file_in_feet_are_read_as_feet():
    sc = scenario_from_text("units: ft\n" + LOT.replace("[30, 0], [30, 20], [0, 20]",
                                                       "[100, 0], [100, 66], [0, 66]")
                            .replace("[[0, 10], [30, 10]], width: 7.0",
                                     "[[0, 33], [100, 33]], width: 24")
                            .replace("slot_width: 2.5", "slot_width: 8.5")
                            .replace("slot_length: 5.0, start: 8.0",
                                     "slot_length: 18, start: 26")
                            .replace("x: 3.0, y: 10.0", "x: 10, y: 33")
                            .replace("x: 24.0, y: 10.0", "x: 80, y: 33")
                            + "roadmap: {turnarounds: {margin: 0.5}}\n")
    assert math.isclose(sc.roadmap.turnarounds.margin, 0.5 * 0.3048)


@pytest.mark.parametrize(("section", "needle", "told"), [
    ("roadmap:\n  turnarounds: {margn: 0.2}\n", "|margn", "unknown key 'margn' (did you mean "
                                                        "'margin'?)"),
    ("roadmap:\n  turnaround: {margin: 0.2}\n", "|turnaround:", "unknown key 'turnaround'"),
    ("roadmap:\n  turnarounds: {margin: 2}\n", "margin: |2", "turnarounds.margin: expected "
                                                             "0 to 1 m, found 2"),
    ("roadmap:\n  turns: {speeds_kmh: [5, 10]}\n", "speeds_kmh: |[", "from the largest down"),
    ("roadmap:\n  multipoint: {expansion_limit: 2.5}\n", "expansion_limit: |2.5",
     "expected an integer"),
    ("maneuvers:\n  way_out: {expansion_limit: 0}\n", "expansion_limit: |0",
     "maneuvers.way_out.expansion_limit: expected"),
    ("maneuvers:\n  way_out: {uturn_land: [2, 8]}\n", "|uturn_land",
     "unknown key 'uturn_land'"),
    ("maneuvers:\n  closing_radii: [0.5]\n", "closing_radii: |[", "multiples of at least 1"),
    ("maneuvers:\n  margin: 0.1\n  margin: 0.2\n", "|margin: 0.2", "duplicate key 'margin'"),
])
def test_a_wrong_key_or_value_is_refused_where_it_stands(section, needle, told):
    text = LOT + section
    with pytest.raises(ScenarioError) as got:
        scenario_from_text(text)
    line, col = position(text, needle)
    assert (got.value.where.line, got.value.where.col) == (line, col)
    assert told in str(got.value)


def test_a_problem_in_each_section_is_reported_at_once():
    text = LOT + "roadmap: {turnarounds: {margin: 2}}\nmaneuvers: {margin: -1}\n"
    with pytest.raises(ScenarioError) as got:
        scenario_from_text(text)
    assert "roadmap.turnarounds.margin" in str(got.value)
    assert "maneuvers.margin" in str(got.value)


@pytest.mark.parametrize("cls", list(KEYS))
def test_every_setting_has_a_key_in_a_scenario_file(cls):
    assert sorted(name for name, _ in KEYS[cls].values()) == sorted(
        f.name for f in dataclasses.fields(cls))


def test_the_page_shows_every_key_with_its_default():
    """docs/scenario.md's block of the two sections: read as a scenario's, it gives the
    default settings, and it names every key there is."""
    import re

    import yaml

    from conftest import ROOT
    from lotsim.roadmap.settings import GROUPS

    page = (ROOT / "docs" / "scenario.md").read_text()
    block = next(b for b in re.findall(r"```yaml\n(.*?)```", page, re.S)
                 if b.startswith("roadmap:"))
    sc = scenario_from_text(LOT + block)
    assert sc.roadmap == RoadmapSettings() and sc.maneuvers == ManeuverSettings()
    shown = yaml.safe_load(block)
    for group, cls in GROUPS.items():
        assert sorted(shown["roadmap"][group]) == sorted(KEYS[cls])
    assert sorted(shown["maneuvers"]) == sorted(KEYS[ManeuverSettings])
    assert sorted(shown["maneuvers"]["way_out"]) == sorted(WAY_OUT_KEYS)


def test_the_page_shows_every_key_of_lot_build_with_its_default():
    """docs/scenario.md's block of ``lot.build``: read as a scenario's lot's, it gives the
    default settings, and it names every key there is."""
    import re

    import yaml

    from conftest import ROOT

    page = (ROOT / "docs" / "scenario.md").read_text()
    block = next(b for b in re.findall(r"```yaml\n(.*?)```", page, re.S)
                 if b.startswith("lot:\n  build:"))
    assert LOT.startswith("lot:\n")
    sc = scenario_from_text(block + LOT.removeprefix("lot:\n"))
    assert sc.lot.settings == LotSettings()
    assert sorted(yaml.safe_load(block)["lot"]["build"]) == sorted(KEYS[LotSettings])
