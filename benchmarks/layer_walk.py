"""How a scenario walks through lotsim's layers, from its YAML file to result.json.

Run: ``python benchmarks/layer_walk.py [SCENARIO]`` (default: the quickstart scenario).

Runs ``lotsim run SCENARIO`` in this process (cache off, no pictures) under a profiler hook
and collects every distinct call from a function of one layer (``lotsim.<layer>....``) to a
function of another. It prints the number of such hops, how many of them go back up (a
lower layer calling into a higher one, e.g. through a callback or a late import), and how
many distinct hops enter each layer. Fewer hops, and none back up, make the pipeline easy to
follow; the numbers are the same on any machine.
"""

from __future__ import annotations

import collections
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ORDER = ["errors", "core", "lot", "vehicles", "roadmap", "maneuvers", "traffic", "scenario",
         "sim", "io", "render", "bench", "api", "cli"]
RANK = {name: i for i, name in enumerate(ORDER)}
RANK["vehicles"] = RANK["lot"]
RANK["verify"] = RANK["core"]
EARLIER = {"lotsim.planners.maneuver": "maneuvers", "lotsim.planners.minslot": "maneuvers",
           "lotsim.planners.cooperative": "traffic", "lotsim.planners.reservation": "traffic",
           "lotsim.lot.graph": "roadmap", "lotsim.lot.turnaround": "roadmap",
           "lotsim.lot.multipoint": "roadmap", "lotsim.geometry": "core", "lotsim.forkmap": "core",
           "lotsim.cache": "core", "lotsim.atomic": "core", "lotsim.settings": "sim",
           "lotsim.trajectory": "vehicles", "lotsim.traffic": "traffic", "lotsim.priority": "sim",
           "lotsim.validation": "sim", "lotsim.limits": "sim", "lotsim.replay": "render",
           "lotsim.check": "verify"}
"""Where the modules of lotsim 0.1.0's earlier layout sit, to compare a run of that code."""


def layer(module: str | None) -> str | None:
    if not module or not module.startswith("lotsim"):
        return None
    for name, where in EARLIER.items():
        if module == name or module.startswith(name + "."):
            return where
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] != "__main__" else "cli"


def main(path: str = str(ROOT / "scenarios" / "quickstart.yaml")) -> None:
    os.environ["LOTSIM_CACHE_DIR"] = "off"
    from lotsim.cli import main as cli_main

    hops: set[tuple[str, str]] = set()

    def hook(frame, event, arg):
        if event != "call":
            return
        callee = frame.f_globals.get("__name__")
        caller_frame = frame.f_back
        caller = caller_frame.f_globals.get("__name__") if caller_frame else None
        a, b = layer(caller), layer(callee)
        if a and b and a != b:
            hops.add((f"{caller}.{caller_frame.f_code.co_name}",
                      f"{callee}.{frame.f_code.co_name}"))

    with tempfile.TemporaryDirectory() as out:
        sys.setprofile(hook)
        try:
            code = cli_main(["run", path, "-o", out, "--no-gif"])
        finally:
            sys.setprofile(None)
    up = [(a, b) for a, b in hops if RANK[layer(b)] > RANK[layer(a)]]
    into = collections.Counter(layer(b) for _, b in hops)
    modules = {(a.rsplit(".", 1)[0], b.rsplit(".", 1)[0]) for a, b in hops}
    modules_up = [(a, b) for a, b in modules if RANK[layer(b)] > RANK[layer(a)]]
    print(f"{Path(path).name}: exit {code}; {len(hops)} distinct function-to-function hops "
          f"between layers, {len(up)} of them back up; {len(modules)} distinct module pairs, "
          f"{len(modules_up)} of them back up")
    print("entering each layer: " + ", ".join(f"{k} {v}" for k, v in into.most_common()))
    for a, b in sorted(up):
        print(f"  up: {a} -> {b}")


if __name__ == "__main__":
    main(*sys.argv[1:])
