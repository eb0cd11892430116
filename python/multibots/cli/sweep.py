"""``multibots sweep``: a study over any scenario fields (docs/sweeps.md)."""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import List, Optional

import typer

from multibots._io import check_folder, check_outputs, load_toml, read_input
from multibots.cli._common import ALLOW_CODE, MAX_WORKERS, named_allocator, whole_flag
from multibots.exceptions import InputError

__all__ = ["sweep"]


def sweep(
    spec: Path = typer.Argument(..., help="The sweep spec (TOML): base scenario and axes."),
    out: Path = typer.Option(Path("out/sweep"), "--out", help="Folder for the run store (runs/), results.csv, "
                             "summary.csv, tests.csv and plots."),
    backend: str = typer.Option("local", "--backend", metavar="NAME", help="local (this machine's cores) or ray."),
    ray_address: Optional[str] = typer.Option(
        None, "--ray-address", metavar="ADDRESS",
        help="A Ray cluster to join (default: a local one started for the study).",
        show_default=False,
    ),
    workers: int = typer.Option(
        0, "--workers", help="Threads or processes (0: one per core); Ray: CPUs of a local cluster.",
        parser=whole_flag("--workers", 0, MAX_WORKERS), metavar="INT",
    ),
    baseline: Optional[str] = typer.Option(
        None, "--baseline", metavar="AXIS=VALUE",
        help="AXIS=VALUE: paired tests of every other value of AXIS against VALUE (tests.csv).",
        show_default=False,
    ),
    plot: List[str] = typer.Option(
        [], "--plot", help="METRIC:AXIS[:BY]: the metric against a numeric axis, a line per value of BY; repeatable.",
        show_default=False,
    ),
    quiet: bool = typer.Option(False, "--quiet", help="No progress bar."),
    allow_code: bool = ALLOW_CODE,
) -> None:
    """Run a sweep: every combination (or zip) of the spec's axes, stored run by run in --out;
    run it again to resume (finished runs are reused, never repeated)."""
    from multibots.experiments.summary import progress_bar
    from multibots.strategies import is_python_allocator
    from multibots.sweeps import OUTPUTS, inputs_of, load_spec, run_planned, write_outputs
    from multibots.sweeps.lorr import is_entry
    from multibots.sweeps.store import polars

    polars()  # the extra, before any work
    if workers < 0:
        raise InputError(f"--workers = {workers}: must be 0 or more")
    if backend not in ("local", "ray"):
        raise InputError(f"--backend = {backend!r}: expected local or ray")
    check_folder(out)
    # Before the spec is loaded: checking its base, or a planned run, loads the strategy,
    # which runs its code.
    code = sorted(n for n in _named_allocators(spec) if is_python_allocator(n) or is_entry(n))
    if code and not allow_code and os.environ.get("MULTIBOTS_ALLOW_CODE") != "1":
        raise InputError(f"{spec}: names Python code ({', '.join(code)}), which would run; add --allow-code if you "
                         "trust the spec")
    sp = load_spec(spec)
    from multibots.sweeps import lorr as lorr_sweep
    from multibots.sweeps.analysis import METRICS, parse_plot

    metrics = lorr_sweep.METRICS if isinstance(sp.base, lorr_sweep.LorrBase) else METRICS

    for p in plot:  # before any run: a bad --plot must not cost the study
        parse_plot(p, sp.axis_names, sp.axes, metrics)
    points = sp.points(workers)
    check_outputs([], inputs_of(points, sp), folders=[("--out", out, OUTPUTS)])
    reuse: list[int] = []
    start = time.perf_counter()
    with progress_bar(len(points), enabled=not quiet) as bar:
        df = run_planned(points, out, workers=workers, backend=backend, ray_address=ray_address, progress=bar.advance,
                         reused=lambda k, n: reuse.append(k))
    seconds = time.perf_counter() - start
    print(f"{len(points)} runs ({', '.join(f'{n}: {len(v)}' for n, v in sp.axes.items())}"
          f"{f', repeats: {sp.repeats}' if sp.repeats > 1 else ''}) in {seconds:.1f} s, backend {backend}")
    print(f"reused {reuse[0] if reuse else 0} of {len(points)} runs from {out / 'runs'}")
    # A lifelong run that reached its horizon finished its work; the rest ended early.
    if "outcome" in df.columns:
        ended = [o for o in df["outcome"].to_list() if o not in ("complete", "horizon")]
        if ended:
            counts = ", ".join(f"{o}: {ended.count(o)}" for o in sorted(set(map(str, ended))))
            print(f"{len(ended)} runs did not complete ({counts}; see the outcome column)")
    for p in write_outputs(df, sp, out, baseline=baseline, plots=tuple(plot)):
        print(f"wrote {p}")


def _named_allocators(spec: Path) -> set[str]:
    """The strategies a spec file names (its base's and the allocator axis), read as plain
    TOML; what cannot be read is left to load_spec, which reports it."""
    try:
        data = load_toml(read_input(spec, InputError, "sweep spec"), str(spec), InputError)
    except InputError:
        return set()
    base = data.get("base")
    if isinstance(base, str):
        path = Path(base)
        if not path.is_absolute() and not path.exists():
            path = spec.parent / path  # as load_spec resolves it
        name = named_allocator(path)
    else:
        name = base.get("allocator") if isinstance(base, dict) else None
    axes = data.get("axes")
    values = axes.get("allocator") if isinstance(axes, dict) else None
    named = {name} | set(values if isinstance(values, list) else [])
    # A LoRR study's Start-Kit Python entries (a planner or scheduler named by its .py file).
    from multibots.sweeps.lorr import ENTRY_AXES, is_entry

    for option in ENTRY_AXES:
        named.add(base.get(option) if isinstance(base, dict) else None)
        values = axes.get(option) if isinstance(axes, dict) else None
        named |= {v for v in (values if isinstance(values, list) else []) if is_entry(v)}
    return {n for n in named if isinstance(n, str)}
