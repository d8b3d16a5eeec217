"""How well ``lotsim run``'s watchdog projects a run's time and memory, and what watching costs.

Run with::

    python benchmarks/bench_limits.py                  # 200 cars through the large lot
    python benchmarks/bench_limits.py --count 800      # longer (about 3 minutes)

The cars are ``scenarios/large_lot.yaml``'s stream, ``--count`` of them at 600 an hour,
each staying 5 to 20 minutes (so the lot fills and empties). Each case runs in its own
process, so that its peak memory is its own:

* ``watched``: planned under a :class:`lotsim.sim.limits.Watchdog` with no budget that records
  its projection of the run's total time and peak memory after 10 %, 25 % and 50 % of the
  trips planned (a car's way in or out), then writes result.json; the projections are
  printed as ratios to what the run really took (1.00 is exact; above 1 the watchdog stops
  a run too early, below 1 too late);
* ``unwatched``: the same run without a watchdog, for the cost of watching (the ratio of the
  two planning times).
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import resource
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _scenario(count: int) -> str:
    text = (ROOT / "scenarios" / "large_lot.yaml").read_text()
    old = "stream: {count: 100, rate_per_hour: 600}"
    assert old in text
    return text.replace(old, f"stream: {{count: {count}, rate_per_hour: 600, "
                        "dwell: [300, 1200]}")


def _case(count: int, watched: bool, queue: mp.Queue) -> None:
    from lotsim.io.result import result_dict, write_json
    from lotsim.io.scenario_yaml import load_scenario
    from lotsim.sim.limits import Budget, Watchdog, resident_memory
    from lotsim.sim.running import simulate

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "load.yaml"
        path.write_text(_scenario(count))
        scenario = load_scenario(path)
        seen: dict[float, tuple[float, float]] = {}
        start = time.perf_counter()
        if watched:
            dog = Watchdog(Budget(2**62, 1e12), None)  # watches, never stops

            def progress(done: int, total: int) -> None:
                dog.progress(done, total)
                for share in (0.1, 0.25, 0.5):
                    if share not in seen and done >= share * total:
                        need = dog.projection(time.perf_counter() - dog.start,
                                              resident_memory())
                        if need is not None:
                            seen[share] = need

            with dog:
                rr = simulate(scenario, progress=progress)
            first_rss = dog.first[1]
        else:
            rr = simulate(scenario)
            first_rss = 0
        write_json(result_dict(rr), Path(tmp) / "result.json")
        total = time.perf_counter() - start
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    queue.put({"total": total, "planning": rr.planning_time, "peak": peak,
               "first_rss": first_rss, "seen": seen})


def _measure(count: int, watched: bool) -> dict:
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_case, args=(count, watched, queue))
    proc.start()
    out = queue.get()
    proc.join()
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=200, help="cars (200)")
    args = ap.parse_args()
    mb = 2**20
    w = _measure(args.count, True)
    print(f"{args.count} cars, large lot: run {w['total']:.1f} s (planning "
          f"{w['planning']:.1f} s), peak memory {w['peak'] / mb:.0f} MB")
    print("projection after   time ratio   memory ratio")
    for share, (seconds, memory) in sorted(w["seen"].items()):
        print(f"  {100 * share:3.0f} % of trips   {seconds / w['total']:10.2f}   "
              f"{memory / w['peak']:12.2f}")
    u = _measure(args.count, False)
    print(f"unwatched: run {u['total']:.1f} s (planning {u['planning']:.1f} s); "
          f"watched / unwatched planning time: {w['planning'] / u['planning']:.2f}")


if __name__ == "__main__":
    main()
