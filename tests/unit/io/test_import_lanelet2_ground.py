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
from osm_xml import road_with_bays, write_osm
from shapely.geometry import Point, Polygon, box

import lotsim
from lotsim.cli import main
from lotsim.io.imports import lanelet2_ground
from lotsim.io.imports.lanelet2 import import_lanelet2
from lotsim.io.scenario_yaml import read_scenario

DATA = Path(__file__).resolve().parents[2] / "data" / "lanelet2"
MAP = DATA / "autonomoustuff_parking_lot.osm"
ORIGIN = (37.380811523812845, -121.90840595108715)  # the map's map_config yaml

def slit_map(path: Path) -> Path:
    """A 40 m two-way road 4.8 m wide with eight bays: its aisle is 5.64 m wide, so past
    each end the ground its two lanes sweep lies 1.04 m apart, and the outline grown 0.5 m
    round the drawn ground keeps a 4 cm slit between them, on the aisle's centre line, at
    the gate's mouth."""
    ways, relations = [], []
    road_with_bays(ways, relations, 4.8)
    return write_osm(path, ways, relations)


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
    src = write_osm(tmp_path / "two.osm", ways, relations)
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


@pytest.fixture(scope="session")  # once a process, however pytest-xdist splits the module
def at_its_origin(tmp_path_factory):
    lot, path = import_at(tmp_path_factory.mktemp("l2"), 0.0, 0.0)
    return lot, {s.id for s in read_scenario(path).scenario.lot.slots}


STEPS = (-0.0001, 0.0, 0.0001)  # about 11 m of latitude, 9 m of longitude
# (an outline grown without the close kept a slit at (-0.0001, 0), (-0.0001, 0.0001) and
# (0.0001, 0.0001))


@pytest.mark.slow  # eight imports of the map, several seconds each
@pytest.mark.parametrize("dlat, dlon", [
    (a, b) for a, b in itertools.product(STEPS, STEPS) if (a, b) != (0.0, 0.0)])
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


@pytest.mark.slow
def test_lotsim_import_takes_an_origin_that_used_to_refuse_the_map(tmp_path, capsys):
    lat, lon = ORIGIN[0] - 0.0001, ORIGIN[1]
    code = main(["import", "lanelet2", str(MAP), "-o", str(tmp_path),
                 "--origin", f"{lat!r},{lon!r}"])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert "1 of 1 lots written" in out.out


def test_a_map_with_no_parking_spot_is_written_without_slots_and_says_so(tmp_path):
    """A road and nothing to park in: written with its aisle and gates, no traffic, and
    the import's line says only that."""
    ways, relations = [], []
    road_with_bays(ways, relations, 6.0, bays=0)
    src = write_osm(tmp_path / "road.osm", ways, relations)
    (lot,) = import_lanelet2(src, tmp_path / "out").lots
    assert lot.written and (lot.mapped, lot.aisles, lot.gates) == (0, 1, 2)
    assert lot.reason == "no slot: no traffic written"
    sc = read_scenario(tmp_path / "out" / "road.yaml").scenario
    assert not sc.lot.slots and sc.traffic is None
