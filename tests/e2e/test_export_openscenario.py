"""OpenSCENARIO / OpenDRIVE export: both files validate against the ASAM XSDs shipped with
scenariogeneration (with xmlschema); every car's polyline, read back, agrees with
result.json within the stated error and runs forward in time; every slot's parkingSpace
stands at the slot; planted faults are rejected by the schemas or by the check."""

from __future__ import annotations

import contextlib
import functools
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import shapely

from export_runs import need, result_path, run_params
from lotsim.api import load_result
from lotsim.io.export.tracks import tracks

POSITION_ERROR = 0.01
"""Every lotsim sample lies within 1 cm [m] of its car's polyline ..."""
HEADING_ERROR = 0.002
"""... and within 2 mrad [rad] of its heading (docs/export.md)."""
SPACE_ERROR = (1e-4, 1e-5)
"""A parkingSpace stands at its slot's centre within 0.1 mm [m] and at its heading within
10 µrad [rad]: the files' rounding (1 µrad of a road's heading moves a slot 10 m along it
by 10 µm)."""


@functools.cache
def schema(name: str):
    """An ASAM XSD shipped with scenariogeneration, loaded by xmlschema."""
    need("xmlschema")
    import scenariogeneration
    import xmlschema

    folder = Path(scenariogeneration.__file__).parent.parent / "schemas"
    return xmlschema.XMLSchema(str(folder / name))


def osc_schema():
    return schema("OpenSCENARIO_1_2.xsd")


def odr_schema():
    return schema("opendrive_17_core.xsd")


@pytest.fixture(scope="module", params=run_params())
def exported(request, tmp_path_factory):
    need("scenariogeneration")
    import lotsim

    doc = load_result(result_path(request.param))
    info = lotsim.export_openscenario(doc, tmp_path_factory.mktemp(f"osc-{request.param}"))
    return doc, info, ET.parse(info.scenario), ET.parse(info.road_network)


def schema_errors(xsd, tree: ET.ElementTree, *, first: bool = False) -> list[str]:
    """The schema's complaints about ``tree`` (up to 3; with ``first``, the first one, found
    without reading the rest of the file)."""
    out = []
    for e in xsd.iter_errors(tree):
        out.append(str(e).splitlines()[0])
        if first or len(out) == 3:
            break
    return out


def test_both_files_validate_against_the_asam_schemas(exported):
    _, info, scenario, road = exported
    assert road.getroot().find("header").get("revMinor") == "7"
    assert scenario.getroot().find("FileHeader").get("revMinor") == "2"
    assert schema_errors(odr_schema(), road) == []
    assert schema_errors(osc_schema(), scenario) == []
    assert scenario.getroot().find("RoadNetwork/LogicFile").get("filepath") == "lot.xodr"


def polylines(scenario: ET.ElementTree) -> dict[str, dict[str, np.ndarray]]:
    """Each car's trajectory as read back: vertex times, positions and headings, its
    teleport at the start and the time its action starts."""
    root = scenario.getroot()
    teleports = {
        a.get("entityRef"): a.find(".//WorldPosition")
        for a in root.iter("Private")
    }  # fmt: skip
    out = {}
    for group in root.iter("ManeuverGroup"):
        car = group.find("Actors/EntityRef").get("entityRef")
        poly = group.find(".//FollowTrajectoryAction//Polyline")
        timing = group.find(".//FollowTrajectoryAction/TimeReference/Timing")
        start = group.find(".//Event/StartTrigger//SimulationTimeCondition")
        verts = poly.findall("Vertex")
        pos = [v.find("Position/WorldPosition") for v in verts]
        out[car] = {
            "t": np.array([float(v.get("time")) for v in verts]),
            "x": np.array([float(p.get("x")) for p in pos]),
            "y": np.array([float(p.get("y")) for p in pos]),
            "h": np.array([float(p.get("h")) for p in pos]),
            "start": float(start.get("value")),
            "timing": (timing.get("domainAbsoluteRelative"), timing.get("scale"),
                       timing.get("offset")),
            "teleport": tuple(float(teleports[car].get(k)) for k in ("x", "y", "h")),
        }  # fmt: skip
    return out


def disagreements(doc: dict, scenario: ET.ElementTree) -> list[str]:
    """What in the polylines read back disagrees with result.json: a car without one,
    vertices out of time order, ends other than the samples', a sample farther than the
    stated error, a start or a teleport not at the first sample."""
    lines = polylines(scenario)
    out = []
    for tr in tracks(doc):
        p = lines.get(tr.id)
        if p is None:
            out.append(f"{tr.id}: no trajectory")
            continue
        if not (np.diff(p["t"]) > 0).all():
            out.append(f"{tr.id}: vertices out of time order")
            continue
        if abs(p["t"][0] - tr.t[0]) > 1e-6 or abs(p["t"][-1] - tr.t[-1]) > 1e-6:
            out.append(f"{tr.id}: ends at {p['t'][0]}..{p['t'][-1]}, not {tr.t[0]}..{tr.t[-1]}")
        x = np.interp(tr.t, p["t"], p["x"])
        y = np.interp(tr.t, p["t"], p["y"])
        h = np.interp(tr.t, p["t"], p["h"])
        dp = float(np.hypot(x - tr.x, y - tr.y).max())
        dh = float(np.abs((h - tr.theta + np.pi) % (2 * np.pi) - np.pi).max())
        if dp > POSITION_ERROR + 1e-9 or dh > HEADING_ERROR + 1e-9:
            out.append(f"{tr.id}: {dp * 1000:.1f} mm, {dh * 1000:.2f} mrad off")
        if np.abs(np.diff(p["h"])).max(initial=0) > math.pi:
            out.append(f"{tr.id}: a heading jumps by more than pi between vertices")
        if p["timing"] != ("absolute", "1.0", "0.0") or abs(p["start"] - tr.t[0]) > 1e-6:
            out.append(f"{tr.id}: starts at {p['start']} ({p['timing']}), not {tr.t[0]}")
        tx, ty, th = p["teleport"]
        if math.hypot(tx - tr.x[0], ty - tr.y[0]) > 1e-6 or abs(th - tr.theta[0]) > 1e-6:
            out.append(f"{tr.id}: teleported to {p['teleport']}")
    return out


