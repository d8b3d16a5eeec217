"""Laying lots out: ``lotsim layout`` on the shipped example plots and on a 1 ha square,
against the hand count of the standard module and the rule of thumb of one bay per
25-30 m² of a surface lot.

Run: ``python benchmarks/bench_layout.py [--runs N] [--jobs N]``.

Each plot is laid out by ``lotsim layout`` as a process (Python's start included), with an
empty on-disk cache each time so that every candidate is prepared. Prints per plot its area,
the bays of the best layout (every one usable by the plot's vehicle types), bays per 100 m²,
m² per bay, the candidates drawn and prepared, the best's mean time to park and throughput
at the plot's demand, and min / median / max wall time of ``--runs`` runs; for the
100 x 60 m rectangle also the hand count (two-way 90° double-loaded modules of 2.5 x 5.0 m
bays on 7 m aisles, a 7 m cross aisle at each end) and for the 30 x 150 m strip (three
rows on a loop), and for every plot its bays against the rule of thumb's range and the
length of the best's dead ends. The counts do not change from run to run or machine to
machine; the times do (docs/performance.md gives them for one machine).
"""

from __future__ import annotations

import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PLOTS = ROOT / "scenarios" / "plots"
HECTARE = """\
name: hectare
description: A 100 x 100 m square, one gate.
boundary: [[0, 0], [100, 0], [100, 100], [0, 100]]
gates: [{id: south, at: [50, 0]}]
"""


def hand_count(length: float, depth: float, bay_width: float = 2.5, bay_length: float = 5.0,
               aisle: float = 7.0) -> int:
    """Two-way 90° double-loaded modules stacked across ``depth``, a cross aisle at each end
    of their ``length`` (docs/layout.md)."""
    return 2 * math.floor(depth / (2 * bay_length + aisle)) * math.floor(
        (length - 2 * aisle) / bay_width)


def lay_out(plot: Path, out: Path, jobs: int | None) -> tuple[float, str]:
    """Wall time of ``lotsim layout`` on ``plot`` with an empty cache, and what it printed."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "LOTSIM_CACHE_DIR": cache}
        args = [sys.executable, "-m", "lotsim", "layout", str(plot), "-o", str(out)]
        if jobs:
            args += ["--jobs", str(jobs)]
        t = time.perf_counter()
        done = subprocess.run(args, env=env, capture_output=True, text=True, cwd=ROOT)
        spent = time.perf_counter() - t
    if done.returncode != 0:
        raise SystemExit(f"lotsim layout {plot} failed:\n{done.stderr}")
    return spent, done.stdout


FIGURES = ("per 100 m²", "aisles [m]", "dead ends", "park [s]", "cars/h")
"""The columns of the table ``lotsim layout`` prints after ``ADA``, in order."""


def _best_line(said: str) -> dict[str, str]:
    """The best candidate's figures from what ``lotsim layout`` printed, by column (a plot
    that asks for bays by use has a column per use between ``drawn`` and ``ADA``)."""
    lines = said.splitlines()
    head = next(x for x in lines if x.startswith(" #")).split()
    cells = next(x for x in lines if x.startswith(" 1 ")).split()
    n = head.index("ADA") + 1
    return {"bays": cells[1], **dict(zip(FIGURES, cells[n:n + len(FIGURES)], strict=True))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--jobs", type=int, default=None)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        square = Path(tmp) / "hectare.yaml"
        square.write_text(HECTARE)
        plots = [*sorted(PLOTS.glob("*.yaml")), square]
        print("| plot | area [m²] | bays | per 100 m² | m² per bay | against 25-30 m² | "
              "dead ends [m] | drawn / prepared | park [s] | cars/h | "
              "wall min / median / max [s] |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for plot in plots:
            times, said = [], ""
            for _ in range(args.runs):
                spent, said = lay_out(plot, Path(tmp) / "lot.yaml", args.jobs)
                times.append(spent)
            head = re.search(r": (\S+), (\d+) m²; (\d+) candidates drawn, (\d+) prepared", said)
            best = _best_line(said)
            area, bays = float(head.group(2)), int(best["bays"])
            per = area / bays
            verdict = "within" if 25 <= per <= 30 else ("denser" if per < 25 else "sparser")
            print(f"| {head.group(1)} | {area:.0f} | {bays} | {best['per 100 m²']} | {per:.1f} | "
                  f"{verdict} | {best['dead ends']} | {head.group(3)} / {head.group(4)} | "
                  f"{best['park [s]']} | {best['cars/h']} | {min(times):.1f} / "
                  f"{statistics.median(times):.1f} / {max(times):.1f} |")
    print(f"\nhand count of the 100 x 60 m rectangle: {hand_count(100, 60)} bays")
    print(f"hand count of the 30 x 150 m strip (three rows on a loop, 5 + 7 + 5 + 7 + 5 m): "
          f"{3 * math.floor((150 - 2 * 7.0) / 2.5)} bays")


if __name__ == "__main__":
    main()
