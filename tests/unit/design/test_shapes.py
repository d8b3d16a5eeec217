"""The plot shapes a designer meets that lotsim once gave no layout: a 30 x 150 m strip with
its gate at a short end, and a plot with its gate at a corner. Each is laid out in full
(``-m slow``: maneuvers planned, the demand run) and held to a hand count of the same
rules worked out here from the module's dimensions, with shapely for the gate's clearance
and lotsim validate, reading the written lot back, for every bay's use."""

from __future__ import annotations

import math

import pytest
from shapely.geometry import LineString, Point, Polygon, box

import lotsim
from conftest import ROOT

PLOTS = ROOT / "scenarios" / "plots"
BAY, DEPTH, AISLE, CLEARANCE = 2.5, 5.0, 7.0, 10.0


def _hand(rows: list[tuple[float, float]], y0: float, y1: float, mouth: LineString) -> int:
    """Bays of ``BAY`` x ``DEPTH`` along y from ``y0`` to ``y1`` in each row (x from, x to),
    less those whose centre lies within the clearance of the gate's ``mouth``."""
    count = 0
    for x0, x1 in rows:
        for k in range(math.floor((y1 - y0) / BAY + 1e-9)):
            centre = Point((x0 + x1) / 2, y0 + (k + 0.5) * BAY)
            count += centre.distance(mouth) >= CLEARANCE
    return count


def test_the_hand_count_of_the_strip():
    # three rows on a loop across the 30 m (5 + 7 + 5 + 7 + 5 = 29 m), the loop's cross
    # aisles along both short ends; 54 bays a row between them; the middle row's first bay
    # stands 8.25 m from the gate's 7 m mouth in the middle of the south end
    mouth = LineString([(15 - AISLE / 2, 0), (15 + AISLE / 2, 0)])
    rows = [(0, 5), (12, 17), (24, 29)]
    assert _hand(rows, AISLE, 150 - AISLE, LineString([(-99, -99), (-98, -99)])) == 162
    assert _hand(rows, AISLE, 150 - AISLE, mouth) == 161


def _laid(tmp_path, name: str):
    out = tmp_path / f"{name}.yaml"
    settings = lotsim.LayoutSettings(orientations=1, offsets=1, prepared=2, compared=1)
    found = lotsim.layout(PLOTS / f"{name}.yaml", out, settings=settings)
    report = lotsim.validate(out)
    slots = [Polygon(s.polygon) for s in report.prepared.lot.slots]
    return found, report, slots


def _clear_of(slots, gate: tuple[float, float]) -> list[float]:
    return [round(p.centroid.distance(Point(gate)), 2) for p in slots
            if p.centroid.distance(Point(gate)) < CLEARANCE - 0.1]


@pytest.mark.slow
def test_the_strip_gets_a_loop_of_at_least_the_hand_count(tmp_path):
    found, report, slots = _laid(tmp_path, "strip30x150")
    hand = _hand([(0, 5), (12, 17), (24, 29)], AISLE, 150 - AISLE,
                 LineString([(15 - AISLE / 2, 0), (15 + AISLE / 2, 0)]))
    assert found.best.bays >= hand
    assert found.best.dead_end_length == 0.0  # a loop
    assert report.complete and len(slots) == found.best.bays
    assert all(Polygon(found.plot.boundary).buffer(1e-6).covers(p) for p in slots)
    assert _clear_of(slots, (15.0, 0.0)) == []


@pytest.mark.slow
def test_a_gate_at_a_corner_gets_a_layout_of_at_least_the_hand_count(tmp_path):
    found, report, slots = _laid(tmp_path, "corner_gate")
    # the 100 x 60 m ladder: 3 modules of 17 m across the 60 m, 34 bays a row between
    # 7 m cross aisles at both ends; the gate 1 m from the south-west corner opens onto
    # the west cross aisle: bays of the south row within the clearance of its mouth dropped
    mouth = LineString([(0, 0), (AISLE, 0)])
    rows = [(y, y + DEPTH) for m in range(3) for y in (17 * m, 17 * m + 12)]
    hand = sum(Point(AISLE + (k + 0.5) * BAY, (y0 + y1) / 2).distance(mouth) >= CLEARANCE
               for y0, y1 in rows for k in range(34))
    assert hand == 200
    assert found.best.bays >= hand
    assert report.complete and len(slots) == found.best.bays
    assert _clear_of(slots, (1.0, 0.0)) == []
    assert all(box(0, 0, 100, 60).buffer(1e-6).covers(p) for p in slots)
