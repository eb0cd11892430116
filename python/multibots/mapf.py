"""The ``MAPF`` module a Start-Kit Python entry imports, provided by MultiBots.

The League of Robot Runners' Start-Kit (MIT, MAPF-Competition/Start-Kit) lets a researcher
write the planner, the scheduler or the executor in Python: a file whose only import is
``MAPF`` and whose class reads ``self.env``, a ``SharedEnvironment``. This module has the same
names, fields and enum values as the Start-Kit's compiled ``MAPF`` module (v3.1.0, and the
2024 fields), in plain Python, so that such a file runs unchanged under ``multibots lorr
--planner-py/--scheduler-py/--executor-py`` (``multibots.lorr_python`` loads it and fills
``env``; docs/lorr.md).

Differences from the Start-Kit's module: containers are plain Python lists and dicts (copies,
not views of the simulator's memory; ``staged_actions`` handed to ``process_new_plan`` is
still changed in place and read back), pairs are tuples (``pair_first``/``pair_second`` work on
them), and ``task_pool`` iterates in task id order. The fields that grow with the fleet are
made Python objects the first time an entry reads them in a call, not before: the Start-Kit
copies a field at each read, and a call that reads little costs little here too.
"""

from __future__ import annotations

import enum
from typing import Any, Optional

__all__ = [
    "Action", "FW", "CR", "CCR", "W", "NA", "ExecutionCommand", "GO", "STOP", "Counter", "Delay", "State",
    "Task", "Plan", "SharedEnvironment", "pair_first", "pair_second",
]


class Action(enum.IntEnum):
    """An action: forward, turn clockwise, turn counter-clockwise, wait, none."""

    FW = 0
    CR = 1
    CCR = 2
    W = 3
    NA = 4


FW, CR, CCR, W, NA = Action.FW, Action.CR, Action.CCR, Action.W, Action.NA


class ExecutionCommand(enum.IntEnum):
    """The executor's command to a robot for a tick."""

    GO = 0
    STOP = 1


GO, STOP = ExecutionCommand.GO, ExecutionCommand.STOP


def pair_first(p: Any) -> Any:
    """The first of a pair (``goal_locations[i][0]`` is ``(cell, t_revealed)``)."""
    return p[0]


def pair_second(p: Any) -> Any:
    """The second of a pair."""
    return p[1]


class Counter:
    """Ticks done of the action under way (``count``) out of ``maxCount`` (``agentCounter``)."""

    # Slots: the Start-Kit's types take no new attributes either, and 10,000 states a call
    # are made faster without a dict each.
    __slots__ = ("count", "maxCount")

    def __init__(self, max_counter: int = 10) -> None:
        self.count = 0
        self.maxCount = max_counter

    def tick(self) -> bool:
        """Counts a tick; whether the action is then complete (and the count back at 0)."""
        self.count += 1
        if self.count >= self.maxCount:
            self.count = 0
            return True
        return False

    def __repr__(self) -> str:
        return f"Counter({self.count}/{self.maxCount})"


class Delay:
    """Whether a robot is held by a delay now (``inDelay``)."""

    __slots__ = ("minDelay", "maxDelay", "inDelay")

    def __init__(self) -> None:
        self.minDelay = 0
        self.maxDelay = 0
        self.inDelay = False


class State:
    """A robot's state: cell (``row * cols + col``), orientation (0 east, 1 south, 2 west,
    3 north), the counter of the action under way, and its delay."""

    __slots__ = ("location", "timestep", "orientation", "counter", "delay")

    def __init__(self, location: int = -1, timestep: int = -1, orientation: int = -1) -> None:
        self.location = location
        self.timestep = timestep
        self.orientation = orientation
        self.counter = Counter()
        self.delay = Delay()

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, State):
            return NotImplemented
        return (self.location, self.orientation, self.counter.count) == (
            other.location, other.orientation, other.counter.count)

    def __hash__(self) -> int:
        return hash((self.location, self.orientation))

    def __repr__(self) -> str:
        return f"State(loc={self.location}, ori={self.orientation}, t={self.timestep})"


