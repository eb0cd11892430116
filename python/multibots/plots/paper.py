"""The paper's Fig. 6-8: T, S and C against the number of robots N, per task group and on average."""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.ticker import MaxNLocator

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

__all__ = ["draw_paper_figures"]

_PAPER_METRICS = (
    ("T", "fig6_task_time", "Task time T (steps)", "Task time"),
    ("S", "fig7_collisions", "Collisions S", "Collisions"),
    ("C", "fig8_charging", "Charging count C", "Charging count"),
)


def _describe_missing(missing: Sequence[tuple[Any, Any]]) -> str:
    """'group 2 at N = 1, 3; group 4 at N = 1' from (group, N) pairs."""
    by_group: dict[Any, list[Any]] = {}
    for g, n in missing:
        by_group.setdefault(g, []).append(n)
    parts = [f"group {g} at N = {', '.join(str(n) for n in sorted(ns))}"
             for g, ns in sorted(by_group.items(), key=lambda kv: str(kv[0]))]
    return "; ".join(parts)


def draw_paper_figures(rows: Iterable[Mapping[str, Any]],
                       out_dir: str | os.PathLike[str],
                       published: Iterable[Mapping[str, Any]] | None = None,
                       seconds_per_step: float | None = None,
                       title: str | None = None) -> list[Path]:
    """Draw the paper's Fig. 6-8 from the results of its experiment.

    Writes ``fig6_task_time``, ``fig7_collisions`` and ``fig8_charging``, each as
    ``.png`` and ``.svg``. Each figure has two panels: (a) one line per task
    group against N (each group shifted sideways by a few hundredths of the N
    step, so that groups with equal values stay visible), and (b) the mean over
    the groups against N. A row whose
    value is None (T of an incomplete run) is left out of that figure, and a note
    under the panels names it; a mean over fewer groups than the others is drawn
    with a hollow marker.

    Args:
        rows: One dict per run with keys ``N``, ``group``, ``T``, ``S`` and ``C``
            (the paper's experiment: 30 rows, N = 1..6 x groups 1..5).
        out_dir: Folder for the figures; created if missing.
        published: The values published in the paper (keys ``N``, ``group``, ``T_seconds``,
            ``S``, ``C``), drawn over each figure as crosses (panel a, in each group's colour)
            and a dashed line of their means (panel b).
        seconds_per_step: With ``published``: T is drawn in seconds, the runs' steps times
            this (the paper's T is wall-clock time, about 0.0508 s per tick).
        title: A line above the figures, such as the rule set drawn.

    Returns:
        The six paths written, PNG then SVG for each figure, in figure order.

    Raises:
        ValueError: ``rows`` is empty.
    """
    rows = [{**r, "N": as_number(r["N"])} for r in rows]
    if not rows:
        raise ValueError("draw_paper_figures needs at least one row")
    pub = [{**p, "N": as_number(p["N"]), "T": p.get("T_seconds")} for p in (published or [])]
    if seconds_per_step is not None:
        rows = [{**r, "T": None if is_missing(r.get("T")) else float(r["T"]) * seconds_per_step} for r in rows]
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    groups = sorted({r["group"] for r in rows}, key=lambda g: (str(type(g)), g))
    all_n = sorted({r["N"] for r in rows})
    written: list[Path] = []
    with matplotlib.rc_context(_RC):
        for key, stem, ylabel, name in _PAPER_METRICS:
            fig = new_figure(figsize=(10, 4.3), dpi=_PNG_DPI, layout="constrained")
            ax_a, ax_b = fig.subplots(1, 2)
            ax_a.set_gid("panel-a")
            ax_b.set_gid("panel-b")
            missing = [(r["group"], r["N"]) for r in rows if is_missing(r.get(key))]
            values: dict[Any, dict[Any, float]] = {g: {} for g in groups}
            for r in rows:
                if not is_missing(r.get(key)):
                    values[r["group"]][r["N"]] = float(r[key])
            # Counts tie often (several groups with S = 0 at N = 1): each group is
            # shifted sideways a little so that no line or marker hides another.
            step = min(np.diff(all_n), default=1.0)
            dodge = 0.07 * step if len(groups) > 1 else 0.0
            for i, g in enumerate(groups):
                ns = sorted(values[g])
                if not ns:
                    continue
                shift = (i - (len(groups) - 1) / 2) * dodge
                ax_a.plot([n + shift for n in ns], [values[g][n] for n in ns],
                          label=f"Group {g}", gid=f"group-line-{i}", **series_style(i))
            mean_n, mean_v, partial = [], [], []
            for n in all_n:
                vs = [values[g][n] for g in groups if n in values[g]]
                if vs:
                    mean_n.append(n)
                    mean_v.append(float(np.mean(vs)))
                    partial.append(len(vs) < len(groups))
            ax_b.plot(mean_n, mean_v, color="#333333", marker="o", gid="mean-line",
                      label="Mean over groups")
            if pub and (key != "T" or seconds_per_step is not None):
                for i, g in enumerate(groups):
                    pts = sorted((p["N"], float(p[key])) for p in pub if p["group"] == g and not is_missing(p.get(key)))
                    if pts:
                        shift = (i - (len(groups) - 1) / 2) * dodge
                        ax_a.plot([n + shift for n, _ in pts], [v for _, v in pts], ls="none", marker="x",
                                  markersize=7, color=series_style(i).get("color"), gid=f"published-{i}")
                pmean = [(n, float(np.mean([float(p[key]) for p in pub if p["N"] == n and not is_missing(p.get(key))])))
                         for n in all_n if any(p["N"] == n for p in pub)]
                ax_b.plot(*zip(*pmean), color="#b03a2e", ls="--", marker="x", gid="published-mean",
                          label="Published (paper's figure)")
                ax_b.legend(loc="best", frameon=False)
            hollow = [(n, v) for n, v, p in zip(mean_n, mean_v, partial) if p]
            if hollow:
                ax_b.plot(*zip(*hollow), ls="none", marker="o", markersize=7,
                          markerfacecolor="white", markeredgecolor="#333333",
                          label="Mean over the complete runs only")
                ax_b.legend(loc="best", frameon=False)
            if key == "T" and seconds_per_step is not None:
                ylabel = "Task time T (s)"
            for ax, sub in ((ax_a, f"(a) {name} of each task group"),
                            (ax_b, f"(b) Mean {name.lower()} over the groups")):
                ax.set_title(sub)
                ax.set_xlabel("Number of robots N")
                ax.set_ylabel(ylabel)
                int_axis(ax, all_n)
                ax.yaxis.set_major_locator(MaxNLocator(nbins=6, integer=key != "T"))
            # Both panels share the y range so they compare at a glance; counts
            # (S, C) start at zero, with room for the markers drawn on zero.
            lo = min(ax_a.get_ylim()[0], ax_b.get_ylim()[0])
            hi = max(ax_a.get_ylim()[1], ax_b.get_ylim()[1])
            if key in ("S", "C"):
                hi = max(hi, 1.0)
                lo = -0.04 * hi
            ax_a.set_ylim(lo, hi)
            ax_b.set_ylim(lo, hi)
            handles, labels = ax_a.get_legend_handles_labels()
            if handles:
                heading = None if not title else title + ("; x: published values" if pub else "")
                fig.legend(handles, labels, loc="outside upper center", title=heading,
                           ncol=min(len(handles), 6), frameon=False)
            if missing:
                note = (f"Incomplete runs ({key} undefined) left out: "
                        f"{_describe_missing(missing)}.")
                fig.get_layout_engine().set(rect=(0, 0.07, 1, 0.93))
                fig.text(0.5, 0.015, note, ha="center", va="bottom", fontsize=8.5,
                         color="#8b0000", wrap=True, gid="missing-note")
            for suffix in ("png", "svg"):
                written.append(save_atomic(fig, out / f"{stem}.{suffix}"))
    return written
