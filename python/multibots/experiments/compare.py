"""The strategy comparison study behind ``multibots compare``.

Every strategy runs on every (N, task list) pair, so the comparison is *paired*: each
strategy sees exactly the same task lists. Built-in strategies run on the engine's threads
(``_core.simulate_many``); Python strategies (``package.module:Class``) run in worker
processes. The study writes

- ``results.csv``: one row per run (strategy, N, tasks, list, T, S, C, distance, cost, ...);
- ``summary.csv``: per strategy, N (and ``all``, pooled over N) and metric, the mean with its
  95% confidence interval (t distribution), and against ``in-turn`` the paired mean
  difference, its relative size, and the p-values of a paired t-test and a Wilcoxon
  signed-rank test;
- ``summary.txt``: the same as a table, as printed;
- ``strategy_*.png|svg``: T, S, C and Cost_total against N, one line per strategy.

Cost_total = w_d · (distance driven by the fleet, px) + w_t · T + w_c · S, with the weights of
the scenario's ``[cost]`` table. T and Cost_total exist only for complete runs; a pair in which
either run is incomplete is left out of the paired tests (``summary.csv`` says how many pairs
each test used).
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
import os
import re
import statistics
import sys
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

from multibots._io import atomic_write_text
from multibots.paper import PAPER_TASKS
from multibots.scenario import Scenario
from multibots.strategies import BUILT_INS, is_python_allocator

__all__ = [
    "METRICS",
    "BASELINE",
    "TaskSpec",
    "StudyInputError",
    "parse_robots",
    "parse_tasks",
    "parse_strategies",
    "plan_runs",
    "run_study",
    "summarize",
    "format_summary",
    "headline",
    "write_outputs",
]

#: The indicators summarised, in order; "cost" is Cost_total.
METRICS: tuple[str, ...] = ("T", "S", "C", "cost")
#: The strategy every other one is tested against.
BASELINE = "in-turn"

RESULT_FIELDS = ["strategy", "N", "tasks", "list", "T", "S", "C", "distance", "cost", "outcome", "delivered", "goods_total"]
SUMMARY_FIELDS = [
    "strategy", "N", "metric", "n", "mean", "sd", "ci_low", "ci_high",
    "pairs", "diff_vs_in_turn", "rel_diff_pct", "p_ttest", "p_wilcoxon",
]


class StudyInputError(ValueError):
    """A study option with a value the study cannot run with (the CLI prints it as one line)."""


@dataclass(frozen=True)
class TaskSpec:
    """Which task lists the study uses: the paper's five, or ``count`` random goods per list."""

    kind: str  # "paper" or "random"
    count: int = 0

    @property
    def label(self) -> str:
        return "paper" if self.kind == "paper" else f"random:{self.count}"


def parse_robots(text: str) -> list[int]:
    """``1..6`` (inclusive), ``3`` or ``1,2,4`` into fleet sizes, ascending and distinct."""
    out: list[int] = []
    for part in text.split(","):
        part = part.strip()
        m = re.fullmatch(r"(\d+)\s*\.\.\s*(\d+)", part)
        if m:
            lo, hi = int(m.group(1)), int(m.group(2))
            if lo > hi:
                raise StudyInputError(f"--robots = {text!r}: the range {part} is empty (write LOW..HIGH)")
            out.extend(range(lo, hi + 1))
        elif part.isdigit():
            out.append(int(part))
        else:
            raise StudyInputError(f"--robots = {text!r}: expected a range such as 1..6 or a list such as 1,2,4")
    if not out or min(out) < 1:
        raise StudyInputError(f"--robots = {text!r}: fleet sizes must be 1 or more")
    return sorted(set(out))


def parse_tasks(text: str) -> TaskSpec:
    """``paper`` (TABLE III's five lists) or ``random:K`` (K goods per list, one list per seed)."""
    t = text.strip()
    if t == "paper":
        return TaskSpec("paper")
    m = re.fullmatch(r"random:(\d+)", t)
    if m and int(m.group(1)) >= 1:
        return TaskSpec("random", int(m.group(1)))
    raise StudyInputError(f"--tasks = {text!r}: expected paper or random:K with K >= 1, such as random:10")


