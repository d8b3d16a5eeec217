"""Whether a long run's cost per car grows with the run: a day's stream through a real lot,
its planning per car hour by hour, and its peak memory.

Run with::

    python benchmarks/bench_day.py                          # dlp_like, 1000 cars at 250/h
    python benchmarks/bench_day.py --lot surface364 --count 3000

The cars arrive at ``--rate`` an hour, each staying 10 to 40 minutes, so the lot reaches
a steady occupancy after its first hour. The run is planned in its own process (its peak
memory is its own). It prints, for each hour of arrivals, the cars, the mean and median
planning time per car [ms], the mean expansions per car and the mean occupancy the cars met
on arrival, then the ratio of the last full hour's mean planning per car to the second
hour's (the first at steady occupancy; 1.00: a car costs the same late in the day as early),
the planning time in all and the peak memory.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

LOTS = ("dlp_like", "surface364")
"""The lots it can run (``scenarios/lots/``), their own stream replaced by the day's."""


def _scenario(lot: str, count: int, rate: float) -> str:
    text = (ROOT / "scenarios" / "lots" / f"{lot}.yaml").read_text()
    lines = text.splitlines()
    k = next(i for i, line in enumerate(lines) if line.strip().startswith("stream:"))
    indent = lines[k][: len(lines[k]) - len(lines[k].lstrip())]
    lines[k] = (f"{indent}stream: {{count: {count}, rate_per_hour: {rate:g}, "
                f"dwell: [600, 2400]}}")
    return "\n".join(lines) + "\n"


def _case(lot: str, count: int, rate: float, queue: mp.Queue) -> None:
    import lotsim

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{lot}-day.yaml"
        path.write_text(_scenario(lot, count, rate))
        prepared = lotsim.prepare(path)
        clock = time.perf_counter()
        rr = lotsim.run(prepared)
        wall = time.perf_counter() - clock
    n_slots = len(prepared.lot_graph.lot.free_slots)
    cars = []
    for v in rr.vehicles:
        a = v.arrival.time
        # the cars in their slots when it came (parked before, not yet set off out)
        held = sum(1 for u in rr.vehicles if u.parked_at is not None and u.parked_at <= a
                   and (u.depart_at is None or u.depart_at > a))
        cars.append((a, v.planning_time, v.expansions, held / n_slots))
    queue.put({"cars": cars, "planning": rr.planning_time, "wall": wall,
               "served": rr.metrics()["served"],
               "peak": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024})


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lot", choices=LOTS, default="dlp_like")
    ap.add_argument("--count", type=int, default=1000, help="cars (1000)")
    ap.add_argument("--rate", type=float, default=250.0, help="cars an hour (250)")
    args = ap.parse_args()
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_case, args=(args.lot, args.count, args.rate, queue))
    proc.start()
    out = queue.get()
    proc.join()
    hours: dict[int, list] = {}
    for a, p, e, occ in out["cars"]:
        hours.setdefault(int(a // 3600), []).append((p, e, occ))
    print(f"{args.count} cars at {args.rate:g}/h through {args.lot}: {out['served']} served, "
          f"planning {out['planning']:.1f} s, run {out['wall']:.1f} s, peak memory "
          f"{out['peak'] / 2**20:.0f} MB")
    print("hour   cars   mean ms   median ms   expansions   occupancy")
    for h in sorted(hours):
        ps = [p for p, _, _ in hours[h]]
        print(f"{h:4d} {len(ps):6d} {1000 * statistics.mean(ps):9.1f} "
              f"{1000 * statistics.median(ps):11.1f} "
              f"{statistics.mean(e for _, e, _ in hours[h]):12.0f} "
              f"{statistics.mean(o for _, _, o in hours[h]):11.2f}")
    full = [h for h in sorted(hours) if len(hours[h]) >= 0.8 * args.rate]
    if len(full) >= 3:
        first, last = full[1], full[-1]
        ratio = (statistics.mean(p for p, _, _ in hours[last])
                 / statistics.mean(p for p, _, _ in hours[first]))
        print(f"mean planning per car, hour {last} / hour {first}: {ratio:.2f}")


if __name__ == "__main__":
    main()
