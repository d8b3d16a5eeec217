"""lotsim.envs.operator, lotsim.envs.episode and lotsim.envs.baselines: the Gymnasium
operator of a lot, on the quickstart lot (one one-way aisle, N1–N10 and S1–S10, five taken,
six listed cars) and the mixed lot (a loop of four aisles, a stream of 30 cars).

The operator's runs are compared with lotsim's own (the shortest baseline plays
``lotsim.run(assignment="shortest")``), its mask with what a stepped run refuses when asked
directly, its rewards with the result's metrics, and every episode with the checker."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from export_runs import need

gymnasium = need("gymnasium", "learn")
need("pettingzoo", "learn")
check_env = need("gymnasium.utils.env_checker", "learn").check_env

import lotsim  # noqa: E402
import lotsim.envs  # noqa: E402
from lotsim.envs import baselines  # noqa: E402
from lotsim.envs.episode import prepared_lot, shipped_scenarios  # noqa: E402
from lotsim.errors import DecisionError, SettingsError  # noqa: E402
from lotsim.io.result import result_dict  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]
CLOSED_SOUTH = "disturbances:\n  closures: [{aisle: south, from: 1, to: 3000}]\n"
"""The mixed lot's south aisle closed from 1 s: its parallel bays L1–L6 are cut off."""


@pytest.fixture(scope="module")
def lots():
    return {name: prepared_lot(name) for name in ("quickstart", "mixed_lot")}


def _doc(rr) -> dict:
    doc = result_dict(rr)
    doc.pop("version", None)
    doc["settings"].pop("lotsim_version")
    return doc


def _play(env, policy, seed):
    """The episode's actions, rewards and last step's flags and info."""
    obs, info = env.reset(seed=seed)
    actions, rewards, over = [], [], False
    while not over:
        actions.append(policy(obs, info))
        obs, reward, terminated, truncated, info = env.step(actions[-1])
        rewards.append(reward)
        over = terminated or truncated
    return actions, rewards, terminated, truncated, info


def test_gymnasium_makes_the_operator_and_its_checker_passes_it_with_no_warning():
    assert lotsim.envs.OPERATOR_ID in gymnasium.registry
    env = gymnasium.make("lotsim/ParkingOperator-v0", scenario="quickstart",
                         render_mode="rgb_array")
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        check_env(env.unwrapped)  # the render check too
    assert [str(w.message) for w in seen] == []
    # the module:id form imports lotsim.envs first
    other = gymnasium.make("lotsim.envs:lotsim/ParkingOperator-v0", scenario="quickstart")
    assert other.unwrapped.slots == env.unwrapped.slots


def test_the_spaces_hold_what_the_lot_has_in_its_order(lots):
    env = lotsim.envs.ParkingOperatorEnv(lots["quickstart"])
    assert env.slots == tuple(s.id for s in lots["quickstart"].lot.slots)
    assert env.slots[:3] == ("N1", "N2", "N3") and env.action_space.n == 21
    obs, info = env.reset()
    assert {k: v.shape for k, v in obs.items()} == {
        "occupancy": (20,), "vehicle": (1,), "entrance": (1,), "static_time": (20,),
        "queues": (1,), "aisles": (1,), "time": (1,)}
    assert obs in env.observation_space
    # ada at the gate at 0 s: N2, N5, S3, S4, S9 taken, the rest hers; waiting allowed
    taken = [env.slots.index(s) for s in ("N2", "N5", "S3", "S4", "S9")]
    assert np.flatnonzero(obs["occupancy"]).tolist() == sorted(taken)
    expected = np.ones(21, dtype=np.int8)
    expected[taken] = 0
    assert info["action_mask"].dtype == np.int8
    assert info["action_mask"].tolist() == expected.tolist()
    assert env.action_masks().tolist() == expected.astype(bool).tolist()
    assert info["car"] == "ada" and info["time"] == 0.0 and obs["time"][0] == 0.0
    # static times: scaled by the cap where she may park, 1 where she may not
    assert np.isinf(info["static_times"][taken]).all()
    free = np.flatnonzero(expected[:-1])
    assert obs["static_time"][free] == pytest.approx(info["static_times"][free] / 300.0)
    assert (obs["static_time"][taken] == 1.0).all()
    assert info["best"]["shortest"] == int(np.argmin(info["static_times"]))


