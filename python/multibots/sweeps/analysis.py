"""Statistics over a sweep's results: mean and 95% interval per cell of the grid, paired tests
against a baseline value of one axis, and plots of a metric against a numeric axis."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Optional

from multibots.exceptions import InputError
from multibots.stats import mean_ci, paired_t_test, wilcoxon

__all__ = ["METRICS", "RANGE", "interval", "paired_tests", "plot", "summarize", "throughput_over_time"]

#: The metrics summarised (those a run has; None values are left out).
#: Every numeric figure a run stores (``runner.figures_of``) can be plotted.
METRICS = ("T", "S", "C", "cost", "distance", "steps", "delivered", "goods_total", "throughput",
           "sustained_throughput", "wait_share", "utilisation", "contacts", "closest", "latency_p50", "latency_p95",
           "energy_per_delivery", "ordered", "backlog_growth", "window", "people_protective_stops", "people_min_gap",
           "people_warning_steps", "people_person_wait_steps", "people_tours", "people_picks", "people_walk_steps",
           "people_blocked_steps", "people_picks_per_hour", "people_tours_per_hour", "people_walk_share",
           "people_blocked_share", "people_alone_picks_per_hour", "people_alone_tours_per_hour",
           "people_alone_walk_share", "people_alone_blocked_share")


#: The range of each figure, which its interval is clipped to (a count or a rate is never
#: below 0, a share never above 1); a figure not named takes any value. The backlog's growth
#: takes either sign: a fleet that keeps up catches up on its backlog by chance as often as it
#: falls behind.
_SHARES = ("wait_share", "utilisation", "people_walk_share", "people_blocked_share", "people_alone_walk_share",
           "people_alone_blocked_share")
_NON_NEGATIVE = ("T", "S", "C", "cost", "distance", "steps", "delivered", "goods_total", "throughput",
                 "sustained_throughput", "contacts", "latency_p50", "latency_p95", "energy_per_delivery", "ordered",
                 "window", "people_protective_stops", "people_warning_steps", "people_person_wait_steps",
                 "people_tours", "people_picks", "people_walk_steps", "people_blocked_steps", "people_picks_per_hour",
                 "people_tours_per_hour", "people_alone_picks_per_hour", "people_alone_tours_per_hour",
                 # A LoRR study's (sweeps/lorr.py).
                 "plan_ms_mean", "schedule_ms_mean", "schedule_errors", "action_errors", "delays")
RANGE: dict[str, tuple[Optional[float], Optional[float]]] = {
    **{m: (0.0, None) for m in _NON_NEGATIVE}, **{m: (0.0, 1.0) for m in _SHARES}}


def interval(values: Sequence[float], metric: str) -> tuple[Optional[float], Optional[float], Optional[float],
                                                            Optional[float]]:
    """Mean, sd and the 95% t interval of the mean of ``metric`` over runs (seeds), clipped to
    the figure's range: the one interval ``compare`` and ``sweep`` report."""
    low, high = RANGE.get(metric, (None, None))
    return mean_ci(values, 0.95, low=low, high=high)


def _number(v: Any) -> Optional[float]:
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) else None


