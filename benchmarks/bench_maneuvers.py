"""Planning every slot's parking maneuver: searched once per shape and checked per bay,
against every distinct problem searched on its own.

Run: ``python benchmarks/bench_maneuvers.py [scenarios/lots/surface364.yaml] [--sample N]``

Plans every (vehicle type, slot, lane) of the lot as preparing it does, in one process
(:func:`lotsim.maneuvers.batch.plan_lot` with one worker: a few problems of each shape
searched, the rest fitted from them, :mod:`lotsim.maneuvers.reuse`), then searches a seeded
sample of the same distinct problems each on its own, the baseline. Prints both times, the
estimated ratio for the whole lot, and how the sampled answers compare: searched ones must
be the very answers of their own search; fitted ones never have more direction changes, and
the figures say how much longer they are.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.maneuvers.batch import plan_lot
from lotsim.maneuvers.planner import search_maneuver
from lotsim.maneuvers.reuse import changes
from lotsim.sim.preparation import maneuver_planner


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("scenario", nargs="?", default="scenarios/lots/surface364.yaml")
    ap.add_argument("--sample", type=int, default=300,
                    help="distinct problems searched on their own (default 300)")
    args = ap.parse_args()
    scenario = load_scenario(args.scenario)
    lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
    planner = maneuver_planner(scenario, lot)
    t0 = time.perf_counter()
    plan_lot(planner, scenario.vehicle_types, workers=1)
    t_lot = time.perf_counter() - t0
    types = {v.name: v for v in scenario.vehicle_types}
    lanes = {lane.id: lane for lane in lot.lanes}
    distinct = {}
    for (vname, sid, lid, style), (key, _, _) in planner._posed.items():
        distinct.setdefault(key, (types[vname], lot.slot_by_id[sid], lanes[lid], style))
    keys = list(distinct)
    rng = np.random.default_rng(7)
    pick = rng.choice(len(keys), size=min(args.sample, len(keys)), replace=False)
    own_time, same, fitted_more, fitted_fewer, fitted_equal, longer = 0.0, 0, 0, 0, 0, []
    for i in pick.tolist():
        key = keys[i]
        v, slot, lane, style = distinct[key]
        problem = planner.problems.pose(v, slot, lane)
        t0 = time.perf_counter()
        own, _ = search_maneuver(problem, style, planner.settings)
        own_time += time.perf_counter() - t0
        got = planner._cache[key]
        if key not in planner._fitted:
            same += own.found == got.found and (not own.found or own.value == got.value)
            continue
        a, b = changes(got.value[0]), (changes(own.value[0]) if own.found else None)
        if b is None or a < b:
            fitted_fewer += 1
        elif a > b:
            fitted_more += 1
        else:
            fitted_equal += 1
            longer.append(sum(s.length for s in got.value[0])
                          - sum(s.length for s in own.value[0]))
    per = own_time / len(pick)
    searched_sample = len(pick) - fitted_more - fitted_fewer - fitted_equal
    print(f"{args.scenario}: {len(lot.slots)} slots, {len(keys)} distinct problems: "
          f"{len(keys) - len(planner._fitted)} searched, {len(planner._fitted)} fitted")
    print(f"  per shape : {t_lot:7.2f} s for the lot (one process)")
    print(f"  each alone: {1e3 * per:6.1f} ms per problem (sample of {len(pick)}), "
          f"{per * len(keys):7.2f} s for the lot (estimated)")
    print(f"  ratio     : {t_lot / (per * len(keys)):5.2f} of the time")
    print(f"  sampled searched problems answered as their own search: "
          f"{same}/{searched_sample}")
    print(f"  sampled fitted problems, direction changes against their own search: "
          f"{fitted_equal} the same, {fitted_fewer} fewer (or it found none), "
          f"{fitted_more} more")
    if longer:
        print(f"  ... longer than their own search, where the changes are the same: mean "
              f"{statistics.mean(longer):.2f} m, median {statistics.median(longer):.2f} m, "
              f"max {max(longer):.2f} m, min {min(longer):.2f} m")


if __name__ == "__main__":
    main()
