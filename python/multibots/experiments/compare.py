"""The strategy comparison study behind ``multibots compare``: its options, its runs and their
journal (the statistics and the files are in :mod:`multibots.experiments.summary`).

Every strategy runs on every (N, task list) pair, so the comparison is *paired*: each
strategy sees exactly the same task lists. A comparison is a sweep (docs/sweeps.md) with its
own axes and outputs: its runs go through the sweep's runner (built-in strategies on the
engine's threads, Python strategies in worker processes), and the runner's store is a
journal (``runs.jsonl``, :mod:`multibots.runs.journal`) keyed by everything that changes a result, so a
study resumes after a kill and reuses what it can, without the study extra.
The study writes

- ``results.csv``: one row per run (strategy, N, tasks, list, T, S, C, distance, cost, ...);
- ``summary.csv``: per strategy, N (and ``all``, pooled over N) and metric, the mean with its
  95% confidence interval (t distribution, clipped at 0: no indicator is negative), and
  against ``in-turn`` the paired mean difference, its relative size, and the p-values of a
  paired t-test and a Wilcoxon signed-rank test (:mod:`multibots.stats`);
- ``summary.txt``: the same as tables at most 100 columns wide, as printed;
- ``strategy_*.png|svg``: T, S, C and Cost_total against N, one line per strategy.

Cost_total = w_d · (distance driven by the fleet, px) + w_t · T + w_c · S, with the weights of
the scenario's ``[cost]`` table. T and Cost_total exist only for complete runs; a pair in which
either run is incomplete is left out of the paired tests (``summary.csv`` says how many pairs
each test used).
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Optional

from multibots import _core
from multibots._text import shown
from multibots.exceptions import InputError, ScenarioError
from multibots.experiments.summary import (
    BASELINE,
    METRICS,
    format_summary,
    format_windows,
    headline,
    progress_bar,
    summarize,
    write_outputs,
)
from multibots.paper import PAPER_TASKS
from multibots.runs import Journal
from multibots.scenario import Scenario
from multibots.strategies import BUILT_INS, is_python_allocator
from multibots.sweeps.runner import PEOPLE_COSTS

__all__ = [
    "OUTPUTS",
    "METRICS",
    "BASELINE",
    "TaskSpec",
    "parse_robots",
    "parse_tasks",
    "parse_strategies",
    "parse_humans",
    "plan_runs",
    "run_study",
    "summarize",
    "format_summary",
    "format_windows",
    "headline",
    "write_outputs",
    "progress_bar",
]

#: What a study writes in its --out folder (shell patterns).
OUTPUTS = ("results.csv", "summary.csv", "summary.txt", "strategy_*", "throughput_over_time.png", "runs.jsonl")

#: Most fleet sizes, seeds and runs a study may plan (docs/limits.md).
MAX_SIZES = 200
MAX_SEEDS = 100_000
MAX_RUNS = 1_000_000
#: The engine's limit on a fleet.
MAX_ROBOTS: int = _core.LIMITS["robots"]


@dataclass(frozen=True)
class TaskSpec:
    """Which task lists the study uses: the paper's five, or ``count`` random goods per list."""

    kind: str  # "paper", "random" or "scenario" (the --scenario file's own tasks or orders)
    count: int = 0

    @property
    def label(self) -> str:
        return self.kind if self.kind != "random" else f"random:{self.count}"


