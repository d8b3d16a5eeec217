"""The ground a Lanelet2 import draws (lotsim.io.imports.lanelet2_ground and the aisles kept
inside it): the boundary has no slit narrower than a car could use, a gate aisle ends inside
it wherever the map's origin puts the numbers, and an aisle whose lanelets leave it is cut
back or dropped, said in the report, never a refusal of the whole map. Maps are written
here as Lanelet2 OSM XML; the boundary is checked with shapely on the file as written."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon, box

import lotsim
from lotsim.cli import main
from lotsim.io.imports import lanelet2_ground
from lotsim.io.imports.lanelet2 import import_lanelet2
from lotsim.io.scenario_yaml import read_scenario

DATA = Path(__file__).resolve().parents[2] / "data" / "lanelet2"
MAP = DATA / "autonomoustuff_parking_lot.osm"
ORIGIN = (37.380811523812845, -121.90840595108715)  # the map's map_config yaml

A, F = 6378137.0, 1 / 298.257223563  # WGS84
E2 = F * (2 - F)


def write_lanelet2(path: Path, ways, relations, origin=(48.0, 11.0)) -> Path:
    """A Lanelet2 OSM XML file: ``ways`` as (id, points [m], tags), ``relations`` as (id,
    [(way id, role)], tags); metres east and north of ``origin`` turned into degrees by the
    ellipsoid's meridian and prime-vertical radii there."""
    lat0, lon0 = origin
    la = math.radians(lat0)
    m_r = A * (1 - E2) / (1 - E2 * math.sin(la) ** 2) ** 1.5
    n_r = A / math.sqrt(1 - E2 * math.sin(la) ** 2)
    nodes: dict[tuple[float, float], int] = {}
    lines = ["<?xml version='1.0' encoding='UTF-8'?>", "<osm version='0.6'>"]
    body = []
    for wid, pts, tags in ways:
        body.append(f"  <way id='{wid}'>")
        for x, y in pts:
            key = (round(x, 6), round(y, 6))
            nodes.setdefault(key, -(len(nodes) + 1))
            body.append(f"    <nd ref='{nodes[key]}' />")
        body += [f"    <tag k='{k}' v='{v}' />" for k, v in tags.items()]
        body.append("  </way>")
    for rid, members, tags in relations:
        body.append(f"  <relation id='{rid}'>")
        body += [f"    <member type='way' ref='{w}' role='{role}' />" for w, role in members]
        body += [f"    <tag k='{k}' v='{v}' />" for k, v in tags.items()]
        body.append("  </relation>")
    for (x, y), nid in nodes.items():
        lat = lat0 + math.degrees(y / m_r)
        lon = lon0 + math.degrees(x / (n_r * math.cos(la)))
        lines.append(f"  <node id='{nid}' lat='{lat:.11f}' lon='{lon:.11f}' />")
    path.write_text("\n".join(lines + body + ["</osm>"]) + "\n")
    return path


def road_with_bays(ways, relations, width: float, *, x0=0.0, y0=0.0, length=40.0,
                   bays=8, first_id=1000):
    """A two-way road ``width`` wide from (x0, y0) east ``length`` m (two lanelets side by
    side sharing their middle bound, both ends open), a 1 m access strip along its north
    edge and ``bays`` 2.5 × 5 m spots behind it."""
    def way(pts, **tags):
        wid = -(first_id + len(ways))
        ways.append((wid, [(x0 + x, y0 + y) for x, y in pts], tags))
        return wid

    south = way([(0, 0), (length, 0)], type="line_thin", subtype="solid")
    middle = way([(0, width / 2), (length, width / 2)], type="line_thin", subtype="dashed")
    north = way([(0, width), (length, width)], type="line_thin", subtype="solid")
    n = len(relations)
    relations.append((-(first_id + n + 1), [(middle, "left"), (south, "right")],
                      {"type": "lanelet", "subtype": "lane"}))
    relations.append((-(first_id + n + 2), [(middle, "left"), (north, "right")],
                      {"type": "lanelet", "subtype": "lane"}))
    start = (length - 2.5 * bays) / 2
    way([(start - 2, width), (length - start + 2, width), (length - start + 2, width + 1),
         (start - 2, width + 1), (start - 2, width)], type="area", subtype="parking_access")
    for k in range(bays):
        x = start + 2.5 * k
        way([(x, width + 1), (x + 2.5, width + 1), (x + 2.5, width + 6), (x, width + 6),
             (x, width + 1)], type="area", subtype="parking_spot")


