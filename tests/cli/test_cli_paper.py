"""``multibots paper``: the paper's 30 runs, its table (at most 100 columns), CSV and figures."""

from __future__ import annotations

import csv
import os

from multibots import Scenario, simulate


def test_paper_command_writes_table_csv_and_figures(cli, tmp_path):
    p = cli("paper", "--out", tmp_path / "out")
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


def test_the_paper_table_fits_a_100_column_terminal(cli, tmp_path):
    p = cli("paper", "--out", tmp_path, "--margin", "8", env={**os.environ, "COLUMNS": "100"})
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) > 8
    for line in lines:
        if not line.startswith("wrote "):  # file paths are as long as the folder's name
            assert len(line) <= 100, line
    # One row per N, every group's T, S, C and the means on it.
    six = next(line for line in lines if line.startswith("  6 |"))
    assert six.count("|") == 6
