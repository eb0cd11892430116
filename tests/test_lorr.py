"""League of Robot Runners problems: the competition's independent checker agrees with every
result (valid, and the same ``numTaskFinished``), the result file has the competition's
fields, the plan time limit works as the competition's, and the command line's errors are one
line. The example problems and the checker live beside the repository
(``../shared/reference/lorr``, ``../shared/tools/lorr_check.py``)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from multibots import lorr
from multibots.exceptions import ScenarioError

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared"
REFERENCE = SHARED / "reference" / "lorr"
CHECKER = SHARED / "tools" / "lorr_check.py"

#: (problem, steps): the warehouse problems are cut short so that the checker's replay of
#: 5,000 robots stays under a minute.
EXAMPLES = [
    ("2023/random.domain/random_100.json", 3000),
    ("2024/random.domain/random_32_32_20_100.json", 3000),
    ("2023/warehouse.domain/warehouse_large_1000.json", 600),
    ("2024/warehouse.domain/warehouse_large_5000.json", 150),
]

needs_examples = pytest.mark.skipif(not CHECKER.is_file(), reason=f"the LoRR examples and checker are not at {SHARED}")


def check(problem: Path, result: Path) -> dict:
    argv = [sys.executable, str(CHECKER), str(problem), str(result)]
    p = subprocess.run(argv, capture_output=True, text=True, timeout=600)
    assert p.stdout.strip(), p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


@needs_examples
@pytest.mark.parametrize(("name", "steps"), EXAMPLES, ids=[e[0].split("/")[-1] for e in EXAMPLES])
def test_the_checker_agrees(tmp_path, name, steps):
    problem = REFERENCE / name
    out = tmp_path / "result.json"
    r = lorr.run(problem, steps=steps, out=out)
    verdict = check(problem, out)
    assert verdict["valid"], verdict["error"]
    assert verdict["finished"] == r.finished == verdict["claimed"]
    assert verdict["steps"] == steps
    assert r.finished > 0
    data = json.loads(out.read_text())
    fields = {"actionModel", "version", "teamSize", "start", "numTaskFinished", "sumOfCost", "makespan",
              "actualPaths", "plannerPaths", "plannerTimes", "errors", "events", "tasks"}
    if name.startswith("2024"):
        fields |= {"actualSchedule", "plannerSchedule", "scheduleErrors"}
    assert fields <= set(data)
    assert data["actionModel"] == "MAPF_T" and data["teamSize"] == r.team_size
    assert sum(r.figures["finished_per_1000"]) == r.finished
    assert json.loads(lorr.figures_path(out).read_text())["finished"] == r.finished


@needs_examples
@pytest.mark.parametrize("scheduler", lorr.SCHEDULERS)
def test_every_scheduler_gives_valid_results(tmp_path, scheduler):
    problem = REFERENCE / "2024/random.domain/random_32_32_20_100.json"
    out = tmp_path / "r.json"
    r = lorr.run(problem, steps=1000, out=out, scheduler=scheduler)
    verdict = check(problem, out)
    assert verdict["valid"] and verdict["finished"] == r.finished > 100, verdict


@needs_examples
def test_runs_are_the_same_for_a_seed(tmp_path):
    problem = REFERENCE / "2023/random.domain/random_100.json"
    paths = []
    for i, seed in enumerate((5, 5, 6)):
        out = tmp_path / f"r{i}.json"
        lorr.run(problem, steps=500, out=out, seed=seed)
        paths.append(json.loads(out.read_text())["actualPaths"])
    assert paths[0] == paths[1]
    assert paths[0] != paths[2]


@needs_examples
def test_plan_time_limit_makes_robots_wait(tmp_path):
    # The first round searches 5,000 distance tables (well over a second on any machine): with
    # a 1 ms limit it overruns by far more than the first three steps, and every robot waits
    # (T) on exactly the steps the planner overran, as the Start-Kit's clock has it. The
    # assertions hold however fast the machine is (CI once ran the round in 0.2 s, which a
    # 100 ms limit made a flaky test).
    problem = REFERENCE / "2024/warehouse.domain/warehouse_large_5000.json"
    out = tmp_path / "r.json"
    r = lorr.run(problem, steps=12, out=out, plan_time_limit_ms=1)
    assert r.figures["timeouts"] >= 3
    data = json.loads(out.read_text())
    paths = [p.split(",") for p in data["actualPaths"]]
    assert paths[0][:3] == ["T", "T", "T"]
    waited = [i for i, a in enumerate(paths[0]) if a == "T"]
    assert len(waited) == r.figures["timeouts"] == data["numEntryTimeouts"]
    assert all([i for i, a in enumerate(p) if a == "T"] == waited for p in paths)
    assert check(problem, out)["valid"]


def tiny_problem(folder, map_text: str, agents: str, tasks: str, rules: str) -> None:
    """A two-robot problem in ``folder``: its map, agents and tasks files, and ``p.json``
    with the JSON members ``rules`` (version, reveal, assignment)."""
    (folder / "m.map").write_text(map_text)
    (folder / "a.agents").write_text(agents)
    (folder / "t.tasks").write_text(tasks)
    (folder / "p.json").write_text(
        '{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 2, ' + rules + "}"
    )


def test_bad_files_are_one_line_naming_file_and_line(cli, tmp_path):
    tiny_problem(tmp_path, "type octile\nheight 2\nwidth 2\nmap\n..\n.@\n", "2\n0\n3\n", "1\n1\n",
                 '"numTasksReveal": 1, "taskAssignmentStrategy": "roundrobin"')
    p = cli("lorr", tmp_path / "p.json", "--steps", "5")
    cli.assert_one_line_error(p, "a.agents, line 3", "obstacle")
    with pytest.raises(ScenarioError, match="a.agents, line 3"):
        lorr.run(tmp_path / "p.json", steps=5)
    cli.assert_one_line_error(cli("lorr", tmp_path / "missing.json"), "missing.json")
    (tmp_path / "a.agents").write_text("2\n0\n1\n")
    cli.assert_one_line_error(cli("lorr", tmp_path / "p.json", "--planner", "astar"), "planner = astar")
    cli.assert_one_line_error(cli("lorr", tmp_path / "p.json", "--plan-time-limit", "0"), "--plan-time-limit")


def test_the_command_prints_the_score(cli, tmp_path):
    tiny_problem(tmp_path, "type octile\nheight 3\nwidth 4\nmap\n....\n.@@.\n....\n", "2\n0\n11\n",
                 "# version for LoRR 2024\n3\n3,8\n11\n0,3\n", '"numTasksReveal": 1.5, "version": "2024 LoRR"')
    out = tmp_path / "r.json"
    p = cli("lorr", tmp_path / "p.json", "--steps", "200", "--out", out)
    assert p.returncode == 0, p.stderr
    finished = json.loads(out.read_text())["numTaskFinished"]
    assert finished > 5
    assert f": {finished:,} finished in 200 steps (2 robots, 2024 rules)" in p.stdout
