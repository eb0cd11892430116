"""Policies as strategies: what a learning environment trained, run by ``simulate`` and ``compare``."""

from __future__ import annotations

import os
from typing import Any, Callable

import numpy as np

from multibots.strategies import Allocator, AllocView, Answer

#: A policy: ``policy(robot, (robot, fleet, queue, action_mask)) -> action code``, the
#: observation parts as the dispatcher environment shows them.
Policy = Callable[[int, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]], int]


class PolicyAllocator(Allocator):
    """A dispatcher policy as a task-allocation strategy.

    At each allocation event the engine asks the policy for each idle robot's action, in the
    dispatcher environment's order and with the observations it shows (``docs/learning.md``),
    so a policy trained on ``multibots/Dispatch-v0`` does the same here. Subclass it with a
    no-argument constructor to name it in a scenario or on the command line
    (``multibots compare --strategies in-turn,path/to/file.py:MyPolicy``).

    Args:
        policy: the policy (see :data:`Policy`), or an object with an ``act`` method of that
            signature.
        max_queue: the queue slots it was trained with.
    """

    name = "policy"

    def __init__(self, policy: Any, max_queue: int = 10) -> None:
        self.policy: Policy = getattr(policy, "act", policy)
        self.max_queue = max_queue

    def allocate(self, view: AllocView) -> Answer:
        return view.decide(self.policy, self.max_queue)


class LinearPolicy:
    """A linear softmax policy over the dispatcher's actions: small, NumPy only.

    Each queue slot's score is ``w_goods · [queue row, robot row] + b_goods``; "charge now"
    and "wait" score ``w_charge · robot row + b_charge`` and ``w_wait · robot row +
    b_wait``. Masked-out actions get no probability. ``act`` takes the most likely action;
    ``probabilities`` gives the distribution a trainer samples from.
    """

    def __init__(self, params: np.ndarray | None = None, robot_features: int = 8, goods_features: int = 10) -> None:
        self.rf, self.gf = robot_features, goods_features
        self.params = (
            np.zeros(self.size(robot_features, goods_features))
            if params is None
            else np.asarray(params, dtype=np.float64)
        )

    @staticmethod
    def size(rf: int = 8, gf: int = 10) -> int:
        return (gf + rf + 1) + 2 * (rf + 1)

    def scores(self, robot: np.ndarray, queue: np.ndarray) -> np.ndarray:
        rf, gf, p = self.rf, self.gf, self.params
        wg, bg = p[: gf + rf], p[gf + rf]
        o = gf + rf + 1
        wc, bc, ww, bw = p[o : o + rf], p[o + rf], p[o + rf + 1 : o + 2 * rf + 1], p[o + 2 * rf + 1]
        goods = queue @ wg[:gf] + robot @ wg[gf:] + bg
        return np.concatenate([goods, [robot @ wc + bc, robot @ ww + bw]])

    def probabilities(self, robot: np.ndarray, queue: np.ndarray, mask: np.ndarray) -> np.ndarray:
        s = np.where(mask.astype(bool), self.scores(robot.astype(np.float64), queue.astype(np.float64)), -np.inf)
        s = np.exp(s - s.max())
        return s / s.sum()

    def act(self, robot_id: int, obs: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> int:
        robot, _fleet, queue, mask = obs
        s = np.where(mask.astype(bool), self.scores(robot.astype(np.float64), queue.astype(np.float64)), -np.inf)
        return int(np.argmax(s))

    def save(self, path: str | os.PathLike[str]) -> None:
        np.savez(path, params=self.params, robot_features=self.rf, goods_features=self.gf)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> LinearPolicy:
        with np.load(path) as z:
            return cls(z["params"], int(z["robot_features"]), int(z["goods_features"]))
