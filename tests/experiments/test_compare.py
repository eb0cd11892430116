"""The study behind ``multibots compare``: option parsing, the paired runs and the statistics
(the command itself: tests/cli/test_cli_compare.py)."""

from __future__ import annotations

import math

import pytest

from multibots import Scenario, simulate
from multibots.exceptions import InputError
from multibots.experiments import compare as study
from multibots.experiments.paper import run_paper

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
        (study.parse_tasks, "random:0"): "--tasks = 'random:0': expected paper, scenario or random:K",
        (study.parse_tasks, "papers"): "--tasks = 'papers': expected paper, scenario or random:K",
        (
            study.parse_strategies,
            "in-turn,greedy",
        ): "--strategies = 'greedy': unknown strategy (built-ins: in-turn, nearest",
        (study.parse_strategies, "in-turn,in-turn"): "--strategies = 'in-turn': named twice",
        (study.parse_strategies, "in-turn,"): "expected comma-separated strategy names",
    }
    for (fn, arg), why in bad.items():
        with pytest.raises(InputError) as e:
            fn(arg)
        assert why in str(e.value), str(e.value)


# --- the study ---------------------------------------------------------------------------


def test_in_turn_rows_on_the_paper_lists_are_the_paper_experiment():
    rows = study.run_study(["in-turn", "nearest"], [1, 2, 3, 4, 5, 6], study.TaskSpec("paper"))
    paper, _ = run_paper()
    mine = {(r["N"], r["list"]): (r["T"], r["S"], r["C"]) for r in rows if r["strategy"] == "in-turn"}
    assert mine == {(p.N, p.group): (p.T, p.S, p.C) for p in paper}
    assert all(r["tasks"] == "paper" for r in rows)


def test_python_strategies_run_in_processes_with_the_same_results():
    rows = study.run_study(
        ["strategies_example.closest:Closest", "in-turn"], [1, 2], study.TaskSpec("random", 5), seeds=2, workers=2
    )
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


def test_confidence_intervals_of_counts_never_go_below_zero():
    rows = _rows({"in-turn": [10, 12, 14, 16], "other": [11, 12, 13, 15]})
    for r, s in zip(rows, [0, 0, 0, 3, 0, 1, 0, 0]):
        r["S"] = s
    summary = study.summarize(rows)
    get = {(r["strategy"], r["N"], r["metric"]): r for r in summary}
    s = get[("in-turn", 1, "S")]
    # The t interval would be 0.75 ± 3.18 · 1.5 / 2, far below 0: it is clipped at 0.
    assert s["mean"] == 0.75 and s["ci_low"] == 0.0
    assert s["ci_high"] == pytest.approx(0.75 + 3.182446305284263 * 1.5 / 2)
    for r in summary:
        assert r["ci_low"] is None or r["ci_low"] >= 0, r


def test_a_real_study_has_no_negative_interval():
    rows = study.run_study(list(study.BUILT_INS), [1, 2, 3], study.TaskSpec("paper"))
    for r in study.summarize(rows):
        assert r["ci_low"] is None or 0 <= r["ci_low"] <= r["mean"] <= r["ci_high"], r


def test_the_summary_says_when_the_wilcoxon_test_cannot_reach_significance():
    from multibots import stats

    assert stats.wilcoxon_floor(5) == 0.0625 and stats.pairs_to_reach(0.05) == 6
    assert stats.wilcoxon([-1, -2, -3, -4, -5]) == stats.wilcoxon_floor(5)  # the floor is reached
    few = study.format_summary(study.summarize(_rows({"in-turn": [10, 12, 14, 16, 18], "fast": [8, 9, 12, 13, 15]})))
    assert "with 5 pairs the Wilcoxon test cannot give p below 0.0625" in " ".join(few.split())
    enough = study.summarize(_rows({"in-turn": [10, 12, 14, 16, 18, 20], "fast": [8, 9, 12, 13, 15, 16]}))
    assert "cannot give p below" not in study.format_summary(enough)
