"""Studies of LoRR schedulers, the user's own among them: what a Start-Kit Python entry sees
at each call (fields made on first read), ``delay_seed`` (another draw of the 2026 delays, the
Start-Kit's for that seed), Python schedulers in LoRR sweeps and in ``multibots compare
--lorr`` beside the built-ins, paired by seed, with intervals and tests."""

from __future__ import annotations

import csv
import json
import re
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
    # The command names the flags the user typed.
    for flags, said in [(["--delay-seed", "3"], "--delay-seed = 3: a 2024 problem has no delays"),
                        (["--disable-staged-action-validation"],
                         "--disable-staged-action-validation: only the 2026 rules stage actions")]:
        p = subprocess.run([sys.executable, "-m", "multibots", "lorr", str(problem), "--steps", "5", *flags],
                           capture_output=True, text=True)
        lines = p.stderr.strip().splitlines()
        assert p.returncode == 2 and len(lines) == 1 and lines[0].startswith(f"multibots: error: {said}"), p.stderr


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
    # The same spec read from elsewhere (a copy beside a copy of the entry... here, the same
    # files named by absolute paths) keys its runs the same: nothing runs again.
    moved = tmp_path / "elsewhere"
    moved.mkdir()
    (moved / "study.toml").write_text(spec.read_text().replace('"pyTaskScheduler.py"', f'"{entry}"'))
    multibots.sweep(moved / "study.toml", tmp_path / "o", reused=lambda k, n: again.append((k, n)))
    assert again[-1] == (8, 8)
    entry.write_text(TEMPLATE.read_text() + "\n# edited\n")  # an edited entry runs again
    multibots.sweep(spec, tmp_path / "o", reused=lambda k, n: again.append((k, n)))
    assert again[-1] == (4, 8)
    from multibots.sweeps import load_spec, write_outputs

    again_df = multibots.sweep(spec, tmp_path / "o")
    write_outputs(again_df, load_spec(spec), tmp_path / "o", baseline="scheduler=soonest")
    summary = pl.read_csv(tmp_path / "o" / "summary.csv")
    assert set(summary["metric"].to_list()) == {"delivered", "throughput", "plan_ms_mean", "schedule_ms_mean",
                                                "schedule_errors", "action_errors", "delays"}


@needs_examples
def test_a_lorr_sweep_checks_its_entry_files_before_any_run(tmp_path: Path) -> None:
    (tmp_path / "broken.py").write_text("import MAPF\nclass pyTaskScheduler(:\n")
    (tmp_path / "wrong.py").write_text("class Other:\n    pass\n")
    for name, frag in [("broken.py", "spec: axes.scheduler = 'broken.py': SyntaxError"),
                       ("wrong.py", "spec: axes.scheduler = 'wrong.py': defines no class pyTaskScheduler")]:
        spec = {"base": {"lorr": str(MAZE), "steps": 20}, "axes": {"scheduler": ["soonest", name]}}
        with pytest.raises(multibots.exceptions.InputError, match=re.escape(frag)):
            _plan(spec, tmp_path)
    problem = SHARED / "reference" / "lorr" / "2024" / "random.domain" / "random_32_32_20_100.json"
    with pytest.raises(multibots.exceptions.InputError, match=r"^spec: axes\.delay_seed = \[3\]: .* has no delays"):
        _plan({"base": {"lorr": str(problem), "steps": 20}, "axes": {"delay_seed": [3]}}, tmp_path)


def _plan(spec: dict, folder: Path) -> list:
    from multibots.sweeps import parse_spec

    return parse_spec(spec, source="spec", folder=folder).points()


