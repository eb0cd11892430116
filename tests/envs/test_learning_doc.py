"""docs/learning.md runs and lists every observation feature the engine has."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

pytest.importorskip("gymnasium")

import multibots.envs

DOC = Path(__file__).resolve().parents[2] / "docs" / "learning.md"


def test_the_python_example_runs():
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    assert blocks
    for code in blocks:
        exec(compile(code, str(DOC), "exec"), {})


def test_every_feature_is_documented():
    text = DOC.read_text()
    for part in ("robot", "fleet", "queue", "state_goods", "state_run"):
        for name, _low, _high in multibots.envs.FEATURES[part]:
            if not name.startswith("state_"):
                assert f"`{name}`" in text, f"{part}.{name}"
