"""DXF import: a plot drawn by ezdxf here (not by lotsim's writer), in feet and in
millimetres, is read into a plot file whose boundary, islands, gates and building entrances
are the drawing's within a millimetre, and lotsim layout lays it out; the plot file is in
feet for a drawing in feet or inches, else in metres; a shipped scenario's lot exported to
DXF comes back as its boundary, island and gate; every bad drawing is one clear error naming
its layer and entity, with nothing written."""

from __future__ import annotations

import sys

import pytest
from shapely.geometry import Point, Polygon

from conftest import ROOT
from export_runs import need
from lotsim.api import DxfLayers, LayoutSettings, read_plot
from lotsim.api.exports import lot_of
from lotsim.cli import main
from lotsim.cli.imports import UNITS as COMMAND_UNITS
from lotsim.design.plot_yaml import GATE_TOLERANCE as PLOT_GATE_TOLERANCE
from lotsim.design.search import candidates
from lotsim.io.imports.dxf import GATE_TOLERANCE, UNITS

FT, MM = 0.3048, 0.001
TOLERANCE = 1e-3
"""Every point read lies within 1 mm [m] of the drawing's (written to the millimetre)."""
BOUNDARY = [(0, 0), (132, 0), (132, 100), (20, 100), (0, 80)]
"""A 132 x 100 ft plot with its north-west corner cut off [ft]."""
ISLAND = [(90, 60), (110, 60), (110, 80), (90, 80)]
"""A 20 x 20 ft planter [ft]."""
FEET = {"south": (66, 0), "east": (132, 50), "lobby": (60, 100)}
"""A gate labelled on the south side, one unlabelled on the east side (a block), and a
building entrance on the north side [ft]."""
DEFAULT = DxfLayers()


def plot_drawing(path, *, insunits: int | None, unit: float, layers: DxfLayers = DEFAULT):
    """The plot above, drawn with ezdxf in a unit of ``unit`` metres, ``$INSUNITS``
    ``insunits`` (None: left out); returns the document (already saved at ``path``)."""
    ezdxf = need("ezdxf")
    doc = ezdxf.new("R2010")
    if insunits is None:
        del doc.header["$INSUNITS"]
    else:
        doc.header["$INSUNITS"] = insunits
    k = FT / unit  # drawing units per foot
    msp = doc.modelspace()

    def at(p):
        return (p[0] * k, p[1] * k)

    msp.add_lwpolyline([at(p) for p in BOUNDARY], close=True,
                       dxfattribs={"layer": layers.boundary})
    msp.add_lwpolyline([at(p) for p in ISLAND], close=True,
                       dxfattribs={"layer": layers.islands[0]})
    msp.add_text("planter", height=2 * k, dxfattribs={"layer": layers.islands[0],
                                                      "insert": at((95, 70))})
    msp.add_point(at(FEET["south"]), dxfattribs={"layer": layers.gates[0]})
    msp.add_text("south", height=2 * k, dxfattribs={"layer": layers.gates[0],
                                                    "insert": at((64, -6))})
    block = doc.blocks.new("GATE")
    block.add_circle((0, 0), 1 * k)
    msp.add_blockref("GATE", at(FEET["east"]), dxfattribs={"layer": layers.gates[0]})
    msp.add_point(at(FEET["lobby"]), dxfattribs={"layer": layers.entrances[0]})
    msp.add_mtext("lobby", dxfattribs={"layer": layers.entrances[0],
                                       "insert": at((58, 104)), "char_height": 2 * k})
    msp.add_line((0, 0), at((10, 10)), dxfattribs={"layer": "NOTES"})
    doc.saveas(path)
    return doc


def metres(points_ft):
    return [(x * FT, y * FT) for x, y in points_ft]


def run(args, capsys) -> tuple[int, str, str]:
    code = main(["import", "dxf", *map(str, args)])
    out, err = capsys.readouterr()
    return code, out, err


