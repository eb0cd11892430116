"""Sweeps (docs/sweeps.md): any axes, a store that survives kill -9, reuse keyed by code and
engine, the Ray backend giving the same results, a killed Ray worker costing only its batch."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import multibots
from multibots.sweeps import Store, parse_spec

pl = pytest.importorskip("polars", reason="the study extra (polars) is not installed")

BASE = {"layout": "paper", "robots": 2, "tasks": {"random": 6, "seed": 1}}


def spec(**axes):
    return {"base": BASE, "axes": axes or {"robots": [1, 2, 3], "robot.threshold": [3.0, 3.5], "seed": [1, 2, 3]}}


def test_a_sweep_over_three_axes(tmp_path: Path) -> None:
    df = multibots.sweep(spec(), tmp_path)
    assert df.height == 18 and df["index"].to_list() == list(range(18))
    assert df["key"].n_unique() == 18
    assert set(df.columns) >= {"robots", "robot.threshold", "seed", "T", "S", "C", "outcome", "throughput"}
    # Each row is exactly the run of its scenario.
    row = df.row(7, named=True)
    s = multibots.Scenario.from_dict({**BASE, "robots": row["robots"], "robot": {"threshold": row["robot.threshold"]},
                                      "tasks": {"random": 6, "seed": row["seed"]}})
    r = multibots.simulate(s)
    assert (row["T"], row["S"], row["C"], row["outcome"]) == (r.T, r.S, r.C, r.outcome)
    # zip: element by element.
    z = multibots.sweep({**spec(robots=[1, 2, 3], seed=[4, 5, 6]), "product": "zip"}, tmp_path / "zip")
    assert z.height == 3 and list(zip(z["robots"], z["seed"])) == [(1, 4), (2, 5), (3, 6)]


def test_the_seed_axis_holds_whatever_order_the_axes_come_in() -> None:
    sp = parse_spec({"base": BASE, "axes": {"seed": [1, 2], "tasks": [{"random": 5}, {"random": 7}]}})
    seeds = [(p.scenario.to_dict()["tasks"]["seed"], len(p.scenario.cells)) for p in sp.points(1)]
    assert seeds == [(1, 5), (1, 7), (2, 5), (2, 7)]


def test_an_edited_layout_file_is_run_again(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # The key holds what the named file holds, not only its path.
    monkeypatch.chdir(tmp_path)
    from multibots.cli import main

    for aisle, name in ((50, "wide.toml"), (60, "other.toml")):
        main(["layout", "generate", "--out", name, "--aisle", str(aisle)])
    s = {"base": {**BASE, "layout": "w.toml"}, "axes": {"robots": [1, 2]}}
    Path("w.toml").write_bytes(Path("wide.toml").read_bytes())
    seen = []
    first = multibots.sweep(s, "o", reused=lambda k, n: seen.append(k))
    multibots.sweep(s, "o", reused=lambda k, n: seen.append(k))
    Path("w.toml").write_bytes(Path("other.toml").read_bytes())
    edited = multibots.sweep(s, "o", reused=lambda k, n: seen.append(k))
    assert seen == [0, 2, 0]
    assert first["T"].to_list() != edited["T"].to_list(), "wider aisles, other task times"


def test_rerun_reuses_everything(tmp_path: Path) -> None:
    multibots.sweep(spec(), tmp_path)
    seen = []
    again = multibots.sweep(spec(), tmp_path, reused=lambda k, n: seen.append((k, n)))
    assert seen == [(18, 18)] and again.height == 18


def test_kill_9_then_resume_loses_and_repeats_nothing(tmp_path: Path) -> None:
    # Enough runs that the sweep is still running when its first part is written: the engine
    # runs these 5,120 in about a second (1,280 once took that long; cruising made them 4x faster).
    big = {"base": BASE, "axes": {"robots": [1, 2, 3, 4], "robot.threshold": [2.5, 3.0, 3.5, 4.0],
                                  "tasks.random": [10, 20], "seed": list(range(1, 161))}}
    total = 4 * 4 * 2 * 160
    import tomllib  # noqa: F401 - only to be sure the spec is TOML-shaped below

    lines = ['base = "base.toml"', "[axes]"] + [f'"{k}" = {v!r}'.replace("'", '"') for k, v in big["axes"].items()]
    (tmp_path / "spec.toml").write_text("\n".join(lines) + "\n")
    (tmp_path / "base.toml").write_text('layout = "paper"\nrobots = 2\ntasks = { random = 6, seed = 1 }\n')
    env = {**os.environ, "MULTIBOTS_SWEEP_FLUSH": "0.02"}
    p = subprocess.Popen([sys.executable, "-m", "multibots", "sweep", "spec.toml", "--out", "k", "--workers", "1",
                          "--quiet"], cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    runs = tmp_path / "k" / "runs"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not list(runs.glob("part-*.parquet")):
        time.sleep(0.01)
    p.send_signal(signal.SIGKILL)
    p.communicate()
    stored = Store(tmp_path / "k").frame().height
    assert 0 < stored < total, stored  # killed part-way
    seen = []
    resumed = multibots.sweep(tmp_path / "spec.toml", tmp_path / "k", reused=lambda k, n: seen.append(k))
    assert seen == [stored]
    parts = pl.concat([pl.read_parquet(f) for f in runs.glob("part-*.parquet")], how="diagonal_relaxed")
    assert parts.height == total and parts["key"].n_unique() == total, "no run lost, none run twice"
    whole = multibots.sweep(tmp_path / "spec.toml", tmp_path / "whole")
    assert resumed.drop("key").equals(whole.drop("key")) and resumed["key"].equals(whole["key"])


def test_an_edited_strategy_is_run_again(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    code = "from multibots.strategies import BUILT_INS\nclass Mine:\n    def allocate(self, view):\n" \
           "        return {int(r): int(g) for r, g in zip(view.idle, view.goods)}\n"
    Path("mine.py").write_text(code)
    s = {"base": {**BASE, "allocator": "mine.py:Mine"}, "axes": {"robots": [1, 2]}}
    seen = []
    multibots.sweep(s, "o", reused=lambda k, n: seen.append(k))
    multibots.sweep(s, "o", reused=lambda k, n: seen.append(k))
    Path("mine.py").write_text(code + "# edited\n")
    multibots.sweep(s, "o", reused=lambda k, n: seen.append(k))
    assert seen == [0, 2, 0]


def test_bad_specs_are_one_line_errors(cli, tmp_path: Path) -> None:
    paper = 'base = { layout = "paper", tasks = [1] }\n'
    for text, frag in [(paper + "[axes]\nrobots = []\n", "axes.robots"),
                       ('base = "nope.toml"\n[axes]\nrobots=[1]\n', "nope.toml"),
                       (paper + 'product = "cube"\n[axes]\nrobots = [1]\n', "product"),
                       (paper + "[axes]\nrobots = [1, 0]\n", "at robots = 0: robots = 0: must be at least 1"),
                       (paper + "repeats = 3\n[axes]\nrobots = [1]\n", "repeats"),
                       ('base = { layout = "paper", tasks = [1], allocator = "os:abort" }\n[axes]\nrobots = [1]\n',
                        "--allow-code")]:
        (tmp_path / "s.toml").write_text(text)
        cli.assert_one_line_error(cli("sweep", tmp_path / "s.toml", "--out", tmp_path / "o", "--quiet"), frag)
    assert not (tmp_path / "o" / "runs").exists()
    # A strategy named only on an axis is not loaded (its code not run) before --allow-code.
    (tmp_path / "evil.py").write_text(f"open({str(tmp_path / 'ran')!r}, 'w').close()\nclass X:\n    pass\n")
    (tmp_path / "s.toml").write_text(paper + f'[axes]\nallocator = ["in-turn", "{tmp_path / "evil.py"}:X"]\n')
    cli.assert_one_line_error(cli("sweep", tmp_path / "s.toml", "--out", tmp_path / "o", "--quiet"), "--allow-code")
    assert not (tmp_path / "ran").exists()
    with pytest.raises(multibots.InputError, match="zip"):
        parse_spec({**spec(robots=[1, 2], seed=[1]), "product": "zip"}).points()


def test_outputs_summary_tests_and_plot(cli, tmp_path: Path) -> None:
    (tmp_path / "s.toml").write_text('base = { layout = "paper", robots = 2, tasks = { random = 6, seed = 1 } }\n'
                                     '[axes]\nrobots = [1, 2]\nallocator = ["in-turn", "nearest"]\nseed = [1, 2, 3]\n')
    out = cli("sweep", tmp_path / "s.toml", "--out", tmp_path / "o", "--baseline", "allocator=in-turn",
              "--plot", "T:robots:allocator", "--quiet")
    assert out.returncode == 0, out.stderr
    for f in ("results.csv", "summary.csv", "tests.csv", "plot-T-robots.png"):
        assert (tmp_path / "o" / f).stat().st_size > 0, f
    summary = pl.read_csv(tmp_path / "o" / "summary.csv")
    assert summary.filter((pl.col("metric") == "T")).height == 4
    assert "reused 0 of 12" in out.stdout


def test_a_bad_plot_costs_no_run_and_lifelong_runs_at_their_horizon_are_complete(cli, tmp_path: Path) -> None:
    (tmp_path / "s.toml").write_text('base = { layout = "paper", robots = 2, tasks = [], orders = { rate = 0.01, '
                                     'horizon = 2000, seed = 1 } }\n[axes]\nrobots = [1, 2]\nseed = [1, 2]\n')
    out = tmp_path / "o"
    for plot, why in (("latency_p99:robots", "METRIC one of"), ("T:robots:robots", "is not another axis"),
                      ("T:seed:nope", "is not another axis")):
        bad = cli("sweep", tmp_path / "s.toml", "--out", out, "--plot", plot, "--quiet")
        assert bad.returncode == 2 and f"--plot = {plot!r}" in bad.stderr and why in bad.stderr, bad.stderr
        assert not (out / "runs").exists() or not any((out / "runs").iterdir())
    ok = cli("sweep", tmp_path / "s.toml", "--out", out, "--plot", "latency_p50:robots", "--quiet")
    assert ok.returncode == 0, ok.stderr
    assert "did not complete" not in ok.stdout and (out / "plot-latency_p50-robots.png").stat().st_size > 0


ray = pytest.importorskip("ray", reason="the ray extra is not installed")


def test_ray_gives_the_local_results_even_when_a_worker_dies(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    s = {"base": BASE, "axes": {"robots": [1, 2, 3], "seed": list(range(1, 9))}}
    local = multibots.sweep(s, tmp_path / "local")
    # The first Ray task to start kills its worker (os._exit): Ray retries the batch.
    marker = tmp_path / "killed"
    monkeypatch.setenv("MULTIBOTS_TEST_KILL_ONCE", str(marker))
    monkeypatch.setattr("multibots.sweeps.runner.RAY_BATCH_COST", 10_000)  # several small tasks
    on_ray = multibots.sweep(s, tmp_path / "ray", backend="ray", workers=2)
    assert marker.exists(), "a worker was killed"
    assert on_ray.equals(local)


def test_points_share_nothing_they_change() -> None:
    # Every point's tables are its own: setting one point's values leaves the others (and the
    # base) as they were.
    sp = parse_spec({"base": {**BASE, "robot": {"threshold": 3.0}},
                     "axes": {"robot.threshold": [2.0, 4.0], "robot.speed": [3.0, 5.0], "seed": [7, 8]}})
    seen = {(p.scenario.to_dict()["robot"]["threshold"], p.scenario.to_dict()["robot"]["speed"],
             p.scenario.to_dict()["tasks"]["seed"]) for p in sp.points()}
    assert seen == {(t, v, s) for t in (2.0, 4.0) for v in (3.0, 5.0) for s in (7, 8)}
    assert sp.base.to_dict()["robot"]["threshold"] == 3.0 and sp.base.to_dict()["tasks"]["seed"] == 1
