"""What a strategy study's rows add up to: means with confidence intervals, paired tests
against ``in-turn``, the text tables ``multibots compare`` prints (at most 100 columns), and
the files it writes.

Every indicator (T, S, C, Cost_total) is 0 or more, so its confidence interval is clipped at
0: with few task lists and many zero counts, mean - t·sd/√n can fall below 0, and a count
cannot. A clipped interval is no longer symmetric about the mean. The interval is the sweep's
(:func:`multibots.sweeps.analysis.interval`): one implementation, one range per figure.
"""

from __future__ import annotations

import csv
import io
import os
import statistics
import sys
import textwrap
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any, Optional

from multibots import stats
from multibots._io import atomic_write_text, staged_folder
from multibots.sweeps.analysis import interval

__all__ = [
    "BASELINE",
    "METRICS",
    "RESULT_FIELDS",
    "SUMMARY_FIELDS",
    "WIDTH",
    "format_summary",
    "headline",
    "progress_bar",
    "summarize",
    "write_outputs",
]

#: The indicators summarised, in order; "cost" is Cost_total, "throughput" deliveries per
#: 1,000 steps, "contacts" pairs of robots closer than r_i + r_j after a move; then the
#: figures of lifelong runs: sustained throughput, order latency p50 and p95 (steps),
#: utilisation and backlog growth (orders per 1,000 steps left unserved) (docs/metrics.md).
#: A figure no run has (T of lifelong runs, latency of finite ones) is left out of the tables.
METRICS: tuple[str, ...] = ("T", "S", "C", "cost", "throughput", "contacts", "sustained_throughput",
                            "latency_p50", "latency_p95", "utilisation", "backlog_growth", "people_picks_per_hour",
                            "people_walk_share", "people_blocked_share")
#: The strategy every other one is tested against, when it is in the study (else the first
#: one compared: an arm such as ``in-turn/wait`` when traffic policies are compared too).
BASELINE = "in-turn"
#: The widest line the text tables print.
WIDTH = 100

RESULT_FIELDS = [
    "strategy", "N", "tasks", "list", "T", "S", "C", "distance", "cost", "outcome", "delivered", "goods_total",
    "throughput", "contacts", "wait_share", "traffic", "rules", "humans", "protective_stops", "min_gap", "windows",
    "window", "sustained_throughput", "latency_p50", "latency_p95", "utilisation", "ordered", "backlog_growth",
    "people_picks_per_hour", "people_tours_per_hour", "people_walk_share", "people_blocked_share",
    "people_alone_picks_per_hour", "people_alone_tours_per_hour", "people_alone_walk_share",
    "people_alone_blocked_share",
]
SUMMARY_FIELDS = [
    "strategy", "N", "metric", "n", "runs", "not_complete", "mean", "sd", "ci_low", "ci_high",
    "pairs", "diff_vs_in_turn", "rel_diff_pct", "p_ttest", "p_wilcoxon",
]
_NAMES = {
    "T": "T (steps)", "S": "S (collisions)", "C": "C (charges)", "cost": "Cost_total",
    "throughput": "throughput (deliveries per 1,000 steps)", "contacts": "contacts",
    "sustained_throughput": "sustained throughput (deliveries per 1,000 steps, settled)",
    "latency_p50": "order latency p50 (steps)", "latency_p95": "order latency p95 (steps)",
    "utilisation": "utilisation (share of robot-steps working)",
    "backlog_growth": "backlog growth (orders per 1,000 steps left unserved)",
    "people_picks_per_hour": "people's picks per worker-hour",
    "people_walk_share": "share of people's time walking",
    "people_blocked_share": "share of people's time held up",
}
#: Decimals each indicator is printed with.
_DIGITS = {"T": 0, "cost": 0, "contacts": 0, "latency_p50": 0, "latency_p95": 0, "throughput": 1,
           "sustained_throughput": 1, "backlog_growth": 1,
           "people_picks_per_hour": 1, "people_walk_share": 3, "people_blocked_share": 3}


def baseline_of(strategies: Sequence[str]) -> str:
    """The arm every other one is tested against: ``in-turn`` (alone, or its first arm when
    traffic policies or rule sets are compared too), else the first arm."""
    for s in strategies:
        if s == BASELINE:
            return s
    for s in strategies:
        if s.split("/")[0] == BASELINE:
            return s
    return strategies[0]


