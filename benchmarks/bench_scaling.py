"""How planning cost grows with work: cars × lot size, HCA*, one process per case.

Run with::

    python benchmarks/bench_scaling.py            # every case (hours: 3000 cars, 5000 slots)
    python benchmarks/bench_scaling.py --quick    # 100 and 300 cars on the 200- and
                                                  # 1000-slot lots (a few minutes)
    python benchmarks/bench_scaling.py --cars 100 300 1000 --slots 200 1000

Lots (generated here, like ``scenarios/large_lot.yaml``): ``k`` two-way aisles 7 m wide,
each between two rows of ``m`` perpendicular 2.5 × 5.0 m slots, joined at both ends by a
two-way cross aisle; one entrance at a corner, one exit at the opposite one. 200 slots
(5 aisles × 2 × 20), 1000 (10 × 2 × 50) and 5000 (25 × 2 × 100).

Traffic: ``n`` cars of one type (fixed seed), each staying 10 to 30 minutes (20 on
average), patience 15 minutes, arriving at 1200 an hour (what one gate lets in: a car every
3 s) or, on a lot too small for that, at the rate that keeps it 70 % full on average
(0.7 × slots × 3 an hour: 420 an hour on 200 slots): slots are freed and reused, busy but
not overloaded. (At 1200 an hour the 200-slot lot is overloaded: cars queue at the gate and
search again every few seconds until they are let in or give up.)

Each case runs in its own process (so its peak memory is its own), on a lot prepared once
and kept in the on-disk cache (:mod:`lotsim.core.diskcache`; preparing is timed apart and printed
with the lot). For each case it prints planning time, planning time per car (mean,
median, p95), expansions per car, peak memory, how the cars ended, and the time and
verdict of ``lotsim check`` (the independent checker) on the result.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

LOTS = {200: (5, 20), 1000: (10, 50), 5000: (25, 100)}
"""Slots → (aisles, slots per row)."""
CARS = (100, 300, 1000, 3000)
RATE = 1200.0  # arrivals per hour: one gate
DWELL = (600.0, 1800.0)  # [s]
FULL = 0.7  # mean occupancy the rate keeps a small lot at


def rate(slots: int) -> float:
    """Arrivals per hour on a lot of ``slots``: :data:`RATE`, or what keeps it :data:`FULL`
    on average (cars stay ``mean(DWELL)``)."""
    return min(RATE, FULL * slots * 3600.0 / (sum(DWELL) / 2))


def grid_lot(aisles: int, per_row: int) -> str:
    """A lot of ``aisles`` two-way aisles, each between two rows of ``per_row``
    perpendicular slots, joined at both ends: the scenario's YAML text."""
    pitch = 17.0  # aisle 7 m + two slot depths of 5 m
    length = 28.0 + per_row * 2.5  # rows from x = 10.5, 10.5 m clear of the east aisle
    height = aisles * pitch
    lines = [
        f"name: grid-{2 * aisles * per_row}",
        f"description: {2 * aisles * per_row} perpendicular slots on {aisles} aisles.",
        "seed: 7",
        "vehicle_types: [valet]",
        "lot:",
        f"  boundary: [[0, 0], [{length}, 0], [{length}, {height}], [0, {height}]]",
        "  aisles:",
        f"    - {{id: west, centerline: [[3.5, 0], [3.5, {height}]], width: 7.0}}",
        f"    - {{id: east, centerline: [[{length - 3.5}, 0], [{length - 3.5}, {height}]], "
        "width: 7.0}",
    ]
    rows = []
    for k in range(aisles):
        y = 8.5 + pitch * k
        lines.append(f"    - {{id: a{k:02d}, centerline: [[3.5, {y}], [{length - 3.5}, {y}]], "
                     "width: 7.0}")
        for side, prefix in (("left", "N"), ("right", "S")):
            rows.append(f"    - {{aisle: a{k:02d}, side: {side}, kind: perpendicular, "
                        f"count: {per_row}, slot_width: 2.5, slot_length: 5.0, start: 10.5, "
                        f"id_prefix: {prefix}{k:02d}-}}")
    lines += ["  rows:", *rows,
              "  entrances: [{id: in, x: 5.25, y: 2.0, heading_deg: 90}]",
              f"  exits: [{{id: out, x: {length - 1.75}, y: {height - 6.0}, heading_deg: 90}}]"]
    return "\n".join(lines) + "\n"


