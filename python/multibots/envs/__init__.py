"""Learning environments: train allocation and charging policies with Gymnasium and PettingZoo.

Importing this module registers ``multibots/Dispatch-v0`` with Gymnasium::

    >>> import gymnasium as gym
    >>> import multibots.envs
    >>> env = gym.make("multibots/Dispatch-v0")        # the paper scenario
    >>> obs, info = env.reset(seed=0)
    >>> sorted(obs)
    ['action_mask', 'fleet', 'queue', 'robot']

- :class:`DispatchEnv`: one decision per call, the idle robot's (a ``gymnasium.Env``).
- :func:`parallel_env`: one agent per robot (a PettingZoo ``ParallelEnv``), with ``state()``.
- :class:`VectorDispatch`: many dispatchers per call, stepped without the GIL.
- :class:`PolicyAllocator`: a trained policy as a strategy for ``simulate`` and ``compare``.

Both environments take any scenario under the paper rules; ``rules = "original"`` is refused
(the authors' code hands out goods itself and takes no decisions). The observation, the
actions, the reward and the endings are documented in ``docs/learning.md``.
Gymnasium and PettingZoo are the ``rl`` extra: ``pip install 'multibots[rl]'``.
"""

from __future__ import annotations

from multibots.envs._common import FEATURES, NO_ACTION, SEEDED, episode_scenario
from multibots.envs.dispatch import DispatchEnv
from multibots.envs.fleet import FleetEnv, parallel_env
from multibots.envs.policy import LinearPolicy, PolicyAllocator
from multibots.envs.vector import VectorDispatch

__all__ = [
    "FEATURES",
    "NO_ACTION",
    "SEEDED",
    "DispatchEnv",
    "FleetEnv",
    "LinearPolicy",
    "PolicyAllocator",
    "VectorDispatch",
    "episode_scenario",
    "parallel_env",
]


def _register() -> None:
    from gymnasium.envs.registration import register, registry

    if "multibots/Dispatch-v0" not in registry:
        register(id="multibots/Dispatch-v0", entry_point="multibots.envs.dispatch:DispatchEnv")


_register()
