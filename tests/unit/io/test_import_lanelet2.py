"""The Lanelet2 importer (lotsim.io.imports.lanelet2), checked against the map read
independently: the XML with ElementTree, positions by a closed-form east-north projection of
WGS84, shapes with shapely. A small map written here imports, builds and validates; bad
inputs give a LotsimError and write nothing."""

from __future__ import annotations

import math
import re
import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from lotsim.errors import LotsimError, ScenarioError
from lotsim.io.imports.lanelet2 import import_lanelet2
from lotsim.io.scenario_yaml import load_scenario, read_scenario

DATA = Path(__file__).resolve().parents[2] / "data" / "lanelet2"
MAP = DATA / "autonomoustuff_parking_lot.osm"
ORIGIN = (37.380811523812845, -121.90840595108715)  # the map's map_config yaml, read by eye

A, F = 6378137.0, 1 / 298.257223563  # WGS84
E2 = F * (2 - F)


def enu(lat, lon, lat0, lon0):
    """East, north [m] of points in the plane tangent to WGS84 at (lat0, lon0): the points
    on the ellipsoid in Earth-centred coordinates, rotated into east and north there."""
    def ecef(la, lo):
        la, lo = np.radians(la), np.radians(lo)
        n = A / np.sqrt(1 - E2 * np.sin(la) ** 2)
        return np.stack([n * np.cos(la) * np.cos(lo), n * np.cos(la) * np.sin(lo),
                         n * (1 - E2) * np.sin(la)], axis=-1)
    d = ecef(np.asarray(lat, float), np.asarray(lon, float)) - ecef(lat0, lon0)
    la, lo = math.radians(lat0), math.radians(lon0)
    east = d @ [-math.sin(lo), math.cos(lo), 0.0]
    north = d @ [-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la)]
    return east, north


def tags(e) -> dict[str, str]:
    return {t.get("k"): t.get("v") for t in e.findall("tag")}


def mapped_spots(path: Path, origin) -> dict[str, Polygon]:
    """Every parking_spot area of the file (multipolygon relations; closed ways that are no
    relation's member) as a polygon in local metres."""
    root = ET.parse(path).getroot()
    nodes = {n.get("id"): (float(n.get("lat")), float(n.get("lon"))) for n in root.iter("node")}
    ways = {w.get("id"): [n.get("ref") for n in w.findall("nd")] for w in root.iter("way")}
    out, members = {}, set()

    def poly(refs):
        lat, lon = zip(*(nodes[r] for r in refs), strict=True)
        x, y = enu(lat, lon, *origin)
        return shapely.polygonize([shapely.LineString(np.column_stack([x, y]))]).geoms[0]

    for r in root.iter("relation"):
        t = tags(r)
        if t.get("type") == "multipolygon" and t.get("subtype") == "parking_spot":
            refs = [m.get("ref") for m in r.findall("member") if m.get("type") == "way"]
            members.update(refs)
            lines = [shapely.LineString(np.column_stack(enu(
                *zip(*(nodes[n] for n in ways[w]), strict=True), *origin))) for w in refs]
            out[r.get("id")] = shapely.polygonize(lines).geoms[0]
    for w in root.iter("way"):
        refs = ways[w.get("id")]
        if (tags(w).get("subtype") == "parking_spot" and refs[0] == refs[-1]
                and w.get("id") not in members):
            out[w.get("id")] = poly(refs)
    return out


def slot_shape(s) -> Polygon:
    c = np.asarray(s.center)
    d = np.array([math.cos(s.heading), math.sin(s.heading)])
    n = np.array([-d[1], d[0]])
    hl, hw = s.length / 2, s.width / 2
    return Polygon([c - hl * d - hw * n, c + hl * d - hw * n, c + hl * d + hw * n,
                    c - hl * d + hw * n])


@pytest.fixture(scope="session")  # once a process, however pytest-xdist splits the module
def imported(tmp_path_factory):
    out = tmp_path_factory.mktemp("l2")
    report = import_lanelet2(MAP, out)
    path = out / "autonomoustuff_parking_lot.yaml"
    text = path.read_text()
    return report, path, text, read_scenario(path)


def reported(text: str) -> dict[str, str]:
    return dict(re.findall(r"^# spot (\S+) not imported: (.*)$", text, flags=re.M))


