"""``multibots compare``: option parsing, the paired runs, the statistics and the files."""

from __future__ import annotations

import csv
import math
import subprocess
import sys
from pathlib import Path

import pytest

from multibots import Scenario, simulate
from multibots.experiments import compare as study
from multibots.experiments.paper import run_paper

ROOT = Path(__file__).resolve().parents[1]


def _cli(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "multibots", *args], capture_output=True, text=True, cwd=cwd)


def _read(path):
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


# --- options -----------------------------------------------------------------------------


def test_option_parsing():
    assert study.parse_robots("1..6") == [1, 2, 3, 4, 5, 6]
    assert study.parse_robots("3") == [3]
    assert study.parse_robots("4,1,2,2") == [1, 2, 4]
    assert study.parse_robots("1..2,5") == [1, 2, 5]
    assert study.parse_tasks("paper") == study.TaskSpec("paper")
    assert study.parse_tasks("random:10") == study.TaskSpec("random", 10)
    assert study.parse_strategies("in-turn, hungarian") == ["in-turn", "hungarian"]
    assert study.parse_strategies("pkg.mod:Cls") == ["pkg.mod:Cls"]
    bad = {
        (study.parse_robots, "3..1"): "--robots = '3..1': the range 3..1 is empty",
        (study.parse_robots, "1-6"): "--robots = '1-6': expected a range such as 1..6",
        (study.parse_robots, "0..2"): "--robots = '0..2': fleet sizes must be 1 or more",
        (study.parse_tasks, "random:0"): "--tasks = 'random:0': expected paper or random:K",
        (study.parse_tasks, "papers"): "--tasks = 'papers': expected paper or random:K",
        (study.parse_strategies, "in-turn,greedy"): "--strategies = 'greedy': unknown strategy (built-ins: in-turn, nearest",
        (study.parse_strategies, "in-turn,in-turn"): "--strategies = 'in-turn': named twice",
        (study.parse_strategies, "in-turn,"): "expected comma-separated strategy names",
    }
    for (fn, arg), why in bad.items():
        with pytest.raises(study.StudyInputError) as e:
            fn(arg)
        assert why in str(e.value), str(e.value)


@pytest.mark.parametrize(
    "args,why",
    [
        (["--robots", "3..1"], "--robots = '3..1': the range 3..1 is empty"),
        (["--robots", "1..7"], "robots = 7: more robots than start nodes (6)"),
        (["--tasks", "random"], "--tasks = 'random': expected paper or random:K"),
        (["--strategies", "in-turn,bogus"], "--strategies = 'bogus': unknown strategy"),
        (["--strategies", "nope_pkg:X"], 'allocator = "nope_pkg:X": cannot import nope_pkg'),
        (["--tasks", "random:5", "--seeds", "0"], "--seeds = 0: must be 1 or more"),
        (["--workers", "-1"], "--workers = -1: must be 0 or more"),
    ],
)
def test_bad_options_are_one_line_with_exit_code_2(args, why, tmp_path):
    r = _cli("compare", "--quiet", "--out", str(tmp_path / "out"), *args)
    assert r.returncode == 2, r.stderr
    assert why in r.stderr and r.stderr.strip().count("\n") == 0 and "Traceback" not in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


# --- the study ---------------------------------------------------------------------------


