"""The independent result checker against the hand-built result of ``tests/hand_built.py``
(a lot small enough to check by eye, every path computed in closed form). Each test breaks
the valid result in one way and expects exactly that rule.
"""

from __future__ import annotations

import ast
import copy
import importlib
import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hand_built import (
    DT,
    PARK_Y,
    SPEED,
    TYPE,
    R,
    box,
    random_traffic,
    refresh_metrics,
    stand,
    stroke,
    v2_path,
    valid_result,
    vehicle,
)

from lotsim.verify import CheckReport, ResultFormatError, check_result, read_result
from lotsim.verify.footprints import _Items, _rects_overlap


@pytest.fixture
def result():
    return valid_result()


def by_id(result, vid):
    return next(v for v in result["vehicles"] if v["id"] == vid)


def rules(report: CheckReport) -> set[str]:
    return {v.rule for v in report.violations}


def assert_only(result, rule, *, refresh=True) -> CheckReport:
    """Check ``result`` (its metrics recomputed first, unless ``refresh`` is False) and
    expect violations of ``rule`` and no other."""
    if refresh:
        refresh_metrics(result)
    report = check_result(result)
    assert not report.ok
    assert rules(report) == {rule}, [str(v) for v in report.violations]
    return report


# ----------------------------------------------------------------- the valid result


def test_valid_result_passes(result):
    report = check_result(result)
    assert report.ok, [str(v) for v in report.violations]
    assert report.stats["vehicles"] == 5
    assert report.stats["vehicles_checked"] == 5
    n = sum(len(v["samples"]["t"]) for v in result["vehicles"])
    assert report.stats["samples"] == n
    # v2 stands still at its last pose until the end: one footprint, not hundreds
    assert report.stats["footprints"] < report.stats["vehicle_instants"]
    assert report.summary().startswith("ok:")


def test_the_fixture_is_tight(result):
    """The quarter circle is at exactly the minimum radius and the steering angle at its
    maximum, so the valid result sits on the kinematic limits; v2 ends 0.3 m from either
    end of P1, so moving it 0.5 m puts it 0.2 m outside."""
    v2 = by_id(result, "v2")["samples"]
    assert max(v2["steer"]) == pytest.approx(TYPE["max_steer"], abs=1e-12)
    dth = np.diff(v2["theta"])
    d = np.hypot(np.diff(v2["x"]), np.diff(v2["y"]))
    assert np.max(dth / np.where(d > 0, d, 1)) == pytest.approx(1 / R, rel=1e-3)
    assert v2["y"][-1] - TYPE["rear"] - 14.5 == pytest.approx(0.3)


def test_json_round_trip(result, tmp_path):
    path = tmp_path / "result.json"
    path.write_text(json.dumps(result))
    assert check_result(read_result(path)).ok


@pytest.mark.parametrize("damage", ["none", "nan", "unequal", "not-increasing",
                                    "missing-key", "gear-value", "string-number", "boolean",
                                    "nested", "empty", "object", "integers"])
