"""DXF export in feet: a scenario in feet (``units: ft``) is drawn in feet, read back with
ezdxf (not lotsim's reader): ``$INSUNITS`` 2 and ``$MEASUREMENT`` 0, ezdxf's audit passes,
every bay times 0.3048 is its slot in metres within 1 mm (shapely), and the texts, arrows,
hatch and dashes are as large on paper as in the metric drawing; ``--dxf-units`` draws a
lot in the other unit, the metric drawing of a feet scenario being the metric scenario's;
a lot drawn in feet and imported comes back as its boundary within 1 mm, in a plot file in
feet."""

from __future__ import annotations

import math

import pytest
import yaml
from shapely.affinity import scale
from shapely.geometry import Polygon

from conftest import ROOT
from export_runs import need
from feet_files import FOOT, to_feet
from lotsim.api import read_plot
from lotsim.api.exports import lot_of
from lotsim.cli import main
from lotsim.errors import SettingsError
from lotsim.io.cad_layers import BAY_LAYERS, LAYER_NAMES

TOLERANCE = 1e-3
"""Every figure read back lies within 1 mm [m] of lotsim's."""
STOREFRONT = ROOT / "scenarios" / "lots" / "storefront.yaml"


def feet_file(tmp_path, source=STOREFRONT):
    """``source`` written in feet (every length divided by 0.3048, ``units: ft``)."""
    path = tmp_path / f"{source.stem}-ft.yaml"
    path.write_text(yaml.safe_dump(to_feet(yaml.safe_load(source.read_text())),
                                   sort_keys=False))
    return path


def export(source, path, *more):
    """``lotsim export SOURCE --dxf PATH``, read back by ezdxf."""
    ezdxf = need("ezdxf")
    assert main(["export", str(source), "--dxf", str(path), *more]) == 0
    return ezdxf.readfile(path)


def in_metres(e) -> Polygon:
    """A closed LWPOLYLINE of a drawing in feet, in metres."""
    assert e.closed
    return scale(Polygon(e.get_points("xy")), FOOT, FOOT, origin=(0, 0))


def far(a: Polygon, b: Polygon) -> float:
    """How far apart two polygons are as shapes [m] (Hausdorff, and the symmetric
    difference's area over the perimeter)."""
    return max(a.hausdorff_distance(b), a.symmetric_difference(b).area / max(a.length, 1e-9))


@pytest.fixture(scope="module")
def drawings(tmp_path_factory):
    """The storefront drawn from its feet file, and from its metric file."""
    tmp = tmp_path_factory.mktemp("dxf-feet")
    feet = export(feet_file(tmp), tmp / "ft.dxf")
    metres = export(STOREFRONT, tmp / "m.dxf")
    return feet, metres, lot_of(STOREFRONT)


def test_a_feet_scenario_is_drawn_in_feet_and_passes_the_audit(drawings):
    feet, metres, _ = drawings
    auditor = feet.audit()
    assert not auditor.has_errors, [str(e) for e in auditor.errors]
    assert (feet.header["$INSUNITS"], feet.header["$MEASUREMENT"]) == (2, 0)
    assert (metres.header["$INSUNITS"], metres.header["$MEASUREMENT"]) == (6, 1)


def test_every_bay_in_feet_is_its_slot_in_metres_within_a_millimetre(drawings):
    feet, _, lot = drawings
    for use, layer in BAY_LAYERS.items():
        drawn = [in_metres(e) for e in feet.modelspace().query(f'LWPOLYLINE[layer=="{layer}"]')]
        mine = [s for s in lot.slots if s.use == use]
        assert len(drawn) == len(mine), use
        for slot in mine:
            assert min(far(p, slot.shape) for p in drawn) <= TOLERANCE, slot.id
    boundary = feet.modelspace().query(f'LWPOLYLINE[layer=="{LAYER_NAMES["boundary"]}"]')
    assert far(in_metres(boundary[0]), lot.boundary) <= TOLERANCE
    for route in ("route_envelope", "route_path"):  # the service routes, in feet too
        ft = feet.modelspace().query(f'LWPOLYLINE[layer=="{LAYER_NAMES[route]}"]')
        assert len(ft) >= 2


