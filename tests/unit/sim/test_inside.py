"""Cars that are inside the lot when they come into a run (lotsim.sim.inside): one standing
in a bay, called out later; one standing on a lane, which holds its ground and sets off
for a slot.

The lot is the documentation's example (checked by eye): one one-way aisle along y = 10 m
with lane nodes every 4 m, four perpendicular slots on each side (N1–N4 left, S1–S4
right, x 8–18 m), N2 and S3 taken at the start, an entrance at x = 3 m and an exit at
x = 24 m. What a car holds is judged by lotsim check and by shapely on the footprints the
result writes, not by the planner's own tables.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely

import lotsim
from lotsim.errors import SettingsError
from lotsim.io.result import result_dict
from lotsim.sim.live import Live
from oracles.sampled import footprints

QUICKSTART = Path(__file__).resolve().parents[3] / "scenarios" / "quickstart.yaml"


@pytest.fixture(scope="module")
def prepared():
    return lotsim.prepare(lotsim.EXAMPLE.split("traffic:")[0])


def _car(doc: dict, car: str) -> dict:
    return next(v for v in doc["vehicles"] if v["id"] == car)


def test_a_car_in_a_bay_stands_there_until_called_out_then_leaves_by_an_exit(prepared):
    live = Live(prepared, traffic=False)
    live.add("kept", "valet", slot="S2", dwell=30.0)
    live.add("ada", "valet", "in", at=0.0)
    live.advance(10.0)
    state = live.state()
    kept = next(c for c in state["cars"] if c["id"] == "kept")
    assert (kept["phase"], kept["slot"], state["occupancy"]["S2"]) == ("parked", "S2", "kept")
    doc = result_dict(live.finish())
    assert lotsim.check(doc).ok
    car = _car(doc, "kept")
    assert (car["entrance"], car["inside"], car["status"]) == (None, {"slot": "S2"},
                                                                "departed")
    t = np.asarray(car["samples"]["t"])
    slot = shapely.Polygon(next(s for s in doc["lot"]["slots"] if s["id"] == "S2")["polygon"])
    feet = footprints(car)
    standing = t <= 30.0 + 1e-9
    # in the bay from the start to its call, out of it by the end
    assert t[0] == 0.0 and shapely.covers(slot.buffer(1e-6), feet[standing]).all()
    assert not shapely.intersects(slot, feet[-1])
    assert t[~standing][0] == pytest.approx(30.0, abs=0.06)
    # nobody else got its bay, and it is not counted as having parked
    assert _car(doc, "ada")["slot"] != "S2"
    assert doc["metrics"]["max_time_to_park"] == pytest.approx(
        live.finish().vehicles[0].parked_at - 0.0, abs=1e-3)


@pytest.fixture(scope="module")
def longer():
    """The quickstart's lot: one one-way aisle 40 m long, ten slots each side."""
    return lotsim.prepare(QUICKSTART.read_text().split("traffic:")[0])


def test_a_car_put_on_a_lane_holds_its_ground_or_is_turned_away_and_nothing_meets(longer):
    """Wherever a car is put on ada's way, the run checks clean: ada is planned round it
    (or it is turned away, saying why, when ada comes at speed with no way round), and
    ada's footprints never meet its ground while it stands there."""
    def farthest(request):  # ada drives the aisle's length
        return request.slots[-1] if request.car == "ada" else request.slots

    lg = longer.lot_graph
    mended = 0
    for _node, d in sorted(lg.graph.nodes(data=True)):
        if d.get("kind") != "lane":
            continue
        live = Live(longer, traffic=False, policy=farthest)
        live.add("ada", "valet", "in", at=0.0)
        live.advance(0.5)
        pose = d["pose"]
        try:
            live.add("stander", "valet", pose=(pose[0] + 0.1, pose[1] - 0.2, pose[2] + 0.05))
        except SettingsError as err:  # where ada is, or gets in the move it is making
            assert "'ada' is there" in str(err)
            continue
        doc = result_dict(live.finish())
        report = lotsim.check(doc)
        assert report.ok, report.summary()
        stander, ada = _car(doc, "stander"), _car(doc, "ada")
        if stander["status"] == "rejected":
            assert "'ada' comes there with no way round it" in stander["reason"]
            assert not stander["samples"]["t"]
            continue
        assert stander["inside"] == {"pose": [pytest.approx(c) for c in pose]}
        assert stander["samples"]["t"][0] == pytest.approx(0.5)
        body = _body(pose, ada["type"])
        t = np.asarray(ada["samples"]["t"])
        stood = (t >= 0.5) & (t <= _standing_until(stander))
        assert not shapely.intersects(footprints(ada)[stood], body).any()
        replans = doc.get("disturbances", {}).get("replans", [])
        mended += [(r["car"], r["why"]) for r in replans] == [
            ("ada", "'stander' stands in its way")]
    assert mended >= 3  # ada was planned round the stander from several places


