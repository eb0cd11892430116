"""`compare` is a thin layer over the sweep's runner: the same runs give the same keys and
figures either way, and the journal is the runner's store."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import multibots
from multibots.experiments import compare as study

# The repository (a `conftest` import would find whichever conftest.py was loaded first).
ROOT = Path(__file__).resolve().parents[2]


pytest.importorskip("polars", reason="the study extra (polars) is not installed")


def test_compare_and_sweep_run_the_same_runs(tmp_path: Path) -> None:
    journal = tmp_path / "runs.jsonl"
    rows = study.run_study(["in-turn", "nearest"], [1, 2], study.parse_tasks("random:3"), seeds=2, workers=2,
                           journal=journal)
    df = multibots.sweep({"base": {"layout": "paper", "robots": 1, "tasks": {"random": 3, "seed": 1}},
                          "axes": {"allocator": ["in-turn", "nearest"], "robots": [1, 2], "seed": [1, 2]}},
                         tmp_path / "sweep", workers=2)
    # The same scenarios: the same keys, so a store could serve either.
    journal_keys = {json.loads(line)["key"] for line in journal.read_text().splitlines()}
    assert journal_keys == set(df["key"].to_list()) and len(journal_keys) == 8
    by_cell = {(r["allocator"], r["robots"], r["seed"]): r for r in df.to_dicts()}
    for row in rows:
        other = by_cell[(row["strategy"], row["N"], row["list"])]
        for name in ("T", "S", "C", "delivered", "distance", "windows"):
            assert row[name] == other[name], name


def test_a_python_strategy_under_several_traffic_policies(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Each arm is labelled "strategy/policy", the strategy by its ``name``; it is still loaded
    # by its module and class.
    monkeypatch.chdir(ROOT)
    closest = "tests/strategies_example/closest.py:Closest"
    rows = study.run_study([closest, "in-turn"], [2], study.parse_tasks("random:4"), seeds=2, workers=2,
                           traffic=["wait", "reserve"], journal=tmp_path / "runs.jsonl")
    arms = {r["strategy"] for r in rows}
    assert arms == {"closest/wait", "closest/reserve", "in-turn/wait", "in-turn/reserve"}
    assert all(r["outcome"] == "complete" for r in rows)
