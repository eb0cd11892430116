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

Axes: ``planner``, ``scheduler``, ``robots``, ``seed``, ``steps``, ``plan_time_limit_ms``,
``delay_seed``. A planner or scheduler value ending in ``.py`` is a Start-Kit Python entry
file (``pyMAPFPlanner.py``, ``pyTaskScheduler.py``; relative to the spec), compared with the
built-ins run for run (``multibots sweep`` asks for ``--allow-code``: the file runs); an edited
file runs again. Under the 2026 rules a run's ``seed`` also draws its delays: seed ``s`` plays
the delays of ``delayConfig.seed + s`` (seed 0, the problem's own, as the Start-Kit plays it;
``repeats = N`` runs seeds 1..N, N other draws), so that the seeds of a study are draws of the
delays and every strategy meets the same draws (paired); a ``delay_seed`` axis or option sets
the seed of the delays itself.

Each run stores the competition's score and MultiBots' figures (:data:`FIGURES`);
``delivered`` and ``throughput`` repeat the score and its rate under the names the sweep's
summary reads, which (with :data:`METRICS`) are what summary.csv and tests.csv give.
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

__all__ = ["AXES", "ENTRY_AXES", "FIGURES", "METRICS", "LorrBase", "LorrPoint", "delay_seed_of", "entry_path",
           "figures_of", "is_entry", "is_lorr_base", "keys_of", "parse_base", "plan", "read_problem", "rules_of",
           "run_one"]

#: The options a LoRR sweep may vary.
AXES = ("planner", "scheduler", "robots", "seed", "steps", "plan_time_limit_ms", "delay_seed")
#: What a LoRR study summarises and tests (the rest of :data:`FIGURES` is in results.csv):
#: tasks (errands under 2023) finished and their rate per 1,000 steps, the planner call's and
#: the scheduler's time, refused schedules, and (2026) delays drawn.
METRICS = ("delivered", "throughput", "plan_ms_mean", "schedule_ms_mean", "schedule_errors", "action_errors",
           "delays")
#: The axes whose value may be a Start-Kit Python entry file, and the role it plays.
ENTRY_AXES = {"planner": "planner", "scheduler": "scheduler"}
#: What each run stores.
FIGURES = ("finished", "finished_per_1000", "windows", "plan_ms_mean", "plan_ms_max", "errors", "action_errors",
           "schedule_errors", "timeouts", "steps", "team_size", "rules", "delivered", "throughput", "schedule_ms_mean",
           "delays")


@dataclass(frozen=True)
class LorrBase:
    """A LoRR run's inputs: the problem file and the options of :func:`multibots.lorr.run`."""

    problem: str
    steps: int = 5000
    planner: str = "auto"
    scheduler: str = "auto"
    seed: int = 0
    robots: Optional[int] = None
    plan_time_limit_ms: Optional[int] = None
    #: (2026) the seed of the delays; None: the problem's ``delayConfig.seed`` plus ``seed``.
    delay_seed: Optional[int] = None
    #: The folder relative to which a Python entry file named in the spec is found.
    folder: Optional[str] = None


def is_entry(value: Any) -> bool:
    """Whether a planner or scheduler value names a Start-Kit Python entry file."""
    return isinstance(value, str) and value.lower().endswith(".py")


def entry_path(value: str, folder: Optional[str]) -> Path:
    """A Python entry file named in a spec: relative to the spec's folder (to the working
    folder for ``compare --lorr``, whose command line names it)."""
    path = Path(value)
    if not path.is_absolute() and folder is not None:
        path = Path(folder) / path
    return path.resolve()


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
    base_folder = os.path.abspath(folder) if folder is not None else None
    for key, v in table.items():
        _check(key, v, f"{source}: base.{key}", base_folder)
    return LorrBase(problem=os.path.abspath(path), folder=base_folder, **table)


