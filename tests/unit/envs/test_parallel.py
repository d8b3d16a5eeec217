"""lotsim.envs.parallel: the cars of a lot's traffic as PettingZoo agents, on the quickstart
lot (six listed cars: ada 0 s, bob 4 s and dee 9 s leave again, cy 8 s, eve 20 s, fay
70 s) and the mixed lot (a stream of 30 cars, each leaving again)."""

from __future__ import annotations

import warnings

import pytest

from export_runs import need

need("gymnasium", "learn")
pettingzoo_test = need("pettingzoo.test", "learn")

import lotsim  # noqa: E402
import lotsim.envs  # noqa: E402
from lotsim.envs import baselines  # noqa: E402
from lotsim.envs.episode import prepared_lot  # noqa: E402
from lotsim.errors import SettingsError  # noqa: E402


@pytest.fixture(scope="module")
def lots():
    return {name: prepared_lot(name) for name in ("quickstart", "mixed_lot")}


def test_pettingzoo_s_api_and_seed_tests_pass_on_two_lots_with_no_warning(lots):
    for name, prepared in lots.items():
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            pettingzoo_test.parallel_api_test(lotsim.envs.parallel_env(prepared),
                                              num_cycles=1000)
            pettingzoo_test.parallel_seed_test(lambda p=prepared: lotsim.envs.parallel_env(p))
        assert [str(w.message) for w in seen] == [], name


def _play(env, seed, policy=baselines.shortest):
    """Every step's agents, and the rewards each car was given, by car."""
    obs, infos = env.reset(seed=seed)
    steps, got = [list(env.agents)], {}
    while env.agents:
        actions = {a: policy(obs[a], infos[a]) for a in env.agents}
        obs, rewards, terminations, truncations, infos = env.step(actions)
        for a, r in rewards.items():
            got[a] = got.get(a, 0.0) + r
        steps.append(list(env.agents))
    return steps, got


def test_a_car_is_an_agent_from_its_arrival_until_it_parks_and_never_again(lots):
    env = lotsim.envs.parallel_env(lots["quickstart"])
    steps, got = _play(env, 1)
    rr = env.result()
    assert lotsim.check(rr).ok
    # one step per choice: ada first, alone; each car an agent over consecutive steps
    assert steps[0] == ["ada"] and steps[-1] == []
    for car in env.possible_agents:
        at = [k for k, agents in enumerate(steps) if car in agents]
        assert at and at == list(range(at[0], at[-1] + 1)), car
    # each car's reward is minus its own minutes to park
    assert got == pytest.approx({v.id: -(v.parked_at - v.arrival.time) / 60.0
                                 for v in rr.vehicles})
    # the same choices as the operator's, and rewards that add up to its return
    operator = lotsim.envs.ParkingOperatorEnv(lots["quickstart"])
    assert baselines.episode_return(operator, baselines.shortest, 1) == \
        pytest.approx(sum(got.values()))
    assert [(v.id, v.slot) for v in operator.result().vehicles] == \
        [(v.id, v.slot) for v in rr.vehicles]


def test_a_car_that_leaves_again_can_stay_an_agent_until_it_has_left(lots):
    parked = _play(lotsim.envs.parallel_env(lots["quickstart"]), 1)[0]
    env = lotsim.envs.parallel_env(lots["quickstart"], until="departed")
    departed, got = _play(env, 1)
    rr = env.result()
    # the steps: ada 0 s, bob 4 s, cy 8 s, dee 9 s, eve 20 s, fay 70 s, the end; all have
    # parked by 36 s, and at fay's choice bob (who leaves at 95 s) and dee (at 76 s) are
    # still in the lot, and the cars that stay are for good
    assert parked[4:6] == [["bob", "cy", "dee", "eve"], ["fay"]]
    assert departed[4:6] == [["ada", "bob", "cy", "dee", "eve"],
                             ["ada", "bob", "cy", "dee", "eve", "fay"]]
    assert max(v.parked_at for v in rr.vehicles if v.id != "fay") < 40.0
    assert [v.id for v in rr.vehicles if v.left_at is not None and v.left_at > 70.0] == \
        ["bob", "dee"]
    # the reward is still each car's minutes to park
    assert got == pytest.approx({v.id: -(v.parked_at - v.arrival.time) / 60.0
                                 for v in rr.vehicles})
    with pytest.raises(SettingsError, match="until: expected one of parked, departed"):
        lotsim.envs.parallel_env(lots["quickstart"], until="left")


def test_only_the_choosing_car_acts_and_the_others_may_only_wait(lots):
    env = lotsim.envs.parallel_env(lots["mixed_lot"])
    obs, infos = env.reset(seed=3)
    for _ in range(8):
        choosing = [a for a in env.agents if obs[a]["action_mask"][:-1].any()]
        assert len(choosing) == 1
        car = choosing[0]
        for a in env.agents:
            if a != car:
                assert obs[a]["action_mask"].tolist() == [0] * len(env.index.slots) + [1]
                assert infos[a] == {}
            assert obs[a] in env.observation_space(a)
        assert infos[car]["car"] == car
        actions = {a: 0 for a in env.agents}  # the others' are ignored
        actions[car] = infos[car]["best"]["shortest"]
        obs, rewards, terminations, truncations, infos = env.step(actions)
    # a choosing car given no action waits, and asks again
    car = next(a for a in env.agents if obs[a]["action_mask"][:-1].any())
    obs, rewards, *_ = env.step({})
    assert car in env.agents and rewards[car] == 0.0


def test_a_refused_choice_costs_the_car_that_made_it(lots):
    env = lotsim.envs.parallel_env(lots["quickstart"])
    obs, infos = env.reset()
    obs, rewards, terminations, truncations, infos = env.step({"ada": 1})  # N2: taken
    assert rewards["ada"] == pytest.approx(-1.0)
    assert infos["ada"]["refused"] == "car 'ada' cannot take slot 'N2': it is occupied " \
                                      "(taken when the run began)"
