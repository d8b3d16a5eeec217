"""Train a masked PPO as a lot's operator and score it against the baselines:
docs/learning.md's training example.

It needs the ``learn`` extra and, outside lotsim's own dependencies, PyTorch and
sb3-contrib (``MaskablePPO``). Install PyTorch first, pinned, so that pip takes the CPU
build rather than the much larger CUDA one, then sb3-contrib (it brings
stable-baselines3)::

    pip install 'lotsim[learn]'
    pip install torch==2.13.0        # or the CPU wheel from https://download.pytorch.org/whl/cpu
    pip install sb3-contrib

Run with::

    python benchmarks/train_operator.py                      # mixed_lot, 49152 steps, seed 0
    python benchmarks/train_operator.py --steps 4096 --lot quickstart

It trains ``MaskablePPO`` on ``gymnasium.make("lotsim/ParkingOperator-v0", scenario=LOT)``
for a fixed number of environment steps (one step per slot decision), in one process and
one thread (``torch.set_num_threads(1)``). The observation is flattened
(``FlattenObservation``) and the action mask is the one the environment gives in
``info["action_mask"]``, handed to the policy by sb3-contrib's ``ActionMasker``. Torch,
numpy and the environment are seeded from ``--seed``, so the same command trains the same
policy and prints the same returns on any machine; only the training time depends on the
machine.

Then it plays the trained policy (deterministic, masked) and each baseline of
:data:`lotsim.envs.baselines.BASELINES` on the evaluation seeds (``--eval-seeds``, default
100 to 109, seeds the training never drew on purpose) and prints, as a Markdown table, each
one's mean return with its standard deviation and lowest and highest, the cars served and
the mean time to park. Every evaluation episode's run must pass ``lotsim.check``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import gymnasium  # noqa: E402

import lotsim  # noqa: E402
import lotsim.envs  # noqa: E402
from lotsim.envs import baselines  # noqa: E402

try:
    import torch
    from sb3_contrib import MaskablePPO
    from sb3_contrib.common.wrappers import ActionMasker
    from stable_baselines3.common.utils import set_random_seed
except ImportError as exc:  # pragma: no cover - an optional install
    raise SystemExit(f"{exc}: this example needs PyTorch and sb3-contrib "
                     f"(pip install torch==2.13.0 sb3-contrib)") from None


class InfoMask(gymnasium.Wrapper):
    """Keeps the action mask of the last ``info`` (``info["action_mask"]``), as booleans,
    and counts the episodes played to their end."""

    episodes = 0

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        self.mask = info["action_mask"].astype(bool)
        return obs, info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        self.mask = info["action_mask"].astype(bool)
        self.episodes += terminated or truncated
        return obs, reward, terminated, truncated, info


def make_env(lot: str) -> tuple[gymnasium.Env, InfoMask]:
    """The operator on ``lot``, its observation flattened and its mask from ``info``, and
    the wrapper that keeps the mask."""
    base = InfoMask(gymnasium.make("lotsim/ParkingOperator-v0", scenario=lot))
    masked = ActionMasker(gymnasium.wrappers.FlattenObservation(base), lambda env: base.mask)
    return masked, base


def play(env, policy, seed: int) -> tuple[float, dict]:
    """One episode of ``policy`` on ``env`` from ``seed``: its return and its run's metrics,
    the run checked."""
    total = baselines.episode_return(env, policy, seed)
    result = env.unwrapped.result()
    report = lotsim.check(result)
    assert report.ok, f"seed {seed}: the run does not check: {report}"
    return total, result.metrics()


def row(name: str, plays: list[tuple[float, dict]]) -> str:
    returns = [r for r, _ in plays]
    served = statistics.mean(m["served"] for _, m in plays)
    park = statistics.mean(m["mean_time_to_park"] for _, m in plays)
    return (f"| {name} | {statistics.mean(returns):.2f} ± {statistics.pstdev(returns):.2f} "
            f"({min(returns):.2f} – {max(returns):.2f}) | {served:.1f} of "
            f"{plays[0][1]['vehicles']} | {park:.1f} |")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lot", default="mixed_lot", help="a shipped scenario's name "
                                                      "(default: mixed_lot)")
    ap.add_argument("--steps", type=int, default=49152,
                    help="environment steps (slot decisions) to train for (default 49152)")
    ap.add_argument("--seed", type=int, default=0, help="torch, numpy and env seed")
    ap.add_argument("--eval-seeds", type=int, nargs=2, default=(100, 110),
                    metavar=("FIRST", "END"), help="evaluate on seeds FIRST to END-1 "
                                                   "(default 100 110)")
    args = ap.parse_args(argv)
    torch.set_num_threads(1)
    set_random_seed(args.seed)  # Python's, numpy's and torch's generators

    env, counted = make_env(args.lot)
    model = MaskablePPO("MlpPolicy", env, n_steps=1024, batch_size=128, n_epochs=10,
                        gamma=0.99, learning_rate=3e-4, ent_coef=0.01, seed=args.seed,
                        device="cpu", verbose=0)
    start = time.perf_counter()
    model.learn(total_timesteps=args.steps)
    took = time.perf_counter() - start
    print(f"trained MaskablePPO on {args.lot}: {model.num_timesteps} steps "
          f"({counted.episodes} episodes) in {took:.0f} s, seed {args.seed}, torch "
          f"{torch.__version__}\n")

    seeds = range(*args.eval_seeds)
    scored, _ = make_env(args.lot)

    def trained(obs, info):
        action, _ = model.predict(obs, action_masks=info["action_mask"].astype(bool),
                                  deterministic=True)
        return int(action)

    print(f"returns over seeds {seeds.start}–{seeds.stop - 1} (every run checked):\n")
    print("| policy | mean return ± sd (min – max) | served | mean time to park [s] |\n"
          "|---|---|---|---|")
    print(row("MaskablePPO", [play(scored, trained, s) for s in seeds]))
    plain = lotsim.envs.ParkingOperatorEnv(args.lot)
    for name, make in baselines.BASELINES.items():
        policy = make()
        plays = [play(plain, policy, s) for s in seeds]
        mean = baselines.mean_return(plain, make(), seeds)
        assert abs(mean - statistics.mean(r for r, _ in plays)) < 1e-9
        print(row(name, plays))
    return 0


if __name__ == "__main__":
    sys.exit(main())
