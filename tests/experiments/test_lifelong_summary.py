"""Lifelong figures in ``compare`` and ``sweep`` summaries: each with its interval over seeds
(one implementation), backlog growth judged from the run's own backlog, and the throughput
over time drawn only for lifelong studies."""

from __future__ import annotations

import statistics

import pytest

import multibots as mb
from multibots import Scenario
from multibots.experiments import compare as study
from multibots.experiments.summary import METRICS, write_outputs
from multibots.sweeps.analysis import interval

LIFELONG = ("sustained_throughput", "latency_p50", "latency_p95", "utilisation", "backlog_growth")
# A small lifelong warehouse: 20 robots, short runs.
BASE = {
    "robots": 20, "tasks": [], "placement": "spread", "unload": "nearest", "allocator": "nearest",
    "layout_generate": {"group_rows": 3, "group_cols": 5, "group_width": 2, "group_height": 6, "chargers": 4,
                        "unloading_rows": 2},
    "charging": {"chargers": "shared"}, "robot": {"consumption": 0.00002},
    "orders": {"rate": 0.02, "horizon": 3000, "restock": 100, "seed": 1}, "metrics": {"warmup": 600, "window": 300},
}


def test_compare_summarises_every_lifelong_figure_with_its_interval_over_seeds(tmp_path):
    base = Scenario.from_dict(BASE)
    rows = study.run_study(["in-turn", "nearest"], [20], study.TaskSpec("scenario"), seeds=4, base=base)
    assert set(LIFELONG) <= set(METRICS)
    summary = {(r["strategy"], r["N"], r["metric"]): r for r in study.summarize(rows)}
    for arm in ("in-turn", "nearest"):
        mine = [r for r in rows if r["strategy"] == arm]
        for m in LIFELONG:
            values = [float(r[m]) for r in mine]
            got = summary[(arm, 20, m)]
            assert got["n"] == 4 and got["mean"] == pytest.approx(statistics.fmean(values))
            assert got["ci_low"] <= got["mean"] <= got["ci_high"]
            assert (got["mean"], got["sd"], got["ci_low"], got["ci_high"]) == interval(values, m)
    text = study.format_summary(study.summarize(rows))
    assert "order latency p95 (steps): mean [95% CI]" in text and "backlog growth" in text
    assert "T (steps): mean" not in text  # lifelong runs never complete
    written = [p.name for p in write_outputs(rows, study.summarize(rows), tmp_path / "o")]
    assert "throughput_over_time.png" in written and (tmp_path / "o" / "throughput_over_time.png").stat().st_size
    assert "strategy_latency_p95.png" in written


def test_a_finite_study_draws_no_throughput_over_time_and_prints_no_lifelong_table(tmp_path):
    rows = study.run_study(["in-turn"], [2], study.TaskSpec("random", 4), seeds=3)
    written = [p.name for p in write_outputs(rows, study.summarize(rows), tmp_path / "o")]
    assert "throughput_over_time.png" not in written
    assert "latency" not in study.format_summary(study.summarize(rows))


def test_backlog_growth_is_the_growth_of_the_backlog_a_run_leaves(tmp_path):
    # Overloaded: the backlog grows. Measured from outside, by stepping and counting open orders.
    s = Scenario.from_dict({**BASE, "orders": {**BASE["orders"], "rate": 0.2, "horizon": 6000}})
    df = mb.sweep({"base": s.to_dict(), "axes": {"robots": [20]}}, tmp_path / "o")
    growth = df["backlog_growth"][0]
    sim = mb.Simulation(s)
    sim.step(3000)
    early = sim.goods_total - sim.delivered
    sim.step(3000)
    late = sim.goods_total - sim.delivered
    seen = (late - early) / 3.0  # per 1,000 steps
    assert seen > 50 and growth == pytest.approx(seen, rel=0.15), (growth, seen)
    # Within its capacity the fleet's backlog does not grow: about 0.
    calm = mb.sweep({"base": BASE, "axes": {"seed": [1, 2, 3]}}, tmp_path / "o")
    assert all(abs(g) < 0.15 * 20 for g in calm["backlog_growth"]), calm["backlog_growth"]
