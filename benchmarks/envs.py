"""Learning environments: dispatcher decisions per second, beside rware's and pogema's env steps.

    .venv/bin/python benchmarks/envs.py [--seconds 3] [--envs 64] [--no-peers]

Random valid actions (a uniform draw among the actions each mask allows, made with NumPy
for the whole batch) on the paper scenario (3 robots, TABLE III group 1), the vector form
``multibots.envs.VectorDispatch`` with one worker: every environment is stepped on the
calling thread, so this is one core. Each repetition runs ``--seconds`` of whole calls;
the median of three is reported. For the record it also measures two workers and the
single ``gymnasium.Env`` (one Python call per decision).

The peers (rware, pogema) are measured with benchmarks/peers.py, in their own virtual
environment (.venv-peers; their pins clash with ours), with random actions and as many
agents as the paper scenario has robots; their figure is environment steps per second
(one ``step`` call moves every agent once).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import multibots.envs as envs


def vector_rate(num_envs: int, workers: int, seconds: float) -> float:
    v = envs.VectorDispatch(num_envs=num_envs, workers=workers)
    obs, _ = v.reset(seed=0)
    rng = np.random.default_rng(0)
    rates = []
    for _ in range(3):
        n, t0 = 0, time.perf_counter()
        while time.perf_counter() - t0 < seconds:
            mask = obs["action_mask"]
            actions = np.argmax(rng.random(mask.shape) * mask, axis=1)
            obs, *_ = v.step(actions)
            n += num_envs
        rates.append(n / (time.perf_counter() - t0))
    return statistics.median(rates)


def single_rate(seconds: float) -> float:
    env = envs.DispatchEnv()
    obs, _ = env.reset(seed=0)
    rng = np.random.default_rng(0)
    n, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        mask = obs["action_mask"]
        obs, _, te, tr, _ = env.step(int(np.argmax(rng.random(mask.shape) * mask)))
        n += 1
        if te or tr:
            obs, _ = env.reset()
    return n / (time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--envs", type=int, default=64)
    ap.add_argument("--no-peers", action="store_true", help="skip rware and pogema")
    a = ap.parse_args()
    one = vector_rate(a.envs, 1, a.seconds)
    two = vector_rate(a.envs, 2, a.seconds)
    single = single_rate(a.seconds)
    print(f"dispatcher, vector form ({a.envs} envs), 1 worker: {one:,.0f} decisions/s (target 50,000)")
    print(f"dispatcher, vector form ({a.envs} envs), 2 workers: {two:,.0f} decisions/s")
    print(f"dispatcher, gymnasium.Env (one call per decision): {single:,.0f} decisions/s")
    if a.no_peers:
        return
    import peers

    for rec in peers.measure_peers(agent_counts=(3,), repetitions=3):
        if rec["status"] == "ok":
            print(f"{rec['peer']} {rec['version']}, 3 agents: {rec['agent_steps_per_s'] / 3:,.0f} env steps/s")
        else:
            print(f"{rec['peer']}: n/a ({rec['reason']})")


if __name__ == "__main__":
    main()
