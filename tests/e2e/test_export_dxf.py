"""DXF export: the drawing, read back with ezdxf (not lotsim's reader), passes ezdxf's audit,
is in metres, and holds the lot as shapely sees it: every bay a closed 4-corner polyline on
its use's layer within 1 mm of the slot (symmetric difference and Hausdorff distance), one
number per bay inside it, the boundary and the areas ring for ring, stripes on the bays'
sides but their entries, arrows on the lanes pointing their way; a planted 2 mm fault is
caught; a failed export leaves nothing."""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon

from conftest import ROOT
from export_runs import need, result_path
from lotsim.api import load_result
from lotsim.api.exports import lot_of
from lotsim.cli import main
from lotsim.io.cad_layers import LAYER_NAMES, bay_layer

TOLERANCE = 1e-3
"""Every figure read back lies within 1 mm [m] of lotsim's."""
SCENARIOS = {name: ROOT / "scenarios" / f"{name}.yaml" for name in ("mixed_lot", "example")}
GATES = {"mixed_lot": (0, 30), "example": (0, 10)}
"""Where each scenario's one gate aisle meets its boundary: half-way between the lanes of
its entrance and exit, which cross it 3.5 m apart."""


def export(source, tmp_path, name="lot.dxf"):
    """The DXF of ``source`` written by ``lotsim export --dxf``, read back by ezdxf."""
    ezdxf = need("ezdxf")
    path = tmp_path / name
    assert main(["export", str(source), "--dxf", str(path)]) == 0
    return ezdxf.readfile(path)


def xy(v) -> tuple[float, float]:
    """An ezdxf vertex's x, y."""
    return (v.x, v.y)


def polylines(doc, layer: str) -> list:
    return [e for e in doc.modelspace().query(f'LWPOLYLINE[layer=="{layer}"]')]


def polygon(e) -> Polygon:
    assert e.closed, f"LWPOLYLINE #{e.dxf.handle} on {e.dxf.layer} is open"
    return Polygon([(x, y) for x, y in e.get_points("xy")])


def far(a: Polygon, b: Polygon) -> float:
    """How far apart two polygons are as shapes: the larger of their Hausdorff distance
    and their symmetric difference's area over their perimeter [m]."""
    return max(a.hausdorff_distance(b), a.symmetric_difference(b).area / max(a.length, 1e-9))


def bay_problems(doc, lot) -> list[str]:
    """Where the bays of ``doc`` differ from ``lot``'s slots by more than 1 mm, or their
    numbers stand elsewhere."""
    drawn = [polygon(e) for e in polylines(doc, bay_layer("standard"))]
    problems = []
    if len(drawn) != len(lot.slots):
        problems.append(f"{len(drawn)} bays drawn, {len(lot.slots)} in the lot")
    centres = np.array([[p.centroid.x, p.centroid.y] for p in drawn]).reshape(-1, 2)
    for slot in lot.slots:
        if not len(centres):
            break
        k = int(np.argmin(np.hypot(*(centres - slot.center).T)))
        d = far(drawn[k], slot.shape)
        if d > TOLERANCE or len(drawn[k].exterior.coords) != 5:
            problems.append(f"bay {slot.id}: {d * 1000:.2f} mm off")
    numbers = {t.dxf.text: t for t in doc.modelspace().query(
        f'TEXT[layer=="{LAYER_NAMES["bay_number"]}"]')}
    for slot in lot.slots:
        t = numbers.get(slot.id)
        if t is None or not slot.shape.contains(Point(xy(t.dxf.align_point))):
            problems.append(f"bay {slot.id}: its number is missing or outside it")
    return problems


@pytest.fixture(scope="module", params=sorted(SCENARIOS))
def exported(request, tmp_path_factory):
    source = SCENARIOS[request.param]
    doc = export(source, tmp_path_factory.mktemp(f"dxf-{request.param}"))
    return doc, lot_of(source), request.param


def test_the_drawing_passes_the_audit_in_metres(exported):
    doc, _, _ = exported
    auditor = doc.audit()
    assert not auditor.has_errors, [str(e) for e in auditor.errors]
    assert doc.header["$INSUNITS"] == 6 and doc.header["$MEASUREMENT"] == 1
    assert {layer.dxf.name for layer in doc.layers} >= set(LAYER_NAMES.values())


