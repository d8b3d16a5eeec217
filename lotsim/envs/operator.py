"""``lotsim/ParkingOperator-v0``: the Gymnasium environment of a lot's operator, who
chooses the slot of each car that comes, one step per choice (docs/learning.md)."""

from __future__ import annotations

import os

import gymnasium
import numpy as np
from gymnasium import spaces

from lotsim.core.checks import replace
from lotsim.envs.episode import (
    Episode,
    LotIndex,
    OperatorSettings,
    features,
    prepared_lot,
    run_settings,
)
from lotsim.errors import SettingsError
from lotsim.scenario import GifSettings, Scenario
from lotsim.sim.preparation import PreparedLot
from lotsim.sim.results import RunResult
from lotsim.sim.settings import MAX_SEED, RunSettings

FRAME_SIZE = (480, 320)
"""Pixels of a frame (:meth:`ParkingOperatorEnv.render`), width by height."""


def observation_space(index: LotIndex) -> spaces.Dict:
    """The features (:func:`~lotsim.envs.episode.features`) as a Gymnasium space: a
    ``Box(0, 1)`` of ``float32`` for each."""
    return spaces.Dict({k: spaces.Box(0.0, 1.0, (n,), dtype=np.float32)
                        for k, n in index.sizes().items()})


def frame(episode: Episode, size: tuple[int, int]) -> np.ndarray:
    """The lot at the episode's run time as an RGB array (height, width, 3) of ``uint8``: the
    GIF's frame (:class:`~lotsim.render.animation.GifRenderer`) of the run so far
    (:meth:`~lotsim.sim.live.Live.snapshot`), the whole lot in view."""
    from lotsim.io.result import result_dict
    from lotsim.render.animation import GifRenderer

    doc = result_dict(episode.live.snapshot())  # the result itself once the run has ended
    renderer = GifRenderer(doc, GifSettings(size=size, view="lot"))
    t = episode.live.now
    return np.asarray(renderer.frame(max(t, 0.0)).convert("RGB"), dtype=np.uint8)


