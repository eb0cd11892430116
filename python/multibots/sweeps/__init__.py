"""Studies of any size (docs/sweeps.md): a base scenario, axes to vary, a results store that
survives a kill, the local machine or a Ray cluster, and statistics over any axis.

    >>> import multibots
    >>> df = multibots.sweep({"base": {"layout": "paper", "robots": 2, "tasks": {"random": 5, "seed": 1}},
    ...                       "axes": {"robots": [1, 2], "seed": [1, 2]}}, out=tmp)   # doctest: +SKIP
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Callable, Optional, Union

from multibots import _args
from multibots._io import check_outputs
from multibots.exceptions import ArgumentError
from multibots.simulation import MAX_WORKERS
from multibots.sweeps.spec import Point, Spec, load_spec, parse_spec
from multibots.sweeps.store import Store, polars

__all__ = ["Point", "Spec", "Store", "load_spec", "parse_spec", "run_planned", "sweep"]


def sweep(spec: Union[str, os.PathLike[str], Mapping[str, Any], Spec], out: Union[str, os.PathLike[str]],
          workers: int = 0, backend: str = "local", ray_address: Optional[str] = None,
          progress: Optional[Callable[[int], None]] = None,
          reused: Optional[Callable[[int, int], None]] = None) -> Any:
    """Runs a sweep (a spec file, a dictionary shaped like one, or a :class:`Spec`), storing
    every run in ``out/runs/``; runs already stored there (same scenario, strategy code and
    engine) are reused. Returns every run of the sweep, in plan order, as a polars DataFrame:
    ``key``, ``index``, one column per axis, and the figures (``runner.FIGURES``).

    Why polars: one package (no pandas and pyarrow pair) that reads and writes Parquet itself,
    keeps column types strict, and loads a study of millions of runs quickly.
    """
    polars()  # the extra, before any work
    out, workers, backend, ray_address, progress, reused = _checked(out, workers, backend, ray_address, progress,
                                                                    reused)
    if isinstance(spec, Spec):
        sp = spec
    elif isinstance(spec, Mapping):
        sp = parse_spec(spec)
    else:
        sp = load_spec(_args.path("spec", spec))  # type: ignore[arg-type]
    points = sp.points(workers)
    check_outputs([], inputs_of(points, sp), folders=[("out", out, OUTPUTS)])
    return run_planned(points, out, workers=workers, backend=backend, ray_address=ray_address,
                       progress=progress, reused=reused)


def _checked(out: Any, workers: Any, backend: Any, ray_address: Any, progress: Any, reused: Any) -> tuple[Any, ...]:
    """The arguments every study takes, checked (:mod:`multibots._args`)."""
    if ray_address is not None and not isinstance(ray_address, str):
        raise ArgumentError(f"ray_address: expected the cluster's address as text, got {type(ray_address).__name__}")
    return (_args.path("out", out), _args.whole("workers", workers, 0, MAX_WORKERS),
            _args.choice("backend", backend, ("local", "ray")), ray_address, _args.function("progress", progress),
            _args.function("reused", reused))


#: What a sweep writes in its --out folder (shell patterns).
OUTPUTS = ("results.csv", "summary.csv", "tests.csv", "plot-*", "throughput-time-*", "runs/*")


def inputs_of(points: list[Any], spec: Optional[Spec] = None) -> list[tuple[str, Path]]:
    """Every file the sweep's runs read: the spec file, each scenario's files (its own file,
    a layout file, CSV tables, a strategy's source) or each LoRR problem's."""
    from multibots import _core
    from multibots.sweeps import lorr as lorr_sweep

    seen: dict[str, tuple[str, Path]] = {}
    if spec is not None and spec.source and os.path.exists(spec.source):
        seen[spec.source] = ("sweep spec", Path(spec.source))
    base_file = getattr(spec.base, "source", None) if spec is not None else None
    if base_file is not None:
        seen[os.fspath(base_file)] = ("base scenario file", Path(base_file))
    for p in points:
        if isinstance(p, lorr_sweep.LorrPoint):
            files = [("problem file", Path(f)) for f in _core.lorr_files(p.run.problem)]
            files += [("Python entry file", lorr_sweep.entry_path(v, p.run.folder))
                      for v in (p.run.planner, p.run.scheduler) if lorr_sweep.is_entry(v)]
        else:
            files = p.scenario.files()
        for what, f in files:
            seen.setdefault(os.fspath(f), (what, f))
    return list(seen.values())


def run_planned(points: list[Point], out: Union[str, os.PathLike[str]], workers: int = 0, backend: str = "local",
                ray_address: Optional[str] = None, progress: Optional[Callable[[int], None]] = None,
                reused: Optional[Callable[[int, int], None]] = None) -> Any:
    """:func:`sweep` of points already planned (``Spec.points``)."""
    from multibots.sweeps.runner import run_points

    pl = polars()
    store = Store(out)
    keys = run_points(points, store, workers=workers, backend=backend, ray_address=ray_address, progress=progress,
                      reused=reused)
    df = store.frame()
    mine = pl.DataFrame({"key": keys, "index": [p.index for p in points]})
    # The sweep's own runs (the store may hold other studies' too), in plan order.
    return mine.join(df.drop("index"), on="key", how="left", maintain_order="left").sort("index")


def write_outputs(df: Any, spec: Spec, out: Union[str, os.PathLike[str]], baseline: Optional[str] = None,
                  plots: tuple[str, ...] = ()) -> list[Path]:
    """results.csv, summary.csv (mean and 95% interval per cell), tests.csv (with a baseline),
    the plots, and for lifelong runs the throughput over time (``throughput-time-AXIS.png``),
    staged so they land together."""
    from multibots._io import atomic_write_text, staged_folder
    from multibots.sweeps import lorr as lorr_sweep
    from multibots.sweeps.analysis import METRICS, paired_tests, parse_baseline, plot, summarize, throughput_over_time

    rows = df.to_dicts()
    axes = spec.axis_names
    # A LoRR study's figures are its own, not the paper's (which its runs do not have).
    metrics = lorr_sweep.METRICS if isinstance(spec.base, lorr_sweep.LorrBase) else METRICS
    written: list[Path] = []
    out = Path(out)
    with staged_folder(out) as stage:
        df.write_csv(stage / "results.csv")
        written.append(stage / "results.csv")
        written.append(atomic_write_text(stage / "summary.csv", _csv(summarize(rows, axes, metrics))))
        if baseline:
            axis, value = parse_baseline(baseline, axes)
            written.append(atomic_write_text(stage / "tests.csv",
                                             _csv(paired_tests(rows, axes, axis, value, metrics))))
        for p in plots:
            written.append(plot(rows, axes, p, stage, metrics))
        written += throughput_over_time(rows, axes, stage)
    return [out / Path(w).relative_to(stage) for w in written]


def _csv(rows: list[dict[str, Any]]) -> str:
    import csv
    import io

    if not rows:
        return ""
    fields = list(dict.fromkeys(k for r in rows for k in r))
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=fields, lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    return buf.getvalue()