def test_texts_arrows_hatches_and_dashes_are_as_large_on_paper(drawings):
    feet, metres, _ = drawings

    def texts(doc):
        return sorted((t.dxf.layer, t.dxf.text, t.dxf.height) for t in doc.modelspace()
                      if t.dxftype() == "TEXT")

    ft, m = texts(feet), texts(metres)
    assert len(ft) == len(m) > 20
    for (la, a, ha), (lb, b, hb) in zip(ft, m, strict=True):
        assert (la, a) == (lb, b) and ha * FOOT == pytest.approx(hb, rel=1e-9), a

    def arrows(doc):
        return sorted(Polygon(e.get_points("xy")).area for e in doc.modelspace().query(
            f'LWPOLYLINE[layer=="{LAYER_NAMES["arrow"]}"]'))

    assert len(arrows(feet)) == len(arrows(metres)) > 0
    for a, b in zip(arrows(feet), arrows(metres), strict=True):
        assert a * FOOT ** 2 == pytest.approx(b, rel=1e-9)

    def hatch_spacing(doc) -> float:  # between the access aisle's lines [drawing units]
        (line,) = next(iter(doc.modelspace().query("HATCH[solid_fill==0]"))).pattern.lines
        return math.hypot(*line.offset)

    assert hatch_spacing(metres) == pytest.approx(0.4)
    assert hatch_spacing(feet) * FOOT == pytest.approx(0.4)
    assert feet.header["$LTSCALE"] * FOOT == pytest.approx(metres.header["$LTSCALE"])
    (fv,), (mv,) = feet.viewports.get("*Active"), metres.viewports.get("*Active")
    assert fv.dxf.height * FOOT == pytest.approx(mv.dxf.height)


@pytest.mark.slow
def test_the_option_draws_a_lot_in_the_other_unit(tmp_path, capsys):
    need("ezdxf")
    feet = feet_file(tmp_path)
    metric_of_feet = export(feet, tmp_path / "a.dxf", "--dxf-units", "m")
    export(STOREFRONT, tmp_path / "b.dxf")
    assert metric_of_feet.header["$INSUNITS"] == 6

    def entities(path) -> str:
        text = path.read_text(encoding="utf-8")
        return text[text.index("ENTITIES"):text.index("ENDSEC", text.index("ENTITIES"))]

    # lengths in feet are read to the nanometre: the same lot, so the same drawing
    assert entities(tmp_path / "a.dxf") == entities(tmp_path / "b.dxf")
    assert "in metres" in capsys.readouterr().out
    assert export(STOREFRONT, tmp_path / "c.dxf", "--dxf-units", "ft").header[
        "$INSUNITS"] == 2
    assert "in feet" in capsys.readouterr().out
    assert main(["export", str(STOREFRONT), "--dxf-units", "ft"]) == 2
    assert "--dxf-units is for the drawing of --dxf" in capsys.readouterr().err
    import lotsim

    with pytest.raises(SettingsError, match="units: expected one of m, ft, found 'yd'"):
        lotsim.export_dxf(STOREFRONT, tmp_path / "d.dxf", units="yd")
    assert not (tmp_path / "d.dxf").exists()


def test_a_metric_lot_drawn_in_feet_comes_back_as_its_plot(tmp_path, capsys):
    need("ezdxf")
    scenario = ROOT / "scenarios" / "mixed_lot.yaml"
    export(scenario, tmp_path / "lot.dxf", "--dxf-units", "ft")
    assert main(["import", "dxf", str(tmp_path / "lot.dxf"), "-o", str(tmp_path)]) == 0
    assert "drawn in ft ($INSUNITS 2)" in capsys.readouterr().out
    text = (tmp_path / "lot.plot.yaml").read_text()
    assert "\nunits: ft\n" in text and "262.467" in text  # 80 m, in feet
    plot = read_plot(tmp_path / "lot.plot.yaml")
    lot = lot_of(scenario)
    assert Polygon(plot.boundary).hausdorff_distance(lot.boundary) < TOLERANCE
    (island,) = plot.islands
    (area,) = [a for a in lot.areas if a.kind == "no_go"]
    assert far(Polygon(island.polygon), area.polygon) < TOLERANCE
    ((name, at),) = [(g.id, g.at) for g in plot.gates]
    assert name == "gate-in" and math.dist(at, (0.0, 30.0)) < TOLERANCE
