"""Angled spots mapped in OpenStreetMap (``amenity=parking_space`` areas) and in Lanelet2
maps (``parking_spot`` areas) are imported as angled slots at their angle: rows of 45° and
60° bays beside an aisle, drawn as lotsim lays angled rows out (rectangles sharing long
sides) and as they are painted (parallelograms along the aisle's edge). Checked with shapely
against the outlines the files were written from: a rectangle's slot is its outline within
a few centimetres, a parallelogram's the largest rectangle along its long sides inside it,
and every slot's long side makes its angle with the aisle within a degree. The lots build,
and ``lotsim validate`` finds every slot usable."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from osm_xml import angled_row, painted_row, write_osm
from shapely.geometry import Polygon

import lotsim
from lotsim.io.imports.lanelet2 import import_lanelet2
from lotsim.io.imports.osm import osm_scenarios
from lotsim.io.scenario_yaml import read_scenario

ROWS = {"north-45": (45, 10.0), "north-60": (60, 32.0)}  # rectangles: angle, first x
PAINTED = {"south-45": (45, 8.0), "south-60": (60, 30.0)}  # parallelograms


def slot_shape(s) -> Polygon:
    c = np.asarray(s.center)
    d = np.array([math.cos(s.heading), math.sin(s.heading)])
    n = np.array([-d[1], d[0]])
    hl, hw = s.length / 2, s.width / 2
    return Polygon([c - hl * d - hw * n, c + hl * d - hw * n, c + hl * d + hw * n,
                    c - hl * d + hw * n])


def to_aisle_deg(s, aisle_dir=(1.0, 0.0)) -> float:
    """The angle between a slot's long side and the aisle [degrees], 0 to 90."""
    d = np.array([math.cos(s.heading), math.sin(s.heading)])
    return math.degrees(math.acos(min(1.0, abs(float(np.dot(d, aisle_dir))))))


def inscribed(outline: list, angle_deg: float) -> Polygon:
    """The largest rectangle inside a parallelogram along its slanted sides, worked out by
    sliding: the strip between the slanted sides, cut back from each painted line until
    both its corners are inside."""
    p = Polygon(outline)
    a, b, c, d = (np.asarray(q, dtype=float) for q in outline)
    u = (d - a) / np.hypot(*(d - a))  # along a slanted side
    n = np.array([-u[1], u[0]])
    n = n if np.dot(b - a, n) > 0 else -n
    w = float(np.dot(b - a, n))  # between the slanted sides
    ts = np.arange(0.0, float(np.hypot(*(d - a))), 0.001)
    inside = [t for t in ts if p.buffer(1e-6).covers(shapely.Point(a + u * t + n * w))
              and p.buffer(1e-6).covers(shapely.Point(a + u * t))]
    t0 = min(inside)
    t1 = max(t for t in ts if p.buffer(1e-6).covers(shapely.Point(a + u * t))
             and p.buffer(1e-6).covers(shapely.Point(a + u * (t - t0) + n * w)))
    return Polygon([a + u * t0, a + u * t1, a + u * t1 + n * w, a + u * t0 + n * w]) \
        if t1 > t0 else Polygon()


def check_slots(slots, rects: dict, painted: dict, within: float) -> None:
    """Every mapped spot is a slot of the kind and angle it is drawn at: a rectangle's is its
    outline, a parallelogram's the rectangle inside it, ``within`` [m], and it keeps inside
    the outline as closely."""
    by_id = {s.id: s for s in slots}
    assert set(by_id) == set(rects) | set(painted)
    for sid, (outline, deg) in {**rects, **painted}.items():
        s = by_id[sid]
        assert s.kind == "angled", sid
        assert to_aisle_deg(s) == pytest.approx(deg, abs=1.0), sid
        want = Polygon(outline) if sid in rects else inscribed(outline, deg)
        got = slot_shape(s)
        assert got.hausdorff_distance(want) < within, (sid, got.hausdorff_distance(want))
        assert Polygon(outline).buffer(within).covers(got), sid


