"""The figure of a capacity question (docs/capacity.md): delivered against demand, or against
fleet size, with the knee marked."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import matplotlib

from multibots.plots._common import _RC, new_figure, save_atomic

__all__ = ["draw_capacity"]


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
                    label="knee (highest sustained)")
        ax.set_ylabel("delivered per 1,000 steps")
        ax.legend()
        fig.tight_layout()
        return save_atomic(fig, path)
