"""A new user's first hour (issue 42): defaults that work past the paper's size, a bottleneck
that is the real one, counts of the runs a mean leaves out, and exit codes that mean what the
README says."""

from __future__ import annotations

import pytest

import multibots
from multibots.experiments.summary import format_summary, summarize
from multibots.result import bottleneck_line

#: The issue's warehouse: 6 × 10 groups, 12 chargers, 200 robots, lifelong orders at 0.2 a
#: step, everything else left at its default.
TWO_HUNDRED = """\
robots = 200
tasks = []
[layout_generate]
group_rows = 6
group_cols = 10
chargers = 12
[orders]
rate = 0.2
"""


@pytest.fixture
def two_hundred(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(TWO_HUNDRED)
    return path


def test_a_fleet_past_the_paper_size_runs_on_its_defaults_and_is_told_why_it_strands(cli, two_hundred):
    p = cli("run", two_hundred)
    # It runs (no refusal for placement or chargers), and ends stranded: exit code 3.
    assert p.returncode == 3, p.stderr
    warning = [line for line in p.stderr.splitlines() if line.startswith("multibots: warning: ")]
    assert len(warning) == 1
    assert "200 robots sharing 12 chargers" in warning[0] and "at least 43 chargers" in warning[0]
    out = p.stdout
    # Spread, reserved lanes: no robot drives through another.
    assert "contacts     0 (" in out
    # Stranded out of energy: said so, and no resource named as the limit.
    assert "bottleneck   stranded: energy" in out
    assert "unloading" not in out.split("bottleneck")[1].splitlines()[0]


def test_the_defaults_resolve_to_the_paper_for_the_paper_and_to_what_scales_beyond():
    paper = multibots.Scenario.paper(robots=6).resolved().to_dict()
    assert paper.get("placement", "departure") == "departure"
    assert paper["traffic"] == "wait" and paper["charging"]["policy"] == "threshold"
    assert paper["charging"]["chargers"] == "home" and paper["unload"] in ("first", "M")
    big = multibots.Scenario.from_dict({"robots": 200, "tasks": [], "orders": {"rate": 0.2},
                                        "layout_generate": {"group_rows": 6, "group_cols": 10, "chargers": 12}})
    r = big.resolved().to_dict()
    assert (r["placement"], r["traffic"], r["unload"]) == ("spread", "reserve", "nearest")
    assert r["charging"]["chargers"] == "shared" and r["charging"]["policy"] == "staggered"
    # A fleet with enough chargers is not warned about.
    assert multibots.Scenario.from_toml("scenarios/warehouse-1000.toml").warnings() == []


def test_the_bottleneck_line_says_the_truth_when_no_resource_is_named():
    assert bottleneck_line(None, "stranded").startswith("stranded: energy")
    assert bottleneck_line(None, "horizon").startswith("no saturated resource")
    # The paper's runs: nothing saturates.
    result = multibots.simulate(multibots.Scenario.paper(robots=3))
    assert result.bottleneck is None and result.resources


@pytest.mark.parametrize("scenario, code", [("scenarios/paper.toml", 0), ("TWO_HUNDRED", 3)])
def test_a_reader_that_leaves_does_not_turn_the_exit_code_into_an_internal_error(cli, two_hundred, scenario, code):
    # `multibots run ... | head -1`: the reader is gone before the command writes.
    path = two_hundred if scenario == "TWO_HUNDRED" else scenario
    proc = cli.popen("run", path)
    proc.stdout.close()
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == code, err
    assert "internal error" not in err and "Traceback" not in err


def test_a_mean_over_the_runs_that_completed_says_how_many_it_left_out():
    rows = []
    for li, (outcome, t) in enumerate([("complete", 100), ("stranded", None), ("stranded", None)], start=1):
        rows.append({"strategy": "in-turn", "N": 2, "list": li, "T": t, "S": 1, "C": 0,
                     "cost": None if t is None else 5, "outcome": outcome})
    summary = summarize(rows)
    t_row = next(r for r in summary if r["metric"] == "T" and r["N"] == 2)
    assert (t_row["n"], t_row["runs"], t_row["not_complete"], t_row["mean"]) == (1, 3, 2, 100)
    text = format_summary(summary)
    assert "runs that did not complete" in text and "2 of 3" in text


def test_a_strategy_plot_marks_the_points_whose_mean_left_runs_out(tmp_path):
    from multibots.plots import draw_strategy_comparison

    rows = [{"strategy": "in-turn", "N": n, "metric": "T", "n": k, "runs": 3, "not_complete": 3 - k,
             "mean": 100.0 * n, "ci_low": 90.0 * n, "ci_high": 110.0 * n} for n, k in ((1, 3), (2, 1))]
    svg = next(p for p in draw_strategy_comparison(rows, tmp_path) if p.suffix == ".svg").read_text()
    assert svg.count('id="strategy-short-0"') == 1  # N = 2 only
    assert "2/3 not complete" in svg


def test_one_fleet_size_still_shows_its_interval(tmp_path):
    from multibots.plots import draw_strategy_comparison

    rows = [{"strategy": s, "N": 4, "metric": "T", "n": 5, "runs": 5, "not_complete": 0, "mean": m,
             "ci_low": m - 10, "ci_high": m + 10} for s, m in (("in-turn", 100.0), ("nearest", 90.0))]
    svg = next(p for p in draw_strategy_comparison(rows, tmp_path) if p.suffix == ".svg").read_text()
    # Whiskers for each strategy, not bare dots under a title that promises intervals.
    assert 'id="strategy-whiskers-0"' in svg and 'id="strategy-whiskers-1"' in svg
