"""``multibots lorr``: a League of Robot Runners problem under the competition's rules, its
result file written, its score printed (``docs/lorr.md``)."""

from __future__ import annotations

import contextlib
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Optional

import typer

from multibots import _core
from multibots.cli._common import parse_number
from multibots.exceptions import ScenarioError

__all__ = ["lorr"]


def _choices(table: tuple[tuple[str, str], ...]) -> str:
    """The engine's built-ins as the help lists them: ``name (what it does)``."""
    return "; ".join(f"{name} ({about})" for name, about in table)


def lorr(
    problem: Path = typer.Argument(
        ..., help="A LoRR problem file (JSON): 2023, 2024 or 2026 (\"version\": \"2026 LoRR\").", show_default=False
    ),
    steps: str = typer.Option(
        "5000", "--steps", metavar="STEPS",
        help="Steps to run (the competition's budget is usually 5000); ticks under the 2026 rules (Start-Kit -s).",
    ),
    out: Optional[Path] = typer.Option(
        None, "--out", help="Write the competition's result file here (PlanViz reads it).", show_default=False
    ),
    planner: str = typer.Option(
        _core.LORR_PLANNERS[0][0], "--planner", metavar="NAME", help=f"Planner: {_choices(_core.LORR_PLANNERS)}.",
    ),
    scheduler: str = typer.Option(
        _core.LORR_SCHEDULERS[0][0], "--scheduler", metavar="NAME",
        help=f"Scheduler (2024, 2026): {_choices(_core.LORR_SCHEDULERS)}.",
    ),
    plan_time_limit: Optional[str] = typer.Option(
        None, "--plan-time-limit", metavar="MS", show_default=False,
        help="The competition's planning time limit per step, in ms: past it every robot waits a step (T).",
    ),
    seed: str = typer.Option("0", "--seed", metavar="INT", help="Seed of the planner's tie-breaks."),
    delay_seed: Optional[str] = typer.Option(
        None, "--delay-seed", metavar="INT", show_default=False,
        help="(2026) Seed of the delays in place of the problem's delayConfig.seed: another draw of its delay model.",
    ),
    record: Optional[Path] = typer.Option(
        None, "--record", show_default=False,
        help="Write a replay of every step to this file (.mbr); multibots view plays it.",
    ),
    planner_py: Optional[Path] = typer.Option(
        None, "--planner-py", show_default=False,
        help="A Start-Kit Python planner file (pyMAPFPlanner.py, import MAPF) in place of --planner.",
    ),
    scheduler_py: Optional[Path] = typer.Option(
        None, "--scheduler-py", show_default=False,
        help="A Start-Kit Python scheduler file (pyTaskScheduler.py) in place of --scheduler (2024, 2026).",
    ),
    executor_py: Optional[Path] = typer.Option(
        None, "--executor-py", show_default=False,
        help="A Start-Kit Python executor file (pyExecutor.py) in place of the built-in tpg (2026).",
    ),
    disable_staged_action_validation: bool = typer.Option(
        False, "--disable-staged-action-validation",
        help="(2026) Accept staged actions that are not a prefix of the old ones then the plan (the Start-Kit's "
        "--disableStagedActionValidation, for the Combined track).",
    ),
) -> None:
    """Run a League of Robot Runners problem, scored as the competition scores it."""
    from multibots import lorr as engine

    # Before the run: no output is an input or another output, and each can be written.
    entries = [p for p in (planner_py, scheduler_py, executor_py) if p is not None]
    engine.check_files(problem, out, record, labels=("--out", "--record"), entries=entries)

    n_steps = parse_number(steps, "--steps", int)
    limit = parse_number(plan_time_limit, "--plan-time-limit", int)
    n_seed = parse_number(seed, "--seed", int)
    n_delay_seed = parse_number(delay_seed, "--delay-seed", int)
    for name, value, flag in (("steps", n_steps, "--steps"), ("plan_time_limit_ms", limit, "--plan-time-limit"),
                              ("seed", n_seed, "--seed"), ("delay_seed", n_delay_seed, "--delay-seed"),
                              ("planner", planner, "--planner"), ("scheduler", scheduler, "--scheduler")):
        engine.check_option(name, value, flag)
    began = time.monotonic()
    with _flags_named():
        result = _run(engine, problem, n_steps, out, planner, scheduler, n_seed, limit, record, planner_py,
                      scheduler_py, executor_py, n_delay_seed, not disable_staged_action_validation)
    _report(problem, result, time.monotonic() - began, scheduler_py, out, record, engine)