def test_every_bay_is_its_slot_within_a_millimetre_and_numbered_inside_it(exported):
    doc, lot, _ = exported
    assert bay_problems(doc, lot) == []
    taken = polylines(doc, LAYER_NAMES["taken"])
    assert len(taken) == len(lot.occupied) > 0
    for e in taken:
        assert any(lot.slot_by_id[s].shape.contains(polygon(e)) for s in lot.occupied)


def test_a_bay_moved_by_two_millimetres_is_caught(exported, tmp_path):
    doc, lot, _ = exported
    e = polylines(doc, bay_layer("standard"))[3]
    e.set_points([(x + 0.002, y) for x, y in e.get_points("xy")], format="xy")
    assert len(bay_problems(doc, lot)) == 1
    e.set_points([(x - 0.002, y) for x, y in e.get_points("xy")], format="xy")
    assert bay_problems(doc, lot) == []


def test_boundary_and_areas_are_lotsim_s_ring_for_ring(exported):
    doc, lot, _ = exported
    (boundary,) = polylines(doc, LAYER_NAMES["boundary"])
    assert far(polygon(boundary), lot.boundary) < TOLERANCE
    for kind, layer in (("no_go", "island"), ("obstacle", "obstacle"), ("wall", "wall")):
        drawn = [polygon(e) for e in polylines(doc, LAYER_NAMES[layer])]
        areas = [a.polygon for a in lot.areas if a.kind == kind]
        assert len(drawn) == len(areas)
        for a in areas:
            assert min(far(a, d) for d in drawn) < TOLERANCE
    aisles = [np.asarray(a.centerline) for a in lot.aisles.values()]
    lines = [np.array(e.get_points("xy")) for e in polylines(doc, LAYER_NAMES["centreline"])]
    assert len(lines) == len(aisles)
    assert all(any(c.shape == d.shape and np.allclose(c, d, atol=TOLERANCE) for d in lines)
               for c in aisles)


def test_stripes_are_the_sides_of_the_bays_but_their_entries(exported):
    doc, lot, _ = exported
    stripes = [LineString([xy(e.dxf.start), xy(e.dxf.end)]) for e in
               doc.modelspace().query(f'LINE[layer=="{LAYER_NAMES["stripe"]}"]')]
    sides = []
    for slot in lot.slots:
        ring = np.asarray(slot.polygon)
        entry = LineString(slot.entry)
        for k in range(4):
            side = LineString([ring[k], ring[(k + 1) % 4]])
            if side.hausdorff_distance(entry) > TOLERANCE:
                sides.append(side)
            else:  # no stripe across the entry
                assert all(s.hausdorff_distance(side) > TOLERANCE for s in stripes)
    assert len(stripes) <= len(sides)
    for side in sides:
        assert min(s.hausdorff_distance(side) for s in stripes) < TOLERANCE


def test_arrows_stand_on_lanes_and_point_their_way(exported):
    doc, lot, _ = exported
    arrows = polylines(doc, LAYER_NAMES["arrow"])
    assert len(arrows) >= len(lot.lanes)
    for e in arrows:
        pts = np.array(e.get_points("xy"))
        tail = (pts[3] + pts[4]) / 2  # the shaft's back end, and the tip
        centre = (tail + pts[0]) / 2
        way = math.atan2(*(pts[0] - tail)[::-1])
        lane = min(lot.lanes, key=lambda ln: ln.line.distance(Point(centre)))
        assert lane.line.distance(Point(centre)) < 0.01
        _, _, heading = lane.pose_at(lane.line.project(Point(centre)))
        assert abs(math.remainder(way - heading, math.tau)) < math.radians(1)
    hatches = doc.modelspace().query(f'HATCH[layer=="{LAYER_NAMES["arrow"]}"]')
    assert len(hatches) == len(arrows)


def test_gates_stand_on_the_boundary_where_the_entrance_lanes_leave_it(exported):
    doc, lot, name = exported
    gates = doc.modelspace().query(f'POINT[layer=="{LAYER_NAMES["gate"]}"]')
    assert len(gates) == 1
    at = Point(xy(gates[0].dxf.location))
    assert lot.boundary.exterior.distance(at) < 1e-6
    assert at.distance(Point(GATES[name])) < 1e-6
    for layer, portals in (("entrance", lot.entrances), ("exit", lot.exits)):
        assert len(polylines(doc, LAYER_NAMES[layer])) == len(portals)


