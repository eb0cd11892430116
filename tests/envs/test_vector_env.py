"""The vector form: one call steps many dispatchers, and each follows the single dispatcher's trajectory."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("gymnasium")

import multibots
from multibots.envs import DispatchEnv, VectorDispatch


def test_vector_matches_single_environments_with_next_step_autoreset():
    s = multibots.Scenario.paper(robots=3, goods=multibots.PAPER_TASKS[1])
    v = VectorDispatch(s, num_envs=3, workers=2)
    singles = [DispatchEnv(s) for _ in range(3)]
    obs, info = v.reset(seed=0)
    sobs = [e.reset(seed=0)[0] for e in singles]
    ended = [False] * 3
    for _ in range(60):
        actions = np.array(
            [int(np.flatnonzero(o["action_mask"])[-2 if o["action_mask"].sum() > 1 else -1]) for o in sobs]
        )
        obs, rew, term, trunc, info = v.step(actions)
        for k, e in enumerate(singles):
            if ended[k]:
                sobs[k], _ = e.reset()
                r = 0.0
                ended[k] = False
            else:
                sobs[k], r, te, tr, _ = e.step(actions[k])
                ended[k] = te or tr
            assert rew[k] == r
            for part in ("robot", "fleet", "queue", "action_mask"):
                assert (obs[part][k] == sobs[k][part]).all()
    assert v.observation_space.contains(obs)


def test_a_refused_action_names_the_environment():
    v = VectorDispatch(num_envs=2)
    v.reset()
    with pytest.raises(multibots.MultibotsError, match=r"env 1: action = 10 \(charge now\)"):
        v.step([0, 10])
