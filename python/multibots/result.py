"""What a run produced: the indicators T, S and C, and per-robot statistics."""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from multibots._core import STATE_NAMES as _STATE_NAMES

__all__ = [
    "FLOW_KEYS", "LIFELONG_KEYS", "OUTCOMES", "PEOPLE_KEYS", "Result", "STATE_NAMES", "bottleneck_line", "people_costs",
]

#: Robot state names, indexed by the state codes of ``Simulation.states`` and replays (the
#: engine's own names).
STATE_NAMES: tuple[str, ...] = tuple(_STATE_NAMES)

#: How a run can end. ``complete``: every goods delivered and every robot home;
#: ``horizon``: a lifelong run reached its horizon; ``incomplete``: the step limit came first;
#: ``gridlock``: nothing moved for ``metrics.gridlock`` steps while robots waited at
#: collisions; ``stranded``: robots ran out of energy and the rest could do nothing, or (at
#: the horizon, orders waiting) any robot is out of energy; ``stalled``: nothing happened
#: while robots stood idle with work left; ``collapse``: a lifelong run reached its horizon
#: with its last windows each under a tenth of the best while orders waited; ``livelock``:
#: robots moved but nothing was picked up or delivered for two battery cycles.
OUTCOMES: tuple[str, ...] = (
    "complete", "horizon", "incomplete", "gridlock", "stranded", "stalled", "collapse", "livelock",
)

#: How well the fleet flowed, for every run (docs/metrics.md): deliveries per window,
#: throughput after the warm-up and sustained over the last half, the shares of robot-steps
#: spent waiting and working, contacts, and where a gridlock happened.
FLOW_KEYS: tuple[str, ...] = (
    "window",
    "windows",
    "throughput",
    "sustained_throughput",
    "wait_share",
    "utilisation",
    "contacts",
    "closest",
    "gridlock",
    "collapse",
    "resources",
    "bottleneck",
)

_ARRAYS = ("distance", "wait_steps", "collisions", "energy_used", "robot_delivered", "charges", "state_steps")

#: The safety figures of a run with people (``Result.people``, docs/people.md).
PEOPLE_KEYS = (
    "count", "min_gap", "gap_p1", "contacts", "protective_stops", "stopped_steps", "warning_steps",
    "person_wait_steps", "person_steps", "tours", "picks", "walk_steps", "blocked_steps", "protective_radius",
    "warning_radius", "px_per_m", "step_seconds", "alone",
)


def people_costs(people: dict[str, Any]) -> dict[str, Optional[float]]:
    """What robots cost people (docs/people.md): per worker-hour (steps read as seconds by the
    run's ``step_seconds``, docs/model.md "Units"), the picks and tours, and the shares of
    their time spent walking and held up (``blocked_steps``); then the same, ``alone_``, for the same
    people over the same steps with the fleet removed (``people["alone"]``)."""

    def rates(p: dict[str, Any]) -> dict[str, Optional[float]]:
        steps = p["person_steps"]
        hours = steps * p["step_seconds"] / 3600.0
        return {
            "picks_per_hour": p["picks"] / hours if hours else None,
            "tours_per_hour": p["tours"] / hours if hours else None,
            "walk_share": p["walk_steps"] / steps if steps else None,
            "blocked_share": p["blocked_steps"] / steps if steps else None,
        }

    alone = people.get("alone")
    mine = rates(people)
    other = rates(alone) if alone else dict.fromkeys(mine)
    return {**mine, **{f"alone_{k}": v for k, v in other.items()}}

def bottleneck_line(b: Optional[dict[str, Any]], outcome: Optional[str] = None) -> str:
    """A run's bottleneck (``Result.bottleneck``, docs/metrics.md) in one line: the resource,
    its busy share, its mean and longest queue, and what would relieve it; or, with none,
    what the truth is instead: the fleet stranded out of energy, or no resource saturated.
    ``multibots run`` prints it, and the viewer shows it."""
    if b is None:
        if outcome == "stranded":
            return ("stranded: energy (robots ran out of energy with work left; the warning before the run, if any, "
                    "gives the numbers: docs/charging.md)")
        return ("no saturated resource (none busy half the steps with a queue that stays; the fleet's size and the "
                "orders set the pace)")
    return (
        f"{b['kind']} {b['node']}: busy {b['busy']:.0%} of steps, queue {b['mean_queue']:.1f} on average"
        f" ({b['longest_queue']} at most); relieve it with {b['relieve']}"
    )


