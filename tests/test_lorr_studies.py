"""Studies of LoRR schedulers, the user's own among them: what a Start-Kit Python entry sees
at each call (fields made on first read), ``delay_seed`` (another draw of the 2026 delays, the
Start-Kit's for that seed), Python schedulers in LoRR sweeps and in ``multibots compare
--lorr`` beside the built-ins, paired by seed, with intervals and tests."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

import multibots
from multibots import lorr
from multibots.exceptions import ScenarioError

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared"
CHECKER = SHARED / "tools" / "lorr_check26.py"
MAZE = SHARED / "reference" / "lorr" / "2026" / "maze.domain" / "maze-example_40.json"
TINY = ROOT / "examples" / "lorr26" / "tiny.json"
TEMPLATE = ROOT / "examples" / "lorr26" / "pyTaskScheduler.py"

needs_examples = pytest.mark.skipif(not CHECKER.is_file(), reason=f"the LoRR 2026 examples are not at {SHARED}")

# Records what the entry sees at every call: the fields' kinds and sizes, and how they relate.
SEES = """
import json
import MAPF


class pyTaskScheduler:
    def initialize(self, preprocess_time_limit):
        self.calls = []

    def plan(self, time_limit):
        env = self.env
        pool = env.task_pool
        seen = {
            "tick": env.system_timestep,
            "n": env.num_of_agents,
            "states": [len(env.curr_states), len(env.system_states), len(env.curr_task_schedule),
                       len(env.goal_locations), len(env.staged_actions)],
            "start_is_curr": env.start_states is env.curr_states,
            "system_ticks": sorted({s.timestep for s in env.system_states}),
            "kinds": sorted({type(t).__name__ for t in pool.values()}),
            "ids_match": all(k == t.task_id for k, t in pool.items()),
            "new_in_pool": all(k in pool for k in env.new_tasks),
            "free": list(env.new_freeagents),
            "schedule_open": all(s == -1 or s in pool for s in env.curr_task_schedule),
            "goals": [g[0][0] if g else -1 for g in env.goal_locations],
            "cells": [s.location for s in env.curr_states],
            "free_cells": all(env.map[s.location] == 0 for s in env.system_states),
        }
        schedule = list(env.curr_task_schedule)
        # An assignment stands for the rest of the call.
        env.curr_task_schedule = [-1] * env.num_of_agents
        seen["assigned"] = env.curr_task_schedule == [-1] * env.num_of_agents
        with open(OUT, "a") as f:
            f.write(json.dumps(seen) + "\\n")
        free = sorted(set(env.new_freeagents))
        for agent, task in zip(free, sorted(k for k, t in pool.items() if t.agent_assigned == -1)):
            schedule[agent] = task
        return schedule
