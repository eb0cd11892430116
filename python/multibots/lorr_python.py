"""Start-Kit Python entries under MultiBots: a planner, scheduler or executor file written for
the League of Robot Runners' Start-Kit (``pyMAPFPlanner.py``, ``pyTaskScheduler.py``,
``pyExecutor.py``; their only import is ``MAPF``) runs unchanged in ``multibots lorr`` and
:func:`multibots.lorr.run` (``planner_py=``, ``scheduler_py=``, ``executor_py=``).

:class:`Entries` loads the files (with :mod:`multibots.mapf` as ``MAPF``), fills each entry's
``self.env`` (a :class:`multibots.mapf.SharedEnvironment`) from what the engine hands it, calls
the entry as the Start-Kit does and hands the answer back as lists of numbers. The engine (the
binding's ``lorr.rs``) calls it at every planner call and, for an executor, at every tick; it
checks every answer as the rules check the Start-Kit's.

An exception in the user's code ends the run with one line naming the entry, the exception and
the user's file and line (``planner pyMAPFPlanner.py: raised IndexError: list index out of
range (pyMAPFPlanner.py, line 27)``); the original exception is the error's ``__cause__``.
"""

from __future__ import annotations

import importlib.util
import os
import sys
import traceback
from pathlib import Path
from typing import Any, Optional, Sequence, Union

from multibots import mapf
from multibots.exceptions import InputError, MultibotsError

__all__ = ["CLASSES", "Entries", "EntryError", "load_entry"]

#: The class each role's file defines, as the Start-Kit names it.
CLASSES = {"planner": "pyMAPFPlanner", "scheduler": "pyTaskScheduler", "executor": "pyExecutor"}

#: Where the Start-Kit's ``-p`` (preprocessing) limit would be, in ms: handed to ``initialize``.
PREPROCESS_MS = 30000


class EntryError(MultibotsError):
    """An exception raised in an entry's code, as one line: the exception and the user's file
    and line. The engine reports it as ``<role> <file>: raised ...``."""


def _place(e: BaseException, path: Path) -> str:
    """`` (file, line N)`` of the innermost frame of the traceback in the user's file, else of
    the innermost frame."""
    frames = traceback.extract_tb(e.__traceback__)
    mine = [f for f in frames if os.path.abspath(f.filename) == str(path)]
    if not (mine or frames):
        return ""
    frame = (mine or frames)[-1]
    return f" ({Path(frame.filename).name}, line {frame.lineno})"


def map_name(problem: "os.PathLike[str] | str") -> str:
    """The map file's name of a problem (the Start-Kit's ``map_name``), or empty."""
    import json

    try:
        with open(problem, encoding="utf-8") as f:
            return Path(str(json.load(f).get("mapFile", ""))).name
    except (OSError, ValueError, AttributeError):
        return ""


def _one_line(e: BaseException, path: Path) -> str:
    msg = " ".join(str(e).split())
    text = f"{type(e).__name__}: {msg}" if msg else type(e).__name__
    return f"raised {text}{_place(e, path)}"


def load_entry(role: str, file: "os.PathLike[str] | str") -> Any:
    """Loads a Start-Kit user file for ``role`` and makes its class (``CLASSES[role]``) with no
    arguments, ``import MAPF`` answered by :mod:`multibots.mapf`.

    Raises:
        InputError: the file is missing, is not Python that loads, or lacks the class (one line
            naming the option and the file; an error while loading names its line).
    """
    flag = f"--{role}-py"
    path = Path(file).resolve()
    if not path.is_file():
        raise InputError(f"{flag} = {str(file)!r}: no such file")
    sys.modules["MAPF"] = mapf
    name = f"_multibots_entry_{role}_{path.stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise InputError(f"{flag} = {str(file)!r}: not a Python file")
    module = importlib.util.module_from_spec(spec)
    # The file's folder first on the path, as the Start-Kit puts python/user_<role> there.
    sys.path.insert(0, str(path.parent))
    try:
        spec.loader.exec_module(module)
        cls = getattr(module, CLASSES[role], None)
        if cls is None:
            raise InputError(
                f"{flag} = {str(file)!r}: defines no class {CLASSES[role]} (the class a Start-Kit {role} file defines)")
        return cls()
    except InputError:
        raise
    except SyntaxError as e:
        raise InputError(f"{flag} = {str(file)!r}: SyntaxError: {e.msg} ({path.name}, line {e.lineno})") from e
    except Exception as e:
        raise InputError(f"{flag} = {str(file)!r}: loading it {_one_line(e, path)}") from e
    finally:
        try:
            sys.path.remove(str(path.parent))
        except ValueError:
            pass


