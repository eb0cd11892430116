"""What both environments share: the optional imports, scenarios, seeds and spaces."""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any, Union

import numpy as np

from multibots import _core
from multibots.exceptions import MissingExtraError, ScenarioError
from multibots.scenario import Scenario

try:
    import gymnasium
    from gymnasium import spaces
except ImportError:  # pragma: no cover - exercised without the extra
    raise MissingExtraError("multibots.envs", "rl") from None

__all__ = [
    "FEATURES",
    "NO_ACTION",
    "SEEDED",
    "ScenarioLike",
    "episode_scenario",
    "gymnasium",
    "observation_space",
    "spaces",
]

#: A scenario, a path to a scenario file, a dict of fields, or None for the paper scenario.
ScenarioLike = Union[Scenario, str, "os.PathLike[str]", Mapping[str, Any], None]

#: The features of each observation part, as ``(name, low, high)`` rows, in order: ``robot``
#: (the deciding robot), ``fleet`` (one row per robot), ``queue`` (one row per queue slot),
#: and the global state's ``state_robot``, ``state_goods`` and ``state_run``.
FEATURES: dict[str, list[tuple[str, float, float]]] = _core.observation_features()

#: The fleet environment's engine code for "no action" (robots that do not decide).
NO_ACTION: int = _core.no_action()

#: What a seed changes: the draw of ``tasks = { random = K, seed }`` and the order stream's
#: ``orders.seed``. A scenario with neither (the paper's fixed task lists) runs the same
#: episode every time, whatever the seed.
SEEDED = ("tasks.seed", "orders.seed")


def resolve_scenario(scenario: ScenarioLike) -> Scenario:
    """The scenario an environment runs: the paper scenario (3 robots, TABLE III group 1) by default."""
    if scenario is None:
        return Scenario.paper()
    if isinstance(scenario, Scenario):
        return scenario
    if isinstance(scenario, (str, os.PathLike)):
        return Scenario.from_toml(scenario)
    if isinstance(scenario, Mapping):
        return Scenario.from_dict(scenario)
    raise ScenarioError(f"scenario = {type(scenario).__name__}: expected a Scenario, a TOML path, a dict or None")


def is_seeded(scenario: Scenario) -> bool:
    """Whether a seed changes the scenario's episodes (:data:`SEEDED`)."""
    d = scenario.to_dict()
    return isinstance(d.get("tasks"), dict) or "orders" in d


def episode_scenario(scenario: Scenario, seed: int) -> Scenario:
    """The scenario with its random task list and order stream drawn from ``seed``."""
    d = scenario.to_dict()
    changes: dict[str, Any] = {}
    if isinstance(d.get("tasks"), dict):
        changes["tasks"] = {**d["tasks"], "seed": int(seed)}
    if "orders" in d:
        changes["orders"] = {"seed": int(seed)}
    return scenario.replace(**changes) if changes else scenario


def next_seed(rng: np.random.Generator) -> int:
    return int(rng.integers(0, 2**63 - 1))


def box(rows: list[tuple[str, float, float]], lead: tuple[int, ...] = ()) -> spaces.Box:
    low = np.array([r[1] for r in rows], dtype=np.float32)
    high = np.array([r[2] for r in rows], dtype=np.float32)
    shape = (*lead, len(rows))
    return spaces.Box(np.broadcast_to(low, shape).copy(), np.broadcast_to(high, shape).copy(), dtype=np.float32)


def observation_space(robots: int, max_queue: int) -> spaces.Dict:
    """A decider's observation: ``robot``, ``fleet``, ``queue`` and ``action_mask``."""
    return spaces.Dict(
        {
            "robot": box(FEATURES["robot"]),
            "fleet": box(FEATURES["fleet"], (robots,)),
            "queue": box(FEATURES["queue"], (max_queue,)),
            "action_mask": spaces.Box(0, 1, (max_queue + 2,), dtype=np.int8),
        }
    )


def state_space(robots: int, max_queue: int) -> spaces.Box:
    """The global state: every robot's row, every slot's row, the run's row, flattened."""
    parts = [
        box(FEATURES["state_robot"], (robots,)),
        box(FEATURES["state_goods"], (max_queue,)),
        box(FEATURES["state_run"]),
    ]
    low = np.concatenate([p.low.ravel() for p in parts])
    high = np.concatenate([p.high.ravel() for p in parts])
    return spaces.Box(low, high, dtype=np.float32)


def as_obs(parts: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> dict[str, np.ndarray]:
    robot, fleet, queue, mask = parts
    return {"robot": robot, "fleet": fleet, "queue": queue, "action_mask": mask}