def test_every_polyline_agrees_with_the_result_within_the_stated_error(exported):
    doc, info, scenario, _ = exported
    assert disagreements(doc, scenario) == []
    assert info.position_error <= POSITION_ERROR and info.heading_error <= HEADING_ERROR
    assert info.vertices < info.samples / 2  # straights and rests thinned out


def spaces(road: ET.ElementTree) -> dict[str, tuple[float, float, float, float, float]]:
    """Each parkingSpace object in the world: centre ``x, y``, heading, length, width
    (its road's reference line is straight lines: every aisle of these lots is)."""
    out = {}
    for r in road.getroot().iter("road"):
        geos = [
            tuple(float(g.get(k)) for k in ("s", "x", "y", "hdg", "length"))
            for g in r.find("planView")
        ]
        for o in r.iter("object"):
            assert o.get("type") == "parkingSpace" and o.find("parkingSpace") is not None
            s, t = float(o.get("s")), float(o.get("t"))
            g = max((g for g in geos if g[0] <= s + 1e-9), key=lambda g: g[0])
            ds, hdg = s - g[0], g[3]
            x = g[1] + ds * math.cos(hdg) - t * math.sin(hdg)
            y = g[2] + ds * math.sin(hdg) + t * math.cos(hdg)
            out[o.get("name")] = (
                x, y, hdg + float(o.get("hdg")), float(o.get("length")), float(o.get("width"))
            )
    return out


def test_every_slot_is_a_parking_space_where_it_is(exported):
    doc, info, _, road = exported
    found = spaces(road)
    slots = doc["lot"]["drawing"]["slots"]
    assert len(found) == len(slots) == info.parking_spaces
    for s in slots:
        x, y, h, length, width = found[s["id"]]
        c = shapely.Polygon(s["polygon"]).centroid
        assert math.hypot(x - c.x, y - c.y) < SPACE_ERROR[0], s["id"]
        assert abs((h - s["heading"] + math.pi) % (2 * math.pi) - math.pi) < SPACE_ERROR[1]
        assert (length, width) == (s["length"], s["width"])


def test_planted_faults_are_rejected(exported):
    doc, _, scenario, road = exported
    verts = next(scenario.getroot().iter("Polyline")).findall("Vertex")
    # a vertex out of time order (the schema has no rule for the order; the check has)
    with planted(verts[1], "time", verts[3].get("time")):
        assert any("out of time order" in d for d in disagreements(doc, scenario))
    # a vertex moved by 5 cm
    p = verts[2].find(".//WorldPosition")
    with planted(p, "y", str(float(p.get("y")) + 0.05)):
        assert any("mm" in d for d in disagreements(doc, scenario))
    # an attribute and a value the schemas do not know
    with planted(verts[0], "speed", "1.0"):
        assert "speed" in " ".join(schema_errors(osc_schema(), scenario, first=True))
    with planted(next(road.getroot().iter("object")), "type", "parkingSlot"):
        assert "parkingSlot" in " ".join(schema_errors(odr_schema(), road, first=True))
    assert disagreements(doc, scenario) == []  # all put back


@contextlib.contextmanager
def planted(element: ET.Element, key: str, value: str):
    """``element``'s attribute ``key`` set to ``value`` for the block, then put back."""
    old = element.get(key)
    element.set(key, value)
    try:
        yield
    finally:
        if old is None:
            del element.attrib[key]
        else:
            element.set(key, old)


@pytest.mark.slow
def test_lotsim_export_openscenario_writes_the_files_or_names_the_extra(
    tmp_path, capsys, monkeypatch
):
    need("scenariogeneration")
    from lotsim.cli import main

    path = str(result_path("ladder"))
    assert main(["export", path, "--openscenario", str(tmp_path / "osc")]) == 0
    assert "openscenario: wrote" in capsys.readouterr().out
    assert sorted(p.name for p in (tmp_path / "osc").iterdir()) == ["lot.xodr", "lot.xosc"]
    monkeypatch.setitem(sys.modules, "scenariogeneration", None)  # as if not installed
    assert main(["export", path, "--openscenario", str(tmp_path / "again")]) == 2
    err = capsys.readouterr().err
    assert "pip install 'lotsim[openscenario]'" in err and "Traceback" not in err
    assert not (tmp_path / "again").exists()