def parse_robots(text: str) -> list[int]:
    """``1..6`` (inclusive), ``3`` or ``1,2,4`` into fleet sizes, ascending and distinct."""
    out: list[int] = []
    for part in text.split(","):
        part = part.strip()
        # ASCII digits, and few of them: int() refuses other digits ("²") and 5,000 of them.
        m = re.fullmatch(r"([0-9]{1,18})\s*\.\.\s*([0-9]{1,18})", part)
        if m:
            lo, hi = int(m.group(1)), int(m.group(2))
            if lo > hi:
                raise InputError(f"--robots = {shown(text)!r}: the range {part} is empty (write LOW..HIGH)")
            if hi - lo + 1 > MAX_SIZES:
                raise InputError(f"--robots = {shown(text, 40)!r}: more than {MAX_SIZES} fleet sizes")
            out.extend(range(lo, hi + 1))
        elif re.fullmatch(r"[0-9]{1,18}", part):
            out.append(int(part))
        else:
            raise InputError(f"--robots = {shown(text)!r}: expected a range such as 1..6 or a list such as 1,2,4")
    if len(out) > MAX_SIZES:
        raise InputError(f"--robots = {shown(text, 40)!r}: more than {MAX_SIZES} fleet sizes")
    if not out or min(out) < 1:
        raise InputError(f"--robots = {shown(text)!r}: fleet sizes must be 1 or more")
    if max(out) > MAX_ROBOTS:
        raise InputError(f"--robots = {shown(text)!r}: at most {MAX_ROBOTS:,} robots")
    return sorted(set(out))


def parse_tasks(text: str) -> TaskSpec:
    """``paper`` (TABLE III's five lists) or ``random:K`` (K goods per list, one list per seed)."""
    t = text.strip()
    if t in ("paper", "scenario"):
        return TaskSpec(t)
    m = re.fullmatch(r"random:([0-9]{1,9})", t)
    if m and int(m.group(1)) >= 1:
        return TaskSpec("random", int(m.group(1)))
    raise InputError(f"--tasks = {shown(text)!r}: expected paper, scenario or random:K with K >= 1, such as random:10")


def parse_strategies(text: str) -> list[str]:
    """Comma-separated strategy names: built-ins, ``module:Class`` or ``file.py:Class``; in order."""
    names = [n.strip() for n in text.split(",")]
    if not text.strip() or any(not n for n in names):
        raise InputError(f"--strategies = {shown(text)!r}: expected comma-separated strategy names")
    for n in names:
        if not is_python_allocator(n) and n not in BUILT_INS:
            raise InputError(
                f"--strategies = {shown(n)!r}: unknown strategy "
                f"(built-ins: {', '.join(BUILT_INS)}; or module:Class, file.py:Class)"
            )
    dup = [n for n in names if names.count(n) > 1]
    if dup:
        raise InputError(f"--strategies = {shown(dup[0])!r}: named twice")
    return names


def task_lists(spec: TaskSpec, seeds: int) -> list[tuple[int, Any]]:
    """(list id, ``tasks`` value) pairs: group numbers for the paper, seeds 1..seeds for random."""
    if spec.kind == "paper":
        return [(g, list(cells)) for g, cells in PAPER_TASKS.items()]
    if seeds < 1:
        raise InputError(f"--seeds = {seeds}: must be 1 or more")
    if seeds > MAX_SEEDS:
        raise InputError(f"--seeds = {seeds}: at most {MAX_SEEDS:,}")
    if spec.kind == "scenario":
        return [(seed, None) for seed in range(1, seeds + 1)]
    return [(seed, {"random": spec.count, "seed": seed}) for seed in range(1, seeds + 1)]


@dataclass(frozen=True)
class Run:
    #: The arm compared: the strategy, with the traffic policy and rule set when several
    #: are compared (``nearest/reserve``).
    strategy: str
    N: int
    list_id: int
    scenario: Scenario
    #: The traffic policy the run plays: ``auto`` resolved for its fleet size (wait for the
    #: paper's fleets, reserve for spread ones: docs/traffic.md).
    traffic: str = "wait"
    rules: str = "paper"
    #: People on the floor (``[humans] count``); None: as the scenario says.
    humans: Optional[int] = None
    #: The strategy's name as the scenario gives it (``allocator``).
    allocator: str = "in-turn"