def slit_map(path: Path) -> Path:
    """A 40 m two-way road 4.8 m wide with eight bays: its aisle is 5.64 m wide, so past
    each end the ground its two lanes sweep lies 1.04 m apart, and the outline grown 0.5 m
    round the drawn ground keeps a 4 cm slit between them, on the aisle's centre line, at
    the gate's mouth."""
    ways, relations = [], []
    road_with_bays(ways, relations, 4.8)
    return write_lanelet2(path, ways, relations)


def written(path: Path):
    sf = read_scenario(path)
    return sf.scenario.lot, Polygon(sf.scenario.lot.boundary)


def slits(boundary: Polygon, width=0.2, depth=0.3, step=0.05) -> list[tuple[float, float]]:
    """Points of the outline that no disc ``width`` across lying outside the boundary
    comes within ``depth`` of: the inside of a slit narrower than ``width`` and deeper than
    ``depth`` (at a corner of the outline of angle θ such a disc comes within
    ``width`` / 2 (1 / sin(θ / 2) - 1), under ``depth`` for every corner over 29°)."""
    r = width / 2
    outside = box(*boundary.buffer(5).bounds).difference(boundary).buffer(-r)
    ring = boundary.exterior
    out = []
    for s in np.arange(0, ring.length, step):
        p = ring.interpolate(s)
        if outside.distance(p) > r + depth:
            out.append((round(p.x, 2), round(p.y, 2)))
    return out


# -- the slit at a gate's mouth ----------------------------------------------------------------
def test_the_probe_finds_the_slit_it_is_meant_to_find():
    """A 4 cm slit 0.8 m deep in a square is found; a 30° notch is not."""
    square = box(0, 0, 10, 10)
    assert not slits(square)
    cut = square.difference(box(9.2, 4.98, 10.5, 5.02))
    found = slits(cut)
    assert found and all(9.2 <= x <= 9.9 and 4.9 < y < 5.1 for x, y in found)
    t = math.tan(math.radians(15))
    assert not slits(square.difference(Polygon([(4, 5), (11, 5 - 7 * t), (11, 5 + 7 * t)])))


def test_a_gate_aisle_at_a_slit_of_the_drawn_ground_imports_builds_and_validates(tmp_path):
    src = slit_map(tmp_path / "slit.osm")
    report = import_lanelet2(src, tmp_path / "out")
    (lot,) = report.lots
    assert lot.written and lot.mapped == 8 and lot.gates == 2
    path = tmp_path / "out" / "slit.yaml"
    spec, boundary = written(path)
    assert not slits(boundary)
    (aisle,) = spec.aisles
    for end in (aisle.centerline[0], aisle.centerline[-1]):
        assert boundary.exterior.distance(Point(end)) >= 0.015  # 2 cm in, to the cm
        assert boundary.contains(Point(end))
    checked = lotsim.validate(path)
    assert checked.complete, checked.summary()


def test_the_boundary_is_the_grown_ground_except_where_it_fills_a_slit(tmp_path):
    """Closing the outline moves it nowhere but into the slits: the closed boundary and the
    one grown 0.5 m without the close lie within the outline's simplification (0.1 m) and
    the centimetre of each other, except within a metre of the slits' mouths."""
    src = slit_map(tmp_path / "slit.osm")
    import_lanelet2(src, tmp_path / "out")
    _, closed = written(tmp_path / "out" / "slit.yaml")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(lanelet2_ground, "BOUNDARY_CLOSE", 0.0)
        import_lanelet2(src, tmp_path / "open")
    _, grown = written(tmp_path / "open" / "slit.yaml")
    found = slits(grown)
    assert found  # without the close, the slits are there
    near = 0.1 + 0.011
    assert closed.buffer(near).covers(grown)
    mouths = shapely.MultiPoint(found).buffer(1.0)
    extra = closed.difference(grown.buffer(near)).difference(mouths)
    assert extra.area < 1e-4, extra


