"""The run journal's key: everything that changes a run's result, and nothing else."""

from __future__ import annotations

import hashlib
from pathlib import Path

import multibots
from multibots import Scenario, _core
from multibots.experiments import compare as study
from multibots.runs import Journal, engine_id, run_key, strategy_id

STRATEGY = """
import multibots


class Mine(multibots.Allocator):
    def allocate(self, view):
        return list(zip(view.idle.tolist(), view.goods.tolist()))
"""


def test_the_engine_id_is_the_version_and_the_extension_s_bytes():
    digest = hashlib.sha256(Path(_core.__file__).read_bytes()).hexdigest()
    assert engine_id() == f"{multibots.__version__}+{digest[:16]}"


def test_a_python_strategy_is_known_by_its_source(tmp_path):
    path = tmp_path / "mine.py"
    path.write_text(STRATEGY, encoding="utf-8")
    name = f"{path}:Mine"
    first = strategy_id(name)
    assert first == "python:" + hashlib.sha256(STRATEGY.encode()).hexdigest()
    path.write_text(STRATEGY + "\n# edited\n", encoding="utf-8")
    assert strategy_id(name) != first
    assert strategy_id("hungarian") == "builtin:hungarian"


def test_the_key_changes_with_each_of_its_parts():
    s = Scenario.paper(robots=2, goods=[11, 8])
    key = run_key(s, "builtin:in-turn", "0.1.0+abc")
    assert run_key(Scenario.paper(robots=2, goods=[11, 8]), "builtin:in-turn", "0.1.0+abc") == key
    assert run_key(s.replace(robots=3), "builtin:in-turn", "0.1.0+abc") != key
    assert run_key(s, "builtin:nearest", "0.1.0+abc") != key
    assert run_key(s, "builtin:in-turn", "0.1.0+def") != key


def test_the_study_reports_what_it_reused(tmp_path):
    journal = tmp_path / "runs.jsonl"
    seen = []
    args = (["in-turn", "nearest"], [1, 2], study.TaskSpec("random", 3), 2)
    first = study.run_study(*args, journal=journal, reused=lambda k, n: seen.append((k, n)))
    assert seen == [(0, 8)]
    again = study.run_study(*args, journal=journal, reused=lambda k, n: seen.append((k, n)))
    assert seen[-1] == (8, 8) and again == first
    # An entry written under another engine's key is not read back for this one.
    book = Journal(journal)
    assert len(book.done) == 8 and book.existed
    stale = tmp_path / "stale.jsonl"
    stale.write_text("".join(
        line.replace(line[8:72], "0" * 64) + "\n" for line in journal.read_text().splitlines()
    ))
    seen.clear()
    study.run_study(*args, journal=stale, reused=lambda k, n: seen.append((k, n)))
    assert seen == [(0, 8)]