def test_compare_writes_paired_results_summary_and_plots(tmp_path):
    out = tmp_path / "cmp"
    r = _cli("compare", "--strategies", "in-turn,hungarian,min-cost", "--robots", "1..2", "--tasks", "random:6",
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
    assert "runs (3 strategies x 2 fleet sizes x 3 task lists)" in r.stdout
    for stem in ("strategy_task_time", "strategy_collisions", "strategy_charging", "strategy_cost"):
        assert (out / f"{stem}.png").stat().st_size > 0 and (out / f"{stem}.svg").stat().st_size > 0
    # Deterministic: the same study writes the same files.
    again = tmp_path / "again"
    r2 = _cli("compare", "--strategies", "in-turn,hungarian,min-cost", "--robots", "1..2", "--tasks", "random:6",
              "--seeds", "3", "--out", str(again), "--quiet", "--no-plots", "--workers", "1")
    assert r2.returncode == 0, r2.stderr
    assert (again / "results.csv").read_text() == (out / "results.csv").read_text()
    assert (again / "summary.csv").read_text() == (out / "summary.csv").read_text()


def test_in_turn_rows_on_the_paper_lists_are_the_paper_experiment():
    rows = study.run_study(["in-turn", "nearest"], [1, 2, 3, 4, 5, 6], study.TaskSpec("paper"))
    paper, _ = run_paper()
    mine = {(r["N"], r["list"]): (r["T"], r["S"], r["C"]) for r in rows if r["strategy"] == "in-turn"}
    assert mine == {(p.N, p.group): (p.T, p.S, p.C) for p in paper}
    assert all(r["tasks"] == "paper" for r in rows)


def test_python_strategies_run_in_processes_with_the_same_results():
    rows = study.run_study(["strategies_example.closest:Closest", "in-turn"], [1, 2], study.TaskSpec("random", 5), seeds=2, workers=2)
    assert len(rows) == 8
    for r in rows:
        if r["strategy"] == "strategies_example.closest:Closest":
            s = Scenario.from_dict({"robots": r["N"], "tasks": {"random": 5, "seed": r["list"]}})
            from strategies_example.closest import Closest

            want = simulate(s, allocator=Closest())
            assert (r["T"], r["S"], r["C"]) == (want.T, want.S, want.C)


def test_base_scenario_fields_apply_to_every_run(tmp_path):
    base = Scenario.from_dict({"tasks": [1], "cost": {"distance": 0.0, "time": 2.0, "collision": 0.0}})
    rows = study.run_study(["in-turn"], [2], study.TaskSpec("random", 4), seeds=2, base=base)
    assert all(r["cost"] == 2.0 * r["T"] for r in rows)


# --- the statistics ----------------------------------------------------------------------


def _rows(values):
    """Rows for strategy -> list of T values (one per list), N = 1, S and C zero."""
    return [
        {"strategy": s, "N": 1, "tasks": "x", "list": k + 1, "T": t, "S": 0, "C": 0, "distance": 0.0, "cost": t,
         "outcome": "complete" if t is not None else "incomplete", "delivered": 1, "goods_total": 1}
        for s, ts in values.items() for k, t in enumerate(ts)
    ]


def test_summary_statistics_on_known_numbers():
    summary = study.summarize(_rows({"in-turn": [10, 12, 14, 16], "fast": [8, 10, 12, 14], "same": [10, 12, 14, 16]}))
    get = {(r["strategy"], r["N"], r["metric"]): r for r in summary}
    base = get[("in-turn", 1, "T")]
    assert base["mean"] == 13.0 and base["sd"] == pytest.approx(math.sqrt(20 / 3))
    # t(0.975, 3) = 3.182446305...
    half = 3.182446305284263 * math.sqrt(20 / 3) / 2
    assert base["ci_low"] == pytest.approx(13 - half) and base["ci_high"] == pytest.approx(13 + half)
    fast = get[("fast", 1, "T")]
    assert fast["diff_vs_in_turn"] == -2.0 and fast["rel_diff_pct"] == pytest.approx(-200 / 13)
    assert fast["p_ttest"] == 0.0  # a constant difference
    assert fast["pairs"] == 4
    assert fast["p_wilcoxon"] == pytest.approx(0.125)  # 4 negative differences: 2 / 2^4
    same = get[("same", 1, "T")]
    assert same["diff_vs_in_turn"] == 0.0 and same["p_ttest"] == 1.0 and same["p_wilcoxon"] == 1.0
    assert study.headline(summary, "T")["strategy"] == "fast"


def test_incomplete_runs_are_left_out_of_means_and_pairs():
    summary = study.summarize(_rows({"in-turn": [10, 12, None, 16], "other": [11, None, 13, 15]}))
    get = {(r["strategy"], r["N"], r["metric"]): r for r in summary}
    assert get[("in-turn", 1, "T")]["n"] == 3 and get[("other", 1, "T")]["n"] == 3
    assert get[("other", 1, "T")]["pairs"] == 2
    assert get[("other", 1, "S")]["pairs"] == 4  # S exists for incomplete runs too
    text = study.format_summary(summary, "x")
    assert "best on T (steps)" in text