"""


def test_a_python_scheduler_sees_every_field_as_the_start_kit_gives_it(tmp_path: Path) -> None:
    out = tmp_path / "seen.jsonl"
    entry = tmp_path / "pyTaskScheduler.py"
    entry.write_text(f"OUT = {str(out)!r}\n" + SEES)
    r = lorr.run(TINY, steps=300, scheduler_py=entry)
    calls = [json.loads(line) for line in out.read_text().splitlines()]
    n = r.team_size
    assert len(calls) >= 6 and [c["tick"] for c in calls] == sorted(c["tick"] for c in calls)
    for c in calls:
        assert c["n"] == n and c["states"] == [n] * 5
        assert c["start_is_curr"] and c["system_ticks"] == [c["tick"]]
        assert c["kinds"] == ["Task"] and c["ids_match"] and c["new_in_pool"] and c["schedule_open"]
        assert c["free_cells"] and c["assigned"]
    # Every robot is free at the first call; the scheduler's answer binds them to tasks, whose
    # errands are the goals the next call sees.
    assert calls[0]["free"] == list(range(n))
    assert any(g != -1 for c in calls[1:] for g in c["goals"])
    assert r.finished > 0


@needs_examples
def test_delay_seed_plays_the_start_kits_draw_for_that_seed(tmp_path: Path) -> None:
    # The outside checker re-draws the delays from the problem file's seed: a copy of the
    # problem with delayConfig.seed = 7 must find our delay_seed=7 run's delays its own.
    data = json.loads(MAZE.read_text())
    for key in ("mapFile", "agentFile", "taskFile"):
        data[key] = str(MAZE.parent / data[key])
    assert data["delayConfig"]["seed"] != 7
    data["delayConfig"]["seed"] = 7
    copy = tmp_path / "maze-seed7.json"
    copy.write_text(json.dumps(data))
    out = tmp_path / "r.json"
    r = lorr.run(MAZE, steps=200, out=out, delay_seed=7)
    p = subprocess.run([sys.executable, str(CHECKER), str(copy), str(out)], capture_output=True, text=True,
                       timeout=600)
    verdict = json.loads(p.stdout.strip().splitlines()[-1])
    assert verdict["valid"] and verdict["delays_seeded"] == "match" and verdict["finished"] == r.finished
    theirs = json.loads(out.read_text())["delayIntervals"]
    lorr.run(MAZE, steps=200, out=tmp_path / "own.json")
    assert json.loads((tmp_path / "own.json").read_text())["delayIntervals"] != theirs


def test_delay_seed_is_refused_where_there_are_no_delays(tmp_path: Path) -> None:
    problem = SHARED / "reference" / "lorr" / "2024" / "random.domain" / "random_32_32_20_100.json"
    if not problem.is_file():
        pytest.skip("no 2024 example")
    with pytest.raises(ScenarioError, match=r"^delay_seed = 3: a 2024 problem has no delays"):
        lorr.run(problem, steps=5, delay_seed=3)
    with pytest.raises(multibots.exceptions.ArgumentError, match=r"^delay_seed = -1: expected an integer"):
        lorr.run(TINY, steps=5, delay_seed=-1)


def test_a_pibt_planner_runs_a_fleet_of_three_under_the_2026_rules() -> None:
    # The lean tables of the 2026 rules were sized for at least 8 robots (an engine panic).
    r = lorr.run(TINY, steps=120, planner="pibt")
    assert r.steps == 120 and r.planner == "pibt"


@needs_examples
def test_a_lorr_sweep_compares_a_python_scheduler_with_a_built_in_seed_by_seed(tmp_path: Path) -> None:
    pl = pytest.importorskip("polars")
    entry = tmp_path / "pyTaskScheduler.py"
    entry.write_text(TEMPLATE.read_text())
    spec = tmp_path / "study.toml"
    spec.write_text(f'repeats = 4\n[base]\nlorr = "{MAZE}"\nsteps = 300\n'
                    '[axes]\nscheduler = ["soonest", "pyTaskScheduler.py"]\n')
    refused = subprocess.run([sys.executable, "-m", "multibots", "sweep", str(spec), "--out", str(tmp_path / "o")],
                             capture_output=True, text=True)
    assert refused.returncode == 2 and "names Python code (pyTaskScheduler.py)" in refused.stderr
    df = multibots.sweep(spec, tmp_path / "o")
    rows = df.to_dicts()
    assert len(rows) == 8
    by = {(r["scheduler"], r["seed"]): r for r in rows}
    for seed in (1, 2, 3, 4):
        mine, theirs = by["pyTaskScheduler.py", seed], by["soonest", seed]
        assert mine["delays"] == theirs["delays"]  # the same draw of the delays, paired
        assert mine["schedule_ms_mean"] > 0
        alone = lorr.run(MAZE, steps=300, scheduler_py=entry, seed=seed,
                         delay_seed=json.loads(MAZE.read_text())["delayConfig"]["seed"] + seed)
        assert mine["finished"] == alone.finished
    assert len({by["soonest", s]["delays"] for s in (1, 2, 3, 4)}) > 1  # seeds are draws
    again: list[tuple[int, int]] = []
    multibots.sweep(spec, tmp_path / "o", reused=lambda k, n: again.append((k, n)))
    assert again == [(8, 8)]
    entry.write_text(TEMPLATE.read_text() + "\n# edited\n")  # an edited entry runs again
    multibots.sweep(spec, tmp_path / "o", reused=lambda k, n: again.append((k, n)))
    assert again[-1] == (4, 8)
    assert pl is not None


@needs_examples
def test_compare_lorr_prints_intervals_and_tests_against_the_first(tmp_path: Path) -> None:
    entry = tmp_path / "pyTaskScheduler.py"
    entry.write_text(TEMPLATE.read_text())
    argv = [sys.executable, "-m", "multibots", "compare", "--lorr", str(MAZE), "--strategies",
            f"soonest,greedy,{entry}", "--steps", "200", "--seeds", "3", "--out", str(tmp_path / "c"), "--quiet"]
    refused = subprocess.run(argv, capture_output=True, text=True)
    assert refused.returncode == 2 and "--allow-code" in refused.stderr
    p = subprocess.run([*argv, "--allow-code"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    table = p.stdout.splitlines()
    assert table[0].split()[:3] == ["scheduler", "robots", "tasks"]
    assert [line.split()[0] for line in table[1:4]] == ["soonest", "greedy", "pyTaskScheduler.py"]
    tests = list(csv.DictReader((tmp_path / "c" / "tests.csv").open()))
    delivered = {r["scheduler"]: r for r in tests if r["metric"] == "delivered"}
    assert set(delivered) == {"greedy", str(entry)} and all(r["pairs"] == "3" for r in delivered.values())
    results = list(csv.DictReader((tmp_path / "c" / "results.csv").open()))
    mean = sum(float(r["delivered"]) for r in results if r["scheduler"] == "soonest") / 3
    assert f"{mean:,.1f}" in table[1]
    bad = subprocess.run([sys.executable, "-m", "multibots", "compare", "--lorr", str(MAZE), "--tasks", "random:3",
                          "--out", str(tmp_path / "d")], capture_output=True, text=True)
    assert bad.returncode == 2 and bad.stderr.startswith("multibots: error: --tasks: the paper model's option")


# A Combined-track executor: it drops what it had staged and stages the new plan's first
# action only, which is no prefix of the old queue followed by the plan.
RESTAGES = """
import MAPF


