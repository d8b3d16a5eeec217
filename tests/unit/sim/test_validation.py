"""lotsim.sim.validation: what ``lotsim validate`` says of a lot, and in which order.

The lot is the one of test_running.py (one one-way aisle along y = 11 m, three
perpendicular slots P1–P3 on its left, an entrance west, an exit east) with slots 4.0 m
long: the 4.90 m valet car fits none of them.
"""

from __future__ import annotations

import json

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
    assert warnings[0].strip() == "warning: valet cannot park in 3 free slots: P1, P2, P3"
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


# -- which slots can a type not use, and why ---------------------------------------------------
TWO_AISLES = """\
name: two-aisles
vehicle_types: [valet, vclass]
lot:
  boundary: [[0, 0], [60, 0], [60, 55], [0, 55]]
  aisles:
    - {id: a, centerline: [[0, 10], [60, 10]], width: 7.0, direction: one-way}
    - {id: b, centerline: [[0, 45], [60, 45]], width: 7.0, direction: one-way}
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 14, slot_width: 2.5,
       slot_length: 5.0, start: 10, id_prefix: A}
    - {aisle: b, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 6.0, start: 10, id_prefix: B}
  entrances:
    - {id: in, x: 2, y: 10, heading_deg: 0}
  exits:
    - {id: out, x: 54, y: 45, heading_deg: 0}
  occupied: [A2]
"""
"""Two one-way aisles that do not meet: the entrance is on a, the exit on b. Row A (5.0 m
bays, A2 taken) can be parked in but not left for the exit; row B (6.0 m) cannot be
reached. The 5.37 m vclass van does not fit row A."""
FREE_A = [f"A{k}" for k in range(1, 15) if k != 2]
VAN = "the car is 5.37 m long, the slot 5.00 m"


@pytest.fixture(scope="module")
def two_aisles():
    return lotsim.validate(TWO_AISLES)


def test_each_type_s_unusable_free_slots_are_listed_in_full_by_row_with_why(two_aisles):
    rows = two_aisles.unusable()
    a, b = "lot.rows[0] (aisle a, left)", "lot.rows[1] (aisle b, left)"
    assert rows["vclass"] == {a: dict.fromkeys(FREE_A, VAN),
                              b: dict.fromkeys(["B1", "B2", "B3"], "no entrance reaches it")}
    assert rows["valet"] == {a: dict.fromkeys(FREE_A, "no exit can be reached from it"),
                             b: dict.fromkeys(["B1", "B2", "B3"], "no entrance reaches it")}
    # what usable() leaves out, no more, no less: every free slot is in one or the other
    for name, usable in two_aisles.usable().items():
        listed = [sid for slots in rows[name].values() for sid in slots]
        assert sorted(listed + usable) == sorted(FREE_A + ["B1", "B2", "B3"])


def test_the_summary_names_the_free_slots_a_type_does_not_fit_and_counts_the_taken(
        two_aisles):
    line = next(ln for ln in two_aisles.summary().splitlines() if "vclass cannot park" in ln)
    assert line.startswith("  warning: vclass cannot park in 13 free slots (and 1 taken): A1, "
                           "A3,")
    assert line.endswith("(all, by row: lotsim validate --unusable)")


def test_validate_unusable_prints_the_table_and_json_writes_it(tmp_path, capsys):
    path = tmp_path / "lot.yaml"
    path.write_text(TWO_AISLES)
    out = tmp_path / "unusable.json"
    assert main(["validate", str(path), "--unusable", "--json", str(out)]) == 0
    said = capsys.readouterr().out
    table = said[said.index("the free slots each vehicle type cannot use"):].splitlines()
    assert table[1:6] == [
        "  valet: cannot use 16 of 16 free slots",
        "    lot.rows[0] (aisle a, left): A1, A3–A14 — no exit can be reached from it",
        "    lot.rows[1] (aisle b, left): B1–B3 — no entrance reaches it",
        "  vclass: cannot use 16 of 16 free slots",
        f"    lot.rows[0] (aisle a, left): A1, A3–A14 — {VAN}",
    ]
    (answer,) = json.loads(out.read_text())
    assert answer["unusable"]["vclass"]["lot.rows[0] (aisle a, left)"]["A14"] == VAN
    assert answer["free_slots"] == 16 and answer["complete"] is False
    # a file that cannot be written is refused before the lot is prepared
    assert main(["validate", str(path), "--json", str(tmp_path / "no" / "x.json")]) == 2
    assert "folder" in capsys.readouterr().err
