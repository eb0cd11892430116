"""When the sweep runner writes finished runs (docs/sweeps.md): every run reported finished is
stored when the study is interrupted, a finished run does not wait for a long call of the
engine, and `compare` killed with SIGKILL loses no run its journal reported."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest

from multibots.sweeps import parse_spec, runner

BASE = {"layout": "paper", "robots": 2, "tasks": {"random": 6, "seed": 1}}


class MemoryStore:
    """A store that keeps runs in memory and notes when each write happened."""

    def __init__(self, flush_seconds: float, write_seconds: float = 0.0) -> None:
        self.flush_seconds = flush_seconds
        self.write_seconds = write_seconds
        self.stored: dict[str, dict[str, Any]] = {}
        self.writes: list[tuple[float, int, str]] = []

    def keys(self) -> set[str]:
        return set(self.stored)

    def write(self, points, keys, figures) -> None:
        time.sleep(self.write_seconds)
        assert threading.current_thread().name == "multibots-sweep-store"
        self.stored.update(zip(keys, figures))
        self.writes.append((time.monotonic(), len(keys), threading.current_thread().name))


def points(n: int):
    return parse_spec({"base": BASE, "axes": {"seed": list(range(1, n + 1))}}).points(1)


def test_an_interrupt_keeps_every_run_reported_finished() -> None:
    pts = points(60)
    store = MemoryStore(flush_seconds=0.0, write_seconds=0.05)
    ticks: list[int] = []
    on_main: list[bool] = []

    def progress(k: int) -> None:
        ticks.append(k)
        on_main.append(threading.current_thread() is threading.main_thread())
        if len(ticks) == 2:
            raise KeyboardInterrupt  # Ctrl-C while the first call's runs may still be writing

    with pytest.raises(KeyboardInterrupt):
        runner.run_points(pts, store, workers=1, progress=progress)
    assert all(on_main), "the progress callback runs on the caller's thread"
    assert len(store.stored) == sum(ticks) == len(set(store.stored)), (ticks, len(store.stored))
    assert 0 < len(store.stored) < len(pts)


class SlowSecondCall:
    """The engine module, with its second `simulate_many` call taking `seconds` longer."""

    def __init__(self, core: Any, seconds: float) -> None:
        self.core, self.seconds, self.calls = core, seconds, 0
        self.second_ended = 0.0

    def __getattr__(self, name: str) -> Any:
        return getattr(self.core, name)

    def simulate_many(self, scenarios, workers):
        self.calls += 1
        out = self.core.simulate_many(scenarios, workers)
        if self.calls == 2:
            time.sleep(self.seconds)
            self.second_ended = time.monotonic()
        return out


def test_a_finished_run_does_not_wait_for_a_long_call(monkeypatch: pytest.MonkeyPatch) -> None:
    slow = SlowSecondCall(runner._core, seconds=3.0)
    monkeypatch.setattr(runner, "_core", slow)
    store = MemoryStore(flush_seconds=0.3)
    pts = points(8)
    runner.run_points(pts, store, workers=1)
    assert slow.calls >= 2 and len(store.stored) == len(pts)
    first_write = store.writes[0][0]
    # The first call's runs are due 0.3 s after it ended: written during the 3 s call.
    assert first_write < slow.second_ended - 2.0, (store.writes, slow.second_ended)


def test_compare_killed_with_sigkill_resumes_without_loss(tmp_path: Path) -> None:
    args = [sys.executable, "-m", "multibots", "compare", "--strategies", "in-turn,nearest", "--robots", "1..4",
            "--tasks", "random:12", "--seeds", "60", "--workers", "1", "--no-plots", "--quiet"]
    p = subprocess.Popen(args + ["--out", "k"], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env={**os.environ})
    journal = tmp_path / "k" / "runs.jsonl"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and (not journal.exists() or journal.read_bytes().count(b"\n") < 20):
        time.sleep(0.01)
    p.send_signal(signal.SIGKILL)
    p.communicate()
    kept = {json.loads(line)["key"] for line in journal.read_text().splitlines() if line.endswith("}")}
    total = 2 * 4 * 60
    assert 0 < len(kept) < total, len(kept)
    again = subprocess.run(args + ["--out", "k"], cwd=tmp_path, capture_output=True, text=True)
    assert again.returncode == 0, again.stderr
    assert f"reused {len(kept)} of {total} runs" in again.stdout + again.stderr
    whole = subprocess.run(args + ["--out", "whole"], cwd=tmp_path, capture_output=True, text=True)
    assert whole.returncode == 0, whole.stderr
    for name in ("results.csv", "summary.csv"):
        assert (tmp_path / "k" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes(), name
