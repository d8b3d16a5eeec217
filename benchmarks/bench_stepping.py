"""What stepping a run and driving it through disturbances cost: ``lotsim.Live`` on the
large lot (1040 slots).

Run with::

    python benchmarks/bench_stepping.py            # 5 pairs (about a minute)
    python benchmarks/bench_stepping.py --pairs 9

The case is ``bench_run.py``'s: 100 cars arriving at 600 an hour, staying (fixed seed),
HCA*. Each pair plans it twice, in turn: in one go (``Live.finish()``, which is what
``lotsim.run`` does) and stepped a second at a time with the run's state read at every
step (``Live.advance`` and ``Live.state``, as a policy or an environment steps it). It
prints the planning time of both (the time spent dealing with events, which is what
stepping could slow; reading the state is timed apart), their ratio pair by pair (min /
median / max), and that the two runs are the same. Then it drives the plan through late
starts (probability 0.1, up to 5 s) and through 10 stalls an hour of 60 s, and prints what
that costs against the planning, and the independent check of each.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import lotsim  # noqa: E402
from lotsim.io.result import result_dict  # noqa: E402
from lotsim.sim.execution import execute  # noqa: E402
from lotsim.sim.running import collector_tuned  # noqa: E402
from lotsim.traffic.demand import StreamSpec, TrafficSpec  # noqa: E402


def prepared_case() -> lotsim.PreparedLot:
    """The large lot with 100 cars at 600 an hour that stay."""
    p = lotsim.prepare(ROOT / "scenarios" / "large_lot.yaml")
    sc = p.scenario
    stream = StreamSpec(count=100, rate=600 / 3600, mix=((sc.vehicle_types[0].name, 1.0),),
                        entrances=tuple(p.lot_graph.entrances), seed=11)
    sc = dataclasses.replace(sc, traffic=TrafficSpec(streams=(stream,), patience=900.0))
    return dataclasses.replace(p, scenario=sc)


def whole(p) -> tuple[lotsim.RunResult, float]:
    with collector_tuned():
        rr = lotsim.Live(p).finish()
    return rr, rr.planning_time


def stepped(p, step: float = 1.0) -> tuple[lotsim.RunResult, float, float]:
    live = lotsim.Live(p)
    reading = 0.0
    t = 0.0
    with collector_tuned():
        while not live.done:
            t += step
            live.advance(t)
            clock = time.perf_counter()
            live.state()
            reading += time.perf_counter() - clock
        rr = live.finish()
    return rr, rr.planning_time, reading


def spread(xs: list[float], fmt: str = "{:.3f}") -> str:
    return " / ".join(fmt.format(x) for x in (min(xs), statistics.median(xs), max(xs)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pairs", type=int, default=5, help="pairs of runs (default 5)")
    args = ap.parse_args()
    p = prepared_case()
    whole(p)  # the lot's first run works out the edge motions the later ones drive
    one, many, ratio, reads, same = [], [], [], [], True
    for _ in range(args.pairs):
        a, ta = whole(p)
        b, tb, read = stepped(p)
        one.append(ta)
        many.append(tb)
        ratio.append(tb / ta)
        reads.append(read)
        same &= result_dict(a) == result_dict(b)
    print(f"100 cars on the large lot, HCA*, {args.pairs} pairs (min / median / max)")
    print(f"  planning in one go: {spread(one)} s")
    print(f"  planning stepped a second at a time: {spread(many)} s "
          f"(and reading the state at every step {spread(reads)} s)")
    print(f"  stepped / in one go, pair by pair: {spread(ratio)}; the same run: {same}")
    plan = a
    for name, spec in (("late starts p 0.1 up to 5 s", lotsim.Disturbances(
            late_probability=0.1, late_max=5.0)),
            ("10 stalls an hour of 60 s", lotsim.Disturbances(stall_rate=10.0,
                                                             stall_duration=(60.0, 60.0)))):
        times = []
        for _ in range(3):
            clock = time.perf_counter()
            ex = execute(plan, spec, memo=p.search_graphs)
            times.append(time.perf_counter() - clock)
        report = lotsim.check(ex)
        tp, te = plan.trip_figures(), ex.trip_figures()
        print(f"  driven through {name}: {spread(times)} s "
              f"({statistics.median(times) / statistics.median(one):.2f} x the planning); "
              f"median time to park {te['median_time_to_park']:.1f} s against "
              f"{tp['median_time_to_park']:.1f} s planned "
              f"({100 * (te['median_time_to_park'] / tp['median_time_to_park'] - 1):+.1f} %); "
              f"lotsim check: {'ok' if report.ok else report.violations[:1]}")


if __name__ == "__main__":
    main()