def test_a_result_read_packed_checks_as_one_read_as_lists(result, tmp_path, damage):
    """``read_result(packed=True)`` makes each sample column a float array as it reads the
    file (what the checker and a replay read them as): the same values as the lists, the
    same report, whatever is wrong with a column (what is not a list of numbers stays as
    read)."""
    v1 = by_id(result, "v1")["samples"]
    if damage == "nan":
        v1["x"][10] = float("nan")
    elif damage == "unequal":
        v1["v"].pop()
    elif damage == "not-increasing":
        v1["t"][20] = v1["t"][19]
    elif damage == "missing-key":
        del v1["steer"]
    elif damage == "gear-value":
        v1["gear"][5] = 2
    elif damage == "string-number":
        v1["y"][3] = "5.0"
    elif damage == "boolean":
        v1["theta"][4] = True
    elif damage == "nested":
        v1["y"][3] = [1.0, 2.0]
    elif damage == "empty":
        for key in v1:
            v1[key] = []
    elif damage == "object":
        v1["v"] = {"0": 1.0}
    elif damage == "integers":
        v1["gear"] = [int(g) for g in v1["gear"]]
    path = tmp_path / "result.json"
    path.write_text(json.dumps(result))
    plain, packed = read_result(path), read_result(path, packed=True)
    arrays = 0
    for a, b in zip(plain["vehicles"], packed["vehicles"], strict=True):
        for key, col in a["samples"].items():
            got = b["samples"][key]
            if isinstance(got, np.ndarray):
                assert got.dtype == float and np.array_equal(got, np.asarray(col, dtype=float),
                                                             equal_nan=True)
                arrays += 1
            else:
                assert got == col or (damage == "nan" and key == "x")
    filled = sum(1 for v in plain["vehicles"] for col in v["samples"].values()
                 if isinstance(col, list) and col)
    # left as read: what is not a list of numbers, and the columns of an object lacking one
    kept = {"string-number": 1, "nested": 1, "missing-key": 6}.get(damage, 0)
    assert arrays == filled - kept and arrays >= 14
    want, got = check_result(plain), check_result(packed)
    assert got.violations == want.violations
    assert {**got.stats, "seconds": 0} == {**want.stats, "seconds": 0}
    assert want.ok == (damage in ("none", "integers"))


# ---------------------------------------------------------------------------- motion


def test_nan_is_structure(result):
    by_id(result, "v1")["samples"]["x"][10] = float("nan")
    report = assert_only(result, "structure")
    assert "samples.x[10]" in report.violations[0].message


@pytest.mark.parametrize("damage", ["unequal", "not-increasing", "missing-key", "status",
                                    "gear-value", "type", "string-number", "duplicate-id"])
def test_structure_problems(result, damage):
    v1 = by_id(result, "v1")
    if damage == "unequal":
        v1["samples"]["v"].pop()
    elif damage == "not-increasing":
        v1["samples"]["t"][20] = v1["samples"]["t"][19]
    elif damage == "missing-key":
        del v1["samples"]["steer"]
    elif damage == "status":
        v1["status"] = "gone"
    elif damage == "gear-value":
        v1["samples"]["gear"][5] = 2
    elif damage == "type":
        del v1["type"]["wheelbase"]
    elif damage == "string-number":
        v1["samples"]["y"][3] = "5.0"
    elif damage == "duplicate-id":
        by_id(result, "v5")["id"] = "v1"
    assert_only(result, "structure")


def test_sampling_gap_while_moving(result):
    s = by_id(result, "v1")["samples"]
    for key in s:
        del s[key][201:206]  # 0.3 s and 0.27 m between two moving samples
    report = assert_only(result, "sampling")
    assert report.violations[0].t == pytest.approx(10.0)


def test_long_gap_needs_gear_zero(result):
    s = by_id(result, "v2")["samples"]
    assert s["t"][-1] - s["t"][-2] == pytest.approx(30.0)
    s["gear"][-2] = 1  # standing, but still in gear: the 30 s gap is not standing still
    assert_only(result, "sampling")


def test_sideways_step(result):
    by_id(result, "v1")["samples"]["y"][50] += 0.2
    assert_only(result, "sideways")


def test_curvature_tighter_than_the_minimum_radius(result):
    # the steering angle is still recorded at its maximum: only the geometry is wrong (the
    # steer no longer matches it either, but with this file's unlimited steering rate the
    # wheels could have swung anywhere between samples: tests/unit/verify/test_dynamics.py
    # tests the heading rule)
    by_id(result, "v2")["samples"] = v2_path(radius=0.8 * R, steer_radius=R)
    assert_only(result, "curvature")


def test_steer_beyond_max(result):
    by_id(result, "v2")["samples"] = v2_path(steer_radius=0.8 * R)
    assert_only(result, "steer")


def test_gear_against_the_direction_of_travel(result):
    s = by_id(result, "v1")["samples"]
    for i in range(100, 105):
        s["gear"][i] = -1
    assert_only(result, "gear")


