"""A day at a real lot: its figures against their targets, and whether a car costs more late
in the day than early.

Run with::

    python benchmarks/bench_day.py                    # 3000 cars over 12 h on dlp_like
    python benchmarks/bench_day.py --repeat 3         # each figure's spread over 3 runs
    python benchmarks/bench_day.py --days 10000       # also 10 000 cars (40 h) at that rate
    python benchmarks/bench_day.py --count 1000       # a shorter day

The day: ``scenarios/lots/dlp_like.yaml`` (364 bays, a little over half taken, one gate)
with its stream replaced by ``--count`` cars at ``--rate`` an hour, each staying a
lognormal 20 minutes (median; ln-spread 0.8, clipped to 5 minutes and 4 hours: most stay
briefly, some for hours), so the lot reaches a steady occupancy within its first hour.

Each repeat prepares the lot first (``lotsim validate``, into the cache) and then runs, as
a user would and with the default limits:

* ``lotsim run DAY.yaml --compact --no-gif`` in a process of its own: its wall time, its
  peak memory (the process's own), the planning time it prints, and the size of the
  result it writes;
* ``lotsim check`` of that result: its wall time;
* (the first repeat) the run again in a process of its own through ``lotsim.run``, for
  each car's planning time: the mean planning per car in each hour of arrivals, and the
  last full hour's against the second's (the first at steady occupancy; 1.00: a car costs
  the same late in the day as early).

It prints each figure with its target, as ``median (min–max)`` over the repeats. With
``--days N`` it also runs N cars at the same rate (some 40 hours for 10 000) and prints its
peak memory against the day's: a run's memory follows the cars present, not the cars
served.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

LOT = "dlp_like"
DWELL = "{lognormal: {median_min: 20, sigma: 0.8}, clip_min: [5, 240]}"
TARGETS = {  # figure → (target, unit, whether more is better)
    "planning": (60.0, "s", False),
    "whole command": (120.0, "s", False),
    "peak memory": (600.0, "MB", False),
    "compact result": (40.0, "MB", False),
    "check": (60.0, "s", False),
    "late / early per car": (1.2, "", False),
}


def day_text(count: int, rate: float) -> str:
    """The day's scenario: the lot's own file with its stream replaced."""
    text = (ROOT / "scenarios" / "lots" / f"{LOT}.yaml").read_text()
    lines = text.splitlines()
    k = next(i for i, line in enumerate(lines) if line.strip().startswith("stream:"))
    indent = lines[k][: len(lines[k]) - len(lines[k].lstrip())]
    lines[k] = (f"{indent}stream: {{count: {count}, rate_per_hour: {rate:g}, "
                f"dwell: {DWELL}}}")
    return "\n".join(lines) + "\n"


def _process(cmd: list[str]) -> tuple[float, float, str]:
    """Run ``cmd``: its wall seconds, its own peak memory [MB] and its output."""
    clock = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - clock
    if proc.returncode not in (0, 3):  # (3: some car still waiting, as lotsim run says)
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}):\n{out[-2000:]}")
    return wall, usage.ru_maxrss / 1024, out


def _per_car(path: str, queue: mp.Queue) -> None:
    import lotsim
    from lotsim import api

    prepared = lotsim.prepare(path)
    with api.collector_tuned():  # as lotsim run plans
        rr = lotsim.run(prepared)
    queue.put([(v.arrival.time, v.planning_time) for v in rr.vehicles])


def _late_over_early(path: str, rate: float) -> tuple[float, list[tuple[int, int, float]]]:
    """The last full hour's mean planning per car over the second hour's, and each hour's
    cars and mean planning [ms], from a run in a process of its own."""
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_per_car, args=(path, queue))
    proc.start()
    cars = queue.get()
    proc.join()
    hours: dict[int, list[float]] = {}
    for a, p in cars:
        hours.setdefault(int(a // 3600), []).append(p)
    table = [(h, len(ps), 1000 * statistics.mean(ps)) for h, ps in sorted(hours.items())]
    full = [(h, n, ms) for h, n, ms in table if n >= 0.8 * rate]
    ratio = full[-1][2] / full[1][2] if len(full) >= 3 else float("nan")
    return ratio, table


def day(count: int, rate: float, tmp: Path, *, per_car: bool = True) -> dict:
    """One day's figures (see the module's docstring)."""
    path = tmp / f"day-{count}.yaml"
    path.write_text(day_text(count, rate))
    # the lot prepared first (into the cache, as a user's second command finds it)
    _process([sys.executable, "-m", "lotsim", "validate", str(path)])
    out = tmp / f"run-{count}"
    wall, peak, said = _process([sys.executable, "-m", "lotsim", "run", str(path), "-o",
                                 str(out), "--compact", "--no-gif"])
    planning = float(re.search(r"planning ([\d.]+) s", said).group(1))
    result = out / "result.json.gz"
    figures = {"planning": planning, "whole command": wall, "peak memory": peak,
               "compact result": result.stat().st_size / 1e6}
    figures["check"] = _process([sys.executable, "-m", "lotsim", "check", str(result)])[0]
    if per_car:
        figures["late / early per car"], figures["hours"] = _late_over_early(str(path), rate)
    return figures


def _spread(xs: list[float]) -> str:
    if len(xs) == 1:
        return f"{xs[0]:.2f}"
    return f"{statistics.median(xs):.2f} ({min(xs):.2f}–{max(xs):.2f})"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=3000, help="cars in the day (3000)")
    ap.add_argument("--rate", type=float, default=250.0, help="cars an hour (250)")
    ap.add_argument("--repeat", type=int, default=1, help="runs of the day (1)")
    ap.add_argument("--days", type=int, metavar="N", help="also run N cars at that rate and "
                    "compare its peak memory with the day's")
    args = ap.parse_args()
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.repeat):
            runs.append(day(args.count, args.rate, Path(tmp), per_car=k == 0))
            print(f"run {k + 1} of {args.repeat} done", file=sys.stderr, flush=True)
        longer = day(args.days, args.rate, Path(tmp), per_car=False) if args.days else None
    hours = args.count / args.rate
    print(f"{args.count} cars over {hours:.1f} h at {args.rate:g} an hour through {LOT}, "
          f"dwell lognormal 20 min (sigma 0.8); {args.repeat} run(s): median (min–max)")
    print(f"{'figure':24s} {'measured':>24s} {'target':>10s}  met")
    for name, (target, unit, _) in TARGETS.items():
        xs = [r[name] for r in runs if name in r]
        met = "yes" if statistics.median(xs) <= target else "no"
        print(f"{name:24s} {_spread(xs) + ' ' + unit:>24s} {f'≤ {target:g} {unit}':>10s}  {met}")
    print("mean planning per car by hour of arrival (first run): hour, cars, ms")
    for h, n, ms in runs[0]["hours"]:
        print(f"  {h:3d} {n:5d} {ms:8.1f}")
    if longer is not None:
        day_peak = statistics.median(r["peak memory"] for r in runs)
        print(f"{args.days} cars over {args.days / args.rate:.0f} h: peak memory "
              f"{longer['peak memory']:.0f} MB, {longer['peak memory'] / day_peak:.2f} of the "
              f"day's; planning {longer['planning']:.0f} s, the whole command "
              f"{longer['whole command']:.0f} s, check {longer['check']:.0f} s")
    peak_self = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"(this script's own peak memory: {peak_self:.0f} MB)")


if __name__ == "__main__":
    main()