def parse_humans(text: str) -> list[Optional[int]]:
    """``--humans 0,20,40``: worker counts to compare, each an arm (docs/people.md)."""
    if not text.strip():
        return [None]
    out: list[Optional[int]] = []
    for part in text.split(","):
        part = part.strip()
        if not re.fullmatch(r"[0-9]{1,6}", part) or int(part) > 100_000:
            raise InputError(f"--humans = {shown(part)!r}: expected comma-separated counts from 0 to 100000")
        if int(part) in out:
            raise InputError(f"--humans = {shown(part)!r}: named twice")
        out.append(int(part))
    return out


def parse_choices(text: str, flag: str, known: Sequence[str]) -> list[str]:
    """A comma-separated list of names from ``known``, in order, each once."""
    names = [n.strip() for n in text.split(",")]
    if not text.strip() or any(not n for n in names):
        raise InputError(f"{flag} = {shown(text)!r}: expected comma-separated names ({', '.join(known)})")
    for n in names:
        if n not in known:
            raise InputError(f"{flag} = {shown(n)!r}: expected one of {', '.join(known)}")
        if names.count(n) > 1:
            raise InputError(f"{flag} = {shown(n)!r}: named twice")
    return names


def plan_runs(
    strategies: Sequence[str], robots: Sequence[int], spec: TaskSpec, seeds: int, base: Optional[Scenario] = None,
    traffic: Sequence[str] = ("auto",), rules: Sequence[str] = ("paper",), humans: Sequence[Optional[int]] = (None,),
    workers: int = 0,
) -> list[Run]:
    """Every (strategy, traffic policy, rule set, N, task list) combination, in that order;
    scenarios validated here (on ``workers`` engine threads). With one traffic policy and one rule set the arms are the
    strategies; else each arm names its policy and rule set too."""
    if spec.kind == "scenario" and base is None:
        raise InputError("--tasks scenario: give the scenario with --scenario FILE")
    lists = task_lists(spec, seeds)
    total = len(strategies) * len(traffic) * len(rules) * len(humans) * len(robots) * len(lists)
    if total > MAX_RUNS:
        raise InputError(f"the study plans {total:,} runs: at most {MAX_RUNS:,}")
    template = {} if base is None else base.to_dict()
    for key in ("robots", "allocator", "starts", "traffic", "rules") + (("tasks",) if spec.kind != "scenario" else ()):
        template.pop(key, None)
    runs = []
    played_by_n: dict[tuple[int, str], str] = {}
    from multibots.strategies import strategy_labels

    labels = strategy_labels(list(strategies))
    for s, tr, ru, hu in ((s, tr, ru, hu) for s in strategies for tr in traffic for ru in rules for hu in humans):
        arm = "/".join([labels[s]] + ([tr] if len(traffic) > 1 else []) + ([ru] if len(rules) > 1 else [])
                       + ([f"{hu} people"] if len(humans) > 1 else []))
        for n in robots:
            for list_id, tasks in lists:
                fields = {**template, "robots": n, "allocator": s, "traffic": tr, "rules": ru}
                if hu is not None:
                    fields["humans"] = {**(fields.get("humans") or {}), "count": hu}
                if fields.get("humans") is not None:
                    # People's tours drawn anew per task list, the same in every arm (paired).
                    fields["humans"] = {**fields["humans"], "seed": list_id}
                if tasks is not None:
                    fields["tasks"] = tasks
                elif fields.get("orders") is not None:
                    # The scenario's own tasks; its order stream drawn anew per seed.
                    fields["orders"] = {**fields["orders"], "seed": list_id}
                try:
                    scenario = Scenario._parsed_only(fields)
                except ScenarioError as e:
                    raise ScenarioError(f"{arm}, N = {n}: {e}") from None
                played = tr if tr != "auto" else _played_traffic(scenario, played_by_n, (n, ru))
                runs.append(Run(arm, n, list_id, scenario, played, ru, hu, s))
    # All at once: each layout is built once, not once per run.
    failed = _core.check_many([r.scenario._core for r in runs], workers)
    if failed is not None:
        k, e = failed
        if not isinstance(e, ScenarioError):
            raise e
        raise ScenarioError(f"{runs[k].strategy}, N = {runs[k].N}: {e}") from None
    return runs