def parse_strategies(text: str) -> list[str]:
    """Comma-separated strategy names: built-ins or ``package.module:Class``; kept in order."""
    names = [n.strip() for n in text.split(",")]
    if not text.strip() or any(not n for n in names):
        raise StudyInputError(f"--strategies = {text!r}: expected comma-separated strategy names")
    for n in names:
        if not is_python_allocator(n) and n not in BUILT_INS:
            raise StudyInputError(f"--strategies = {n!r}: unknown strategy (built-ins: {', '.join(BUILT_INS)}; or package.module:Class)")
    dup = [n for n in names if names.count(n) > 1]
    if dup:
        raise StudyInputError(f"--strategies = {dup[0]!r}: named twice")
    return names


def task_lists(spec: TaskSpec, seeds: int) -> list[tuple[int, Any]]:
    """(list id, ``tasks`` value) pairs: group numbers for the paper, seeds 1..seeds for random."""
    if spec.kind == "paper":
        return [(g, list(cells)) for g, cells in PAPER_TASKS.items()]
    if seeds < 1:
        raise StudyInputError(f"--seeds = {seeds}: must be 1 or more")
    return [(seed, {"random": spec.count, "seed": seed}) for seed in range(1, seeds + 1)]


@dataclass(frozen=True)
class Run:
    strategy: str
    N: int  # noqa: N815 - the paper's name
    list_id: int
    scenario: Scenario


def plan_runs(
    strategies: Sequence[str], robots: Sequence[int], spec: TaskSpec, seeds: int, base: Optional[Scenario] = None
) -> list[Run]:
    """Every (strategy, N, task list) combination, strategy outer; scenarios validated here."""
    lists = task_lists(spec, seeds)
    template = {} if base is None else base.to_dict()
    for key in ("tasks", "robots", "allocator", "starts"):
        template.pop(key, None)
    runs = []
    for s in strategies:
        for n in robots:
            for list_id, tasks in lists:
                scenario = Scenario.from_dict({**template, "robots": n, "tasks": tasks, "allocator": s})
                runs.append(Run(s, n, list_id, scenario))
    return runs


def _row(run: Run, spec: TaskSpec, raw: dict[str, Any], weights: dict[str, float]) -> dict[str, Any]:
    distance = float(raw["distance"])
    t = raw["T"]
    cost = None if t is None else weights["distance"] * distance + weights["time"] * t + weights["collision"] * raw["S"]
    return {
        "strategy": run.strategy,
        "N": run.N,
        "tasks": spec.label,
        "list": run.list_id,
        "T": t,
        "S": raw["S"],
        "C": raw["C"],
        "distance": distance,
        "cost": cost,
        "outcome": raw["outcome"],
        "delivered": raw["delivered"],
        "goods_total": raw["goods_total"],
    }


def _slim_raw(raw: dict[str, Any]) -> dict[str, Any]:
    """The engine's result dictionary reduced to what a row needs (JSON-ready)."""
    return {
        "T": raw["T"], "S": raw["S"], "C": raw["C"], "distance": float(raw["distance"].sum()),
        "outcome": raw["outcome"], "delivered": raw["delivered"], "goods_total": raw["goods_total"],
    }


def _run_in_process(toml: str) -> dict[str, Any]:
    """A worker process's job: one run of a scenario with a Python strategy."""
    from multibots import _core

    return _slim_raw(_core.simulate(Scenario.from_toml_str(toml, "<study>")._core))


