"""``multibots paper``: the paper's 30 runs, its table, results.csv and Fig. 6-8."""

from __future__ import annotations

import os
from pathlib import Path

import typer

from multibots.exceptions import InputError

__all__ = ["paper"]


def paper(
    out: Path = typer.Option(Path("out/paper"), "--out", help="Folder for results.csv and the figures."),
    margin: float = typer.Option(0.0, "--margin", help="Collision margin, px (the authors' code used 8)."),
    workers: int = typer.Option(0, "--workers", help="Threads (0: one per core)."),
) -> None:
    """Run the paper's 30 runs (N = 1..6 × TABLE III): table, results.csv, Fig. 6-8."""
    from multibots.experiments.paper import format_paper_table, run_paper, write_paper_csv
    from multibots.plots import draw_paper_figures

    if workers < 0:
        raise InputError(f"--workers = {workers}: must be 0 or more")
    rows, seconds = run_paper(margin=margin, workers=workers)
    print(format_paper_table(rows))
    print(f"\n30 runs in {seconds * 1000:.1f} ms (wall clock, {workers or os.cpu_count()} threads)")
    csv_path = write_paper_csv(rows, out / "results.csv")
    figures = draw_paper_figures([r.as_dict() for r in rows], out)
    print(f"wrote {csv_path}")
    for f in figures:
        print(f"wrote {f}")
