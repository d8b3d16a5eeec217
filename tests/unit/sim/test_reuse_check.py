"""The reuse check of a preparation: every piece recalled from a store is worked out again
and compared. With the real keys it passes on shipped lots and their edits; a key that
drops one of its inputs makes it fail."""

from __future__ import annotations

from pathlib import Path

import pytest

import lotsim.lot.clearance
import lotsim.maneuvers.batch
from lotsim.core.reusecheck import ReuseCheck
from lotsim.errors import ReuseMismatch
from lotsim.io.scenario_yaml import load_scenario
from lotsim.sim.preparation import prepare_lot

ROOT = Path(__file__).resolve().parents[3]

# a two-way aisle (each slot served by both lanes: nose-in and backed-in are both searched)
# with two rows 40 m apart, so that an edit of one leaves the other's problems as they were
TWO_WAY = """
name: two-way-check
seed: 1
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [80, 0], [80, 20], [0, 20]]
  aisles: [{id: a, centerline: [[0, 10], [80, 10]], width: 7.0}]
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 8, id_prefix: N}
    - {aisle: a, side: right, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 60, id_prefix: S}
  entrances: [{id: in, x: 2, y: 8.25, heading_deg: 0}]
  exits: [{id: out, x: 74, y: 8.25, heading_deg: 0}]
traffic: {vehicles: [{id: x, arrival: 0}]}
"""
EDIT = ("slot_length: 5.0, start: 60", "slot_length: 5.3, start: 60")

# a dead end whose far corner is cut off by the edit: the lanes, aisles and slots stay as
# they were, and the turnaround at the closed end has less room
DEAD_END = """
name: dead-end-check
seed: 1
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [34, 0], [34, 17], [0, 17]]
  aisles: [{id: a, centerline: [[0, 8.5], [33, 8.5]], width: 7.0}]
  rows:
    - {aisle: a, side: right, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 8, id_prefix: S}
    - {aisle: a, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 5.0, start: 8, id_prefix: N}
  entrances: [{id: in, x: 2.0, y: 6.75, heading_deg: 0}]
  exits: [{id: out, x: 5.0, y: 10.25, heading_deg: 180}]
traffic: {vehicles: [{id: x, arrival: 0}]}
"""
CORNER_CUT = ("[34, 0], [34, 17]", "[34, 0], [34, 13], [30, 17]")