@pytest.mark.slow
def test_the_shortest_baseline_plays_the_run_lotsim_plays(lots):
    for name, seeds in (("quickstart", [1]), ("mixed_lot", [4, 11])):
        prepared = lots[name]
        env = lotsim.envs.ParkingOperatorEnv(prepared)
        for seed in seeds:
            _play(env, baselines.shortest, seed)
            settings = lotsim.RunSettings(assignment="shortest",
                                          seed=seed if name == "mixed_lot" else None)
            assert _doc(env.result()) == _doc(lotsim.run(prepared, settings)), (name, seed)


@pytest.mark.slow
def test_every_episode_checks_and_its_return_is_the_cars_minutes_to_park(lots):
    for name, prepared in lots.items():
        env = lotsim.envs.ParkingOperatorEnv(prepared)
        for by, make in baselines.BASELINES.items():
            actions, rewards, terminated, truncated, info = _play(env, make(), 2)
            rr = env.result()
            assert lotsim.check(rr).ok, (name, by)
            assert terminated and not truncated
            m = rr.metrics()
            parked = sum(v.parked_at is not None for v in rr.vehicles)
            minutes = parked * m["mean_time_to_park"] / 60 + 10.0 * (len(rr.vehicles) - parked)
            assert sum(rewards) == pytest.approx(-minutes), (name, by)
            assert info["metrics"]["served"] == m["served"]


def test_a_seed_gives_the_same_episode_and_another_seed_another_traffic(lots):
    env = lotsim.envs.ParkingOperatorEnv(lots["mixed_lot"])

    def cars(seed):
        obs, info = env.reset(seed=seed)
        return [(c["id"], c["arrival"]) for c in env.episode.state()["cars"]]

    assert cars(5) == cars(5) != cars(6)
    one = _play(env, baselines.random_slot(3), 5)
    two = _play(env, baselines.random_slot(3), 5)
    assert one[:4] == two[:4]
    # without a seed: the scenario's own first, then seeds drawn from the last one
    fresh = lotsim.envs.ParkingOperatorEnv(lots["mixed_lot"])
    fresh.reset()
    assert fresh.episode.settings.seed == lots["mixed_lot"].scenario.seed
    fresh.reset(seed=5)
    fresh.reset()
    after_five = fresh.episode.settings.seed
    fresh.reset(seed=5)
    fresh.reset()
    assert fresh.episode.settings.seed == after_five != 5


def test_a_slot_the_lot_cannot_give_makes_the_car_wait_at_a_cost_or_is_refused(lots):
    env = lotsim.envs.ParkingOperatorEnv(lots["quickstart"])
    obs, info = env.reset()
    n2 = env.slots.index("N2")
    obs, reward, terminated, truncated, info = env.step(n2)
    assert info["refused"] == "car 'ada' cannot take slot 'N2': it is occupied (taken when " \
                              "the run began)"
    assert reward == pytest.approx(-1.0)
    assert info["car"] == "bob"  # ada waits and asks again after the retry time
    strict = lotsim.envs.ParkingOperatorEnv(lots["quickstart"], refused="raise")
    strict.reset()
    with pytest.raises(DecisionError, match=r"car 'ada' cannot take slot 'N2': it is occupied"):
        strict.step(n2)
    strict.step(strict.slots.index("N1"))  # the choice is still hers
    with pytest.raises(SettingsError, match=r"action: expected a slot's index \(0 to 19\) or "
                                            r"20 to wait, found 21"):
        strict.step(21)
    with pytest.raises(SettingsError, match="refused: expected one of wait, raise"):
        lotsim.envs.ParkingOperatorEnv(lots["quickstart"], refused="skip")
    with pytest.raises(SettingsError, match="no such setting of OperatorSettings"):
        lotsim.envs.ParkingOperatorEnv(lots["quickstart"], horizn=5)