def test_every_mapped_spot_is_a_slot_or_reported_with_why(imported):
    report, path, text, sf = imported
    spots = mapped_spots(MAP, ORIGIN)
    assert len(spots) == 240  # the map's parking_spot areas, counted by hand in JOSM too
    slots = {s.id for s in sf.scenario.lot.slots}
    why = reported(text)
    assert slots.isdisjoint({f"P{k}" for k in why})
    assert slots | {f"P{k}" for k in why} == {f"P{k}" for k in spots}
    assert all(why.values())
    (lot,) = report.lots
    assert lot.written and lot.mapped == len(slots) and lot.path == path
    assert len(slots) >= 190  # the import serves most of the map's spots


def test_the_kinds_are_what_the_spots_geometry_says(imported):
    """Each slot is perpendicular: its long side makes 80-100 degrees with the lanelet it
    faces (the nearest lanelet's direction, read here from the file's bounds)."""
    *_, sf = imported
    root = ET.parse(MAP).getroot()
    nodes = {n.get("id"): (float(n.get("lat")), float(n.get("lon"))) for n in root.iter("node")}
    ways = {w.get("id"): [n.get("ref") for n in w.findall("nd")] for w in root.iter("way")}
    segs = []
    for r in root.iter("relation"):
        if tags(r).get("type") == "lanelet":
            (left,) = [m.get("ref") for m in r.findall("member") if m.get("role") == "left"]
            lat, lon = zip(*(nodes[n] for n in ways[left]), strict=True)
            x, y = enu(lat, lon, *ORIGIN)
            segs += [shapely.LineString([(x[i], y[i]), (x[i + 1], y[i + 1])])
                     for i in range(len(x) - 1)]
    tree = shapely.STRtree(segs)
    kinds = {}
    for s in sf.scenario.lot.slots:
        seg = segs[tree.nearest(shapely.Point(s.center))]
        (x0, y0), (x1, y1) = seg.coords
        road = math.atan2(y1 - y0, x1 - x0)
        angle = abs(math.degrees(math.remainder(s.heading - road, math.pi)))
        kinds[s.id] = "perpendicular" if angle > 80 else "angled" if angle > 10 else "parallel"
    assert kinds == {s.id: s.kind for s in sf.scenario.lot.slots}


def test_slots_are_the_mapped_spots(imported):
    """Each slot covers its mapped outline but a rim of at most a few centimetres: the map's
    spots are not quite rectangles (up to 7 cm off), neighbours share sides, and a slot is
    drawn 1 cm in from them (more where written neighbours would still overlap)."""
    *_, sf = imported
    spots = mapped_spots(MAP, ORIGIN)
    worst = 0.0
    for s in sf.scenario.lot.slots:
        spot = spots[s.id[1:]]
        rect = slot_shape(s)
        assert rect.intersection(spot).area / rect.area > 0.995
        assert spot.intersection(rect).area / spot.area > 0.97
        worst = max(worst, rect.hausdorff_distance(spot))
    assert worst < 0.1


def test_the_projection_is_the_tangent_plane_at_the_maps_origin(imported):
    """The header names the origin of the map's yaml; each slot's centre is its spot's
    (the mean of its four corners, projected here in closed form) to the centimetre."""
    _, _, text, sf = imported
    assert "lat 37.3808115, lon -121.9084060" in text
    assert "origin from the map's autonomoustuff_parking_lot.yaml" in text
    spots = mapped_spots(MAP, ORIGIN)
    for s in sf.scenario.lot.slots:
        ring = np.asarray(shapely.simplify(spots[s.id[1:]], 0.02).exterior.coords)[:-1]
        assert len(ring) == 4
        assert np.hypot(*(ring.mean(axis=0) - s.center)) < 0.011


def test_the_closed_form_and_the_frame_agree_to_a_micrometre():
    from lotsim.io.imports.frame import TangentPlane

    lat = ORIGIN[0] + np.array([-0.0008, 0.0, 0.0011])
    lon = ORIGIN[1] + np.array([0.0012, -0.0009, 0.0])
    x, y = TangentPlane(*ORIGIN).to_local(lat, lon)
    ex, ny = enu(lat, lon, *ORIGIN)
    assert np.allclose(x, ex, atol=1e-6) and np.allclose(y, ny, atol=1e-6)
    # and the first-order closed form (meridian and prime-vertical radii) to a centimetre
    la = math.radians(ORIGIN[0])
    m_r = A * (1 - E2) / (1 - E2 * math.sin(la) ** 2) ** 1.5
    n_r = A / math.sqrt(1 - E2 * math.sin(la) ** 2)
    assert np.allclose(y, np.radians(lat - ORIGIN[0]) * m_r, atol=0.01)
    assert np.allclose(x, np.radians(lon - ORIGIN[1]) * n_r * math.cos(la), atol=0.01)


