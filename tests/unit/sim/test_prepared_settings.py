"""A prepared lot is made with its scenario's lot, roadmap and maneuver settings, cached
under them, and a run's result.json says which they were, in numbers that make them
again."""

from __future__ import annotations

import json

import pytest

import lotsim
import lotsim.api
from lotsim.api.scenarios import EXAMPLE
from lotsim.errors import ScenarioError, SettingsError
from lotsim.io.result import result_dict
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.settings import LotSettings
from lotsim.maneuvers.settings import ManeuverSettings
from lotsim.roadmap.settings import (
    GROUPS,
    MultipointSettings,
    RoadmapSettings,
    TurnaroundSettings,
)
from lotsim.sim.preparation import prepare_lot

WIDER = RoadmapSettings(turnarounds=TurnaroundSettings(margin=0.25),
                        multipoint=MultipointSettings(expansion_limit=2000))


@pytest.fixture
def folder(tmp_path, monkeypatch):
    where = tmp_path / "cache"
    monkeypatch.setenv("LOTSIM_CACHE_DIR", str(where))
    return where


def _maneuvers(prepared) -> dict:
    g = prepared.lot_graph.graph
    return {(u, v): {k: m.segments for k, m in d["maneuvers"].items()}
            for u, v, d in g.edges(data=True) if d["kind"] == "park"}


def test_a_lot_prepared_with_other_settings_is_prepared_again_not_loaded(folder):
    sc = load_scenario(EXAMPLE)
    assert not prepare_lot(sc).lot_graph.from_cache
    assert prepare_lot(sc).lot_graph.from_cache
    assert not lotsim.prepare(sc, roadmap=WIDER).lot_graph.from_cache
    assert lotsim.prepare(sc, roadmap=WIDER).lot_graph.from_cache
    assert not lotsim.prepare(sc, maneuvers=ManeuverSettings(margin=0.2)).lot_graph.from_cache
    # the margin given to prepare_lot and the same margin in the settings are one lot
    assert prepare_lot(sc, margin=0.2).lot_graph.from_cache
    assert not lotsim.prepare(sc, maneuvers=ManeuverSettings(max_changes=4)).lot_graph.from_cache
    assert not lotsim.prepare(sc, lot=LotSettings(sweep=0.1)).lot_graph.from_cache
    assert lotsim.prepare(sc, lot=LotSettings(sweep=0.1)).lot_graph.from_cache


def test_the_lot_settings_given_to_prepare_build_the_lot():
    prepared = lotsim.prepare(EXAMPLE, lot=LotSettings(lane_clearance=0.2), cache=False)
    assert prepared.lot.settings == prepared.scenario.lot.settings == LotSettings(
        lane_clearance=0.2)
    # the example's 7 m one-way aisle as a two-way one: room for its two lanes with the
    # default clearance, not with 1 m each side
    two_way = EXAMPLE.replace("direction: one-way", "direction: two-way")
    assert lotsim.prepare(two_way, cache=False).lot.aisles["main"]
    with pytest.raises(ScenarioError, match="1.00 m lane clearance"):
        lotsim.prepare(two_way, lot=LotSettings(lane_clearance=1.0), cache=False)


def test_the_scenarios_maneuver_settings_plan_its_maneuvers():
    sc = load_scenario(EXAMPLE)
    plain = prepare_lot(sc, cache=False)
    wide = lotsim.prepare(sc, maneuvers=ManeuverSettings(margin=0.3), cache=False)
    assert wide.maneuver_planner.settings.margin == 0.3
    assert plain.maneuver_planner.settings == ManeuverSettings()
    assert _maneuvers(wide) != _maneuvers(plain)
    case = lotsim.api.maneuver_case(sc, "N3", maneuvers=ManeuverSettings(margin=0.3))
    assert case.planner.margin == 0.3
    assert lotsim.api.maneuver_case(sc, "N3", maneuvers=ManeuverSettings(margin=0.3),
                                    margin=0.2).planner.margin == 0.2


def test_prepare_refuses_settings_of_another_kind():
    with pytest.raises(SettingsError, match="roadmap: expected RoadmapSettings"):
        lotsim.prepare(EXAMPLE, roadmap=ManeuverSettings(), cache=False)
    with pytest.raises(SettingsError, match="maneuvers: expected ManeuverSettings"):
        lotsim.prepare(EXAMPLE, maneuvers={"margin": 0.2}, cache=False)
    with pytest.raises(SettingsError, match="lot: expected LotSettings"):
        lotsim.prepare(EXAMPLE, lot=RoadmapSettings(), cache=False)


def test_result_json_writes_the_settings_the_lot_was_prepared_with_and_they_make_them_again():
    lot = "\nlot:\n  build: {lane_clearance: 0.1, crawl_speed_kmh: 1.8}\n"
    text = EXAMPLE.replace("\nlot:\n", lot) + ("roadmap:\n  turnarounds: {margin: 0.25}\n"
                                               "  multipoint: {expansion_limit: 2000}\n"
                                               "maneuvers: {margin: 0.2, "
                                               "ease_ramps: [2.0, 1.0]}\n")
    prepared = lotsim.prepare(text, cache=False)
    doc = json.loads(json.dumps(result_dict(lotsim.run(prepared))))
    written = doc["settings"]
    assert written["roadmap"]["turnarounds"]["margin"] == 0.25
    assert written["maneuvers"]["margin"] == 0.2
    assert written["lot"] == {"lane_clearance": 0.1, "sweep": 0.2, "crawl_speed": 0.5}
    assert LotSettings(**written["lot"]) == prepared.scenario.lot.settings
    again = RoadmapSettings(**{name: GROUPS[name](**values)
                               for name, values in written["roadmap"].items()})
    assert again == WIDER == prepared.scenario.roadmap
    way_out = MultipointSettings(**written["maneuvers"]["way_out"])
    assert ManeuverSettings(**{**written["maneuvers"], "way_out": way_out}
                            ) == prepared.scenario.maneuvers
