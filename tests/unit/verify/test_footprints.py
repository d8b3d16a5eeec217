"""The checker's batched footprint rules against the straightforward reference
(:mod:`oracles.reference_footprints`: a shapely polygon per vehicle per instant), and faults
planted in a result the planner made, which the checker must catch where they are.

The random results reuse the hand-built lot of ``tests/unit/verify/test_check.py`` (40 × 20 m, three
slots, a car parked at start, an obstacle), with vehicles on random arcs that run into each
other, the parked car, the obstacle, the boundary and each other's slots.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from hand_built import random_traffic, refresh_metrics, valid_result

from lotsim.verify import check_result, footprints
from oracles.reference_footprints import reference_footprints, report_findings

NOTCH = [[0, 0], [40, 0], [40, 20], [29, 20], [29, 13], [28, 13], [28, 20], [0, 20]]
"""The test lot's boundary with a notch cut down from its top edge, between P3 and the
obstacle: the lot is no longer its own bounding box."""


def busy_result(seed: int, *, notch: bool) -> dict:
    """Random traffic in the test lot; some cars parked in (or named for) slots P1/P2."""
    rng = np.random.default_rng(100 + seed)
    result = valid_result()
    result["vehicles"] = random_traffic(seed, n=10)
    for v in result["vehicles"]:
        if rng.random() < 0.6:
            v["slot"] = str(rng.choice(["P1", "P2"]))
            if rng.random() < 0.5:
                v["status"], v["reason"] = "parked", ""
    if notch:
        result["lot"]["boundary"] = NOTCH
    return refresh_metrics(result)


@pytest.mark.parametrize("notch", [False, True])
def test_footprint_rules_match_the_reference(notch):
    kinds = set()
    for seed in range(5, 8):
        result = busy_result(seed, notch=notch)
        expected = reference_footprints(result)
        found = report_findings(check_result(result, max_violations=100_000))
        assert found == expected, (seed, sorted(found ^ expected))
        kinds |= {f[0] for f in expected}
    # every rule is exercised (a checker that never finds anything would not pass)
    assert kinds == {"overlap", "parked", "obstacle", "boundary", "slot"}


# ------------------------------------------------------------- faults in a planned run


def pair_side_by_side(doc: dict) -> tuple[dict, dict, float]:
    """Two vehicles of the run that both move at one moment, and that moment [s]."""
    moving = [v for v in doc["vehicles"] if len(v["samples"]["t"]) > 100]
    for a in moving:
        for b in moving:
            ta, tb = a["samples"]["t"], b["samples"]["t"]
            start, end = max(ta[0], tb[0]), min(ta[-1], tb[-1])
            if a is not b and end - start > 5.0:
                return a, b, round(start + 2.0, 2)
    raise AssertionError("no two vehicles of the run are in the lot together")


@pytest.mark.slow
def test_a_car_moved_into_another_is_found_where_it_was_put(mixed_lot_doc):
    doc = copy.deepcopy(mixed_lot_doc)
    assert check_result(doc).ok
    a, b, t = pair_side_by_side(doc)
    sa, sb = a["samples"], b["samples"]
    i = int(np.searchsorted(sa["t"], t))
    for n in range(i, i + 20):  # a put half a metre beside b for 20 of its samples
        tn = sa["t"][n]
        th = float(np.interp(tn, sb["t"], np.unwrap(sb["theta"])))
        sa["x"][n] = float(np.interp(tn, sb["t"], sb["x"])) - 0.5 * math.sin(th)
        sa["y"][n] = float(np.interp(tn, sb["t"], sb["y"])) + 0.5 * math.cos(th)
        sa["theta"][n] = th
    report = check_result(doc, max_violations=1000)
    ids = tuple(sorted((a["id"], b["id"])))
    found = [f for f in report_findings(report) if f[:3] == ("overlap", *ids)]
    assert len(found) == 1
    # first at the first instant after a left its own path, at the latest on its sample i
    assert sa["t"][i - 1] < found[0][3] * 0.05 < sa["t"][i] + 1e-9
    # the same finding, one instant at a time, on these two cars
    doc["vehicles"] = [a, b]
    assert {f for f in reference_footprints(doc) if f[0] == "overlap"} == set(found)


def cruising_sample(samples: dict) -> int:
    """A sample in the middle of a stretch where the car drives at a steady speed, its
    neighbours on the result's regular grid (a move's end falls between grid instants)."""
    v = np.abs(np.array(samples["v"]))
    dt = np.diff(np.array(samples["t"]))
    even = np.abs(dt - np.median(dt)) < 1e-9
    steady = ((v[2:-2] > 0.5) & (np.abs(v[4:] - v[:-4]) < 0.01)
              & even[:-3] & even[1:-2] & even[2:-1] & even[3:])
    return int(np.flatnonzero(steady)[0]) + 2


def test_a_steering_jump_is_found_where_it_was_put(mixed_lot_doc):
    doc = copy.deepcopy(mixed_lot_doc)
    veh = doc["vehicles"][3]
    s = veh["samples"]
    i = cruising_sample(s)
    s["steer"][i] += 0.2  # far beyond 0.05 s of the steering rate
    report = check_result(doc)
    found = [v for v in report.violations if v.rule == "steer_rate"]
    assert [(v.vehicle, v.t) for v in found] == [(veh["id"], s["t"][i - 1])]


def test_a_jerk_spike_is_found_where_it_was_put(mixed_lot_doc):
    doc = copy.deepcopy(mixed_lot_doc)
    veh = doc["vehicles"][5]
    s = veh["samples"]
    i = cruising_sample(s)
    s["v"][i] -= 0.04 * math.copysign(1.0, s["v"][i])  # about 2 · 0.04 / 0.05² = 32 m/s³
    report = check_result(doc)
    assert {v.rule for v in report.violations} == {"jerk"}
    assert [(v.vehicle, v.t) for v in report.violations] == [(veh["id"], s["t"][i])]


def test_the_memory_bound_counts_the_instants_interpolated_not_the_span(monkeypatch):
    """A car standing between two samples is interpolated at the stretch's two ends only, so
    a long stay does not count against the bound (a 3000-car run spans 78 M car-instants)."""
    result = valid_result()  # 2021 car-instants from first to last sample; v2 stands 30 s
    monkeypatch.setattr(footprints, "MAX_INSTANTS", 1500)
    assert check_result(result).ok
    monkeypatch.setattr(footprints, "MAX_INSTANTS", 1000)
    report = check_result(result)
    assert [v.rule for v in report.violations] == ["internal"]
    assert "more than the footprint rules handle" in report.violations[0].message
