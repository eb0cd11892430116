"""The worked example of docs/learning.md: the trainer runs, and the trained policy is a strategy."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("gymnasium")

import multibots
from multibots.strategies import load_strategy

ROOT = Path(__file__).resolve().parents[2]


def test_the_trainer_runs_and_saves_weights(tmp_path):
    out = tmp_path / "p.npz"
    cmd = [sys.executable, str(ROOT / "examples/train_dispatch.py"), "--iterations", "1", "--population", "3"]
    p = subprocess.run([*cmd, "--episodes", "1", "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert out.exists() and "iteration  1" in p.stdout


def test_the_shipped_policy_plugs_in_as_a_strategy():
    strategy = load_strategy(str(ROOT / "examples/trained_dispatch.py") + ":TrainedDispatch")
    r = multibots.simulate(multibots.Scenario.paper(robots=3), allocator=strategy())
    assert r.outcome == "complete"
