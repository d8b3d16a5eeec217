"""The exports' shared parts, with no third-party package: visits and resampling of the
README's run, and ``lotsim export``'s errors (a missing extra, no format, not a result, a
scenario where a run is needed)."""

from __future__ import annotations

import sys

import numpy as np

from conftest import ROOT
from export_runs import result_path
from lotsim.api import load_result
from lotsim.cli import main
from lotsim.io.export.tracks import resample_error, tracks, visits


def test_every_car_of_the_readme_run_parks_in_its_slot_and_leaves_after_its_dwell():
    doc = load_result(result_path("mixed_lot"))
    vs = visits(doc)
    assert len(vs) == len(doc["vehicles"])
    for v in doc["vehicles"]:
        visit = vs[v["id"]]
        assert visit.slot == v["slot"] and visit.park is not None
        assert visit.start <= visit.park < visit.leave <= visit.end  # every car left again
        assert visit.exit == "gate-out"


def test_the_step_skips_samples_by_less_than_a_centimetre_and_a_longer_one_by_more():
    doc = load_result(result_path("mixed_lot"))
    tr = tracks(doc)[0]
    grid = np.arange(np.ceil(tr.t[0] / 0.1), np.floor(tr.t[-1] / 0.1) + 1) * 0.1
    p, h = resample_error(tr, grid)
    assert p < 0.01 and h < 0.002
    coarse = np.arange(np.ceil(tr.t[0]), np.floor(tr.t[-1]) + 1)
    assert resample_error(tr, coarse)[0] > 0.01  # the measure can fail


def test_export_names_the_missing_extra_and_exits_2(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "commonroad", None)  # as if not installed
    path = str(result_path("mixed_lot"))
    assert main(["export", path, "--commonroad", str(tmp_path / "cr")]) == 2
    err = capsys.readouterr().err
    assert "pip install 'lotsim[commonroad]'" in err and "Traceback" not in err
    assert not (tmp_path / "cr").exists()
    assert main(["export", path]) == 2
    assert "at least one of --commonroad DIR" in capsys.readouterr().err
    assert main(["export", str(tmp_path), "--commonroad", str(tmp_path / "cr")]) == 2


def test_dxf_export_names_its_extra_and_takes_a_scenario_alone(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ezdxf", None)  # as if not installed
    scenario = str(ROOT / "scenarios" / "example.yaml")
    target = tmp_path / "out" / "lot.dxf"
    assert main(["export", scenario, "--dxf", str(target)]) == 2
    err = capsys.readouterr().err
    assert "the dxf export needs the ezdxf package: pip install 'lotsim[dxf]'" in err
    assert "Traceback" not in err and not target.parent.exists()
    assert main(["export", scenario, "--dxf", str(tmp_path / "lot.dwg")]) == 2
    assert "--dxf: expected a file name ending in .dxf" in capsys.readouterr().err
    assert main(["export", scenario, "--dxf", str(target), "--sumo", str(tmp_path)]) == 2
    assert "this is a lotsim scenario, not a result" in capsys.readouterr().err