class Journal:
    """Finished runs, appended one JSON line each and flushed to disk as they finish, so that
    a study that is killed loses no finished run: run it again and it resumes.

    A run is keyed by its scenario (which names its strategy), so a journal only ever
    answers for the very same run. A line cut short by the kill is ignored.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self.done: dict[str, dict[str, Any]] = {}
        if self.path.exists():
            for line in self.path.read_text(encoding="utf-8").splitlines():
                try:
                    entry = json.loads(line)
                    self.done[entry["key"]] = entry["result"]
                except (ValueError, KeyError, TypeError):
                    continue

    @staticmethod
    def key(run: Run) -> str:
        return hashlib.sha256(run.scenario.to_toml().encode()).hexdigest()

    def record(self, entries: Sequence[tuple[Run, dict[str, Any]]]) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with self.path.open("a+b") as f:
            # A kill may have cut the last line short: start on a line of our own.
            if f.tell() > 0:
                f.seek(-1, os.SEEK_END)
                if f.read(1) != b"\n":
                    f.write(b"\n")
            for run, result in entries:
                key = self.key(run)
                self.done[key] = result
                f.write((json.dumps({"key": key, "result": result}, separators=(",", ":")) + "\n").encode())
            f.flush()
            os.fsync(f.fileno())


def run_study(
    strategies: Sequence[str],
    robots: Sequence[int],
    spec: TaskSpec,
    seeds: int = 30,
    workers: int = 0,
    base: Optional[Scenario] = None,
    progress: Optional[Callable[[int], None]] = None,
    journal: Optional[str | os.PathLike[str]] = None,
) -> list[dict[str, Any]]:
    """Runs the study and returns one row per run, in plan order (deterministic).

    ``progress`` is called with the number of runs just finished. With ``journal`` (a file),
    every finished run is recorded there at once, and runs already recorded are not run again.
    """
    from multibots import _core

    runs = plan_runs(strategies, robots, spec, seeds, base)
    weights = (base or runs[0].scenario).to_dict()["cost"]
    workers = workers or os.cpu_count() or 1
    results: list[Optional[dict[str, Any]]] = [None] * len(runs)
    tick = progress or (lambda k: None)
    book = Journal(journal) if journal is not None else None
    if book is not None:
        for k, run in enumerate(runs):
            results[k] = book.done.get(Journal.key(run))
        already = sum(r is not None for r in results)
        if already:
            tick(already)

    def finished(entries: list[tuple[int, dict[str, Any]]]) -> None:
        for k, raw in entries:
            results[k] = raw
        if book is not None:
            book.record([(runs[k], raw) for k, raw in entries])
        tick(len(entries))

    engine_jobs = [k for k, r in enumerate(runs) if results[k] is None and not is_python_allocator(r.strategy)]
    python_jobs = [k for k, r in enumerate(runs) if results[k] is None and is_python_allocator(r.strategy)]
    # Chunks a few times the thread count: big enough to keep every core busy, small enough
    # for the progress bar to move.
    chunk = max(4 * workers, 8)
    for start in range(0, len(engine_jobs), chunk):
        ks = engine_jobs[start:start + chunk]
        raws = _core.simulate_many([runs[k].scenario._core for k in ks], workers)
        finished([(k, _slim_raw(raw)) for k, raw in zip(ks, raws)])
    if python_jobs:
        import multiprocessing

        # spawn, not fork: the parent may run a progress thread; the child gets sys.path.
        ctx = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=min(workers, len(python_jobs)), mp_context=ctx) as pool:
            futures = {pool.submit(_run_in_process, runs[k].scenario.to_toml()): k for k in python_jobs}
            try:
                for f in as_completed(futures):
                    finished([(futures[f], f.result())])
            except BaseException:
                # Finished runs are in the journal; do not wait for the others.
                pool.shutdown(wait=False, cancel_futures=True)
                raise
    return [_row(run, spec, raw, weights) for run, raw in zip(runs, results) if raw is not None]


# --- statistics ---------------------------------------------------------------------------


def _mean_ci(values: Sequence[float]) -> tuple[Optional[float], Optional[float], Optional[float], Optional[float]]:
    """Mean, standard deviation and the 95% t confidence interval (None where undefined)."""
    from scipy import stats

    n = len(values)
    if n == 0:
        return None, None, None, None
    mean = statistics.fmean(values)
    if n == 1:
        return mean, None, None, None
    sd = statistics.stdev(values)
    half = float(stats.t.ppf(0.975, n - 1)) * sd / math.sqrt(n)
    return mean, sd, mean - half, mean + half


def _paired(xs: Sequence[float], ys: Sequence[float]) -> tuple[Optional[float], Optional[float]]:
    """p-values of the paired t-test and the Wilcoxon signed-rank test of ys against xs."""
    from scipy import stats

    diffs = [y - x for x, y in zip(xs, ys)]
    if len(diffs) < 2:
        return None, None
    if all(d == 0 for d in diffs):
        # No difference at all: both tests are undefined (zero variance); nothing to reject.
        return 1.0, 1.0
    if len(set(diffs)) == 1:
        # A constant non-zero difference: the t statistic is infinite.
        p_t = 0.0
    else:
        p_t = float(stats.ttest_rel(ys, xs).pvalue)
    nonzero = [d for d in diffs if d != 0]
    p_w = float(stats.wilcoxon(nonzero).pvalue) if nonzero else 1.0
    return p_t, p_w


def _value(row: dict[str, Any], metric: str) -> Optional[float]:
    v = row[metric]
    return None if v is None else float(v)


def summarize(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Summary rows: per strategy, N (and "all") and metric; see the module docstring."""
    strategies = list(dict.fromkeys(r["strategy"] for r in rows))
    ns = sorted({r["N"] for r in rows})
    by_key = {(r["strategy"], r["N"], r["list"]): r for r in rows}
    lists = list(dict.fromkeys(r["list"] for r in rows))
    out = []
    for s in strategies:
        for n in [*ns, "all"]:
            keys = [(s, m, li) for m in (ns if n == "all" else [n]) for li in lists]
            for metric in METRICS:
                vals = [v for k in keys if k in by_key and (v := _value(by_key[k], metric)) is not None]
                mean, sd, lo, hi = _mean_ci(vals)
                row: dict[str, Any] = {
                    "strategy": s, "N": n, "metric": metric, "n": len(vals),
                    "mean": mean, "sd": sd, "ci_low": lo, "ci_high": hi,
                    "pairs": None, "diff_vs_in_turn": None, "rel_diff_pct": None, "p_ttest": None, "p_wilcoxon": None,
                }
                if s != BASELINE and any(k[0] == BASELINE for k in by_key):
                    xs, ys = [], []
                    for k in keys:
                        b = by_key.get((BASELINE, k[1], k[2]))
                        mine = by_key.get(k)
                        if b is None or mine is None:
                            continue
                        x, y = _value(b, metric), _value(mine, metric)
                        if x is not None and y is not None:
                            xs.append(x)
                            ys.append(y)
                    if xs:
                        diff = statistics.fmean(ys) - statistics.fmean(xs)
                        base_mean = statistics.fmean(xs)
                        p_t, p_w = _paired(xs, ys)
                        row.update(
                            pairs=len(xs), diff_vs_in_turn=diff,
                            rel_diff_pct=(100.0 * diff / base_mean) if base_mean else None,
                            p_ttest=p_t, p_wilcoxon=p_w,
                        )
                out.append(row)
    return out


