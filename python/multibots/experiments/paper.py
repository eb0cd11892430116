"""The paper's experiment: N = 1..6 robots × the five task lists of TABLE III."""

from __future__ import annotations

import csv
import io
import os
import statistics
import time
from dataclasses import dataclass
from pathlib import Path

from multibots._io import atomic_write_text
from multibots.paper import PAPER_ROBOTS, PAPER_TASKS
from multibots.scenario import Scenario
from multibots.simulation import simulate_many

__all__ = ["PaperRow", "paper_scenarios", "run_paper", "format_paper_table", "write_paper_csv"]


@dataclass(frozen=True)
class PaperRow:
    """One run of the experiment."""

    N: int
    group: int
    T: int | None
    S: int
    C: int

    def as_dict(self) -> dict[str, int | None]:
        return {"N": self.N, "group": self.group, "T": self.T, "S": self.S, "C": self.C}


def paper_scenarios(margin: float = 0.0) -> list[tuple[int, int, Scenario]]:
    """The 30 scenarios as (N, group, scenario), N outer."""
    return [
        (n, g, Scenario.paper(robots=n, goods=cells, margin=margin))
        for n in PAPER_ROBOTS
        for g, cells in PAPER_TASKS.items()
    ]


def run_paper(margin: float = 0.0, workers: int = 0) -> tuple[list[PaperRow], float]:
    """Runs the 30 runs on ``workers`` threads (0: every core).

    Returns:
        The rows, and the wall-clock seconds the engine took for all of them.
    """
    runs = paper_scenarios(margin)
    start = time.perf_counter()
    results = simulate_many([s for _, _, s in runs], workers=workers)
    seconds = time.perf_counter() - start
    rows = [PaperRow(n, g, r.T, r.S, r.C) for (n, g, _), r in zip(runs, results)]
    return rows, seconds


def _mean(values: list[int | None]) -> str:
    known = [v for v in values if v is not None]
    return f"{statistics.fmean(known):.1f}" if known else "-"


def format_paper_table(rows: list[PaperRow]) -> str:
    """The table as text, at most 100 columns: one line per N, T/S/C per group, and the means
    over the groups."""
    groups = sorted({r.group for r in rows})
    head1 = "   " + "".join(f" |{f'group {g}':>13}" for g in groups) + f" |{'mean over groups':>20}"
    head2 = "  N" + "".join(f" |{'T':>6}{'S':>4}{'C':>3}" for _ in groups) + f" |{'T':>8}{'S':>6}{'C':>6}"
    lines = [head1, head2, "-" * len(head2)]
    for n in sorted({r.N for r in rows}):
        mine = {r.group: r for r in rows if r.N == n}
        cells = []
        for g in groups:
            r = mine[g]
            t = "-" if r.T is None else str(r.T)
            cells.append(f" |{t:>6}{r.S:>4}{r.C:>3}")
        means = [_mean([mine[g].T for g in groups]), _mean([mine[g].S for g in groups]),
                 _mean([mine[g].C for g in groups])]
        lines.append(f"{n:>3}" + "".join(cells) + f" |{means[0]:>8}{means[1]:>6}{means[2]:>6}")
    return "\n".join(lines)


def write_paper_csv(rows: list[PaperRow], path: str | os.PathLike[str]) -> Path:
    """Writes ``N,group,T,S,C`` (T empty when incomplete), atomically."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["N", "group", "T", "S", "C"])
    for r in rows:
        w.writerow([r.N, r.group, "" if r.T is None else r.T, r.S, r.C])
    return atomic_write_text(path, buf.getvalue())
