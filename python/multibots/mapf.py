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
them), and ``task_pool`` iterates in task id order.
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

    def __init__(self) -> None:
        self.minDelay = 0
        self.maxDelay = 0
        self.inDelay = False


class State:
    """A robot's state: cell (``row * cols + col``), orientation (0 east, 1 south, 2 west,
    3 north), the counter of the action under way, and its delay."""

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

    def __init__(self) -> None:
        self.num_of_agents = 0
        self.rows = 0
        self.cols = 0
        self.map_name = ""
        self.map: list[int] = []
        self.file_storage_path = ""
        self.goal_locations: list[list[tuple[int, int]]] = []
        self.curr_timestep = 0
        self.system_timestep = 0
        self.curr_states: list[State] = []
        self.start_states: list[State] = []
        self.system_states: list[State] = []
        self.task_pool: dict[int, Task] = {}
        self.new_tasks: list[int] = []
        self.new_freeagents: list[int] = []
        self.curr_task_schedule: list[int] = []
        self.staged_actions: list[list[Action]] = []
        self.min_planner_communication_time = 1000
        self.action_time = 100
        self.max_counter = 10