def check_plot(path):
    """The plot file ``path`` holds the plot above, within a millimetre."""
    plot = read_plot(path)
    assert Polygon(plot.boundary).hausdorff_distance(Polygon(metres(BOUNDARY))) < TOLERANCE
    (island,) = plot.islands
    assert island.id == "planter"
    assert Polygon(island.polygon).hausdorff_distance(Polygon(metres(ISLAND))) < TOLERANCE
    assert {g.id for g in plot.gates} == {"south", "east"}
    for g in plot.gates:
        assert Point(g.at).distance(Point(metres([FEET[g.id]])[0])) < TOLERANCE
    (lobby,) = plot.building_entrances
    assert lobby.id == "lobby"
    assert Point(lobby.at).distance(Point(metres([FEET["lobby"]])[0])) < TOLERANCE
    return plot


@pytest.mark.parametrize(("insunits", "unit"), [(2, FT), (4, MM)], ids=["ft", "mm"])
def test_a_plot_in_feet_or_millimetres_is_read_in_metres(tmp_path, capsys, insunits, unit):
    plot_drawing(tmp_path / "site.dxf", insunits=insunits, unit=unit)
    code, out, err = run([tmp_path / "site.dxf", "-o", tmp_path / "site.yaml"], capsys)
    assert (code, err) == (0, "")
    assert f"1 island, 2 gates, 1 building entrance; drawn in " \
           f"{'ft' if unit == FT else 'mm'} ($INSUNITS {insunits})" in out
    plot = check_plot(tmp_path / "site.yaml")
    drawn = candidates(plot, LayoutSettings(orientations=1, offsets=1))
    assert drawn and max(c.bays for c in drawn) > 10  # a layout has room for bays


@pytest.mark.parametrize(("insunits", "unit", "written"),
                         [(1, 0.0254, "ft"), (2, FT, "ft"), (4, MM, "m"), (5, 0.01, "m"),
                          (6, 1.0, "m")], ids=["in", "ft", "mm", "cm", "m"])
def test_the_plot_file_is_in_feet_for_a_drawing_in_feet_or_inches(tmp_path, capsys, insunits,
                                                                  unit, written):
    plot_drawing(tmp_path / "site.dxf", insunits=insunits, unit=unit)
    assert run([tmp_path / "site.dxf", "-o", tmp_path / "site.yaml"], capsys)[0] == 0
    text = (tmp_path / "site.yaml").read_text()
    assert f"\nunits: {written}\n" in text
    assert ("[132, 100]" if written == "ft" else "[40.234, 30.48]") in text  # a corner
    check_plot(tmp_path / "site.yaml")


def test_the_tolerance_of_a_gate_and_the_units_are_the_plot_file_s_and_the_command_s():
    assert GATE_TOLERANCE == PLOT_GATE_TOLERANCE
    assert tuple(UNITS) == COMMAND_UNITS


def test_layers_named_by_the_user_and_circles_and_arcs_are_read(tmp_path, capsys):
    ezdxf = need("ezdxf")
    layers = DxfLayers(boundary="Lot line", islands=("TREES", "KIOSK"), gates=("DRIVE",),
                       entrances=("DOORS",))
    plot_drawing(tmp_path / "site.dxf", insunits=2, unit=FT, layers=layers)
    doc = ezdxf.readfile(tmp_path / "site.dxf")
    doc.modelspace().add_circle((40, 40), 5, dxfattribs={"layer": "KIOSK"})  # [ft]
    doc.saveas(tmp_path / "site.dxf")
    code, _, err = run([tmp_path / "site.dxf", "-o", tmp_path / "site.yaml",
                        "--boundary-layer", "lot line", "--island-layer", "TREES",
                        "--island-layer", "KIOSK", "--gate-layer", "DRIVE",
                        "--entrance-layer", "DOORS"], capsys)
    assert (code, err) == (0, "")
    plot = read_plot(tmp_path / "site.yaml")
    kiosk = Polygon(next(i.polygon for i in plot.islands if i.id != "planter"))
    circle = Point(40 * FT, 40 * FT).buffer(5 * FT, quad_segs=256)
    assert kiosk.hausdorff_distance(circle) < 0.01 + TOLERANCE  # arcs followed within 1 cm
    assert len(plot.islands) == 2


