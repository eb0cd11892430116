"""``multibots compare`` on the command line: files, one-line errors, tables that fit 100
columns, and the run journal that reuses what has not changed."""

from __future__ import annotations

import csv
import os

import pytest

from multibots import Scenario, simulate


def _read(path):
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize(
    "args,why",
    [
        (["--robots", "3..1"], "--robots = '3..1': the range 3..1 is empty"),
        (["--robots", "1..7", "--rules", "original", "--strategies", "in-turn"],
         "robots = 7: the original rules run at most 6 robots"),
        (["--tasks", "random"], "--tasks = 'random': expected paper, scenario or random:K"),
        (["--strategies", "in-turn,bogus"], "--strategies = 'bogus': unknown strategy"),
        (["--strategies", "nope_pkg:X"], 'allocator = "nope_pkg:X": cannot import nope_pkg'),
        (["--tasks", "random:5", "--seeds", "0"], "--seeds = 0: must be 1 or more"),
        (["--workers", "-1"], "--workers = -1: must be 0 or more"),
    ],
)
def test_bad_options_are_one_line_with_exit_code_2(cli, args, why, tmp_path):
    r = cli("compare", "--quiet", "--out", str(tmp_path / "out"), *args)
    cli.assert_one_line_error(r, why)
    assert not (tmp_path / "out").exists()


def test_compare_writes_paired_results_summary_and_plots(cli, tmp_path):
    out = tmp_path / "cmp"
    r = cli("compare", "--strategies", "in-turn,hungarian,min-cost", "--robots", "1..2", "--tasks", "random:6",
             "--seeds", "3", "--out", str(out))
    assert r.returncode == 0, r.stderr
    rows = _read(out / "results.csv")
    assert len(rows) == 3 * 2 * 3
    assert {(x["strategy"], x["N"], x["list"]) for x in rows} == {
        (s, str(n), str(k)) for s in ("in-turn", "hungarian", "min-cost") for n in (1, 2) for k in (1, 2, 3)
    }
    # Paired: each (N, seed) is the same task list for every strategy; check one against the API.
    one = next(x for x in rows if x["strategy"] == "hungarian" and x["N"] == "2" and x["list"] == "3")
    s = Scenario.from_dict({"robots": 2, "tasks": {"random": 6, "seed": 3}})
    res = simulate(s, allocator="hungarian")
    assert (int(one["T"]), int(one["S"]), int(one["C"])) == (res.T, res.S, res.C)
    assert float(one["cost"]) == pytest.approx(0.25 * float(res.distance.sum()) + res.T + 50 * res.S)
    summary = _read(out / "summary.csv")
    keys = {(x["strategy"], x["N"], x["metric"]) for x in summary}
    for strategy in ("in-turn", "hungarian", "min-cost"):
        for n in ("1", "2", "all"):
            for metric in ("T", "S", "C", "cost"):
                assert (strategy, n, metric) in keys
    pooled = next(x for x in summary if x["strategy"] == "hungarian" and x["N"] == "all" and x["metric"] == "T")
    assert pooled["n"] == "6" and pooled["pairs"] == "6"
    assert float(pooled["ci_low"]) <= float(pooled["mean"]) <= float(pooled["ci_high"])
    assert pooled["p_ttest"] != "" and pooled["p_wilcoxon"] != ""
    base = next(x for x in summary if x["strategy"] == "in-turn" and x["N"] == "all" and x["metric"] == "T")
    assert base["pairs"] == "" and base["p_ttest"] == ""
    text = (out / "summary.txt").read_text()
    assert "T (steps): mean [95% CI]" in text and "against in-turn" in text and text.startswith("best on")
    assert "runs (3 arms x 2 fleet sizes x 3 task lists)" in r.stdout
    for stem in ("strategy_task_time", "strategy_collisions", "strategy_charging", "strategy_cost"):
        assert (out / f"{stem}.png").stat().st_size > 0 and (out / f"{stem}.svg").stat().st_size > 0
    # Deterministic: the same study writes the same files.
    again = tmp_path / "again"
    r2 = cli("compare", "--strategies", "in-turn,hungarian,min-cost", "--robots", "1..2", "--tasks", "random:6",
              "--seeds", "3", "--out", str(again), "--quiet", "--no-plots", "--workers", "1")
    assert r2.returncode == 0, r2.stderr
    assert (again / "results.csv").read_text() == (out / "results.csv").read_text()
    assert (again / "summary.csv").read_text() == (out / "summary.csv").read_text()




