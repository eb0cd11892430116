"""The command line: quick runs, files, the paper experiment, and every bad input of issue 2."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

from multibots import Scenario, simulate

from geometry import formula_t


def cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "multibots", *args], capture_output=True, text=True, cwd=cwd, timeout=300)


def test_quick_run_json():
    p = cli("run", "--robots", "3", "--goods", "11,8,39,28,53,1,69,42,79,6", "--json")
    assert p.returncode == 0, p.stderr
    lines = p.stdout.strip().splitlines()
    assert len(lines) == 1
    out = json.loads(lines[0])
    expected = simulate(Scenario.paper(robots=3, goods=[11, 8, 39, 28, 53, 1, 69, 42, 79, 6]))
    assert {k: out[k] for k in ("T", "S", "C", "outcome", "steps", "delivered")} == {
        "T": expected.T, "S": expected.S, "C": expected.C, "outcome": "complete", "steps": expected.T, "delivered": 10,
    }


def test_quick_run_flags(tmp_path):
    p = cli("run", "--robots", "1", "--goods", "42", "--starts", "C", "--unload", "O", "--margin", "8", "--step-limit", "5000", "--json", "--record", str(tmp_path / "r.mbr"))
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["T"] == formula_t(42, "C", "O")
    assert (tmp_path / "r.mbr").stat().st_size > 0


def test_run_scenario_file_and_table(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text(Scenario.paper(robots=1, goods=[42]).to_toml())
    p = cli("run", str(f))
    assert p.returncode == 0, p.stderr
    assert "T (steps)  726" in p.stdout
    # Flags override the file.
    p = cli("run", str(f), "--goods", "11", "--json")
    assert json.loads(p.stdout)["T"] == formula_t(11)


def test_paper_command_writes_table_csv_and_figures(tmp_path):
    p = cli("paper", "--out", str(tmp_path / "out"))
    assert p.returncode == 0, p.stderr
    assert "group 5" in p.stdout
    rows = list(csv.DictReader((tmp_path / "out" / "results.csv").open()))
    assert len(rows) == 30 and list(rows[0]) == ["N", "group", "T", "S", "C"]
    assert {(int(r["N"]), int(r["group"])) for r in rows} == {(n, g) for n in range(1, 7) for g in range(1, 6)}
    first = next(r for r in rows if r["N"] == "1" and r["group"] == "1")
    assert int(first["T"]) == simulate(Scenario.paper(robots=1, goods=[11, 8, 39, 28, 53, 1, 69, 42, 79, 6])).T
    for stem in ("fig6_task_time", "fig7_collisions", "fig8_charging"):
        for ext in ("png", "svg"):
            assert (tmp_path / "out" / f"{stem}.{ext}").stat().st_size > 1000


def test_layout_command(tmp_path):
    for name in ("layout.png", "layout.svg"):
        p = cli("layout", "--out", str(tmp_path / name))
        assert p.returncode == 0, p.stderr
        assert (tmp_path / name).stat().st_size > 1000
    p = cli("layout", "--json")
    assert len(json.loads(p.stdout)["cells"]) == 80


@pytest.mark.parametrize("command", [[], ["run"], ["paper"], ["layout"], ["view"], ["render"]])
def test_help_everywhere(command):
    p = cli(*command, "--help")
    assert p.returncode == 0 and "Usage" in p.stdout


# Every bad input of issue 2, point 4: (TOML text or None for a CLI-only case, expected fragments).
BAD_FILES = {
    "unknown key": ("tasks = [1]\nrobts = 3\n", ["unknown field `robts`"]),
    "unknown nested key": ("tasks = [1]\n[robot]\nsped = 4.0\n", ["robot", "unknown field `sped`"]),
    "wrong type": ("tasks = [1]\nrobots = \"three\"\n", ["robots", "\"three\""]),
    "wrong type nested": ("tasks = [1]\n[robot]\nspeed = \"fast\"\n", ["robot.speed", "\"fast\""]),
    "zero speed": ("tasks = [1]\n[robot]\nspeed = 0.0\n", ["robot.speed = 0"]),
    "negative speed": ("tasks = [1]\n[robot]\nspeed = -4.0\n", ["robot.speed = -4"]),
    "zero radius": ("tasks = [1]\n[robot]\nradius = 0.0\n", ["robot.radius = 0"]),
    "negative radius": ("tasks = [1]\n[robot]\nradius = -1.0\n", ["robot.radius = -1"]),
    "zero consumption": ("tasks = [1]\n[robot]\nconsumption = 0.0\n", ["robot.consumption = 0"]),
    "negative charge rate": ("tasks = [1]\n[robot]\ncharge_rate = -0.05\n", ["robot.charge_rate = -0.05"]),
    "zero loading": ("tasks = [1]\n[dwell]\nloading = 0\n", ["dwell.loading = 0"]),
    "negative unloading": ("tasks = [1]\n[dwell]\nunloading = -20\n", ["dwell.unloading", "-20"]),
    "zero step limit": ("tasks = [1]\nstep_limit = 0\n", ["step_limit = 0"]),
    "negative step limit": ("tasks = [1]\nstep_limit = -5\n", ["step_limit", "-5"]),
    "threshold at full": ("tasks = [1]\n[robot]\nthreshold = 10.0\n", ["robot.threshold = 10"]),
    "threshold above full": ("tasks = [1]\n[robot]\nthreshold = 12.0\nenergy_full = 10.0\n", ["robot.threshold = 12"]),
    "cell out of range": ("tasks = [1, 80]\n", ["tasks[1] = 80", "out of range"]),
    "negative cell": ("tasks = [-1]\n", ["tasks[0] = -1"]),
    "repeated cell": ("tasks = [5, 7, 5]\n", ["tasks[2] = 5", "twice"]),
    "empty task list": ("tasks = []\n", ["tasks", "empty"]),
    "missing tasks": ("robots = 2\n", ["missing field `tasks`"]),
    "unknown start": ("tasks = [1]\nrobots = 2\nstarts = [\"A\", \"Z\"]\n", ["starts[1] = \"Z\"", "unknown node"]),
    "unknown unload": ("tasks = [1]\nunload = \"Q2\"\n", ["unload = \"Q2\"", "unknown node"]),
    "too many robots": ("tasks = [1]\nrobots = 7\n", ["robots = 7", "more robots than start nodes"]),
    "start not departure": ("tasks = [1]\nrobots = 2\nstarts = [\"A\", \"M\"]\n", ["starts[1] = \"M\"", "departure zone"]),
    "repeated start": ("tasks = [1]\nrobots = 2\nstarts = [\"B\", \"B\"]\n", ["starts[1] = \"B\"", "distinct"]),
    "unload not unloading": ("tasks = [1]\nunload = \"A\"\n", ["unload = \"A\"", "unloading zone"]),
    "malformed toml": ("tasks = [1, 2\n", ["s.toml", "line"]),
    "unknown layout": ("tasks = [1]\nlayout = \"moon\"\n", ["layout = \"moon\""]),
}


def _assert_one_line_error(p: subprocess.CompletedProcess[str], fragments: list[str]) -> None:
    assert p.returncode == 2, (p.returncode, p.stdout, p.stderr)
    err = p.stderr.strip()
    assert len(err.splitlines()) == 1, err
    assert "Traceback" not in p.stderr
    for frag in fragments:
        assert frag in err, (frag, err)


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_scenario_files(tmp_path, case):
    text, fragments = BAD_FILES[case]
    f = tmp_path / "s.toml"
    f.write_text(text)
    _assert_one_line_error(cli("run", str(f)), fragments)


def test_missing_unreadable_and_directory_files(tmp_path):
    _assert_one_line_error(cli("run", str(tmp_path / "nope.toml")), ["nope.toml", "no such file"])
    binary = tmp_path / "b.toml"
    binary.write_bytes(b"\xff\xfe\x00tasks")
    _assert_one_line_error(cli("run", str(binary)), ["b.toml", "UTF-8"])
    _assert_one_line_error(cli("run", str(tmp_path)), ["is a directory"])


BAD_FLAGS = {
    "goods not numbers": (["--goods", "11,x"], ["--goods", "11,x"]),
    "goods empty": (["--goods", ","], ["--goods"]),
    "robots zero": (["--robots", "0", "--goods", "1"], ["robots = 0"]),
    "robots not int": (["--robots", "two", "--goods", "1"], ["two"]),
    "negative margin": (["--goods", "1", "--margin", "-1"], ["collision.margin = -1"]),
    "bad start": (["--robots", "1", "--goods", "1", "--starts", "M"], ["starts[0] = \"M\""]),
    "bad unload": (["--goods", "1", "--unload", "B"], ["unload = \"B\""]),
    "cell out of range": (["--goods", "1,99"], ["tasks[1] = 99"]),
    "zero step limit": (["--goods", "1", "--step-limit", "0"], ["step_limit = 0"]),
    "nothing to run": ([], ["--goods"]),
    "unknown option": (["--bogus"], ["--bogus"]),
    "allocator that is no allocator": (["--goods", "1", "--allocator", "os:getcwd"], ["allocator = \"os:getcwd\""]),
    "unknown allocator": (["--goods", "1", "--allocator", "fastest"], ["allocator = \"fastest\""]),
    "margin not finite": (["--goods", "1", "--margin", "nan"], ["--margin", "nan"]),
}


@pytest.mark.parametrize("case", sorted(BAD_FLAGS))
def test_bad_flags(case):
    args, fragments = BAD_FLAGS[case]
    _assert_one_line_error(cli("run", *args), fragments)


def test_bad_layout_output(tmp_path):
    _assert_one_line_error(cli("layout", "--out", str(tmp_path / "x.txt")), ["--out", "x.txt"])