def _check(name: str, value: Any, where: str, folder: Optional[str]) -> None:
    """One option's value, or a one-line error naming where it was and the value."""
    from multibots import lorr

    if name in ENTRY_AXES and is_entry(value):
        from multibots import lorr_python

        path = entry_path(value, folder)
        if not path.is_file():
            raise InputError(f"{where} = {shown(value)!r}: no such Python entry file")
        # Loaded (its class made) before any run: a file that cannot serve is one line now,
        # not an error in the middle of the study. The caller has allowed its code to run.
        try:
            lorr_python.load_entry(ENTRY_AXES[name], path)
        except InputError as e:
            reason = str(e).split(": ", 1)[-1]
            raise InputError(f"{where} = {shown(value)!r}: {reason}") from None
        return
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
            _check(name, v, f"{source}: axes.{name}", base.folder)
    names = list(axes)
    data = read_problem(base.problem)
    delays, rules = delay_seed_of(data), rules_of(data)
    if delays is None and ("delay_seed" in axes or base.delay_seed is not None):
        where = f"axes.delay_seed = {shown(axes['delay_seed'])}" if "delay_seed" in axes else \
            f"base.delay_seed = {base.delay_seed}"
        raise InputError(f"{source}: {where}: {Path(base.problem).name} has no delays (only the 2026 rules draw "
                         "them)")
    for option, role in ENTRY_AXES.items():
        given = [v for v in [getattr(base, option), *axes.get(option, [])] if is_entry(v)]
        if given and role == "scheduler" and rules == "2023":
            raise InputError(f"{source}: scheduler = {shown(given[0])!r}: the 2023 rules have no scheduler (errands "
                             "go round robin)")
    out: list[LorrPoint] = []
    for combo in combos:
        for rep in reps:
            values = list(zip(names, combo)) + ([("seed", rep)] if rep is not None else [])
            run = replace(base, **dict(values))
            if delays is not None and run.delay_seed is None:
                run = replace(run, delay_seed=(delays + run.seed) % 2**32)
            out.append(LorrPoint(len(out), tuple(values), run))
    teams = [p.run.robots for p in out if p.run.robots is not None]
    try:
        # Built-in names only: an entry file is checked when its run loads it.
        names = [base.planner, base.scheduler]
        _core.LorrRun(base.problem, *("auto" if is_entry(v) else v for v in names), 0, None,
                      max(teams) if teams else None)
    except MultibotsError as e:
        where = f" at robots = {max(teams)}" if teams else ""
        raise ScenarioError(f"{source}:{where} {e}") from None
    return out


def read_problem(problem: str) -> dict[str, Any]:
    """A problem file's JSON object (empty when it cannot be read: the engine says why)."""
    try:
        with open(problem, encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def rules_of(data: Mapping[str, Any]) -> str:
    """The rules a problem is played under, as the engine tells them (a ``delayConfig`` or a
    2026 version: 2026; a 2024 version: 2024; else 2023)."""
    version = str(data.get("version", ""))
    if "2026" in version or "delayConfig" in data:
        return "2026"
    return "2024" if "2024" in version else "2023"


def delay_seed_of(data: Mapping[str, Any]) -> Optional[int]:
    """The ``delayConfig.seed`` of a 2026 problem as the engine reads it (a number, truncated,
    unsigned 32-bit; absent: 0), or None: the 2023/2024 rules draw no delays."""
    if rules_of(data) != "2026":
        return None
    cfg = data.get("delayConfig")
    seed = cfg.get("seed", 0) if isinstance(cfg, dict) else 0
    if isinstance(seed, bool) or not isinstance(seed, (int, float)) or seed != seed:
        return 0
    return int(seed) % 2**32


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
        # The run's inputs, an entry file by its resolved path and its bytes (an edited
        # scheduler runs again though its name is the same), not by where the spec was read.
        inputs = asdict(p.run)
        del inputs["folder"]
        code = ""
        for option in ENTRY_AXES:
            if is_entry(inputs[option]):
                path = entry_path(inputs[option], p.run.folder)
                inputs[option] = str(path)
                code += hashlib.sha256(path.read_bytes()).hexdigest()
        text = json.dumps(inputs, sort_keys=True)
        keys.append(hashlib.sha256(f"lorr\n{engine}\n{text}\n{digests[p.run.problem]}\n{code}".encode()).hexdigest())
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
        "delivered": finished, "throughput": rate, "schedule_ms_mean": figures.get("schedule_ms_mean"),
        "delays": figures.get("delays"),
    }


def run_one(run: LorrBase) -> dict[str, Any]:
    """A worker process's job: one LoRR run, its figures."""
    from multibots import lorr

    names, files = {}, {}
    for option in ENTRY_AXES:
        value = getattr(run, option)
        if is_entry(value):
            files[f"{option}_py"] = entry_path(value, run.folder)
        else:
            names[option] = value
    r = lorr.run(run.problem, steps=run.steps, seed=run.seed, plan_time_limit_ms=run.plan_time_limit_ms,
                 robots=run.robots, delay_seed=run.delay_seed, **names, **files)
    return figures_of(r.figures, r.team_size, r.version)
