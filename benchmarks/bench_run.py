"""Multi-vehicle planning speed: ``lotsim run`` on the large lot (1040 slots).

Run with::

    python benchmarks/bench_run.py            # both cases (a few minutes)
    python benchmarks/bench_run.py --quick    # the 100-vehicle case only

Cases (fixed seeds):

* 100 cars arriving at 600 an hour, staying: planning time against the 2 s target, and the
  95th percentile of a car's planning time against 50 ms;
* 1000 cars at 1200 an hour, each staying 10 to 30 minutes, so slots are freed and reused
  (arrivals, departures, queueing): planning time against the 30 s target, peak memory
  against 400 MB.

For each it prints planning time, per-vehicle planning time (median, p95), expansions,
the peak memory of the process, how every vehicle ended, and the check of the result by
the independent checker. The baseline measured in the same run is CA* (straight-line
heuristic) on the 100-car case: the ratio says what HCA*'s true-distance heuristic buys.
HCA* runs first, as in a fresh ``lotsim run``: the process keeps a few things between runs
(speed profiles, their samples, grid blocks) that a later run finds ready. Lot preparation
(maneuvers for every slot) is timed apart; it is done once per lot. Planning times are wall
clock: on a busy machine they grow with the load (compare ratios, or the run's CPU time,
printed beside it and kept as ``cpu``).
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lotsim.io.result import result_dict, write_json  # noqa: E402
from lotsim.io.scenario_yaml import load_scenario  # noqa: E402
from lotsim.sim.preparation import prepare_graph  # noqa: E402
from lotsim.sim.running import collector_tuned, simulate  # noqa: E402
from lotsim.sim.settings import RunSettings  # noqa: E402
from lotsim.traffic.demand import StreamSpec, TrafficSpec, UniformDwell  # noqa: E402
from lotsim.verify import check_result  # noqa: E402


def peak_mb() -> float:
    """Peak resident memory of this process so far [MB] (Linux reports kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def case(sc, lg, count: int, rate: float, dwell, planner: str, *, check: bool = True,
         keep: Path | None = None) -> dict:
    """Plan ``count`` cars; the metrics, wall time, peak memory (and the check). ``keep``:
    write the result document there."""
    stream = StreamSpec(count=count, rate=rate / 3600, mix=((sc.vehicle_types[0].name, 1.0),),
                        entrances=tuple(lg.entrances), dwell=dwell, seed=11)
    sc = dataclasses.replace(sc, traffic=TrafficSpec(streams=(stream,), patience=900.0))
    t, cpu = time.perf_counter(), time.process_time()
    with collector_tuned():
        rr = simulate(sc, RunSettings(planner=planner), lot_graph=lg)
    wall, cpu = time.perf_counter() - t, time.process_time() - cpu
    m = rr.metrics()
    out = {"wall": wall, "cpu": cpu, **m, "peak_mb": peak_mb()}
    if keep is not None:
        write_json(result_dict(rr), keep)
    if check:
        t = time.perf_counter()
        report = check_result(result_dict(rr))
        out["check"] = "ok" if report.ok else f"{report.stats['violations']} violations"
        out["check_s"] = time.perf_counter() - t
    return out


def met(value: float, target: float | None, unit: str) -> str:
    if target is None:
        return ""
    return f" (target <= {target:g} {unit}: {'met' if value <= target else 'NOT met'})"


def show(name: str, r: dict, target: float | None, *, p95: float | None = None,
         memory: float | None = None) -> None:
    print(f"{name}")
    print(f"  planning {r['planning_time']:.2f} s{met(r['planning_time'], target, 's')} "
          f"(run {r['wall']:.2f} s, {r['cpu']:.2f} s of CPU)")
    print(f"  per vehicle: median {1000 * r['planning_time_median']:.1f} ms, "
          f"p95 {1000 * r['planning_time_p95']:.1f} ms"
          f"{met(1000 * r['planning_time_p95'], p95, 'ms')}; {r['searches']} searches, "
          f"{r['expansions']} expansions ({r['expansions'] / max(1, r['searches']):.0f} "
          "per search)")
    print(f"  parked {r['parked']}, departed {r['departed']}, waiting {r['waiting']}, "
          f"rejected {r['rejected']}; mean time to park {r['mean_time_to_park']:.1f} s, "
          f"total waiting {r['total_waiting']:.0f} s")
    if "check" in r:
        print(f"  lotsim check: {r['check']} ({r['check_s']:.1f} s); peak memory "
              f"{r['peak_mb']:.0f} MB{met(r['peak_mb'], memory, 'MB')}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="only the 100-vehicle case")
    args = ap.parse_args()
    sc = load_scenario(ROOT / "scenarios" / "large_lot.yaml")
    t = time.perf_counter()
    lg = prepare_graph(sc)
    print(f"large lot: {len(lg.lot.slots)} slots ({len(lg.lot.free_slots)} free), "
          f"{lg.graph.number_of_nodes()} nodes; prepared in {time.perf_counter() - t:.1f} s")
    hca = case(sc, lg, 100, 600, None, "hca")
    base = case(sc, lg, 100, 600, None, "ca", check=False)
    show("100 cars, CA* (baseline)", base, None)
    show("100 cars, HCA*", hca, 2.0, p95=50.0)
    print(f"  HCA* / CA*: {base['planning_time'] / hca['planning_time']:.1f}x faster, "
          f"{base['expansions'] / max(1, hca['expansions']):.1f}x fewer expansions")
    if not args.quick:
        big = case(sc, lg, 1000, 1200, UniformDwell(600.0, 1800.0), "hca")
        show("1000 cars with departures, HCA*", big, 30.0, memory=400.0)


if __name__ == "__main__":
    main()
