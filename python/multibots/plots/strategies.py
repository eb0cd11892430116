"""The figures of a strategy study: each indicator against N, one line per strategy, CI as a band."""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np

from multibots.plots._common import (
    _PNG_DPI,
    _RC,
    as_number,
    int_axis,
    is_missing,
    new_figure,
    save_atomic,
    series_style,
)

__all__ = ["draw_strategy_comparison"]

_STRATEGY_METRICS = {
    "T": ("strategy_task_time", "Task time T (steps)", "Task time"),
    "S": ("strategy_collisions", "Collisions S", "Collisions"),
    "C": ("strategy_charging", "Charging count C", "Charging count"),
    "cost": ("strategy_cost", "Cost", "Cost"),
}


def _metric_stem(metric: str) -> tuple[str, str, str]:
    """File stem, axis label and short name of a strategy-study metric."""
    if metric in _STRATEGY_METRICS:
        return _STRATEGY_METRICS[metric]
    slug = re.sub(r"[^A-Za-z0-9]+", "_", str(metric)).strip("_").lower() or "metric"
    return f"strategy_{slug}", str(metric), str(metric)


def draw_strategy_comparison(summary_rows: Iterable[Mapping[str, Any]],
                             out_dir: str | os.PathLike[str]) -> list[Path]:
    """Draw one figure per metric of a strategy study.

    Each figure has one line per strategy (mean against N) with its 95%
    confidence interval as a shaded band of the same colour. A strategy keeps its
    colour and marker across the figures. Files are named
    ``strategy_task_time``, ``strategy_collisions``, ``strategy_charging`` and
    ``strategy_cost`` for the metrics T, S, C and cost (any other metric name
    becomes ``strategy_<name>``), each written as ``.png`` and ``.svg``.

    Args:
        summary_rows: Dicts with keys ``strategy``, ``N``, ``metric`` (``"T"``,
            ``"S"``, ``"C"`` or ``"cost"``), ``mean``, ``ci_low`` and ``ci_high``.
            A row whose mean is None/NaN is skipped; a missing CI bound leaves a
            gap in the band.
        out_dir: Folder for the figures; created if missing.

    Returns:
        The paths written, PNG then SVG per metric, metrics in the order T, S, C,
        cost, then any others in order of appearance; a metric with no mean anywhere (T of
        lifelong runs) gets no figure.

    Raises:
        ValueError: ``summary_rows`` is empty.
    """
    rows = [{**r, "N": as_number(r["N"])} for r in summary_rows]
    if not rows:
        raise ValueError("draw_strategy_comparison needs at least one row")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    strategies: list[Any] = []
    metrics: list[Any] = []
    for r in rows:
        if r["strategy"] not in strategies:
            strategies.append(r["strategy"])
        if r["metric"] not in metrics:
            metrics.append(r["metric"])
    order = {m: i for i, m in enumerate(_STRATEGY_METRICS)}
    first = {m: i for i, m in enumerate(metrics)}
    metrics.sort(key=lambda m: (order.get(m, len(order)), first[m]))

    def num(v: Any) -> float:
        return float("nan") if is_missing(v) else float(v)

    written: list[Path] = []
    with matplotlib.rc_context(_RC):
        for metric in metrics:
            # No figure without data: T and Cost_total of lifelong runs, which never complete.
            if all(is_missing(r["mean"]) for r in rows if r["metric"] == metric):
                continue
            stem, ylabel, name = _metric_stem(metric)
            fig = new_figure(figsize=(6.4, 4.4), dpi=_PNG_DPI, layout="constrained")
            ax = fig.add_subplot()
            ax.set_gid("panel-a")
            all_n: set[Any] = set()
            marked = False
            for i, s in enumerate(strategies):
                pts = sorted(
                    ((r["N"], num(r["mean"]), num(r.get("ci_low")), num(r.get("ci_high")),
                      int(r.get("not_complete") or 0) if r.get("n") != r.get("runs", r.get("n")) else 0, r.get("runs"))
                     for r in rows
                     if r["metric"] == metric and r["strategy"] == s and not is_missing(r["mean"])),
                    key=lambda p: p[0])
                if not pts:
                    continue
                ns, mean, lo, hi = (np.array(c, dtype=float) for c in list(zip(*pts))[:4])
                all_n.update(p[0] for p in pts)
                style = series_style(i)
                ax.fill_between(ns, lo, hi, color=style["color"], alpha=0.18,
                                linewidth=0, gid=f"strategy-band-{i}")
                # Whiskers as well as the band: a band over one N is invisible.
                bar = ax.errorbar(ns, mean, yerr=[np.nan_to_num(mean - lo), np.nan_to_num(hi - mean)], label=str(s),
                                  capsize=3, **style)
                bar[0].set_gid(f"strategy-line-{i}")
                bar[2][0].set_gid(f"strategy-whiskers-{i}")
                for n, m, _, _, short, runs in pts:
                    if short:
                        # Runs left out of this mean: said on the point, never hidden.
                        marked = True
                        ax.plot([n], [m], marker="o", markersize=11, markerfacecolor="none", markeredgecolor="red",
                                linestyle="none", gid=f"strategy-short-{i}")
                        ax.annotate(f"{short}/{runs} not complete", (n, m), textcoords="offset points", xytext=(6, 6),
                                    fontsize=7, color="red")
            if marked:
                ax.text(0.01, 0.01, "red rings: means over the runs that completed; the others are counted on "
                        "the point", transform=ax.transAxes, fontsize=7, color="red")
            ax.set_xlabel("Number of robots N")
            ax.set_ylabel(ylabel)
            ax.set_title(f"{name} by strategy (mean and 95% CI)")
            int_axis(ax, all_n, log_if_wide=True)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(loc="best", frameon=False, title="Strategy")
            for suffix in ("png", "svg"):
                written.append(save_atomic(fig, out / f"{stem}.{suffix}"))
    return written
