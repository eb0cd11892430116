"""``multibots paper``: the paper's 30 runs, its table (at most 100 columns), CSV and figures."""

from __future__ import annotations

import csv
import os

from multibots import Scenario, simulate


def test_paper_command_writes_table_csv_and_figures(cli, tmp_path):
    p = cli("paper", "--out", tmp_path / "out")
    assert p.returncode == 0, p.stderr
    # The three-way table: published, original rules, paper rules, and the match counts
    # measured against the authors' code (docs/original-rules.md).
    assert "original rules vs published: S equal in 28/30, C equal in 29/30, T within 3 s in 30/30" in p.stdout
    assert "paper rules    vs published: S equal in 10/30, C equal in 20/30" in p.stdout
    row = next(line for line in p.stdout.splitlines() if line.startswith("6  1 |"))
    # N = 6, group 1: published 59 s, S 7, C 0; the original rules 1167 ticks (59.3 s), 7, 0.
    assert row.split("|")[1].split() == ["59", "7", "0"]
    assert row.split("|")[2].split() == ["1167", "59.3", "7", "0"]
    rows = list(csv.DictReader((tmp_path / "out" / "results.csv").open()))
    assert list(rows[0]) == ["rules", "N", "group", "T", "T_seconds", "S", "C"]
    assert [sum(r["rules"] == k for r in rows) for k in ("published", "original", "paper")] == [30, 30, 30]
    assert {(int(r["N"]), int(r["group"])) for r in rows} == {(n, g) for n in range(1, 7) for g in range(1, 6)}
    first = next(r for r in rows if r["N"] == "1" and r["group"] == "1" and r["rules"] == "paper")
    assert int(first["T"]) == simulate(Scenario.paper(robots=1, goods=[11, 8, 39, 28, 53, 1, 69, 42, 79, 6])).T
    orig = next(r for r in rows if r["N"] == "1" and r["group"] == "1" and r["rules"] == "original")
    assert int(orig["T"]) == simulate(Scenario.paper(robots=1, goods=[11, 8, 39, 28, 53, 1, 69, 42, 79, 6],
                                                      rules="original")).T == 6383
    for folder in (tmp_path / "out", tmp_path / "out" / "paper-rules"):
        for stem in ("fig6_task_time", "fig7_collisions", "fig8_charging"):
            for ext in ("png", "svg"):
                assert (folder / f"{stem}.{ext}").stat().st_size > 1000
        # The published values are drawn over each figure.
        assert 'id="published-mean"' in (folder / "fig7_collisions.svg").read_text()


def test_paper_runs_one_rule_set_on_request(cli, tmp_path):
    p = cli("paper", "--out", tmp_path, "--rules", "original")
    assert p.returncode == 0, p.stderr
    assert "paper rules" not in p.stdout.splitlines()[0]
    assert not (tmp_path / "paper-rules").exists()
    bad = cli("paper", "--out", tmp_path, "--rules", "both-ish")
    assert bad.returncode == 2
    assert bad.stderr.strip() == "multibots: error: --rules = 'both-ish': expected both, original or paper"


def test_the_paper_table_fits_a_100_column_terminal(cli, tmp_path):
    p = cli("paper", "--out", tmp_path, "--margin", "8", env={**os.environ, "COLUMNS": "100"})
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) > 8
    for line in lines:
        if not line.startswith("wrote "):  # file paths are as long as the folder's name
            assert len(line) <= 100, line
    # One row per run: published, original rules, paper rules.
    six = next(line for line in lines if line.startswith("6  5 |"))
    assert six.count("|") == 4
