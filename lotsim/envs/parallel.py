"""The parking operator's run as a PettingZoo ``ParallelEnv`` whose agents are the cars
(docs/learning.md)."""

from __future__ import annotations

import os

import numpy as np

from lotsim.envs import LearnUnavailable

try:
    from pettingzoo import ParallelEnv
except ImportError:
    raise LearnUnavailable("lotsim.envs.parallel needs pettingzoo: pip install "
                           "'lotsim[learn]'") from None
from gymnasium import spaces

from lotsim.core.checks import choice_problem, replace
from lotsim.envs.episode import (
    Episode,
    LotIndex,
    OperatorSettings,
    features,
    mask,
    prepared_lot,
    run_settings,
)
from lotsim.envs.operator import FRAME_SIZE, frame
from lotsim.errors import SettingsError
from lotsim.scenario import GifSettings, Scenario
from lotsim.sim.preparation import PreparedLot
from lotsim.sim.results import RunResult
from lotsim.sim.settings import MAX_SEED, RunSettings
from lotsim.traffic.demand import arrivals

UNTIL = {"parked": ("queued", "driving", "parking"),
         "departed": ("queued", "driving", "parking", "parked", "leaving")}
"""How long a car is an agent: the phases (:data:`lotsim.sim.live.PHASES`) it is live in,
from its arrival until it parks, or until it has left again."""


