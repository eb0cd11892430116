"""League of Robot Runners problems, run under the competition's rules and scored as it scores
them (``docs/lorr.md``). The engine owns the rules (``crates/multibots-core/src/rules/grid``);
this module runs it, writes the competition's result file and MultiBots' figures.

Example (``multibots lorr`` on the command line does the same)::

    import multibots.lorr
    r = multibots.lorr.run("warehouse_large_5000.json", steps=5000, out="result.json")
    print(r.finished, r.figures["finished_per_1000"])
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Optional, Union

from multibots import _args, _core
from multibots._io import OutputSet, check_outputs
from multibots._text import shown
from multibots.exceptions import ArgumentError, InputError

__all__ = ["ABOUT", "PLANNERS", "SCHEDULERS", "LorrResult", "check_files", "check_option", "run"]

#: The built-in planners, as the engine names them; the first is the default.
PLANNERS: tuple[str, ...] = tuple(name for name, _ in _core.LORR_PLANNERS)
#: The built-in schedulers (2024 and 2026 rules); the first (``auto``: ``reassign`` under the
#: 2024 rules, ``soonest`` under the 2026 rules) is the default.
SCHEDULERS: tuple[str, ...] = tuple(name for name, _ in _core.LORR_SCHEDULERS)
#: One line on what each built-in planner and scheduler does, by name.
ABOUT: dict[str, str] = dict(_core.LORR_PLANNERS + _core.LORR_SCHEDULERS)

#: Steps between two calls of ``progress``.
PROGRESS_EVERY = 50


@dataclass(frozen=True)
class LorrResult:
    """What a run gave: the competition's score and MultiBots' figures.

    Attributes:
        finished: ``numTaskFinished``, the competition's score.
        steps: steps run (ticks under the 2026 rules).
        team_size: robots.
        version: the rules, ``"2023"``, ``"2024"`` or ``"2026"``.
        planner: the planner that played (``auto`` resolved).
        scheduler: the scheduler that played (``auto`` resolved; empty under the 2023 rules).
        figures: MultiBots' figures (finished per 1,000 steps, planning time per round,
            errors, timeouts).
        out: the result file written, if any.
    """

    finished: int
    steps: int
    team_size: int
    version: str
    planner: str = ""
    scheduler: str = ""
    figures: dict[str, Any] = field(default_factory=dict)
    out: Optional[Path] = None


def run(
    problem: Union[str, os.PathLike[str]],
    steps: int = 5000,
    out: Optional[Union[str, os.PathLike[str]]] = None,
    planner: str = "auto",
    scheduler: str = "auto",
    seed: int = 0,
    plan_time_limit_ms: Optional[int] = None,
    progress: Optional[Callable[[int, int], None]] = None,
    record: Optional[Union[str, os.PathLike[str]]] = None,
    robots: Optional[int] = None,
    planner_py: Optional[Union[str, os.PathLike[str]]] = None,
    scheduler_py: Optional[Union[str, os.PathLike[str]]] = None,
    executor_py: Optional[Union[str, os.PathLike[str]]] = None,
    delay_seed: Optional[int] = None,
    staged_validation: bool = True,
) -> LorrResult:
    """Runs a LoRR problem for ``steps`` steps.

    Args:
        problem: the problem JSON (its map, agents and tasks files are read relative to it).
        steps: the step budget (the competition's is usually 5,000); under the 2026 rules
            (``"version": "2026 LoRR"``, or a ``delayConfig``) ticks, like the Start-Kit's ``-s``.
        out: where to write the competition's result file (atomically); its figures go
            beside it as ``<out>.multibots.json``.
        planner: a planner of :data:`PLANNERS`.
        scheduler: a scheduler of :data:`SCHEDULERS` (2024 and 2026 problems).
        seed: the planner's tie-breaks.
        plan_time_limit_ms: the competition's time limit per planning round; past it the
            robots wait a step per limit used (``T`` in the paths). None: no limit, and the
            run is the same on every machine. 2023 and 2024 rules only: under the 2026 rules
            the planner is called every 10 ticks whatever it takes, as the Start-Kit's
            default build does with a fast planner (docs/lorr.md).
        progress: called as ``progress(step, finished)`` every 50 steps.
        record: write a replay of every step here (``.mbr``, docs/replay-format.md), which
            ``multibots view`` plays: the grid, the robots with their headings and each
            robot's goal. Written under a temporary name and renamed at the end.
        robots: run with the first ``robots`` agents of the agents file instead of the
            problem's ``teamSize`` (2024: the task pool is sized for them,
            ``int(numTasksReveal * robots)``).
        planner_py, scheduler_py, executor_py: a Start-Kit Python entry file
            (``pyMAPFPlanner.py``, ``pyTaskScheduler.py``, ``pyExecutor.py``, whose only
            import is ``MAPF``) playing that part in place of the built-in
            (:mod:`multibots.lorr_python`); any subset. An executor needs a 2026 problem, a
            scheduler a 2024 or 2026 one.
        delay_seed: (2026 rules) the seed of the delays in place of the problem's
            ``delayConfig.seed``: another draw of the same delay model, the one the Start-Kit
            gives with that seed in the problem file. None: the problem's.
        staged_validation: (2026 rules) whether an executor's staged actions must stay a
            prefix of those it had followed by the new plan (waits left out), as the
            Start-Kit checks them; False is its ``--disableStagedActionValidation``, which the
            Combined track allows an executor that stages its own actions.

    Raises:
        ScenarioError: a problem file that cannot be read (the message names the file and
            the line).
        ArgumentError: an argument of the wrong kind or out of its range, or an unknown
            planner or scheduler (:func:`check_option`).
        InputError: a Python entry file that cannot be loaded.
        AllocatorError: a Python entry raised (one line: the entry, the exception, the user's
            file and line; the exception is its ``__cause__``) or answered what the rules
            cannot take.
    """
    problem = _args.path("problem", problem)
    for name, value in (("steps", steps), ("planner", planner), ("scheduler", scheduler), ("seed", seed),
                        ("plan_time_limit_ms", plan_time_limit_ms), ("robots", robots), ("delay_seed", delay_seed)):
        check_option(name, value, error=ArgumentError)
    out = _args.path("out", out, optional=True)
    record = _args.path("record", record, optional=True)
    planner_py = _args.path("planner_py", planner_py, optional=True)
    scheduler_py = _args.path("scheduler_py", scheduler_py, optional=True)
    executor_py = _args.path("executor_py", executor_py, optional=True)
    progress = _args.function("progress", progress)
    if not isinstance(staged_validation, bool):
        raise ArgumentError(f"staged_validation = {staged_validation!r}: expected True or False")
    check_files(problem, out, record, entries=[p for p in (planner_py, scheduler_py, executor_py) if p is not None])
    entries = None
    if planner_py is not None or scheduler_py is not None or executor_py is not None:
        from multibots import lorr_python

        entries = lorr_python.Entries(planner_py, scheduler_py, executor_py)
        entries.map_name = lorr_python.map_name(problem)
    # The result, its figures and the replay are one set: all written, or none.
    with OutputSet({"out": out, "figures": None if out is None else figures_path(out), "record": record}) as tmp:
        recorded = os.fspath(tmp["record"]) if "record" in tmp else None
        engine = _core.LorrRun(os.fspath(problem), planner, scheduler, seed, plan_time_limit_ms, robots, recorded,
                               entries, delay_seed, staged_validation)
        while engine.t < steps:
            engine.run_to(min(steps, engine.t + PROGRESS_EVERY))
            if progress is not None:
                progress(engine.t, engine.finished)
        if out is not None:
            engine.write_result(tmp["out"])
            engine.write_figures(tmp["figures"])
        engine.finish_record()
    return LorrResult(
        finished=engine.finished,
        steps=engine.t,
        team_size=engine.team_size,
        version=engine.version,
        planner=engine.planner,
        scheduler=engine.scheduler,
        figures=json.loads(engine.figures_json()),
        out=out,
    )


def check_files(problem: Path, out: Optional[Path], record: Optional[Path],
                labels: tuple[str, str] = ("out", "record"), entries: Sequence[Path] = ()) -> None:
    """Before a run: no output (``out``, the figures beside it, ``record``; named by
    ``labels``) is a file the run reads (the problem and the map, agents and tasks files it
    names, and the Python ``entries``) or another output, and each can be written.

    Raises:
        OutputError: one line naming the output, its path and the file it would replace.
    """
    names = ("problem file", "map file", "agents file", "tasks file")
    inputs = [(names[min(k, 3)], Path(p)) for k, p in enumerate(_core.lorr_files(problem))]
    inputs += [("Python entry file", Path(p)) for p in entries]
    figures = None if out is None else figures_path(out)
    check_outputs([(labels[0], out), (f"{labels[0]}'s figures", figures), (labels[1], record)], inputs)


def figures_path(out: Path) -> Path:
    """Where MultiBots' figures go beside a result file."""
    return out.with_name(out.name + ".multibots.json")


