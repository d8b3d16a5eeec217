"""Candidate layouts as drawn, checked by shapely alone: every bay inside the plot, clear of
its islands, of every other bay and of every aisle; every gate's aisle inside the plot; the
counts a person can work out by hand on a rectangle."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Point, Polygon

from conftest import ROOT
from lotsim.design.candidates import draw, modules_of, orientations, pitch
from lotsim.design.drawn import CLEAR
from lotsim.design.plot_yaml import read_plot
from lotsim.design.search import candidates
from lotsim.design.settings import LayoutSettings

PLOTS = sorted((ROOT / "scenarios" / "plots").glob("*.yaml"))


SHRINK = 1e-3
"""Two shapes overlap when one shrunk by this much still meets the other [m]: shapes that
only touch (a bay's entry on its aisle's edge, neighbours sharing a side) do not, whatever
GEOS makes of the sliver where their edges meet in floating point."""


def _overlaps(a, b) -> bool:
    return a.buffer(-SHRINK, join_style="mitre").intersects(b)


def _violations(plot, cand) -> list[str]:
    """What is wrong with ``cand``'s bays and aisles, by shapely's predicates."""
    outline = Polygon(plot.boundary)
    islands = [Polygon(i.polygon) for i in plot.islands]
    bays = [(r.aisle, p) for r in cand.rows for p in r.polygons]
    strips = {a.id: LineString([a.start, a.end]).buffer(a.width / 2, cap_style="flat")
              for a in cand.aisles}
    wrong = []
    for aisle, bay in bays:
        if not outline.covers(bay):
            wrong.append(f"a bay of {aisle} leaves the plot")
        if any(_overlaps(bay, i) for i in islands):
            wrong.append(f"a bay of {aisle} overlaps an island")
        for aid, strip in strips.items():
            if _overlaps(bay, strip):
                wrong.append(f"a bay of {aisle} overlaps aisle {aid}")
            if aid != aisle and bay.distance(strip) < CLEAR - 1e-9:
                wrong.append(f"a bay of {aisle} comes within {CLEAR} m of aisle {aid}")
    polys = [b for _, b in bays]
    tree = shapely.STRtree(polys)
    left, right = tree.query(polys, predicate="intersects")
    for i, j in zip(left, right, strict=True):
        if i < j and _overlaps(polys[i], polys[j]):
            wrong.append(f"bays {i} and {j} overlap")
    for g in plot.gates:  # no bay's centre within the clearance of a gate (its mouth takes
        # the gate in, to the 0.05 m its aisle is moved and the 0.02 m it begins inside)
        at = Point(g.at)
        slack = outline.exterior.distance(at) + CLEAR + 0.02 + 1e-6
        for aisle, bay in bays:
            if bay.centroid.distance(at) < plot.gate_clearance - slack:
                wrong.append(f"a bay of {aisle} stands {bay.centroid.distance(at):.2f} m from "
                             f"gate {g.id}")
    for a in cand.aisles:
        if not outline.buffer(1e-6).covers(LineString([a.start, a.end])):
            wrong.append(f"aisle {a.id} leaves the plot")
        if any(_overlaps(strips[a.id], i) for i in islands):
            wrong.append(f"aisle {a.id} crosses an island")
    return wrong


@pytest.mark.slow
@pytest.mark.parametrize("path", PLOTS, ids=lambda p: p.stem)
def test_every_drawn_bay_is_inside_the_plot_and_clear_of_islands_aisles_and_bays(path):
    plot = read_plot(path)
    drawn = candidates(plot, LayoutSettings(orientations=2, offsets=1))
    assert drawn
    for cand in drawn:
        assert _violations(plot, cand) == [], cand.label


@pytest.mark.slow
def test_the_oracle_sees_a_bay_that_overlaps():
    # the checks above can fail: a bay moved onto its neighbour, or into the island
    plot = read_plot(ROOT / "scenarios" / "plots" / "island.yaml")
    cand = candidates(plot, LayoutSettings(orientations=1, offsets=1))[0]
    row = next(r for r in cand.rows if r.count >= 2)
    row.polygons[1] = shapely.affinity.translate(row.polygons[0], 0.5, 0.0)
    assert any("overlap" in w for w in _violations(plot, cand))
    row.polygons[0] = Polygon(plot.islands[0].polygon).buffer(-1)
    assert any("island" in w for w in _violations(plot, cand))
    gate = plot.gates[0].at
    row.polygons[0] = Point(gate[0], gate[1] + 6.0).buffer(1.0)
    assert any("from gate" in w for w in _violations(plot, cand))


def test_a_rectangle_s_ring_and_modules_are_where_a_person_puts_them():
    # 100 x 60 m, 2.5 x 5.0 m bays, 7 m aisles: the ring's centre line runs one bay
    # length plus half an aisle (and the 0.05 m kept clear) in from the boundary, and
    # each module aisle crosses it from side to side
    plot = read_plot(ROOT / "scenarios" / "plots" / "rect60x100.yaml")
    module = modules_of(plot)[0]
    assert (module.angle, module.one_way, module.width) == (90, False, 7.0)
    assert pitch(module, plot) == pytest.approx(5 + 7 + 5 + CLEAR)
    cand = draw(plot, module, 0.0, 0.0, False)
    d = 5.0 + 3.5 + CLEAR
    ring = sorted(tuple(round(v, 6) for v in a.start) for a in cand.aisles if a.role == "ring")
    assert ring == [(d, d), (d, 60 - d), (100 - d, d), (100 - d, 60 - d)]
    for a in cand.aisles:
        if a.role == "module":
            assert {round(a.start[0], 6), round(a.end[0], 6)} == {d, 100 - d}
    # the perimeter row along the north side fills the ring's length with whole bays
    north = [r for r in cand.rows if r.aisle == "r1-3" and r.side == "right"]
    assert sum(r.count for r in north) == math.floor((100 - 2 * d) / 2.5)


def test_orientations_follow_the_boundary_s_edges_longest_first():
    plot = read_plot(ROOT / "scenarios" / "plots" / "trapezoid.yaml")
    got = orientations(plot, 8)
    # the 120 m south side, then square to it; the 30° side; the west side is square to
    # the south side (the same directions)
    assert got[:2] == [0.0, 90.0]
    assert any(abs(a - 150.0) < 0.1 for a in got) and len(got) == 4
    assert orientations(plot, 1) == [0.0]


def test_angled_modules_are_one_way_and_lean_the_way_their_aisle_runs():
    plot = read_plot(ROOT / "scenarios" / "plots" / "l_shape.yaml")
    kinds = {(m.angle, m.one_way, m.width) for m in modules_of(plot)}
    assert kinds == {(90, False, 7.0), (60, True, 5.5), (45, True, 4.5)}
    m45 = next(m for m in modules_of(plot) if m.angle == 45)
    cand = draw(plot, m45, 0.0, 0.0, False)
    modules = [a for a in cand.aisles if a.role == "module"]
    assert modules and all(a.one_way for a in modules)
    for a in modules:  # each angled bay's long side makes 45° with its aisle
        ux, uy = a.end[0] - a.start[0], a.end[1] - a.start[1]
        for r in cand.rows:
            if r.aisle != a.id:
                continue
            pts = list(r.polygons[0].exterior.coords)
            sides = [(pts[k + 1][0] - pts[k][0], pts[k + 1][1] - pts[k][1]) for k in range(4)]
            long = max(sides, key=lambda v: math.hypot(*v))
            cos = abs(long[0] * ux + long[1] * uy) / math.hypot(*long) / math.hypot(ux, uy)
            assert math.degrees(math.acos(cos)) == pytest.approx(45.0)


@pytest.mark.slow
def test_no_two_candidates_are_alike():
    plot = read_plot(ROOT / "scenarios" / "plots" / "island.yaml")
    drawn = candidates(plot, LayoutSettings(orientations=1, offsets=3))
    shapes = [tuple((r.aisle, r.side, round(r.start, 6), r.count) for r in c.rows)
              for c in drawn]
    assert len({tuple(sorted(s)) for s in shapes}) == len(shapes)
    assert {c.ringed for c in drawn} == {True, False}  # both ways round the island


@pytest.mark.parametrize("orientation, offset", itertools.product((0.0, 33.0), (0.0, 4.0)))
def test_a_plot_turned_gives_its_bays_turned(orientation, offset):
    # the same square drawn in a frame turned with it holds the same count of bays
    def square(turn: float) -> str:
        c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
        pts = [(x * c - y * s, x * s + y * c) for x, y in ((0, 0), (60, 0), (60, 60), (0, 60))]
        gate = (30 * c, 30 * s)
        return (f"boundary: {[[round(x, 9), round(y, 9)] for x, y in pts]}\n"
                f"gates: [{{id: g, at: [{gate[0]!r}, {gate[1]!r}]}}]\n"
                "bays: {angles_deg: [90]}\n")

    base, turned = read_plot(square(0.0)), read_plot(square(orientation))
    a = draw(base, modules_of(base)[0], 0.0, offset, False)
    b = draw(turned, modules_of(turned)[0], orientation, offset, False)
    assert a.bays == b.bays > 0


def test_spines_run_square_to_their_gate_s_edge_and_branch_at_right_angles():
    # a spine runs in from the gate on the west edge, square to it, to 1 m short of the
    # far side; with branches, aisles at right angles off it
    plot = read_plot("boundary: [[0, 0], [40, 0], [40, 50], [0, 50]]\n"
                     "gates: [{id: west, at: [0, 25]}]\nbays: {angles_deg: [90]}\n")
    drawn = [c for c in candidates(plot, LayoutSettings(orientations=2, offsets=2))
             if c.spine is not None]
    assert {c.spine[1] for c in drawn} == {False, True}
    for c in drawn:
        spine = next(a for a in c.aisles if a.role == "gate")
        assert spine.start[1] == pytest.approx(25) == spine.end[1]
        assert spine.end[0] == pytest.approx(40 - 1.0, abs=0.06)  # the dead end's room
        for b in (a for a in c.aisles if a.role == "module"):
            assert b.start[0] == pytest.approx(b.end[0])  # square to the spine
            assert b.start[1] == pytest.approx(25)        # beginning on its centre line
        assert _violations(plot, c) == []


@pytest.mark.slow
@pytest.mark.parametrize("x", [0.0, 1.0, 2.0, 3.0])
def test_a_gate_at_a_plot_s_corner_gets_candidates_whose_mouth_takes_it_in(x):
    plot = read_plot("boundary: [[0, 0], [100, 0], [100, 60], [0, 60]]\n"
                     f"gates: [{{id: south, at: [{x}, 0]}}]\nbays: {{angles_deg: [90]}}\n")
    drawn = candidates(plot, LayoutSettings(orientations=2, offsets=1))
    assert drawn and max(c.bays for c in drawn) > 150
    for c in drawn:
        assert _violations(plot, c) == [], c.label
        gate = next((a for a in c.aisles if a.id == "gate-south"), None)
        if gate is None:  # the gate opens onto the ring beside its edge, abeam of it
            assert c.along and abs(c.gates[0].entrance[0] - x) <= 3.5 + CLEAR + 1e-6
            continue
        mouth = LineString([(gate.start[0] - gate.width / 2, 0.0),
                            (gate.start[0] + gate.width / 2, 0.0)])
        assert mouth.distance(Point(x, 0.0)) <= 0.06  # the gate lies in the aisle's mouth
        strip = LineString([gate.start, gate.end]).buffer(gate.width / 2, cap_style="flat")
        assert Polygon(plot.boundary).buffer(1e-6).covers(strip)


def _random_plots(seed: int, count: int):
    """``count`` plots of 4 to 8 corners at random angles and 25-70 m from a centre (star
    shapes, concave as often as not), a gate at a random point of the edge, a 8 x 6 m
    island at the centre of some."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        n = int(rng.integers(4, 9))
        ang = np.sort(rng.uniform(0, 2 * math.pi, n))
        r = rng.uniform(25, 70, n)
        pts = [(round(float(ri * math.cos(a)), 2), round(float(ri * math.sin(a)), 2))
               for ri, a in zip(r, ang, strict=True)]
        poly = Polygon(pts)
        if not poly.is_valid:
            continue
        g = poly.exterior.interpolate(rng.uniform(0, poly.exterior.length))
        text = f"boundary: {[list(p) for p in pts]}\ngates: [{{id: g, at: [{g.x!r}, {g.y!r}]}}]\n"
        if rng.random() < 0.4:
            c = poly.centroid
            box = [[c.x - 4, c.y - 3], [c.x + 4, c.y - 3], [c.x + 4, c.y + 3], [c.x - 4, c.y + 3]]
            text += f"islands: [{{id: i, polygon: {box}}}]\n"
        out.append(read_plot(text))
    return out