class ParkingParallelEnv(ParallelEnv):
    """The cars of a lot's traffic as agents; each car that waits for a slot chooses it.

    The run is :class:`~lotsim.envs.operator.ParkingOperatorEnv`'s: one step per choice,
    its scenario, settings and seeds alike. A car is an agent from its arrival until it
    parks (``until="parked"``) or leaves the lot again (``"departed"``), or is turned away;
    it is never an agent again. At each step one car chooses (the one whose
    ``action_mask`` marks slots); the others' actions are ignored (their masks allow only
    waiting), and a choosing car given no action waits. A car that came and was settled
    between two choices, never live at a step (turned away on arrival, or after its
    patience in a full lot's queue), is no agent.

    Each agent's observation is ``{"observation": Box(0, 1), "action_mask": int8}``: the
    features of :func:`~lotsim.envs.episode.features` (its own type, gate and, when it
    chooses, its slots' static times) flattened in the order of
    :meth:`~lotsim.envs.episode.LotIndex.sizes`. Its reward is its own cost, given at the
    step it is settled: minus the minutes from its arrival to standing in its slot, or minus
    ``rejected_cost`` if it never parks; and minus ``refused_cost`` for an action the lot
    could not honour (it then waits). The rewards of all agents add up to the Gymnasium
    environment's.

    Parameters
    ----------
    scenario, settings, render_mode, operator, frame_size, **overrides
        As :class:`~lotsim.envs.operator.ParkingOperatorEnv`'s.
    until : {"parked", "departed"}, keyword-only
        How long a car is an agent.

    Examples
    --------
    >>> import lotsim, lotsim.envs
    >>> env = lotsim.envs.parallel_env(lotsim.EXAMPLE)
    >>> obs, infos = env.reset(seed=1)
    >>> env.agents, infos["ada"]["best"]["shortest"]
    (['ada'], 0)
    >>> obs, rewards, terminations, truncations, infos = env.step({"ada": 0})
    >>> env.agents, terminations
    (['ada', 'bob'], {'ada': False, 'bob': False})
    """

    metadata = {"name": "lotsim_parking_v0", "render_modes": ["rgb_array"], "render_fps": 4,
                "is_parallelizable": True}

    def __init__(self, scenario: PreparedLot | Scenario | str | os.PathLike = "quickstart",
                 settings: RunSettings | None = None, *, render_mode: str | None = None,
                 until: str = "parked", operator: OperatorSettings | None = None,
                 frame_size: tuple[int, int] = FRAME_SIZE, **overrides) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise SettingsError("render_mode", f"expected 'rgb_array' or None, found "
                                               f"{render_mode!r}")
        problem = choice_problem(until, tuple(UNTIL))
        if problem is not None:
            raise SettingsError("until", problem)
        self.prepared = prepared_lot(scenario)
        self.settings = run_settings(self.prepared, settings)
        if operator is not None and not isinstance(operator, OperatorSettings):
            raise SettingsError("operator", f"expected OperatorSettings, found "
                                            f"{type(operator).__name__}")
        self.operator = replace(operator or OperatorSettings(), overrides)
        GifSettings(size=frame_size)
        self.render_mode, self.frame_size, self.until = render_mode, tuple(frame_size), until
        self.index = LotIndex.of(self.prepared)
        sc = self.prepared.scenario
        self.possible_agents = [a.id for a in arrivals(sc.traffic, sc.seed)]
        self.agents: list[str] = []
        n = sum(self.index.sizes().values())
        self._spaces = {a: (spaces.Dict({
            "observation": spaces.Box(0.0, 1.0, (n,), dtype=np.float32),
            "action_mask": spaces.Box(0, 1, (self.index.wait + 1,), dtype=np.int8)}),
            spaces.Discrete(self.index.wait + 1)) for a in self.possible_agents}
        self.episode: Episode | None = None
        self._rng: np.random.Generator | None = None
        self._gone: set[str] = set()  # cars that were agents and are no more

    def observation_space(self, agent: str) -> spaces.Dict:
        return self._space(agent)[0]

    def action_space(self, agent: str) -> spaces.Discrete:
        return self._space(agent)[1]

    def _space(self, agent: str):
        if agent not in self._spaces:
            raise SettingsError("agent", f"expected a car of the traffic, found {agent!r}")
        return self._spaces[agent]

    def reset(self, seed: int | None = None, options: dict | None = None):
        """Start an episode (seeds as :meth:`ParkingOperatorEnv.reset`'s); ``options`` are
        not used."""
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        elif self._rng is None:
            seed = self.prepared.scenario.seed
            self._rng = np.random.default_rng(seed)
        else:
            seed = int(self._rng.integers(MAX_SEED))
        self.episode = Episode(self.prepared, self.settings, self.operator, seed,
                               index=self.index)
        self._gone = set()
        state = self.episode.state()
        self.agents = self._live(state)
        return ({a: self._observe(a, state) for a in self.agents},
                {a: self._info(a) for a in self.agents})

    def step(self, actions: dict):
        """The choosing car's action taken, the run played on to the next choice."""
        episode = self._require()
        if episode.done:
            raise SettingsError("actions", "the episode is over: reset it")
        car = episode.request.car
        refused = episode.act(actions.get(car, self.index.wait))
        state = episode.state()
        costs = episode.settle(state)
        before = list(self.agents)
        live = [] if episode.done else self._live(state)
        keys = before + [a for a in live if a not in before]
        rewards = {a: -costs.get(a, 0.0) for a in keys}
        if refused is not None and car in rewards:
            rewards[car] -= self.operator.refused_cost
        ended = episode.done and not episode.truncated
        terminations = {a: ended or (a not in live and not episode.truncated) for a in keys}
        truncations = {a: episode.truncated for a in keys}
        observations = {a: self._observe(a, state) for a in keys}
        infos = {a: self._info(a, refused if a == car else None) for a in keys}
        self._gone.update(a for a in keys if a not in live)
        self.agents = live
        return observations, rewards, terminations, truncations, infos

    def render(self):
        """The lot now as an RGB array (``render_mode="rgb_array"``), else None."""
        if self.render_mode != "rgb_array":
            return None
        return frame(self._require(), self.frame_size)

    def result(self) -> RunResult:
        """The episode's run (:meth:`~lotsim.envs.episode.Episode.result`)."""
        return self._require().result()

    def close(self) -> None:
        """Nothing to let go of."""

    def _require(self) -> Episode:
        if self.episode is None:
            raise SettingsError("env", "no episode yet: call reset() first")
        return self.episode

    def _live(self, state: dict) -> list[str]:
        """The agents now: the cars in the phases :data:`UNTIL` names, not gone before."""
        phases = UNTIL[self.until]
        return [c["id"] for c in state["cars"]
                if c["phase"] in phases and c["id"] not in self._gone]

    def _chooses(self, agent: str) -> bool:
        episode = self._require()
        return not episode.done and episode.request.car == agent

    def _observe(self, agent: str, state: dict) -> dict[str, np.ndarray]:
        episode = self._require()
        request = episode.request if self._chooses(agent) else None
        car = next(c for c in state["cars"] if c["id"] == agent)
        seen = features(self.index, self.operator, state, episode.horizon, car, request)
        return {"observation": np.concatenate([seen[k] for k in self.index.sizes()]),
                "action_mask": mask(self.index, request)}

    def _info(self, agent: str, refused: str | None = None) -> dict:
        """The choosing car's is the Gymnasium environment's; the others' are empty, but
        for ``refused``: what the car's last action asked that the lot could not give."""
        out = self._require().info() if self._chooses(agent) else {}
        if refused is not None:
            out["refused"] = refused
        return out
