"""The baselines' returns in the operator environment (``lotsim/ParkingOperator-v0``):
docs/learning.md's table.

Run with (the ``learn`` extra installed)::

    python benchmarks/env_baselines.py                 # quickstart and mixed_lot, seeds 0-9
    python benchmarks/env_baselines.py --seeds 3
    python benchmarks/env_baselines.py --lots quickstart ring

For each lot and each baseline (:data:`lotsim.envs.baselines.BASELINES`: shortest,
nearest, priced, random) it plays the episodes of seeds 0 to N-1 with the default settings
and prints, as a Markdown table, the mean return (minus the car-minutes getting parked, and
10 minutes for each car that never parked) with the lowest and highest, and the mean of the cars
served and of the mean time to park [s] over those episodes. Every episode's run is checked
(``lotsim.check``). The quickstart lot's six cars are listed, so its seeds change nothing
but the random baseline's draws, whose generator goes on from one episode to the next.
Machine-independent: the same figures on any machine.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import lotsim  # noqa: E402
import lotsim.envs  # noqa: E402
from lotsim.envs import baselines  # noqa: E402
from lotsim.envs.episode import prepared_lot  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lots", nargs="+", default=["quickstart", "mixed_lot"],
                    help="shipped scenarios' names (default: quickstart mixed_lot)")
    ap.add_argument("--seeds", type=int, default=10, help="episodes per baseline (seeds 0 "
                                                          "to N-1; default 10)")
    args = ap.parse_args(argv)
    seeds = range(args.seeds)
    print("| lot | baseline | mean return (min – max) | served | mean time to park [s] |\n"
          "|---|---|---|---|---|")
    for name in args.lots:
        env = lotsim.envs.ParkingOperatorEnv(prepared_lot(name))
        for by, make in baselines.BASELINES.items():
            policy = make()
            returns, served, park = [], [], []
            for seed in seeds:
                returns.append(baselines.episode_return(env, policy, seed))
                rr = env.result()
                if not lotsim.check(rr).ok:
                    raise SystemExit(f"{name}, {by}, seed {seed}: the run does not check")
                m = rr.metrics()
                served.append(m["served"])
                park.append(m["mean_time_to_park"])
            print(f"| {name} | {by} | {statistics.mean(returns):.2f} ({min(returns):.2f} – "
                  f"{max(returns):.2f}) | {statistics.mean(served):.1f} of "
                  f"{m['vehicles']} | {statistics.mean(park):.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
