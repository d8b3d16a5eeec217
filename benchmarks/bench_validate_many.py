"""Validating many lots at once: the lots of an OpenStreetMap extract, one after another, on
local processes, and on a Dask cluster of one and two workers.

Run: ``python benchmarks/bench_validate_many.py [SOURCE.osm.pbf] [--runs N]`` (default the
test extract in ``tests/data/osm``; the Dask rows need ``pip install 'lotsim[dask]'``).

The extract's lots are imported once into a temporary folder; then ``lotsim validate`` of
all of them is timed as a process (Python's start included), with the on-disk cache off so
that every lot is prepared: one file after another (each lot on every core), ``--jobs 2``
(two files at once, each on one core), and ``--scheduler`` on a local Dask cluster of one
and of two single-threaded worker processes (the cluster started before the clock). Prints
min / median / max wall time of ``--runs`` runs and each row's median against the serial
one.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LOTSIM = (sys.executable, "-m", "lotsim")


def timed(args: list[str], runs: int) -> list[float]:
    """Wall times of ``runs`` runs of ``lotsim`` with ``args`` (cache off)."""
    env = {**os.environ, "LOTSIM_CACHE_DIR": "off"}
    out = []
    for _ in range(runs):
        t = time.perf_counter()
        done = subprocess.run([*LOTSIM, *args], env=env, capture_output=True, text=True)
        out.append(time.perf_counter() - t)
        if done.returncode not in (0, 1):
            raise SystemExit(f"lotsim {' '.join(args)} failed:\n{done.stderr}")
    return out


DEFAULT_SOURCE = ROOT / "tests" / "data" / "osm" / "test.osm.pbf"


def measure(source: str | os.PathLike, runs: int) -> tuple[int, dict[str, list[float]]]:
    """The lots of ``source`` imported into a temporary folder, then ``lotsim validate`` of
    all of them timed each way: how many lots, and the wall times by way."""
    sys.path.insert(0, str(ROOT))
    import lotsim

    folder = Path(tempfile.mkdtemp(prefix="lotsim-many-"))
    lotsim.import_osm(source, folder)
    files = sorted(str(p) for p in folder.glob("*.yaml"))
    rows = [("one after another", files), ("--jobs 2", [*files, "--jobs", "2"])]
    times = {name: timed(["validate", *a], runs) for name, a in rows}
    try:
        import distributed
    except ImportError:
        return len(files), times
    was = os.environ.get("LOTSIM_CACHE_DIR")
    os.environ["LOTSIM_CACHE_DIR"] = "off"  # the Dask workers inherit it
    try:
        for n in (1, 2):
            with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                          dashboard_address=None) as cluster:
                times[f"Dask, {n} worker{'s' * (n > 1)}"] = timed(
                    ["validate", *files, "--scheduler", cluster.scheduler_address], runs)
    finally:
        if was is None:
            os.environ.pop("LOTSIM_CACHE_DIR", None)
        else:
            os.environ["LOTSIM_CACHE_DIR"] = was
    return len(files), times


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("source", nargs="?", default=str(DEFAULT_SOURCE))
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args(argv)
    lots, times = measure(args.source, args.runs)
    print(f"{lots} lots imported from {args.source}; {os.cpu_count()} cores, {args.runs} "
          "runs each")
    if len(times) == 2:
        print("(no Dask rows: pip install 'lotsim[dask]')")
    serial = statistics.median(times["one after another"])
    print("| how | wall s min / median / max | median against one after another |")
    print("|---|---|---|")
    for name, ts in times.items():
        med = statistics.median(ts)
        print(f"| {name} | {min(ts):.1f} / {med:.1f} / {max(ts):.1f} | {med / serial:.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
