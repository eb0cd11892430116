"""The fleet environment (PettingZoo ParallelEnv): PettingZoo's checkers, state, masks, rewards."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from pettingzoo.test import parallel_api_test, parallel_seed_test

import multibots
from multibots.envs import parallel_env

#: A small lifelong run on a generated layout.
LIFELONG = {
    "robots": 6,
    "tasks": [],
    "placement": "spread",
    "unload": "nearest",
    "layout_generate": {"group_rows": 2, "group_cols": 2, "group_height": 4, "chargers": 3},
    "charging": {"chargers": "shared"},
    "orders": {"rate": 0.05, "horizon": 600, "restock": 50, "seed": 3},
}


def test_parallel_api_test():
    parallel_api_test(parallel_env(), num_cycles=1000)
    parallel_api_test(parallel_env(LIFELONG), num_cycles=200)


def test_parallel_seed_test():
    parallel_seed_test(lambda: parallel_env(invalid="wait"))
    parallel_seed_test(lambda: parallel_env(LIFELONG, invalid="wait"), num_cycles=50)


def test_state_masks_and_rewards_add_up_to_minus_cost_total():
    env = parallel_env(multibots.Scenario.paper(robots=4))
    obs, infos = env.reset(seed=0)
    assert env.state_space.contains(env.state())
    rng = np.random.default_rng(1)
    total = 0.0
    while env.agents:
        actions = {}
        for a in env.agents:
            mask = obs[a]["action_mask"]
            assert mask[-1] == 1 and env.observation_space(a).contains(obs[a])
            if not infos[a]["deciding"]:
                assert mask.sum() == 1
            actions[a] = int(rng.choice(np.flatnonzero(mask)))
        obs, rew, term, trunc, infos = env.step(actions)
        total += sum(rew.values())
        assert env.state_space.contains(env.state())
    assert all(term.values()) and not any(trunc.values())
    assert total == pytest.approx(-env.result()["cost"], abs=1e-6)


def test_a_busy_robot_may_only_wait():
    env = parallel_env()
    env.reset()
    env.step({"robot_0": 0, "robot_1": 1, "robot_2": 2})
    with pytest.raises(multibots.MultibotsError, match=r"does not decide at this point"):
        env.step({"robot_0": 0, "robot_1": 0, "robot_2": 0})
