"""A file in feet (``units: ft``) is the same lot as the file in metres: every length the
file gives is read in feet, and nothing else is.

The feet files are made here from shipped metric files by converting exactly the keys
docs/scenario.md and docs/layout.md list as lengths, so a length lotsim failed to convert,
or a number it converted that is not a length (a time, a rate, a count, an angle, a
playback speed), makes the two differ.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
import yaml
from shapely.geometry import Polygon

from conftest import ROOT
from feet_files import FOOT, to_feet
from lotsim.api import prepare
from lotsim.design.plot_yaml import read_plot
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle


def _write(path, doc):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def _same_lot(a, b):
    # the lot as preparing it builds it (for the envelope of its types), before any maneuver
    la, lb = (build_lot(x.lot, DesignVehicle.envelope(x.vehicle_types)) for x in (a, b))
    assert la.boundary.equals_exact(lb.boundary, 1e-6)
    assert [s.id for s in la.slots] == [s.id for s in lb.slots]
    for sa, sb in zip(la.slots, lb.slots, strict=True):
        assert np.allclose(sa.polygon, sb.polygon, atol=1e-6), sa.id
        assert (sa.use, sa.kind) == (sb.use, sb.kind)
    assert la.aisles.keys() == lb.aisles.keys()
    for k in la.aisles:
        assert la.aisles[k].polygon.equals_exact(lb.aisles[k].polygon, 1e-6), k
        assert abs(la.aisles[k].width - lb.aisles[k].width) < 1e-9
    for xa, xb in zip(la.areas, lb.areas, strict=True):
        assert xa.polygon.equals_exact(xb.polygon, 1e-6)
    assert len(la.access_aisles) == len(lb.access_aisles)
    for xa, xb in zip(la.access_aisles, lb.access_aisles, strict=True):
        assert Polygon(xa.polygon).equals_exact(Polygon(xb.polygon), 1e-6)
    if la.pavement is not None or lb.pavement is not None:
        assert la.pavement.symmetric_difference(lb.pavement).area < 1e-6


def _run(path, out):
    env = {**os.environ, "LOTSIM_CACHE_DIR": "off"}
    proc = subprocess.run([sys.executable, "-m", "lotsim", "run", str(path), "-o", str(out),
                           "--no-gif"], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return (out / "result.json").read_bytes()


def _both(folder, name):
    """The shipped scenario ``name`` with lengths it leaves out, written in metres and in
    feet under ``folder``: the two files."""
    doc = yaml.safe_load((ROOT / "scenarios" / name).read_text())
    doc.setdefault("name", "same")
    if name == "example.yaml":  # lengths the shipped files leave out
        doc["lot"]["paved"] = {"corner_radius": 2.5}
    else:
        row = next(r for r in doc["lot"]["rows"] if r.get("use") == "van_accessible")
        row["access_aisle_width"] = 2.6
    return _write(folder / "m" / "s.yaml", doc), _write(folder / "ft" / "s.yaml", to_feet(doc))


NAMES = ["example.yaml", "lots/storefront.yaml"]


@pytest.mark.parametrize("name", NAMES)
def test_a_scenario_in_feet_is_the_same_lot(tmp_path, name):
    metric, feet = _both(tmp_path, name)
    sm, sf = load_scenario(metric), load_scenario(feet)
    assert sf.units == "ft" and sm.units == "m"
    for vm, vf in zip(sm.vehicle_types, sf.vehicle_types, strict=True):
        for k in ("width", "front", "rear", "wheelbase", "max_steer"):
            assert getattr(vm, k) == pytest.approx(getattr(vf, k), abs=1e-12), k
        for k in ("max_accel", "max_brake", "max_jerk", "max_lateral_accel",
                  "max_forward_speed", "max_reverse_speed", "max_steer_rate"):
            assert getattr(vm.limits, k) == pytest.approx(getattr(vf.limits, k), abs=1e-12)
    assert sm.traffic == sf.traffic and sm.disturbances == sf.disturbances
    for rm, rf in zip(sm.routes, sf.routes, strict=True):
        assert rm.goal.within == pytest.approx(rf.goal.within, abs=1e-9)
    _same_lot(sm, sf)


# the storefront's run as well (its van-accessible row's access aisles): -m slow
@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_a_scenario_in_feet_is_the_same_run(tmp_path, name):
    metric, feet = _both(tmp_path, name)
    # lengths in feet are read to the nanometre, so the run is the metric one, byte for byte
    assert _run(metric, tmp_path / "out-m") == _run(feet, tmp_path / "out-ft")


def test_a_plot_in_feet_is_the_same_plot(tmp_path):
    doc = yaml.safe_load((ROOT / "scenarios" / "plots" / "island.yaml").read_text())
    doc.update(bays={"angles_deg": [90, 60], "width": 2.6, "length": 5.4},
               aisles={"one_way": True, "widths": {90: {"two-way": 7.2}, 60: {"one-way": 5.0}},
                       "circulation": 7.0},
               building_entrances=[{"id": "door", "at": doc["gates"][0]["at"]}],
               vehicle_types=["valet", {"name": "van", "width": 2.0, "front": 4.2, "rear": 1.0,
                                        "wheelbase": 3.3, "max_steer_deg": 30,
                                        "max_accel": 2.0}])
    metric = read_plot(_write(tmp_path / "m" / "p.yaml", doc))
    feet = read_plot(_write(tmp_path / "ft" / "p.yaml", to_feet(doc)))
    assert np.allclose(metric.boundary, feet.boundary, atol=1e-6)
    for a, b in zip(metric.islands, feet.islands, strict=True):
        assert np.allclose(a.polygon, b.polygon, atol=1e-6)
    for a, b in zip(metric.gates + metric.building_entrances,
                    feet.gates + feet.building_entrances, strict=True):
        assert np.allclose(a.at, b.at, atol=1e-6)
    assert (metric.angles, metric.one_way, metric.demand) == (feet.angles, feet.one_way,
                                                             feet.demand)
    for x in ("bay_width", "bay_length", "circulation_width"):
        assert getattr(metric, x) == pytest.approx(getattr(feet, x), abs=1e-9), x
    assert [k for k, _ in metric.aisle_widths] == [k for k, _ in feet.aisle_widths]
    assert np.allclose([w for _, w in metric.aisle_widths], [w for _, w in feet.aisle_widths])
    for vm, vf in zip(metric.vehicle_types, feet.vehicle_types, strict=True):
        assert vm.length == pytest.approx(vf.length) and vm.width == pytest.approx(vf.width)
        assert vm.limits.max_accel == pytest.approx(vf.limits.max_accel)


@pytest.mark.slow
def test_validate_reports_a_feet_scenarios_lengths_in_feet(tmp_path):
    import csv
    import io
    import re

    from lotsim.api import validate

    doc = yaml.safe_load((ROOT / "scenarios/lots/storefront.yaml").read_text())
    metric = validate(_write(tmp_path / "m" / "s.yaml", doc))
    feet = validate(_write(tmp_path / "ft" / "s.yaml", to_feet(doc)))
    # every length of the metric summary, divided by the foot, is the feet summary's
    m_text, f_text = metric.summary(), feet.summary()
    pattern = r"(\d+\.\d+) (m²|m)\b"
    m_found = re.findall(pattern, m_text)
    f_found = re.findall(r"(\d+\.\d+) (ft²|ft)\b", f_text)
    assert m_found and len(m_found) == len(f_found)
    for (a, ua), (b, ub) in zip(m_found, f_found, strict=True):
        scale = FOOT ** 2 if ua == "m²" else FOOT
        assert ub == ("ft²" if ua == "m²" else "ft")
        # each is rounded to its last digit: the two may differ by both roundings
        da, db = len(a.split(".")[1]), len(b.split(".")[1])
        assert float(b) == pytest.approx(float(a) / scale,
                                         abs=0.5 * 10 ** -da / scale + 0.5 * 10 ** -db + 1e-9)
    assert " m," not in f_text and " m)" not in f_text
    # the schedule's lengths in feet, and its columns named so
    rows_m = list(csv.DictReader(io.StringIO(metric.schedule_csv())))
    rows_f = list(csv.DictReader(io.StringIO(feet.schedule_csv())))
    assert "length_ft" in rows_f[0] and "length_m" not in rows_f[0]
    for a, b in zip(rows_m, rows_f, strict=True):
        assert float(b["length_ft"]) == pytest.approx(float(a["length_m"]) / FOOT, abs=1e-3)
        assert float(b["width_ft"]) == pytest.approx(float(a["width_m"]) / FOOT, abs=1e-3)


@pytest.mark.slow
def test_a_plot_in_feet_is_laid_out_in_feet(tmp_path):
    # the same candidate of the shipped storefront plot and of its feet copy, written as
    # lotsim layout writes it: the feet one states units: ft and reads back as the same lot
    from lotsim.design.allocation import allocate, stretches
    from lotsim.design.preparing import scenario_text
    from lotsim.design.search import candidates
    from lotsim.design.settings import LayoutSettings
    from lotsim.io.scenario_yaml import read_scenario

    doc = yaml.safe_load((ROOT / "scenarios" / "plots" / "storefront_plot.yaml").read_text())
    settings = LayoutSettings(orientations=1, offsets=1)
    texts = []
    for plot in (read_plot(_write(tmp_path / "m" / "p.yaml", doc)),
                 read_plot(_write(tmp_path / "ft" / "p.yaml", to_feet(doc)))):
        cand = max(candidates(plot, settings), key=lambda c: c.bays)
        alloc = allocate(plot, stretches(plot, cand.rows, None))
        texts.append(scenario_text(plot, cand, settings, allocation=alloc)[0])
    drawn = {a.id: (a.start, a.end) for a in cand.aisles}
    metric, feet = texts
    assert "units:" not in metric
    assert [ln for ln in feet.splitlines() if not ln.startswith("#")][0] == "units: ft"
    assert "slot_width: 8.2021," in feet  # 2.5 m
    m, f = tmp_path / "m" / "lot.yaml", tmp_path / "ft" / "lot.yaml"
    m.write_text(metric)
    f.write_text(feet)
    assert read_scenario(f).scenario.units == "ft"
    la, lb = prepare(m, cache=False).lot, prepare(f, cache=False).lot
    assert [(s.id, s.use) for s in la.slots] == [(s.id, s.use) for s in lb.slots]
    for sa, sb in zip(la.slots, lb.slots, strict=True):
        assert np.allclose(sa.polygon, sb.polygon, atol=1e-3), sa.id
    for k in la.aisles:  # as drawn; the metric file rounds them to the centimetre
        assert np.allclose(lb.aisles[k].centerline, drawn[k], atol=1e-3), k
        assert np.allclose(la.aisles[k].centerline, drawn[k], atol=5e-3), k
    for xa, xb in zip(la.access_aisles, lb.access_aisles, strict=True):
        assert np.allclose(xa.polygon, xb.polygon, atol=1e-3)
    for pa, pb in zip(la.entrances + la.exits, lb.entrances + lb.exits, strict=True):
        assert np.allclose(pa.pose, pb.pose, atol=1e-3)
