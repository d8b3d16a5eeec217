"""Gate aisles where the aisle square to the boundary cannot be drawn: a gate at an acute
corner, in a thin spike near its tip, on the edge of the notch where a spike leaves the
plot. Each small plot is checked by shapely alone: every gate aisle's strip of its width in
the plot, its pieces end to end, its last piece ending on another aisle's centre line at
30° or more, the gate's entrance and exit on the lanes of its first piece, the gate near
its mouth, and the bays clear of everything (:func:`test_candidates._violations`)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from shapely.geometry import LineString, Point, Polygon
from unit.design.test_candidates import _violations

from lotsim.design.plot_yaml import read_plot
from lotsim.design.search import candidates
from lotsim.design.settings import LayoutSettings

SETTINGS = LayoutSettings(orientations=1, offsets=1)


def _corner_plot() -> str:
    # a 90 m south side; the west side leaves the south-west corner at 72°; the gate on
    # that corner: square to either edge, the aisle leaves the plot at once
    x, y = 80 * math.cos(math.radians(72)), 80 * math.sin(math.radians(72))
    return (f"boundary: [[0, 0], [90, 0], [90, {y:.3f}], [{x:.3f}, {y:.3f}]]\n"
            "gates: [{id: g, at: [0, 0]}]\n")


def _spike_plot() -> str:
    # an 80 x 60 m plot with a spike 10 m wide at its base, 22° at its tip, on the north
    # side; the gate 3 m from the tip: square to its edge, the aisle crosses the spike
    h = 5 / math.tan(math.radians(11))
    s = 3 / math.hypot(5, h)
    return (f"boundary: [[0, 0], [80, 0], [80, 60], [40, 60], [35, {60 + h:.3f}], [30, 60], "
            f"[0, 60]]\ngates: [{{id: g, at: [{35 - 5 * s:.6f}, {60 + h - h * s:.6f}]}}]\n")


def _notch_plot() -> str:
    # a 70 x 50 m plot with a spike 20 m tall off its north side; the gate on the notch
    # between the spike's east edge and the north side, 2.5 m from its reflex corner:
    # square to that edge, the aisle crosses the spike and leaves the plot
    return ("boundary: [[0, 0], [70, 0], [70, 50], [44, 50], [40, 70], [36, 50], [0, 50]]\n"
            "gates: [{id: g, at: [43.5, 52.5]}]\n")


PLOTS = {"acute corner": _corner_plot, "thin spike": _spike_plot, "notch": _notch_plot}


def _unit(a, b):
    d = (b[0] - a[0], b[1] - a[1])
    n = math.hypot(*d)
    return d[0] / n, d[1] / n


def _gate_problems(plot, cand) -> list[str]:
    """What is wrong with ``cand``'s gate aisles, by shapely and plain geometry."""
    outline = Polygon(plot.boundary)
    wrong = []
    others = [a for a in cand.aisles if a.role != "gate"]
    for spec, gate in zip(plot.gates, cand.gates, strict=True):
        pieces = [a for a in cand.aisles if a.role == "gate" and
                  (a.id == gate.aisle or a.id.startswith(gate.aisle + "-"))]
        if not pieces or pieces[0].id != gate.aisle:
            if not any(a.id == gate.aisle for a in others):
                wrong.append(f"gate {gate.id} has no aisle")
            continue
        for a in pieces:
            strip = LineString([a.start, a.end]).buffer(a.width / 2, cap_style="flat")
            if not outline.buffer(1e-6).covers(strip):
                wrong.append(f"{a.id}'s strip leaves the plot")
        for a, b in zip(pieces, pieces[1:], strict=False):
            if math.dist(a.end, b.start) > 1e-9:
                wrong.append(f"{a.id} and {b.id} do not meet end to end")
        last = pieces[-1]
        if cand.spine is None:
            end = Point(last.end)
            met = [o for o in others if LineString([o.start, o.end]).distance(end) < 1e-6]
            if not met:
                wrong.append(f"{last.id} ends on no aisle")
            u = _unit(last.start, last.end)
            for o in met:
                v = _unit(o.start, o.end)
                angle = math.degrees(math.acos(min(1.0, abs(u[0] * v[0] + u[1] * v[1]))))
                if angle < 30.0 - 1e-6:
                    wrong.append(f"{last.id} meets {o.id} at {angle:.1f}°")
        first = pieces[0]
        centre = LineString([first.start, first.end])
        u = _unit(first.start, first.end)
        for name, (x, y, h), way in (("entrance", gate.entrance, 1.0),
                                     ("exit", gate.exit, -1.0)):
            off = centre.distance(Point(x, y))  # on the middle of a lane, past the mouth
            if abs(off - first.width / 4) > 1e-6 or centre.project(Point(x, y)) <= 0.0:
                wrong.append(f"gate {gate.id}'s {name} is not on a lane of {first.id}")
            if abs(math.cos(h) * u[0] + math.sin(h) * u[1] - way) > 1e-6:  # in, or out
                wrong.append(f"gate {gate.id}'s {name} does not head along {first.id}")
        if math.dist(spec.at, first.start) > 30.0 + 1e-6 or \
                not outline.buffer(0.5).covers(LineString([spec.at, first.start])):
            wrong.append(f"gate {gate.id} is not near its aisle's mouth")
    return wrong


