"""What a run produced: the indicators T, S and C, and per-robot statistics."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["Result", "STATE_NAMES"]

#: Robot state names, indexed by the state codes of ``Simulation.states`` and replays.
STATE_NAMES: tuple[str, ...] = (
    "IDLE",
    "TO_PICKUP",
    "LOADING",
    "TO_DROP",
    "UNLOADING",
    "TO_CHARGER",
    "CHARGING",
    "TO_HOME",
    "PARKED",
    "STRANDED",
    "WAIT_CHARGER",
)

_ARRAYS = ("distance", "wait_steps", "collisions", "energy_used", "robot_delivered", "charges", "state_steps")


class Result:
    """The outcome of one run.

    Attributes:
        T: task time in steps, or None when the run is incomplete.
        S: collisions (waits begun).
        C: charging count.
        outcome: "complete" or "incomplete".
        steps: steps run.
        delivered: goods delivered; goods_total: goods in the task list.
        stranded: ids of robots that ran out of energy.
        lifelong: for lifelong runs (``[orders]``), throughput (deliveries per 1,000 steps),
            latency_p50/p95/p99/mean (steps), utilisation, energy_per_delivery and the order
            counts (ordered = delivered + in_flight + queued + waiting); None otherwise.
        distance, wait_steps, collisions, energy_used, robot_delivered, charges: one value
            per robot (NumPy arrays); state_steps: (N, 11) steps ending in each state.
    """

    __slots__ = ("T", "S", "C", "outcome", "steps", "delivered", "goods_total", "stranded", "lifelong", *_ARRAYS)

    T: int | None
    S: int
    C: int
    outcome: str
    steps: int
    delivered: int
    goods_total: int
    stranded: list[int]
    lifelong: dict[str, Any] | None
    distance: np.ndarray
    wait_steps: np.ndarray
    collisions: np.ndarray
    energy_used: np.ndarray
    robot_delivered: np.ndarray
    charges: np.ndarray
    state_steps: np.ndarray

    def __init__(self, raw: dict[str, Any]) -> None:
        for key in self.__slots__:
            value = raw.get(key)
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
            object.__setattr__(self, key, value)

    @property
    def complete(self) -> bool:
        """Whether every goods was delivered and every robot got home."""
        return self.outcome == "complete"

    def to_dict(self) -> dict[str, Any]:
        """The result as plain JSON-ready values; per-robot figures under ``robots``."""
        robots = {k: getattr(self, k).tolist() for k in _ARRAYS if k != "state_steps"}
        robots["state_steps"] = {name: self.state_steps[:, i].tolist() for i, name in enumerate(STATE_NAMES)}
        return {
            "T": self.T,
            "S": self.S,
            "C": self.C,
            "outcome": self.outcome,
            "steps": self.steps,
            "delivered": self.delivered,
            "goods_total": self.goods_total,
            "stranded": list(self.stranded),
            "lifelong": self.lifelong,
            "robots": robots,
        }

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Result) and self.to_dict() == other.to_dict()

    def __repr__(self) -> str:
        return f"Result(T={self.T}, S={self.S}, C={self.C}, outcome={self.outcome!r}, delivered={self.delivered}/{self.goods_total})"