def test_a_result_s_lot_is_drawn_as_its_scenario_s(tmp_path):
    path = result_path("mixed_lot")
    doc = export(path, tmp_path)
    lot = lot_of(load_result(path))
    assert bay_problems(doc, lot) == []
    assert bay_problems(doc, lot_of(SCENARIOS["mixed_lot"])) == []


def test_a_failed_export_leaves_the_file_as_it_was(tmp_path, monkeypatch, capsys):
    need("ezdxf")
    import lotsim
    import lotsim.io.export.dxf as dxf

    target = tmp_path / "lot.dxf"
    target.write_text("an earlier drawing")
    real = dxf.dxf_document

    def unwritable(drawing, **units):  # fails while the file is being written
        doc = real(drawing, **units)
        doc.encode = lambda text: None
        return doc

    def unfinished(drawing, **units):  # fails half-way through the drawing
        doc = real(drawing, **units)
        doc.write = lambda stream: (stream.write("0\nSECTION\n"), 1 / 0)
        return doc

    monkeypatch.setattr(dxf, "dxf_document", unwritable)
    with pytest.raises(TypeError):
        lotsim.export_dxf(SCENARIOS["example"], target)
    monkeypatch.setattr(dxf, "dxf_document", unfinished)
    with pytest.raises(ZeroDivisionError):
        main(["export", str(SCENARIOS["example"]), "--dxf", str(target)])
    assert target.read_text() == "an earlier drawing"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lot.dxf"]
    monkeypatch.setattr(dxf, "dxf_document", real)
    missing = tmp_path / "new" / "lot.dxf"
    bad = tmp_path / "bad.yaml"
    shutil.copy(SCENARIOS["example"], bad)
    bad.write_text(bad.read_text().replace("width: 7.0", "width: wide"))
    assert main(["export", str(bad), "--dxf", str(missing)]) == 2
    assert "bad.yaml:" in capsys.readouterr().err
    assert not missing.parent.exists()


def test_two_exports_of_a_lot_hold_the_same_entities(tmp_path):
    need("ezdxf")
    import lotsim

    def entities(path) -> str:
        text = path.read_text(encoding="utf-8")
        return text[text.index("ENTITIES"):text.index("ENDSEC", text.index("ENTITIES"))]

    a = lotsim.export_dxf(SCENARIOS["mixed_lot"], tmp_path / "a.dxf").path
    b = lotsim.export_dxf(SCENARIOS["mixed_lot"], tmp_path / "b.dxf").path
    assert entities(a) == entities(b) and len(entities(a)) > 10_000


USE_LAYERS = {"standard": "C-PRKG", "compact": "C-PRKG-CMPT", "accessible": "C-PRKG-ACCS",
              "van_accessible": "C-PRKG-ACCV", "ev": "C-PRKG-EVCH", "motorcycle": "C-PRKG-MCYC"}
"""docs/export.md's layer of each use of bay, as the page gives them."""


@pytest.mark.slow
def test_a_lot_of_several_uses_has_each_bay_on_its_use_s_layer(tmp_path):
    source = ROOT / "scenarios" / "lots" / "storefront.yaml"
    doc = export(source, tmp_path)
    assert not doc.audit().has_errors
    lot = lot_of(source)
    uses = {s.use for s in lot.slots}
    assert len(uses) >= 4
    for use, layer in USE_LAYERS.items():
        drawn = [polygon(e) for e in polylines(doc, layer)]
        mine = [s for s in lot.slots if s.use == use]
        assert len(drawn) == len(mine), use
        for slot in mine:
            assert min(far(p, slot.shape) for p in drawn) <= TOLERANCE, slot.id
    aisles = [polygon(e) for e in polylines(doc, "C-PRKG-ACCA")]
    assert len(aisles) == len(lot.access_aisles) == 2
    for a in lot.access_aisles:
        assert min(far(p, a.shape) for p in aisles) <= TOLERANCE, a.id
    hatches = list(doc.modelspace().query('HATCH[layer=="C-PRKG-ACCA"]'))
    assert len(hatches) == 2 and all(h.dxf.solid_fill == 0 for h in hatches)