#: The engine's words for the options a flag sets, and the flags (the refusals of the 2026
#: options by a 2023/2024 problem name the option; the command names what the user typed).
_FLAGS = {"delay_seed = ": "--delay-seed = ", "staged_validation = False": "--disable-staged-action-validation"}


@contextlib.contextmanager
def _flags_named() -> Iterator[None]:
    try:
        yield
    except ScenarioError as e:
        text = str(e)
        for word, flag in _FLAGS.items():
            if text.startswith(word):
                raise ScenarioError(flag + text[len(word):]) from None
        raise


def _run(engine: Any, problem: Path, n_steps: int, out: Optional[Path], planner: str, scheduler: str, n_seed: int,
         limit: Optional[int], record: Optional[Path], planner_py: Optional[Path], scheduler_py: Optional[Path],
         executor_py: Optional[Path], n_delay_seed: Optional[int], staged_validation: bool) -> Any:
    """The run, with a progress bar when a person watches."""
    # The bar only when a person watches: stdout on a terminal (not piped or redirected).
    if sys.stdout.isatty() and sys.stderr.isatty():
        from rich.console import Console
        from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

        with Progress(
            TextColumn("{task.description}"), BarColumn(), TextColumn("step {task.completed:,.0f}/{task.total:,.0f}"),
            TextColumn("finished {task.fields[finished]:,}"), TimeRemainingColumn(), transient=True,
            console=Console(stderr=True),
        ) as bar:
            task = bar.add_task(problem.name, total=n_steps, finished=0)
            return engine.run(
                problem, n_steps, out, planner, scheduler, n_seed, limit,
                progress=lambda t, f: bar.update(task, completed=t, finished=f), record=record,
                planner_py=planner_py, scheduler_py=scheduler_py, executor_py=executor_py, delay_seed=n_delay_seed,
                staged_validation=staged_validation,
            )
    return engine.run(problem, n_steps, out, planner, scheduler, n_seed, limit, record=record,
                      planner_py=planner_py, scheduler_py=scheduler_py, executor_py=executor_py,
                      delay_seed=n_delay_seed, staged_validation=staged_validation)


def _report(problem: Path, result: Any, wall: float, scheduler_py: Optional[Path], out: Optional[Path],
            record: Optional[Path], engine: Any) -> None:
    """The run's line, and where its files went."""
    fig = result.figures
    if result.version == "2026":
        # A Python scheduler's share of a planner call: what the user's code costs.
        mine = f" (its scheduler {fig['schedule_ms_mean']:.2f})" if scheduler_py is not None else ""
        print(
            f"{problem.name}: {result.finished:,} finished in {result.steps:,} ticks "
            f"({result.team_size:,} robots, 2026 rules, planner {result.planner.removeprefix('planner ')}, "
            f"scheduler {result.scheduler.removeprefix('scheduler ')}); "
            f"planning {fig['plan_ms_mean']:.2f} ms/call mean{mine}, {fig['plan_ms_max']:.0f} ms max; "
            f"delays {fig.get('delays', 0):,}, action model messages {fig['action_errors']:,}, "
            f"schedule errors {fig['schedule_errors']}; wall {wall:.1f} s"
        )
    else:
        print(
            f"{problem.name}: {result.finished:,} finished in {result.steps:,} steps "
            f"({result.team_size:,} robots, {result.version} rules, planner {result.planner}); "
            f"planning {fig['plan_ms_mean']:.2f} ms/step mean, {fig['plan_ms_max']:.0f} ms max; "
            f"errors {fig['action_errors'] + fig['schedule_errors']}, timeouts {fig['timeouts']}; wall {wall:.1f} s"
        )
    if out is not None:
        print(f"result: {out} (figures: {engine.figures_path(out).name})")
    if record is not None:
        print(f"replay: {record} (multibots view {record})")