def test_an_aisle_that_leaves_the_boundary_is_cut_back_and_said(tmp_path):
    """Without the close, the gate aisle runs into the slit: it is cut back inside the
    boundary, the header and the report say so, and the lot builds."""
    src = slit_map(tmp_path / "slit.osm")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(lanelet2_ground, "BOUNDARY_CLOSE", 0.0)
        report = import_lanelet2(src, tmp_path / "out")
    (lot,) = report.lots
    assert lot.written and lot.mapped == 8
    assert "aisle L-1002 cut back by" in lot.reason
    text = (tmp_path / "out" / "slit.yaml").read_text()
    assert "# aisle L-1002 cut back by" in text
    spec, boundary = written(tmp_path / "out" / "slit.yaml")
    (aisle,) = spec.aisles
    assert boundary.buffer(1e-6).covers(shapely.LineString(aisle.centerline))


def test_a_road_off_the_lots_ground_is_dropped_and_named(tmp_path):
    """A second road 30 m north, drawn apart from the lot: the boundary holds the larger
    ground; the other road's aisle is dropped, the report names it, and its spots are
    listed as not imported, with why."""
    ways, relations = [], []
    road_with_bays(ways, relations, 6.0)
    road_with_bays(ways, relations, 6.0, y0=30.0, length=20.0, bays=2, first_id=2000)
    src = write_lanelet2(tmp_path / "two.osm", ways, relations)
    report = import_lanelet2(src, tmp_path / "out")
    (lot,) = report.lots
    assert lot.written and lot.mapped == 8 and lot.aisles == 1
    assert "aisle L-2004 dropped: its lanelets lie outside the lot's boundary" in lot.reason
    text = (tmp_path / "out" / "two.yaml").read_text()
    assert "# aisle L-2004 dropped" in text
    assert text.count("opens onto aisle L-2004, dropped") == 2


# -- the shipped map, wherever its origin is put ---------------------------------------------
def import_at(tmp_path: Path, dlat: float, dlon: float):
    out = tmp_path / f"{dlat:+.4f}{dlon:+.4f}"
    report = import_lanelet2(MAP, out, origin=(ORIGIN[0] + dlat, ORIGIN[1] + dlon))
    return report.lots[0], out / "autonomoustuff_parking_lot.yaml"


@pytest.fixture(scope="module")
def at_its_origin(tmp_path_factory):
    lot, path = import_at(tmp_path_factory.mktemp("l2"), 0.0, 0.0)
    return lot, {s.id for s in read_scenario(path).scenario.lot.slots}


STEPS = (-0.0001, 0.0, 0.0001)  # about 11 m of latitude, 9 m of longitude


@pytest.mark.parametrize("dlat, dlon", [(a, b) for a, b in itertools.product(STEPS, STEPS)
                                        if (a, b) != (0.0, 0.0)])
def test_the_shipped_map_imports_the_same_near_its_own_origin(tmp_path, at_its_origin,
                                                              dlat, dlon):
    """The origin moves the numbers by centimetres' worth of rounding, not the lot: the
    same slots, aisles and gates, and no slit in the boundary. (At (-0.0001, 0),
    (-0.0001, +0.0001) and (+0.0001, +0.0001), an outline grown without the close keeps a
    3 cm slit at the mouth of the gate aisle L6714, which ends inside it.)"""
    base, slots = at_its_origin
    lot, path = import_at(tmp_path, dlat, dlon)
    assert (lot.mapped, lot.aisles, lot.gates) == (base.mapped, base.aisles, base.gates)
    spec, boundary = written(path)
    assert {s.id for s in spec.slots} == slots
    assert not slits(boundary)


@pytest.mark.slow
@pytest.mark.parametrize("dlat", (-0.001, -0.0003, 0.0003, 0.001))
def test_the_shipped_map_imports_wherever_its_origin_is_put_nearby(tmp_path, at_its_origin,
                                                                   dlat):
    base, slots = at_its_origin
    for dlon in (-0.001, -0.0003, 0.0, 0.0003, 0.001):
        lot, path = import_at(tmp_path, dlat, dlon)
        assert lot.mapped == base.mapped, (dlat, dlon)
        assert {s.id for s in read_scenario(path).scenario.lot.slots} == slots


def test_lotsim_import_takes_an_origin_that_used_to_refuse_the_map(tmp_path, capsys):
    lat, lon = ORIGIN[0] - 0.0001, ORIGIN[1]
    code = main(["import", "lanelet2", str(MAP), "-o", str(tmp_path),
                 "--origin", f"{lat!r},{lon!r}"])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert "1 of 1 lots written" in out.out