def _played_traffic(scenario: Scenario, known: dict[tuple[int, str], str], key: tuple[int, str]) -> str:
    """The policy ``traffic = "auto"`` plays for a (fleet size, rule set) ``key`` (the layout
    is the same for every run of a study, so once per key)."""
    if key not in known:
        try:
            known[key] = str(scenario.resolved().to_dict().get("traffic", "wait"))
        except ScenarioError:
            known[key] = "auto"  # check_many reports the scenario's error below
    return known[key]


def _row(run: Run, spec: TaskSpec, raw: dict[str, Any]) -> dict[str, Any]:
    """A results.csv row: the run's arm, N and list, and its figures (``sweeps.runner.figures_of``)."""
    return {
        "strategy": run.strategy,
        "N": run.N,
        "tasks": spec.label,
        "list": run.list_id,
        "T": raw["T"],
        "S": raw["S"],
        "C": raw["C"],
        "distance": float(raw["distance"]),
        "cost": raw.get("cost"),
        "outcome": raw["outcome"],
        "delivered": raw["delivered"],
        "goods_total": raw["goods_total"],
        "throughput": raw.get("throughput"),
        "contacts": raw.get("contacts"),
        "wait_share": raw.get("wait_share"),
        "traffic": run.traffic,
        "rules": run.rules,
        "humans": run.humans,
        "protective_stops": raw.get("people_protective_stops"),
        "min_gap": raw.get("people_min_gap"),
        "windows": raw.get("windows", ""),
        "window": raw.get("window"),
        "sustained_throughput": raw.get("sustained_throughput"),
        "latency_p50": raw.get("latency_p50"),
        "latency_p95": raw.get("latency_p95"),
        "utilisation": raw.get("utilisation"),
        "ordered": raw.get("ordered"),
        "backlog_growth": raw.get("backlog_growth"),
        **{f"people_{k}": raw.get(f"people_{k}") for k in PEOPLE_COSTS},
    }


def run_study(
    strategies: Sequence[str],
    robots: Sequence[int],
    spec: TaskSpec,
    seeds: int = 30,
    workers: int = 0,
    base: Optional[Scenario] = None,
    progress: Optional[Callable[[int], None]] = None,
    journal: Optional[str | os.PathLike[str]] = None,
    reused: Optional[Callable[[int, int], None]] = None,
    traffic: Sequence[str] = ("auto",),
    rules: Sequence[str] = ("paper",),
    humans: Sequence[Optional[int]] = (None,),
    runs: Optional[Sequence[Run]] = None,
) -> list[dict[str, Any]]:
    """Runs the study (the runs ``plan_runs`` gives, planned here unless given) and returns
    one row per run, in plan order (deterministic).

    Args:
        progress: called with the number of runs just finished (or taken from the journal).
        journal: a file (``runs.jsonl``): finished runs are recorded there as they finish
            (within about a second), and runs recorded under the same key
            (:mod:`multibots.runs.journal`: scenario, strategy source, engine build)
            are not run again.
        reused: called once, before any run, with (runs taken from the journal, all runs).
    """
    from multibots.sweeps.runner import run_points
    from multibots.sweeps.spec import Point

    if runs is None:
        runs = plan_runs(strategies, robots, spec, seeds, base, traffic, rules, humans, workers)
    # The sweep's runner (docs/sweeps.md) with the journal as its store: the same keys, the
    # same engine calls and worker processes, the same reuse.
    book = Journal(journal)
    points = [Point(k, (), r.scenario, r.allocator) for k, r in enumerate(runs)]
    keys = run_points(points, book, workers=workers, progress=progress, reused=reused)
    return [_row(run, spec, book.done[key]) for run, key in zip(runs, keys)]
