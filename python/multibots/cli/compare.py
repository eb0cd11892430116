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
from multibots.cli._common import MAX_WORKERS, named_allocator, parse_number, whole_flag
from multibots.exceptions import InputError

__all__ = ["DEFAULT_STRATEGIES", "compare", "compare_lorr"]

DEFAULT_STRATEGIES = "in-turn,nearest,hungarian,auction,energy-aware,min-cost"


def compare(
    strategies: Optional[str] = typer.Option(
        None, "--strategies", metavar="NAMES", show_default=False,
        help=f"Comma-separated strategies: built-ins, package.module:Class, module:Class or path/to/file.py:Class "
        f"(default: {DEFAULT_STRATEGIES}). With --lorr: schedulers, built-in or Start-Kit Python files "
        "(pyTaskScheduler.py; default: every built-in).",
    ),
    robots: Optional[str] = typer.Option(
        None, "--robots", metavar="RANGE", show_default=False,
        help="Fleet sizes: a range such as 1..6 (inclusive) or a list such as 1,2,4 (default: 1..6; with --lorr: the "
        "problem's team).",
    ),
    tasks: str = typer.Option(
        "paper", "--tasks", metavar="SPEC",
        help="paper (TABLE III's five lists), random:K (K goods per list, one list per seed) or scenario (the "
        "--scenario file's own tasks or orders; with orders, one order stream per seed).",
    ),
    seeds: Optional[int] = typer.Option(
        None, "--seeds", show_default=False,
        help="With --tasks random:K or scenario: how many lists or order streams (seeds 1..SEEDS; default 30). With "
        "--lorr: runs per scheduler (default 5; 2026 rules: each seed a draw of the delays).",
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
    lorr: Optional[Path] = typer.Option(
        None, "--lorr", show_default=False, metavar="PROBLEM",
        help="Compare LoRR schedulers on this League of Robot Runners problem (JSON) instead: paired runs, 95% CIs "
        "and tests against the first scheduler (docs/lorr.md).",
    ),
    steps: Optional[str] = typer.Option(
        None, "--steps", metavar="STEPS", show_default=False,
        help="With --lorr: steps per run (ticks under the 2026 rules; default 5000).",
    ),
    allow_code: bool = typer.Option(
        False, "--allow-code",
        help="With --lorr: let the Start-Kit Python files that --strategies names run (only files you trust).",
    ),
) -> None:
    """Compare task-allocation strategies on paired runs: CSV, summary with 95% CIs and tests, plots.

    Finished runs are kept in OUT/runs.jsonl; a run whose scenario, strategy source and engine
    build are unchanged is reused, not run again (delete the file to start over).
    """
    from multibots.experiments import compare as study
    from multibots.scenario import Scenario
    from multibots.strategies import is_python_allocator

    check_folder(out)
    if lorr is not None:
        paper_only = {"--tasks": tasks != "paper", "--traffic": traffic is not None, "--rules": rules != "paper",
                      "--humans": humans != "", "--scenario": scenario is not None}
        for flag, given in paper_only.items():
            if given:
                raise InputError(f"{flag}: the paper model's option; a LoRR comparison (--lorr) takes --strategies, "
                                 "--robots, --seeds and --steps")
        return compare_lorr(lorr, strategies, robots, seeds, steps, out, workers, plots, quiet, allow_code)
    if steps is not None:
        raise InputError(f"--steps = {steps}: only with --lorr (the paper model's runs end when their tasks do)")
    strategies = strategies if strategies is not None else DEFAULT_STRATEGIES
    robots = robots if robots is not None else "1..6"
    seeds = seeds if seeds is not None else 30
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


def compare_lorr(problem: Path, strategies: Optional[str], robots: Optional[str], seeds: Optional[int],
                 steps: Optional[str], out: Path, workers: int, plots: bool, quiet: bool, allow_code: bool) -> None:
    """``compare --lorr``: schedulers (built-ins and Start-Kit Python files) on one LoRR problem,
    as a sweep (``sweeps/lorr.py``: kill-safe store in OUT/runs, resumed), each seed a paired
    run; the summary and the paired tests against the first scheduler printed and written."""
    from multibots import lorr as engine
    from multibots.experiments.compare import parse_robots
    from multibots.experiments.summary import progress_bar
    from multibots.sweeps import OUTPUTS, inputs_of, parse_spec, run_planned, write_outputs
    from multibots.sweeps.lorr import is_entry

    if seeds is not None and seeds < 1:
        raise InputError(f"--seeds = {seeds}: must be 1 or more")
    every = ",".join(n for n in engine.SCHEDULERS if n != "auto")
    names = [n.strip() for n in (every if strategies is None else strategies).split(",") if n.strip()]
    if not names or len(set(names)) != len(names):
        raise InputError(f"--strategies = {strategies!r}: expected distinct schedulers, comma-separated")
    from multibots.sweeps.lorr import read_problem, rules_of

    if rules_of(read_problem(os.path.abspath(problem))) == "2023":
        raise InputError(f"--lorr = {str(problem)!r}: a 2023 problem has no scheduler to compare (errands go round "
                         "robin)")
    code = [n for n in names if is_entry(n)]
    if code and not allow_code and os.environ.get("MULTIBOTS_ALLOW_CODE") != "1":
        raise InputError(f"--strategies names Python code ({', '.join(code)}), which would run; add --allow-code")
    n_steps = parse_number(steps, "--steps", int)
    base: dict[str, object] = {"lorr": os.path.abspath(problem)}
    if n_steps is not None:
        base["steps"] = n_steps
    axes: dict[str, list[object]] = {"scheduler": names}
    if robots is not None:
        axes["robots"] = list(parse_robots(robots))
    # Python files relative to the working folder, as the command line names them.
    spec = parse_spec({"base": base, "axes": axes, "repeats": seeds if seeds is not None else 5},
                      source="--lorr", folder=Path.cwd())
    points = spec.points(workers)
    check_outputs([], inputs_of(points, spec), folders=[("--out", out, OUTPUTS)])
    reuse: list[int] = []
    start = time.perf_counter()
    with progress_bar(len(points), enabled=not quiet) as bar:
        df = run_planned(points, out, workers=workers, progress=bar.advance, reused=lambda k, n: reuse.append(k))
    seconds = time.perf_counter() - start
    rows = df.to_dicts()
    baseline = names[0]
    written = write_outputs(df, spec, out, baseline=f"scheduler={baseline}",
                            plots=("delivered:robots:scheduler",) if plots and "robots" in axes else ())
    print(_lorr_table(rows, names, baseline))
    print(f"\n{len(points)} runs ({len(names)} schedulers x {len(axes.get('robots', [None]))} team sizes x "
          f"{spec.repeats} seeds) in {seconds:.1f} s; reused {reuse[0] if reuse else 0} from {out / 'runs'}")
    for p in written:
        print(f"wrote {p}")


def _lorr_table(rows: list[dict[str, object]], names: list[str], baseline: str) -> str:
    """Tasks finished per scheduler (and team): mean and 95% CI over seeds, the paired
    difference from the baseline and its t test's p-value."""
    from multibots.stats import mean_ci, paired_t_test

    teams = sorted({r["team_size"] for r in rows}, key=lambda t: int(str(t)))
    # A file by its name; by its path where two share a name (the Start-Kit names every
    # scheduler pyTaskScheduler.py).
    bases = [Path(n).name for n in names]
    shown_as = {n: b if bases.count(b) == 1 else n for n, b in zip(names, bases)}

    def tasks(name: str, team: object) -> dict[object, float]:
        return {r["seed"]: float(str(r["delivered"])) for r in rows if (r["scheduler"], r["team_size"]) == (name, team)}

    lines = [f"{'scheduler':<28} {'robots':>7} {'tasks (95% CI)':>24} {'vs ' + baseline:>22} {'p':>7}"]
    for team in teams:
        base = tasks(baseline, team)
        for name in names:
            mine = tasks(name, team)
            mean, _, lo, hi = mean_ci(list(mine.values()), 0.95, low=0.0)
            ci = f"{mean:,.1f} ({lo:,.1f}-{hi:,.1f})" if lo is not None and hi is not None else f"{mean:,.1f}"
            seeds = sorted(set(mine) & set(base))
            diff = p = ""
            if name != baseline and seeds:
                d = [mine[s] - base[s] for s in seeds]
                diff = f"{sum(d) / len(d):+,.1f}"
                if len(d) >= 2 and any(x != d[0] for x in d):
                    p = f"{paired_t_test([base[s] for s in seeds], [mine[s] for s in seeds]):.3f}"
            lines.append(f"{shown_as[name]:<28} {team:>7} {ci:>24} {diff:>22} {p:>7}")
    return "\n".join(lines)
