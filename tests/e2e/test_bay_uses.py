"""The storefront lot (``scenarios/lots/storefront.yaml``): bays by use, access aisles,
the code's counts and the bay schedule, end to end. Each car parks only in a bay its type
may use and no footprint touches an access aisle (judged with shapely from the result's
numbers, and by ``lotsim check``); a planted car on an aisle, or in a bay its type may not
use, makes the check fail; ``validate`` keeps each type out of the bays it may not use,
with why, counts the bays against ADA 2010 and writes a schedule that adds up to the
scenario's rows."""

from __future__ import annotations

import copy
import csv
import math

import numpy as np
import pytest
import shapely
import yaml

from conftest import ROOT
from lotsim import api
from lotsim.api.results import result_document
from lotsim.cli import main
from oracles.sampled import footprints

STOREFRONT = ROOT / "scenarios" / "lots" / "storefront.yaml"
RAW = yaml.safe_load(STOREFRONT.read_text(encoding="utf-8"))
MARK_OF = {"accessible": "accessible", "van_accessible": "accessible", "ev": "ev",
           "motorcycle": "motorcycle"}
"""docs/scenario.md's rule: the mark a type needs for a bay of each use."""


@pytest.fixture(scope="module")
def result():
    return result_document(api.run(STOREFRONT))


def may_use(car: dict, slot: dict) -> bool:
    use = slot.get("use", "standard")
    marks = set(car["type"].get("marks", []))
    if use in MARK_OF:
        return MARK_OF[use] in marks
    if use == "compact":
        poly = shapely.Polygon(slot["polygon"])
        ring = np.asarray(slot["polygon"])
        sides = sorted(np.hypot(*(np.roll(ring, -1, axis=0) - ring).T))
        return (car["type"]["front"] + car["type"]["rear"] <= sides[-1] + 1e-9
                and car["type"]["width"] <= poly.area / sides[-1] + 1e-9)
    return True


@pytest.mark.slow
def test_the_run_checks_and_every_car_parks_where_its_type_may(result):
    report = api.check(result)
    assert report.ok, [str(v) for v in report.violations]
    slots = {s["id"]: s for s in result["lot"]["slots"]}
    served = [car for car in result["vehicles"] if car["slot"] is not None]
    assert len(served) == len(RAW["traffic"]["vehicles"])
    assert all(may_use(car, slots[car["slot"]]) for car in served)
    # the accessible cars' bays are by their marks, the others' never accessible
    assert {slots[c["slot"]].get("use", "standard") for c in served
            if "accessible" not in c["type"].get("marks", [])}.isdisjoint(
        {"accessible", "van_accessible"})


def test_no_footprint_touches_an_access_aisle(result):
    aisles = [shapely.Polygon(a["polygon"]) for a in result["lot"]["access_aisles"]]
    assert len(aisles) == 2  # H1 and H2 share one; V1 has its own
    for car in result["vehicles"]:
        if car["samples"]["t"]:
            feet = footprints(car)
            assert not any(shapely.intersects(feet, a).any() and
                           max(shapely.area(shapely.intersection(feet, a))) > 1e-6
                           for a in aisles), car["id"]


def test_a_car_routed_over_an_access_aisle_fails_the_check(result):
    planted = copy.deepcopy(result)
    car = next(c for c in planted["vehicles"] if len(c["samples"]["t"]) > 20)
    k = len(car["samples"]["t"]) // 2
    x, y = car["samples"]["x"][k], car["samples"]["y"][k]
    # an aisle where the car drove: as if it had been routed across one
    planted["lot"]["access_aisles"].append(
        {"id": "planted", "polygon": [[x - 0.8, y - 2.5], [x + 0.8, y - 2.5],
                                      [x + 0.8, y + 2.5], [x - 0.8, y + 2.5]]})
    found = [v for v in api.check(planted).violations if v.rule == "access_aisle"]
    assert found and found[0].vehicle == car["id"] and "planted" in found[0].message


def test_a_car_in_a_bay_its_type_may_not_use_fails_the_check(result):
    planted = copy.deepcopy(result)
    badge = next(c for c in planted["vehicles"] if "accessible" in c["type"].get("marks", [])
                 and c["slot"] is not None
                 and next(s for s in planted["lot"]["slots"] if s["id"] == c["slot"]
                          ).get("use") in ("accessible", "van_accessible"))
    del badge["type"]["marks"]
    plain = next(c for c in planted["vehicles"] if "marks" not in c["type"]
                 and c["slot"] is not None and c is not badge)
    next(s for s in planted["lot"]["slots"] if s["id"] == plain["slot"])["use"] = "ev"
    found = {v.vehicle for v in api.check(planted).violations if v.rule == "bay_use"}
    assert found == {badge["id"], plain["id"]}


