"""``multibots compare``: strategies against each other on paired runs, with confidence
intervals and tests; finished runs are kept in ``runs.jsonl`` and reused when nothing that
changes their result has changed."""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Optional

import typer

from multibots._io import check_folder, check_outputs, load_toml, read_input
from multibots.cli._common import MAX_WORKERS, named_allocator, whole_flag
from multibots.exceptions import InputError

__all__ = ["DEFAULT_STRATEGIES", "compare"]

DEFAULT_STRATEGIES = "in-turn,nearest,hungarian,auction,energy-aware,min-cost"


def compare(
    strategies: str = typer.Option(
        DEFAULT_STRATEGIES, "--strategies", metavar="NAMES",
        help="Comma-separated strategies: built-ins, package.module:Class, module:Class or path/to/file.py:Class.",
    ),
    robots: str = typer.Option(
        "1..6", "--robots", metavar="RANGE",
        help="Fleet sizes: a range such as 1..6 (inclusive) or a list such as 1,2,4."
    ),
    tasks: str = typer.Option(
        "paper", "--tasks", metavar="SPEC",
        help="paper (TABLE III's five lists), random:K (K goods per list, one list per seed) or scenario (the "
        "--scenario file's own tasks or orders; with orders, one order stream per seed).",
    ),
    seeds: int = typer.Option(
        30, "--seeds", help="With --tasks random:K or scenario: how many lists or order streams (seeds 1..SEEDS).",
        parser=whole_flag("--seeds", 0, 100_000), metavar="INT",
    ),
    traffic: Optional[str] = typer.Option(
        None, "--traffic", metavar="NAMES",
        help="Traffic policies to compare too, comma-separated: auto (wait for the paper's "
        "fleets, reserve for fleets spread along the aisles), wait, gate, reserve (default: the scenario's, "
        "else auto).", show_default=False,
    ),
    rules: str = typer.Option(
        "paper", "--rules", metavar="NAMES",
        help="Rule sets to compare too, comma-separated: paper, original (in-turn only)."
    ),
    humans: str = typer.Option(
        "", "--humans", metavar="COUNTS",
        help="People on the floor to compare too, comma-separated counts such as 0,20,40 "
        "(the scenario's [humans] table, or its defaults: docs/people.md).",
    ),
    out: Path = typer.Option(
        Path("out/compare"), "--out",
        help="Folder for results.csv, summary.csv, summary.txt, the figures and the run journal runs.jsonl.",
    ),
    workers: int = typer.Option(
        0, "--workers", help="Threads (built-ins) or processes (Python strategies); 0: one per core.",
        parser=whole_flag("--workers", 0, MAX_WORKERS), metavar="INT",
    ),
    scenario: Optional[Path] = typer.Option(
        None, "--scenario", show_default=False,
        help="A scenario file whose other fields (cost weights, charging, robot, ...) every run uses.",
    ),
    plots: bool = typer.Option(True, "--plots/--no-plots", help="Draw T, S, C and Cost_total against N."),
    quiet: bool = typer.Option(False, "--quiet", help="No progress bar."),
) -> None:
    """Compare task-allocation strategies on paired runs: CSV, summary with 95% CIs and tests, plots.

    Finished runs are kept in OUT/runs.jsonl; a run whose scenario, strategy source and engine
    build are unchanged is reused, not run again (delete the file to start over).
    """
    from multibots.experiments import compare as study
    from multibots.scenario import Scenario
    from multibots.strategies import is_python_allocator

    check_folder(out)
    names = study.parse_strategies(strategies)
    rule_sets = study.parse_choices(rules, "--rules", ("paper", "original"))
    crowds = study.parse_humans(humans)
    ns = study.parse_robots(robots)
    spec = study.parse_tasks(tasks)
    if workers < 0:
        raise InputError(f"--workers = {workers}: must be 0 or more")
    if spec.kind == "random" and seeds < 1:
        raise InputError(f"--seeds = {seeds}: must be 1 or more")
    base = None
    if scenario is not None:
        named = named_allocator(scenario)
        if named is not None and is_python_allocator(named):
            # --strategies replaces the file's allocator: loading the file as it is would
            # import the Python strategy it names, running code the user did not choose.
            data = load_toml(read_input(scenario, InputError, "scenario file"), str(scenario), InputError)
            del data["allocator"]
            base = Scenario.from_dict(data)
        else:
            base = Scenario.from_toml(scenario)
    own = "auto" if base is None else str(base.to_dict().get("traffic") or "auto")
    traffics = study.parse_choices(traffic if traffic is not None else own, "--traffic",
                                   ("auto", "wait", "gate", "reserve"))
    # Validates every scenario (fleet sizes, Python strategies' imports) before any run.
    runs = study.plan_runs(names, ns, spec, seeds, base, traffics, rule_sets, crowds, workers)
    inputs = [("scenario file", scenario)] if scenario is not None else []
    inputs += [("strategy file", Path(n.rpartition(":")[0])) for n in names if n.rpartition(":")[0].endswith(".py")]
    check_outputs([], inputs, folders=[("--out", out, study.OUTPUTS)])
    total = len(runs)
    journal = out / "runs.jsonl"
    had_journal = journal.exists()
    reuse: list[int] = []
    start = time.perf_counter()
    with study.progress_bar(total, enabled=not quiet) as bar:
        rows = study.run_study(
            names, ns, spec, seeds, workers, base, progress=bar.advance, journal=journal,
            reused=lambda k, n: reuse.append(k), traffic=traffics, rules=rule_sets, humans=crowds, runs=runs,
        )
    seconds = time.perf_counter() - start
    summary = study.summarize(rows)
    print(study.format_summary(summary, spec.label))
    print("\n".join(study.format_windows(rows)))
    lists = 5 if spec.kind == "paper" else seeds
    arms = len(names) * len(traffics) * len(rule_sets) * len(crowds)
    print(
        f"\n{total} runs ({arms} arms x {len(ns)} fleet sizes x {lists} task lists) in {seconds:.1f} s"
        f" on {workers or os.cpu_count()} workers"
    )
    if had_journal:  # also when it reused nothing: an edited strategy or a new engine build
        print(f"reused {reuse[0] if reuse else 0} of {total} runs from {journal}")
    for p in study.write_outputs(rows, summary, out, spec.label, plots=plots):
        print(f"wrote {p}")
