"""Planning every slot's parking maneuver, with the geometry cache against without it.

Run: ``python benchmarks/bench_maneuvers.py [scenarios/large_lot.yaml] [--sample N]``

Plans every (vehicle type, slot, lane) of the lot with one ManeuverPlanner (which
plans each distinct local geometry once and moves the result rigidly), then plans
a seeded sample of the same problems with the cache emptied before each one, the
baseline. Prints both times, the per-problem ratio, and checks that the sampled
maneuvers agree (same changes, length within 1 mm) — the cache must not change
answers, only their cost.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from lotsim.errors import InfeasibleManeuver
from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import build_lot
from lotsim.lot.model import DesignVehicle
from lotsim.maneuvers.planner import ManeuverPlanner
from lotsim.roadmap.assemble import build_graph
from lotsim.roadmap.reach import reachable_ranges


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("scenario", nargs="?", default="scenarios/large_lot.yaml")
    ap.add_argument("--sample", type=int, default=40, help="problems planned without cache")
    args = ap.parse_args()
    scenario = load_scenario(args.scenario)
    lot = build_lot(scenario.lot, DesignVehicle.envelope(scenario.vehicle_types))
    ranges = reachable_ranges(build_graph(lot))

    def planner() -> ManeuverPlanner:
        return ManeuverPlanner(lot, parked_width=scenario.parked_vehicle.width,
                               lane_ranges=ranges)

    cached = planner()
    problems = [(v, s, lane) for v in scenario.vehicle_types for s in lot.slots
                for lane in cached.lanes_for(s)]
    t0 = time.perf_counter()
    results = {}
    for v, s, lane in problems:
        try:
            results[(v.name, s.id, lane.id)] = cached.plan(v, s, lane)
        except InfeasibleManeuver:
            results[(v.name, s.id, lane.id)] = None
    t_cached = time.perf_counter() - t0
    rng = np.random.default_rng(7)
    pick = rng.choice(len(problems), size=min(args.sample, len(problems)), replace=False)
    fresh = planner()
    t0 = time.perf_counter()
    agree = 0
    for i in pick:
        v, s, lane = problems[i]
        fresh._cache.clear()
        try:
            m = fresh.plan(v, s, lane)
        except InfeasibleManeuver:
            m = None
        ref = results[(v.name, s.id, lane.id)]
        same = (m is None and ref is None) or (
            m is not None and ref is not None and m.changes == ref.changes
            and abs(m.length - ref.length) < 1e-3)
        agree += same
    t_fresh = (time.perf_counter() - t0) / len(pick)
    n = len(problems)
    print(f"{args.scenario}: {len(lot.slots)} slots, {n} (type, slot, lane) problems")
    print(f"  with cache : {t_cached:7.2f} s total, {1e3 * t_cached / n:6.1f} ms per problem; "
          f"{cached.stats['planned']} planned, {cached.stats['reused']} reused")
    print(f"  no cache   : {1e3 * t_fresh:6.1f} ms per problem (sample of {len(pick)}), "
          f"{t_fresh * n:7.2f} s for the lot (estimated)")
    print(f"  speed-up   : {t_fresh * n / t_cached:5.1f}x; sampled answers agree: "
          f"{agree}/{len(pick)}")


if __name__ == "__main__":
    main()