def _mask_agrees_with_the_run(prepared, settings, choose, at):
    """At each decision ``at`` of an episode played by ``choose``: every slot the mask
    leaves out is refused by a stepped run asked directly (replayed to that decision), and
    every slot it marks is taken."""
    env = lotsim.envs.ParkingOperatorEnv(prepared, settings)
    obs, info = env.reset()
    answers, checked = [], 0
    for k in range(max(at) + 1):
        if "car" not in info:
            break
        if k in at:
            live = _replayed(prepared, settings, answers)
            for i, sid in enumerate(env.slots):
                if info["action_mask"][i]:
                    _replayed(prepared, settings, answers).decide(sid)  # no error
                else:
                    with pytest.raises(DecisionError, match=f"cannot take slot '{sid}'"):
                        live.decide(sid)
                checked += 1
        action = choose(obs, info)
        answers.append(env.slots[action])
        obs, _, terminated, truncated, info = env.step(action)
    return checked


def _replayed(prepared, settings, answers):
    live = lotsim.Live(prepared, settings, policy=lotsim.ASK)
    for sid in answers:
        live.next_decision()
        live.decide(sid)
    assert live.next_decision() is not None
    return live


@pytest.mark.slow
def test_the_mask_marks_exactly_the_slots_a_stepped_run_accepts(lots):
    settings = lotsim.RunSettings()
    assert _mask_agrees_with_the_run(lots["quickstart"], settings, baselines.shortest,
                                     at=range(6)) == 6 * 20
    # the mixed lot with its south aisle closed: what the closure cuts off is masked too
    closed = lotsim.prepare((ROOT / "scenarios" / "mixed_lot.yaml").read_text()
                            .split("animation:")[0] + CLOSED_SOUTH)
    env = lotsim.envs.ParkingOperatorEnv(closed)
    obs, info = env.reset()
    south = [i for i, s in enumerate(env.slots) if s.startswith("L")]
    assert info["action_mask"][south].any()  # at 0 s, before the closure
    obs, _, _, _, info = env.step(baselines.shortest(obs, info))
    assert info["time"] > 1.0 and not info["action_mask"][south].any()
    n = len(env.slots)
    assert _mask_agrees_with_the_run(closed, settings, baselines.nearest, at=[1, 2]) == 2 * n


def test_an_episode_past_its_horizon_is_truncated_and_its_run_carried_to_the_end(lots):
    env = lotsim.envs.ParkingOperatorEnv(lots["quickstart"], horizon=5.0)
    obs, info = env.reset()
    with pytest.raises(SettingsError, match="the episode goes on"):
        env.result()
    actions, rewards, terminated, truncated, info = _play(env, baselines.shortest, 1)
    # ada (0 s) and bob (4 s) choose; cy asks at 8 s, past the horizon
    assert len(actions) == 2 and truncated and not terminated
    assert info["action_mask"].tolist() == [0] * 20 + [1]
    rr = env.result()
    assert lotsim.check(rr).ok and rr.metrics()["served"] == 6
    with pytest.raises(SettingsError, match="the episode is over"):
        env.step(0)
    # the time feature runs over the horizon, at most 1
    long = lotsim.envs.ParkingOperatorEnv(lots["quickstart"])
    obs, info = long.reset()
    assert long.episode.horizon == 70.0 + 600.0  # fay's arrival and the patience
    for _ in range(5):
        obs, *_ = long.step(baselines.shortest(obs, info))
        info = long.episode.info()
    assert obs["time"][0] == pytest.approx(70.0 / 670.0)


