"""lotsim.sim.execution: a planned run driven through late starts, slow cars and stalls.

The judge is the independent checker (``lotsim.check``, which shares no code with the
planner): every executed run must pass it, stalls included, and the same delays driven
without the plan's order must fail it. The scenario is the shipped mixed lot (30 cars in
an hour, two aisles, cars leaving); hand-built runs check the schedule's ties by eye.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import lotsim
from lotsim.io.result import result_dict
from lotsim.sim.execution import Execution, Run, execute, retimed, runs_of, schedule
from lotsim.sim.results import RunResult
from lotsim.traffic.disturbances import Disturbances, Stall


@pytest.fixture(scope="module")
def planned():
    prepared = lotsim.prepare("scenarios/mixed_lot.yaml")
    return prepared, lotsim.run(prepared)


def _executed(planned, spec):
    prepared, plan = planned
    return execute(plan, spec, memo=prepared.search_graphs)


def test_a_run_without_disturbances_is_driven_exactly_as_planned(planned):
    plan = planned[1]
    ex = _executed(planned, Disturbances())
    a, b = result_dict(plan), result_dict(ex)
    assert a["vehicles"] == b["vehicles"] and a["metrics"] == b["metrics"]
    assert ex.execution.waited == pytest.approx(0.0, abs=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("spec", [
    Disturbances(late_probability=0.3, late_max=10.0),
    Disturbances(speed=(0.6, 1.0)),
    Disturbances(stall_rate=20.0, stall_duration=(30.0, 120.0)),
    Disturbances(late_probability=0.3, late_max=10.0, speed=(0.6, 1.0), stall_rate=10.0,
                 seed=11),
])
def test_every_disturbed_run_passes_the_independent_check(planned, spec):
    plan = planned[1]
    ex = _executed(planned, spec)
    report = lotsim.check(ex)
    assert report.ok, report.violations[:3]
    # every car accounted for, each as the plan had it (a delay parks it later, not
    # elsewhere)
    assert [(v.id, v.slot, v.status) for v in ex.vehicles] == \
        [(v.id, v.slot, v.status) for v in plan.vehicles]
    for v, p in zip(ex.vehicles, plan.vehicles, strict=True):
        if p.parked_at is not None:
            assert v.parked_at >= p.parked_at - 1e-9
    doc = result_dict(ex)["disturbances"]
    assert doc["settings"] == spec.as_dict()
    if spec.stall_rate:
        assert doc["stalls"], "stalls at this rate over an hour must stop some car"


@pytest.mark.slow
def test_the_same_seed_drives_the_same_run_and_another_seed_another(planned):
    spec = Disturbances(late_probability=0.5, late_max=8.0, stall_rate=10.0, seed=3)
    a = result_dict(_executed(planned, spec))
    b = result_dict(_executed(planned, spec))
    c = result_dict(_executed(planned, dataclasses.replace(spec, seed=4)))
    assert a == b and a["vehicles"] != c["vehicles"]


def test_late_starts_and_stalls_follow_the_spec(planned):
    ex = _executed(planned, Disturbances(late_probability=1.0, late_max=4.0,
                                         stalls=(Stall("s05", 0.0, 45.0),)))
    rec = ex.execution
    runs = sum(len(runs_of(v, 0)) for v in planned[1].vehicles)
    # every start from a standstill is late (probability 1), by at most late_max
    assert len(rec.late) == runs and all(0 < x["by"] <= 4.0 for x in rec.late)
    (stall,) = rec.stalls
    assert stall["car"] == "s05" and stall["t1"] - stall["t0"] == pytest.approx(45.0)
    assert lotsim.check(ex).ok


def test_a_slow_car_drives_its_plan_stretched_by_its_factor(planned):
    ex = _executed(planned, Disturbances(speed=(0.5, 0.5)))
    for v, p in zip(ex.vehicles, planned[1].vehicles, strict=True):
        for m, q in zip([m for m in v.moves if m.motion is not None],
                        [q for q in p.moves if q.motion is not None], strict=True):
            assert m.t1 - m.t0 == pytest.approx(2 * (q.t1 - q.t0))
            tau = np.linspace(0.0, q.motion.duration, 7)
            a = q.motion.at(tau, wheelbase=v.vehicle.wheelbase)
            b = m.motion.at(2 * tau, wheelbase=v.vehicle.wheelbase)
            np.testing.assert_allclose(b[0], a[0], atol=1e-9)  # the same path
            np.testing.assert_allclose(b[1], a[1] / 2, atol=1e-9)  # at half the speed
    assert lotsim.check(ex).ok


@pytest.mark.slow
def test_a_stall_driven_without_the_plans_order_collides_and_with_it_does_not(planned):
    # stop each car in turn for a minute at its first standstill on the lanes: with the
    # order of the plan the others wait for it; moved alone (the others on their plans),
    # it is run into by some car
    prepared, plan = planned
    collided = []
    for k, v in enumerate(plan.vehicles):
        rs = runs_of(v, k)
        stops = [r for r in rs[1:] if not r.in_slot]
        if not stops:
            continue
        spec = Disturbances(stalls=(Stall(v.id, rs[stops[0].index - 1].t1, 60.0),))
        ex = _executed(planned, spec)
        assert lotsim.check(ex).ok
        alone = dataclasses.replace(plan, vehicles=[
            ex.vehicles[j] if j == k else u for j, u in enumerate(plan.vehicles)])
        report = lotsim.check(alone)
        if any(x.rule == "overlap" for x in report.violations):
            collided.append(v.id)
        if len(collided) == 2:
            break
    assert collided, "no stall of a car on its own met any other car"


def test_the_checker_sees_a_car_that_moves_during_its_stall(planned):
    ex = _executed(planned, Disturbances(stalls=(Stall("s05", 0.0, 45.0),)))
    doc = result_dict(ex)
    (stall,) = doc["disturbances"]["stalls"]
    doc["disturbances"]["stalls"][0] = {**stall, "t0": stall["t0"] - 2.0}
    report = lotsim.check(doc)
    assert [v.rule for v in report.violations] == ["stall"]


def _run(car, index, t0, t1, factor=1.0):
    return Run(car, index, 0, 0, t0, t1, factor=factor)


def test_two_runs_that_pass_each_other_both_ways_are_held_to_one_pace():
    # car 1's run B leaves place P at 3 s into it, which car 0's run A enters at 4 s; A
    # leaves place Q at 6 s, which B enters at 6 s: their timing is tied. At half speed A
    # would leave Q at 12 s, so B must set off 6 s later, so A (behind it at P) too, and so
    # on without end: B is slowed to A's pace, and both keep both orders
    a, b = _run(0, 0, 0.0, 10.0, factor=0.5), _run(1, 0, 0.0, 10.0)
    src, dst = np.array([0, 1]), np.array([1, 0])  # A first at Q, B first at P
    alpha, beta = np.array([6.0, 3.0]), np.array([6.0, 4.0])
    rec = Execution(Disturbances(), 0, {}, [], [])
    starts = schedule([a, b], src, dst, alpha, beta, [[a], [b]], rec)
    assert b.factor == 0.5 and rec.slowed == 1
    sa, sb = starts[id(a)], starts[id(b)]
    assert sa + 6.0 / a.factor <= sb + 6.0 / b.factor + 1e-9
    assert sb + 3.0 / b.factor <= sa + 4.0 / a.factor + 1e-9
    # at one pace the tie needs no slowing
    a2, b2 = _run(0, 0, 0.0, 10.0, factor=0.5), _run(1, 0, 0.0, 10.0, factor=0.5)
    rec2 = Execution(Disturbances(), 0, {}, [], [])
    schedule([a2, b2], src, dst, alpha, beta, [[a2], [b2]], rec2)
    assert rec2.slowed == 0


def test_a_late_run_delays_those_after_it_by_what_their_order_needs():
    # car 1's run enters at 3 s into it what car 0's run leaves at 8 s into its own
    a, b = _run(0, 0, 0.0, 10.0), _run(1, 0, 6.0, 12.0)
    a.late = 4.0
    rec = Execution(Disturbances(), 0, {}, [], [])
    starts = schedule([a, b], np.array([0]), np.array([1]), np.array([8.0]), np.array([3.0]),
                      [[a], [b]], rec)
    assert starts[id(a)] == pytest.approx(4.0)  # late
    assert starts[id(b)] == pytest.approx(4.0 + 8.0 - 3.0)  # waits for it to have left


def test_retimed_moves_keep_each_car_continuous(planned):
    plan = planned[1]
    v = next(v for v in plan.vehicles if v.arrival.dwell is not None)
    rs = runs_of(v, 0)
    starts = {id(r): r.t0 + 5.0 * (k + 1) for k, r in enumerate(rs)}
    out = retimed(v, rs, starts)
    for m, n in zip(out.moves, out.moves[1:], strict=False):
        assert n.t0 == pytest.approx(m.t1)
    assert out.moves[0].kind == "outside" and out.parked_at is not None
    assert isinstance(plan, RunResult)