def test_gear_at_a_cusp_may_be_either(result):
    s = by_id(result, "v5")["samples"]
    cusp = s["v"].index(0.0)
    assert s["gear"][cusp] == 1 and s["gear"][cusp + 1] == -1
    s["gear"][cusp] = -1
    assert check_result(result).ok


def test_speed_above_the_zone_limit(result):
    s = by_id(result, "v1")["samples"]
    inside = [18 < x < 24 for x in s["x"]]
    for i, flag in enumerate(inside):
        if not flag:
            s["v"][i] = 1.5  # allowed outside the zone
    assert check_result(result).ok
    for i, flag in enumerate(inside):
        if flag:
            s["v"][i] = 1.5
    report = assert_only(result, "speed")
    assert "1.000 m/s" in report.violations[0].message


def test_chord_speed_above_the_zone_limit(result):
    fast = stroke((3.0, 5.0, 0.0), [(31.0, 0.0)], t0=0.0, speed=1.5, stop=False)
    fast["v"] = [SPEED] * len(fast["v"])  # the recorded speed lies
    by_id(result, "v1")["samples"] = fast
    refresh_metrics(result)
    assert_only(result, "speed")


def test_reverse_speed_limit(result):
    s = by_id(result, "v5")["samples"]
    s["v"] = [-2.5 if g == -1 else v for v, g in zip(s["v"], s["gear"], strict=True)]
    assert_only(result, "speed")


def test_sample_before_arrival(result):
    by_id(result, "v1")["arrival"] = 0.5
    assert_only(result, "arrival")


# ------------------------------------------------------------------------ footprints


def test_overlap_reported_once_at_its_first_instant(result):
    s = by_id(result, "v5")["samples"]
    s["y"] = [y - 7.0 for y in s["y"]]  # onto v1's lane while v1 passes
    report = assert_only(result, "overlap")
    # v1 drives through v5 for seconds, v2 then starts into it: one report per pair
    first, second = report.violations
    assert "v1 and v5" in first.message and "m²" in first.message
    assert first.t == pytest.approx(5.0)
    assert "v2 and v5" in second.message
    assert second.t == pytest.approx(10.0)


def test_footprints_may_touch_but_not_overlap_by_more_than_the_shrink(result):
    waiting = stand(stroke((6.0, 13.8, 0.0), [(0.0, 0.0)], t0=20.0), 1.0)
    result["vehicles"].append(vehicle("v6", 20.0, "waiting", waiting, reason="blocked"))
    refresh_metrics(result)
    assert check_result(result).ok  # side by side with v5, touching
    by_id(result, "v6")["samples"]["y"] = [13.79, 13.79]  # 1 cm into v5: within 2 x 1 cm
    assert check_result(result).ok
    by_id(result, "v6")["samples"]["y"] = [13.77, 13.77]  # 3 cm into v5
    report = assert_only(result, "overlap")
    assert report.violations[0].t == pytest.approx(20.0)


def test_departed_vehicle_is_gone_after_its_last_sample(result):
    v1_end = by_id(result, "v1")["samples"]["t"][-1]
    there = stand(stroke((34.0, 5.0, 0.0), [(0.0, 0.0)], t0=v1_end + 0.1), 1.0)
    result["vehicles"].append(vehicle("v6", 20.0, "waiting", there, reason="blocked"))
    refresh_metrics(result)
    assert check_result(result).ok
    there["t"] = [t - 2.0 for t in there["t"]]  # now it arrives while v1 is still there
    assert_only(result, "overlap")


def test_waiting_vehicle_stays_at_its_last_pose(result):
    there = stand(stroke((6.0, 12.0, 0.0), [(0.0, 0.0)], t0=60.0), 1.0)
    result["vehicles"].append(vehicle("v6", 20.0, "waiting", there, reason="blocked"))
    refresh_metrics(result)
    report = assert_only(result, "overlap")
    assert report.violations[0].t == pytest.approx(60.0)