def _fmt(v: Optional[float], digits: int = 1) -> str:
    return "-" if v is None else f"{v:.{digits}f}"


def _fmt_p(p: Optional[float]) -> str:
    if p is None:
        return "-"
    return "<0.001" if p < 0.001 else f"{p:.3f}"


def _p_is(p: Optional[float]) -> str:
    return "p < 0.001" if p is not None and p < 0.001 else f"p = {_fmt_p(p)}"


def headline(summary: Sequence[dict[str, Any]], metric: str) -> Optional[dict[str, Any]]:
    """The strategy with the lowest mean of ``metric`` pooled over N, with its pooled row."""
    pooled = [r for r in summary if r["N"] == "all" and r["metric"] == metric and r["mean"] is not None]
    if not pooled:
        return None
    # Ties go to the strategy named first.
    return min(pooled, key=lambda r: r["mean"])


def format_summary(summary: Sequence[dict[str, Any]], spec_label: str = "") -> str:
    """The summary as plain text: per metric, mean [95% CI] per strategy and N, then the tests."""
    strategies = list(dict.fromkeys(r["strategy"] for r in summary))
    ns = list(dict.fromkeys(r["N"] for r in summary))
    idx = {(r["strategy"], r["N"], r["metric"]): r for r in summary}
    names = {"T": "T (steps)", "S": "S (collisions)", "C": "C (charges)", "cost": "Cost_total"}
    width = max(12, *(len(s) for s in strategies))
    lines = []
    if spec_label:
        lines.append(f"task lists: {spec_label}")
    for metric in METRICS:
        digits = 0 if metric in ("T", "cost") else 2
        lines.append("")
        lines.append(f"{names[metric]}: mean [95% CI]")
        head = f"{'strategy':<{width}}" + "".join(f" | {('N=' + str(n)):^23}" for n in ns)
        lines.append(head)
        lines.append("-" * len(head))
        for s in strategies:
            cells = []
            for n in ns:
                r = idx[(s, n, metric)]
                ci = "" if r["ci_low"] is None else f" [{_fmt(r['ci_low'], digits)}, {_fmt(r['ci_high'], digits)}]"
                cells.append(f" | {(_fmt(r['mean'], digits) + ci):^23}")
            lines.append(f"{s:<{width}}" + "".join(cells))
    if any(r["pairs"] for r in summary):
        lines.append("")
        lines.append(f"against {BASELINE}, pooled over N (paired; diff = strategy - {BASELINE}; negative is better):")
        head = f"{'strategy':<{width}} | metric | pairs |    diff |  diff % | p (t-test) | p (Wilcoxon)"
        lines.append(head)
        lines.append("-" * len(head))
        for s in strategies:
            for metric in METRICS:
                r = idx.get((s, "all", metric))
                if r is None or not r["pairs"]:
                    continue
                lines.append(
                    f"{s:<{width}} | {metric:>6} | {r['pairs']:>5} | {_fmt(r['diff_vs_in_turn'], 1):>7} | {_fmt(r['rel_diff_pct'], 1):>7} "
                    f"| {_fmt_p(r['p_ttest']):>10} | {_fmt_p(r['p_wilcoxon']):>12}"
                )
    for metric in ("T", "cost"):
        best = headline(summary, metric)
        if best is None:
            continue
        base = idx.get((BASELINE, "all", metric))
        text = f"best on {names[metric]} (mean over every N and list): {best['strategy']} with {_fmt(best['mean'], 1)}"
        if base is not None and base["mean"] and best["strategy"] != BASELINE:
            d = best["mean"] - base["mean"]
            text += f", {abs(d):.1f} ({abs(100 * d / base['mean']):.1f}%) {'below' if d < 0 else 'above'} {BASELINE} ({_fmt(base['mean'], 1)})"
            text += f"; paired t-test {_p_is(best['p_ttest'])}, Wilcoxon {_p_is(best['p_wilcoxon'])}"
        lines.insert(0, text)
    return "\n".join(lines).lstrip("\n")


