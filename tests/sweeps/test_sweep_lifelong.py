"""A sweep's figures are all plottable, against any axis (a strategy or a policy as
categories), and lifelong sweeps draw their throughput over time per axis value."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import multibots
from multibots.sweeps import parse_spec, write_outputs
from multibots.sweeps.analysis import METRICS, summarize
from multibots.sweeps.runner import figures_of

pl = pytest.importorskip("polars", reason="the study extra (polars) is not installed")

LIFELONG = {
    "robots": 12, "tasks": [], "placement": "spread", "unload": "nearest",
    "layout_generate": {"group_rows": 3, "group_cols": 4, "group_width": 2, "group_height": 6, "chargers": 4,
                        "unloading_rows": 2},
    "charging": {"chargers": "shared"}, "humans": {"count": 3},
    "orders": {"rate": 0.02, "horizon": 2400, "restock": 100, "seed": 1}, "metrics": {"warmup": 400, "window": 400},
}


def test_every_numeric_figure_a_run_stores_is_a_metric() -> None:
    from multibots import _core

    raw = figures_of(_core.simulate(multibots.Scenario.from_dict(LIFELONG)._core))
    numeric = {k for k, v in raw.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
    assert numeric and numeric <= set(METRICS), numeric - set(METRICS)


def test_any_figure_against_any_axis_and_the_throughput_over_time(cli, tmp_path: Path) -> None:
    spec = {"base": LIFELONG, "axes": {"allocator": ["in-turn", "nearest"], "robots": [8, 12], "seed": [1, 2]}}
    df = multibots.sweep(spec, tmp_path / "o")
    sp = parse_spec(spec)
    plots = tuple(f"{m}:{a}" for m in METRICS for a in ("allocator", "robots"))
    written = {p.name for p in write_outputs(df, sp, tmp_path / "o", plots=plots)}
    for m in METRICS:
        assert f"plot-{m}-allocator.png" in written and f"plot-{m}-robots.png" in written
    assert {"throughput-time-allocator.png", "throughput-time-robots.png"} <= written
    # The lifelong figures have intervals per cell, over the seeds.
    summary = summarize(df.to_dicts(), sp.axis_names)
    for r in summary:
        if r["metric"] in ("sustained_throughput", "latency_p95", "utilisation", "backlog_growth"):
            assert r["n"] == 2 and r["ci_low"] <= r["mean"] <= r["ci_high"], r
    # And from the command line, a category axis.
    (tmp_path / "s.toml").write_text('base = { layout = "paper", robots = 2, tasks = { random = 4, seed = 1 } }\n'
                                     '[axes]\nallocator = ["in-turn", "nearest"]\nseed = [1, 2]\n')
    out = cli("sweep", tmp_path / "s.toml", "--out", tmp_path / "p", "--plot", "T:allocator", "--quiet")
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "p" / "plot-T-allocator.png").stat().st_size > 0
    # Finite runs have no throughput over time: no such figure.
    assert not list((tmp_path / "p").glob("throughput-time*"))


def test_a_utilisation_interval_stays_a_share() -> None:
    from multibots.sweeps.analysis import interval

    mean, _, lo, hi = interval([0.99, 1.0, 0.97], "utilisation")
    assert hi == 1.0 and lo < mean < 1.0 and not math.isnan(mean)