def _body(pose, vtype: dict) -> shapely.Polygon:
    """A car of ``vtype`` (as the result writes it) standing at ``pose``."""
    return footprints({"samples": {"x": [pose[0]], "y": [pose[1]], "theta": [pose[2]]},
                        "type": vtype})[0]


def _standing_until(car: dict) -> float:
    """When a car that stood on a lane set off (its first sample with speed)."""
    v = np.abs(np.asarray(car["samples"]["v"]))
    t = np.asarray(car["samples"]["t"])
    moving = np.flatnonzero(v > 1e-3)
    return float(t[moving[0]]) if moving.size else math.inf


def test_a_car_on_a_lane_parks_sooner_than_one_from_the_gate(prepared):
    pose = prepared.lot_graph.graph.nodes[4]["pose"]  # x = 15, well inside the aisle
    times = []
    for where in ({"entrance": "in"}, {"pose": pose}):
        live = Live(prepared, traffic=False)
        live.add("x", "valet", **where)
        rr = live.finish()
        assert rr.vehicles[0].status == "parked"
        assert lotsim.check(result_dict(rr)).ok
        times.append(rr.metrics()["mean_time_to_park"])
    assert 0.0 < times[1] < times[0]


@pytest.mark.parametrize("kw, words", [
    ({"slot": "N2"}, "occupied"),
    ({"slot": "Z9"}, "no slot 'Z9'"),
    ({"pose": (15.0, 14.0, 0.0)}, "on no lane"),
    ({"pose": (15.0, 10.0, math.pi)}, "on no lane"),
    ({"slot": "S2", "pose": (15.0, 10.0, 0.0)}, "expected one of entrance, slot or pose"),
    ({}, "found none"),
])
def test_a_car_that_cannot_be_where_it_is_said_to_be_is_refused_with_the_reason(
        prepared, kw, words):
    live = Live(prepared, traffic=False)
    with pytest.raises(SettingsError, match=words):
        live.add("x", "valet", **kw)
    assert live.state()["cars"] == []


def test_a_car_inside_the_lot_is_added_where_it_is_now_and_not_onto_another(prepared):
    live = Live(prepared, traffic=False)
    with pytest.raises(SettingsError, match="added where it is now"):
        live.add("x", "valet", slot="S2", at=5.0)
    live.add("ada", "valet", "in", at=0.0, dwell=60.0)
    live.advance(9.0)
    ada = next(c for c in live.state()["cars"] if c["id"] == "ada")
    with pytest.raises(SettingsError, match="taken by 'ada'"):
        live.add("x", "valet", slot=ada["slot"])
    # where ada drives now
    node = min((n for n, d in prepared.lot_graph.graph.nodes(data=True)
                if d.get("kind") == "lane"),
               key=lambda n: math.dist(prepared.lot_graph.graph.nodes[n]["pose"][:2],
                                       ada["pose"][:2]))
    if math.dist(prepared.lot_graph.graph.nodes[node]["pose"][:2], ada["pose"][:2]) < 2.0:
        with pytest.raises(SettingsError, match="'ada' is there"):
            live.add("y", "valet", pose=prepared.lot_graph.graph.nodes[node]["pose"])


def test_a_car_is_not_put_on_closed_ground(prepared):
    live = Live(prepared, traffic=False)
    live.close("aisle", "main", 60.0)
    live.advance(1.0)
    pose = prepared.lot_graph.graph.nodes[4]["pose"]
    with pytest.raises(SettingsError, match="the aisle 'main' is closed there until 60 s"):
        live.add("x", "valet", pose=pose)
    live.advance(60.0)
    live.add("x", "valet", pose=pose)
    assert lotsim.check(result_dict(live.finish())).ok


def test_the_checker_finds_a_car_that_did_not_start_where_it_stood(prepared):
    live = Live(prepared, traffic=False)
    live.add("kept", "valet", slot="S2", dwell=10.0)
    doc = result_dict(live.finish())
    assert lotsim.check(doc).ok
    moved = {**doc, "vehicles": [{**_car(doc, "kept"), "inside": {"slot": "S1"}}]}
    assert "inside" in {v.rule for v in lotsim.check(moved).violations}
    late = {**doc, "vehicles": [{**_car(doc, "kept"), "arrival": -5.0}]}
    assert "inside" in {v.rule for v in lotsim.check(late).violations}
    gated = {**doc, "vehicles": [{**_car(doc, "kept"), "entrance": "in"}]}
    assert "structure" in {v.rule for v in lotsim.check(gated).violations}
    posed = {**doc, "vehicles": [{**_car(doc, "kept"), "inside": {"pose": [1.0, 2.0, 0.0]}}]}
    assert "inside" in {v.rule for v in lotsim.check(posed).violations}
