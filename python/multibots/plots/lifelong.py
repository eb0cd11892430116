"""Throughput over time of lifelong runs: deliveries per 1,000 steps in each window, the mean
across runs (seeds) with its 95% interval as a band, one line per arm or axis value."""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Optional

from multibots.stats import mean_ci

__all__ = ["Series", "bands", "draw_throughput_over_time", "series_of"]


#: A run's throughput over time: (the step a window ends at, deliveries per 1,000 steps in it).
Series = list[tuple[int, float]]


def series_of(row: Mapping[str, Any]) -> Optional[Series]:
    """A run's deliveries per 1,000 steps in each window (its ``windows`` and ``window``), or
    None when it lasted fewer than two windows."""
    windows = [int(v) for v in str(row.get("windows") or "").split(";") if v]
    width = int(row.get("window") or 1000)
    if len(windows) < 2 or width <= 0:
        return None
    return [((j + 1) * width, 1000.0 * w / width) for j, w in enumerate(windows)]


def bands(runs: Sequence[Series]) -> tuple[list[int], list[float], list[float], list[float]]:
    """Per window (as many as the shortest run has): the step it ends at (the first run's),
    the mean across runs and its 95% interval (the mean itself for a single run), clipped at 0."""
    k = min(len(r) for r in runs)
    steps = [s for s, _ in runs[0][:k]]
    means, los, his = [], [], []
    for j in range(k):
        mean, _, lo, hi = mean_ci([r[j][1] for r in runs], low=0.0)
        m = mean if mean is not None else math.nan
        means.append(m)
        los.append(lo if lo is not None else m)
        his.append(hi if hi is not None else m)
    return steps, means, los, his


def draw_throughput_over_time(groups: Mapping[str, Sequence[Series]], path: str | os.PathLike[str],
                              note: str = "") -> Optional[Path]:
    """One line per group (its runs' series, :func:`series_of`), with the band of its 95%
    interval across runs; None, and no file, when no group has a run."""
    import matplotlib

    from multibots.plots._common import _RC, new_figure, save_atomic

    groups = {k: v for k, v in groups.items() if v}
    if not groups:
        return None
    with matplotlib.rc_context(_RC):  # type: ignore[arg-type]
        fig = new_figure(figsize=(7, 4.2))
        ax = fig.add_subplot()
        for i, (label, runs) in enumerate(groups.items()):
            xs, means, los, his = bands(runs)
            ax.plot(xs, means, color=f"C{i % 10}", label=f"{label} ({len(runs)} runs)")
            ax.fill_between(xs, los, his, color=f"C{i % 10}", alpha=0.18)
        ax.set_xlabel("step (end of each window)")
        ax.set_ylabel("deliveries per 1,000 steps")
        title = "Throughput over time: mean and 95% interval across runs"
        ax.set_title(f"{title}\n{note}" if note else title, fontsize=9)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        return save_atomic(fig, path)
