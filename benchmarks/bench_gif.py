"""GIF rendering speed: 1000 frames of 800×600 with 100 vehicles (target: under 15 s).

Run with::

    python benchmarks/bench_gif.py                       # plans the 100 cars first (~30 s)
    python benchmarks/bench_gif.py --result runs/large-lot/result.json   # reuse a run

The vehicles are the 100 cars of ``scenarios/large_lot.yaml`` (1040 slots, shipped seed),
planned by ``lotsim run`` unless a result is given. Cases, each in its own process so that
its peak memory is its own:

* ``run``: the whole run (every car arrives, drives in and parks) in 1000 frames;
* ``all moving``: the same cars shifted in time so that all 100 enter at once, 1000 frames
  over their first 40 s: 100 moving cars, trails and target slots in every frame;
* ``3000 frames``: the ``run`` case with three times the frames, to show that memory does
  not grow with the length of the GIF (``--quick`` skips it);
* baseline, measured in the same run: the same ``all moving`` frames handed to imageio as
  RGB arrays, which makes the writer quantise every frame (100 frames, scaled to 1000).

Prints seconds, frames per second, file size and peak memory per case, and the ratio of
the baseline's time to lotsim's.
"""

from __future__ import annotations

import argparse
import copy
import json
import multiprocessing as mp
import resource
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import imageio.v3 as iio  # noqa: E402
import numpy as np  # noqa: E402

from lotsim.io.result import result_dict  # noqa: E402
from lotsim.io.scenario_yaml import load_scenario  # noqa: E402
from lotsim.render.animation import GifRenderer, GifSettings, write_gif  # noqa: E402
from lotsim.render.replay import Replay  # noqa: E402
from lotsim.sim.running import simulate  # noqa: E402
from lotsim.sim.settings import RunSettings  # noqa: E402


def peak_mb() -> float:
    """Peak resident memory of this process so far [MB] (Linux reports kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def all_at_once(doc: dict) -> dict:
    """The run with every vehicle's samples shifted so that it enters at t = 0."""
    out = copy.deepcopy(doc)
    for v in out["vehicles"]:
        s = v["samples"]
        if s["t"]:
            shift = s["t"][0]
            s["t"] = [t - shift for t in s["t"]]
            v["arrival"] = 0.0
    return out


def settings_for(doc: dict, frames: int, span: float | None = None) -> GifSettings:
    r = Replay(doc)
    span = (r.end - r.start) if span is None else span
    return GifSettings(fps=20, speed=span * 20 / frames, size=(800, 600), start=r.start,
                       end=r.start + span, max_frames=frames)


def lotsim_case(doc: dict, frames: int, span: float | None, out) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        info = write_gif(doc, Path(tmp) / "a.gif", settings_for(doc, frames, span))
        wall = time.perf_counter() - t
        out.put({"wall": wall, "frames": info.frames, "mb": info.bytes / 1e6,
                 "peak_mb": peak_mb()})


def rgb_case(doc: dict, frames: int, span: float, out) -> None:
    settings = settings_for(doc, frames, span)
    renderer = GifRenderer(doc, settings)
    times = settings.start + np.arange(frames) * settings.speed / settings.fps
    t = time.perf_counter()
    rgb = np.stack([np.asarray(renderer.frame(float(x)).convert("RGB")) for x in times])
    with tempfile.TemporaryDirectory() as tmp:
        iio.imwrite(Path(tmp) / "a.gif", rgb, loop=0, duration=1000 / settings.fps)
        size = (Path(tmp) / "a.gif").stat().st_size
    out.put({"wall": time.perf_counter() - t, "frames": frames, "mb": size / 1e6,
             "peak_mb": peak_mb()})


def in_child(fn, *args) -> dict:
    ctx = mp.get_context("fork")
    q = ctx.Queue()
    p = ctx.Process(target=fn, args=(*args, q))
    p.start()
    res = q.get()
    p.join()
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--result", type=Path, help="a result.json of the large lot to reuse")
    ap.add_argument("--quick", action="store_true", help="skip the 3000-frame case")
    args = ap.parse_args()
    if args.result:
        doc = json.loads(args.result.read_text())
    else:
        t = time.perf_counter()
        rr = simulate(load_scenario(ROOT / "scenarios" / "large_lot.yaml"), RunSettings())
        doc = json.loads(json.dumps(result_dict(rr)))
        print(f"planned the large lot's {len(doc['vehicles'])} cars in "
              f"{time.perf_counter() - t:.1f} s")
    n = len(doc["vehicles"])
    moving = all_at_once(doc)
    rows = [("run", in_child(lotsim_case, doc, 1000, None)),
            ("all moving", in_child(lotsim_case, moving, 1000, 40.0))]
    if not args.quick:
        rows.append(("3000 frames", in_child(lotsim_case, doc, 3000, None)))
    base = in_child(rgb_case, moving, 100, 4.0)
    base_1000 = base["wall"] * 10
    print(f"\n{n} vehicles, 800x600, fps 20")
    print(f"{'case':14} {'frames':>6} {'seconds':>8} {'frames/s':>9} {'file MB':>8} "
          f"{'peak MB':>8}")
    for name, r in rows:
        print(f"{name:14} {r['frames']:6d} {r['wall']:8.2f} {r['frames'] / r['wall']:9.1f} "
              f"{r['mb']:8.2f} {r['peak_mb']:8.0f}")
    print(f"{'RGB baseline':14} {base['frames']:6d} {base['wall']:8.2f} "
          f"{base['frames'] / base['wall']:9.1f} {base['mb']:8.2f} {base['peak_mb']:8.0f}"
          f"   (x10 = {base_1000:.1f} s for 1000 frames)")
    worst = max(r["wall"] for name, r in rows if name != "3000 frames")
    print(f"\ntarget: 1000 frames in under 15 s: {'met' if worst < 15 else 'NOT met'} "
          f"(slowest case {worst:.1f} s)")
    moving_wall = dict(rows)["all moving"]["wall"]
    print(f"palette frames vs RGB frames (all moving, 1000 frames): "
          f"{base_1000 / moving_wall:.1f}x faster")


if __name__ == "__main__":
    main()