def usable_everywhere(path: Path) -> None:
    report = lotsim.validate(path)
    slots = {s.id for s in report.prepared.lot.slots}
    assert {t: set(ids) for t, ids in report.usable().items()} == {
        t: slots for t in report.usable()}, report.summary()


# -- Lanelet2 ----------------------------------------------------------------------------------
def lanelet2_map(path: Path):
    """A 60 m two-way road along x (y 0..6, both ends open). North: a 1 m access strip and
    two rows of 2.5 × 5 m bays at 45° and 60° whose entries slant away from the aisle, the
    access area following their saw-tooth; cars drive in heading west, the way the lane on
    that side runs. South: a straight 1 m access strip and two rows of bays painted at 45°
    and 60° as parallelograms 5.5 m deep, entered heading east."""
    ways, relations = [], []

    def way(pts, **tags):
        wid = -(1000 + len(ways))
        ways.append((wid, pts, tags))
        return wid

    south = way([(0, 0), (60, 0)], type="line_thin", subtype="solid")
    middle = way([(0, 3), (60, 3)], type="line_thin", subtype="dashed")
    north = way([(0, 6), (60, 6)], type="line_thin", subtype="solid")
    relations.append((-1, [(middle, "left"), (south, "right")],
                      {"type": "lanelet", "subtype": "lane"}))
    relations.append((-2, [(middle, "left"), (north, "right")],
                      {"type": "lanelet", "subtype": "lane"}))
    rects, top = {}, []
    for deg, x in (ROWS["north-60"], ROWS["north-45"]):  # the saw-tooth east to west
        bays, saw = angled_row(deg, 4, x, 7.0)
        top += [(saw[0][0], 7.0), *saw]
        for bay in bays:
            rects[f"P{way([*bay, bay[0]], type='area', subtype='parking_spot')}"] = (bay, deg)
    way([(5, 6), (55, 6), (55, 7), *top, (5, 7), (5, 6)], type="area",
        subtype="parking_access")
    way([(5, 0), (5, -1), (55, -1), (55, 0), (5, 0)], type="area", subtype="parking_access")
    painted = {}
    for deg, x in PAINTED.values():
        for bay in painted_row(deg, 4, x, -1.0):
            painted[f"P{way([*bay, bay[0]], type='area', subtype='parking_spot')}"] = (bay, deg)
    return write_osm(path, ways, relations), rects, painted