def test_last_pose_after_the_last_instant_is_checked(result):
    """A vehicle whose last sample comes after the run's last grid instant still holds its
    last pose from the next instant on (here it ends 4 cm on, 5 cm into the standing v5):
    that pose is checked, not only the one interpolated at the last instant before it."""
    end = max(v["samples"]["t"][-1] for v in result["vehicles"] if v["samples"]["t"])
    t0 = math.ceil((end + 1.0) / DT) * DT
    # heading -x towards v5's front (x = 9.9): 20 whole samples, then 4 cm more
    length = 20 * SPEED * DT + 0.04
    pieces = [(length, 0.0)]
    there = stroke((13.75 + length, 12.0, math.pi), pieces, t0=t0)
    assert round(there["t"][-1] / DT % 1.0, 6) not in (0.0, 1.0)  # off the instant grid
    result["vehicles"].append(vehicle("v6", t0, "waiting", there, reason="blocked"))
    report = assert_only(result, "overlap")
    assert "v5 and v6" in report.violations[0].message
    assert report.violations[0].t == pytest.approx(math.ceil(there["t"][-1] / DT) * DT)
    there["x"] = [x + 0.04 for x in there["x"]]  # ends touching v5: fine
    refresh_metrics(result)
    assert check_result(result).ok


def test_drive_into_the_obstacle(result):
    result["lot"]["obstacles"] = [box(30, 4.5, 31, 5.5)]
    report = assert_only(result, "obstacle")
    # the shrunk front (x + 3.89) reaches x = 30 at t = 23.11 / 0.9 = 25.68 s
    assert report.violations[0].t == pytest.approx(25.70)
    assert report.violations[0].vehicle == "v1"


def test_drive_into_a_car_parked_at_start(result):
    result["lot"]["parked"] = [box(30, 4.5, 31.8, 9.4)]
    assert_only(result, "parked")


def test_leave_the_boundary(result):
    result["lot"]["boundary"] = box(0, 0, 36, 20)
    report = assert_only(result, "boundary")
    assert report.violations[0].vehicle == "v1"


# ----------------------------------------------------------------------- final state


def test_parked_half_a_metre_outside_its_slot(result):
    by_id(result, "v2")["samples"] = v2_path(final_y=PARK_Y - 0.5)
    report = assert_only(result, "slot")
    assert "not within slot P1" in report.violations[0].message


def test_parked_in_a_slot_occupied_at_start(result):
    by_id(result, "v2")["slot"] = "P3"
    report = assert_only(result, "slot")
    assert any("occupied at start" in v.message for v in report.violations)


def test_parked_but_still_moving(result):
    by_id(result, "v2")["samples"]["v"][-1] = 0.5
    by_id(result, "v2")["samples"]["gear"][-1] = 1
    rules_found = rules(check_result(result))
    assert "slot" in rules_found
    assert rules_found <= {"slot", "sampling"}  # a 30 s gap is no longer standing still


def test_two_parked_vehicles_hold_one_slot(result):
    # P1 widened to two cars: v6 stands in its left half, v2 parks in its right half
    result["lot"]["slots"][0]["polygon"] = box(17.4, 14.5, 22.6, 20)
    beside = stand(stroke((18.7, PARK_Y, math.pi / 2), [(0.0, 0.0)], t0=20.0), 40.0)
    result["vehicles"].append(vehicle("v6", 20.0, "parked", beside, slot="P1"))
    refresh_metrics(result)
    report = assert_only(result, "slot")
    (v,) = report.violations
    assert "held by v2 and v6" in v.message or "held by v6 and v2" in v.message


def test_two_parked_vehicles_name_one_slot(result):
    in_p2 = stand(stroke((23.9, PARK_Y, math.pi / 2), [(0.0, 0.0)], t0=20.0), 40.0)
    result["vehicles"].append(vehicle("v6", 20.0, "parked", in_p2, slot="P1"))
    refresh_metrics(result)
    report = assert_only(result, "slot")
    assert any("held by" in v.message for v in report.violations)
    assert any("not within slot P1" in v.message for v in report.violations)


def test_parked_without_slot(result):
    by_id(result, "v2")["slot"] = None
    assert_only(result, "slot")


def test_unknown_slot(result):
    by_id(result, "v2")["slot"] = "P9"
    assert_only(result, "slot")