# --- statistics ---------------------------------------------------------------------------


def _paired(xs: Sequence[float], ys: Sequence[float]) -> tuple[Optional[float], Optional[float]]:
    """p-values of the paired t-test and the Wilcoxon signed-rank test of ys against xs."""
    diffs = [y - x for x, y in zip(xs, ys)]
    if len(diffs) < 2:
        return None, None
    if all(d == 0 for d in diffs):
        # No difference at all: both tests are undefined (zero variance); nothing to reject.
        return 1.0, 1.0
    # A constant non-zero difference: the t statistic is infinite.
    p_t = 0.0 if len(set(diffs)) == 1 else stats.paired_t_test(xs, ys)
    return p_t, stats.wilcoxon(diffs)


def _value(row: dict[str, Any], metric: str) -> Optional[float]:
    v = row.get(metric)
    return None if v is None else float(v)


def summarize(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Summary rows: per strategy, N (and "all") and metric, the mean with its 95% CI and,
    against the baseline, the paired difference and tests (see the module docstring)."""
    strategies = list(dict.fromkeys(r["strategy"] for r in rows))
    ns = sorted({r["N"] for r in rows})
    by_key = {(r["strategy"], r["N"], r["list"]): r for r in rows}
    lists = list(dict.fromkeys(r["list"] for r in rows))
    base = baseline_of(strategies)
    has_baseline = len(strategies) > 1
    out = []
    for s in strategies:
        for n in [*ns, "all"]:
            keys = [(s, m, li) for m in (ns if n == "all" else [n]) for li in lists]
            runs = [by_key[k] for k in keys if k in by_key]
            # Runs that ended short of their goal (stranded, jammed, out of steps): T and
            # Cost_total have no value for them, and every mean says how many it leaves out.
            short = sum(1 for r in runs if r.get("outcome") not in ("complete", "horizon"))
            for metric in METRICS:
                vals = [v for k in keys if k in by_key and (v := _value(by_key[k], metric)) is not None]
                mean, sd, lo, hi = interval(vals, metric)
                row: dict[str, Any] = {
                    "strategy": s, "N": n, "metric": metric, "n": len(vals), "runs": len(runs), "not_complete": short,
                    "mean": mean, "sd": sd, "ci_low": lo, "ci_high": hi,
                    "pairs": None, "diff_vs_in_turn": None, "rel_diff_pct": None, "p_ttest": None, "p_wilcoxon": None,
                }
                if s != base and has_baseline:
                    row.update(_against_baseline(by_key, keys, metric, base))
                out.append(row)
    return out


def _against_baseline(by_key: dict[Any, dict[str, Any]], keys: list[Any], metric: str, base: str) -> dict[str, Any]:
    xs, ys = [], []
    for k in keys:
        b = by_key.get((base, k[1], k[2]))
        mine = by_key.get(k)
        if b is None or mine is None:
            continue
        x, y = _value(b, metric), _value(mine, metric)
        if x is not None and y is not None:
            xs.append(x)
            ys.append(y)
    if not xs:
        return {}
    diff = statistics.fmean(ys) - statistics.fmean(xs)
    base_mean = statistics.fmean(xs)
    p_t, p_w = _paired(xs, ys)
    return {
        "pairs": len(xs), "diff_vs_in_turn": diff,
        "rel_diff_pct": (100.0 * diff / base_mean) if base_mean else None,
        "p_ttest": p_t, "p_wilcoxon": p_w,
    }


def headline(summary: Sequence[dict[str, Any]], metric: str) -> Optional[dict[str, Any]]:
    """The strategy with the lowest mean of ``metric`` pooled over N, with its pooled row."""
    pooled = [r for r in summary if r["N"] == "all" and r["metric"] == metric and r["mean"] is not None]
    if not pooled:
        return None
    # Ties go to the strategy named first.
    return min(pooled, key=lambda r: r["mean"])


# --- text ---------------------------------------------------------------------------------


def _fmt(v: Optional[float], digits: int = 1) -> str:
    return "-" if v is None else f"{v:.{digits}f}"


def _fmt_p(p: Optional[float]) -> str:
    if p is None:
        return "-"
    return "<0.001" if p < 0.001 else f"{p:.3f}"


def _p_is(p: Optional[float]) -> str:
    return "p < 0.001" if p is not None and p < 0.001 else f"p = {_fmt_p(p)}"


def _label_width(labels: Iterable[str]) -> int:
    """The label column: as wide as the labels up to 24 characters; a longer label gets a line
    of its own (:func:`_labelled`)."""
    return max([8, *(len(s) for s in labels if len(s) <= 24)])


def _labelled(label: str, width: int, rest: str) -> list[str]:
    if len(label) <= width:
        return [f"{label:<{width}}{rest}"]
    return [label, f"{'':<{width}}{rest}"]


def _grid(title: str, labels: list[str], columns: list[str], cells: dict[tuple[str, str], str]) -> list[str]:
    """A table of ``cells[label, column]``, split into blocks of columns that fit :data:`WIDTH`."""
    w = _label_width(labels)
    cw = max(len(c) for c in [*columns, *cells.values()])
    per_block = max(1, (WIDTH - w) // (cw + 3))
    lines = [title]
    for b in range(0, len(columns), per_block):
        block = columns[b:b + per_block]
        head = f"{'strategy':<{w}}" + "".join(f" | {c:^{cw}}" for c in block)
        if b:
            lines.append("")
        lines += [head, "-" * len(head)]
        for s in labels:
            lines += _labelled(s, w, "".join(f" | {cells[s, c]:^{cw}}" for c in block).rstrip())
    return lines


def format_windows(rows: Sequence[dict[str, Any]]) -> list[str]:
    """Deliveries per window over time, the mean over each arm's runs, as sparklines (for
    studies whose runs last at least two windows)."""
    from multibots._text import sparkline

    series: dict[str, list[list[int]]] = {}
    for r in rows:
        w = [int(v) for v in str(r.get("windows") or "").split(";") if v]
        if len(w) >= 2:
            series.setdefault(r["strategy"], []).append(w)
    if not series:
        return []
    width = _label_width(list(series))
    lines = ["", "deliveries per window over time (mean over each arm's runs; see results.csv):"]
    for arm, runs in series.items():
        k = min(len(w) for w in runs)
        mean = [statistics.fmean(w[j] for w in runs) for j in range(k)]
        line = f"{arm:<{width}} {sparkline(mean, 60)} {min(mean):.0f}..{max(mean):.0f}"
        lines.append(line if len(line) <= WIDTH else line[:WIDTH])
    return lines


def format_summary(summary: Sequence[dict[str, Any]], spec_label: str = "") -> str:
    """The summary as plain text, at most :data:`WIDTH` columns: per metric, mean [95% CI] per
    strategy and N (in blocks of N that fit), then the paired tests, headlines first."""
    strategies = list(dict.fromkeys(r["strategy"] for r in summary))
    ns = list(dict.fromkeys(r["N"] for r in summary))
    idx = {(r["strategy"], r["N"], r["metric"]): r for r in summary}
    base_name = baseline_of(strategies)
    lines = []
    if spec_label:
        lines.append(f"task lists: {spec_label}")
    for metric in METRICS:
        if all(idx[(s, n, metric)]["n"] == 0 for s in strategies for n in ns):
            continue  # T and Cost_total of lifelong runs, which never complete
        digits = _DIGITS.get(metric, 2)
        cells = {}
        for s in strategies:
            for n in ns:
                r = idx[(s, n, metric)]
                ci = "" if r["ci_low"] is None else f" [{_fmt(r['ci_low'], digits)}, {_fmt(r['ci_high'], digits)}]"
                cells[s, f"N={n}"] = _fmt(r["mean"], digits) + ci
        lines.append("")
        lines += _grid(f"{_NAMES[metric]}: mean [95% CI]", strategies, [f"N={n}" for n in ns], cells)
    if any(r["not_complete"] for r in summary):
        # Said before any mean can mislead: a strategy whose runs strand has its T over the
        # few that finished.
        cells = {(s, f"N={n}"): f"{idx[(s, n, 'S')]['not_complete']} of {idx[(s, n, 'S')]['runs']}"
                 for s in strategies for n in ns}
        lines.append("")
        lines += _grid("runs that did not complete (stranded, jammed, out of steps; left out of T, Cost_total)",
                       strategies, [f"N={n}" for n in ns], cells)
    if any(r["pairs"] for r in summary):
        lines += ["", f"against {base_name}, pooled over N (paired; diff = strategy - {base_name};",
                  "negative is better, but for throughput, sustained throughput, utilisation, picks):"]
        w = _label_width(strategies)
        head = f"{'strategy':<{w}} |     metric | pairs |      diff |  diff % | p (t-test) | p (Wilcoxon)"
        lines += [head, "-" * len(head)]
        for s in strategies:
            first = True
            for metric in METRICS:
                r = idx.get((s, "all", metric))
                if r is None or not r["pairs"]:
                    continue
                label = s if first or len(s) <= w else ""  # a long name once, on its own line
                first = False
                rest = (
                    f" | {metric:>10} | {r['pairs']:>5} | {_fmt(r['diff_vs_in_turn'], 1):>9} | "
                    f"{_fmt(r['rel_diff_pct'], 1):>7} | {_fmt_p(r['p_ttest']):>10} | {_fmt_p(r['p_wilcoxon']):>12}"
                )
                lines += _labelled(label, w, rest)
        few = min((r["pairs"] for r in summary if r["pairs"]), default=0)
        if 0 < few < stats.pairs_to_reach(0.05):
            lines += textwrap.wrap(
                f"note: with {few} pairs the Wilcoxon test cannot give p below {stats.wilcoxon_floor(few):.4g} "
                f"(2 / 2^{few}), whatever the data, so it cannot reach 0.05; it needs at least "
                f"{stats.pairs_to_reach(0.05)} pairs (more seeds or task lists)", WIDTH, subsequent_indent="  ")
    for metric in ("T", "cost"):
        best = headline(summary, metric)
        if best is None:
            continue
        base = idx.get((base_name, "all", metric))
        text = f"best on {_NAMES[metric]} (mean over every N and list): {best['strategy']} with {_fmt(best['mean'], 1)}"
        if base is not None and base["mean"] and best["strategy"] != base_name:
            d = best["mean"] - base["mean"]
            text += (
                f", {abs(d):.1f} ({abs(100 * d / base['mean']):.1f}%) {'below' if d < 0 else 'above'} {base_name}"
                f" ({_fmt(base['mean'], 1)}); paired t-test {_p_is(best['p_ttest'])},"
                f" Wilcoxon {_p_is(best['p_wilcoxon'])}"
            )
        wrapped = textwrap.wrap(text, WIDTH, subsequent_indent="  ", break_on_hyphens=False)
        lines[0:0] = wrapped
    return "\n".join(lines).lstrip("\n")


# --- files --------------------------------------------------------------------------------


def _csv(rows: Iterable[dict[str, Any]], fields: Sequence[str]) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(fields), lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({
            k: ("" if r.get(k) is None else (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k])) for k in fields
        })
    return buf.getvalue()


def write_outputs(
    rows: Sequence[dict[str, Any]], summary: Sequence[dict[str, Any]], out: str | os.PathLike[str],
    spec_label: str = "", plots: bool = True,
) -> list[Path]:
    """Writes results.csv, summary.csv, summary.txt and the figures (for lifelong runs also
    ``throughput_over_time.png``), all or none (staged)."""
    out = Path(out)
    with staged_folder(out) as stage:
        written = [
            atomic_write_text(stage / "results.csv", _csv(rows, RESULT_FIELDS)),
            atomic_write_text(stage / "summary.csv", _csv(summary, SUMMARY_FIELDS)),
            atomic_write_text(stage / "summary.txt", format_summary(summary, spec_label) + "\n"),
        ]
        if plots:
            from multibots.plots import draw_strategy_comparison
            from multibots.plots.lifelong import Series, draw_throughput_over_time, series_of

            per_n = [r for r in summary if r["N"] != "all"]
            written += draw_strategy_comparison(per_n, stage)
            # Lifelong runs: each arm's throughput over time, a band across its runs.
            groups: dict[str, list[Series]] = {}
            for r in rows:
                series = series_of(r)
                if series is not None:
                    groups.setdefault(str(r["strategy"]), []).append(series)
            drawn = draw_throughput_over_time(groups, stage / "throughput_over_time.png", "per strategy, every N "
                                              "and seed")
            if drawn is not None:
                written.append(drawn)
    return [out / Path(p).relative_to(stage) for p in written]


def progress_bar(total: Optional[int], enabled: bool = True) -> Any:
    """A rich progress bar on stderr; a context manager whose ``advance(k)`` moves it.
    ``total`` None: runs counted as they finish, with no end known ahead."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

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
