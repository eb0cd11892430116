"""What a run produced: the indicators T, S and C, and per-robot statistics."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["LIFELONG_KEYS", "Result", "STATE_NAMES"]

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

#: The figures of a lifelong run (``Result.lifelong``), in the order the engine gives them.
LIFELONG_KEYS: tuple[str, ...] = (
    "ordered",
    "delivered",
    "in_flight",
    "queued",
    "waiting",
    "throughput",
    "latency_p50",
    "latency_p95",
    "latency_p99",
    "latency_mean",
    "utilisation",
    "energy_per_delivery",
)

# Decimals kept by ``to_dict(rounded=True)``: px to 1/100 px, energy to 1e-6 of a unit (the
# consumption per step is 0.005 by default), ratios and rates to 4 and 3 decimals. Enough to
# tell any two runs apart, without the float noise of sums (8.080000000000169).
_DECIMALS = {
    "distance": 2,
    "energy_used": 6,
    "energy_per_delivery": 6,
    "throughput": 3,
    "latency_mean": 3,
    "utilisation": 4,
}


def _rounded(key: str, value: Any) -> Any:
    digits = _DECIMALS.get(key)
    if digits is None:
        return value
    if isinstance(value, list):
        return [round(float(v), digits) for v in value]
    return None if value is None else round(float(value), digits)


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
            counts (ordered = delivered + in_flight + queued + waiting), the keys of
            :data:`LIFELONG_KEYS`; None otherwise.
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

    def to_dict(self, rounded: bool = False) -> dict[str, Any]:
        """The result as plain JSON-ready values; per-robot figures under ``robots``.

        The shape is the same for every run: ``lifelong`` always holds every key of
        :data:`LIFELONG_KEYS`, each None for a run without orders.

        Args:
            rounded: round distances, energies and rates to a sensible number of decimals
                (``multibots run --json`` does), instead of the engine's exact floats.
        """
        robots: dict[str, Any] = {k: getattr(self, k).tolist() for k in _ARRAYS if k != "state_steps"}
        robots["state_steps"] = {name: self.state_steps[:, i].tolist() for i, name in enumerate(STATE_NAMES)}
        lifelong = dict.fromkeys(LIFELONG_KEYS) if self.lifelong is None else dict(self.lifelong)
        if rounded:
            robots = {k: _rounded(k, v) for k, v in robots.items()}
            lifelong = {k: _rounded(k, v) for k, v in lifelong.items()}
        return {
            "T": self.T,
            "S": self.S,
            "C": self.C,
            "outcome": self.outcome,
            "steps": self.steps,
            "delivered": self.delivered,
            "goods_total": self.goods_total,
            "stranded": list(self.stranded),
            "lifelong": lifelong,
            "robots": robots,
        }

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Result) and self.to_dict() == other.to_dict()

    def __repr__(self) -> str:
        return (
            f"Result(T={self.T}, S={self.S}, C={self.C}, outcome={self.outcome!r}, "
            f"delivered={self.delivered}/{self.goods_total})"
        )