def test_departed_far_from_the_exit(result):
    s = by_id(result, "v1")["samples"]
    for key in s:
        del s[key][300:]
    refresh_metrics(result)
    report = assert_only(result, "exit")
    assert "gate-out" in report.violations[0].message


def test_rejected_without_reason(result):
    by_id(result, "v3")["reason"] = ""
    assert_only(result, "reason")


def test_waiting_without_reason(result):
    by_id(result, "v5")["reason"] = "  "
    assert_only(result, "reason")


def test_rejected_with_samples(result):
    by_id(result, "v3")["samples"] = stand(stroke((6.0, 17.0, 0.0), [(0.0, 0.0)], t0=12.0),
                                           1.0)
    assert_only(result, "status")


def test_metrics_must_match_the_vehicles(result):
    result["metrics"]["parked"] = 2
    assert_only(result, "metrics", refresh=False)


# --------------------------------------------------------------------- file handling


def test_load_result_rejects_what_is_not_json(tmp_path):
    path = tmp_path / "result.json"
    path.write_text('{"format": "lotsim-result",')
    with pytest.raises(ResultFormatError, match="not JSON"):
        read_result(path)
    with pytest.raises(ResultFormatError, match="cannot read"):
        read_result(tmp_path / "missing.json")


@pytest.mark.parametrize(("content", "match"), [
    ([1, 2], "expected a JSON object"),
    ({"format": "geojson"}, "'format' is 'geojson'"),
    ({"format": "lotsim-result", "version": 1}, "missing top-level keys 'lot'"),
    ("version-2", "unsupported result version 2"),
])
def test_load_result_rejects_json_that_is_not_a_result(tmp_path, content, match):
    if content == "version-2":
        content = valid_result() | {"version": 2}
    path = tmp_path / "result.json"
    path.write_text(json.dumps(content))
    with pytest.raises(ResultFormatError, match=match):
        read_result(path)
    assert rules(check_result(content)) == {"structure"}


# ------------------------------------------------------------------- the checker itself


def test_never_raises_on_damaged_results():
    """Random values written at random places: violations, never an exception."""
    rng = np.random.default_rng(7)
    junk = [None, "junk", [], {}, [[1]], -1.5, float("nan"), True, [None, None]]
    base = valid_result()
    for _ in range(40):
        damaged = copy.deepcopy(base)
        node, path = damaged, []
        while isinstance(node, dict | list) and node:
            keys = list(node) if isinstance(node, dict) else list(range(len(node)))
            key = keys[int(rng.integers(len(keys)))]
            path.append(key)
            if rng.random() < 0.3 or not isinstance(node[key], dict | list) or not node[key]:
                node[key] = junk[int(rng.integers(len(junk)))]
                break
            node = node[key]
        report = check_result(damaged)
        assert isinstance(report, CheckReport)
        assert "internal" not in rules(report), (path, [str(v) for v in report.violations])


def test_a_failing_stage_is_reported_not_raised(result, monkeypatch):
    def broken(*args):
        raise ZeroDivisionError("boom")

    # the module that runs the stages (lotsim.check, the attribute, is lotsim.api.check)
    monkeypatch.setattr(importlib.import_module("lotsim.verify.checker"), "_check_motion", broken)
    report = check_result(result)
    assert not report.ok
    assert rules(report) == {"internal"}
    assert "boom" in report.violations[0].message


def test_max_violations_limits_the_list_not_the_count(result):
    for v in result["vehicles"]:
        v["status"] = "unknown"
    report = check_result(result, max_violations=2)
    assert len(report.violations) == 2
    assert report.stats["violations"] == 5
    assert not report.ok
    assert not check_result(result, max_violations=0).ok


