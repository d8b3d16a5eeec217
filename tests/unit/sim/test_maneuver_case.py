"""lotsim.sim.maneuver_case: one slot's parking problem, answered without preparing the
lot: a car longer than the slot is refused before any lane is worked out, and the lanes'
turns and turnarounds are taken from those kept for the lot before."""

from __future__ import annotations

import pytest

from conftest import ROOT
from lotsim.api import maneuver_case
from lotsim.cli import main
from lotsim.errors import InfeasibleManeuver
from lotsim.sim import preparation

SHORT = """\
name: short
vehicle_types: [valet, corsa]
lot:
  boundary: [[0, 0], [40, 0], [40, 22], [0, 22]]
  aisles:
    - {id: a, centerline: [[0, 11], [40, 11]], width: 7.0, direction: one-way}
  rows:
    - {aisle: a, side: left, kind: perpendicular, count: 3, slot_width: 2.5,
       slot_length: 4.0, start: 12, id_prefix: P}
  entrances:
    - {id: in, x: 3.0, y: 11.0, heading_deg: 0}
"""
"""Three 4.0 m bays: the 4.90 m valet car fits none, the 3.62 m corsa all."""
CULDESAC = ROOT / "scenarios" / "lots" / "culdesac.yaml"


def test_a_car_longer_than_the_slot_is_refused_before_any_lane_is_worked_out(
        monkeypatch, tmp_path, capsys):
    def worked_out(*_args, **_kwargs):
        raise AssertionError("the lanes were worked out for a car that cannot fit")

    monkeypatch.setattr(preparation, "lane_graph", worked_out)
    with pytest.raises(InfeasibleManeuver,
                       match=r"valet cannot park in slot 'P2': the car is 4\.90 m long, "
                             r"the slot 4\.00 m"):
        maneuver_case(SHORT, "P2")
    path = tmp_path / "short.yaml"
    path.write_text(SHORT)
    assert main(["maneuver", str(path), "--slot", "P2"]) == 1
    assert "the car is 4.90 m long, the slot 4.00 m" in capsys.readouterr().err
    with pytest.raises(AssertionError, match="worked out"):  # one that fits is planned
        maneuver_case(SHORT, "P2", vehicle="corsa")


@pytest.mark.slow
def test_the_turns_kept_for_a_lot_answer_the_next_question_on_it(monkeypatch, tmp_path):
    monkeypatch.setenv("LOTSIM_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(preparation, "REMEMBER_FROM", 0)
    memos = []

    class Noted(preparation.RoadmapMemo):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            memos.append(self)

    monkeypatch.setattr(preparation, "RoadmapMemo", Noted)
    first = maneuver_case(CULDESAC, "N2").plan()
    assert memos[-1].worked > 0 and memos[-1].recalled == 0
    again = maneuver_case(CULDESAC, "N2").plan()
    assert memos[-1].worked == 0 and memos[-1].recalled == memos[0].worked
    assert (again.lane, again.station, again.strokes()) == (first.lane, first.station,
                                                            first.strokes())