def test_a_frame_shows_the_lot_as_it_is_now(lots):
    env = lotsim.envs.ParkingOperatorEnv(lots["quickstart"], render_mode="rgb_array",
                                         frame_size=(320, 240))
    obs, info = env.reset()
    first = env.render()
    assert first.shape == (240, 320, 3) and first.dtype == np.uint8
    for _ in range(3):
        env.step(baselines.shortest(obs, env.episode.info()))
    later = env.render()
    assert (later != first).any()  # cars have come and moved
    _play(env, baselines.shortest, 1)
    assert env.render().shape == (240, 320, 3)  # the run's end
    short = lotsim.envs.ParkingOperatorEnv(lots["quickstart"], render_mode="rgb_array",
                                           horizon=5.0)
    _play(short, baselines.shortest, 1)
    assert short.render().shape == (320, 480, 3)  # the default size
    assert short.episode.live.done is False  # a truncated episode is drawn, not carried on
    plain = lotsim.envs.ParkingOperatorEnv(lots["quickstart"])
    plain.reset()
    assert plain.render() is None


def test_the_lot_is_named_or_given_and_a_wrong_one_says_what_there_is(lots):
    names = shipped_scenarios()
    assert {"quickstart", "mixed_lot", "ring", "surface364"} <= set(names)
    with pytest.raises(SettingsError, match=r"expected a shipped scenario's name \(.*"
                                            r"quickstart.*\), a scenario file or its text, "
                                            r"found 'quikstart'"):
        lotsim.envs.ParkingOperatorEnv("quikstart")
    from_text = lotsim.envs.ParkingOperatorEnv(lotsim.EXAMPLE)
    assert from_text.slots == ("N1", "N2", "N3", "N4", "S1", "S2", "S3", "S4")
    with pytest.raises(SettingsError, match="priority: the operator chooses each car's slot "
                                            "as it comes: expected 'arrival'"):
        lotsim.envs.ParkingOperatorEnv(lots["quickstart"],
                                       lotsim.RunSettings(priority="shortest_first"))
    with pytest.raises(SettingsError, match="no episode yet"):
        lotsim.envs.ParkingOperatorEnv(lots["quickstart"]).step(0)


def test_the_random_baseline_takes_free_slots_and_the_returns_are_reproducible(lots):
    env = lotsim.envs.ParkingOperatorEnv(lots["mixed_lot"])
    obs, info = env.reset(seed=1)
    pick = baselines.random_slot(0)
    choices = [pick(obs, info) for _ in range(50)]
    assert all(info["action_mask"][c] for c in choices) and len(set(choices)) > 5
    again = baselines.random_slot(0)
    assert choices == [again(obs, info) for _ in range(50)]
    a = baselines.mean_return(env, baselines.random_slot(0), seeds=[1, 2])
    b = baselines.mean_return(env, baselines.random_slot(0), seeds=[1, 2])
    assert a == b < 0
    assert baselines.shortest(obs, {"action_mask": np.array([0, 1])}) == 1  # no car: waits


def test_the_readme_s_example_of_the_environment_runs_as_written():
    from test_docs_code import shown_blocks

    (code,) = [c for _, c in shown_blocks(ROOT / "README.md") if "ParkingOperator" in c]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    assert namespace["reward"] <= 0 and not namespace["terminated"]
    assert namespace["info"]["action_mask"].dtype == np.int8


def test_info_holds_the_best_slot_of_the_rankings_asked_for(lots):
    env = lotsim.envs.ParkingOperatorEnv(lots["quickstart"], rankings=["shortest", "shortest"])
    assert env.operator.rankings == ("shortest",)
    obs, info = env.reset()
    assert info["best"] == {"shortest": 0}
    with pytest.raises(SettingsError, match=r"the nearest baseline reads "
                                            r"info\['best'\]\['nearest'\]"):
        baselines.nearest(obs, info)
    with pytest.raises(SettingsError, match="rankings: expected one of nearest, shortest, "
                                            "priced, found 'cheapest'"):
        lotsim.envs.ParkingOperatorEnv(lots["quickstart"], rankings=("cheapest",))
    with pytest.raises(SettingsError, match="rankings: expected a sequence"):
        lotsim.envs.ParkingOperatorEnv(lots["quickstart"], rankings="shortest")