def test_validate_keeps_each_type_out_of_the_bays_it_may_not_use():
    report = api.validate(STOREFRONT)
    rows = RAW["lot"]["rows"]
    by_prefix = {r["id_prefix"]: r.get("use", "standard") for r in rows}
    types = {t if isinstance(t, str) else t["name"]: set() if isinstance(t, str)
             else {m for m in MARK_OF.values() if t.get(m)} for t in RAW["vehicle_types"]}
    for name, usable in report.usable().items():
        for sid in usable:
            use = by_prefix[sid.rstrip("0123456789")]
            assert use not in MARK_OF or MARK_OF[use] in types[name], (name, sid)
        assert not any(by_prefix[s.rstrip("0123456789")] == "compact" for s in usable) \
            or name == "ev_hatch"
    why = report.unusable()["valet"]
    assert "not marked accessible: true" in why["lot.rows[0] (aisle A, left)"]["H1"]
    assert report.complete  # keeping types out of bays is the rule, not a fault


def test_the_counts_meet_ada_and_the_walks_go_over_the_pavement():
    report = api.validate(STOREFRONT)
    bays = report.bays
    total = sum(r["count"] for r in RAW["lot"]["rows"])
    assert bays.total == total == 21
    checks = {c.use: c for c in bays.checks}
    assert (checks["accessible"].required, checks["accessible"].found) == (1, 3)
    assert (checks["van_accessible"].required, checks["van_accessible"].found) == (1, 1)
    assert bays.met
    door = (RAW["lot"]["building_entrances"][0]["x"], RAW["lot"]["building_entrances"][0]["y"])
    lot = report.prepared.lot
    for w in bays.walks:
        # from the middle of the bay's side on its access aisle (shapely: the side the two
        # share), and nothing in the way of the door from there: the straight line
        slot, aisle = lot.slot_by_id[w.slot], next(a for a in lot.access_aisles
                                                  if w.slot in a.slots)
        shared = slot.shape.intersection(aisle.shape)
        assert shared.length == pytest.approx(5.0)
        assert shared.centroid.distance(shapely.Point(w.path[0])) < 1e-9
        assert w.distance == pytest.approx(math.dist(w.path[0], door))
        assert w.straight == pytest.approx(w.distance)
    assert {w.slot for w in bays.walks} == {"H1", "H2", "V1"}
    lines = "\n".join(bays.lines())
    assert "walk to shop_door over the pavement (straight line" in lines


@pytest.mark.slow
def test_a_stated_table_not_met_says_by_how_many():
    text = STOREFRONT.read_text(encoding="utf-8").replace(
        "standard: ADA 2010",
        "standard: {name: City code, require: {ev: {share: 0.25}, accessible: {count: 4}}}")
    bays = api.validate(text).bays
    assert bays.standard == "City code" and not bays.met
    checks = {c.use: c for c in bays.checks}
    assert (checks["ev"].required, checks["ev"].found, checks["ev"].short) == (6, 3, 3)
    assert (checks["accessible"].required, checks["accessible"].short) == (4, 1)


def test_the_schedule_adds_up_to_the_rows(tmp_path, capsys):
    out = tmp_path / "bays.csv"
    assert main(["validate", str(STOREFRONT), "--schedule", str(out)]) == 0
    lines = list(csv.DictReader(out.open(encoding="utf-8")))
    assert len(lines) == len(RAW["lot"]["rows"])
    for line, row in zip(lines, RAW["lot"]["rows"], strict=True):
        assert line["use"] == row.get("use", "standard")
        assert int(line["count"]) == row["count"]
        assert (float(line["length_m"]), float(line["width_m"])) == (row["slot_length"],
                                                                    row["slot_width"])
        assert float(line["angle_deg"]) == 90.0
    assert [int(line["access_aisles"]) for line in lines][:2] == [1, 1]


def test_a_schedule_that_cannot_be_written_is_bad_input(tmp_path, capsys):
    assert main(["validate", str(STOREFRONT), "--schedule", str(tmp_path / "no" / "x.csv"),
                 ]) == 2
    assert "--schedule" in capsys.readouterr().err
    assert main(["validate", str(STOREFRONT), "--schedule", str(tmp_path / "x.txt")]) == 2


def bays_section() -> str:
    page = (ROOT / "docs" / "scenario.md").read_text(encoding="utf-8")
    return page.split("## Bays by use", 1)[1].split("\n## ", 1)[0]


def test_the_scenario_page_shows_the_storefront_as_shipped():
    shown = bays_section().split("```yaml\n", 1)[1].split("```", 1)[0]
    assert shown == STOREFRONT.read_text(encoding="utf-8")


def test_the_scenario_page_shows_what_validate_says_of_an_aisle_on_a_bay(
        tmp_path, monkeypatch, capsys):
    said = bays_section().split("\n```\nlotsim: ", 1)[1].split("\n```", 1)[0]
    text = STOREFRONT.read_text(encoding="utf-8")
    for old, new in (("count: 2, slot_width: 2.5", "count: 3, slot_width: 2.5"),
                     ("start: 15.0, id_prefix: V", "start: 17.1, id_prefix: V")):
        assert text.count(old) == 1
        text = text.replace(old, new)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "lot.yaml").write_text(text, encoding="utf-8")
    assert main(["validate", "lot.yaml"]) == 2
    assert capsys.readouterr().err == f"lotsim: {said}\n"
