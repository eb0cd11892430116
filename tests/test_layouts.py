"""Layouts as data through Python: generate, check, run, errors (the command line's side is in
tests/cli/test_cli_layout.py)."""

from __future__ import annotations

import re

import pytest

from multibots import LayoutError, Scenario, ScenarioError, layout_json, simulate
from multibots.layouts import check_layout_file, generate_layout, parse_group_size


def test_generated_paper_layout_equals_the_paper_layout(tmp_path):
    path = tmp_path / "paper.toml"
    path.write_text(generate_layout(), encoding="utf-8")
    data = check_layout_file(path)
    paper = layout_json("paper")
    for key in ("nodes", "edges", "spurs", "cells", "departure", "unloading", "chargers", "bounds"):
        assert data[key] == paper[key], key
    # The worked example on the file layout: T = 726.
    s = Scenario.paper(robots=1, goods=[42], layout=str(path))
    assert simulate(s).T == 726


def test_bad_layout_files_are_named_errors(cli, tmp_path):
    good = generate_layout()
    cases = {
        "unknown field": (good.replace("cell_size", "cell_sise", 1), "unknown field `cell_sise`"),
        "broken graph": (good.replace('out = ["L"]', "out = []", 1), "not strongly connected"),
        "bad service point": (
            good.replace("service = [25.0, 75.0]", "service = [30.0, 75.0]", 1),
            "does not lie strictly inside its edge",
        ),
        "unknown node": (good.replace('departure = ["A"', 'departure = ["ZZ"', 1), 'departure[0]: unknown node "ZZ"'),
    }
    for name, (text, message) in cases.items():
        path = tmp_path / f"{name.replace(' ', '_')}.toml"
        path.write_text(text, encoding="utf-8")
        with pytest.raises((LayoutError, ScenarioError), match=re.escape(message)):
            check_layout_file(path)
        p = cli("layout", "check", str(path))
        assert p.returncode == 2 and message in p.stderr and p.stderr.count("\n") == 1, (name, p.stderr)
        # A scenario naming the file fails with the same message.
        with pytest.raises((LayoutError, ScenarioError), match=re.escape(message)):
            simulate(Scenario.from_dict({"layout": str(path), "tasks": [1]}))


def test_group_size_parser():
    assert parse_group_size("2x4") == (2, 4)
    assert parse_group_size("1X10") == (1, 10)
    with pytest.raises(ScenarioError, match="expected WxH"):
        parse_group_size("2")
