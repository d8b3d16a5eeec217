"""Property: whatever disturbances a run meets — late starts, slow cars, stalls, an aisle or
gate closed for a while, bays taken — the run that is driven passes the independent check
(no overlap at any instant, every limit, every stall stood through, no car on closed
ground, none in a taken bay), every car ends parked, departed, waiting or rejected with a
reason, and the same seed drives the same file.

Disturbances are drawn with a fixed seed per example from a ``numpy.random.Generator`` over
the shipped mixed lot (30 cars, four aisles, two gates, cars leaving) and the quickstart (a
burst of six cars at one aisle). The default profile draws a few (some ten seconds); the
``slow`` test draws many more.
"""

from __future__ import annotations

import numpy as np
import pytest

import lotsim
from lotsim.io.result import result_dict
from lotsim.traffic.disturbances import Closure, Disturbances, Stall, TakenBay

LOTS = ("scenarios/mixed_lot.yaml", "scenarios/quickstart.yaml")


@pytest.fixture(scope="module")
def lots():
    return {path: lotsim.prepare(path) for path in LOTS}


def _drawn(prepared, plan, rng: np.random.Generator) -> Disturbances:
    """Disturbances of every kind, drawn from ``rng`` for ``plan``'s cars and lot."""
    end = max((m.t1 for v in plan.vehicles for m in v.moves), default=60.0)
    cars = [v.id for v in plan.vehicles]
    aisles = sorted(prepared.lot.aisles)
    gates = sorted({*prepared.lot_graph.entrances, *prepared.lot_graph.exits})
    closures, taken, stalls = [], [], []
    for _ in range(int(rng.integers(0, 3))):
        start = float(rng.uniform(0, end / 2))
        kind = "aisle" if rng.random() < 0.6 else "gate"
        what = aisles if kind == "aisle" else gates
        closures.append(Closure(kind, what[int(rng.integers(len(what)))], round(start, 3),
                                round(start + float(rng.uniform(10, 300)), 3)))
    for _ in range(int(rng.integers(0, 3))):
        slot = prepared.lot.slots[int(rng.integers(len(prepared.lot.slots)))].id
        taken.append(TakenBay(slot, round(float(rng.uniform(0, end / 2)), 3)))
    for _ in range(int(rng.integers(0, 3))):
        stalls.append(Stall(cars[int(rng.integers(len(cars)))],
                            round(float(rng.uniform(0, end)), 3),
                            round(float(rng.uniform(5, 90)), 3)))
    lo = float(rng.uniform(0.5, 1.0))
    return Disturbances(late_probability=float(rng.uniform(0, 0.5)),
                        late_max=float(rng.uniform(0, 10)), speed=(lo, 1.0),
                        stall_rate=float(rng.choice([0.0, 20.0])), stalls=tuple(stalls),
                        closures=tuple(closures), taken=tuple(taken),
                        seed=int(rng.integers(2**31)))


def _check_examples(lots, seeds) -> None:
    for seed in seeds:
        rng = np.random.default_rng(seed)
        path = LOTS[seed % len(LOTS)]
        prepared = lots[path]
        plan = lotsim.run(prepared)
        spec = _drawn(prepared, plan, rng)
        rr = lotsim.run(prepared, disturbances=spec)
        report = lotsim.check(rr)
        assert report.ok, (seed, path, spec, report.violations[:3])
        assert len(rr.vehicles) == len(plan.vehicles)
        for v in rr.vehicles:
            assert v.status in ("parked", "departed", "waiting", "rejected")
            assert (v.status in ("parked", "departed")) != bool(v.reason), (seed, v.id)
        if seed % 3 == 0:  # the same seed, the same file
            again = lotsim.run(prepared, disturbances=spec)
            assert result_dict(again) == result_dict(rr)


@pytest.mark.slow
def test_a_run_through_random_disturbances_is_checked_and_accounts_for_every_car(lots):
    _check_examples(lots, range(4))


@pytest.mark.slow
def test_many_runs_through_random_disturbances(lots):
    _check_examples(lots, range(4, 64))