@pytest.mark.parametrize("kind", PLOTS)
def test_a_gate_where_no_square_aisle_fits_gets_candidates_with_a_gate_aisle_in_the_plot(kind):
    plot = read_plot(PLOTS[kind]())
    drawn = candidates(plot, SETTINGS)
    assert any(c.spine is None for c in drawn), "no ring candidate"
    for c in drawn:
        assert _gate_problems(plot, c) == [], c.label
        assert _violations(plot, c) == [], c.label


def test_a_gate_on_an_acute_corner_has_its_aisle_along_the_corner_s_bisector():
    # the corner's bisector runs at 36° from the south side; the ring's corner lies on it
    plot = read_plot(_corner_plot())
    ring = [c for c in candidates(plot, SETTINGS) if c.spine is None]
    assert ring
    for c in ring:
        gate = next(a for a in c.aisles if a.id == c.gates[0].aisle)
        u = _unit(gate.start, gate.end)
        assert math.degrees(math.atan2(u[1], u[0])) == pytest.approx(36.0, abs=5.0)


def test_the_oracle_sees_a_gate_aisle_that_leaves_the_plot_or_meets_nothing():
    plot = read_plot(_spike_plot())
    c = next(c for c in candidates(plot, SETTINGS) if c.spine is None)
    gate = next(a for a in c.aisles if a.id == c.gates[0].aisle)
    gate.start = (gate.start[0] + 4.0, gate.start[1])
    assert any("leaves the plot" in w for w in _gate_problems(plot, c))
    last = [a for a in c.aisles if a.role == "gate"][-1]
    last.end = (last.end[0] + 0.5 * (last.end[0] - last.start[0]), last.end[1])
    assert any("ends on no aisle" in w or "leaves" in w for w in _gate_problems(plot, c))


def test_only_a_candidate_that_cannot_have_square_gate_aisles_is_drawn_turned():
    # 1 m from the south-west corner of a 100 x 60 m plot: a ring inside perimeter rows
    # has no square gate aisle (it would leave the plot), so it comes turned, along the
    # corner's bisector (45°); the ring along the gate's edges opens onto it square, as
    # before, and a 100 x 60 m plot's gate at the middle of its side turns nowhere
    root = Path(__file__).resolve().parents[3] / "scenarios" / "plots"
    drawn = candidates(read_plot(root / "corner_gate.yaml"), SETTINGS)
    turned = [c for c in drawn if c.gates[0].approach is not None]
    square = [c for c in drawn if c.gates[0].approach is None]
    assert turned and square
    for c in turned:
        gate = next(a for a in c.aisles if a.id == c.gates[0].aisle)
        u = _unit(gate.start, gate.end)
        assert math.degrees(math.atan2(u[1], u[0])) == pytest.approx(45.0, abs=5.0)
        assert not c.along and _violations(read_plot(root / "corner_gate.yaml"), c) == []
    assert all(c.gates[0].approach is None
               for c in candidates(read_plot(root / "rect60x100.yaml"), SETTINGS))