def _csv(rows: Iterable[dict[str, Any]], fields: Sequence[str]) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(fields), lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k])) for k in fields})
    return buf.getvalue()


def write_outputs(rows: Sequence[dict[str, Any]], summary: Sequence[dict[str, Any]], out: str | os.PathLike[str], spec_label: str = "", plots: bool = True) -> list[Path]:
    """Writes results.csv, summary.csv, summary.txt (atomically) and the figures."""
    out = Path(out)
    written = [
        atomic_write_text(out / "results.csv", _csv(rows, RESULT_FIELDS)),
        atomic_write_text(out / "summary.csv", _csv(summary, SUMMARY_FIELDS)),
        atomic_write_text(out / "summary.txt", format_summary(summary, spec_label) + "\n"),
    ]
    if plots:
        from multibots.plots import draw_strategy_comparison

        per_n = [r for r in summary if r["N"] != "all"]
        written += draw_strategy_comparison(per_n, out)
    return written


def progress_bar(total: int, enabled: bool = True) -> Any:
    """A rich progress bar on stderr; a context manager whose ``advance(k)`` moves it."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

    class Bar:
        def __enter__(self) -> Bar:
            self.p = Progress(
                TextColumn("runs"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn(),
                console=Console(file=sys.stderr), disable=not enabled, transient=False,
            )
            self.p.__enter__()
            self.task = self.p.add_task("runs", total=total)
            return self

        def advance(self, k: int) -> None:
            self.p.advance(self.task, k)

        def __exit__(self, *exc: Any) -> None:
            self.p.__exit__(*exc)

    return Bar()