@pytest.mark.slow
@pytest.mark.parametrize("plot", _random_plots(5, 4), ids=lambda p: f"{len(p.boundary)}-gon")
def test_random_plots_give_bays_clear_of_everything(plot):
    for cand in candidates(plot, LayoutSettings(orientations=2, offsets=1)):
        assert _violations(plot, cand) == [], cand.label


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(6))
def test_many_random_plots_give_bays_clear_of_everything(seed):
    for plot in _random_plots(100 + seed, 10):
        for cand in candidates(plot, LayoutSettings(orientations=3, offsets=2)):
            assert _violations(plot, cand) == [], cand.label


def test_a_gate_on_an_edge_the_ring_runs_beside_opens_straight_onto_it():
    # the 30 m strip, its gate in the middle of the south end: the ring's south leg runs
    # beside that edge (half a 7 m aisle and the clearance in), with no perimeter row
    # between; a car comes in on the lane nearer the boundary, which runs east (right-hand
    # traffic), and leaves on the far lane, westward, both abeam of the gate
    plot = read_plot(ROOT / "scenarios" / "plots" / "strip30x150.yaml")
    module = modules_of(plot)[0]
    cand = draw(plot, module, 90.0, 0.0, False, True, (0,))
    assert cand is not None and cand.along == (0,)
    assert not [a for a in cand.aisles if a.role == "gate"]
    south = next(a for a in cand.aisles if a.id == cand.gates[0].aisle)
    assert south.start[1] == pytest.approx(3.5 + CLEAR) == south.end[1]
    (x, y, h), (x2, y2, h2) = cand.gates[0].entrance, cand.gates[0].exit
    assert (x, y) == pytest.approx((15.0, 3.55 - 1.75))
    assert math.cos(h) == pytest.approx(1.0)
    assert (x2, y2) == pytest.approx((15.0, 3.55 + 1.75))
    assert math.cos(h2) == pytest.approx(-1.0)
    # no bay between the leg and the south boundary
    assert not any(p.centroid.y < 3.55 for r in cand.rows for p in r.polygons)
    assert _violations(plot, cand) == []