def test_units_come_from_the_option_when_the_drawing_has_none(tmp_path, capsys):
    plot_drawing(tmp_path / "site.dxf", insunits=0, unit=FT)
    out = tmp_path / "site.yaml"
    code, _, err = run([tmp_path / "site.dxf", "-o", out], capsys)
    assert code == 2 and not out.exists()
    assert "$INSUNITS is 0 (unitless)" in err and "--units mm|cm|m|in|ft" in err
    assert run([tmp_path / "site.dxf", "-o", out, "--units", "ft"], capsys)[0] == 0
    check_plot(out)
    plot_drawing(tmp_path / "yards.dxf", insunits=10, unit=FT)
    code, _, err = run([tmp_path / "yards.dxf", "-o", tmp_path / "yards.yaml"], capsys)
    assert code == 2 and "$INSUNITS is 10 (yards): lotsim reads drawings in mm, cm, m, in, " \
                         "ft" in err
    plot_drawing(tmp_path / "old.dxf", insunits=None, unit=FT)
    assert "unitless" in run([tmp_path / "old.dxf", "-o", out], capsys)[2]


def bad_drawing(tmp_path, change) -> tuple:
    """The plot above in metres with ``change(doc, msp)`` made: what importing it says."""
    plot_drawing(tmp_path / "bad.dxf", insunits=6, unit=FT)
    ezdxf = need("ezdxf")
    doc = ezdxf.readfile(tmp_path / "bad.dxf")
    handles = change(doc, doc.modelspace())
    doc.saveas(tmp_path / "bad.dxf")
    return handles, tmp_path / "out" / "bad.yaml"


def boundary(msp):
    return msp.query(f'LWPOLYLINE[layer=="{DEFAULT.boundary}"]')[0]


def open_boundary(doc, msp):
    e = boundary(msp)
    pts = e.get_points("xy")
    msp.delete_entity(e)
    return [msp.add_line(a, b, dxfattribs={"layer": DEFAULT.boundary}).dxf.handle
            for a, b in zip(pts, pts[1:], strict=False)]


def two_boundaries(doc, msp):
    other = msp.add_lwpolyline([(200, 0), (220, 0), (220, 10)], close=True,
                               dxfattribs={"layer": DEFAULT.boundary})
    return [boundary(msp).dxf.handle, other.dxf.handle]


def gate_off(doc, msp):
    return [msp.add_point((20 * FT, 30 * FT), dxfattribs={"layer": DEFAULT.gates[0]})
            .dxf.handle]


def island_out(doc, msp):
    return [msp.add_lwpolyline([(120, 20), (140, 20), (140, 25), (120, 25)], close=True,
                               dxfattribs={"layer": DEFAULT.islands[0]}).dxf.handle]


def crossing(doc, msp):
    e = boundary(msp)
    e.set_points([(0, 0), (40, 30), (40, 0), (0, 30)], format="xy")
    return [e.dxf.handle]


@pytest.mark.parametrize(("change", "said"), [
    (open_boundary, "layer 'C-PRKG-OTLN': expected a closed boundary (a closed LWPOLYLINE "
                    "or POLYLINE, a CIRCLE, an ELLIPSE or a closed SPLINE), found only open "
                    "lines: LINE #{0}"),
    (two_boundaries, "layer 'C-PRKG-OTLN': expected one closed boundary, found 2: "
                     "LWPOLYLINE #{0}, LWPOLYLINE #{1}"),
    (gate_off, "layer 'C-PRKG-GATE': POINT #{0} at (6.10, 9.14) m is 6.10 m from the "
               "boundary (LWPOLYLINE #"),
    (island_out, "layer 'C-PRKG-ISLD': LWPOLYLINE #{0}: expected an island inside the "
                 "boundary, found one reaching"),
    (crossing, "layer 'C-PRKG-OTLN': LWPOLYLINE #{0}: expected a simple polygon, but "
               "Self-intersection"),
], ids=["open", "two", "gate-off", "island-out", "crossing"])
def test_a_bad_drawing_is_one_clear_error_and_nothing_is_written(tmp_path, capsys, change,
                                                                 said):
    handles, out = bad_drawing(tmp_path, change)
    code, stdout, err = run([tmp_path / "bad.dxf", "-o", out], capsys)
    assert code == 2 and stdout == "" and "Traceback" not in err
    assert said.format(*handles) in err, err
    assert err.startswith(f"lotsim: {tmp_path / 'bad.dxf'}: layer ")
    assert not out.parent.exists()


