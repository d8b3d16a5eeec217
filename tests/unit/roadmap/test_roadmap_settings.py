"""The roadmap's settings: each group checks its values, a build is made with the settings it
is given (a memo made with others is refused), and setting a value other than its default
changes the graph the way the setting says."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from small_lots import TINY_TEE

from conftest import ROOT, scenario_from_text
from lotsim.errors import SettingsError
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.roadmap.assemble import build_graph
from lotsim.roadmap.memo import RoadmapMemo, designs_of
from lotsim.roadmap.settings import (
    AreaTurnSettings,
    MultipointSettings,
    RoadmapSettings,
    TurnaroundSettings,
    TurnSettings,
)

LOTS = ROOT / "scenarios" / "lots"


def _lot(sc):
    return build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))


def _edges(lg, kind: str) -> list[tuple[tuple[str, str], tuple]]:
    """The edges of ``kind``: (from lane, to lane) and the path."""
    g = lg.graph
    return [((g.nodes[u]["lane"], g.nodes[v]["lane"]), d["path"])
            for u, v, d in g.edges(data=True) if d["kind"] == kind]


# -- checked on construction ------------------------------------------------------------------
@pytest.mark.parametrize(("cls", "name", "value"), [
    (TurnSettings, "speeds", ()),
    (TurnSettings, "speeds", (1.0, 2.0)),  # not fastest first
    (TurnSettings, "through_overlap", -1.0),
    (AreaTurnSettings, "radii", (0.5,)),
    (AreaTurnSettings, "leads", (0.0, 3.0)),
    (AreaTurnSettings, "speeds", ("slow",)),
    (MultipointSettings, "expansion_limit", 0),
    (MultipointSettings, "headings", 2.5),
    (MultipointSettings, "weight", 0.9),
    (MultipointSettings, "reverse", math.inf),
    (MultipointSettings, "uturn_land", (2.0,)),
    (MultipointSettings, "closing_radii", (0.8, 1.0)),
    (TurnaroundSettings, "margin", 1.5),
    (TurnaroundSettings, "max_changes", -1),
    (TurnaroundSettings, "starts", (-2.0,)),
    (TurnaroundSettings, "probe", 0.0),
    (RoadmapSettings, "turnarounds", MultipointSettings()),
])
def test_a_value_out_of_range_is_refused_naming_its_setting(cls, name, value):
    with pytest.raises(SettingsError) as got:
        cls(**{name: value})
    assert got.value.name == name


def test_a_list_given_for_a_tuple_is_kept_as_a_tuple_and_the_settings_hash():
    s = TurnaroundSettings(starts=[0.0, 3.0])
    assert s.starts == (0.0, 3.0)
    assert hash(RoadmapSettings(turnarounds=s)) == hash(
        RoadmapSettings(turnarounds=TurnaroundSettings(starts=(0.0, 3.0))))


# -- a build and its memo ---------------------------------------------------------------------
def test_a_memo_made_with_other_settings_is_refused():
    sc = load_scenario(LOTS / "culdesac.yaml")
    lot = _lot(sc)
    memo = RoadmapMemo(lot)
    wider = RoadmapSettings(turnarounds=TurnaroundSettings(margin=0.2))
    with pytest.raises(SettingsError, match="settings it was made with"):
        build_graph(lot, vehicles=sc.vehicle_types, memo=memo, settings=wider)
    with pytest.raises(SettingsError, match="expected RoadmapSettings"):
        build_graph(lot, settings={"turnarounds": {"margin": 0.2}})


def test_the_store_keys_of_a_lot_differ_with_its_settings():
    # a piece remembered from a preparation with other settings is never recalled: every
    # piece's key starts from the lot's key, which holds the settings
    sc = load_scenario(LOTS / "culdesac.yaml")
    lot = _lot(sc)
    plain = RoadmapMemo(lot, {}).lot_key
    assert RoadmapMemo(lot, {}, settings=RoadmapSettings()).lot_key == plain
    other = RoadmapSettings(multipoint=MultipointSettings(expansion_limit=500))
    assert RoadmapMemo(lot, {}, settings=other).lot_key != plain


# -- a setting changes what it says ------------------------------------------------------------
def test_a_wider_turnaround_margin_keeps_every_turnaround_that_far_from_the_bays_and_edge():
    """The cul-de-sac's turnarounds, checked with shapely on footprints 5 cm apart: with a
    margin of 0.3 m every body stays 0.3 m clear of every slot and of the lot's edge; with
    the default 0.1 m some come nearer, so the margin is what moved them."""
    sc = load_scenario(LOTS / "culdesac.yaml")
    lot = _lot(sc)
    slots = shapely.union_all([s.shape for s in lot.slots])
    edge = lot.boundary.exterior

    def nearest(margin: float) -> float:
        settings = RoadmapSettings(turnarounds=TurnaroundSettings(margin=margin))
        turnarounds = _edges(build_graph(lot, vehicles=sc.vehicle_types, settings=settings),
                       "turnaround")
        assert turnarounds
        poses = np.concatenate([s.sample(0.05) for _, path in turnarounds for s in path])
        bodies = shapely.polygons(lot.design.footprints(poses))
        return min(shapely.distance(bodies, slots).min(), shapely.distance(bodies, edge).min())

    assert nearest(0.3) >= 0.3 - 1e-3
    assert nearest(0.1) < 0.3 - 1e-3


@pytest.mark.slow
def test_an_expansion_limit_too_small_leaves_the_short_arm_without_its_multi_point_turn():
    """The tee's only way from the spur onto the east-bound lane is a multi-point turn: a
    search that may expand one state finds none, and the dead end it also needed is noted."""
    sc = scenario_from_text(TINY_TEE)
    lot = _lot(sc)
    onto_arm = ("spur>", "a0>")
    plain = build_graph(lot, vehicles=sc.vehicle_types)
    assert onto_arm in [k for k, _ in _edges(plain, "turnaround")]
    assert not any("dead end" in note for note in plain.skipped_turns)
    starved = build_graph(lot, vehicles=sc.vehicle_types, settings=RoadmapSettings(
        multipoint=MultipointSettings(expansion_limit=1)))
    assert onto_arm not in [k for k, _ in _edges(starved, "turnaround")]
    assert any("dead end" in note for note in starved.skipped_turns)


def test_a_dead_end_without_a_turnaround_is_noted_with_the_settings_searched_with():
    """The cul-de-sac's closed end, where a car turns round in a few strokes: allowed one
    direction change, and a multi-point search of one state, it has none, and its note
    says what was searched."""
    sc = load_scenario(LOTS / "culdesac.yaml")
    lot = _lot(sc)
    assert _edges(build_graph(lot, vehicles=sc.vehicle_types), "turnaround")
    starved = build_graph(lot, vehicles=sc.vehicle_types, settings=RoadmapSettings(
        multipoint=MultipointSettings(expansion_limit=1),
        turnarounds=TurnaroundSettings(max_changes=1, margin=0.15)))
    assert not _edges(starved, "turnaround")
    notes = [n for n in starved.skipped_turns if "dead end" in n]
    assert notes and all("up to 1 direction changes keeping 0.15 m clear" in n for n in notes)


def test_junction_turns_are_sized_only_for_the_design_speeds_given():
    """A turn for speed v has an arc of radius max(R, v²/a_lat), or 2 R, or 3 R (a turn
    through the junction's area: 1 R or 1.5 R). With only a crawl (1.5 km/h, far below any
    radius's speed) every arc is one of those multiples of some type's radius; with the
    default speeds (up to 15 km/h) some arc is sized by its speed instead."""
    sc = load_scenario(ROOT / "scenarios" / "mixed_lot.yaml")
    lot = _lot(sc)
    designs = designs_of(sc.vehicle_types) or {"": lot.design}
    radii = [f * d.min_radius for d in designs.values() for f in (1.0, 1.5, 2.0, 3.0)]

    def sized_by_speed(settings) -> list[float]:
        turns = _edges(build_graph(lot, vehicles=sc.vehicle_types, settings=settings), "turn")
        assert turns
        arcs = [1 / abs(s.curvature) for _, path in turns for s in path
                if s.sharpness == 0.0 and s.curvature != 0.0]
        return [r for r in arcs if not any(math.isclose(r, x, rel_tol=1e-6) for x in radii)]

    assert sized_by_speed(RoadmapSettings(turns=TurnSettings(speeds=(1.5 / 3.6,)))) == []
    assert sized_by_speed(RoadmapSettings()) != []


@pytest.mark.slow
def test_the_default_settings_make_the_graph_made_without_any():
    sc = scenario_from_text(TINY_TEE)
    lot = _lot(sc)
    assert (_edges(build_graph(lot, vehicles=sc.vehicle_types, settings=RoadmapSettings()),
                   "turnaround")
            == _edges(build_graph(lot, vehicles=sc.vehicle_types), "turnaround"))