def summarize(rows: Sequence[dict[str, Any]], axes: Sequence[str],
              metrics: Sequence[str] = METRICS) -> list[dict[str, Any]]:
    """One row per cell (the axes' values other than ``seed``) and metric: n, mean, sd and the
    95% interval of the mean (:func:`interval`, clipped to the figure's range)."""
    cells = [a for a in axes if a != "seed"]
    groups: dict[tuple[Any, ...], list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault(tuple(r.get(a) for a in cells), []).append(r)
    out = []
    for cell, members in groups.items():
        for m in metrics:
            values = [x for x in (_number(r.get(m)) for r in members) if x is not None]
            mean, sd, lo, hi = interval(values, m)
            out.append({**dict(zip(cells, cell)), "metric": m, "n": len(values), "mean": mean, "sd": sd,
                        "ci_low": lo, "ci_high": hi})
    return out


def parse_baseline(text: str, axes: Sequence[str]) -> tuple[str, str]:
    axis, sep, value = text.partition("=")
    if not sep or axis not in axes or axis == "seed":
        raise InputError(f"--baseline = {text!r}: expected AXIS=VALUE with one of the axes ({', '.join(axes)})")
    return axis, value


def paired_tests(rows: Sequence[dict[str, Any]], axes: Sequence[str], axis: str, value: str,
                 metrics: Sequence[str] = METRICS) -> list[dict[str, Any]]:
    """Each other value of ``axis`` against ``value``, run for run: pairs agree on every other
    axis (the seed included). Mean difference, paired t test and Wilcoxon signed-rank p-values."""
    others = [a for a in axes if a != axis]
    cells = [a for a in others if a != "seed"]
    by_key = {(str(r.get(axis)),) + tuple(r.get(a) for a in others): r for r in rows}
    values = sorted({str(r.get(axis)) for r in rows} - {value})
    if value not in {str(r.get(axis)) for r in rows}:
        raise InputError(f"--baseline {axis}={value}: no run has {axis} = {value}")
    out = []
    cell_keys = sorted({tuple(r.get(a) for a in cells) for r in rows}, key=repr)
    for v in values:
        for cell in cell_keys:
            for m in metrics:
                xs, ys = [], []
                for r in rows:
                    if str(r.get(axis)) != value or tuple(r.get(a) for a in cells) != cell:
                        continue
                    other = by_key.get((v,) + tuple(r.get(a) for a in others))
                    x, y = _number(r.get(m)), _number(other.get(m)) if other else None
                    if x is not None and y is not None:
                        xs.append(x)
                        ys.append(y)
                diffs = [y - x for x, y in zip(xs, ys)]
                p_t = p_w = None
                if len(diffs) >= 2 and any(d != diffs[0] for d in diffs):
                    p_t = paired_t_test(xs, ys)
                    p_w = wilcoxon(diffs)
                out.append({**dict(zip(cells, cell)), axis: v, "baseline": value, "metric": m, "pairs": len(diffs),
                            "mean_diff": sum(diffs) / len(diffs) if diffs else None, "p_ttest": p_t, "p_wilcoxon": p_w})
    return out


def parse_plot(spec: str, axes: Sequence[str], values: Optional[dict[str, Sequence[Any]]] = None,
               metrics: Sequence[str] = METRICS) -> tuple[str, str, Optional[str]]:
    """Checks ``METRIC:AXIS[:BY]`` against the sweep's axes before any run: ``(metric, axis,
    by)``, ``by`` None when not given. Any axis will do: a numeric one is a scale, any other
    (a strategy, a traffic policy) a category per value."""
    parts = spec.split(":")
    if len(parts) not in (2, 3) or parts[0] not in metrics or parts[1] not in axes:
        raise InputError(f"--plot = {spec!r}: expected METRIC:AXIS[:BY], METRIC one of {', '.join(metrics)}, "
                         f"AXIS one of {', '.join(axes)}")
    metric, axis = parts[0], parts[1]
    by = parts[2] if len(parts) == 3 else None
    if by is not None and (by not in axes or by == axis):
        others = ", ".join(a for a in axes if a != axis)
        raise InputError(f"--plot = {spec!r}: {by} is not another axis (one of {others})")
    return metric, axis, by


def plot(rows: Sequence[dict[str, Any]], axes: Sequence[str], spec: str, out: Path,
         metrics: Sequence[str] = METRICS) -> Path:
    """``METRIC:AXIS[:BY]``: the metric's mean (with its 95% interval) against an axis (its
    values as categories when they are not numbers), one line per value of BY (default: the
    first other axis with several values). The title names the axes the means are taken over."""
    import numpy as np

    from multibots.plots._common import new_figure, save_atomic

    metric, axis, by = parse_plot(spec, axes, metrics=metrics)
    numeric = all(_number(r.get(axis)) is not None for r in rows)
    # A category axis keeps its values in the order of the rows (the spec's order).
    ticks = list(dict.fromkeys(str(r.get(axis)) for r in rows))

    def x_of(r: dict[str, Any]) -> float:
        return float(r[axis]) if numeric else float(ticks.index(str(r.get(axis))))

    if by is None:
        by = next((a for a in axes if a not in (axis, "seed") and len({repr(r.get(a)) for r in rows}) > 1), None)
    over = [a for a in axes if a not in (axis, by) and len({repr(r.get(a)) for r in rows}) > 1]
    fig = new_figure(figsize=(7, 4.5))
    ax = fig.add_subplot()
    lines = sorted({repr(r.get(by)) for r in rows}) if by else ["all"]
    marked = False
    for line in lines:
        members = [r for r in rows if by is None or repr(r.get(by)) == line]
        xs = sorted({x_of(r) for r in members})
        means, los, his, short = [], [], [], []
        for x in xs:
            at = [r for r in members if x_of(r) == x]
            vals = [v for v in (_number(r.get(metric)) for r in at) if v is not None]
            mean, _, lo, hi = interval(vals, metric)
            means.append(mean if mean is not None else math.nan)
            los.append(lo if lo is not None else means[-1])
            his.append(hi if hi is not None else means[-1])
            # Runs the mean leaves out (a stranded run has no T): counted on the point.
            short.append((len(at) - len(vals), len(at)))
        label = f"{by} = {line.strip(chr(39))}" if by else metric
        mean_a, lo_a, hi_a = (np.array(v, dtype=float) for v in (means, los, his))
        bar = ax.errorbar(xs, means, yerr=[np.nan_to_num(mean_a - lo_a), np.nan_to_num(hi_a - mean_a)], marker="o",
                          capsize=3, label=label)
        ax.fill_between(xs, los, his, alpha=0.15, color=bar[0].get_color())
        for x, m, (missing, total) in zip(xs, means, short):
            if missing:
                marked = True
                shown_at = m if not math.isnan(m) else 0.0
                ax.plot([x], [shown_at], marker="o", markersize=11, markerfacecolor="none", markeredgecolor="red",
                        linestyle="none")
                ax.annotate(f"{missing}/{total} not in mean", (x, shown_at), textcoords="offset points",
                            xytext=(6, 6), fontsize=7, color="red")
    if not numeric:
        ax.set_xticks(range(len(ticks)), ticks)
    ax.set_xlabel(axis)
    ax.set_ylabel(f"{metric} (mean, 95% interval)")
    title = f"mean over {', '.join(over)}" if over else "one run per point"
    if marked:
        title += f"; red rings: runs with no {metric} (not complete) left out of the mean, counted on the point"
    ax.set_title(title, fontsize=8 if marked else 9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    path = out / f"plot-{metric}-{axis.replace('.', '_')}.png"
    return save_atomic(fig, path)


def throughput_over_time(rows: Sequence[dict[str, Any]], axes: Sequence[str], out: Path) -> list[Path]:
    """For lifelong runs: deliveries per 1,000 steps in each window, the mean with its 95%
    band across runs, one figure per axis that varies (a line per value; the runs of the
    other axes and the seeds pooled), or one line when none varies. No runs with at least two
    windows, no figure."""
    from multibots.plots.lifelong import Series, draw_throughput_over_time, series_of

    varying = [a for a in axes if a != "seed" and len({repr(r.get(a)) for r in rows}) > 1]
    written = []
    for axis in varying or [None]:
        groups: dict[str, list[Series]] = {}
        for r in rows:
            label = f"{axis} = {r.get(axis)}" if axis else "all runs"
            series = series_of(r)
            if series is not None:
                groups.setdefault(label, []).append(series)
        name = f"throughput-time-{axis.replace('.', '_')}.png" if axis else "throughput-time.png"
        path = draw_throughput_over_time(groups, out / name, f"per {axis}, runs pooled" if axis else "")
        if path is not None:
            written.append(path)
    return written