def check_option(name: str, value: Any, where: Optional[str] = None, error: type[InputError] = InputError) -> None:
    """Checks one option of a LoRR run against the engine's names and limits
    (``_core.LORR_PLANNERS``, ``_core.LIMITS``, docs/limits.md): the one check that
    :func:`run`, ``multibots lorr`` and LoRR sweeps share.

    Raises:
        InputError: (``error``) one line naming ``where`` (the parameter, a flag or a sweep's
            key; by default ``name``) and the value.
    """
    limits = _core.LIMITS

    def bad(expected: str) -> InputError:
        return error(f"{where or name} = {shown(repr(value))}: {expected}")

    whole = isinstance(value, int) and not isinstance(value, bool)
    if name == "planner" and value not in PLANNERS:
        raise bad(f"not a planner (known: {', '.join(PLANNERS)})")
    if name == "scheduler" and value not in SCHEDULERS:
        raise bad(f"not a scheduler (known: {', '.join(SCHEDULERS)})")
    if name == "robots" and not (value is None or (whole and 1 <= value <= limits["robots"])):
        raise bad(f"expected a number of robots from 1 to {limits['robots']:,}")
    if name == "steps" and not (whole and 0 <= value <= limits["lorr_steps"]):
        raise bad(f"expected a number of steps from 0 to {limits['lorr_steps']:,}")
    if name == "seed" and not (whole and 0 <= value < 2**64):
        raise bad("expected an integer from 0 to 2^64 - 1")
    if name == "delay_seed" and not (value is None or (whole and 0 <= value < 2**32)):
        raise bad("expected an integer from 0 to 2^32 - 1 (the Start-Kit's delay seed is unsigned 32-bit)")
    if name == "plan_time_limit_ms" and not (value is None or (whole and 1 <= value <= limits["plan_time_limit_ms"])):
        raise bad(f"expected milliseconds from 1 to {limits['plan_time_limit_ms']:,}")
