"""The fleet: one agent per robot (a PettingZoo ``ParallelEnv``), made by :func:`parallel_env`."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Optional

import numpy as np

from multibots import _core
from multibots.envs._common import (
    NO_ACTION,
    ScenarioLike,
    as_obs,
    episode_scenario,
    is_seeded,
    next_seed,
    observation_space,
    resolve_scenario,
    spaces,
    state_space,
)
from multibots.exceptions import MissingExtraError

try:
    from pettingzoo import ParallelEnv
except ImportError:  # pragma: no cover - exercised without the extra
    raise MissingExtraError("multibots.envs", "rl") from None


class FleetEnv(ParallelEnv):
    """Every robot is an agent (``robot_0``, ``robot_1``, ...); all act at each decision point.

    The robots that decide (idle ones) have the dispatcher's actions and mask; the others may
    only "wait" (their mask allows nothing else; a missing action counts as "wait" for them).
    Two robots that pick the same goods: the lower id takes them, the other waits
    (``info["conflict"]``). Each robot's reward is its own distance, collisions, charges and
    deliveries and an equal share of the time, so the fleet's rewards add up to the
    dispatcher's. ``state()`` is the global state (``state_space``). Arguments as
    :class:`multibots.envs.DispatchEnv`.
    """

    metadata = {"name": "multibots_fleet_v0", "render_modes": []}

    def __init__(
        self,
        scenario: ScenarioLike = None,
        *,
        max_queue: int = 10,
        reward: Optional[Mapping[str, Any]] = None,
        invalid: str = "refuse",
        render_mode: Optional[str] = None,
    ) -> None:
        self.scenario = resolve_scenario(scenario)
        self._seeded = is_seeded(self.scenario)
        self._core = _core.Fleet(self.scenario._core, max_queue, dict(reward) if reward else None, invalid)
        n = self._core.robots
        self.max_queue = max_queue
        self.render_mode = render_mode
        self.possible_agents = [f"robot_{i}" for i in range(n)]
        self.agents: list[str] = []
        obs_space = observation_space(n, max_queue)
        self.observation_spaces = {a: obs_space for a in self.possible_agents}
        self.action_spaces = {a: spaces.Discrete(max_queue + 2) for a in self.possible_agents}
        self.state_space = state_space(n, max_queue)
        self._rng = np.random.default_rng()
        self._fresh = True

    def observation_space(self, agent: str) -> spaces.Dict:
        return self.observation_spaces[agent]

    def action_space(self, agent: str) -> spaces.Discrete:
        return self.action_spaces[agent]

    def reset(
        self, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[dict[str, Any], dict[str, Any]]:
        """Starts an episode (seeds and ``options={"scenario": s}`` as the dispatcher's)."""
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        base, seeded = self.scenario, self._seeded
        if options and options.get("scenario") is not None:
            base = resolve_scenario(options["scenario"])
            seeded = is_seeded(base)
        s = episode_scenario(base, next_seed(self._rng)) if seeded else base
        # A new engine already stands at its scenario's first decision point. The engine
        # checks a new scenario (as many robots, the paper rules) before anything changes.
        if not (self._fresh and s is self.scenario):
            self._core.reset(s._core)
        self.scenario, self._seeded = base, seeded
        self._fresh = False
        self.agents = list(self.possible_agents)
        obs, infos = self._observe(None, None)
        return obs, infos

    def step(
        self, actions: Mapping[str, Any]
    ) -> tuple[dict[str, Any], dict[str, float], dict[str, bool], dict[str, bool], dict[str, Any]]:
        codes = np.full(len(self.possible_agents), NO_ACTION, dtype=np.int64)
        for agent, a in actions.items():
            codes[self.possible_agents.index(agent)] = int(a)
        rewards, invalid, conflict, terminated, truncated = self._core.step(codes)
        obs, infos = self._observe(invalid, conflict)
        live = self.agents
        rew = {a: float(rewards[i]) for i, a in enumerate(self.possible_agents) if a in live}
        terms = dict.fromkeys(live, terminated)
        truncs = dict.fromkeys(live, truncated)
        obs = {a: obs[a] for a in live}
        infos = {a: infos[a] for a in live}
        if terminated or truncated:
            self.agents = []
        return obs, rew, terms, truncs, infos

    def _observe(
        self, invalid: Optional[np.ndarray], conflict: Optional[np.ndarray]
    ) -> tuple[dict[str, Any], dict[str, Any]]:
        robot, fleet, queue, mask = self._core.observe()
        deciders = self._core.deciders()
        obs: dict[str, Any] = {}
        infos: dict[str, Any] = {}
        for i, a in enumerate(self.possible_agents):
            obs[a] = as_obs((robot[i], fleet[i], queue[i], mask[i]))
            infos[a] = {
                "action_mask": mask[i],
                "deciding": bool(deciders[i]),
                "invalid": bool(invalid[i]) if invalid is not None else False,
                "conflict": bool(conflict[i]) if conflict is not None else False,
            }
        return obs, infos

    def state(self) -> np.ndarray:
        """The global state: every robot's state, every queue slot, the run (``docs/learning.md``)."""
        return self._core.state()

    def result(self) -> dict[str, Any]:
        """The run's result so far (``docs/metrics.md``)."""
        return self._core.result()

    def close(self) -> None:
        pass


def parallel_env(scenario: ScenarioLike = None, **kwargs: Any) -> FleetEnv:
    """The fleet environment, as PettingZoo's own environments are made: ``parallel_env(...)``."""
    return FleetEnv(scenario, **kwargs)
