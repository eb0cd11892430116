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
from typing import Any

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


def measure(seconds: float = 3.0, num_envs: int = 64, with_peers: bool = True) -> dict[str, Any]:
    """Every figure of this benchmark, for benchmarks/run_all.py too."""
    d: dict[str, Any] = {
        "seconds": seconds,
        "envs": num_envs,
        "vector_1": vector_rate(num_envs, 1, seconds),
        "vector_2": vector_rate(num_envs, 2, seconds),
        "single": single_rate(seconds),
        "peers": [],
    }
    if with_peers:
        import peers

        d["peers"] = peers.measure_peers(agent_counts=(3,), repetitions=3)
    return d


def markdown(d: dict[str, Any]) -> list[str]:
    """The section of docs/benchmarks.md."""
    lines = [
        "## Learning environments",
        "",
        "`benchmarks/envs.py`: random allowed actions on the paper scenario (3 robots, TABLE III group 1), "
        f"median of 3 × {d['seconds']:g} s. Target: ≥ 50,000 decisions/s, vector form, one core.",
        "",
        "| environment | per second |",
        "|---|---:|",
        f"| MultiBots dispatcher, vector form ({d['envs']} envs), 1 worker (one core) | {d['vector_1']:,.0f} decisions |",
        f"| MultiBots dispatcher, vector form ({d['envs']} envs), 2 workers | {d['vector_2']:,.0f} decisions |",
        f"| MultiBots dispatcher, `gymnasium.Env` (a Python call per decision) | {d['single']:,.0f} decisions |",
    ]
    for r in d["peers"]:
        if r["status"] == "ok":
            lines.append(f"| {r['peer']} {r['version']}, 3 agents, random actions | {r['agent_steps_per_s'] / 3:,.0f} env steps |")
        else:
            lines.append(f"| {r['peer']} | n/a: {r['reason']} |")
    lines += [
        "",
        "A dispatcher decision covers about 200 simulation steps of the paper model (600 robot-steps, collision "
        "waiting, energy); a peer's env step moves each agent one grid cell. The target is not met: the engine's "
        "own step is the cost (a profile of `cargo run --release --example decisions_speed` puts over 90% in "
        "collisions and motion, under 10% in decisions and observations).",
    ]
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--envs", type=int, default=64)
    ap.add_argument("--no-peers", action="store_true", help="skip rware and pogema")
    a = ap.parse_args()
    print("\n".join(markdown(measure(a.seconds, a.envs, not a.no_peers))))


if __name__ == "__main__":
    main()