@pytest.mark.slow
def test_an_import_is_byte_for_byte_the_same(imported, tmp_path):
    _, path, text, _ = imported
    import_lanelet2(MAP, tmp_path)
    assert (tmp_path / path.name).read_bytes() == path.read_bytes()


# the whole 203-bay map prepared for both types (some 20 s): -m slow, beside the map's other
# whole-lot checks (tests/e2e/test_import_lanelet2.py); the small map's bays are checked
# usable by default (test_every_bay_of_the_small_map_is_reachable_and_usable)
@pytest.mark.slow
def test_the_demo_map_has_the_usable_bays_docs_import_md_gives(imported):
    """docs/import.md: of the 203 slots, the zoe can use 195 and the altis 181 (8 spots too
    short for either, 10 more for the altis, 4 it can park in but not leave): what a
    change to the roadmap or the maneuvers must keep, or say why it does not."""
    import lotsim

    _, path, _, _ = imported
    report = lotsim.validate(path)
    usable = {name: len(ids) for name, ids in report.usable().items()}
    assert usable == {"altis": 181, "zoe": 195}


def test_gates_stand_on_the_open_road_ends_at_the_maps_edge(imported):
    """Four of the map's five road ends without a next lanelet lie at its edge; the fifth
    ends in a court of spots. Each of the four has an entrance and an exit, heading in and
    out, within 10 m of where its lanelet ends."""
    _, _, text, sf = imported
    lot = sf.scenario.lot
    assert len(lot.entrances) == len(lot.exits) == 4
    root = ET.parse(MAP).getroot()
    nodes = {n.get("id"): (float(n.get("lat")), float(n.get("lon"))) for n in root.iter("node")}
    ways = {w.get("id"): [n.get("ref") for n in w.findall("nd")] for w in root.iter("way")}
    lanelets = {r.get("id"): r for r in root.iter("relation")
                if tags(r).get("type") == "lanelet"}
    for gate in (*lot.entrances, *lot.exits):
        lanelet = lanelets[gate.id.split("-")[1]]
        bounds = [ways[m.get("ref")] for m in lanelet.findall("member")
                  if m.get("role") in ("left", "right")]
        ends = [nodes[b[k]] for b in bounds for k in (0, -1)]
        x, y = enu(*zip(*ends, strict=True), *ORIGIN)
        assert np.hypot(x - gate.pose[0], y - gate.pose[1]).min() < 10


