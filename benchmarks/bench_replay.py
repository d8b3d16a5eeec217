"""The HTML replay of a big run: file size, load time and frame rate in headless Chromium.

Run with::

    python benchmarks/bench_replay.py                    # plans 1000 cars first (~5-10 min)
    python benchmarks/bench_replay.py --cars 100         # the large lot's 100 cars (~30 s)
    python benchmarks/bench_replay.py --result runs/x/result.json   # reuse a run

The run is the large lot's (``scenarios/large_lot.yaml``, 1040 slots): with ``--cars
1000``, the 1000-car case of ``bench_run.py`` (1200 an hour, each staying 10 to 30
minutes, seed 11), so slots are freed and reused; with fewer cars, the same stream cut
short. The result is kept in ``runs/bench-replay/`` and reused by the next run of this
script with the same ``--cars``.

Prints, for the replay written by ``lotsim.render_html``:

* its size, against a baseline measured in the same run: the same page with every sample
  kept (no thinning), and the result.json it was made from;
* the time to write it;
* load time in headless Chromium (``--window-size 1280x800``): from navigation start to
  the first frame drawn, as the page measures it (``performance.now()``), median of
  ``--repeat`` loads;
* frame rate while playing at ×4 and at ×60 around the busiest moment of the run (most
  cars driving), all of the lot in view and zoomed in 4×: frames drawn per second over
  ``--seconds`` of wall time (the page draws once per animation frame while playing, so
  this is also requestAnimationFrame's rate, at most the display's 60 Hz);
* the time one frame takes to draw (cars, trails, counters, timeline cursor), mean of 200
  frames drawn back to back.

Targets: the 1000-car run loads in under 3 s and plays at 30 fps or better.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))  # the DevTools client the browser tests use

from chromium import Chromium  # noqa: E402
from lotsim.io.result import result_dict, write_json  # noqa: E402
from lotsim.io.scenario_yaml import load_scenario  # noqa: E402
from lotsim.render import html as html_mod  # noqa: E402
from lotsim.render.replay import Replay  # noqa: E402
from lotsim.scenario import HtmlSettings  # noqa: E402
from lotsim.sim.preparation import prepare_graph  # noqa: E402
from lotsim.sim.running import simulate  # noqa: E402
from lotsim.sim.settings import RunSettings  # noqa: E402
from lotsim.traffic.demand import StreamSpec, TrafficSpec, UniformDwell  # noqa: E402


def make_result(cars: int) -> Path:
    path = ROOT / "runs" / "bench-replay" / f"result-{cars}.json"
    if path.is_file():
        print(f"reusing {path.relative_to(ROOT)}")
        return path
    sc = load_scenario(ROOT / "scenarios" / "large_lot.yaml")
    lg = prepare_graph(sc)
    stream = StreamSpec(count=cars, rate=1200 / 3600, mix=((sc.vehicle_types[0].name, 1.0),),
                        entrances=tuple(lg.entrances), dwell=UniformDwell(600.0, 1800.0), seed=11)
    sc = dataclasses.replace(sc, traffic=TrafficSpec(streams=(stream,), patience=900.0))
    t = time.perf_counter()
    rr = simulate(sc, RunSettings(planner="hca"), lot_graph=lg)
    print(f"planned {cars} cars in {time.perf_counter() - t:.0f} s")
    path.parent.mkdir(parents=True, exist_ok=True)
    write_json(result_dict(rr), path)
    return path


def page_bytes(doc: dict, *, thin: bool) -> int:
    if thin:
        page, _, _ = html_mod.html_page(doc, HtmlSettings())
        return len(page.encode())
    real = html_mod.thin
    html_mod.thin = lambda t, *a, **k: np.ones(len(t), dtype=bool)
    try:
        page, _, _ = html_mod.html_page(doc, HtmlSettings())
    finally:
        html_mod.thin = real
    return len(page.encode())


FPS = """new Promise(done => {
  const n0 = lotsimReplay.frames(), t0 = performance.now();
  setTimeout(() => done((lotsimReplay.frames() - n0) * 1000 / (performance.now() - t0)),
             %d);
})"""

DRAW = """(() => {
  const t = lotsimReplay.time(), t0 = performance.now();
  for (let k = 0; k < 200; k++) lotsimReplay.setTime(t + 0.05 * k);
  return (performance.now() - t0) / 200;
})()"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cars", type=int, default=1000)
    ap.add_argument("--result", type=Path, help="a result.json to use instead")
    ap.add_argument("--repeat", type=int, default=3, help="loads timed (3)")
    ap.add_argument("--seconds", type=float, default=5.0, help="wall time per fps figure")
    args = ap.parse_args()
    path = args.result or make_result(args.cars)
    doc = json.loads(path.read_text())
    replay = Replay(doc)
    print(f"{path}: {len(doc['vehicles'])} vehicles, {replay.end - replay.start:.0f} s of run")

    out = Path(tempfile.mkdtemp(prefix="bench-replay-")) / "replay.html"
    t = time.perf_counter()
    info = html_mod.write_html(doc, out)
    written = time.perf_counter() - t
    full = page_bytes(doc, thin=False)
    print(f"replay.html: {info.bytes / 1e6:.2f} MB, written in {written:.1f} s; "
          f"{info.kept} of {info.samples} samples kept ({100 * info.kept / info.samples:.1f} %)")
    print(f"  baseline, every sample kept: {full / 1e6:.2f} MB (thinning: "
          f"{full / info.bytes:.1f}x smaller); result.json {path.stat().st_size / 1e6:.1f} MB")

    # the busiest moment: most cars driving
    times = np.linspace(replay.start, replay.end, 400)
    busy = max(times, key=lambda t: replay.counts(float(t))["driving"])
    with Chromium((1280, 800), timeout=120) as b:
        loads = []
        for _ in range(args.repeat):
            b.open(out.as_uri(), wait="window.lotsimReplay && lotsimReplay.readyAt > 0")
            loads.append(b.evaluate("lotsimReplay.readyAt") / 1000)
        assert not b.errors(), b.errors()
        print(f"load (navigation start to first frame): median {statistics.median(loads):.2f} s "
              f"of {args.repeat} ({', '.join(f'{v:.2f}' for v in loads)}); target < 3 s")
        counts = b.evaluate(f"lotsimReplay.setTime({busy}); lotsimReplay.counts()")
        print(f"busiest moment t = {busy:.0f} s: {counts['driving']} driving, "
              f"{counts['parked']} parked, {counts['waiting']} waiting")
        ms = int(args.seconds * 1000)
        for label, zoom in (("whole lot", None), ("zoomed in 4x", 4)):
            if zoom:
                b.send("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": 640, "y": 360,
                                                    "deltaX": 0, "deltaY": -924})
            for speed in (4, 60):
                b.evaluate(f"lotsimReplay.setTime({busy}); "
                           f"document.getElementById('speed').value = '{speed}'; "
                           "document.getElementById('speed').dispatchEvent(new Event('change'));"
                           " lotsimReplay.play(); 1")
                fps = b.evaluate(FPS % ms)
                b.evaluate("lotsimReplay.pause()")
                print(f"  {label}, x{speed}: {fps:.1f} frames per second over "
                      f"{args.seconds:g} s; target >= 30")
            b.evaluate(f"lotsimReplay.setTime({busy})")
            print(f"  {label}: one frame drawn in {b.evaluate(DRAW):.1f} ms (mean of 200)")
        assert not b.errors(), b.errors()


if __name__ == "__main__":
    main()
