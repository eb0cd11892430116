"""Measure one peer simulator (rware or pogema) at one agent count.

This file runs *inside the peers' virtual environment* (.venv-peers, made by
benchmarks/peers.py), never in the project's own environment: rware and pogema pin
numpy<2, pydantic 1 and gymnasium 0.28, which clash with the project's dependencies.
It imports nothing from the project.

    .venv-peers/bin/python benchmarks/peer_worker.py --peer rware --agents 100

prints one JSON object on its last stdout line (see `measure`). Progress goes to stderr.

Method: build the environment, reset it with a fixed seed, take warm-up steps, then time
`repetitions` consecutive repetitions on the same episode. A repetition runs whole steps
until at least `min_rep_seconds` of wall time have passed (at least one step). Each step
draws one uniformly random action per agent from a seeded numpy Generator (inside the
timed loop, as a random policy would) and calls the peer's own `step`, which also builds
the peer's per-agent observations and rewards: that is part of what the peer does per
step and cannot be switched off through its public API. Episodes never end during the
measurement (no time limit), so no reset is timed.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import statistics
import sys
import time
import warnings
from importlib import metadata
from typing import Any, Callable

# Traversable cells per agent. The paper's warehouse (docs/model.md) is 800 x 550 px, i.e.
# 16 x 11 cells of 50 px = 176 cells, worked by 6 robots: 176 / 6 = 29.3 cells per robot.
# Both peers get the same density at every agent count.
CELLS_PER_AGENT = 176 / 6

# rware's registered layouts all use column height 8; we keep it.
RWARE_COLUMN_HEIGHT = 8
# pogema's default random-obstacle density.
POGEMA_OBSTACLE_DENSITY = 0.3

N_ACTIONS = 5  # both peers: rware NOOP/FORWARD/LEFT/RIGHT/TOGGLE_LOAD, pogema stay + 4 moves


def _log(msg: str) -> None:
    print(f"[peer_worker] {msg}", file=sys.stderr, flush=True)


def rware_layout(n_agents: int) -> dict[str, int]:
    """Shelf rows/columns for about CELLS_PER_AGENT cells per agent, on a near-square grid.

    rware's grid is height (column_height + 1) * shelf_rows + 2 by width
    3 * shelf_columns + 1 (shelf_columns must be odd). Every cell is traversable by an
    agent that carries no shelf (agents drive under shelves), so all cells count.
    """
    target = CELLS_PER_AGENT * n_agents
    h_per_row = RWARE_COLUMN_HEIGHT + 1
    # near-square: height ~ h_per_row * r and width ~ 3 * c, equal when c = 3 * r, so
    # cells ~ (h_per_row * r) ** 2
    rows = max(1, round(math.sqrt(target / (h_per_row * h_per_row))))
    height = h_per_row * rows + 2
    cols_f = (target / height - 1) / 3
    lo = max(1, int(math.floor(cols_f)))
    if lo % 2 == 0:
        lo -= 1
    lo = max(1, lo)
    hi = lo + 2
    cols = lo if abs(cols_f - lo) <= abs(hi - cols_f) else hi
    cols = max(3, cols)  # rware's smallest registered layout ("tiny") has 3 columns
    width = 3 * cols + 1
    if height * width < n_agents:
        raise ValueError(f"layout too small for {n_agents} agents")
    return {
        "shelf_rows": rows,
        "shelf_columns": cols,
        "column_height": RWARE_COLUMN_HEIGHT,
        "grid_height": height,
        "grid_width": width,
    }


def pogema_size(n_agents: int) -> int:
    """Square map side so that free (non-obstacle) cells per agent ~ CELLS_PER_AGENT."""
    return max(8, math.ceil(math.sqrt(CELLS_PER_AGENT * n_agents / (1 - POGEMA_OBSTACLE_DENSITY))))


def build_rware(n_agents: int, seed: int) -> tuple[Callable[[list[int]], Any], dict[str, Any]]:
    from rware.warehouse import RewardType, Warehouse

    lay = rware_layout(n_agents)
    # As rware's registered "rware-<size>-<N>ag-v2" tasks (normal difficulty): msg_bits 0,
    # sensor_range 1, request queue = number of agents, individual rewards, flattened
    # observations; but no episode limit (max_steps None), so the measurement never resets.
    kwargs: dict[str, Any] = dict(
        shelf_columns=lay["shelf_columns"],
        column_height=lay["column_height"],
        shelf_rows=lay["shelf_rows"],
        n_agents=n_agents,
        msg_bits=0,
        sensor_range=1,
        request_queue_size=n_agents,
        max_inactivity_steps=None,
        max_steps=None,
        reward_type=RewardType.INDIVIDUAL,
    )
    env = Warehouse(**kwargs)
    assert all(sp.n == N_ACTIONS for sp in env.action_space.spaces)
    env.reset(seed=seed)
    cells = lay["grid_height"] * lay["grid_width"]
    params = {
        "class": "rware.warehouse.Warehouse",
        **{k: v for k, v in kwargs.items() if k != "reward_type"},
        "reward_type": "INDIVIDUAL",
        "observation_type": "FLATTENED",
        "grid": [lay["grid_height"], lay["grid_width"]],
        "cells": cells,
        "shelves": len(env.shelfs),
        "traversable_cells_per_agent": round(cells / n_agents, 2),
        "reset_seed": seed,
    }
    return env.step, params


def build_pogema(n_agents: int, seed: int) -> tuple[Callable[[list[int]], Any], dict[str, Any]]:
    from pogema import GridConfig, pogema_v0

    size = pogema_size(n_agents)
    cfg = dict(
        num_agents=n_agents,
        size=size,
        density=POGEMA_OBSTACLE_DENSITY,
        seed=seed,
        on_target="restart",  # lifelong: a new goal on arrival, agents never leave
        collision_system="priority",
        obs_radius=5,
        observation_type="default",
        max_episode_steps=10**9,  # no truncation during the measurement
    )
    env = pogema_v0(grid_config=GridConfig(**cfg))
    assert env.action_space.n == N_ACTIONS
    env.reset(seed=seed)
    free = int(round(size * size * (1 - POGEMA_OBSTACLE_DENSITY)))
    params = {
        "class": "pogema.pogema_v0 (PogemaLifeLong + wrappers)",
        **cfg,
        "grid": [size, size],
        "cells": size * size,
        "traversable_cells_per_agent": round(free / n_agents, 2),
        "reset_seed": seed,
    }
    return env.step, params


BUILDERS = {"rware": build_rware, "pogema": build_pogema}


def measure(
    peer: str,
    n_agents: int,
    repetitions: int = 5,
    min_rep_seconds: float = 1.0,
    warmup_seconds: float = 0.2,
    seed: int = 0,
) -> dict[str, Any]:
    import numpy as np

    warnings.simplefilter("ignore")  # gymnasium's passive checker and deprecation chatter
    t0 = time.perf_counter()
    step, params = BUILDERS[peer](n_agents, seed)
    build_s = time.perf_counter() - t0
    _log(f"{peer} n={n_agents}: built and reset in {build_s:.2f} s; grid {params['grid']}")

    rng = np.random.default_rng(seed)

    def run(min_seconds: float) -> tuple[int, float, float]:
        steps = 0
        cpu0 = time.process_time()
        start = time.perf_counter()
        while True:
            step(rng.integers(0, N_ACTIONS, size=n_agents).tolist())
            steps += 1
            elapsed = time.perf_counter() - start
            if elapsed >= min_seconds:
                return steps, elapsed, time.process_time() - cpu0

    warm_steps, warm_s, _ = run(warmup_seconds)
    _log(f"{peer} n={n_agents}: warm-up {warm_steps} steps in {warm_s:.2f} s")
    reps = []
    for i in range(repetitions):
        steps, elapsed, cpu = run(min_rep_seconds)
        reps.append({"steps": steps, "seconds": elapsed, "cpu_seconds": cpu,
                     "agent_steps_per_s": steps * n_agents / elapsed,
                     "agent_steps_per_cpu_s": steps * n_agents / cpu if cpu > 0 else None})
        _log(f"{peer} n={n_agents}: rep {i + 1}/{repetitions}: {steps} steps, "
             f"{steps * n_agents / elapsed:,.0f} agent-steps/s")
    rates = [r["agent_steps_per_s"] for r in reps]
    med = statistics.median(rates)
    return {
        "peer": peer,
        "version": metadata.version(peer),
        "agents": n_agents,
        "status": "ok",
        "agent_steps_per_s": med,
        "steps_per_s": med / n_agents,
        "agent_steps_per_s_min": min(rates),
        "agent_steps_per_s_max": max(rates),
        # Secondary: per second of this process's CPU time; less sensitive to other
        # processes competing for the cores, but not what a user waits for.
        "agent_steps_per_cpu_s": statistics.median(
            r["agent_steps_per_cpu_s"] for r in reps if r["agent_steps_per_cpu_s"]),
        "repetitions": repetitions,
        "min_rep_seconds": min_rep_seconds,
        "reps": reps,
        "warmup_steps": warm_steps,
        "build_seconds": build_s,
        "action_seed": seed,
        "env": params,
        "runtime": {
            "python": platform.python_version(),
            "numpy": np.__version__,
            **{d: metadata.version(d) for d in ("gymnasium", "networkx", "pydantic") if _has(d)},
        },
    }


def _has(dist: str) -> bool:
    try:
        metadata.version(dist)
        return True
    except metadata.PackageNotFoundError:
        return False


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--peer", choices=sorted(BUILDERS), required=True)
    ap.add_argument("--agents", type=int, required=True)
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--min-rep-seconds", type=float, default=1.0)
    ap.add_argument("--warmup-seconds", type=float, default=0.2)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args(argv)
    res = measure(a.peer, a.agents, a.repetitions, a.min_rep_seconds, a.warmup_seconds, a.seed)
    print(json.dumps(res), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
