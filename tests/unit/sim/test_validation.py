"""lotsim.sim.validation: what ``lotsim validate`` says of a lot, and in which order.

The lot is the one of test_running.py (one one-way aisle along y = 11 m, three
perpendicular slots P1–P3 on its left, an entrance west, an exit east) with slots 4.0 m
long: the 4.90 m valet car fits none of them.
"""

from __future__ import annotations

import pytest

import lotsim
from lotsim.cli import main

SHORT = """\
name: short
seed: 3
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [40, 0], [40, 22], [0, 22]]
  aisles:
    - {id: a, centerline: [[0, 11], [40, 11]], width: 7.0, direction: one-way}
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 4.0, start: 12, id_prefix: P}
  entrances:
    - {id: in, x: 3.0, y: 11.0, heading_deg: 0}
  exits:
    - {id: out, x: 34.0, y: 11.0, heading_deg: 0}
"""
TRAFFIC = "traffic: {vehicles: [{id: x, arrival: 0, dwell: 30}]}\n"
TOO_SHORT = "the car is 4.90 m long, the slot 4.00 m"


@pytest.mark.parametrize("traffic", ["", TRAFFIC], ids=["lot only", "with traffic"])
def test_a_slot_too_short_for_the_car_is_said_to_be_so_first_and_not_ok(traffic):
    report = lotsim.validate(SHORT + traffic)  # not refused as "no route to a free slot"
    lines = report.summary().splitlines()
    assert lines[0] == "<scenario>: valid but incomplete — short"
    warnings = [ln for ln in lines if "warning:" in ln]
    assert warnings[0].strip() == "warning: valet cannot park in 3 slots: P1, P2, P3"
    assert lines[lines.index(warnings[0]) + 1].strip() == f"because {TOO_SHORT}"
    # the lanes are not to blame: no slot is said to be out of reach
    assert not any("cannot be reached" in ln for ln in lines)
    if traffic:
        assert report.turned_away["valet"].endswith(f"fits no slot of this lot ({TOO_SHORT})")


def test_a_run_turns_the_car_away_saying_it_is_longer_than_the_slot(tmp_path, capsys):
    path = tmp_path / "short.yaml"
    path.write_text(SHORT + TRAFFIC)
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert f"x: rejected: vehicle type 'valet' fits no slot of this lot ({TOO_SHORT})" in out


def test_strict_validation_headed_as_its_exit_says(tmp_path, capsys):
    short = tmp_path / "short.yaml"
    short.write_text(SHORT)
    fits = tmp_path / "fits.yaml"
    fits.write_text(SHORT.replace("slot_length: 4.0", "slot_length: 5.0"))
    assert main(["validate", "--strict", str(short)]) == 1
    assert capsys.readouterr().out.startswith(f"{short}: valid but incomplete — short\n")
    assert main(["validate", "--strict", str(fits)]) == 0
    assert capsys.readouterr().out.startswith(f"{fits}: ok — short\n")