class Task:
    """A revealed task: its errands (``locations``), the next one's index, who has it."""

    def __init__(self) -> None:
        self.task_id = -1
        self.t_completed = -1
        self.t_revealed = -1
        self.agent_assigned = -1
        self.locations: list[int] = []
        self.idx_next_loc = 0

    def get_next_loc(self) -> int:
        """The next errand's cell (-1 once all are done)."""
        return self.locations[self.idx_next_loc] if self.idx_next_loc < len(self.locations) else -1

    def is_finished(self) -> bool:
        """Whether every errand is done."""
        return self.idx_next_loc >= len(self.locations)

    def __repr__(self) -> str:
        return f"Task(id={self.task_id}, locations={self.locations}, next={self.idx_next_loc})"


class Plan:
    """A planner's answer as the executor receives it: ``actions[robot]``, a list of actions."""

    def __init__(self, actions: Optional[list[list[Action]]] = None) -> None:
        self.actions: list[list[Action]] = actions if actions is not None else []


class _Lazy:
    """A field of :class:`SharedEnvironment` made on first read in a call, by the source the
    environment was last handed (``SharedEnvironment._load``); assigning it keeps the value
    assigned until the next call."""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name
        self.slot = "_" + name

    def __get__(self, env: Any, owner: Optional[type] = None) -> Any:
        if env is None:
            return self
        cache = env.__dict__
        try:
            return cache[self.slot]
        except KeyError:
            value = env._source(self.name) if env._source is not None else ({} if self.name == "task_pool" else [])
            cache[self.slot] = value
            return value

    def __set__(self, env: Any, value: Any) -> None:
        env.__dict__[self.slot] = value


_LAZY = ("goal_locations", "curr_states", "start_states", "system_states", "task_pool", "new_tasks",
         "new_freeagents", "curr_task_schedule", "staged_actions")


class SharedEnvironment:
    """What an entry sees (``self.env``), with the Start-Kit's field names.

    Fields: ``num_of_agents``, ``rows``, ``cols``, ``map_name``, ``map`` (1 = obstacle, by
    cell), ``file_storage_path``, ``goal_locations`` (per robot ``[(cell, t_revealed)]`` of
    its task's next errand, or empty), ``curr_timestep`` (0, as in the Start-Kit),
    ``system_timestep`` (the tick), ``curr_states`` and ``start_states`` (where the executor
    said each robot will be when the plan arrives; 2024: where it is), ``system_states``
    (where each robot is, with ``delay.inDelay``), ``task_pool`` (task id → :class:`Task`),
    ``new_tasks``, ``new_freeagents``, ``curr_task_schedule``, ``staged_actions``,
    ``min_planner_communication_time``, ``action_time``, ``max_counter``.
    """

    goal_locations = _Lazy()
    curr_states = _Lazy()
    start_states = _Lazy()
    system_states = _Lazy()
    task_pool = _Lazy()
    new_tasks = _Lazy()
    new_freeagents = _Lazy()
    curr_task_schedule = _Lazy()
    staged_actions = _Lazy()

    def __init__(self) -> None:
        #: Makes a lazy field's value by its name (None: the fields are empty or assigned).
        self._source: Optional[Any] = None
        self.num_of_agents = 0
        self.rows = 0
        self.cols = 0
        self.map_name = ""
        self.map: list[int] = []
        self.file_storage_path = ""
        self.curr_timestep = 0
        self.system_timestep = 0
        self.min_planner_communication_time = 1000
        self.action_time = 100
        self.max_counter = 10

    def __getstate__(self) -> dict[str, Any]:
        # Every field made, and the source (the engine's snapshot) left out: a pickled or
        # copied environment holds plain values, as the eager one did.
        state = dict(self.__dict__)
        for name in _LAZY:
            state["_" + name] = getattr(self, name)
        state["_source"] = None
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)

    def _load(self, source: Any, names: tuple[str, ...] = _LAZY) -> None:
        """A new call: the lazy fields ``names`` are made again from ``source`` (a function of
        the field's name) when read; the others keep their values."""
        self._source = source
        for name in names:
            self.__dict__.pop("_" + name, None)
