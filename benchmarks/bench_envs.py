"""Decisions per second of the operator environment (``lotsim/ParkingOperator-v0``,
docs/learning.md), against the stepped run under it.

Run with (the ``learn`` extra installed)::

    python benchmarks/bench_envs.py              # quickstart and surface364, 3 rounds
    python benchmarks/bench_envs.py --rounds 5
    python benchmarks/bench_envs.py --lots quickstart mixed_lot

Each lot is prepared first (from the on-disk cache when it can; not timed) and played once
untimed (its first run works out the edge motions later runs reuse). Then each round plays
the same episodes (seeds 0, 1, 2) four ways, in turn: the environment stepped by the
shortest baseline, by the random baseline, by the shortest baseline with ``info["best"]``
holding that ranking alone (``rankings=("shortest",)``), and the bare stepped run
(``lotsim.Live(policy=lotsim.ASK)``) answering each choice with the slot the shortest
baseline takes, which is the planning every decision costs whatever reads it. It prints,
as a Markdown table, the decisions per CPU second of each (the process's time: the stepping
is one thread, and a busy machine slows its wall clock, not this; median of the rounds,
with their min and max) and the environment's rate over the bare run's: what the
features, the mask, the rankings and the rewards cost on top of the planning.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import lotsim  # noqa: E402
import lotsim.envs  # noqa: E402
from lotsim.envs import baselines  # noqa: E402
from lotsim.envs.episode import prepared_lot, seeds_traffic  # noqa: E402

SEEDS = (0, 1, 2)


def env_episodes(env, policy_of, seeds) -> tuple[int, float]:
    """Decisions and CPU seconds of playing ``seeds`` in ``env``, a fresh policy each."""
    decisions, clock = 0, time.process_time()
    for seed in seeds:
        policy = policy_of()
        obs, info = env.reset(seed=seed)
        over = False
        while not over:
            obs, _, terminated, truncated, info = env.step(policy(obs, info))
            decisions += 1
            over = terminated or truncated
    return decisions, time.process_time() - clock


def bare_episodes(prepared, seeds) -> tuple[int, float]:
    """The same episodes stepped bare, each choice answered with the best slot: decisions
    and CPU seconds."""
    decisions, clock = 0, time.process_time()
    for seed in seeds:
        settings = lotsim.RunSettings(seed=seed if seeds_traffic(prepared) else None)
        live = lotsim.Live(prepared, settings, policy=lotsim.ASK)
        while (request := live.next_decision()) is not None:
            live.decide(request.ranked("shortest")[0])
            decisions += 1
        live.finish()
    return decisions, time.process_time() - clock


def spread(rates: list[float]) -> str:
    return f"{statistics.median(rates):.1f} ({min(rates):.1f}–{max(rates):.1f})"


WAYS = ("env, shortest", "env, random", "env, no rankings", "bare run")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lots", nargs="+", default=["quickstart", "surface364"],
                    help="shipped scenarios' names (default: quickstart surface364)")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    print(f"decisions per CPU second, median of {args.rounds} rounds (min–max), seeds "
          f"{', '.join(map(str, SEEDS))}\n")
    print(f"| lot | slots | decisions | {' | '.join(WAYS)} | env / bare |")
    print("|---|---|---|" + "---|" * (len(WAYS) + 1))
    for name in args.lots:
        prepared = prepared_lot(name)
        env = lotsim.envs.ParkingOperatorEnv(prepared)
        plain = lotsim.envs.ParkingOperatorEnv(prepared, rankings=("shortest",))
        env_episodes(env, lambda: baselines.shortest, SEEDS)  # the motions, worked out once
        rates: dict[str, list[float]] = {w: [] for w in WAYS}
        for _ in range(args.rounds):
            n, s = env_episodes(env, lambda: baselines.shortest, SEEDS)
            rates["env, shortest"].append(n / s)
            m, s = env_episodes(env, lambda: baselines.random_slot(0), SEEDS)
            rates["env, random"].append(m / s)
            m, s = env_episodes(plain, lambda: baselines.shortest, SEEDS)
            rates["env, no rankings"].append(m / s)
            k, s = bare_episodes(prepared, SEEDS)
            rates["bare run"].append(k / s)
            assert k == n, "the bare run took other decisions than the environment"
        ratio = statistics.median(rates["env, shortest"]) / statistics.median(rates["bare run"])
        print(f"| {name} | {len(env.slots)} | {n} | "
              + " | ".join(spread(rates[w]) for w in WAYS) + f" | {ratio:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
