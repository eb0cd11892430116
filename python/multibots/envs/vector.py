"""Many dispatchers stepped in one call, without the GIL (a ``gymnasium.vector.VectorEnv``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Optional

import numpy as np

from multibots import _core
from multibots.envs._common import (
    ScenarioLike,
    episode_scenario,
    gymnasium,
    is_seeded,
    observation_space,
    resolve_scenario,
    spaces,
)
from multibots.exceptions import ScenarioError

_OBS = ("robot", "fleet", "queue", "action_mask")


class VectorDispatch(gymnasium.vector.VectorEnv):
    """``num_envs`` dispatchers (``multibots/Dispatch-v0``) stepped by one call.

    The engine steps every environment to its next decision without the GIL, on ``workers``
    threads (1: the calling thread; 0: one per core). Autoreset is Gymnasium's "next step":
    after an episode ends, the next ``step`` starts the following one, ignores that
    environment's action and pays it no reward. Observations are dicts of arrays with one
    row per environment; ``info`` holds ``action_mask``, ``robot`` (the deciding robot, -1 at
    an end), ``t`` and ``invalid``.

    Args:
        scenario: as :class:`DispatchEnv`; every environment runs it (seeded scenarios draw
            each environment's episodes from ``seed + k`` and then from the generator).
        num_envs: how many environments.
        workers: threads stepping them.
        max_queue, reward, invalid: as :class:`DispatchEnv`.
    """

    metadata = {
        "render_modes": [],
        "autoreset_mode": getattr(gymnasium.vector, "AutoresetMode", None) and gymnasium.vector.AutoresetMode.NEXT_STEP,
    }

    def __init__(
        self,
        scenario: ScenarioLike = None,
        num_envs: int = 8,
        *,
        workers: int = 1,
        max_queue: int = 10,
        reward: Optional[Mapping[str, Any]] = None,
        invalid: str = "refuse",
    ) -> None:
        if not isinstance(num_envs, int) or num_envs < 1:
            raise ScenarioError(f"num_envs = {num_envs!r}: must be 1 or more")
        self.scenario = resolve_scenario(scenario)
        self._seeded = is_seeded(self.scenario)
        self._core = _core.VectorDispatch(
            [self.scenario._core] * num_envs, max_queue, dict(reward) if reward else None, invalid, workers
        )
        self.num_envs = num_envs
        self.robots = self._core.robots
        self.max_queue = max_queue
        self.single_action_space = spaces.Discrete(max_queue + 2)
        self.single_observation_space = observation_space(self.robots, max_queue)
        self.action_space = spaces.MultiDiscrete(np.full(num_envs, max_queue + 2))
        self.observation_space = gymnasium.vector.utils.batch_space(self.single_observation_space, num_envs)
        self._rng = np.random.default_rng()

    def _draw(self, envs: Any, seed: Optional[int] = None) -> None:
        for k in envs:
            s = seed + int(k) if seed is not None else int(self._rng.integers(0, 2**63 - 1))
            self._core.set_next(int(k), episode_scenario(self.scenario, s)._core)

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        if self._seeded:
            self._draw(range(self.num_envs), seed)
        rows = self._core.reset()
        return {k: rows[k] for k in _OBS}, self._info(rows)

    def step(self, actions: Any) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        rows = self._core.step(np.asarray(actions, dtype=np.int64).reshape(self.num_envs))
        if self._seeded:
            self._draw(np.flatnonzero(rows["terminated"] | rows["truncated"]))
        obs = {k: rows[k] for k in _OBS}
        return obs, rows["reward"], rows["terminated"], rows["truncated"], self._info(rows)

    @staticmethod
    def _info(rows: dict[str, np.ndarray]) -> dict[str, Any]:
        return {
            "action_mask": rows["action_mask"],
            "robot": rows["robot_id"],
            "t": rows["t"],
            "invalid": rows["invalid"],
        }

    def result(self, k: int) -> dict[str, Any]:
        """Environment ``k``'s run so far (``docs/metrics.md``)."""
        return self._core.result(k)
