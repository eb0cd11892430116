"""Sweeps with a League of Robot Runners problem as their base (docs/lorr.md): the run's
options as axes, the same store (kill -9 resumes, finished runs reused), the LoRR figures as
result fields, and bad axes as one line before any run."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import multibots
from multibots import lorr
from multibots.sweeps import Store

pl = pytest.importorskip("polars", reason="the study extra (polars) is not installed")

MAP = "type octile\nheight 4\nwidth 8\nmap\n........\n.@@..@@.\n........\n...@@...\n"


def problem(folder: Path) -> Path:
    """A 2024 problem of 4 agents (a team of 1 to 4) with two-errand tasks."""
    (folder / "m.map").write_text(MAP)
    (folder / "a.agents").write_text("4\n0\n7\n16\n31\n")
    (folder / "t.tasks").write_text("# version for LoRR 2024\n5\n3,20\n17,6\n24,2\n12,30\n8,23\n")
    path = folder / "p.json"
    path.write_text('{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 4, '
                    '"numTasksReveal": 1.5, "version": "2024 LoRR"}')
    return path


def test_a_lorr_sweep_runs_each_point_as_lorr_run_would(tmp_path: Path) -> None:
    p = problem(tmp_path)
    spec = {"base": {"lorr": str(p), "steps": 150}, "axes": {"scheduler": ["nearest", "greedy"], "robots": [1, 2, 4]}}
    df = multibots.sweep(spec, tmp_path / "out", workers=2)
    assert df.height == 6 and df["key"].n_unique() == 6
    for row in df.to_dicts():
        alone = lorr.run(p, steps=150, scheduler=row["scheduler"], robots=row["robots"])
        assert row["team_size"] == row["robots"] == alone.team_size
        assert row["finished"] == row["delivered"] == alone.finished
        assert row["finished_per_1000"] == pytest.approx(alone.finished * 1000 / 150)
        assert row["windows"] == ";".join(map(str, alone.figures["finished_per_1000"]))
        assert row["errors"] == alone.figures["action_errors"] + alone.figures["schedule_errors"]
        assert row["steps"] == 150 and row["rules"] == "2024" and row["plan_ms_mean"] >= 0
    assert df.filter(pl.col("robots") == 4)["finished"].min() > 0
    seen = []
    again = multibots.sweep(spec, tmp_path / "out", reused=lambda k, n: seen.append((k, n)))
    assert seen == [(6, 6)] and again.drop("key").equals(df.drop("key"))
    # An edited task file runs again, though the problem's path is the same.
    (tmp_path / "t.tasks").write_text("# version for LoRR 2024\n3\n3,20\n17,6\n24,2\n")
    multibots.sweep(spec, tmp_path / "out", reused=lambda k, n: seen.append((k, n)))
    assert seen[-1] == (0, 6)


def test_the_command_writes_results_and_a_plain_json_base(cli, tmp_path: Path) -> None:
    problem(tmp_path)
    (tmp_path / "s.toml").write_text('base = "p.json"\n[axes]\nseed = [0, 1]\nsteps = [40]\n')
    p = cli("sweep", tmp_path / "s.toml", "--out", tmp_path / "o", "--quiet")
    assert p.returncode == 0, p.stderr
    rows = pl.read_csv(tmp_path / "o" / "results.csv")
    assert rows["seed"].to_list() == [0, 1] and rows["team_size"].to_list() == [4, 4]
    assert {"finished", "finished_per_1000", "plan_ms_mean", "errors"} <= set(rows.columns)
    summary = pl.read_csv(tmp_path / "o" / "summary.csv")
    # The LoRR figures, not the paper's (which a LoRR run does not have).
    assert set(summary.filter(pl.col("n") > 0)["metric"].to_list()) >= {"delivered", "throughput", "plan_ms_mean"}
    assert "T" not in summary["metric"].to_list()


def test_bad_lorr_sweeps_are_one_line_before_any_run(cli, tmp_path: Path) -> None:
    problem(tmp_path)
    for text, frag in [('base = "p.json"\n[axes]\nplanner = ["pibt", "astar"]\n', "axes.planner = 'astar'"),
                       ('base = "p.json"\n[axes]\nscheduler = ["fifo"]\n', "axes.scheduler = 'fifo': not a scheduler"),
                       ('base = "p.json"\n[axes]\nallocator = ["nearest"]\n', "axes.allocator: not an option"),
                       ('base = "p.json"\n[axes]\nrobots = [2, 0]\n', "axes.robots = 0"),
                       ('base = "p.json"\n[axes]\nrobots = [2, 9]\n', "at robots = 9"),
                       ('base = "nope.json"\n[axes]\nseed = [1]\n', "base.lorr = 'nope.json'"),
                       ('base = { lorr = "p.json", stepz = 3 }\n[axes]\nseed = [1]\n', "base.stepz")]:
        (tmp_path / "s.toml").write_text(text)
        cli.assert_one_line_error(cli("sweep", tmp_path / "s.toml", "--out", tmp_path / "o", "--quiet"), frag)
    assert not (tmp_path / "o").exists()


def test_a_lorr_sweep_runs_on_ray_as_locally(tmp_path: Path) -> None:
    # One runner for every rule set: the Ray backend runs LoRR problems too, to the same scores.
    pytest.importorskip("ray", reason="the ray extra is not installed")
    problem(tmp_path)
    spec = {"base": {"lorr": str(tmp_path / "p.json"), "steps": 60}, "axes": {"seed": [0, 1, 2]}}
    local = multibots.sweep(spec, tmp_path / "local")
    on_ray = multibots.sweep(spec, tmp_path / "ray", backend="ray", workers=2)
    assert on_ray["finished"].to_list() == local["finished"].to_list()
    assert on_ray["seed"].to_list() == [0, 1, 2] and min(local["finished"].to_list()) > 0


def test_kill_9_then_resume_loses_and_repeats_nothing(tmp_path: Path) -> None:
    problem(tmp_path)
    seeds = list(range(40))
    spec = f'base = {{ lorr = "p.json", steps = 20000 }}\n[axes]\nseed = {json.dumps(seeds)}\n'
    (tmp_path / "s.toml").write_text(spec)
    env = {**os.environ, "MULTIBOTS_SWEEP_FLUSH": "0.02"}
    p = subprocess.Popen([sys.executable, "-m", "multibots", "sweep", "s.toml", "--out", "k", "--workers", "1",
                          "--quiet"], cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    runs = tmp_path / "k" / "runs"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not list(runs.glob("part-*.parquet")):
        time.sleep(0.01)
    p.send_signal(signal.SIGKILL)
    p.communicate()
    stored = Store(tmp_path / "k").frame().height
    assert 0 < stored < len(seeds), stored  # killed part-way
    seen = []
    resumed = multibots.sweep(tmp_path / "s.toml", tmp_path / "k", reused=lambda k, n: seen.append(k))
    assert seen == [stored]
    parts = pl.concat([pl.read_parquet(f) for f in runs.glob("part-*.parquet")], how="diagonal_relaxed")
    assert parts.height == len(seeds) and parts["key"].n_unique() == len(seeds), "no run lost, none run twice"
    whole = multibots.sweep(tmp_path / "s.toml", tmp_path / "whole")
    clock = ["key", "plan_ms_mean", "plan_ms_max"]  # planning times are the machine's, not the run's
    assert resumed.drop(clock).equals(whole.drop(clock)) and resumed["key"].equals(whole["key"])