# -- a small map of our own ----------------------------------------------------------------
def small_map(path: Path, origin=(48.0, 11.0), *, spots=None) -> Path:
    """A 40 m road of two lanelets side by side (east on the south half, west on the north
    half, sharing their middle bound), a 1 m access strip along its north edge with four
    2.5 × 5 m spots behind it (two as multipolygons, two as closed ways), and on its south
    edge a bay and a 7 × 2.5 m kerbside space; both ends open. ``spots`` (each a list of
    corners [m]), when given, are the map's only spots, as closed ways."""
    lat0, lon0 = origin
    la = math.radians(lat0)
    m_r = A * (1 - E2) / (1 - E2 * math.sin(la) ** 2) ** 1.5
    n_r = A / math.sqrt(1 - E2 * math.sin(la) ** 2)
    pts = {}

    def node(x, y):
        key = (x, y)
        if key not in pts:
            pts[key] = -(len(pts) + 1)
        return pts[key]

    ways, rels = [], []

    def way(xy, **tg):
        wid = -(1000 + len(ways))
        ways.append((wid, [node(*p) for p in xy], tg))
        return wid

    south = way([(0, 0), (40, 0)], type="line_thin", subtype="solid")
    middle = way([(0, 3), (40, 3)], type="line_thin", subtype="dashed")
    north = way([(0, 6), (40, 6)], type="line_thin", subtype="solid")
    rels.append((-1, [("way", middle, "left"), ("way", south, "right")],
                 {"type": "lanelet", "subtype": "lane", "speed_limit": "10km/h"}))
    rels.append((-2, [("way", middle, "left"), ("way", north, "right")],
                 {"type": "lanelet", "subtype": "lane", "speed_limit": "10km/h"}))
    way([(8, 6), (32, 6), (32, 7), (8, 7), (8, 6)], type="area", subtype="parking_access")
    for corners in spots or ():
        way([*corners, corners[0]], type="area", subtype="parking_spot")
    for k, x in enumerate(() if spots is not None else (10.0, 12.5, 15.0, 17.5)):
        corners = [(x, 7), (x + 2.5, 7), (x + 2.5, 12), (x, 12)]
        if k < 2:
            a = way(corners[:3], type="area", subtype="parking_spot")
            b = way([*corners[2:], corners[0]], type="area", subtype="parking_spot")
            rels.append((-10 - k, [("way", a, "outer"), ("way", b, "outer")],
                         {"type": "multipolygon", "subtype": "parking_spot"}))
        else:
            way([*corners, corners[0]], type="area", subtype="parking_spot")
    if spots is None:
        way([(22, 0), (22, -5), (24.5, -5), (24.5, 0), (22, 0)], type="area",
            subtype="parking_spot")
        way([(28, 0), (28, -2.5), (35, -2.5), (35, 0), (28, 0)], type="area",
            subtype="parking_spot")
    lines = ["<?xml version='1.0' encoding='UTF-8'?>", "<osm version='0.6'>"]
    for (x, y), nid in pts.items():
        lat = lat0 + math.degrees(y / m_r)
        lon = lon0 + math.degrees(x / (n_r * math.cos(la)))
        lines.append(f"  <node id='{nid}' lat='{lat:.11f}' lon='{lon:.11f}' />")
    for wid, refs, tg in ways:
        lines.append(f"  <way id='{wid}'>")
        lines += [f"    <nd ref='{r}' />" for r in refs]
        lines += [f"    <tag k='{k}' v='{v}' />" for k, v in tg.items()]
        lines.append("  </way>")
    for rid, members, tg in rels:
        lines.append(f"  <relation id='{rid}'>")
        lines += [f"    <member type='{t}' ref='{r}' role='{role}' />" for t, r, role in members]
        lines += [f"    <tag k='{k}' v='{v}' />" for k, v in tg.items()]
        lines.append("  </relation>")
    lines.append("</osm>")
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture(scope="session")  # once a process, however pytest-xdist splits the module
def small(tmp_path_factory):
    from lotsim.sim.preparation import prepare_graph

    tmp = tmp_path_factory.mktemp("small")
    src = small_map(tmp / "little.osm")
    report = import_lanelet2(src, tmp / "out")
    text = (tmp / "out" / "little.yaml").read_text()
    sc = load_scenario(tmp / "out" / "little.yaml")
    return report, text, sc, prepare_graph(sc)


def test_a_small_map_imports_and_builds(small):
    report, text, sc, _ = small
    assert "origin at the centroid of the map's nodes" in text
    lot = sc.lot
    kinds = {s.id: s.kind for s in lot.slots}
    assert kinds == {"P-10": "perpendicular", "P-11": "perpendicular",
                     "P-1008": "perpendicular", "P-1009": "perpendicular",
                     "P-1010": "perpendicular", "P-1011": "parallel"}
    # a car in the kerbside space faces the way the traffic beside it runs: east, on the
    # road's south side
    kerb = next(s for s in lot.slots if s.id == "P-1011")
    assert math.cos(kerb.heading) == pytest.approx(1.0, abs=1e-3)
    (aisle,) = lot.aisles
    assert not aisle.one_way  # two lanelets side by side, opposite: one two-way aisle
    assert aisle.width >= 6.0 - 1e-9  # their joint width, widened to the spots
    assert len(lot.entrances) == len(lot.exits) == 2
    assert report.lots[0].aisles == 1 and report.lots[0].gates == 2
    assert report.lots[0].mapped == 6


def test_every_bay_of_the_small_map_is_reachable_and_usable(small):
    *_, lg = small
    reach = lg.reachability()
    bays = {s.id for s in lg.lot.slots if s.kind == "perpendicular"}
    assert not bays & set(reach.no_way_in) and not bays & set(reach.no_way_out), reach
    for car, (no_in, no_out) in reach.by_type.items():
        assert not bays & set(no_in) and not bays & set(no_out), car
        assert not bays & set(lg.infeasible.get(car, {})), lg.infeasible


