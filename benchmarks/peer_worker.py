"""Measure one peer simulator (rware or pogema) at one agent count, with and without its observations.

This file runs *inside the peers' virtual environment* (.venv-peers, made by
benchmarks/peers.py), never in the project's own environment: rware and pogema pin
numpy<2, pydantic 1 and gymnasium 0.28, which clash with the project's dependencies.
It imports nothing from the project.

    .venv-peers/bin/python benchmarks/peer_worker.py --peer rware --agents 100 --cells-per-agent 4.13
    .venv-peers/bin/python benchmarks/peer_worker.py --peer pogema --agents 1000 --warehouse 12,25,2,8

prints one JSON object on its last stdout line (see `measure`). Progress goes to stderr.

Layouts (free cells per agent, the density every figure depends on):

- pogema, `--warehouse R,C,W,H`: our own generated warehouse as a pogema map: R x C storage
  groups of W x H cells between aisles one cell wide; aisle cells are free, storage cells
  are obstacles. So pogema's agents get exactly our free cells, in our geometry (pogema
  lets agents move both ways in every aisle; ours are one-way).
- pogema, `--cells-per-agent X` without `--warehouse`: a random map, 30% obstacles
  (pogema's default), sized for X free cells per agent.
- rware, `--cells-per-agent X`: rware's own shelf layout, sized for about X cells per agent.
  Every rware cell is free to an agent that carries no shelf (agents drive under shelves),
  so all cells count.

Method: build the environment, reset it with a fixed seed, take warm-up steps, then time
`repetitions` rounds on the same episode. A round runs the peer's full `step` (with its
per-agent observations) for at least `min_rep_seconds` of wall time, and the same `step`
with the observations switched off for as long again, in alternating order (ABBA), so
both see the same load. "Switched off" means the method that builds one agent's
observation (rware `Warehouse._make_obs`) or all of them (pogema `Pogema._obs`) is
replaced, on this instance, by one that returns None: everything else the step does
(moves, collisions, goals, rewards, infos, wrappers) still runs. Neither peer offers a
cheaper legal observation setting (pogema's "POMAPF"/"MAPF" types build the same
windows and more; rware's image observations cost more), so this is the step without
observations, measured, not estimated.

Each step draws one uniformly random action per agent from a seeded numpy Generator
(inside the timed loop, as a random policy would). Episodes never end during the
measurement (no time limit), so no reset is timed.

Cell moves: after the timed rounds, an untimed pass of the same episode (at least
`count_seconds`, at least one step) compares every agent's cell before and after each
step; moves_per_agent_step is moved agents / agent-steps there, and the cell-move rates
are the agent-step rates times it. Random actions include standing still (both), turns
and load/unload (rware: only FORWARD moves), and moves refused by walls, obstacles and
other agents.
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

# rware's registered layouts all use column height 8; small fleets may use less (see rware_layout).
RWARE_COLUMN_HEIGHT = 8
# pogema's default random-obstacle density (random maps only).
POGEMA_OBSTACLE_DENSITY = 0.3

N_ACTIONS = 5  # both peers: rware NOOP/FORWARD/LEFT/RIGHT/TOGGLE_LOAD, pogema stay + 4 moves


def _log(msg: str) -> None:
    print(f"[peer_worker] {msg}", file=sys.stderr, flush=True)


def rware_layout(n_agents: int, cells_per_agent: float) -> dict[str, int]:
    """rware's shelf rows/columns/column height for about `cells_per_agent` cells per agent.

    rware's grid is height (column_height + 1) * shelf_rows + 2 by width
    3 * shelf_columns + 1 (shelf_columns odd, at least 3 here as in rware's "tiny").
    Column height 8 (rware's registered layouts) when a layout with it comes within 3% of
    the target cells, else whichever column height (8 down to 4) comes closest; near-square.
    """
    target = cells_per_agent * n_agents
    best: tuple[tuple[float, bool, float, float], dict[str, int]] | None = None
    for ch in range(RWARE_COLUMN_HEIGHT, 3, -1):
        h_per_row = ch + 1
        # near-square: height ~ h_per_row * r, width ~ 3 * c; cells ~ (h_per_row * r) ** 2
        r0 = max(1, round(math.sqrt(target / (h_per_row * h_per_row))))
        for rows in {max(1, r0 - 1), r0, r0 + 1}:
            height = h_per_row * rows + 2
            cols_f = (target / height - 1) / 3
            for cols in range(max(3, int(cols_f) - 3), int(cols_f) + 4):
                if cols % 2 == 0:
                    continue
                width = 3 * cols + 1
                cells = height * width
                if cells < n_agents:
                    continue
                # closeness to the target (within 3% counts as equal), then ch = 8, then squareness
                err = abs(cells - target) / target
                score = (max(0.0, err - 0.03), ch != RWARE_COLUMN_HEIGHT, err, abs(math.log(height / width)))
                if best is None or score < best[0]:
                    best = (score, {"shelf_rows": rows, "shelf_columns": cols, "column_height": ch,
                                    "grid_height": height, "grid_width": width})
    if best is None:
        raise ValueError(f"no rware layout for {n_agents} agents at {cells_per_agent} cells each")
    return best[1]


def warehouse_map(rows: int, cols: int, width: int, height: int) -> list[str]:
    """Our generated warehouse (docs/layout-format.md) as text rows: '.' aisle, '#' storage.

    R x C groups of W x H cells, aisles one cell wide around and between them (aisle width =
    cell size, as in every named size), so the map is (C + 1 + C W) x (R + 1 + R H) cells.
    """
    out = []
    for y in range(rows * (height + 1) + 1):
        aisle_row = y % (height + 1) == 0
        out.append("".join("." if aisle_row or x % (width + 1) == 0 else "#"
                           for x in range(cols * (width + 1) + 1)))
    return out


def pogema_size(n_agents: int, cells_per_agent: float) -> int:
    """Square random-map side so that free (non-obstacle) cells per agent ~ cells_per_agent."""
    return max(8, math.ceil(math.sqrt(cells_per_agent * n_agents / (1 - POGEMA_OBSTACLE_DENSITY))))


class Peer:
    """A built environment: step(actions), observations on/off, and who moved."""

    step: Callable[[list[int]], Any]
    params: dict[str, Any]

    def observations(self, on: bool) -> None:
        raise NotImplementedError

    def cells(self) -> list[tuple[int, int]]:
        raise NotImplementedError


class Rware(Peer):
    def __init__(self, n_agents: int, seed: int, cells_per_agent: float) -> None:
        from rware.warehouse import RewardType, Warehouse

        lay = rware_layout(n_agents, cells_per_agent)
        # As rware's registered "rware-<size>-<N>ag-v2" tasks (normal difficulty): msg_bits 0,
        # sensor_range 1, request queue = number of agents, individual rewards, flattened
        # observations; but no episode limit (max_steps None), so the measurement never resets.
        kwargs: dict[str, Any] = dict(
            shelf_columns=lay["shelf_columns"], column_height=lay["column_height"],
            shelf_rows=lay["shelf_rows"], n_agents=n_agents, msg_bits=0, sensor_range=1,
            request_queue_size=n_agents, max_inactivity_steps=None, max_steps=None,
            reward_type=RewardType.INDIVIDUAL,
        )
        self.env = env = Warehouse(**kwargs)
        assert all(sp.n == N_ACTIONS for sp in env.action_space.spaces)
        env.reset(seed=seed)
        self.step = env.step
        cells = lay["grid_height"] * lay["grid_width"]
        self.params = {
            "class": "rware.warehouse.Warehouse",
            **{k: v for k, v in kwargs.items() if k != "reward_type"},
            "reward_type": "INDIVIDUAL", "observation_type": "FLATTENED",
            "layout": "rware shelves",
            "grid": [lay["grid_height"], lay["grid_width"]], "cells": cells,
            "shelves": len(env.shelfs), "free_cells": cells,
            "free_cells_per_agent": round(cells / n_agents, 2), "reset_seed": seed,
        }

    def observations(self, on: bool) -> None:
        if on:
            self.env.__dict__.pop("_make_obs", None)
        else:
            self.env._make_obs = lambda agent: None  # one agent's observation, per agent per step

    def cells(self) -> list[tuple[int, int]]:
        return [(a.x, a.y) for a in self.env.agents]


class Pogema(Peer):
    def __init__(self, n_agents: int, seed: int, cells_per_agent: float,
                 warehouse: tuple[int, int, int, int] | None) -> None:
        from pogema import GridConfig, pogema_v0

        cfg: dict[str, Any] = dict(
            num_agents=n_agents, seed=seed,
            on_target="restart",  # lifelong: a new goal on arrival, agents never leave
            collision_system="priority", obs_radius=5, observation_type="default",
            max_episode_steps=10**9,  # no truncation during the measurement
        )
        if warehouse:
            rows = warehouse_map(*warehouse)
            cfg["map"] = "\n".join(rows)
            free = sum(r.count(".") for r in rows)
            grid = [len(rows), len(rows[0])]
            layout = "our warehouse {}x{} groups of {}x{}".format(*warehouse)
        else:
            size = pogema_size(n_agents, cells_per_agent)
            cfg.update(size=size, density=POGEMA_OBSTACLE_DENSITY)
            free = int(round(size * size * (1 - POGEMA_OBSTACLE_DENSITY)))
            grid = [size, size]
            layout = f"random, obstacles {POGEMA_OBSTACLE_DENSITY:.0%}"
        self.env = env = pogema_v0(grid_config=GridConfig(**cfg))
        assert env.action_space.n == N_ACTIONS
        env.reset(seed=seed)
        self.base = env.unwrapped
        self.step = env.step
        shown = {k: v for k, v in cfg.items() if k != "map"}
        self.params = {
            "class": "pogema.pogema_v0 (PogemaLifeLong + wrappers)", **shown,
            "layout": layout, "grid": grid, "cells": grid[0] * grid[1], "free_cells": free,
            "free_cells_per_agent": round(free / n_agents, 2), "reset_seed": seed,
        }

    def observations(self, on: bool) -> None:
        if on:
            self.base.__dict__.pop("_obs", None)
        else:
            self.base._obs = lambda: None  # all agents' observations, once per step

    def cells(self) -> list[tuple[int, int]]:
        return [tuple(p) for p in self.base.grid.positions_xy]


def build(peer: str, n_agents: int, seed: int, cells_per_agent: float,
          warehouse: tuple[int, int, int, int] | None) -> Peer:
    if peer == "rware":
        return Rware(n_agents, seed, cells_per_agent)
    if peer == "pogema":
        return Pogema(n_agents, seed, cells_per_agent, warehouse)
    raise ValueError(peer)


def measure(
    peer: str,
    n_agents: int,
    cells_per_agent: float,
    warehouse: tuple[int, int, int, int] | None = None,
    repetitions: int = 5,
    min_rep_seconds: float = 1.0,
    warmup_seconds: float = 0.2,
    count_seconds: float = 1.0,
    seed: int = 0,
) -> dict[str, Any]:
    import numpy as np

    warnings.simplefilter("ignore")  # gymnasium's passive checker and deprecation chatter
    t0 = time.perf_counter()
    env = build(peer, n_agents, seed, cells_per_agent, warehouse)
    build_s = time.perf_counter() - t0
    params = env.params
    _log(f"{peer} n={n_agents}: built and reset in {build_s:.2f} s; grid {params['grid']}, "
         f"{params['free_cells_per_agent']} free cells per agent")

    rng = np.random.default_rng(seed)

    def run(min_seconds: float) -> tuple[int, float, float]:
        steps = 0
        step = env.step
        cpu0 = time.process_time()
        start = time.perf_counter()
        while True:
            step(rng.integers(0, N_ACTIONS, size=n_agents).tolist())
            steps += 1
            elapsed = time.perf_counter() - start
            if elapsed >= min_seconds:
                return steps, elapsed, time.process_time() - cpu0

    env.observations(True)
    warm_steps, warm_s, _ = run(warmup_seconds)
    _log(f"{peer} n={n_agents}: warm-up {warm_steps} steps in {warm_s:.2f} s")
    reps: dict[bool, list[dict[str, Any]]] = {True: [], False: []}
    for i in range(repetitions):
        for obs in ((True, False) if i % 2 == 0 else (False, True)):
            env.observations(obs)
            steps, elapsed, cpu = run(min_rep_seconds)
            reps[obs].append({"steps": steps, "seconds": elapsed, "cpu_seconds": cpu,
                              "agent_steps_per_s": steps * n_agents / elapsed,
                              "agent_steps_per_cpu_s": steps * n_agents / cpu if cpu > 0 else None})
        _log(f"{peer} n={n_agents}: round {i + 1}/{repetitions}: "
             f"{reps[True][-1]['agent_steps_per_s']:,.0f} agent-steps/s with observations, "
             f"{reps[False][-1]['agent_steps_per_s']:,.0f} without")

    # Untimed: who moved, on the same episode (observations do not change the dynamics).
    env.observations(False)
    moved = count_steps = 0
    start = time.perf_counter()
    while count_steps == 0 or time.perf_counter() - start < count_seconds:
        before = env.cells()
        env.step(rng.integers(0, N_ACTIONS, size=n_agents).tolist())
        moved += sum(a != b for a, b in zip(before, env.cells()))
        count_steps += 1
    env.observations(True)
    moves = moved / (count_steps * n_agents)
    _log(f"{peer} n={n_agents}: {moves:.3f} cell moves per agent-step over {count_steps} steps")

    def summary(rs: list[dict[str, Any]]) -> dict[str, float]:
        rates = [r["agent_steps_per_s"] for r in rs]
        return {"median": statistics.median(rates), "min": min(rates), "max": max(rates),
                "cpu": statistics.median(r["agent_steps_per_cpu_s"] for r in rs if r["agent_steps_per_cpu_s"])}

    on, off = summary(reps[True]), summary(reps[False])
    return {
        "peer": peer,
        "version": metadata.version(peer),
        "agents": n_agents,
        "status": "ok",
        # with the peer's observations (its full step), median over the rounds
        "agent_steps_per_s": on["median"],
        "steps_per_s": on["median"] / n_agents,
        "agent_steps_per_s_min": on["min"],
        "agent_steps_per_s_max": on["max"],
        # Secondary: per second of this process's CPU time; less sensitive to other
        # processes competing for the cores, but not what a user waits for.
        "agent_steps_per_cpu_s": on["cpu"],
        # the same step with the observations switched off
        "agent_steps_per_s_no_obs": off["median"],
        "agent_steps_per_s_no_obs_min": off["min"],
        "agent_steps_per_s_no_obs_max": off["max"],
        "agent_steps_per_cpu_s_no_obs": off["cpu"],
        # share of the full step's time spent on observations: 1 - time without / time with
        "observation_share": 1 - on["median"] / off["median"],
        "moves_per_agent_step": moves,
        "count_steps": count_steps,
        "cell_moves_per_s": on["median"] * moves,
        "cell_moves_per_s_no_obs": off["median"] * moves,
        "repetitions": repetitions,
        "min_rep_seconds": min_rep_seconds,
        "reps": reps[True],
        "reps_no_obs": reps[False],
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
    ap.add_argument("--peer", choices=("pogema", "rware"), required=True)
    ap.add_argument("--agents", type=int, required=True)
    ap.add_argument("--cells-per-agent", type=float, required=True,
                    help="free cells per agent (rware's layout; pogema's random map)")
    ap.add_argument("--warehouse", default=None,
                    help="pogema only: our warehouse R,C,W,H as the map (overrides --cells-per-agent)")
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--min-rep-seconds", type=float, default=1.0)
    ap.add_argument("--warmup-seconds", type=float, default=0.2)
    ap.add_argument("--count-seconds", type=float, default=1.0)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args(argv)
    wh = tuple(int(v) for v in a.warehouse.split(",")) if a.warehouse else None
    if wh is not None and len(wh) != 4:
        ap.error("--warehouse takes R,C,W,H")
    res = measure(a.peer, a.agents, a.cells_per_agent, wh, a.repetitions, a.min_rep_seconds,
                  a.warmup_seconds, a.count_seconds, a.seed)  # type: ignore[arg-type]
    print(json.dumps(res), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
