"""Fingerprints of every shipped scenario: its prepared graph and its run's result.json.

Run: ``python benchmarks/fingerprint.py OUT.json [SCENARIO ...]`` (default: every
scenario in ``scenarios/`` and ``scenarios/lots/``), then
``python benchmarks/fingerprint.py --compare A.json B.json``.

For a change that must not change any answer (a refactor, a speed-up), take fingerprints
before and after and compare them. For each scenario it prints and stores

- ``graph``: a SHA-256 over every node and edge of the prepared lot graph with all their
  data (poses, paths, maneuvers, turns, turnarounds), in the graph's own order, plus the
  slots each vehicle type cannot use and why;
- ``result``: a SHA-256 of the ``result.json`` that ``lotsim run`` writes, without its
  ``settings``;
- ``settings``: a SHA-256 of that ``settings`` section, its version fields left out.

Preparation runs with the on-disk cache off, so every lot is planned afresh.
"""

from __future__ import annotations

import argparse
import dataclasses
import enum
import hashlib
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def canonical(x) -> object:
    """A JSON-able form of graph data that depends on values only, not on where a class
    lives: dataclasses by their class name and fields, arrays as nested lists."""
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return [type(x).__name__, {f.name: canonical(getattr(x, f.name))
                                   for f in dataclasses.fields(x)}]
    if isinstance(x, np.ndarray):
        return ["array", str(x.dtype), canonical(x.tolist())]
    if isinstance(x, np.generic):
        return canonical(x.item())
    if isinstance(x, enum.Enum):
        return ["enum", type(x).__name__, x.name]
    if isinstance(x, dict):
        return ["dict", [[canonical(k), canonical(v)] for k, v in x.items()]]
    if isinstance(x, (list, tuple)):
        return [canonical(v) for v in x]
    if isinstance(x, (set, frozenset)):
        return ["set", sorted(repr(canonical(v)) for v in x)]
    if isinstance(x, float):
        return repr(x)
    if x is None or isinstance(x, (str, int, bool)):
        return x
    if hasattr(x, "wkb_hex"):  # a shapely geometry
        return ["geom", x.wkb_hex]
    if hasattr(x, "__dict__"):
        return [type(x).__name__, canonical(vars(x))]
    if hasattr(x, "__slots__"):
        return [type(x).__name__, {s: canonical(getattr(x, s)) for s in x.__slots__
                                   if hasattr(x, s)}]
    return repr(x)


def graph_digest(path: Path) -> str:
    import lotsim

    prepared = lotsim.prepare(path, cache=False)
    lg = prepared.lot_graph
    h = hashlib.sha256()
    for n, d in lg.graph.nodes(data=True):
        h.update(json.dumps(["n", n, canonical(d)]).encode())
    for u, v, d in lg.graph.edges(data=True):
        h.update(json.dumps(["e", u, v, canonical(d)]).encode())
    h.update(json.dumps(canonical(prepared.infeasible)).encode())
    return h.hexdigest()


def result_digest(path: Path) -> tuple[str, str]:
    with tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, LOTSIM_CACHE_DIR="off")
        proc = subprocess.run([sys.executable, "-m", "lotsim", "run", str(path), "-o", out,
                               "--no-gif"], capture_output=True, text=True, env=env)
        if proc.returncode not in (0, 1):
            failed = f"exit {proc.returncode}: {proc.stderr.strip()[-300:]}"
            return failed, failed
        doc = json.loads(Path(out, "result.json").read_text())
        settings = {k: v for k, v in doc.pop("settings", {}).items() if "version" not in k}
        return (hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest(),
                hashlib.sha256(json.dumps(settings, sort_keys=True).encode()).hexdigest())


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--compare", nargs=2, metavar=("A.json", "B.json"),
                    help="compare two fingerprint files; exit 1 when any part differs")
    ap.add_argument("out", nargs="?", metavar="OUT.json", help="where to write them")
    ap.add_argument("scenarios", nargs="*", metavar="SCENARIO",
                    help="default: every scenario in scenarios/ and scenarios/lots/")
    args = ap.parse_args(argv)
    if args.compare:
        a, b = (json.loads(Path(p).read_text()) for p in args.compare)
        bad = 0
        for name in sorted(set(a) | set(b)):
            for part in ("graph", "result", "settings"):
                x, y = a.get(name, {}).get(part), b.get(name, {}).get(part)
                same = x == y
                bad += not same
                print(f"{'same' if same else 'DIFFERENT':9s} {part:6s} {name}")
        return 1 if bad else 0
    if args.out is None:
        ap.error("give OUT.json (or --compare A.json B.json)")
    out = Path(args.out)
    paths = [Path(p) for p in args.scenarios] or sorted(
        [*ROOT.glob("scenarios/*.yaml"), *ROOT.glob("scenarios/lots/*.yaml")])
    prints = {}
    for p in paths:
        t0 = time.perf_counter()
        name = p.resolve().as_posix().split("/scenarios/", 1)[-1]
        result, settings = result_digest(p)
        prints[name] = {"graph": graph_digest(p), "result": result, "settings": settings}
        print(f"{name}: {time.perf_counter() - t0:.1f} s  graph {prints[name]['graph'][:12]}"
              f"  result {prints[name]['result'][:12]}", flush=True)
    out.write_text(json.dumps(prints, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
