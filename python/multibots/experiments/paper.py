"""The paper's experiment: N = 1..6 robots × the five task lists of TABLE III, under both rule
sets, beside the values published in the paper's Fig. 6(a), 7(a) and 8(a)."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import time
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from multibots._io import atomic_write_text
from multibots.paper import PAPER_ROBOTS, PAPER_TASKS
from multibots.scenario import Scenario
from multibots.simulation import simulate_many

__all__ = [
    "RULES",
    "SECONDS_PER_TICK",
    "PaperRow",
    "format_paper_table",
    "matches",
    "paper_scenarios",
    "published_rows",
    "run_paper",
    "write_paper_csv",
]

#: The rule sets the experiment runs: the authors' code, and the model of docs/model.md.
RULES = ("original", "paper")

#: The paper's T is wall-clock time: about 0.0508 s per tick of the authors' 50 ms timer
#: (a least-squares fit over the 30 runs, docs/original-rules.md).
SECONDS_PER_TICK = 0.0508


@dataclass(frozen=True)
class PaperRow:
    """One run of the experiment: ``rules`` is ``"original"``, ``"paper"`` or ``"published"``
    (the values read off the paper's figures, whose T is in seconds and has no steps)."""

    rules: str
    N: int
    group: int
    T: int | None
    S: int
    C: int
    T_seconds: float | None = None

    def as_dict(self) -> dict[str, Any]:
        return {"rules": self.rules, "N": self.N, "group": self.group, "T": self.T, "S": self.S, "C": self.C,
                "T_seconds": self.T_seconds}


def published_rows() -> list[PaperRow]:
    """The paper's published values (Fig. 6(a), 7(a), 8(a)), as shipped in
    ``multibots/data/paper_figures.json`` with their source."""
    data = json.loads(resources.files("multibots").joinpath("data/paper_figures.json").read_text("utf-8"))
    return [
        PaperRow("published", n, g, None, data["S"][f"N{n}"][g - 1], data["C"][f"N{n}"][g - 1],
                 float(data["T_seconds"][f"N{n}"][g - 1]))
        for n in PAPER_ROBOTS
        for g in PAPER_TASKS
    ]


def paper_scenarios(margin: float = 0.0, rules: str = "paper") -> list[tuple[int, int, Scenario]]:
    """The 30 scenarios as (N, group, scenario), N outer. ``margin`` applies to the paper
    rules; the original rules use the authors' own contact distance."""
    extra: dict[str, Any] = {"rules": rules} if rules != "paper" else {"margin": margin}
    return [
        (n, g, Scenario.paper(robots=n, goods=cells, **extra))
        for n in PAPER_ROBOTS
        for g, cells in PAPER_TASKS.items()
    ]


def run_paper(margin: float = 0.0, workers: int = 0, rules: tuple[str, ...] = RULES) -> tuple[list[PaperRow], float]:
    """Runs the 30 runs under each rule set in ``rules`` on ``workers`` threads (0: every
    core).

    Returns:
        The rows (rule set by rule set), and the wall-clock seconds the engine took.
    """
    runs = [(r, n, g, s) for r in rules for n, g, s in paper_scenarios(margin, r)]
    start = time.perf_counter()
    results = simulate_many([s for *_, s in runs], workers=workers)
    seconds = time.perf_counter() - start
    rows = [
        PaperRow(r, n, g, res.T, res.S, res.C,
                 None if res.T is None or r != "original" else round(res.T * SECONDS_PER_TICK, 1))
        for (r, n, g, _), res in zip(runs, results)
    ]
    return rows, seconds


def matches(rows: list[PaperRow], published: list[PaperRow], rules: str) -> dict[str, int]:
    """How many of a rule set's runs equal the published S and C exactly, and how many have
    a T within 3 s of the published one (it was read off a line plot to about ±3 s; the
    paper rules' steps count as ticks of 0.0508 s)."""
    pub = {(p.N, p.group): p for p in published}
    out = {"S": 0, "C": 0, "T": 0, "runs": 0}
    for r in rows:
        if r.rules != rules:
            continue
        p = pub[(r.N, r.group)]
        out["runs"] += 1
        out["S"] += r.S == p.S
        out["C"] += r.C == p.C
        if r.T is not None and p.T_seconds is not None:
            out["T"] += abs(r.T * SECONDS_PER_TICK - p.T_seconds) <= 3.0
    return out


def _t(v: int | None) -> str:
    return "-" if v is None else str(v)


def format_paper_table(rows: list[PaperRow], published: list[PaperRow] | None = None) -> str:
    """The runs side by side, at most 100 columns: per run the published T (s), S and C, the
    original rules' T (ticks, and seconds at 0.0508 s a tick), S and C, and the paper rules'
    T (steps), S and C; then the count of exact matches with the published values and the
    means over the groups."""
    published = published_rows() if published is None else published
    by = {(r.rules, r.N, r.group): r for r in [*rows, *published]}
    rules = [r for r in RULES if any(row.rules == r for row in rows)]
    head1 = f"{'':5}|{'published':^17}|" + "".join(
        f"{'original rules (authors code)':^29}|" if r == "original" else f"{'paper rules':^19}|" for r in rules)
    head2 = f"{'N  g':5}|{'T s':>7}{'S':>5}{'C':>5} |" + "".join(
        f"{'ticks':>8}{'T s':>9}{'S':>5}{'C':>5} |" if r == "original" else f"{'T steps':>9}{'S':>4}{'C':>4} |"
        for r in rules)
    lines = [head1, head2, "-" * len(head2)]
    for n in sorted({r.N for r in rows}):
        for g in sorted({r.group for r in rows}):
            p = by[("published", n, g)]
            line = f"{n:<2} {g:<2}|{p.T_seconds:>7.0f}{p.S:>5}{p.C:>5} |"
            for r in rules:
                x = by[(r, n, g)]
                if r == "original":
                    secs = "-" if x.T is None else f"{x.T * SECONDS_PER_TICK:.1f}"
                    line += f"{_t(x.T):>8}{secs:>9}{x.S:>5}{x.C:>5} |"
                else:
                    line += f"{_t(x.T):>9}{x.S:>4}{x.C:>4} |"
            lines.append(line)
    lines.append("")
    for r in rules:
        m = matches(rows, published, r)
        name = "original rules" if r == "original" else "paper rules   "
        lines.append(f"{name} vs published: S equal in {m['S']}/{m['runs']}, C equal in {m['C']}/{m['runs']}, "
                     f"T within 3 s in {m['T']}/{m['runs']}")
    lines.append("")
    lines.append("mean over the groups  N:  " + "".join(f"{n:>8}" for n in sorted({r.N for r in rows})))
    def value(x: PaperRow, key: str) -> float | None:
        if key == "T s":
            return x.T_seconds if x.rules == "published" else None if x.T is None else x.T * SECONDS_PER_TICK
        return float(x.S if key == "S" else x.C)

    for key in ("T s", "S", "C"):
        for r in ["published", *rules]:
            vals = []
            for n in sorted({x.N for x in rows}):
                vs = [v for x in [*rows, *published] if x.rules == r and x.N == n and (v := value(x, key)) is not None]
                vals.append(f"{sum(vs) / len(vs):>8.1f}" if vs else f"{'-':>8}")
            lines.append(f"{r:>10} {key:<4}            " + "".join(vals))
    lines.append("(T s of the paper rules: their steps at 0.0508 s, as if they were the timer's ticks)")
    return "\n".join(lines)


def write_paper_csv(
    rows: list[PaperRow], path: str | os.PathLike[str], published: list[PaperRow] | None = None
) -> Path:
    """Writes ``rules,N,group,T,T_seconds,S,C`` atomically: the published values (``rules =
    published``, T in seconds only), then every run (T in ticks or steps, empty when
    incomplete; T_seconds for the original rules at 0.0508 s a tick)."""
    published = published_rows() if published is None else published
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["rules", "N", "group", "T", "T_seconds", "S", "C"])
    for r in [*published, *rows]:
        secs = "" if r.T_seconds is None or math.isnan(r.T_seconds) else r.T_seconds
        w.writerow([r.rules, r.N, r.group, "" if r.T is None else r.T, secs, r.S, r.C])
    return atomic_write_text(path, buf.getvalue())