class ParkingOperatorEnv(gymnasium.Env):
    """A lot's operator chooses the slot of each car at a gate: one step per choice.

    Each episode is a run of the lot (:class:`~lotsim.sim.live.Live`), its traffic drawn
    from the episode's seed; each step answers the choice of one car, then plays the run
    on to the next car that asks.

    Parameters
    ----------
    scenario : PreparedLot, Scenario, path, YAML text or a shipped scenario's name
        The lot and its traffic (``"quickstart"``, ``"mixed_lot"``, ...:
        :func:`~lotsim.envs.episode.shipped_scenarios`), prepared once (from the on-disk
        cache when it can).
    settings : RunSettings, optional
        How to plan (planner, window, ...; cars planned as they come).
    render_mode : {"rgb_array"} or None, keyword-only
    operator : OperatorSettings, optional, keyword-only
        The horizon, the features' caps and the costs
        (:class:`~lotsim.envs.episode.OperatorSettings`).
    frame_size : (int, int), keyword-only
        Pixels of a frame, width by height.
    **overrides
        Fields of :class:`~lotsim.envs.episode.OperatorSettings` to change
        (``horizon=600``, ``refused="raise"``, ...).

    Spaces
    ------
    Action: ``Discrete(n_slots + 1)``: the slot (by its index in ``lot.slots``, the
    environment's :attr:`slots`) the car tries, or ``n_slots`` to let it wait (it asks
    again ``settings.retry`` seconds later, within its patience).
    ``info["action_mask"]`` (``int8``) marks the free slots its type can use, and waiting;
    :meth:`action_masks` gives it as booleans. Observation: a ``Dict`` of ``Box(0, 1)``
    (:func:`~lotsim.envs.episode.features`): ``occupancy``, ``vehicle`` (one-hot),
    ``entrance`` (one-hot), ``static_time``, ``queues``, ``aisles`` and ``time``.

    Reward
    ------
    Minus the minutes each car took from its arrival to standing in its slot, given at the
    step in which it came to stand there, and minus ``rejected_cost`` minutes (10) for each
    car that never parked, at the step it was turned away (or the last). An episode's
    return is so minus the traffic's car-minutes getting parked (the cars that parked times
    ``metrics()["mean_time_to_park"]``, over 60) and ``rejected_cost`` for each car that
    never parked. Waiting costs through the time to park it adds. An action the lot cannot
    honour (a masked slot) costs ``refused_cost`` minutes (1) more and the car waits;
    ``info["refused"]`` names the slot and why (``refused="raise"`` raises
    :class:`~lotsim.errors.DecisionError` instead).

    Episodes end when the run does (terminated), or at the first choice past the
    ``horizon`` (truncated). :meth:`result` is the episode's run, which
    :func:`lotsim.check` verifies. ``reset(seed=s)`` plays the run that
    ``lotsim.run(prepared, settings)`` plays with ``seed=s`` where the scenario's traffic
    is a stream drawn by the run's seed (listed cars are the same for every seed);
    ``reset()`` without a seed draws the next episode's seed from the last one, and the
    first episode's is the scenario's own.

    Examples
    --------
    >>> import gymnasium
    >>> import lotsim.envs
    >>> env = gymnasium.make("lotsim/ParkingOperator-v0", scenario=lotsim.EXAMPLE)
    >>> obs, info = env.reset(seed=1)
    >>> info["car"], env.unwrapped.slots[info["best"]["shortest"]]
    ('ada', 'N1')
    >>> obs, reward, terminated, truncated, info = env.step(info["best"]["shortest"])
    >>> info["car"], terminated
    ('bob', False)
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 4}

    def __init__(self, scenario: PreparedLot | Scenario | str | os.PathLike = "quickstart",
                 settings: RunSettings | None = None, *, render_mode: str | None = None,
                 operator: OperatorSettings | None = None,
                 frame_size: tuple[int, int] = FRAME_SIZE, **overrides) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise SettingsError("render_mode", f"expected 'rgb_array' or None, found "
                                               f"{render_mode!r}")
        self.prepared = prepared_lot(scenario)
        self.settings = run_settings(self.prepared, settings)
        if operator is not None and not isinstance(operator, OperatorSettings):
            raise SettingsError("operator", f"expected OperatorSettings, found "
                                            f"{type(operator).__name__}")
        self.operator = replace(operator or OperatorSettings(), overrides)
        GifSettings(size=frame_size)  # refused here, not at the first frame
        self.render_mode, self.frame_size = render_mode, tuple(frame_size)
        self.index = LotIndex.of(self.prepared)
        self.action_space = spaces.Discrete(self.index.wait + 1)
        self.observation_space = observation_space(self.index)
        self.episode: Episode | None = None

    @property
    def slots(self) -> tuple[str, ...]:
        """The slot ids, in the order of the actions (the last action waits)."""
        return self.index.slots

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode: the traffic drawn from ``seed`` (see the class), played to the
        first car that asks for a slot. ``options`` are not used."""
        if seed is None and self._np_random is None:
            seed = self.prepared.scenario.seed  # the first episode is the scenario's own
        super().reset(seed=seed)
        if seed is None:
            seed = int(self.np_random.integers(MAX_SEED))
        self.episode = Episode(self.prepared, self.settings, self.operator, seed,
                               index=self.index)
        return self._observe(self.episode.state()), self.episode.info()

    def step(self, action):
        """Answer the waiting car's choice with ``action`` and play on to the next one."""
        episode = self._require()
        refused = episode.act(action)
        state = episode.state()
        cost = sum(episode.settle(state).values())
        if refused is not None:
            cost += self.operator.refused_cost
        terminated = episode.done and not episode.truncated
        return (self._observe(state), float(-cost), bool(terminated),
                bool(episode.truncated), episode.info(refused))

    def action_masks(self) -> np.ndarray:
        """The actions the lot can honour now, as booleans (``info["action_mask"]``)."""
        return self._require().info()["action_mask"].astype(bool)

    def render(self):
        """The lot now as an RGB array (``render_mode="rgb_array"``), else None."""
        if self.render_mode != "rgb_array":
            return None
        return frame(self._require(), self.frame_size)

    def result(self) -> RunResult:
        """The episode's run (:meth:`~lotsim.envs.episode.Episode.result`)."""
        return self._require().result()

    def _require(self) -> Episode:
        if self.episode is None:
            raise SettingsError("env", "no episode yet: call reset() first")
        return self.episode

    def _observe(self, state: dict) -> dict[str, np.ndarray]:
        episode = self._require()
        request = None if episode.done else episode.request
        car = (next(c for c in state["cars"] if c["id"] == request.car)
               if request is not None else None)
        return features(self.index, self.operator, state, episode.horizon, car, request)
