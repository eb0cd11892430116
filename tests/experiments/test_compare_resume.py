"""A comparison study that is killed loses no finished run, and resumes where it stopped."""

from __future__ import annotations

import json

import pytest

from multibots.experiments import compare as study


def _study(journal, progress=None):
    spec = study.parse_tasks("random:4")
    return study.run_study(
        ["in-turn", "nearest"], [1, 2, 3], spec, seeds=4, workers=2, progress=progress, journal=journal
    )


def test_an_interrupted_study_resumes_from_its_journal(tmp_path):
    journal = tmp_path / "runs.jsonl"
    full = _study(None)
    assert len(full) == 2 * 3 * 4

    ticks = []

    def stop_after_first_batch(k):
        ticks.append(k)
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        _study(journal, progress=stop_after_first_batch)
    kept = journal.read_text().splitlines()
    assert len(kept) == ticks[0] > 0, "the finished batch is on disk"

    # A kill can cut the last line short: it is ignored.
    with journal.open("a") as f:
        f.write('{"key": "abc", "res')

    resumed = []
    rows = _study(journal, progress=resumed.append)
    assert resumed[0] == len(kept), "runs already in the journal are not run again"
    assert sum(resumed) == len(full)
    assert rows == full

    # Every run is now in the journal: a third call runs nothing.
    again = []
    assert _study(journal, progress=again.append) == full
    assert again == [len(full)]
    keys = {json.loads(line)["key"] for line in journal.read_text().splitlines() if line.endswith("}")}
    assert len(keys) == len(full)
