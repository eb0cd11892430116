"""Layouts as data through Python and the command line: generate, check, draw, run, errors."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from multibots import LayoutError, Scenario, ScenarioError, layout_json, simulate
from multibots.layouts import check_layout_file, generate_layout, parse_group_size

ROOT = Path(__file__).resolve().parent.parent


def cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "multibots", *args], capture_output=True, text=True, cwd=cwd, timeout=300)


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


def test_cli_generate_writes_a_checked_file(tmp_path):
    out = tmp_path / "wh.toml"
    p = cli("layout", "generate", "--group-rows", "3", "--group-cols", "4", "--group-size", "1x6", "--chargers", "2", "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert "wrote" in p.stdout and "20 crossings" in p.stdout
    data = check_layout_file(out)
    assert len(data["cells"]) == 3 * 4 * 6
    assert len(data["chargers"]) == 2
    assert not list(tmp_path.glob(".*.tmp")), "no temporary file left behind"
    p = cli("layout", "check", str(out))
    assert p.returncode == 0 and "ok" in p.stdout
    # The drawing command takes a layout file too.
    p = cli("layout", "--layout", str(out), "--json")
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["cells"] == data["cells"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--group-rows", "0"], "--group-rows = 0: must be at least 1"),
        (["--group-cols", "0"], "--group-cols = 0: must be at least 1"),
        (["--group-size", "3x4"], "--group-size = 3: must be 1 or 2"),
        (["--group-size", "2by4"], "--group-size = '2by4': expected WxH"),
        (["--chargers", "9"], "--chargers = 9: must be between 1 and 6"),
        (["--aisle", "0"], "--aisle = 0: must be greater than 0"),
    ],
)
def test_cli_generate_errors_are_one_line_exit_2(tmp_path, args, message):
    p = cli("layout", "generate", "--out", str(tmp_path / "x.toml"), *args)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert p.stderr.count("\n") == 1 and message in p.stderr, p.stderr
    assert not (tmp_path / "x.toml").exists()


def test_bad_layout_files_are_named_errors(tmp_path):
    good = generate_layout()
    cases = {
        "unknown field": (good.replace("cell_size", "cell_sise", 1), "unknown field `cell_sise`"),
        "broken graph": (good.replace('out = ["L"]', "out = []", 1), "not strongly connected"),
        "bad service point": (good.replace("service = [25.0, 75.0]", "service = [30.0, 75.0]", 1), "does not lie strictly inside its edge"),
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
