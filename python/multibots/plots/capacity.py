"""The figure of a capacity question (docs/capacity.md): delivered against demand, or against
fleet size, with the knee marked."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import matplotlib

from multibots.plots._common import _RC, new_figure, save_atomic

__all__ = ["draw_capacities", "draw_capacity"]


def draw_capacity(answer: Any, path: str | os.PathLike[str]) -> Path:
    """Draws ``answer`` (a :class:`multibots.sweeps.capacity.Capacity`) to ``path``: the mean
    deliveries per 1,000 steps after the warm-up at each level tried, the line where delivered
    equals demand, and the knee (the highest sustained level)."""
    by_rate = answer.question == "rate"
    levels = answer.curve
    xs = [lv.demand if by_rate else lv.robots for lv in levels]
    ys = [lv.to_dict()["throughput_per_1000"] for lv in levels]
    with matplotlib.rc_context(_RC):
        fig = new_figure(figsize=(6.4, 4.2))
        ax = fig.add_subplot()
        ax.plot(xs, ys, "o-", label="delivered (mean of the seeds)")
        if by_rate:
            top = max(xs + ys) if xs else 1.0
            ax.plot([0, top], [0, top], ":", color="grey", label="delivered = demand")
            ax.set_xlabel("demand, orders per 1,000 steps")
            ax.set_title("Throughput against demand")
        else:
            ax.axhline(1000 * answer.rate, linestyle=":", color="grey", label="demand")
            ax.set_xlabel("robots")
            ax.set_title("Throughput against fleet size")
        knee = answer.knee
        if knee is not None:
            kx = knee.demand if by_rate else knee.robots
            ax.plot([kx], [knee.to_dict()["throughput_per_1000"]], "*", markersize=14, color="C3",
                    label="knee (highest sustained)" if by_rate else "answer (smallest fleet that sustains)")
        ax.set_ylabel("delivered per 1,000 steps")
        ax.legend()
        fig.tight_layout()
        return save_atomic(fig, path)


def draw_capacities(combos: Any, path: str | os.PathLike[str]) -> Path:
    """Draws several answers (:class:`multibots.sweeps.capacity.Combination`, one per strategy
    and traffic policy) on one figure: a curve each, with its knee marked."""
    by_rate = combos[0].answer.question == "rate"
    with matplotlib.rc_context(_RC):
        fig = new_figure(figsize=(6.8, 4.4))
        ax = fig.add_subplot()
        top = 1.0
        for i, c in enumerate(combos):
            a = c.answer
            xs = [lv.demand if by_rate else lv.robots for lv in a.curve]
            ys = [lv.to_dict()["throughput_per_1000"] for lv in a.curve]
            top = max([top, *xs, *ys])
            ax.plot(xs, ys, "o-", color=f"C{i % 10}", markersize=4, label=c.label)
            knee = a.knee
            if knee is not None:
                ax.plot([knee.demand if by_rate else knee.robots], [knee.to_dict()["throughput_per_1000"]], "*",
                        markersize=13, color=f"C{i % 10}")
        if by_rate:
            ax.plot([0, top], [0, top], ":", color="grey", label="delivered = demand")
            ax.set_xlabel("demand, orders per 1,000 steps")
            ax.set_title("Throughput against demand; * the knee of each", fontsize=10)
        else:
            ax.axhline(1000 * combos[0].answer.rate, linestyle=":", color="grey", label="demand")
            ax.set_xlabel("robots")
            ax.set_title("Throughput against fleet size; * the smallest fleet of each", fontsize=10)
        ax.set_ylabel("delivered per 1,000 steps (mean of the seeds)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        return save_atomic(fig, path)
