"""Train a small dispatcher policy on the paper's warehouse, NumPy only, in about a minute on one core.

    .venv/bin/python examples/train_dispatch.py [--iterations 30] [--out examples/dispatch_policy.npz]

The policy is :class:`multibots.envs.LinearPolicy` (37 weights: a score per queue slot from
the slot's and the robot's features, and one each for "charge now" and "wait"), trained by
the cross-entropy method: each iteration draws a population of weight vectors around a
Gaussian, runs each greedily on the same training episodes of ``multibots/Dispatch-v0``,
and refits the Gaussian to the best fifth. The score is the mean of ``-Cost_total`` (the
sum of the environment's default rewards).

Training episodes are the paper scenario with random task lists (10 goods, seeds from
10,000 on, fresh ones each iteration) and 1 to 6 robots, so that TABLE III's five lists,
on which ``multibots compare`` judges it, stay unseen. The weights go to ``--out``; the
strategy ``examples/trained_dispatch.py:TrainedDispatch`` loads them::

    multibots compare --strategies in-turn,nearest,hungarian,examples/trained_dispatch.py:TrainedDispatch
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import multibots
from multibots.envs import DispatchEnv, LinearPolicy


def episode_cost(env: DispatchEnv, policy: LinearPolicy, seed: int) -> float:
    """Cost_total of one greedy episode (the negative of its rewards' sum)."""
    obs, _ = env.reset(seed=seed)
    total = 0.0
    while True:
        a = policy.act(0, (obs["robot"], obs["fleet"], obs["queue"], obs["action_mask"]))
        obs, r, terminated, truncated, _ = env.step(a)
        total += r
        if terminated or truncated:
            return -total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--iterations", type=int, default=30)
    ap.add_argument("--population", type=int, default=32)
    ap.add_argument("--episodes", type=int, default=2, help="random task lists per fleet size and iteration")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, default=Path(__file__).with_name("dispatch_policy.npz"))
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    # One environment per fleet size; a seed draws each episode's task list.
    envs = {
        n: DispatchEnv(multibots.Scenario.paper(robots=n, tasks={"random": 10, "seed": 0}), max_queue=10)
        for n in range(1, 7)
    }
    size = LinearPolicy.size()
    mean, std = np.zeros(size), np.full(size, 0.5)
    elite = max(2, a.population // 5)
    t0 = time.perf_counter()
    next_seed = 10_000
    for it in range(a.iterations):
        seeds = list(range(next_seed, next_seed + a.episodes))
        next_seed += a.episodes
        # The mean itself is a candidate, so a good policy is never lost to sampling noise.
        cands = np.vstack([mean, mean + std * rng.standard_normal((a.population - 1, size))])
        scores = np.array(
            [np.mean([episode_cost(env, LinearPolicy(c), s) for env in envs.values() for s in seeds]) for c in cands]
        )
        best = cands[np.argsort(scores)[:elite]]
        mean, std = best.mean(axis=0), best.std(axis=0) + 0.02
        print(f"iteration {it + 1:>2}: mean Cost_total {scores[0]:9.1f} (policy), best {scores.min():9.1f}", flush=True)
    LinearPolicy(mean).save(a.out)
    print(f"saved {a.out} after {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
