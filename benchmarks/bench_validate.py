"""Where users wait before a run: ``lotsim validate`` cold and warm, and WHCA* against HCA*.

Run with::

    python benchmarks/bench_validate.py            # all rows (a few minutes)
    python benchmarks/bench_validate.py --quick    # the large lot and the congested lot only

Rows (each ``lotsim validate`` is a whole process, as a user runs it):

* ``validate`` of the large lot (1040 slots) and of the 364-bay surface lot (four types),
  with an empty cache (cold: the lot is planned) and again (warm: it is loaded from the
  on-disk cache, :mod:`lotsim.core.diskcache`); the ratio cold / warm is what the cache buys;
* a congested lot (18 cars into 15 free bays of a one-aisle T lot, each staying 30–35 s):
  WHCA* planning time against HCA*'s for the same traffic, measured in the same run (the
  target is at most 2×), with WHCA* searching every replan as the baseline of what
  skipping replans that cannot end sooner buys.

Targets (on 2 cores): cold ≤ 3 s (large lot), ≤ 6 s (364-bay lot);
warm ≤ 0.5 s; WHCA* ≤ 2× HCA*.
"""

from __future__ import annotations

import argparse
import copy
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import lotsim.sim.running  # noqa: E402
from lotsim.io.scenario_yaml import parse_scenario  # noqa: E402
from lotsim.io.yamlnodes import parse_text  # noqa: E402

CONGESTED = """\
name: congested
seed: 76263
vehicle_types: [msv, valet, altis]
lot:
  boundary: [[0, 0], [45.76, 0], [45.76, 16.8], [0, 16.8]]
  aisles:
  - {id: spur, centerline: [[23.08, 0], [23.08, 8.4]], width: 6.0}
  - {id: a0, centerline: [[1.0, 8.4], [44.76, 8.4]], width: 6.0}
  rows:
  - {aisle: a0, side: right, kind: perpendicular, count: 7, slot_width: 2.44,
     slot_length: 5.4, start: 0.0, id_prefix: 0r0-}
  - {aisle: a0, side: right, kind: perpendicular, count: 7, slot_width: 2.44,
     slot_length: 5.4, start: 25.58, id_prefix: 0r1-}
  - {aisle: a0, side: left, kind: perpendicular, count: 7, slot_width: 2.44,
     slot_length: 5.4, start: 0.0, id_prefix: 0l2-}
  entrances: [{id: gate-in, x: 24.58, y: 1.5, heading_deg: 90}]
  exits: [{id: gate-out, x: 21.58, y: 4.5, heading_deg: -90}]
  occupied: {fraction: 0.8, seed: 97, min_free: 15}
traffic:
  patience: 600
  stream: {count: 18, rate_per_hour: 240, mix: {msv: 1, valet: 1, altis: 1}, dwell: [30, 35]}
"""
"""A one-aisle T lot of 6 m aisles, as the property tests draw them (where WHCA* took 92 s)."""


def validate(path: Path, cache: str) -> float:
    """Wall time [s] of one ``lotsim validate`` process with ``LOTSIM_CACHE_DIR=cache``.

    Python keeps the modules it compiles, as it does on a user's machine (and as ``pip
    install`` leaves them): where the environment says not to (``PYTHONDONTWRITEBYTECODE``,
    as on the machine these figures were first taken on), every process would compile
    lotsim's source again, about 0.15 s that no user waits for twice."""
    env = {**os.environ, "LOTSIM_CACHE_DIR": cache}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "lotsim", "validate", str(path)], env=env,
                   check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t


def cold_warm(path: Path) -> tuple[float, float]:
    """Wall times [s] of ``lotsim validate`` with an empty cache, then the best of three
    with the cache it left."""
    with tempfile.TemporaryDirectory() as cache:
        cold = validate(path, cache)
        warm = min(validate(path, cache) for _ in range(3))
    return cold, warm


def validate_rows(paths: list[Path]) -> None:
    print(f"{'lotsim validate':<28} {'cold [s]':>9} {'warm [s]':>9} {'cold/warm':>10}")
    for path in paths:
        cold, warm = cold_warm(path)
        print(f"{path.name:<28} {cold:>9.2f} {warm:>9.2f} {cold / warm:>9.1f}x")


def whca_row() -> dict[str, dict]:
    """Plan the congested lot with HCA*, WHCA* and WHCA* searching every replan; print a line
    each and the ratios; the metrics by name."""
    sc = parse_scenario(parse_text(CONGESTED, "congested.yaml"))
    lg = lotsim.sim.preparation.prepare_graph(sc, cache=False)
    rows = {}
    for name, planner, skip in (("HCA*", "hca", True), ("WHCA* 10 s", "whca", True),
                                ("WHCA*, every replan", "whca", False)):
        settings = lotsim.sim.settings.RunSettings(
            planner=planner, tuning=lotsim.sim.settings.RunTuning(skip_fruitless=skip))
        # each on a copy of the lot: none drives the edge motions another worked out
        with lotsim.sim.running.collector_tuned():
            m = lotsim.sim.running.simulate(sc, settings, lot_graph=copy.deepcopy(lg)).metrics()
        rows[name] = m
        print(f"congested lot, {name:<20} planning {m['planning_time']:6.1f} s, "
              f"{m['searches']:4d} searches, {m['expansions']:7d} expansions; mean time to "
              f"park {m['mean_time_to_park']:.1f} s; departed {m['departed']}/{m['vehicles']}")
    hca, whca, full = (rows[k]["planning_time"] for k in rows)
    print(f"  WHCA* / HCA*: {whca / hca:.1f}x (target ≤ 2x); every replan / WHCA*: "
          f"{full / whca:.1f}x")
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the large lot and the congested lot")
    args = ap.parse_args()
    lots = [ROOT / "scenarios" / "large_lot.yaml"]
    if not args.quick:
        lots.append(ROOT / "scenarios" / "lots" / "surface364.yaml")
    validate_rows(lots)
    whca_row()


if __name__ == "__main__":
    main()