def test_a_layer_the_drawing_lacks_is_named_with_the_layers_it_has(tmp_path, capsys):
    plot_drawing(tmp_path / "site.dxf", insunits=2, unit=FT)
    code, _, err = run([tmp_path / "site.dxf", "-o", tmp_path / "p.yaml",
                        "--boundary-layer", "LOT", "--gate-layer", "ROADS"], capsys)
    assert code == 2
    assert "no layer 'LOT' in the drawing (its layers: 0, C-BLDG-ENTR, C-PRKG-GATE, " \
           "C-PRKG-ISLD, C-PRKG-OTLN, Defpoints, NOTES); name the layer with " \
           "--boundary-layer" in err
    assert "no layer 'ROADS' in the drawing" in err and "--gate-layer" in err
    assert "not a DXF drawing" in run([ROOT / "README.md", "-o", tmp_path / "p.yaml"],
                                      capsys)[2]


def test_a_shipped_lot_exported_comes_back_as_its_plot(tmp_path, capsys):
    need("ezdxf")
    scenario = ROOT / "scenarios" / "mixed_lot.yaml"
    assert main(["export", str(scenario), "--dxf", str(tmp_path / "lot.dxf")]) == 0
    code, _, err = run([tmp_path / "lot.dxf", "-o", tmp_path], capsys)
    assert (code, err) == (0, "")
    plot = read_plot(tmp_path / "lot.plot.yaml")
    lot = lot_of(scenario)
    assert Polygon(plot.boundary).symmetric_difference(lot.boundary).area < 1e-6
    assert Polygon(plot.boundary).hausdorff_distance(lot.boundary) < TOLERANCE
    (island,) = plot.islands
    (area,) = [a for a in lot.areas if a.kind == "no_go"]
    assert island.id == area.id and Polygon(island.polygon).equals(area.polygon)
    assert [(g.id, g.at) for g in plot.gates] == [("gate-in", (0.0, 30.0))]


def test_the_import_names_its_extra_and_other_formats_refuse_its_options(tmp_path, capsys,
                                                                         monkeypatch):
    monkeypatch.setitem(sys.modules, "ezdxf", None)
    code, _, err = run([tmp_path / "site.dxf", "-o", tmp_path / "p.yaml"], capsys)
    assert code == 2 and "pip install 'lotsim[dxf]'" in err and "Traceback" not in err
    assert main(["import", "osm", str(tmp_path / "x.osm"), "-o", str(tmp_path),
                 "--units", "ft"]) == 2
    assert "--units is for DXF drawings" in capsys.readouterr().err
    assert run([tmp_path / "site.dxf", "-o", tmp_path / "p.txt"], capsys)[0] == 2


@pytest.mark.slow
def test_lotsim_layout_lays_out_the_plot_read(tmp_path, capsys):
    plot_drawing(tmp_path / "site.dxf", insunits=2, unit=FT)
    assert run([tmp_path / "site.dxf", "-o", tmp_path / "site.yaml"], capsys)[0] == 0
    assert main(["layout", str(tmp_path / "site.yaml"), "-o", str(tmp_path / "lot.yaml"),
                 "--orientations", "1", "--offsets", "1", "--prepared", "1"]) == 0
    out = capsys.readouterr().out
    assert "wrote" in out and (tmp_path / "lot.yaml").exists()
    assert main(["validate", "--strict", str(tmp_path / "lot.yaml")]) == 0
