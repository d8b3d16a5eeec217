"""What lotsim makes of real lots: import a file, then validate and run every lot it wrote.

Run: ``python benchmarks/bench_imports.py osm tests/data/osm/test.osm.pbf`` or
``python benchmarks/bench_imports.py lanelet2 tests/data/lanelet2/autonomoustuff_parking_lot.osm``.

Prints one row per lot of the source: its area, slots mapped / inferred / the source's
capacity tag, aisles, gates, the slots each vehicle type can use (of the free ones), the
time a cold ``validate`` took (on-disk cache off), and for a lot with a gate the mean time
to park of a run of its default traffic and whether ``lotsim check`` passes it. Skipped
lots are listed with the reason.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("LOTSIM_CACHE_DIR", "off")  # every lot planned afresh

import lotsim  # noqa: E402  (after the cache is turned off)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("format", choices=("osm", "lanelet2"))
    ap.add_argument("source")
    ap.add_argument("--no-run", action="store_true", help="validate only")
    args = ap.parse_args(argv)
    out = Path(tempfile.mkdtemp(prefix="lotsim-import-"))
    t0 = time.perf_counter()
    report = (lotsim.import_osm(args.source, out) if args.format == "osm"
              else lotsim.import_lanelet2(args.source, out))
    print(f"imported {args.source} in {time.perf_counter() - t0:.1f} s into {out}")
    print("| lot | area m² | slots mapped / inferred / capacity | aisles | gates | usable "
          "per type (of free) | validate s | mean time to park s | check |")
    print("|---|---|---|---|---|---|---|---|---|")
    for lot in report.lots:
        cap = "-" if lot.capacity is None else str(lot.capacity)
        head = (f"| {lot.id} | {lot.area:.0f} | {lot.mapped} / {lot.inferred} / {cap} | "
                f"{lot.aisles} | {lot.gates} |")
        if not lot.written:
            print(f"{head} skipped: {lot.reason} | | | |")
            continue
        t0 = time.perf_counter()
        try:
            rep = lotsim.validate(lot.path)
        except lotsim.LotsimError as exc:
            print(f"{head} validate fails: {exc} | | | |")
            continue
        took = time.perf_counter() - t0
        g = rep.prepared.lot_graph
        free = len(g.lot.free_slots)
        usable = ", ".join(f"{name} {len(ids)}/{free}" for name, ids in rep.usable().items())
        park, verdict = "", ""
        if not args.no_run and g.lot.entrances and rep.prepared.scenario.traffic is not None:
            result = lotsim.run(rep.prepared)
            park = f"{result.metrics()['mean_time_to_park']:.1f}"
            check = lotsim.check(result)
            verdict = "ok" if check.ok else f"{len(check.violations)} violations"
        print(f"{head} {usable} | {took:.1f} | {park} | {verdict} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