@pytest.mark.xfail(strict=True, reason="the space is written 1 cm inside its mapped outline, "
                   "and a car backing in swings its corner over the 1 cm of unpaved kerb "
                   "beyond the space's ends, between its open side and the aisle's ground")
def test_the_kerbside_space_of_the_small_map_is_usable(small):
    *_, lg = small
    assert not any("P-1011" in slots for slots in lg.infeasible.values()), lg.infeasible


def test_an_origin_given_is_used_and_said(tmp_path):
    src = small_map(tmp_path / "little.osm")
    import_lanelet2(src, tmp_path / "a", origin=(48.0, 11.0))
    text = (tmp_path / "a" / "little.yaml").read_text()
    assert "lat 48.0000000, lon 11.0000000 (origin given)" in text
    # the road's south edge is the line y = 0 of the frame at the given origin
    sf = read_scenario(tmp_path / "a" / "little.yaml")
    south = next(s for s in sf.scenario.lot.slots if s.id == "P-1010")
    assert south.center == pytest.approx((23.25, -2.5), abs=0.011)


# -- bad inputs ------------------------------------------------------------------------------
def test_a_missing_file_is_an_error_and_nothing_is_written(tmp_path):
    with pytest.raises(LotsimError, match="no such file"):
        import_lanelet2(tmp_path / "none.osm", tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_broken_xml_is_located(tmp_path):
    bad = tmp_path / "bad.osm"
    bad.write_text("<?xml version='1.0'?>\n<osm>\n  <node id='1' lat='1' lon='2'>\n</osm>\n")
    with pytest.raises(ScenarioError, match="not well-formed XML") as err:
        import_lanelet2(bad, tmp_path / "out")
    assert err.value.where is not None and err.value.where.line == 4
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("body, message", [
    ("<html><body/></html>", "expected an OSM XML file"),
    ("<osm version='0.6'/>", "expected OSM nodes"),
    ("<osm><node id='1' lat='91' lon='2'/></osm>", "expected lat within"),
    ("<osm><node id='1' lat='1' lon='2'/><way id='5'><nd ref='1'/><nd ref='9'/>"
     "<tag k='type' v='area'/><tag k='subtype' v='Walls'/></way></osm>",
     "refers to node 9"),
])
def test_files_that_are_not_lanelet2_maps_are_refused(tmp_path, body, message):
    bad = tmp_path / "bad.osm"
    bad.write_text(body)
    with pytest.raises(LotsimError, match=message):
        import_lanelet2(bad, tmp_path / "out")


def test_a_map_with_no_lanelets_is_refused(tmp_path):
    src = small_map(tmp_path / "little.osm")
    text = re.sub(r"  <relation id='-[12]'>.*?</relation>\n", "", src.read_text(), flags=re.S)
    src.write_text(text)
    with pytest.raises(LotsimError, match="expected lanelets"):
        import_lanelet2(src, tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_a_broken_map_config_is_an_error(tmp_path):
    src = small_map(tmp_path / "little.osm")
    (tmp_path / "little.yaml").write_text(textwrap.dedent("""\
        map_config:
          latitude: north
        """))
    with pytest.raises(LotsimError, match="expected map_config with latitude and longitude"):
        import_lanelet2(src, tmp_path / "out")


def test_a_map_whose_every_spot_is_dropped_is_written_without_slots_or_traffic(tmp_path):
    """One spot 3 m from the road, which no car reaches: the lot is written, with its
    aisle and gates, the spot's reason and no traffic (there is nowhere to park)."""
    src = small_map(tmp_path / "far.osm",
                    spots=[[(22, -3), (22, -8), (24.5, -8), (24.5, -3)]])
    report = import_lanelet2(src, tmp_path / "out")
    (lot,) = report.lots
    assert lot.mapped == 0 and lot.aisles == 1 and lot.gates == 2
    assert lot.reason.endswith("no slot: no traffic written")
    text = (tmp_path / "out" / "far.yaml").read_text()
    assert len(reported(text)) == 1 and "3.00 m away" in text
    sc = load_scenario(tmp_path / "out" / "far.yaml")
    assert not sc.lot.slots
    assert sc.traffic is None
