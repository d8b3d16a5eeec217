"""``lotsim import osm --layout``: a lot that maps no aisles is laid out by ``lotsim layout``
on its plot — its outline, its islands kept clear, a gate where a road meets its edge — and
written as a scenario that validates strictly; its plot file is written beside it."""

from __future__ import annotations

import math

import pytest
from shapely.geometry import Point, Polygon

import lotsim
from lotsim.io.imports.osm import NO_AISLE

LAT, LON = 60.0, 25.0
R = 6_371_000.0


def _node(nid: int, x: float, y: float) -> str:
    lat = LAT + math.degrees(y / R)
    lon = LON + math.degrees(x / (R * math.cos(math.radians(LAT))))
    return f'<node id="{nid}" lat="{lat:.8f}" lon="{lon:.8f}"/>'


def _bare_lot(tmp_path):
    """A 44 x 36 m lot with no aisle, a 4 x 4 m kiosk in it, and a residential road that
    ends 3 m south of the middle of its south edge."""
    corners = [(-22, -18), (22, -18), (22, 18), (-22, 18)]
    kiosk = [(10, 8), (14, 8), (14, 12), (10, 12)]
    nodes = [_node(1 + i, x, y) for i, (x, y) in enumerate(corners)]
    nodes += [_node(11 + i, x, y) for i, (x, y) in enumerate(kiosk)]
    nodes += [_node(21, 0, -60), _node(22, 0, -21)]
    ways = ['<way id="100"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><nd ref="1"/>'
            '<tag k="amenity" v="parking"/></way>',
            '<way id="110"><nd ref="11"/><nd ref="12"/><nd ref="13"/><nd ref="14"/>'
            '<nd ref="11"/><tag k="building" v="kiosk"/></way>',
            '<way id="120"><nd ref="21"/><nd ref="22"/><tag k="highway" v="residential"/>'
            '</way>']
    path = tmp_path / "bare.osm"
    path.write_text('<osm version="0.6">' + "".join(nodes + ways) + "</osm>")
    return path


def test_without_layout_a_bare_lot_is_skipped_as_before(tmp_path):
    report = lotsim.import_osm(_bare_lot(tmp_path), tmp_path / "out")
    (lot,) = report.lots
    assert not lot.written and lot.reason == NO_AISLE
    assert list((tmp_path / "out").iterdir()) == []


@pytest.mark.slow
def test_with_layout_a_bare_lot_is_laid_out_round_its_kiosk_from_its_road(tmp_path):
    out = tmp_path / "out"
    settings = lotsim.LayoutSettings(orientations=1, offsets=1, prepared=1, compared=1)
    report = lotsim.import_osm(_bare_lot(tmp_path), out, layout=True, settings=settings)
    (lot,) = report.lots
    assert lot.written and lot.inferred > 0, lot.reason
    assert "laid out by lotsim layout" in lot.reason
    assert sorted(p.name for p in out.iterdir()) == ["way-100.plot.yaml", "way-100.yaml"]
    plot = lotsim.read_plot(out / "way-100.plot.yaml")
    # the gate where the road ends, on the south edge; the kiosk kept clear, inside
    ((gx, gy),) = [g.at for g in plot.gates]
    assert plot.gates[0].id == "south"
    assert gx == pytest.approx(0.0, abs=0.1) and gy == pytest.approx(-18.0, abs=0.1)
    (kiosk,) = plot.islands
    assert Polygon(kiosk.polygon).area == pytest.approx((4 - 0.2) ** 2, rel=0.02)
    report = lotsim.validate(out / "way-100.yaml")
    assert report.complete and len(report.prepared.lot.slots) == lot.inferred
    shape = Polygon(kiosk.polygon)
    assert all(Polygon(s.polygon).intersection(shape).area == 0
               for s in report.prepared.lot.slots)
    text = (out / "way-100.yaml").read_text()
    assert text.startswith("# OpenStreetMap way 100") and "ODbL" in text
    assert Point(gx, gy).distance(Polygon(plot.boundary).exterior) < 1e-6
