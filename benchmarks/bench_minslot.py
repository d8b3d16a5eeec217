"""Minimum-slot table: exact contacts against a 1 mm stepped simulation.

Run: ``python benchmarks/bench_minslot.py [--processes 2] [--sample 3]``

1. Computes the full table — the catalogue's seven cars × slot widths {1.2, 1.3, 1.4, 1.5}
   × car width × direction changes 0..10 at 1 cm — with the exact planner, in parallel
   processes, and prints the wall time (target: at most 5 s on 2 cores).
2. For one car (altis, width 1.4 × car width) re-answers some of the same queries
   ("fewest changes for slot length L") with a 1 mm stepped simulation of the same
   strategy (vectorised over start headings, as the exact one is), checks that the
   minimum lengths agree to 1 cm (stepped parks at L_Γ + 1 cm with ≤ Γ changes and not
   at L_Γ − 1 cm), and prints the per-query time ratio (target: ≥ 100×).
Everything is measured in this run, so the ratios do not depend on the machine.
"""

from __future__ import annotations

import argparse
import math
import time
from multiprocessing import Pool

import numpy as np

from lotsim.core.geometry import advance
from lotsim.maneuvers.minslot import (
    NO_SOLUTION,
    SlotFrame,
    _inside,
    _start_free,
    edges_cross_walls,
    fewest_changes,
    min_slot_lengths,
    start_headings,
    start_poses,
)
from lotsim.vehicles import CATALOGUE

CARS = ["msv", "zoe", "corsa", "vw", "benz", "altis", "vclass"]
FACTORS = [1.2, 1.3, 1.4, 1.5]
STEP_DEG = 0.1


def _table_entry(job: tuple[str, float]) -> tuple[str, float, list]:
    name, factor = job
    car = CATALOGUE[name]
    rows = min_slot_lengths(car, factor * car.width, max_changes=10, step_deg=STEP_DEG)
    return name, factor, [r.length for r in rows]


def full_table(processes: int) -> list[tuple[str, float, list]]:
    """Every entry of the table, in the order of ``CARS`` × ``FACTORS``.

    The workers take one entry at a time, the widest slots first (they cost the most), so
    neither is left alone with a long tail of entries at the end.
    """
    jobs = [(name, f) for f in sorted(FACTORS, reverse=True) for name in CARS]
    with Pool(processes) as pool:
        done = {entry[:2]: entry for entry in pool.imap(_table_entry, jobs, chunksize=1)}
    return [done[(name, f)] for name in CARS for f in FACTORS]


def stepped_fewest_changes(car, length, width, max_changes=10, step=0.001):
    """The same strategy, stepped: 1 mm moves on the arcs, stop before the step that touches."""
    frame = SlotFrame(length, width)
    thetas = start_headings(STEP_DEG)
    poses = start_poses(car, frame, thetas)
    active = _start_free(car, frame, poses)
    poses = poses[active]
    walls = frame.walls
    for k in range(max_changes + 1):
        kappa = car.max_curvature if k % 2 == 0 else -car.max_curvature
        gear = -1.0 if k % 2 == 0 else 1.0
        moving = np.ones(len(poses), dtype=bool)
        for _ in range(math.ceil(2 * math.pi / abs(kappa) / step)):
            idx = np.flatnonzero(moving)
            if idx.size == 0:
                break
            nxt = advance(poses[idx], gear * step, kappa)
            corners = car.footprints(nxt)
            if _inside(corners, frame).any():
                return k
            hit = edges_cross_walls(corners, walls)
            poses[idx[~hit]] = nxt[~hit]
            moving[idx[hit]] = False
    return NO_SOLUTION


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--sample", type=int, default=3, help="changes counts checked stepped")
    args = ap.parse_args()

    t0 = time.perf_counter()
    table = full_table(args.processes)
    t_table = time.perf_counter() - t0
    print(f"full table: {len(CARS)} cars × {len(FACTORS)} widths × changes 0..10 at 1 cm: "
          f"{t_table:.1f} s on {args.processes} processes")
    print(f"{'car':7} {'W/w':>4} " + " ".join(f"{g:>5}" for g in range(11)))
    for name, f, lengths in table:
        cells = " ".join(f"{v:5.2f}" if v is not None else "    -" for v in lengths)
        print(f"{name:7} {f:4.1f} {cells}")

    exact_time, stepped_time, queries = stepped_queries(table, args.sample)
    print(f"per query: exact {1e3 * exact_time / queries:.1f} ms, 1 mm stepped "
          f"{1e3 * stepped_time / queries:.0f} ms, ratio {stepped_time / exact_time:.0f}x")


def stepped_queries(table: list[tuple[str, float, list]], sample: int
                    ) -> tuple[float, float, int]:
    """Re-answer the altis 1.4 × width row's thresholds for 1..``sample`` changes, exact
    and 1 mm stepped, printing a line each; the summed times [s] and the query count."""
    car = CATALOGUE["altis"]
    width = 1.4 * car.width
    lengths = dict(zip(range(11), next(t[2] for t in table if t[:2] == ("altis", 1.4)),
                       strict=True))
    exact_time = stepped_time = 0.0
    queries = 0
    for g in range(1, 1 + sample):
        for length, must_park in ((lengths[g] + 0.01, True), (lengths[g] - 0.01, False)):
            t1 = time.perf_counter()
            exact, _ = fewest_changes(car, length, width, max_changes=10, step_deg=STEP_DEG)
            t2 = time.perf_counter()
            stepped = stepped_fewest_changes(car, length, width)
            t3 = time.perf_counter()
            exact_time += t2 - t1
            stepped_time += t3 - t2
            queries += 1
            parks = stepped != NO_SOLUTION and stepped <= g
            verdict = "agrees" if parks == must_park else "DISAGREES"
            print(f"  altis W={width:.3f} L={length:.2f}: exact {exact} changes, "
                  f"stepped {stepped}; min length for {g} {verdict} to 1 cm")
    return exact_time, stepped_time, queries


if __name__ == "__main__":
    main()