# --- tables that fit a terminal ------------------------------------------------------------


def test_the_printed_tables_fit_a_100_column_terminal(cli, tmp_path):
    # Every built-in, six fleet sizes, and a Python strategy named by a long path.
    strategies = "in-turn,nearest,hungarian,auction,energy-aware,min-cost,tests/strategies_example/closest.py:Closest"
    p = cli("compare", "--strategies", strategies, "--robots", "1..6", "--tasks", "paper", "--out", tmp_path,
            "--no-plots", "--quiet", env={**os.environ, "COLUMNS": "100"})
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    for line in lines:
        if not line.startswith("wrote "):  # file paths are as long as the folder's name
            assert len(line) <= 100, line
    text = (tmp_path / "summary.txt").read_text()
    assert max(len(line) for line in text.splitlines()) <= 100
    # Every strategy, every N and the pooled column are in the tables; a Python strategy
    # by its own name, not its file's path.
    for name in strategies.split(",")[:-1] + ["closest"]:
        assert name in text
    assert "closest.py" not in text
    for n in ["N=1", "N=6", "N=all"]:
        assert n in text


# --- the run journal ---------------------------------------------------------------------------

CLOSEST = """
import multibots


class Pick(multibots.Allocator):
    def allocate(self, view):
        lengths = view.route_lengths()
        out, taken = {}, set()
        for i, robot in enumerate(view.idle):
            free = [j for j in range(len(view.goods)) if j not in taken]
            if free:
                j = PICK(free, key=lambda j: (lengths[i, j], j))
                taken.add(j)
                out[int(robot)] = int(view.goods[j])
        return out
"""


def _study(cli, folder):
    p = cli("compare", "--strategies", "in-turn,mine.py:Pick", "--robots", "2..3", "--tasks", "random:6",
            "--seeds", "3", "--out", "out", "--no-plots", "--quiet", "--workers", "2", cwd=folder)
    assert p.returncode == 0, p.stderr
    rows = {(r["strategy"], r["N"], r["list"]): (r["T"], r["S"], r["C"]) for r in _read(folder / "out" / "results.csv")}
    return p.stdout, rows


def test_the_journal_reuses_unchanged_runs_and_reruns_an_edited_strategy(cli, tmp_path):
    mine = tmp_path / "mine.py"
    mine.write_text(CLOSEST.replace("PICK", "min"), encoding="utf-8")
    out, first = _study(cli, tmp_path)
    assert "reused" not in out
    assert len(first) == 2 * 2 * 3
    # Nothing changed: every run is reused, and the results are the same.
    out, again = _study(cli, tmp_path)
    assert "reused 12 of 12 runs from out/runs.jsonl" in out
    assert again == first
    # The strategy is edited (farthest goods first): its runs run again, in-turn's are reused.
    mine.write_text(CLOSEST.replace("PICK", "max"), encoding="utf-8")
    out, edited = _study(cli, tmp_path)
    assert "reused 6 of 12 runs from out/runs.jsonl" in out
    # A journal that answers for nothing says so too.
    (folder := tmp_path / "other").mkdir()
    mine2 = folder / "mine.py"
    mine2.write_text(CLOSEST.replace("PICK", "max"), encoding="utf-8")
    (folder / "out").mkdir()
    (folder / "out" / "runs.jsonl").write_text('{"key": "0", "result": {}}\n', encoding="utf-8")
    assert "reused 0 of 12 runs from out/runs.jsonl" in _study(cli, folder)[0]
    base = {k: v for k, v in first.items() if k[0] == "in-turn"}
    assert {k: v for k, v in edited.items() if k[0] == "in-turn"} == base
    # The class has no `name`: tables call it by its kebab-cased class name.
    changed = [k for k in first if k[0] == "pick" and first[k] != edited[k]]
    assert changed, "the edited strategy's results are new"
    # Each edited run is what the edited strategy gives now.
    import importlib.util

    spec = importlib.util.spec_from_file_location("mine_edited", mine)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    s = Scenario.from_dict({"robots": 3, "tasks": {"random": 6, "seed": 2}})
    want = simulate(s, allocator=module.Pick())
    assert edited[("pick", "3", "2")] == (str(want.T), str(want.S), str(want.C))