def _alongside(a, b) -> float:
    """How far aisles ``a`` and ``b``, parallel, run alongside each other [m]."""
    u = np.subtract(a.end, a.start) / math.dist(a.start, a.end)
    sa = sorted(float(np.dot(np.subtract(p, a.start), u)) for p in (a.start, a.end))
    sb = sorted(float(np.dot(np.subtract(p, a.start), u)) for p in (b.start, b.end))
    return min(sa[1], sb[1]) - max(sa[0], sb[0])


@pytest.mark.slow
@pytest.mark.parametrize("name", ["rect60x100", "trapezoid"])
def test_no_module_runs_beside_a_ring_leg_closer_than_a_row_each_needs(name):
    # between a module aisle and a ring leg it runs beside, room for the ring's inner row
    # and the module's row: half of each aisle, the two bays' depths and the clearance (on
    # the rectangle, the modules of the third offset would run 11.37 m from the south leg)
    plot = read_plot(ROOT / "scenarios" / "plots" / f"{name}.yaml")
    for cand in candidates(plot, LayoutSettings(orientations=1, offsets=3)):
        rings = [a for a in cand.aisles if a.role == "ring"]
        for m in (a for a in cand.aisles if a.role == "module"):
            angle = math.radians(cand.module.angle)
            deep = plot.bay_length * math.sin(angle) + plot.bay_width * math.cos(angle)
            room = plot.circulation_width / 2 + plot.bay_length + CLEAR + deep + m.width / 2
            line = LineString([m.start, m.end])
            for r in rings:
                cross = np.cross(np.subtract(m.end, m.start), np.subtract(r.end, r.start))
                if abs(cross) > 1e-6 * math.dist(m.start, m.end) * math.dist(r.start, r.end):
                    continue  # not parallel
                if _alongside(m, r) >= 1.0:
                    gap = line.distance(LineString([r.start, r.end]))
                    assert gap >= room - 1e-6, (cand.label, m.id, r.id, gap)
