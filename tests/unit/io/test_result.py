"""lotsim.io.result: a run's vehicles sampled for result.json, and the settings it records."""

import dataclasses
import math

import numpy as np
import pytest

from conftest import ONE_AISLE, scenario_from_text
from lotsim.io.result import SAMPLE_DT, result_dict, samples
from lotsim.sim.preparation import prepare_graph
from lotsim.sim.running import simulate
from lotsim.sim.settings import RunSettings, RunTuning
from lotsim.traffic.demand import Arrival, TrafficSpec


@pytest.fixture(scope="module")
def small():
    sc = scenario_from_text(ONE_AISLE + "traffic: {vehicles: [{id: x, arrival: 0}]}\n")
    return sc, prepare_graph(sc)


def _run(small, *cars, settings=None):
    sc, lg = small
    sc = dataclasses.replace(sc, traffic=TrafficSpec(vehicles=cars, patience=60.0))
    return simulate(sc, settings, lot_graph=lg)


def test_samples_run_from_entering_to_parking_on_the_result_grid(small):
    v = _run(small, Arrival("x", "valet", "in", 0.0)).vehicles[0]
    trace = samples(v)
    inside = [m for m in v.moves if m.kind != "outside"]
    assert trace.start_time == pytest.approx(inside[0].t0)
    assert trace.end_time == pytest.approx(inside[-1].t1)
    # on the common grid while it moves; longer gaps only between two standing samples
    gap = np.diff(trace.t)
    assert (np.round(trace.t[1:-1] / SAMPLE_DT, 6) % 1 == 0).sum() > len(trace.t) / 2
    wide = gap > SAMPLE_DT + 1e-9
    assert ((trace.gear[:-1][wide] == 0) & (trace.gear[1:][wide] == 0)).all()
    assert trace.poses[-1] == pytest.approx(v.parked_pose, abs=1e-6)
    # a car that never got in has no samples
    never = dataclasses.replace(v, moves=[])
    assert samples(never) is None


def test_a_car_setting_off_microseconds_before_a_sample_instant_stands_until_then(small):
    # a car whose wait ended 2 µs before an instant of the sample grid had its drive's
    # first grid sample (rolling for 2 µs, 4e-12 m/s) merged onto the wait's end, so the
    # wait ended in gear 1 and `lotsim check` found an 8 s gap in its sampling. Each move
    # of a car that parks and leaves is shifted so that one drive after standing starts
    # 1.5 µs before a grid instant, which the samples must show as standing to the end
    v = _run(small, Arrival("goes", "valet", "in", 0.0, 20.0)).vehicles[0]
    k = next(k for k, m in enumerate(v.moves) if k and m.motion is not None
             and v.moves[k - 1].motion is None)  # a drive after standing
    t0 = v.moves[k].t0
    shift = math.ceil(t0 / SAMPLE_DT) * SAMPLE_DT - 1.5e-6 - t0
    v.moves = [dataclasses.replace(m, t0=m.t0 + shift, t1=m.t1 + shift) for m in v.moves]
    tr = samples(v)
    start = t0 + shift
    at = int(np.argmin(np.abs(tr.t - start)))
    assert abs(tr.t[at] - start) < 1e-9
    assert tr.gear[at] == 0 and tr.v[at] == 0.0  # it stands until it sets off
    assert tr.t[at + 1] - tr.t[at] <= SAMPLE_DT + 2e-6 and tr.gear[at + 1] != 0
    rest = np.abs(tr.v) < 1e-9
    assert (tr.gear[rest] == 0).all() and (tr.v[rest] == 0).all()


def test_the_settings_section_records_the_sampling_and_every_tuning_value(small):
    tuning = RunTuning(probes=2, congested_for=0.0, skip_fruitless=False)
    doc = result_dict(_run(small, Arrival("x", "valet", "in", 0.0),
                           settings=RunSettings(tuning=tuning)))
    assert doc["settings"]["dt"] == SAMPLE_DT
    assert doc["settings"]["tuning"] == {
        "probes": 2, "probe_floor": 400, "probe_rate": 8.0, "congested_for": 0.0,
        "heuristics_kept": 16, "skip_fruitless": False, "flow_window": 600.0}
