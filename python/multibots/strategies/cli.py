"""``multibots compare``: added to the main typer app by ``register(app)``."""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any, Optional

import typer

DEFAULT_STRATEGIES = "in-turn,nearest,hungarian,auction,energy-aware,min-cost"


def compare(
    strategies: str = typer.Option(DEFAULT_STRATEGIES, "--strategies", help="Comma-separated strategies: built-ins or package.module:Class."),
    robots: str = typer.Option("1..6", "--robots", help="Fleet sizes: a range such as 1..6 (inclusive) or a list such as 1,2,4."),
    tasks: str = typer.Option("paper", "--tasks", help="paper (TABLE III's five lists) or random:K (K goods per list, one list per seed)."),
    seeds: int = typer.Option(30, "--seeds", help="With --tasks random:K: how many random lists (seeds 1..SEEDS)."),
    out: Path = typer.Option(Path("out/compare"), "--out", help="Folder for results.csv, summary.csv, summary.txt and the figures."),
    workers: int = typer.Option(0, "--workers", help="Threads (built-ins) or processes (Python strategies); 0: one per core."),
    scenario: Optional[Path] = typer.Option(
        None, "--scenario", help="A scenario file whose other fields (cost weights, charging, robot, ...) every run uses.", show_default=False
    ),
    plots: bool = typer.Option(True, "--plots/--no-plots", help="Draw T, S, C and Cost_total against N."),
    quiet: bool = typer.Option(False, "--quiet", help="No progress bar."),
) -> None:
    """Compare task-allocation strategies on paired runs: CSV, summary with 95% CIs and tests, plots."""
    from multibots.cli import BadInput
    from multibots.experiments import compare as study
    from multibots.scenario import Scenario

    try:
        names = study.parse_strategies(strategies)
        ns = study.parse_robots(robots)
        spec = study.parse_tasks(tasks)
        if workers < 0:
            raise study.StudyInputError(f"--workers = {workers}: must be 0 or more")
        if spec.kind == "random" and seeds < 1:
            raise study.StudyInputError(f"--seeds = {seeds}: must be 1 or more")
    except study.StudyInputError as e:
        raise BadInput(str(e)) from None
    base = Scenario.from_toml(scenario) if scenario is not None else None
    # Validates every scenario (fleet sizes, Python strategies' imports) before any run.
    total = len(study.plan_runs(names, ns, spec, seeds, base))
    start = time.perf_counter()
    with study.progress_bar(total, enabled=not quiet) as bar:
        rows = study.run_study(names, ns, spec, seeds, workers, base, progress=bar.advance, journal=out / "runs.jsonl")
    seconds = time.perf_counter() - start
    summary = study.summarize(rows)
    text = study.format_summary(summary, spec.label)
    print(text)
    lists = 5 if spec.kind == "paper" else seeds
    print(f"\n{total} runs ({len(names)} strategies x {len(ns)} fleet sizes x {lists} task lists) in {seconds:.1f} s on {workers or os.cpu_count()} workers")
    for p in study.write_outputs(rows, summary, out, spec.label, plots=plots):
        print(f"wrote {p}")


def register(app: Any) -> None:
    """Adds ``compare`` to the ``multibots`` app."""
    app.command(name="compare")(compare)
