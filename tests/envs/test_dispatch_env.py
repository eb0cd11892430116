"""The dispatcher environment (multibots/Dispatch-v0): Gymnasium's checker, seeds, masks, endings, rewards."""

from __future__ import annotations

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

import multibots  # noqa: E402
import multibots.envs  # noqa: E402
from multibots.envs import DispatchEnv  # noqa: E402

#: A small lifelong run on a generated layout, and its random-task variant.
LIFELONG = {
    "robots": 6,
    "tasks": [],
    "placement": "spread",
    "unload": "nearest",
    "layout_generate": {"group_rows": 2, "group_cols": 2, "group_height": 4, "chargers": 3},
    "charging": {"chargers": "shared"},
    "orders": {"rate": 0.05, "horizon": 600, "restock": 50, "seed": 3},
}


def play(env, seed=0, rng_seed=0, limit=10_000):
    """Random valid actions to the end: the rewards, the last info, and every observation's digest."""
    obs, info = env.reset(seed=seed)
    rng = np.random.default_rng(rng_seed)
    rewards, digest = [], []
    for _ in range(limit):
        assert env.observation_space.contains(obs)
        mask = obs["action_mask"]
        assert mask[-1] == 1 and (info["action_mask"] == mask).all()
        a = rng.choice(np.flatnonzero(mask))
        obs, r, terminated, truncated, info = env.step(a)
        rewards.append(r)
        digest.append(float(sum(v.sum() for v in obs.values())))
        if terminated or truncated:
            return rewards, info, digest, terminated, truncated
    raise AssertionError("no end")


def test_registered_on_import_and_the_default_is_the_paper_scenario():
    env = gym.make("multibots/Dispatch-v0")
    assert env.unwrapped.scenario == multibots.Scenario.paper()
    assert env.action_space == gym.spaces.Discrete(12)
    assert env.unwrapped.observation_space is env.unwrapped.observation_space


def test_gymnasium_check_env():
    check_env(DispatchEnv(invalid="wait"), skip_render_check=True)
    check_env(DispatchEnv(LIFELONG, invalid="wait"), skip_render_check=True)


def test_rewards_add_up_to_minus_cost_total_and_the_end_is_terminated():
    env = DispatchEnv()
    rewards, info, _, terminated, truncated = play(env)
    assert terminated and not truncated and info["outcome"] == "complete"
    assert sum(rewards) == pytest.approx(-env.result()["cost"], abs=1e-6)
    assert (info["action_mask"] == np.eye(12, dtype=np.int8)[11]).all()


def test_in_turn_actions_reproduce_the_in_turn_run():
    s = multibots.Scenario.paper(robots=4, goods=multibots.PAPER_TASKS[2])
    env = DispatchEnv(s)
    obs, _ = env.reset()
    while True:
        mask = obs["action_mask"]
        obs, _, te, tr, _ = env.step(int(np.flatnonzero(mask)[0]))
        if te or tr:
            break
    want = multibots.simulate(s)
    got = env.result()
    assert (got["T"], got["S"], got["C"], got["cost"]) == (want.T, want.S, want.C, want.cost)


def test_the_step_limit_truncates():
    env = DispatchEnv(multibots.Scenario.paper(step_limit=500))
    rewards, info, _, terminated, truncated = play(env)
    assert truncated and not terminated and info["outcome"] == "incomplete"
    # No Cost_total for an incomplete run: its terms with the paper's weights.
    assert sum(rewards) == pytest.approx(-(0.25 * info["distance"] + info["t"] + 50 * info["S"]), abs=1e-6)


def test_same_seed_same_episode_and_seeded_scenarios_differ_by_seed():
    a, b = play(DispatchEnv(LIFELONG), seed=5), play(DispatchEnv(LIFELONG), seed=5)
    assert a[0] == b[0] and a[2] == b[2]
    c = play(DispatchEnv(LIFELONG), seed=6)
    assert c[2] != a[2]
    assert a[4] and not a[3]  # the horizon truncates a lifelong run


def test_masked_out_actions_are_refused_with_one_line_or_taken_as_wait():
    env = DispatchEnv()
    env.reset()
    with pytest.raises(
        multibots.MultibotsError,
        match=r"^decision at step 1: action = 10 \(charge now\): not allowed for robot 0: robot 0 is full",
    ):
        env.step(10)
    env = DispatchEnv(invalid="wait")
    env.reset()
    assert env.step(10)[4]["invalid"]


def test_bad_settings_name_the_field():
    with pytest.raises(multibots.ScenarioError, match=r"^max_queue = 0: must be 1 to 1024$"):
        DispatchEnv(max_queue=0)
    with pytest.raises(multibots.ScenarioError, match=r"^reward.speed = 1: unknown weight"):
        DispatchEnv(reward={"speed": 1})
    with pytest.raises(multibots.ScenarioError, match=r'^invalid = "skip": must be "refuse" or "wait"$'):
        DispatchEnv(invalid="skip")


def test_the_original_rules_are_refused_naming_the_field():
    with pytest.raises(multibots.MultibotsError, match=r'^rules = "original"'):
        DispatchEnv(multibots.Scenario.paper(rules="original"))


@pytest.mark.parametrize("traffic", ["wait", "gate", "reserve"])
def test_any_traffic_policy_runs(traffic):
    env = DispatchEnv(multibots.Scenario.paper(robots=6, traffic=traffic))
    _, info, _, terminated, _ = play(env)
    assert terminated and info["delivered"] == 10


def test_a_custom_reward():
    env = DispatchEnv(reward={"distance": 0, "time": 0, "collision": 0, "delivery": 1})
    rewards, *_ = play(env)
    assert sum(rewards) == 10


def test_a_policy_plugs_in_as_a_strategy():
    """PolicyAllocator sees what the environment shows: front-slot actions are in-turn."""

    def front(robot, obs):
        return int(np.flatnonzero(obs[3])[0])

    s = multibots.Scenario.paper(robots=5, goods=multibots.PAPER_TASKS[4])
    got = multibots.simulate(s, allocator=multibots.envs.PolicyAllocator(front))
    want = multibots.simulate(s)
    assert (got.T, got.S, got.C) == (want.T, want.S, want.C)


def test_a_missing_extra_names_it():
    import subprocess
    import sys

    code = (
        "import sys; sys.modules['gymnasium'] = None\n"
        "try:\n import multibots.envs\nexcept ImportError as e:\n print(e)"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert "pip install 'multibots[rl]'" in p.stdout, p.stdout + p.stderr


def test_another_scenario_at_reset_and_a_refused_one_changes_nothing():
    env = DispatchEnv()
    env.reset()
    with pytest.raises(multibots.ScenarioError, match=r"^robots = 4: the environment's spaces are for 3 robots$"):
        env.reset(options={"scenario": multibots.Scenario.paper(robots=4)})
    assert env.scenario == multibots.Scenario.paper()
    other = multibots.Scenario.paper(goods=multibots.PAPER_TASKS[3])
    env.reset(options={"scenario": other})
    assert env.scenario == other and env.unwrapped.result()["goods_total"] == len(multibots.PAPER_TASKS[3])
