"""The original rules (docs/original-rules.md) through the Python API and the command line:
golden values measured with the authors' code, replays, and one-line refusals."""

from __future__ import annotations

import json

import pytest

import multibots
from multibots import PAPER_TASKS, Replay, Scenario, ScenarioError, simulate, simulate_many


def original(n, group=1, **kw):
    return Scenario.paper(robots=n, goods=PAPER_TASKS[group], rules="original", **kw)


def test_the_paper_runs_match_the_authors_code():
    # (ticks, S, C) measured with run_authors.py; N = 1, 3 and 6 of task group 1.
    results = simulate_many([original(1), original(3), original(6)])
    assert [(r.T, r.S, r.C, r.outcome) for r in results] == [
        (6383, 0, 3, "complete"), (1777, 3, 0, "complete"), (1167, 7, 0, "complete")]


def test_a_replay_of_the_original_rules_reads_back(tmp_path):
    path = tmp_path / "o.mbr"
    r = simulate(original(3, 2), record=path)
    with Replay(path) as rp:
        assert rp.summary["T"] == r.T == 2708 and rp.summary["S"] == 1 and rp.summary["C"] == 3
        last = rp.frame(rp.frames - 1)
        assert last["delivered"] == 10
        assert "rules = \"original\"" in rp.header["scenario"]


def test_run_json_and_refusals(cli):
    p = cli("run", "--robots", "2", "--goods", "74,50,62,15,49,34,14,72,31,37", "--rules", "original", "--json")
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert (d["T"], d["S"], d["C"], d["outcome"]) == (3273, 2, 2, "complete")
    bad = cli("run", "--robots", "3", "--goods", "1,2", "--rules", "original")
    assert bad.returncode == 2
    assert bad.stderr.count("\n") == 1 and "original rules" in bad.stderr


def test_the_original_rules_refuse_what_they_cannot_run():
    with pytest.raises(ScenarioError, match="allocator"):
        multibots.Simulation(original(3), allocator=lambda view: {})
    with pytest.raises(ScenarioError, match="layout"):
        Scenario.from_dict({"rules": "original", "layout_generate": {}, "robots": 2, "tasks": [1, 2]}).validate()
