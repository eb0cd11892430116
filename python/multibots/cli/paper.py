"""``multibots paper``: the paper's 30 runs under both rule sets beside the published values,
results.csv and Fig. 6-8."""

from __future__ import annotations

import os
from pathlib import Path

import typer

from multibots._io import check_folder, check_outputs, staged_folder
from multibots.cli._common import MAX_WORKERS, finite_flag, whole_flag
from multibots.exceptions import InputError

__all__ = ["paper"]


def paper(
    out: Path = typer.Option(Path("out/paper"), "--out", help="Folder for results.csv and the figures."),
    margin: float = typer.Option(
        0.0, "--margin", help="Collision margin of the paper rules, px (the authors' code used 8).",
        parser=finite_flag("--margin"), metavar="NUMBER",
    ),
    rules: str = typer.Option("both", "--rules", metavar="NAME",
                              help="Rule sets to run: both, original (the authors' code) or paper."),
    workers: int = typer.Option(
        0, "--workers", help="Threads (0: one per core).", parser=whole_flag("--workers", 0, MAX_WORKERS), metavar="INT"
    ),
) -> None:
    """Run the paper's 30 runs (N = 1..6 × TABLE III) under the original and the paper rules,
    beside the values published in the paper: table, results.csv, Fig. 6-8."""
    from multibots.experiments.paper import (
        SECONDS_PER_TICK,
        format_paper_table,
        published_rows,
        run_paper,
        write_paper_csv,
    )
    from multibots.plots import draw_paper_figures

    if workers < 0:
        raise InputError(f"--workers = {workers}: must be 0 or more")
    chosen = {"both": ("original", "paper"), "original": ("original",), "paper": ("paper",)}.get(rules)
    if chosen is None:
        raise InputError(f"--rules = {rules!r}: expected both, original or paper")
    check_folder(out)
    check_outputs([], [], folders=[("--out", out, ())])  # the folder can be written, before the runs
    rows, seconds = run_paper(margin=margin, workers=workers, rules=chosen)
    published = published_rows()
    print(format_paper_table(rows, published))
    print(f"\n{len(rows)} runs in {seconds * 1000:.1f} ms (wall clock, {workers or os.cpu_count()} threads)")
    pub = [p.as_dict() for p in published]
    written = []
    # Staged: the table and its figures land together or not at all (a full disk).
    with staged_folder(out) as stage:
        written.append(write_paper_csv(rows, stage / "results.csv", published))
        for r in chosen:
            # The original rules' figures are the paper's own, in its folder; the paper rules'
            # go beside them when both run.
            folder = stage if r == chosen[0] else stage / f"{r}-rules"
            label = "original rules (the authors' code)" if r == "original" else "paper rules (docs/model.md)"
            written += draw_paper_figures([x.as_dict() for x in rows if x.rules == r], folder, published=pub,
                                          seconds_per_step=SECONDS_PER_TICK, title=label)
    for f in written:
        print(f"wrote {out / Path(f).relative_to(stage)}")