def test_separating_axes_agree_with_shapely():
    rng = np.random.default_rng(3)
    n = 4000
    th = rng.uniform(-math.pi, math.pi, n)
    items = _Items(
        veh=np.arange(n), ka=np.zeros(n, dtype=int), kb=np.zeros(n, dtype=int),
        cx=rng.uniform(0, 8, n), cy=rng.uniform(0, 8, n), ux=np.cos(th), uy=np.sin(th),
        hx=rng.uniform(0.5, 3, n), hy=rng.uniform(0.3, 1.5, n))
    a, b = np.arange(0, n, 2), np.arange(1, n, 2)
    polys = items.polygons(np.arange(n))
    expected = shapely.intersects(polys[a], polys[b])
    assert 0.2 < expected.mean() < 0.8  # both outcomes are exercised
    assert np.array_equal(_rects_overlap(items, a, b), expected)


def brute_force_overlaps(vehicles):
    """First instant of every overlapping pair, one shapely test per pair and instant."""
    ends = [(v["samples"]["t"][0], v["samples"]["t"][-1]) for v in vehicles]
    k0 = math.ceil(min(a for a, _ in ends) / DT - 1e-9)
    k1 = math.floor(max(b for _, b in ends) / DT + 1e-9)
    first = {}
    for k in range(k0, k1 + 1):
        t = k * DT
        present = []
        for v, (a, b) in zip(vehicles, ends, strict=True):
            if t < a - 1e-9 or (t > b + 1e-9 and v["status"] == "departed"):
                continue
            s = v["samples"]
            j = min(max(int(np.searchsorted(s["t"], t)) - 1, 0), len(s["t"]) - 2)
            f = min(max((t - s["t"][j]) / (s["t"][j + 1] - s["t"][j]), 0.0), 1.0)
            dth = (s["theta"][j + 1] - s["theta"][j] + math.pi) % (2 * math.pi) - math.pi
            x = s["x"][j] + f * (s["x"][j + 1] - s["x"][j])
            y = s["y"][j] + f * (s["y"][j + 1] - s["y"][j])
            th = s["theta"][j] + f * dth
            c, n = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
            a0, a1, w = -TYPE["rear"] + 0.01, TYPE["front"] - 0.01, TYPE["width"] / 2 - 0.01
            pts = [np.array([x, y]) + c * p + n * q for p, q in ((a0, -w), (a1, -w), (a1, w),
                                                                   (a0, w))]
            present.append((v["id"], shapely.Polygon(pts)))
        for i, (ia, pa) in enumerate(present):
            for ib, pb in present[i + 1:]:
                pair = tuple(sorted((ia, ib)))
                if pair not in first and pa.intersects(pb):
                    first[pair] = k
    return first


@pytest.mark.parametrize("seed", range(3))
def test_overlaps_match_brute_force(seed):
    result = valid_result()
    result["vehicles"] = random_traffic(seed)
    refresh_metrics(result)
    expected = brute_force_overlaps(result["vehicles"])
    report = check_result(result, max_violations=10_000)
    found = {}
    for v in report.violations:
        if v.rule == "overlap":
            a, b = v.message.split(" overlap")[0].split(" and ")
            found[tuple(sorted((a, b)))] = round(v.t / DT)
    assert len(expected) >= 5  # the traffic is dense enough to mean something
    assert found == expected


def test_a_standing_pose_written_one_rounding_unit_apart_still_stands(result):
    """Found by the property tests: a node's pose and a motion's first sample, computed along
    two paths, were written 0.1 mm apart (a coordinate on a half unit); the car stood."""
    s = by_id(result, "v2")["samples"]  # v2 ends standing for 30 s
    s["y"][-1] = round(s["y"][-1] + 1e-4, 4)
    assert check_result(refresh_metrics(result)).ok
    s["y"][-1] = round(s["y"][-1] + 4e-4, 4)  # half a millimetre: it moved
    assert_only(result, "sampling")


def test_the_checker_imports_nothing_from_lotsim_but_an_error_type():
    # the checker shares no code with what it checks (docs/result.md)
    package = Path(importlib.import_module("lotsim.verify").__file__).parent
    found = set()
    for path in package.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module:
                found.add(node.module)
            elif isinstance(node, ast.Import):
                found.update(alias.name for alias in node.names)
    outside = {m for m in found if m.split(".")[0] == "lotsim"
               and not m.startswith("lotsim.verify.")}
    assert outside == {"lotsim.errors"}