def _state(loc: int, heading: int, count: int, held: bool, tick: int, counter: int) -> mapf.State:
    s = mapf.State(loc, tick, heading)
    s.counter.count = count
    s.counter.maxCount = counter
    s.delay.inDelay = held
    return s


class Entries:
    """The Python entries of a run: the objects, their environments, and the calls the engine
    makes (``schedule``, ``plan``, ``process_new_plan``, ``next_command``)."""

    def __init__(self, planner: Optional[Union[str, os.PathLike[str]]] = None,
                 scheduler: Optional[Union[str, os.PathLike[str]]] = None,
                 executor: Optional[Union[str, os.PathLike[str]]] = None) -> None:
        self.files: dict[str, Path] = {}
        self.objects: dict[str, Any] = {}
        for role, file in (("planner", planner), ("scheduler", scheduler), ("executor", executor)):
            if file is not None:
                self.objects[role] = load_entry(role, file)
                self.files[role] = Path(file).resolve()
        self.env = mapf.SharedEnvironment()
        self.exec_env = mapf.SharedEnvironment()
        self.version = "2026"
        self.predicted: list[mapf.State] = []
        #: The map file's name (``map_name``), set by the caller from the problem.
        self.map_name = ""

    @property
    def roles(self) -> tuple[str, ...]:
        """The roles played by Python, for the engine."""
        return tuple(self.objects)

    def label(self, role: str) -> str:
        """The entry's name in errors and results: the role and the file's name."""
        return f"{role} {self.files[role].name}"

    def _call(self, role: str, method: str, *args: Any) -> Any:
        try:
            return getattr(self.objects[role], method)(*args)
        except Exception as e:
            raise EntryError(_one_line(e, self.files[role])) from e

    # The engine's calls --------------------------------------------------------------------

    def begin(self, version: str, rows: int, cols: int, obstacles: Sequence[int], agents: int,
              counter: int, comm_ms: int, tick_ms: int) -> None:
        """Fills the environments' fixed fields and calls each entry's ``initialize``."""
        self.version = version
        for env in (self.env, self.exec_env):
            env.num_of_agents, env.rows, env.cols, env.map_name = agents, rows, cols, self.map_name
            env.map = list(obstacles)
            env.max_counter, env.min_planner_communication_time, env.action_time = counter, comm_ms, tick_ms
            env.goal_locations = [[] for _ in range(agents)]
            env.curr_task_schedule = [-1] * agents
            env.staged_actions = [[] for _ in range(agents)]
        self.exec_env.new_freeagents = list(range(agents))
        for role, obj in self.objects.items():
            obj.env = self.exec_env if role == "executor" else self.env
            try:
                self._call(role, "initialize", PREPROCESS_MS)
            except EntryError as e:
                raise EntryError(f"{self.label(role)}: initialize {e}") from e.__cause__

    def _sync(self, tick: int, predicted: Sequence[tuple[int, int, int, bool]],
              system: Sequence[tuple[int, int, int, bool]], tasks: Sequence[tuple[int, int, int, list[int], int]],
              schedule: Sequence[int], goals: Sequence[Optional[tuple[int, int]]], new_tasks: Sequence[int],
              new_free: Sequence[int], staged: Sequence[Sequence[int]]) -> None:
        env = self.env
        m = env.max_counter
        env.system_timestep = tick
        env.curr_states = [_state(*p, -1, m) for p in predicted]
        env.start_states = env.curr_states
        env.system_states = [_state(*p, tick, m) for p in system]
        pool: dict[int, mapf.Task] = {}
        for task_id, revealed, agent, locations, done in tasks:
            t = mapf.Task()
            t.task_id, t.t_revealed, t.agent_assigned = task_id, revealed, agent
            t.locations, t.idx_next_loc = list(locations), done
            pool[task_id] = t
        env.task_pool = pool
        env.curr_task_schedule = list(schedule)
        env.goal_locations = [[] if g is None else [(int(g[0]), int(g[1]))] for g in goals]
        env.new_tasks = list(new_tasks)
        env.new_freeagents = list(new_free)
        env.staged_actions = [[mapf.Action(a) for a in q] for q in staged]

    def schedule(self, time_limit: int, *state: Any) -> list[int]:
        """The scheduler's call: a task id or -1 per robot."""
        self._sync(*state)
        answer = self._call("scheduler", "plan", time_limit)
        try:
            return [int(x) for x in answer]
        except (TypeError, ValueError) as e:
            raise EntryError(f"answered {type(answer).__name__}, not a list of task ids: {e}") from None

    def plan(self, time_limit: int, synced: bool, *state: Any) -> list[list[int]]:
        """The planner's call: each robot's actions (2024 rules: its one action, as a list of
        one). ``synced``: the scheduler was Python and the environment is already filled; the
        schedule and goals are then the proposal's."""
        if synced:
            _, _, _, _, schedule, goals, *_ = state
            self.env.curr_task_schedule = list(schedule)
            self.env.goal_locations = [[] if g is None else [(int(g[0]), int(g[1]))] for g in goals]
        else:
            self._sync(*state)
        answer = self._call("planner", "plan", time_limit)
        try:
            # One action per robot (the 2024 Start-Kit's answer) or a list per robot.
            return [[int(row)] if not hasattr(row, "__iter__") else [int(a) for a in row] for row in answer]
        except (TypeError, ValueError) as e:
            raise EntryError(f"answered {type(answer).__name__}, not a list of actions per robot: {e}") from None

    def _sync_exec(self, tick: int, system: Sequence[tuple[int, int, int, bool]],
                   staged: Sequence[Sequence[int]]) -> None:
        env = self.exec_env
        env.system_timestep = tick
        env.system_states = [_state(*p, tick, env.max_counter) for p in system]
        if not self.predicted:
            self.predicted = [_state(p[0], p[1], 0, False, -1, env.max_counter) for p in system]
        env.curr_states = self.predicted
        env.start_states = self.predicted
        env.staged_actions = [[mapf.Action(a) for a in q] for q in staged]

    def process_new_plan(self, sync_limit: int, tick: int, system: Any, staged: Any,
                         plan: Sequence[Sequence[int]]) -> tuple[list[list[int]], list[tuple[int, int]]]:
        """The executor's ``process_new_plan``: the staged actions it left (changed in place)
        and where it says each robot will be."""
        self._sync_exec(tick, system, staged)
        queues = self.exec_env.staged_actions
        new_plan = mapf.Plan([[mapf.Action(a) for a in row] for row in plan])
        answer = self._call("executor", "process_new_plan", sync_limit, new_plan, queues)
        try:
            predicted = list(answer)
            out = [(int(s.location), int(s.orientation)) for s in predicted]
        except (TypeError, ValueError, AttributeError) as e:
            raise EntryError(
                f"process_new_plan answered {type(answer).__name__}, not a list of MAPF.State: {e}") from None
        self.predicted = [mapf.State(loc, -1, ori) for loc, ori in out]
        return [[int(a) for a in q] for q in queues], out

    def next_command(self, exec_limit: int, tick: int, system: Any, staged: Any) -> list[int]:
        """The executor's ``next_command``: GO (0) or STOP (1) per robot."""
        self._sync_exec(tick, system, staged)
        answer = self._call("executor", "next_command", exec_limit)
        try:
            return [int(c) for c in answer]
        except (TypeError, ValueError) as e:
            raise EntryError(f"next_command answered {type(answer).__name__}, not a list of commands: {e}") from None
