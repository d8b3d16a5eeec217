"""Building the large lot and its graph; batched sweep checks against a per-pose loop.

Run: ``python benchmarks/bench_lot_build.py [scenarios/large_lot.yaml]``

Prints the time to load, build and graph the lot, and the speed-up of the batched
(vectorised shapely + STRtree) lane sweep check over checking one footprint at a
time against every obstacle with shapely — both measured in this run, so the ratio
does not depend on the machine. Both must find the same blocked samples.
"""

from __future__ import annotations

import sys
import time

import numpy as np
import shapely

from lotsim.io.scenario_yaml import load_scenario
from lotsim.lot.build import lane_collider
from lotsim.lot.clearance import Collider
from lotsim.sim.preparation import prepare_graph


def per_pose(collider: Collider, bodies: np.ndarray, obstacles: list) -> np.ndarray:
    out = np.zeros(len(bodies), dtype=bool)
    for i, pts in enumerate(bodies):
        poly = shapely.MultiPoint(pts).convex_hull
        out[i] = not collider.allowed.covers(poly) or any(poly.intersects(o) for o in obstacles)
    return out


def main(path: str = "scenarios/large_lot.yaml") -> None:
    t0 = time.perf_counter()
    scenario = load_scenario(path)
    t1 = time.perf_counter()
    lg = prepare_graph(scenario)
    t2 = time.perf_counter()
    lot = lg.lot
    print(f"{path}: {len(lot.slots)} slots, {lg.graph.number_of_nodes()} nodes, "
          f"{lg.graph.number_of_edges()} edges")
    print(f"load {t1 - t0:.2f} s, build lot + graph {t2 - t1:.2f} s")

    collider = lane_collider(lot)
    obstacles = list(collider.tree.geometries)
    lanes = lot.lanes[:4]
    bodies = np.concatenate(
        [Collider.sweeps(lot.design.footprints(lane.sample(lot.settings.sweep))) for lane in lanes]
    )
    t3 = time.perf_counter()
    fast = collider.blocked(bodies)
    t4 = time.perf_counter()
    slow = per_pose(collider, bodies, obstacles)
    t5 = time.perf_counter()
    assert np.array_equal(fast, slow), "batched and per-pose checks disagree"
    print(f"sweep check of {len(bodies)} footprint pairs: batched {1e3 * (t4 - t3):.1f} ms, "
          f"per-pose loop {1e3 * (t5 - t4):.1f} ms, ratio {(t5 - t4) / (t4 - t3):.0f}x")


if __name__ == "__main__":
    main(*sys.argv[1:])
