"""`multibots capacity`: the rate it finds is one the warehouse carries (the backlog stays
bounded a fifth below it and grows a quarter above it, checked by runs of their own, on seeds
the search never saw), the smallest fleet for a rate, and the command's output and errors."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import multibots as mb
from multibots import Scenario
from multibots.sweeps.capacity import fleet_for

pytest.importorskip("polars")

# A warehouse nobody tuned for: 120 robots, a generated layout unlike the shipped ones.
BASE = {
    "robots": 120, "tasks": [], "placement": "spread", "unload": "nearest", "allocator": "hungarian",
    "layout_generate": {"group_rows": 6, "group_cols": 10, "group_width": 2, "group_height": 6, "chargers": 10,
                        "unloading_rows": 2},
    "charging": {"chargers": "shared"}, "robot": {"consumption": 0.00002},
    "orders": {"rate": 0.05, "horizon": 6000, "restock": 100, "seed": 1},
}


def backlog_at(scenario: Scenario, steps: list[int]) -> list[int]:
    """Orders still open (ordered less delivered) after each of ``steps``, from a run of its own."""
    sim = mb.Simulation(scenario)
    out = []
    for s in steps:
        sim.step(s - sim.t)
        out.append(sim.goods_total - sim.delivered)
    return out


def test_the_rate_found_is_carried_below_it_and_overflows_above_it(tmp_path):
    base = Scenario.from_dict(BASE)
    answer = mb.capacity(base, out=tmp_path, seeds=3)
    r = answer.sustainable_rate
    assert r is not None and answer.knee is not None and answer.knee.rate == r
    # The levels on either side of the knee bracket it within the precision asked for.
    above = [lv for lv in answer.curve if lv.rate > r]
    assert above and not above[0].sustained(answer.served) and above[0].rate / r <= 1.05 + 1e-9
    for seed in (101, 102, 103):
        for share, grows in ((0.8, False), (1.25, True)):
            s = base.replace(orders={"rate": share * r, "horizon": 12_000, "seed": seed})
            b = backlog_at(s, [4000, 12_000])
            demand = share * r * 8000
            if grows:
                assert b[1] - b[0] > 0.08 * demand, (seed, share, b, demand)
            else:
                assert b[1] - b[0] < 0.03 * demand, (seed, share, b, demand)


def test_the_smallest_fleet_for_a_rate_sustains_it_and_one_robot_fewer_does_not(tmp_path):
    answer = fleet_for(Scenario.from_dict(BASE), 0.08, out=tmp_path, seeds=2)
    n = answer.robots
    assert n is not None and answer.rate == 0.08
    by_size = {lv.robots: lv for lv in answer.curve}
    assert by_size[n].sustained(answer.served)
    assert n == 1 or not by_size[n - 1].sustained(answer.served)


def _cli(*args: str, cwd) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "multibots", "capacity", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


def test_the_command_prints_one_json_object_with_the_rate_and_the_curve(tmp_path):
    path = tmp_path / "w.toml"
    path.write_text(Scenario.from_dict(BASE).to_toml())
    p = _cli(str(path), "--json", "--seeds", "2", "--out", str(tmp_path / "out"), cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["question"] == "rate" and d["sustainable_rate"] > 0
    rates = [lv["rate"] for lv in d["curve"]]
    assert rates == sorted(rates) and d["sustainable_rate"] in rates
    knee = next(lv for lv in d["curve"] if lv["rate"] == d["sustainable_rate"])
    assert knee["sustained"] and knee["served"] >= d["served"]
    # The table, and the figure beside the store.
    p = _cli(str(path), "--seeds", "2", "--out", str(tmp_path / "out"), "--quiet", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert "sustainable rate:" in p.stdout and (tmp_path / "out" / "capacity.png").stat().st_size > 0


@pytest.mark.parametrize("args,why", [
    (["--seeds", "0"], "--seeds = 0: must be at least 1"),
    (["--served", "1.5"], "--served = 1.5: must be above 0 and at most 1"),
    (["--robots-for", "nan"], "--robots-for = nan: must be a finite number"),
    (["--horizon", "500"], "--horizon = 500: at least 2000 steps"),
    (["--robots", "0"], "--robots = 0: must be at least 1"),
    (["--robots", "x"], "--robots = 'x': not an integer"),
    (["--allocators", "nearest,closest"], "--allocators = 'closest': unknown; expected one of in-turn"),
    (["--traffic", "wait,honk"], "--traffic = 'honk': unknown; expected one of auto, wait, gate, reserve"),
    (["--traffic", "wait,wait"], "--traffic = 'wait': named twice"),
    (["--allocators", "hungarain"], "(did you mean hungarian?)"),
])
def test_bad_flags_get_one_line_naming_the_flag(tmp_path, args, why):
    # Unknown strategy or policy names list the known ones.
    path = tmp_path / "w.toml"
    path.write_text(Scenario.from_dict(BASE).to_toml())
    p = _cli(str(path), *args, "--out", str(tmp_path / "out"), cwd=tmp_path)
    assert p.returncode == 2 and why in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr


def test_a_fixed_task_list_is_refused_with_what_to_do(tmp_path):
    path = tmp_path / "paper.toml"
    path.write_text('layout = "paper"\nrobots = 2\ntasks = [1, 2]\n')
    p = _cli(str(path), "--out", str(tmp_path / "out"), cwd=tmp_path)
    assert p.returncode == 2 and "[orders]" in p.stderr, p.stderr


def test_past_the_knee_the_single_unloading_zone_is_named_with_its_relief(tmp_path):
    # Every goods to one unloading zone for the whole warehouse.
    one_zone = {**BASE, "unload": "first", "layout_generate": {**BASE["layout_generate"], "unloading_rows": 1}}
    answer = mb.capacity(Scenario.from_dict(one_zone), out=tmp_path, seeds=2)
    b = answer.bottleneck
    assert answer.sustainable_rate is not None and b is not None, answer.to_dict()
    assert b["kind"] == "unloading" and "unloading_rows" in b["relieve"]
    assert json.loads(json.dumps(answer.to_dict()))["bottleneck"]["node"] == b["node"]


# A small warehouse, so that four searches stay cheap.
SMALL = {**BASE, "robots": 30, "allocator": "in-turn",
         "layout_generate": {**BASE["layout_generate"], "group_rows": 3, "group_cols": 5, "chargers": 4},
         "orders": {**BASE["orders"], "horizon": 2000}}


def test_one_search_per_strategy_and_policy_each_as_its_own_search_answers(tmp_path):
    base = Scenario.from_dict(SMALL)
    combos = mb.capacity(base, allocators=["nearest", "hungarian"], traffic=["wait", "reserve"], out=tmp_path,
                         seeds=2)
    assert [(c.allocator, c.traffic) for c in combos] == [
        ("nearest", "wait"), ("nearest", "reserve"), ("hungarian", "wait"), ("hungarian", "reserve")]
    for c in combos:
        # The same answer as the single search of that combination (whose runs the store holds).
        alone = mb.capacity(base.replace(allocator=c.allocator, traffic=c.traffic), out=tmp_path, seeds=2)
        assert alone.runs == c.answer.runs and c.answer.sustainable_rate == alone.sustainable_rate
        assert [lv.to_dict() for lv in alone.curve] == [lv.to_dict() for lv in c.answer.curve]
        assert c.to_dict()["allocator"] == c.allocator and c.to_dict()["sustainable_rate"] == alone.sustainable_rate
    # A list left out keeps the scenario's own choice.
    only = mb.capacity(base, traffic=["reserve"], out=tmp_path, seeds=2)
    assert [(c.allocator, c.traffic) for c in only] == [("in-turn", "reserve")]


def test_the_command_compares_combinations_in_a_table_a_figure_and_json(tmp_path):
    path = tmp_path / "w.toml"
    path.write_text(Scenario.from_dict(SMALL).to_toml())
    args = [str(path), "--allocators", "nearest,hungarian", "--traffic", "reserve", "--seeds", "2",
            "--out", str(tmp_path / "out")]
    p = _cli(*args, "--json", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    entries = json.loads(p.stdout)["combinations"]
    assert [(e["allocator"], e["traffic"]) for e in entries] == [("nearest", "reserve"), ("hungarian", "reserve")]
    for e in entries:
        assert e["question"] == "rate" and e["curve"]
        assert e["sustainable_rate"] is None or e["sustainable_rate"] in [lv["rate"] for lv in e["curve"]]
    p = _cli(*args, "--quiet", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    for e in entries:
        row = next(line for line in lines if line.startswith(f"{e['allocator']}/{e['traffic']} "))
        assert f"{e['sustainable_rate']:.4g}" in row.split()[1]
    rates = [e["sustainable_rate"] for e in entries if e["sustainable_rate"] is not None]
    if rates:
        # One winner, or a tie named as such (equal answers are not ranked by flag order).
        said = "tie: " if rates.count(max(rates)) > 1 else "best: "
        assert said in p.stdout, p.stdout
    assert (tmp_path / "out" / "capacity.png").stat().st_size > 0


def test_robots_sets_the_fleet_of_the_question(tmp_path):
    path = tmp_path / "w.toml"
    path.write_text(Scenario.from_dict(SMALL).to_toml())
    p = _cli(str(path), "--robots", "20", "--seeds", "1", "--json", "--out", str(tmp_path / "out"), cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["robots"] == 20 and {lv["robots"] for lv in d["curve"]} == {20}
