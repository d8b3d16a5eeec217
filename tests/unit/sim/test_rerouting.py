"""lotsim.sim.rerouting: a car held up past ``repair_after`` while a run is driven through
its stalls is planned again from where it stands, and takes the new way only when it gets
there sooner.

The judge is the independent checker (``lotsim.check``, sharing no code with the planner):
every driven run, repairs and all, passes it. The same stalls driven with no repair give
each repaired car's time to compare with, and the stalls drawn are the same in both. The
lot is the shipped mixed lot (two aisles, cars leaving), stalled an hour at 60 an hour.
"""

from __future__ import annotations

import dataclasses

import pytest

import lotsim
from lotsim.errors import ScenarioError
from lotsim.io.result import result_dict
from lotsim.sim.execution import execute
from lotsim.sim.rerouting import NONE_FOUND
from lotsim.traffic.disturbances import Disturbances

STALLS = Disturbances(stall_rate=60.0, stall_duration=(60.0, 90.0), seed=2)


@pytest.fixture(scope="module")
def driven():
    prepared = lotsim.prepare("scenarios/mixed_lot.yaml")
    plan = lotsim.run(prepared)

    def drive(after):
        spec = dataclasses.replace(STALLS, repair_after=after)
        return execute(plan, spec, memo=prepared.search_graphs)

    return plan, drive(None), drive(5.0), drive


def _reached(v) -> float:
    """When ``v`` is done with the leg it was planned again on: it left, or it parked."""
    return v.left_at if v.left_at is not None else v.parked_at


def test_a_car_held_up_is_planned_again_and_gets_there_sooner_and_safely(driven):
    plan, waiting, repaired, _ = driven
    report = lotsim.check(repaired)
    assert report.ok, report.violations[:3]
    taken = [r for r in repaired.lot_changes.replans if r.outcome != NONE_FOUND]
    assert taken and repaired.execution.repaired == len(taken)
    before = {v.id: v for v in waiting.vehicles}
    for r in taken:
        v = next(u for u in repaired.vehicles if u.id == r.car)
        w = before[r.car]
        # it is done with the leg it was planned again on, a second or more sooner; in the
        # same slot, every car as the plan had it
        if v.left_at is not None and w.left_at is not None and r.t > w.parked_at:
            assert v.left_at <= w.left_at - 1.0 + 1e-6
        else:
            assert v.parked_at <= w.parked_at - 1.0 + 1e-6
        assert "past its plan" in r.why
    assert [(v.id, v.slot, v.status) for v in repaired.vehicles] == \
        [(v.id, v.slot, v.status) for v in plan.vehicles]


def test_repairs_keep_every_stall_that_was_drawn(driven):
    _, waiting, repaired, _ = driven
    a, b = waiting.execution, repaired.execution
    assert len(a.stalls) + a.dropped + a.moved > 0
    assert len(a.stalls) + a.dropped == len(b.stalls) + b.dropped
    # each stall of the run driven with repairs was stood through by its car: checked
    assert not [x for x in lotsim.check(repaired).violations if x.rule == "stall"]


def test_a_threshold_no_wait_reaches_changes_nothing(driven):
    _, waiting, _, drive = driven
    longest = max(m.t1 - m.t0 for v in waiting.vehicles for m in v.moves if m.kind == "wait")
    calm = drive(min(3600.0, longest + 10.0))
    assert result_dict(calm)["vehicles"] == result_dict(waiting)["vehicles"]
    assert calm.execution.repaired == 0


@pytest.mark.slow
def test_the_same_seed_repairs_alike(driven):
    _, _, repaired, drive = driven
    again = drive(5.0)
    assert result_dict(again) == result_dict(repaired)


@pytest.mark.parametrize("value, expected", [("12", 12.0), ("never", None), ("~", None)])
def test_the_scenario_sets_the_threshold(value, expected):
    sc = lotsim.load_scenario(lotsim.EXAMPLE + f"disturbances: {{repair_after: {value}}}\n")
    assert sc.disturbances.repair_after == expected


@pytest.mark.parametrize("value, words", [
    ("0.5", "expected a number ≥ 1, found 0.5"), ("soon", "expected seconds (1 to 3600) or never"),
])
def test_a_bad_threshold_is_told_where_it_is(value, words):
    line = lotsim.EXAMPLE.count("\n") + 1
    with pytest.raises(ScenarioError) as err:
        lotsim.load_scenario(lotsim.EXAMPLE + f"disturbances: {{repair_after: {value}}}\n")
    assert f"<scenario>:{line}:" in str(err.value) and words in str(err.value)
