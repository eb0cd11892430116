"""People in the aisles from Python and the command line (docs/people.md)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

import multibots
from multibots.strategies import AllocView

# The repository (a `conftest` import would find whichever conftest.py was loaded first).
ROOT = Path(__file__).resolve().parents[1]


PEOPLE = ROOT / "scenarios" / "people.toml"


def test_positions_and_radii() -> None:
    s = multibots.Scenario.from_toml(PEOPLE)
    sim = multibots.Simulation(s)
    assert sim.human_positions.shape == (10, 2) and np.all(sim.human_radii == 6.25)
    start = sim.human_positions.copy()
    for _ in range(100):
        sim.step()
    assert not np.array_equal(start, sim.human_positions), "people walk"
    # No person ever inside a robot's body.
    gaps = np.hypot(*(sim.human_positions[:, None, :] - sim.positions[None, :, :]).transpose(2, 0, 1))
    assert gaps.min() >= 12.5 + 6.25
    plain = multibots.Simulation(multibots.Scenario.from_dict({"layout": "paper", "robots": 2, "tasks": [11]}))
    assert plain.human_positions.shape == (0, 2) and plain.human_radii.shape == (0,)


def test_result_figures_and_cost_of_people(cli) -> None:
    r = multibots.simulate(multibots.Scenario.from_toml(PEOPLE))
    p = r.people
    assert p["count"] == 10 and p["contacts"] == 0 and p["protective_stops"] > 0
    assert p["min_gap"] >= 0 and p["gap_p1"] >= p["min_gap"] - 0.25
    assert p["person_steps"] == 10 * r.steps
    none = multibots.simulate(multibots.Scenario.from_toml(PEOPLE).replace(humans={"count": 0}))
    assert none.people is None and none.T < r.T, "people cost the fleet time"
    out = cli("run", PEOPLE)
    assert out.returncode == 0, out.stderr
    assert "protective stops" in out.stdout and "contacts 0" in out.stdout and "without people" in out.stdout
    js = json.loads(cli("run", PEOPLE, "--json").stdout)
    assert js["people"]["count"] == 10 and js["people"]["contacts"] == 0
    plain = json.loads(cli("run", "--goods", "11,8", "--json").stdout)
    assert set(plain["people"]) == set(js["people"]) and plain["people"]["count"] is None


def test_compare_varies_the_number_of_people(cli, tmp_path) -> None:
    out = cli("compare", "--scenario", PEOPLE, "--tasks", "scenario", "--seeds", "2", "--humans", "0,5",
              "--strategies", "in-turn,nearest", "--robots", "3", "--out", tmp_path, "--no-plots", "--quiet")
    assert out.returncode == 0, out.stderr
    rows = list(csv.DictReader((tmp_path / "results.csv").open()))
    assert {r["strategy"] for r in rows} == {"in-turn/0 people", "in-turn/5 people", "nearest/0 people",
                                             "nearest/5 people"}
    assert {r["humans"] for r in rows} == {"0", "5"}
    assert all(r["protective_stops"] == "" for r in rows if r["humans"] == "0")
    cli.assert_one_line_error(cli("compare", "--humans", "many", "--quiet"), "--humans", "many")


def test_bad_people_values_are_one_line_errors(cli, tmp_path) -> None:
    for body, field in [("speed = -1", "humans.speed"), ("slow = 2", "humans.slow"), ("nope = 1", "nope")]:
        (tmp_path / "s.toml").write_text(f'layout = "paper"\nrobots = 2\ntasks = [11]\n[humans]\ncount = 2\n{body}\n')
        cli.assert_one_line_error(cli("run", tmp_path / "s.toml"), field)
    original = 'layout = "paper"\nrobots = 2\ntasks = [11]\nrules = "original"\n[humans]\ncount = 2\n'
    (tmp_path / "o.toml").write_text(original)
    cli.assert_one_line_error(cli("run", tmp_path / "o.toml"), "humans.count", "paper rules")


def test_strategies_see_the_people() -> None:
    """An allocator reads the people from its view, in the same frame as the robots."""
    seen: list[np.ndarray] = []

    def in_turn(view: AllocView) -> dict[int, int]:
        seen.append(view.human_positions.copy())
        return dict(zip(view.idle.tolist(), view.goods.tolist()))

    sim = multibots.Simulation(multibots.Scenario.from_toml(PEOPLE), allocator=in_turn)
    for _ in range(400):
        sim.step()
        if len(seen) >= 2 and not np.array_equal(seen[0], seen[-1]):
            break
    assert seen and all(h.shape == (10, 2) for h in seen)
    assert not np.array_equal(seen[0], seen[-1]), "the view follows people as they walk"
    # What the strategy saw on its last call is where the people were then: within one
    # step's walk of where they are now.
    assert np.all(np.isfinite(seen[-1])) and np.abs(seen[-1] - sim.human_positions).max() < 50
    plain = multibots.Simulation(multibots.Scenario.paper(robots=1, goods=[42]), allocator=in_turn)
    seen.clear()
    plain.step()
    assert seen[-1].shape == (0, 2)


# A lifelong floor with people, so that runs with different fleets last the same steps.
LIFELONG = {
    "robots": 12, "tasks": [], "placement": "spread", "unload": "nearest", "allocator": "in-turn",
    "layout_generate": {"group_rows": 3, "group_cols": 4, "group_width": 2, "group_height": 6, "chargers": 4,
                        "unloading_rows": 2},
    "charging": {"chargers": "shared"}, "humans": {"count": 8, "seed": 3},
    "orders": {"rate": 0.03, "horizon": 3000, "restock": 100, "seed": 1},
}


def test_what_robots_cost_people_against_the_same_people_without_robots(cli) -> None:
    sim = multibots.Simulation(multibots.Scenario.from_toml(PEOPLE))
    moved = 0
    last = sim.human_positions.copy()
    while not sim.done:
        sim.step()
        now = sim.human_positions.copy()
        moved += int(np.count_nonzero(np.any(now != last, axis=1)))
        last = now
    p = sim.result().people
    a = p["alone"]
    # Judged from positions: a person that moved was walking.
    assert moved <= p["walk_steps"] <= p["person_steps"]
    assert p["person_wait_steps"] <= p["blocked_steps"] <= p["walk_steps"]
    # The run without robots: the same people over the same steps, and no robot near them.
    assert a["count"] == 10 and a["person_steps"] == p["person_steps"] and a["alone"] is None
    assert a["protective_stops"] == 0 and a["person_wait_steps"] == 0 and a["min_gap"] is None
    # On the paper's small floor six robots cost ten pickers picks, and hold them up.
    assert p["picks"] < a["picks"] and p["blocked_steps"] > 5 * a["blocked_steps"]
    costs = multibots.result.people_costs(p)
    hours = p["person_steps"] * 0.05 / 3600
    assert costs["picks_per_hour"] == p["picks"] / hours and costs["alone_picks_per_hour"] == a["picks"] / hours
    out = cli("run", PEOPLE)
    assert out.returncode == 0, out.stderr
    line = next(s for s in out.stdout.splitlines() if s.startswith("per worker"))
    assert f"{costs['picks_per_hour']:.1f} ({costs['alone_picks_per_hour']:.1f}) picks" in line
    assert "held up" in out.stdout


def test_people_without_robots_do_not_depend_on_what_the_fleet_does() -> None:
    # (A fleet of another size starts elsewhere, and stations keep clear of where robots start:
    # its people are placed otherwise.)
    base = multibots.Scenario.from_dict(LIFELONG)
    runs = [multibots.simulate(base.replace(**change)).people for change in
            ({}, {"allocator": "nearest"}, {"traffic": "reserve"}, {"orders": {"rate": 0.06}})]
    assert all(r["alone"] == runs[0]["alone"] for r in runs)
    assert len({(r["walk_steps"], r["blocked_steps"], r["picks"]) for r in runs}) > 1, "robots change people's time"


def test_people_costs_are_figures_of_sweeps_and_compare(tmp_path) -> None:
    from multibots.experiments import compare as study
    from multibots.sweeps.analysis import METRICS

    df = multibots.sweep({"base": LIFELONG, "axes": {"humans.count": [4, 8], "seed": [1, 2]}}, tmp_path / "s")
    for m in ("people_picks_per_hour", "people_alone_picks_per_hour", "people_walk_share", "people_blocked_share"):
        assert m in METRICS and df[m].null_count() == 0 and df[m].min() >= 0
    rows = study.run_study(["in-turn", "nearest"], [12], study.TaskSpec("scenario"), seeds=2,
                           base=multibots.Scenario.from_dict(LIFELONG))
    assert all(r["people_picks_per_hour"] > 0 and r["people_alone_picks_per_hour"] > 0 for r in rows)
    text = study.format_summary(study.summarize(rows))
    assert "people's picks per worker-hour: mean [95% CI]" in text