@pytest.fixture
def own_cache(tmp_path, monkeypatch):
    """An empty cache of this test's own, so that what is recalled is what it prepared."""
    monkeypatch.setenv("LOTSIM_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def prepared_twice(text: str, edit: tuple[str, str]) -> tuple[ReuseCheck, ReuseCheck]:
    """The reuse checks of preparing ``text``, then the lot again, then its edit."""
    changed = text.replace(*edit)
    assert changed != text
    checks = []
    for doc in (text, text, changed):
        check = ReuseCheck()
        prepare_lot(load_scenario(doc), remember_from=1, check=check)
        checks.append(check)
    return checks[1], checks[2]


@pytest.mark.parametrize("name, edit", [
    ("two_rows.yaml", ("count: 10, slot_width: 3.6", "count: 9, slot_width: 3.6")),
    ("quickstart.yaml", ("occupied: [N2, N5, S3, S4, S9]", "occupied: [N2, N5, S3, S4]")),
])
def test_shipped_lot_and_its_edit_recall_what_they_would_work_out(own_cache, name, edit):
    again, edited = prepared_twice((ROOT / "scenarios" / name).read_text(), edit)
    assert again.counts == {"prepared lots": [1, 1, 0]}  # the lot loaded, and compared
    assert edited.counts, "the edit recalled nothing: the check was not exercised"
    assert all(r == v > 0 and m == 0 for r, v, m in edited.counts.values()), edited.counts


def test_the_check_covers_the_maneuver_and_roadmap_stores(own_cache):
    _, edited = prepared_twice(TWO_WAY, EDIT)
    assert {"roadmap", "maneuver problems posed", "maneuver exact keys",
            "maneuver answers"} <= set(edited.counts), edited.counts


def test_a_key_that_drops_the_style_makes_the_check_fail(own_cache, monkeypatch):
    real = lotsim.maneuvers.batch.exact_key
    # nose-in and backed-in searches of one problem now share a key: the second of them
    # kept overwrites the first, and the edited lot recalls it for both
    monkeypatch.setattr(lotsim.maneuvers.batch, "exact_key",
                        lambda problem, style: real(problem, "any"))
    with pytest.raises(ReuseMismatch) as caught:
        prepared_twice(TWO_WAY, EDIT)
    assert caught.value.store == "maneuver answers"
    assert caught.value.key and "recalled" in caught.value.what


def edges_of(prepared) -> dict:
    """Each edge of a prepared lot's graph: its kind, length [m] and durations by vehicle
    type [s] (a park edge's come from its maneuver)."""
    return {(u, v): (d["kind"], d["length"], tuple(sorted(d.get("duration", {}).items())))
            for u, v, d in prepared.lot_graph.graph.edges(data=True)}


def test_without_the_check_the_same_fault_passes_unseen(own_cache, monkeypatch, tmp_path):
    """What the check is for: the faulty key gives a wrong maneuver, the preparation goes
    on, and the lot differs from one prepared afresh."""
    real = lotsim.maneuvers.batch.exact_key
    monkeypatch.setattr(lotsim.maneuvers.batch, "exact_key",
                        lambda problem, style: real(problem, "any"))
    changed = TWO_WAY.replace(*EDIT)
    prepare_lot(load_scenario(TWO_WAY), remember_from=1, check=None)
    recalled = prepare_lot(load_scenario(changed), remember_from=1, check=None)
    monkeypatch.setattr(lotsim.maneuvers.batch, "exact_key", real)
    monkeypatch.setenv("LOTSIM_CACHE_DIR", str(tmp_path / "fresh"))
    fresh = prepare_lot(load_scenario(changed), remember_from=1, check=None)
    assert edges_of(recalled) != edges_of(fresh)


def a_collider_key_without_the_allowed_region(monkeypatch) -> None:
    """The planted fault of the roadmap store: what a collider holds about a box keyed
    without the region a body must stay in (an edge of the lot moved under a piece that
    checked against it goes unseen)."""
    real = lotsim.lot.clearance.CheckedAround
    monkeypatch.setattr(lotsim.lot.clearance, "CheckedAround",
                        lambda edge, labels, shapes, allowed: real(edge, labels, shapes, None))


def test_the_dead_end_and_its_corner_cut_recall_what_they_would_work_out(own_cache):
    _, edited = prepared_twice(DEAD_END, CORNER_CUT)
    assert edited.counts.get("roadmap", [0])[0] > 0, edited.counts
    assert all(r == v and m == 0 for r, v, m in edited.counts.values()), edited.counts


def test_a_collider_key_that_drops_the_lot_edge_makes_the_roadmap_check_fail(
        own_cache, monkeypatch):
    a_collider_key_without_the_allowed_region(monkeypatch)
    with pytest.raises(ReuseMismatch) as caught:
        prepared_twice(DEAD_END, CORNER_CUT)
    assert caught.value.store == "roadmap"


def test_without_the_check_the_roadmap_fault_passes_unseen(own_cache, monkeypatch,
                                                           tmp_path):
    a_collider_key_without_the_allowed_region(monkeypatch)
    changed = DEAD_END.replace(*CORNER_CUT)
    prepare_lot(load_scenario(DEAD_END), remember_from=1, check=None)
    recalled = prepare_lot(load_scenario(changed), remember_from=1, check=None)
    monkeypatch.undo()
    monkeypatch.setenv("LOTSIM_CACHE_DIR", str(tmp_path / "fresh"))
    fresh = prepare_lot(load_scenario(changed), remember_from=1, check=None)
    assert edges_of(recalled) != edges_of(fresh)


def test_the_check_is_read_from_the_environment(own_cache, monkeypatch):
    monkeypatch.setenv("LOTSIM_VERIFY_REUSE", "1")
    real = lotsim.maneuvers.batch.exact_key
    monkeypatch.setattr(lotsim.maneuvers.batch, "exact_key",
                        lambda problem, style: real(problem, "any"))
    prepare_lot(load_scenario(TWO_WAY), remember_from=1)
    with pytest.raises(ReuseMismatch):
        prepare_lot(load_scenario(TWO_WAY.replace(*EDIT)), remember_from=1)
    monkeypatch.setenv("LOTSIM_VERIFY_REUSE", "0")
    prepare_lot(load_scenario(TWO_WAY.replace(*EDIT).replace("two-way-check", "other")),
                remember_from=1)
