"""Disturbances on the command line and in a scenario file: ``lotsim run --late/--speed/
--stalls`` and the ``disturbances`` section, what they write and how a mistake is told."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import lotsim
from lotsim.cli import main
from lotsim.errors import ScenarioError

DOCS = Path(__file__).resolve().parents[3] / "docs" / "scenario.md"


def _section() -> str:
    """The ``disturbances`` block of docs/scenario.md, as written there."""
    text = DOCS.read_text(encoding="utf-8")
    block = re.search(r"```yaml\n(disturbances:.*?)```", text, re.S)
    assert block, "docs/scenario.md shows a disturbances section"
    return block.group(1)


def test_the_documented_section_is_read_as_it_says():
    sc = lotsim.load_scenario(lotsim.EXAMPLE + _section())
    d = sc.disturbances
    assert (d.late_probability, d.late_max, d.speed) == (0.1, 5.0, (0.8, 1.0))
    assert (d.stall_rate, d.stall_duration, d.seed) == (10.0, (30.0, 120.0), 7)
    assert d.stalls == (lotsim.Stall("bob", 3.0, 60.0),)


@pytest.mark.parametrize("section, key, token, words", [
    ("disturbances: {late_starts: {probability: 1.5, max: 5}}",
     "disturbances.late_starts.probability", "1.5", "expected a number ≤ 1, found 1.5"),
    ("disturbances: {speed: [0.9, 0.5]}", "disturbances.speed", "[0.9",
     "low <= high"),
    ("disturbances: {stalls: {at: [{car: zed, time: 1, duration: 5}]}}",
     "disturbances.stalls.at[0].car", "zed", "id of a car of the traffic, found 'zed'"),
    ("disturbances: {stall: {rate_per_hour: 3}}", "disturbances", "stall:", "stall"),
])
def test_a_bad_section_is_told_at_its_line_and_column(section, key, token, words):
    line = lotsim.EXAMPLE.count("\n") + 1
    with pytest.raises(ScenarioError) as err:
        lotsim.load_scenario(lotsim.EXAMPLE + section + "\n")
    assert f"<scenario>:{line}:{section.index(token) + 1}: {key}" in str(err.value)
    assert words in str(err.value)


@pytest.mark.slow
def test_run_drives_the_plan_through_the_options_and_check_verifies_it(tmp_path, capsys):
    out = tmp_path / "o"
    code = main(["run", "scenarios/mixed_lot.yaml", "-o", str(out), "--no-gif",
                 "--late", "0.2,4", "--stalls", "20,40,40", "--repair-after", "12",
                 "--disturbance-seed", "5"])
    assert code == 0
    said = capsys.readouterr().out
    doc = json.loads((out / "result.json").read_text())
    rec = doc["disturbances"]
    assert rec["seed"] == 5 and rec["settings"]["stall_rate"] == 20.0
    assert rec["settings"]["repair_after"] == 12.0 and rec["replans"]
    # a repair is a car held up that was planned again and given a new plan
    assert rec["repaired"] == sum(not r["outcome"].startswith("none found")
                                  for r in rec["replans"])
    assert rec["stalls"] and all(s["t1"] - s["t0"] == pytest.approx(40.0)
                                 for s in rec["stalls"])
    assert f"{len(rec['late'])} late starts, {len(rec['stalls'])} stalls" in said
    assert main(["check", str(out / "result.json")]) == 0


def test_no_disturbances_drives_the_scenarios_own_as_planned(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(lotsim.EXAMPLE + "disturbances: {late_starts: {probability: 1, max: 9}}\n")
    assert main(["run", str(path), "-o", str(tmp_path / "a"), "--no-gif"]) == 0
    assert main(["run", str(path), "-o", str(tmp_path / "b"), "--no-gif",
                 "--no-disturbances"]) == 0
    a = json.loads((tmp_path / "a" / "result.json").read_text())
    b = json.loads((tmp_path / "b" / "result.json").read_text())
    assert len(a["disturbances"]["late"]) > 0 and "disturbances" not in b
    assert a["metrics"]["makespan"] > b["metrics"]["makespan"]


@pytest.mark.parametrize("argv, words", [
    (["--late", "0.5"], "--late: expected 2 numbers separated by commas, found '0.5'"),
    (["--late", "2,5"], "--late: expected 0 to 1, found 2"),
    (["--speed", "0,1"], "--speed: expected 0.1 to 1, found 0"),
    (["--stalls", "5,9"], "--stalls: expected 1 or 3 numbers"),
    (["--repair-after", "soon"], "--repair-after: expected seconds or never, found 'soon'"),
    (["--repair-after", "0"], "--repair-after: expected 1 to 3600 seconds, found 0"),
    (["--no-disturbances", "--late", "0.1,2"], "--no-disturbances: drives the plan as "
                                               "planned; it cannot go with --late"),
])
def test_a_bad_option_is_refused_before_any_planning(argv, words, tmp_path, capsys):
    code = main(["run", "scenarios/quickstart.yaml", "-o", str(tmp_path / "o"), "--no-gif",
                 *argv])
    assert code == 2 and words in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