def one_case(slots: int, cars: int) -> dict:
    """Plan and check one case in this process; the figures as a dict."""
    from lotsim.io.result import result_dict
    from lotsim.io.scenario_yaml import parse_scenario
    from lotsim.io.yamlnodes import parse_text
    from lotsim.sim.preparation import prepare_graph
    from lotsim.sim.running import collector_tuned, simulate
    from lotsim.sim.settings import RunSettings
    from lotsim.traffic.demand import StreamSpec, TrafficSpec, UniformDwell
    from lotsim.verify import check_result

    sc = parse_scenario(parse_text(grid_lot(*LOTS[slots]), f"grid-{slots}.yaml"))
    t = time.perf_counter()
    lg = prepare_graph(sc)
    prepared = time.perf_counter() - t
    stream = StreamSpec(count=cars, rate=rate(slots) / 3600, mix=(("valet", 1.0),),
                        entrances=tuple(lg.entrances), dwell=UniformDwell(*DWELL), seed=11)
    sc = dataclasses.replace(sc, traffic=TrafficSpec(streams=(stream,), patience=900.0))
    with collector_tuned():
        rr = simulate(sc, RunSettings(planner="hca"), lot_graph=lg)
    m = rr.metrics()
    t = time.perf_counter()
    report = check_result(result_dict(rr))
    checked = time.perf_counter() - t
    return {"slots": len(lg.lot.slots), "prepare_s": prepared, "from_cache": lg.from_cache,
            **{k: m[k] for k in ("planning_time", "planning_time_median", "planning_time_p95",
                                 "expansions", "parked", "departed", "rejected", "vehicles")},
            "check_s": checked, "check": "ok" if report.ok else report.summary(),
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="100 and 300 cars on the 200- and 1000-slot lots")
    ap.add_argument("--cars", type=int, nargs="+", choices=CARS, help="car counts")
    ap.add_argument("--slots", type=int, nargs="+", choices=sorted(LOTS), help="lot sizes")
    ap.add_argument("--case", nargs=2, type=int, metavar=("SLOTS", "CARS"),
                    help=argparse.SUPPRESS)  # one case, in this process, as JSON
    args = ap.parse_args()
    if args.case:
        print(json.dumps(one_case(*args.case)))
        return
    cars = args.cars or ((100, 300) if args.quick else CARS)
    slots = args.slots or ((200, 1000) if args.quick else sorted(LOTS))
    print(f"HCA*, cars of one type staying {DWELL[0] / 60:g}-{DWELL[1] / 60:g} min, one "
          "process per case (2-core figures in the README)")
    print(f"{'slots':>5} {'rate/h':>6} {'cars':>5} {'plan [s]':>9} {'ms/car':>7} "
          f"{'median':>7} {'p95':>7} {'exp/car':>8} {'peak MB':>8} {'parked':>7} "
          f"{'left':>5} {'away':>5} {'check [s]':>10}")
    for n_slots in slots:
        for n in cars:
            out = subprocess.run([sys.executable, __file__, "--case", str(n_slots), str(n)],
                                 check=True, capture_output=True, text=True)
            r = json.loads(out.stdout.strip().splitlines()[-1])
            per = 1000 * r["planning_time"] / max(1, r["vehicles"])
            print(f"{r['slots']:>5} {rate(n_slots):>6.0f} {n:>5} {r['planning_time']:>9.1f} "
                  f"{per:>7.1f} {1000 * r['planning_time_median']:>7.1f} "
                  f"{1000 * r['planning_time_p95']:>7.1f} "
                  f"{r['expansions'] / max(1, r['vehicles']):>8.0f} {r['peak_mb']:>8.0f} "
                  f"{r['parked']:>7} {r['departed']:>5} {r['rejected']:>5} "
                  f"{r['check_s']:>6.1f} {r['check']}", flush=True)
            if not r["from_cache"]:
                print(f"      (the {r['slots']}-slot lot was prepared in "
                      f"{r['prepare_s']:.1f} s, then kept in the cache)", flush=True)


if __name__ == "__main__":
    main()
