"""DXF export of a lot with service routes: read back with ezdxf, each route's envelope is
on its layer as planned (within 1 mm: area, symmetric difference and Hausdorff distance),
with the route's id inside it, and its path on its own layer, reverse strokes dashed; the
drawing passes the audit; an envelope moved by 2 mm is caught; a scenario without routes
has none."""

from __future__ import annotations

from functools import reduce

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon

from conftest import ROOT
from export_runs import need
from lotsim.api.exports import lot_of
from lotsim.cli import main
from lotsim.io.cad_layers import LAYER_NAMES
from lotsim.io.export.dxf import APPID
from lotsim.io.scenario_yaml import load_scenario
from lotsim.roadmap.service_routes import plan_routes

TOLERANCE = 1e-3
"""[m]: the envelope read back is the planned one within a millimetre."""
STOREFRONT = ROOT / "scenarios" / "lots" / "storefront.yaml"
ENVELOPE, PATH = LAYER_NAMES["route_envelope"], LAYER_NAMES["route_path"]


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    ezdxf = need("ezdxf")
    path = tmp_path_factory.mktemp("dxf-routes") / "storefront.dxf"
    assert main(["export", str(STOREFRONT), "--dxf", str(path)]) == 0
    sc = load_scenario(STOREFRONT)
    return ezdxf.readfile(path), plan_routes(lot_of(sc), sc.routes)


def envelopes(doc) -> dict[str, Polygon]:
    """Route id (the extended data of its rings) → the envelope drawn on its layer: its
    rings even-odd (a ring inside another is a hole), checked against its TEXT inside."""
    msp = doc.modelspace()
    rings: dict[str, list[Polygon]] = {}
    for e in msp.query(f'LWPOLYLINE[layer=="{ENVELOPE}"]'):
        assert e.closed
        (code, of), = e.get_xdata(APPID)
        rings.setdefault(of, []).append(Polygon(e.get_points("xy")))
    out = {of: reduce(lambda a, b: a.symmetric_difference(b), rs) for of, rs in rings.items()}
    names = {t.dxf.text: Point(t.dxf.align_point.x, t.dxf.align_point.y)
             for t in msp.query(f'TEXT[layer=="{ENVELOPE}"]')}
    assert sorted(names) == sorted(out)
    assert all(out[n].contains(p) for n, p in names.items())
    return out


def far(a, b) -> float:
    """The largest of the difference of areas [m²], the symmetric difference's area over
    the perimeter [m] and the Hausdorff distance [m]."""
    return max(abs(a.area - b.area), a.symmetric_difference(b).area / max(a.length, 1e-9),
               a.hausdorff_distance(b))


def test_the_drawing_passes_the_audit_and_has_the_route_layers(exported):
    doc, _ = exported
    auditor = doc.audit()
    assert not auditor.has_errors, [str(e) for e in auditor.errors]
    assert {ENVELOPE, PATH} <= {layer.dxf.name for layer in doc.layers}
    assert (ENVELOPE, PATH) == ("C-PRKG-ENVL", "C-PRKG-ROUT")


def test_each_envelope_is_the_planned_one_within_a_millimetre(exported):
    doc, reports = exported
    drawn = envelopes(doc)
    assert sorted(drawn) == sorted(r.id for r in reports)
    for r in reports:
        assert far(drawn[r.id], r.envelope) < TOLERANCE, r.id
        assert abs(drawn[r.id].area - r.area) < TOLERANCE


def test_an_envelope_moved_by_two_millimetres_is_caught(exported):
    doc, reports = exported
    e = next(iter(doc.modelspace().query(f'LWPOLYLINE[layer=="{ENVELOPE}"]')))
    points = list(e.get_points("xy"))
    e.set_points([(x + 0.002, y) for x, y in points], format="xy")
    try:
        drawn = envelopes(doc)
        assert any(far(drawn[r.id], r.envelope) > TOLERANCE for r in reports)
    finally:
        e.set_points(points, format="xy")


def test_each_path_is_drawn_stroke_by_stroke_reverse_dashed(exported):
    doc, reports = exported
    lines = list(doc.modelspace().query(f'LWPOLYLINE[layer=="{PATH}"]'))
    strokes = sum(r.changes + 1 for r in reports)
    assert len(lines) == strokes
    dashed = [e for e in lines if e.dxf.get("linetype") == "DASHED"]
    assert 0 < len(dashed) < len(lines)
    ends = {tuple(np.round(p, 3)) for e in lines for p in (e.get_points("xy")[0],
                                                           e.get_points("xy")[-1])}
    for r in reports:  # each path starts and ends where the route's poses do
        assert tuple(np.round(r.poses[0, :2], 3)) in ends
        assert tuple(np.round(r.poses[-1, :2], 3)) in ends
    by_id = {r.id: r for r in reports}
    for e in lines:  # each stroke names its route and lies in the route's own envelope
        (_, of), = e.get_xdata(APPID)
        assert by_id[of].envelope.buffer(TOLERANCE).contains(
            shapely.LineString(e.get_points("xy")))


def test_a_scenario_without_routes_draws_none(tmp_path):
    ezdxf = need("ezdxf")
    path = tmp_path / "example.dxf"
    assert main(["export", str(ROOT / "scenarios" / "example.yaml"), "--dxf", str(path)]) == 0
    doc = ezdxf.readfile(path)
    assert len(doc.modelspace().query(f'*[layer=="{ENVELOPE}" | layer=="{PATH}"]')) == 0