#: The figures of a lifelong run (``Result.lifelong``), in the order the engine gives them.
LIFELONG_KEYS: tuple[str, ...] = (
    "ordered",
    "delivered",
    "in_flight",
    "queued",
    "waiting",
    "latency_p50",
    "latency_p95",
    "latency_p99",
    "latency_mean",
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
    "sustained_throughput": 3,
    "latency_mean": 3,
    "utilisation": 4,
    "wait_share": 4,
    "closest": 3,
    "cost": 2,
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
        outcome: how the run ended, one of :data:`OUTCOMES`.
        steps: steps run.
        delivered: goods delivered; goods_total: goods in the task list.
        stranded: ids of robots that ran out of energy.
        cost: Cost_total = w_d * distance + w_t * T + w_c * S with the scenario's weights,
            or None when the run is incomplete.
        window, windows, throughput, sustained_throughput, wait_share, utilisation,
            contacts, closest, gridlock: how the fleet flowed (:data:`FLOW_KEYS`,
            docs/metrics.md): deliveries in each complete window of ``window`` steps,
            deliveries per 1,000 steps after the warm-up and over the last half of the
            windows, the shares of robot-steps spent waiting and working on orders, pairs of
            robots closer than r_i + r_j after each step and the closest approach, for a
            gridlock the step, the waiting robots and the crossings where they wait, and
            for a collapse or stranded robots (outcomes ``collapse`` and ``stranded``) the step
            it began (for robots stranded while the windows held, the step the first ran
            out), the best and last windows, the stranded robots and where robots stood;
            resources: each unloading zone, charger, the charger queue and the busiest
            crossings and lanes with kind, node, busy share, mean and longest queue; bottleneck: the
            one that limits the fleet, with ``relieve`` (what would relieve it), or None.
        lifelong: for lifelong runs (``[orders]``), latency_p50/p95/p99/mean (steps),
            energy_per_delivery and the order counts (ordered = delivered + in_flight +
            queued + waiting), the keys of :data:`LIFELONG_KEYS`; None otherwise.
        people: for runs with people (``[humans]``, docs/people.md), the safety figures, the
            keys of :data:`PEOPLE_KEYS`: min_gap and gap_p1 (person-robot gap, px, smallest
            and 1st percentile), contacts, protective_stops, stopped_steps, warning_steps,
            person_wait_steps, person_steps, tours, picks, walk_steps, blocked_steps, the
            zones' radii, px_per_m and step_seconds, and alone: the same figures of the same
            people over the same steps with the fleet removed (:func:`people_costs` reads
            them per worker-hour); None otherwise.
        distance, wait_steps, collisions, energy_used, robot_delivered, charges: one value
            per robot (NumPy arrays); state_steps: (N, 11) steps ending in each state.
    """

    __slots__ = (
        "T", "S", "C", "outcome", "steps", "delivered", "goods_total", "stranded", "cost", *FLOW_KEYS, "lifelong",
        "people", *_ARRAYS,
    )

    T: int | None
    S: int
    C: int
    outcome: str
    steps: int
    delivered: int
    goods_total: int
    stranded: list[int]
    cost: float | None
    window: int
    windows: list[int]
    throughput: float | None
    sustained_throughput: float | None
    wait_share: float
    utilisation: float
    contacts: int
    closest: float | None
    gridlock: dict[str, Any] | None
    collapse: dict[str, Any] | None
    resources: list[dict[str, Any]]
    bottleneck: dict[str, Any] | None
    lifelong: dict[str, Any] | None
    people: dict[str, Any] | None
    distance: np.ndarray
    wait_steps: np.ndarray
    collisions: np.ndarray
    energy_used: np.ndarray
    robot_delivered: np.ndarray
    charges: np.ndarray
    state_steps: np.ndarray

    def __init__(self, raw: dict[str, Any]) -> None:
        # A batch makes one per run: the arrays are the only fields to freeze.
        get = raw.get
        for key in self.__slots__:
            object.__setattr__(self, key, get(key))
        for key in _ARRAYS:
            value = get(key)
            if isinstance(value, np.ndarray):
                value.setflags(write=False)

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
        people = dict.fromkeys(PEOPLE_KEYS) if self.people is None else dict(self.people)
        flow = {k: getattr(self, k) for k in FLOW_KEYS}
        flow["windows"] = list(self.windows)
        if self.gridlock is not None:
            g = self.gridlock
            crossings = [list(c) for c in g["crossings"]]
            flow["gridlock"] = {"step": g["step"], "waiting": list(g["waiting"]), "crossings": crossings}
        flow["resources"] = [dict(u) for u in (self.resources or [])]
        if self.collapse is not None:
            c = self.collapse
            flow["collapse"] = {**c, "crossings": [list(x) for x in c["crossings"]]}
        top = {"cost": self.cost, **flow}
        if rounded:
            robots = {k: _rounded(k, v) for k, v in robots.items()}
            lifelong = {k: _rounded(k, v) for k, v in lifelong.items()}
            people = {k: round(v, 2) if isinstance(v, float) else v for k, v in people.items()}
            if isinstance(people.get("alone"), dict):
                people["alone"] = {k: round(v, 2) if isinstance(v, float) else v for k, v in people["alone"].items()}
            top = {k: _rounded(k, v) if k != "windows" else v for k, v in top.items()}
        return {
            "T": self.T,
            "S": self.S,
            "C": self.C,
            "outcome": self.outcome,
            "steps": self.steps,
            "delivered": self.delivered,
            "goods_total": self.goods_total,
            "stranded": list(self.stranded),
            **top,
            "lifelong": lifelong,
            "people": people,
            "robots": robots,
        }

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Result) and self.to_dict() == other.to_dict()

    def __repr__(self) -> str:
        return (
            f"Result(T={self.T}, S={self.S}, C={self.C}, outcome={self.outcome!r}, "
            f"delivered={self.delivered}/{self.goods_total})"
        )
