"""Sweeps over a League of Robot Runners problem (docs/lorr.md): the base is a problem JSON,
the axes are the run's options, and every run goes through the sweep's store (kill-safe,
resumed by key) like a scenario's.

```toml
base = "warehouse_large_5000.json"   # a LoRR problem (relative to the spec), steps 5000
# or: [base] lorr = "warehouse_large_5000.json", steps = 1000, scheduler = "greedy"
[axes]
scheduler = ["nearest", "greedy", "hungarian"]
robots = [1000, 2000, 5000]          # the first N agents; the 2024 pool sized for N
seed = [0, 1]
```

Axes: ``planner``, ``scheduler``, ``robots``, ``seed``, ``steps``, ``plan_time_limit_ms``.
Each run stores the competition's score and MultiBots' figures (:data:`FIGURES`); ``delivered``
and ``throughput`` repeat the score and its rate under the names the sweep's summary reads.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Optional

from multibots._text import shown
from multibots.exceptions import InputError, MultibotsError, ScenarioError

__all__ = ["AXES", "FIGURES", "LorrBase", "LorrPoint", "figures_of", "is_lorr_base", "keys_of", "parse_base",
           "plan", "run_one"]

#: The options a LoRR sweep may vary.
AXES = ("planner", "scheduler", "robots", "seed", "steps", "plan_time_limit_ms")
#: What each run stores.
FIGURES = ("finished", "finished_per_1000", "windows", "plan_ms_mean", "plan_ms_max", "errors", "action_errors",
           "schedule_errors", "timeouts", "steps", "team_size", "rules", "delivered", "throughput")


@dataclass(frozen=True)
class LorrBase:
    """A LoRR run's inputs: the problem file and the options of :func:`multibots.lorr.run`."""

    problem: str
    steps: int = 5000
    planner: str = "auto"
    scheduler: str = "spread"
    seed: int = 0
    robots: Optional[int] = None
    plan_time_limit_ms: Optional[int] = None


@dataclass(frozen=True)
class LorrPoint:
    """One run of a LoRR sweep: its index in the plan, the axis values and its inputs."""

    index: int
    values: tuple[tuple[str, Any], ...]
    run: LorrBase


def is_lorr_base(value: Any) -> bool:
    """Whether a spec's ``base`` names a LoRR problem: a ``.json`` path, or a table with
    ``lorr``."""
    if isinstance(value, str):
        return value.lower().endswith(".json")
    return isinstance(value, Mapping) and "lorr" in value


def parse_base(value: Any, source: str, folder: Optional[Path]) -> LorrBase:
    """The base of a LoRR sweep, its options checked; the problem path made absolute."""
    table = {"lorr": value} if isinstance(value, str) else dict(value)
    known = {"lorr"} | set(AXES)
    for key in table:
        if key not in known:
            raise InputError(f"{source}: base.{shown(str(key))}: not an option of a LoRR run "
                             f"(known: {', '.join(sorted(known))})")
    raw = table.pop("lorr")
    if not isinstance(raw, str) or not raw:
        raise InputError(f"{source}: base.lorr = {shown(repr(raw))}: expected a problem file's path")
    path = Path(raw)
    if not path.is_absolute() and folder is not None and not path.exists():
        path = folder / path
    if not path.is_file():
        raise InputError(f"{source}: base.lorr = {shown(raw)!r}: no such problem file")
    for key, v in table.items():
        _check(key, v, f"{source}: base.{key}")
    return LorrBase(problem=os.path.abspath(path), **table)


def _check(name: str, value: Any, where: str) -> None:
    """One option's value, or a one-line error naming where it was and the value."""
    from multibots import lorr

    lorr.check_option(name, value, where)


def plan(base: LorrBase, axes: Mapping[str, list[Any]], combos: Sequence[tuple[Any, ...]],
         reps: Sequence[Optional[int]], source: str) -> list[LorrPoint]:
    """Every run of the sweep, in plan order; the problem is read once, with the largest
    team, so that a file or a team the problem cannot give is one line before any run."""
    from multibots import _core

    for name, values in axes.items():
        if name not in AXES:
            raise InputError(f"{source}: axes.{shown(name)}: not an option of a LoRR run (axes: {', '.join(AXES)})")
        for v in values:
            _check(name, v, f"{source}: axes.{name}")
    names = list(axes)
    out: list[LorrPoint] = []
    for combo in combos:
        for rep in reps:
            values = list(zip(names, combo)) + ([("seed", rep)] if rep is not None else [])
            out.append(LorrPoint(len(out), tuple(values), replace(base, **dict(values))))
    teams = [p.run.robots for p in out if p.run.robots is not None]
    try:
        _core.LorrRun(base.problem, base.planner, base.scheduler, 0, None, max(teams) if teams else None)
    except MultibotsError as e:
        where = f" at robots = {max(teams)}" if teams else ""
        raise ScenarioError(f"{source}:{where} {e}") from None
    return out


def _files_digest(problem: str) -> str:
    """The bytes of the problem file and of the map, agents and tasks files it names: an
    edited file runs again though its path is the same."""
    h = hashlib.sha256()
    p = Path(problem)
    text = p.read_bytes()
    h.update(text)
    try:
        named = json.loads(text)
    except ValueError:
        named = {}
    for key in ("mapFile", "agentFile", "taskFile"):
        name = named.get(key) if isinstance(named, dict) else None
        f = p.parent / name if isinstance(name, str) else None
        h.update(f.read_bytes() if f is not None and f.is_file() else b"-")
    return h.hexdigest()


def keys_of(points: Sequence[LorrPoint], engine: str) -> list[str]:
    """Each run's key: its inputs, the files they name, the engine build."""
    digests: dict[str, str] = {}
    keys = []
    for p in points:
        if p.run.problem not in digests:
            digests[p.run.problem] = _files_digest(p.run.problem)
        text = json.dumps(asdict(p.run), sort_keys=True)
        keys.append(hashlib.sha256(f"lorr\n{engine}\n{text}\n{digests[p.run.problem]}".encode()).hexdigest())
    return keys


def figures_of(figures: Mapping[str, Any], team_size: int, rules: str) -> dict[str, Any]:
    """A run's figures (``multibots.lorr`` result figures) as the stored scalars."""
    steps = int(figures["steps"])
    finished = int(figures["finished"])
    rate = finished * 1000 / steps if steps else None
    errors = int(figures["action_errors"]) + int(figures["schedule_errors"])
    return {
        "finished": finished, "finished_per_1000": rate,
        "windows": ";".join(map(str, figures["finished_per_1000"])),
        "plan_ms_mean": figures["plan_ms_mean"], "plan_ms_max": figures["plan_ms_max"], "errors": errors,
        "action_errors": figures["action_errors"], "schedule_errors": figures["schedule_errors"],
        "timeouts": figures["timeouts"], "steps": steps, "team_size": team_size, "rules": rules,
        "delivered": finished, "throughput": rate,
    }


def run_one(run: LorrBase) -> dict[str, Any]:
    """A worker process's job: one LoRR run, its figures."""
    from multibots import lorr

    r = lorr.run(run.problem, steps=run.steps, planner=run.planner, scheduler=run.scheduler, seed=run.seed,
                 plan_time_limit_ms=run.plan_time_limit_ms, robots=run.robots)
    return figures_of(r.figures, r.team_size, r.version)