@pytest.fixture(scope="session")  # once a process, however pytest-xdist splits the module
def lanelet2_lot(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("angled-l2")
    src, rects, painted = lanelet2_map(tmp / "angled.osm")
    report = import_lanelet2(src, tmp / "out", origin=(48.0, 11.0))
    return report, tmp / "out" / "angled.yaml", rects, painted


@pytest.mark.slow
def test_lanelet2_angled_spots_are_angled_slots_at_their_angle(lanelet2_lot):
    report, path, rects, painted = lanelet2_lot
    (lot,) = report.lots
    assert lot.mapped == 16 and not lot.reason
    check_slots(read_scenario(path).scenario.lot.slots, rects, painted, 0.03)
    text = path.read_text()
    assert "kind: angled, angle_deg: 45," in text and "kind: angled, angle_deg: 60," in text
    assert "# Spots drawn as parallelograms" in text


def test_lanelet2_angled_lot_validates_with_every_slot_usable(lanelet2_lot):
    _, path, _, _ = lanelet2_lot
    usable_everywhere(path)


# -- OpenStreetMap -----------------------------------------------------------------------------
def osm_lot(path: Path):
    """A 60 × 30 m lot (way 1) with a two-way aisle along y = 15 (7 m: edges at 11.5 and
    18.5) from a road 5 m west of it; north of the aisle two rows of 2.5 × 5 m bays at 45°
    and 60°, drawn as rectangles; south, two rows painted at 45° and 60° as parallelograms
    5.5 m deep, tagged parking:orientation=diagonal."""
    ways = [(1, [(0, 0), (60, 0), (60, 30), (0, 30), (0, 0)], {"amenity": "parking"}),
            (2, [(-5, 15), (55, 15)], {"highway": "service", "service": "parking_aisle"}),
            (3, [(-5, -20), (-5, 15), (-5, 50)], {"highway": "residential"})]
    rects, painted = {}, {}
    for deg, x in ROWS.values():
        for bay in angled_row(deg, 4, x, 18.5)[0]:
            wid = 100 + len(ways)
            ways.append((wid, [*bay, bay[0]], {"amenity": "parking_space"}))
            rects[f"w{wid}"] = (bay, deg)
    for deg, x in PAINTED.values():
        for bay in painted_row(deg, 4, x, 11.5):
            wid = 100 + len(ways)
            ways.append((wid, [*bay, bay[0]], {"amenity": "parking_space",
                                               "parking:orientation": "diagonal"}))
            painted[f"w{wid}"] = (bay, deg)
    return write_osm(path, ways, [], origin=(60.0, 25.0)), rects, painted


@pytest.fixture(scope="session")  # once a process, however pytest-xdist splits the module
def osm_imported(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("angled-osm")
    src, rects, painted = osm_lot(tmp / "angled.osm")
    report = osm_scenarios(src, tmp / "out")
    return report, tmp / "out" / "way-1.yaml", rects, painted


@pytest.mark.slow
def test_osm_angled_spaces_are_angled_slots_at_their_angle(osm_imported):
    """Within 5 cm: each bay is moved 2 cm off the aisle's edge, where its front corner lies,
    and drawn 1 cm inside its long sides. The lot's frame is centred on its centroid
    (30, 15): the outlines are shifted so."""
    report, path, rects, painted = osm_imported
    (lot,) = report.lots
    assert lot.written and lot.mapped == 16
    shifted = {k: ([(x - 30.0, y - 15.0) for x, y in o], deg) for k, (o, deg) in rects.items()}
    shifted_p = {k: ([(x - 30.0, y - 15.0) for x, y in o], deg)
                 for k, (o, deg) in painted.items()}
    check_slots(read_scenario(path).scenario.lot.slots, shifted, shifted_p, 0.05)
    text = path.read_text()
    assert "# parking_space way 103 (at 45° to the aisle)" in text
    assert "# parking_space way 107 (at 60° to the aisle)" in text
    assert "a parallelogram: the rectangle inside it" in text


def test_osm_angled_lot_validates_with_every_slot_usable(osm_imported):
    _, path, _, _ = osm_imported
    usable_everywhere(path)


def test_a_space_tagged_diagonal_but_drawn_square_is_written_perpendicular_and_said(
        tmp_path):
    ways = [(1, [(0, 0), (40, 0), (40, 20), (0, 20), (0, 0)], {"amenity": "parking"}),
            (2, [(-5, 10), (35, 10)], {"highway": "service", "service": "parking_aisle"}),
            (3, [(-5, -20), (-5, 40)], {"highway": "residential"}),
            (4, [(20, 13.5), (22.5, 13.5), (22.5, 18.5), (20, 18.5), (20, 13.5)],
             {"amenity": "parking_space", "parking:orientation": "diagonal"})]
    src = write_osm(tmp_path / "square.osm", ways, [], origin=(60.0, 25.0))
    osm_scenarios(src, tmp_path / "out")
    text = (tmp_path / "out" / "way-1.yaml").read_text()
    assert ("# parking_space way 4 (at 90° to the aisle; tagged "
            "parking:orientation=diagonal, drawn perpendicular)") in text
    (slot,) = read_scenario(tmp_path / "out" / "way-1.yaml").scenario.lot.slots
    assert slot.kind == "perpendicular"
