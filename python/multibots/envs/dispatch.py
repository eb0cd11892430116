"""``multibots/Dispatch-v0``: one idle robot's decision per step (a ``gymnasium.Env``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Optional

import numpy as np

from multibots import _core
from multibots.envs._common import (
    ScenarioLike,
    as_obs,
    episode_scenario,
    gymnasium,
    is_seeded,
    next_seed,
    observation_space,
    resolve_scenario,
    spaces,
)


class DispatchEnv(gymnasium.Env):
    """The dispatcher: at each decision point, each idle robot in turn picks an action.

    Actions (``Discrete(max_queue + 2)``): ``k < max_queue`` takes the goods in queue slot
    ``k`` (front first), ``max_queue`` is "charge now", ``max_queue + 1`` is "wait". The
    observation's ``action_mask`` (also ``info["action_mask"]``) marks the allowed ones; "wait"
    is always allowed. The engine runs the fleet between decisions without returning to Python.

    Args:
        scenario: a :class:`multibots.Scenario`, a TOML path, a dict of fields, or None for the
            paper scenario (3 robots, TABLE III group 1). The paper rules only.
        max_queue: queue slots shown and selectable (1 to 1024).
        reward: weights replacing the default reward, the negative of Cost_total's increment
            with the scenario's ``[cost]`` weights: any of ``distance``, ``time``,
            ``collision``, ``charge`` (per charge), ``delivery`` (gained per delivery) and
            ``failure`` (a number, or ``"clock"``: ``time`` × steps left at a failed end).
        invalid: what a masked-out action does: ``"refuse"`` (raise
            :class:`multibots.DecisionError`, nothing changes) or ``"wait"`` (it counts as
            "wait"; ``info["invalid"]`` says so).
        render_mode: unused (watch runs with ``multibots view``).

    Episodes end ``terminated`` when the work is done (or the fleet can do nothing more:
    gridlock, stalled, stranded, livelock, with the failure penalty), and ``truncated`` at
    the step limit or the lifelong horizon.
    """

    metadata = {"render_modes": []}

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
        self._core = _core.Dispatcher(self.scenario._core, max_queue, dict(reward) if reward else None, invalid)
        self.robots = self._core.robots
        self.max_queue = max_queue
        self.action_space = spaces.Discrete(max_queue + 2)
        self.observation_space = observation_space(self.robots, max_queue)
        self.render_mode = render_mode
        self._fresh = True

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Starts an episode. With a seeded scenario (``multibots.envs.SEEDED``) each episode
        draws its tasks and orders from the environment's generator; ``options={"scenario": s}``
        runs another scenario with as many robots."""
        super().reset(seed=seed)
        base, seeded = self.scenario, self._seeded
        if options and options.get("scenario") is not None:
            base = resolve_scenario(options["scenario"])
            seeded = is_seeded(base)
        s = episode_scenario(base, next_seed(self.np_random)) if seeded else base
        # A new engine already stands at its scenario's first decision point. The engine
        # checks a new scenario (as many robots, the paper rules) before anything changes.
        if not (self._fresh and s is self.scenario):
            self._core.reset(s._core)
        self.scenario, self._seeded = base, seeded
        self._fresh = False
        return self._observe(False)

    def step(self, action: Any) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        reward, terminated, truncated, invalid = self._core.step(int(action))
        obs, info = self._observe(invalid)
        return obs, reward, terminated, truncated, info

    def _observe(self, invalid: bool) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        obs = as_obs(self._core.observe())
        info: dict[str, Any] = self._core.progress()
        info["action_mask"] = obs["action_mask"]
        info["robot"] = self._core.robot
        info["invalid"] = invalid
        if self._core.ended:
            info["outcome"] = self._core.result()["outcome"]
        return obs, info

    def result(self) -> dict[str, Any]:
        """The run's result so far, as ``multibots.simulate`` reports it (``docs/metrics.md``)."""
        return self._core.result()

    def action_masks(self) -> np.ndarray:
        """The current action mask (for libraries that ask the environment for it)."""
        return self._core.observe()[3]