class pyExecutor:
    def initialize(self, preprocess_time_limit):
        pass

    def process_new_plan(self, sync_time_limit, plan, staged_actions):
        for i, row in enumerate(plan.actions):
            staged_actions[i][:] = [a for a in row if a not in (MAPF.Action.W, MAPF.Action.NA)][:1]
        return list(self.env.system_states)

    def next_command(self, exec_time_limit):
        return [MAPF.ExecutionCommand.GO] * self.env.num_of_agents
"""


@needs_examples
def test_staged_action_validation_is_the_start_kits_and_can_be_turned_off(tmp_path: Path) -> None:
    entry = tmp_path / "pyExecutor.py"
    entry.write_text(RESTAGES)
    with pytest.raises(multibots.exceptions.AllocatorError, match=r"^executor pyExecutor\.py: robot \d+'s staged "
                       r"actions \w* are not a prefix of \w* then \w*"):
        lorr.run(MAZE, steps=100, executor_py=entry)
    out = tmp_path / "r.json"
    r = lorr.run(MAZE, steps=100, executor_py=entry, out=out, staged_validation=False)
    p = subprocess.run([sys.executable, str(CHECKER), str(MAZE), str(out)], capture_output=True, text=True,
                       timeout=600)
    verdict = json.loads(p.stdout.strip().splitlines()[-1])
    assert verdict["valid"] and verdict["finished"] == r.finished and r.steps == 100
    cli = subprocess.run([sys.executable, "-m", "multibots", "lorr", str(MAZE), "--steps", "100", "--executor-py",
                          str(entry), "--disable-staged-action-validation"], capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    problem = SHARED / "reference" / "lorr" / "2024" / "random.domain" / "random_32_32_20_100.json"
    if problem.is_file():
        with pytest.raises(ScenarioError, match=r"^staged_validation = False: only the 2026 rules stage actions"):
            lorr.run(problem, steps=5, staged_validation=False)
