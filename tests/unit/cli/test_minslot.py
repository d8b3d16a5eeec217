"""`lotsim minslot`: table, JSON contract, vehicle files, bad input."""

import json

import pytest

from lotsim.cli import main
from lotsim.vehicles import CATALOGUE
from oracles.closed_form import one_change_excess


def test_json_rows_for_every_change_count(capsys):
    assert main(["minslot", "--car", "msv", "--width", "2.2", "--max-changes", "3",
                 "--json", "--step-deg", "0.2"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["car"] == "msv" and doc["width"] == 2.2
    assert [r["changes"] for r in doc["rows"]] == [0, 1, 2, 3]
    lengths = [r["length"] for r in doc["rows"]]
    assert lengths == sorted(lengths, reverse=True)
    car = CATALOGUE["msv"]
    assert lengths[1] == pytest.approx(car.length + one_change_excess(car, 2.2)[0], abs=0.02)


def test_length_is_null_where_no_length_works(capsys):
    # a 1.6 m slot fits only the corsa (1.532 m wide) of all catalogue cars
    assert main(["minslot", "--all-cars", "--width", "1.6", "--max-changes", "1",
                 "--json", "--resolution", "0.05", "--step-deg", "0.5"]) == 0
    docs = {d["car"]: d for d in json.loads(capsys.readouterr().out)}
    assert set(docs) == set(CATALOGUE)
    assert all(r["length"] is not None for r in docs["corsa"]["rows"])
    for name in set(CATALOGUE) - {"corsa"}:
        assert [r["length"] for r in docs[name]["rows"]] == [None, None]


def test_vehicle_yaml_file(tmp_path, capsys):
    path = tmp_path / "van.yaml"
    path.write_text("name: van\nwidth: 1.9\nfront: 3.9\nrear: 1.0\nwheelbase: 3.0\n"
                    "max_steer_deg: 33\n")
    assert main(["minslot", "--car", str(path), "--width", "2.3", "--max-changes", "1",
                 "--step-deg", "0.5", "--resolution", "0.05"]) == 0
    assert "van: car length 4.900 m" in capsys.readouterr().out


@pytest.mark.parametrize(("argv", "words"), [
    (["--car", "altis", "--width", "1.5"], "narrower than altis"),
    (["--car", "altis", "--width", "-2"], "positive slot width"),
    (["--car", "altis", "--width", "2.5", "--max-changes", "-1"], "expected 0 to 50"),
    (["--car", "beetle", "--width", "2.5"], "--car: unknown vehicle 'beetle'"),
    # the option as typed ('--vehicle van' was answered as '--car: unknown car'), and the
    # names known
    (["--vehicle", "van", "--width", "2.5"], "lotsim: --vehicle: unknown vehicle 'van'; "
     "expected one of msv, zoe, corsa, vw, benz, altis, vclass, valet (lotsim cars lists "
     "them)"),
])
def test_bad_input_exits_2_with_a_message(capsys, argv, words):
    assert main(["minslot", *argv]) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err


def test_bad_vehicle_file_is_located(tmp_path, capsys):
    path = tmp_path / "bad.yaml"
    path.write_text("name: van\nwidth: -1.9\nfront: 3.9\nrear: 1.0\nwheelbase: 3.0\n"
                    "max_steer_deg: 33\n")
    assert main(["minslot", "--car", str(path), "--width", "2.3"]) == 2
    assert f"{path}:2:8: width: expected a positive number" in capsys.readouterr().err


def test_plot_writes_a_png(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    from PIL import Image

    out = tmp_path / "curve.png"
    assert main(["minslot", "--car", "corsa", "--width", "2.0", "--max-changes", "2",
                 "--step-deg", "0.5", "--resolution", "0.05", "--plot", str(out)]) == 0
    with Image.open(out) as img:
        assert img.format == "PNG" and img.size[0] > 300
    assert [p.name for p in tmp_path.iterdir()] == ["curve.png"]


@pytest.mark.parametrize("width", [1.5, -2.0, float("nan")])
def test_a_width_is_refused_alike_by_python_and_the_command_line(capsys, width):
    # the CLI had a narrow-slot check of its own, where lotsim.minslot returned no lengths
    import lotsim

    with pytest.raises(lotsim.SettingsError) as err:
        lotsim.minslot("altis", width)
    assert err.value.name == "width"
    assert main(["minslot", "--car", "altis", "--width", str(width)]) == 2
    assert capsys.readouterr().err == f"lotsim: --width: {err.value.message}\n"


def test_a_sweep_over_cars_lists_those_a_slot_is_too_narrow_for_with_no_length():
    import lotsim

    assert "narrower than altis (1.78 m wide)" in str(
        pytest.raises(lotsim.SettingsError, lotsim.minslot, "altis", 1.5).value)
    table = lotsim.minslot("altis", 1.5, narrow_ok=True, max_changes=1)
    assert [(r.changes, r.length) for r in table.rows] == [(0, None), (1, None)]


def test_minslot_and_maneuver_name_the_vehicle_alike(capsys):
    """minslot and maneuver name the vehicle alike: --vehicle, or --car."""
    args = ["--width", "2.5", "--max-changes", "2"]
    assert main(["minslot", "--vehicle", "zoe", *args]) == 0
    by_vehicle = capsys.readouterr().out
    assert main(["minslot", "--car", "zoe", *args]) == 0
    assert capsys.readouterr().out == by_vehicle and "zoe" in by_vehicle
    from lotsim.cli.parser import build_parser

    helps = {name: " ".join(p.format_help().split())
             for name, p in build_parser().commands.items()}
    assert "--vehicle TYPE, --car TYPE" in helps["minslot"]
    assert "--vehicle TYPE, --car TYPE" in helps["maneuver"]
    assert "--assignment" in helps["run"] and "--all-vehicles" in helps["minslot"]


def test_the_vehicle_file_of_the_docs_is_one(tmp_path):
    """The vehicle file docs/scenario.md shows is one lotsim reads."""
    import re

    import lotsim
    from conftest import ROOT

    text = (ROOT / "docs" / "scenario.md").read_text()
    section = text[text.index("## A vehicle file"):]
    block = re.search(r"```yaml\n(.*?)```", section, re.S).group(1)
    path = tmp_path / "van.yaml"
    path.write_text(block)
    van = lotsim.car(str(path))
    assert (van.name, van.width, van.length, van.wheelbase) == ("van", 2.0, 5.2, 3.3)
