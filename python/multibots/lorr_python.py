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


def _task(task_id: int, revealed: int, agent: int, locations: list[int], done: int) -> mapf.Task:
    t = mapf.Task()
    t.task_id, t.t_revealed, t.agent_assigned = task_id, revealed, agent
    t.locations, t.idx_next_loc = locations, done
    return t


def _state(loc: int, heading: int, count: int, held: bool, tick: int, counter: int) -> mapf.State:
    s = mapf.State(loc, tick, heading)
    s.counter.count = count
    s.counter.maxCount = counter
    s.delay.inDelay = held
    return s


class _PlanSource:
    """Makes a planner-side field of ``env`` from a ``PlanSnapshot`` (the binding's
    ``lorr_entries.rs``), when the entry reads it."""

    def __init__(self, env: mapf.SharedEnvironment, snapshot: Any, news: Any) -> None:
        self.env, self.snapshot, self.news = env, snapshot, news

    def __call__(self, name: str) -> Any:
        snap, m = self.snapshot, self.env.max_counter
        if name == "curr_states":
            return [_state(*p, -1, m) for p in snap.predicted()]
        if name == "start_states":
            return self.env.curr_states
        if name == "system_states":
            return [_state(*p, snap.tick, m) for p in snap.system()]
        if name == "task_pool":
            return {row[0]: _task(*row) for row in snap.tasks()}
        if name == "curr_task_schedule":
            return snap.schedule()
        if name == "goal_locations":
            return [[] if g is None else [(g[0], g[1])] for g in snap.goals()]
        if name == "new_tasks":
            return self.news.new_tasks()
        if name == "new_freeagents":
            return self.news.new_free()
        if name == "staged_actions":
            return [[mapf.Action(a) for a in q] for q in snap.staged()]
        raise AttributeError(name)


class _ExecSource:
    """Makes an executor-side field of ``env`` from an ``ExecSnapshot``, when read; the
    states it predicted stand for ``curr_states``."""

    def __init__(self, env: mapf.SharedEnvironment, snapshot: Any, predicted: list[mapf.State]) -> None:
        self.env, self.snapshot, self.predicted = env, snapshot, predicted

    def __call__(self, name: str) -> Any:
        if name in ("curr_states", "start_states"):
            return self.predicted
        if name == "system_states":
            return [_state(*p, self.snapshot.tick, self.env.max_counter) for p in self.snapshot.system()]
        if name == "staged_actions":
            return [[mapf.Action(a) for a in q] for q in self.snapshot.staged()]
        # The executor is not handed the tasks (the Start-Kit's executor sees them empty).
        return {} if name == "task_pool" else []


#: The executor's fields that change between its calls (the others stay as first given).
_EXEC_FIELDS = ("curr_states", "start_states", "system_states", "staged_actions")


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
        #: The scheduler's snapshot at the last call, whose news the planner then sees.
        self._scheduled: Any = None
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

    def _sync(self, snapshot: Any, news: Any = None) -> None:
        """A planner-side call: the environment's fields made from ``snapshot`` (a
        ``PlanSnapshot``) when read; ``news``: the snapshot whose new tasks and freed robots
        stand (the scheduler's, for a planner called after it)."""
        self.env.system_timestep = snapshot.tick
        self.env._load(_PlanSource(self.env, snapshot, news or snapshot))

    def schedule(self, time_limit: int, snapshot: Any) -> list[int]:
        """The scheduler's call: a task id or -1 per robot."""
        self._sync(snapshot)
        self._scheduled = snapshot
        answer = self._call("scheduler", "plan", time_limit)
        if type(answer) is list and set(map(type, answer)) <= {int}:
            return answer  # as it is: a copy costs a millisecond a call at 10,000 robots
        try:
            return [int(x) for x in answer]
        except (TypeError, ValueError) as e:
            raise EntryError(f"answered {type(answer).__name__}, not a list of task ids: {e}") from None

    def plan(self, time_limit: int, synced: bool, snapshot: Any) -> list[list[int]]:
        """The planner's call: each robot's actions (2024 rules: its one action, as a list of
        one). ``synced``: the scheduler was Python; the planner then sees the tasks and robots
        that were new at the scheduler's call, and the schedule and goals of its proposal."""
        self._sync(snapshot, self._scheduled if synced else None)
        answer = self._call("planner", "plan", time_limit)
        try:
            # One action per robot (the 2024 Start-Kit's answer) or a list per robot.
            return [[int(row)] if not hasattr(row, "__iter__") else [int(a) for a in row] for row in answer]
        except (TypeError, ValueError) as e:
            raise EntryError(f"answered {type(answer).__name__}, not a list of actions per robot: {e}") from None

    def _sync_exec(self, snapshot: Any) -> None:
        env = self.exec_env
        env.system_timestep = snapshot.tick
        if not self.predicted:
            self.predicted = [_state(p[0], p[1], 0, False, -1, env.max_counter) for p in snapshot.system()]
        env._load(_ExecSource(env, snapshot, self.predicted), _EXEC_FIELDS)

    def process_new_plan(self, sync_limit: int, snapshot: Any,
                         plan: Sequence[Sequence[int]]) -> tuple[list[list[int]], list[tuple[int, int]]]:
        """The executor's ``process_new_plan``: the staged actions it left (changed in place)
        and where it says each robot will be."""
        self._sync_exec(snapshot)
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

    def next_command(self, exec_limit: int, snapshot: Any) -> list[int]:
        """The executor's ``next_command``: GO (0) or STOP (1) per robot."""
        self._sync_exec(snapshot)
        answer = self._call("executor", "next_command", exec_limit)
        try:
            return [int(c) for c in answer]
        except (TypeError, ValueError) as e:
            raise EntryError(f"next_command answered {type(answer).__name__}, not a list of commands: {e}") from None