# The planner's view when the scheduler is Python too (2024 rules): the tasks and robots that
# were new at the scheduler's call, and the schedule it proposed.
SYNCED_SCHEDULER = """
import json


class pyTaskScheduler:
    def initialize(self, t):
        pass

    def plan(self, time_limit):
        env = self.env
        schedule = list(env.curr_task_schedule)
        free = [a for a in env.new_freeagents]
        open_tasks = sorted(k for k, t in env.task_pool.items() if t.agent_assigned == -1)
        for a, t in zip(free, open_tasks):
            schedule[a] = t
        with open(OUT, "a") as f:
            f.write(json.dumps({"who": "scheduler", "tick": env.system_timestep, "new": sorted(env.new_tasks),
                                "free": sorted(env.new_freeagents), "schedule": schedule}) + "\\n")
        return schedule
"""
SYNCED_PLANNER = """
import json
import pickle
import MAPF


class pyMAPFPlanner:
    def initialize(self, t):
        pass

    def plan(self, time_limit):
        env = self.env
        copy = pickle.loads(pickle.dumps(env))  # a plain copy of every field
        with open(OUT, "a") as f:
            f.write(json.dumps({"who": "planner", "tick": env.system_timestep, "new": sorted(env.new_tasks),
                                "free": sorted(env.new_freeagents), "schedule": list(env.curr_task_schedule),
                                "copied": [copy.curr_task_schedule == env.curr_task_schedule,
                                           [s.location for s in copy.curr_states] ==
                                           [s.location for s in env.curr_states],
                                           sorted(copy.task_pool) == sorted(env.task_pool)]}) + "\\n")
        return [MAPF.Action.W] * env.num_of_agents
"""


def test_a_python_planner_after_a_python_scheduler_sees_its_news_and_its_proposal(tmp_path: Path) -> None:
    problem = SHARED / "reference" / "lorr" / "2024" / "random.domain" / "random_32_32_20_100.json"
    if not problem.is_file():
        pytest.skip("no 2024 example")
    out = tmp_path / "calls.jsonl"
    (tmp_path / "s.py").write_text(f"OUT = {str(out)!r}\n" + SYNCED_SCHEDULER)
    (tmp_path / "p.py").write_text(f"OUT = {str(out)!r}\n" + SYNCED_PLANNER)
    lorr.run(problem, steps=4, scheduler_py=tmp_path / "s.py", planner_py=tmp_path / "p.py")
    calls = [json.loads(line) for line in out.read_text().splitlines()]
    assert [c["who"] for c in calls] == ["scheduler", "planner"] * 4
    for sched, plan in zip(calls[::2], calls[1::2]):
        assert plan["tick"] == sched["tick"]
        assert (plan["new"], plan["free"]) == (sched["new"], sched["free"])
        assert plan["schedule"] == sched["schedule"]
        assert plan["copied"] == [True, True, True]
    assert calls[0]["free"] == list(range(len(calls[0]["schedule"]))) and calls[0]["new"]


# An executor whose environment keeps what it was first given and what it assigns.
KEEPS = """
import json
import MAPF


class pyExecutor:
    def initialize(self, t):
        self.first_free = list(self.env.new_freeagents)
        self.env.mine = "kept"

    def process_new_plan(self, sync_time_limit, plan, staged_actions):
        for i, row in enumerate(plan.actions):
            staged_actions[i].extend(a for a in row if a not in (MAPF.Action.W, MAPF.Action.NA))
        with open(OUT, "a") as f:
            f.write(json.dumps({"free": list(self.env.new_freeagents) == self.first_free,
                                "mine": getattr(self.env, "mine", None),
                                "start_is_curr": self.env.start_states is self.env.curr_states,
                                "system": len(self.env.system_states)}) + "\\n")
        return list(self.env.system_states)

    def next_command(self, exec_time_limit):
        return [MAPF.ExecutionCommand.GO if q else MAPF.ExecutionCommand.STOP for q in self.env.staged_actions]
"""


def test_a_python_executor_keeps_its_fields_between_calls(tmp_path: Path) -> None:
    out = tmp_path / "calls.jsonl"
    (tmp_path / "pyExecutor.py").write_text(f"OUT = {str(out)!r}\n" + KEEPS)
    r = lorr.run(TINY, steps=60, executor_py=tmp_path / "pyExecutor.py")
    calls = [json.loads(line) for line in out.read_text().splitlines()]
    assert len(calls) >= 5
    assert all(c == {"free": True, "mine": "kept", "start_is_curr": True, "system": r.team_size} for c in calls)


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
