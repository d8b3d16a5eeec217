"""Baselines for the operator (:class:`~lotsim.envs.operator.ParkingOperatorEnv`): the run's
own rankings and a random choice, each a policy ``policy(observation, info) -> action``,
and the mean return of a policy over seeds.

``shortest``, ``nearest`` and ``priced`` take the best slot by the ranking of that name
(:data:`~lotsim.sim.settings.ASSIGNMENTS`), which the environment gives in ``info["best"]``:
``shortest`` plays what ``lotsim.run(prepared, assignment="shortest")`` plays, to the byte
on the quickstart and mixed lots (the tests check it), as long as a car finds its way to
its best slot in its probe: where that probe runs out in a busy aisle, a run's own
ranking goes on to look at the next best slots, where the operator's car asks again.
``random_slot(seed)`` takes one of the free slots the car can use at random. Each waits
when no car asks (``info`` without a car). They serve the PettingZoo agents as they are: the
choosing car's ``info`` is the operator's, and the others' masks (in their observations)
allow only waiting.

Examples
--------
>>> import lotsim, lotsim.envs
>>> env = lotsim.envs.ParkingOperatorEnv(lotsim.EXAMPLE)
>>> round(mean_return(env, shortest, seeds=[1]), 3)
-0.956
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np

from lotsim.errors import SettingsError

Policy = Callable[[dict, dict], int]
"""A policy: the action for an observation and its info."""


def _mask(observation, info: dict) -> np.ndarray:
    """The action mask: the operator's ``info``'s, or a PettingZoo agent's observation's."""
    return info["action_mask"] if "action_mask" in info else observation["action_mask"]


def _wait(observation, info: dict) -> int:
    return len(_mask(observation, info)) - 1


def _best(observation, info: dict, by: str) -> int:
    if "best" not in info:
        return _wait(observation, info)
    if by not in info["best"]:
        raise SettingsError("rankings", f"the {by} baseline reads info['best'][{by!r}]: "
                                        f"keep {by!r} in the environment's rankings")
    return info["best"][by]


def shortest(observation: dict, info: dict) -> int:
    """The free slot of least static time (the way in, the maneuver, and the way out for a
    car that will leave), ties by slot id."""
    return _best(observation, info, "shortest")


def nearest(observation: dict, info: dict) -> int:
    """The free slot nearest the car's gate in a straight line."""
    return _best(observation, info, "nearest")


def priced(observation: dict, info: dict) -> int:
    """The free slot of least static time plus the delay its maneuvers are expected to
    cause the cars passing it (:meth:`lotsim.sim.assignment.SlotAssigner.prices`)."""
    return _best(observation, info, "priced")


def random_slot(seed: int = 0) -> Policy:
    """A policy that takes one of the free slots the car can use (never waiting unless no
    car asks), uniformly, from its own generator seeded with ``seed``: the same calls give
    the same choices."""
    rng = np.random.default_rng(seed)

    def policy(observation: dict, info: dict) -> int:
        free = np.flatnonzero(_mask(observation, info)[:-1])
        return int(rng.choice(free)) if len(free) else _wait(observation, info)

    return policy


BASELINES: dict[str, Callable[[], Policy]] = {
    "shortest": lambda: shortest, "nearest": lambda: nearest, "priced": lambda: priced,
    "random": lambda: random_slot(0)}
"""Each baseline by name, as a maker of a fresh policy (the random one's generator anew)."""


def episode_return(env, policy: Policy, seed: int) -> float:
    """The return of one episode of ``env`` (a Gymnasium environment) reset with ``seed``
    and played by ``policy`` to its end."""
    obs, info = env.reset(seed=seed)
    total, over = 0.0, False
    while not over:
        obs, reward, terminated, truncated, info = env.step(policy(obs, info))
        total += reward
        over = terminated or truncated
    return float(total)


def mean_return(env, policy: Policy, seeds: Iterable[int] = range(5)) -> float:
    """The mean of :func:`episode_return` over ``seeds``, in the order given."""
    returns = [episode_return(env, policy, s) for s in seeds]
    return float(np.mean(returns))
