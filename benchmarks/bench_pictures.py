"""How long the still pictures take on a large input: a lot of 1000 slots, a timeline of
1000 vehicles.

Run with::

    python benchmarks/bench_pictures.py

Rows, each the best of three:

* ``draw_lot``: the picture of a lot with four aisles and 1000 perpendicular slots (30 %
  taken, seed 1) at the default 1200×900 with its graph, labels and a title, against the
  same lot cut to 100 slots, drawn the same way (baseline, same run): the ratio says how
  the drawing grows with the lot (10 is linear);
* ``timeline``: the timeline figure of 1000 vehicles (the quickstart's six cars repeated
  every 30 s) drawn on its canvas, against the same for 100 vehicles (baseline).

Targets (the bounds those tests asserted, on this 2-core machine): the 1000-slot lot under
2 s, the 1000-vehicle timeline under 5 s (matplotlib).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lotsim.io.scenario_yaml import parse_scenario  # noqa: E402
from lotsim.io.yamlnodes import parse_text  # noqa: E402
from lotsim.lot.build import build_lot  # noqa: E402
from lotsim.lot.model import DesignVehicle  # noqa: E402
from lotsim.roadmap.assemble import build_graph  # noqa: E402


def lot_text(per_row: int) -> str:
    """Four aisles, eight rows of ``per_row`` perpendicular slots [-]."""
    length = 2.0 + 2.5 * per_row + 2.0
    rows = "\n".join(
        f"    - {{aisle: a{k}, side: {side}, kind: perpendicular, count: {per_row},"
        f" slot_width: 2.5, slot_length: 5.0, start: 2.0, id_prefix: {side[0].upper()}{k}-}}"
        for k in range(4) for side in ("left", "right"))
    aisles = "\n".join(
        f"    - {{id: a{k}, centerline: [[0, {8.5 + 17 * k}], [{length}, {8.5 + 17 * k}]],"
        f" width: 7.0}}" for k in range(4))
    return f"""
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [{length}, 0], [{length}, 68], [0, 68]]
  aisles:
{aisles}
  rows:
{rows}
  entrances:
    - {{id: in, x: 1.0, y: 6.75, heading_deg: 0}}
  exits:
    - {{id: out, x: 5.0, y: 10.25, heading_deg: 180}}
  occupied: {{fraction: 0.3, seed: 1}}
"""


def best(fn, repeat: int = 3) -> float:
    """Shortest of ``repeat`` timings of ``fn()`` [s]."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def lot_graph(per_row: int):
    sc = parse_scenario(parse_text(lot_text(per_row), "bench.yaml"))
    return build_graph(build_lot(sc.lot, DesignVehicle.envelope(sc.vehicle_types)))


def timeline_doc(base: dict, n: int) -> dict:
    vehicles = []
    for k in range(n):
        v = json.loads(json.dumps(base["vehicles"][k % len(base["vehicles"])]))
        shift = 30.0 * (k // len(base["vehicles"]))
        v["id"], v["arrival"] = f"v{k}", v["arrival"] + shift
        v["samples"]["t"] = [t + shift for t in v["samples"]["t"]]
        vehicles.append(v)
    return dict(base, vehicles=vehicles)


def main() -> None:
    from lotsim.render import draw_lot

    big, small = lot_graph(125), lot_graph(13)  # 1000 and 104 slots
    t_big = best(lambda: draw_lot(big, show_graph=True, title="big"))
    t_small = best(lambda: draw_lot(small, show_graph=True, title="small"))
    print(f"draw_lot   {len(big.lot.slots):5d} slots {t_big:6.2f} s   "
          f"{len(small.lot.slots):4d} slots {t_small:6.2f} s   ratio {t_big / t_small:5.1f}"
          f"   (target < 2 s: {'met' if t_big < 2 else 'NOT met'})")

    try:
        import matplotlib  # noqa: F401

        from lotsim.render.plots import timeline_figure
    except ImportError:
        print("timeline   skipped: it needs matplotlib")
        return
    import lotsim

    result = lotsim.run(lotsim.prepare(ROOT / "scenarios" / "quickstart.yaml"))
    base = result.to_dict()

    def draw(n: int) -> None:
        timeline_figure(timeline_doc(base, n)).canvas.draw()

    t_big, t_small = best(lambda: draw(1000)), best(lambda: draw(100))
    print(f"timeline   1000 vehicles {t_big:6.2f} s    100 vehicles {t_small:6.2f} s   "
          f"ratio {t_big / t_small:5.1f}   (target < 5 s: {'met' if t_big < 5 else 'NOT met'})")


if __name__ == "__main__":
    main()
