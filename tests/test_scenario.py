"""Scenarios: files users start from, round trips, the Python builders and engine errors."""

from __future__ import annotations

from pathlib import Path

import pytest

import multibots
from multibots import Scenario, ScenarioError, simulate

SCENARIOS = sorted((Path(__file__).parent.parent / "scenarios").glob("*.toml"))


def test_there_are_scenarios():
    assert any(p.name == "paper.toml" for p in SCENARIOS)


@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.name)
def test_every_scenario_file_loads_and_round_trips(path):
    s = Scenario.from_toml(path)
    assert Scenario.from_toml_str(s.to_toml()) == s
    assert Scenario.from_dict(s.to_dict()) == s


def test_paper_toml_is_group_1_with_three_robots():
    s = Scenario.from_toml(Path(__file__).parent.parent / "scenarios" / "paper.toml")
    assert s == Scenario.paper(robots=3, goods=multibots.PAPER_TASKS[1])
    assert simulate(s).T == 1719


def test_defaults_are_the_paper_model():
    d = Scenario.paper(robots=1, goods=[42]).to_dict()
    assert d["robot"] == {
        "radius": 12.5,
        "speed": 4.0,
        "energy_full": 10.0,
        "threshold": 3.5,
        "consumption": 0.005,
        "charge_rate": 0.05,
    }
    assert d["dwell"] == {"loading": 10, "unloading": 20}
    assert d["collision"] == {"margin": 0.0, "angle": 30.0}
    assert d["step_limit"] == 100000 and d["unload"] == "M" and d["allocator"] == "in-turn"


def test_replace_merges_nested_tables():
    s = Scenario.paper(robots=2, goods=[1, 2]).replace(robot={"speed": 8.0})
    d = s.to_dict()
    assert d["robot"]["speed"] == 8.0 and d["robot"]["radius"] == 12.5


def test_python_errors_are_scenario_errors():
    with pytest.raises(ScenarioError, match=r"robot\.speed = 0: must be greater than 0"):
        Scenario.paper(robot={"speed": 0})
    with pytest.raises(ScenarioError, match="more robots than start nodes"):
        Scenario.paper(robots=7, placement="departure")
    with pytest.raises(multibots.MultibotsError):
        Scenario.from_dict({"tasks": [1], "colour": "red"})


def test_random_task_lists_are_seeded():
    a = Scenario.from_dict({"tasks": {"random": 10, "seed": 7}})
    b = Scenario.from_toml_str("tasks = { random = 10, seed = 7 }")
    assert a.cells == b.cells and len(set(a.cells)) == 10
    assert Scenario.from_dict({"tasks": {"random": 10, "seed": 8}}).cells != a.cells


def test_paper_takes_goods_or_tasks_but_not_both():
    assert Scenario.paper(robots=2, tasks={"random": 5, "seed": 1}).cells == Scenario.from_dict(
        {"robots": 2, "tasks": {"random": 5, "seed": 1}}).cells
    assert Scenario.paper(robots=2, tasks=[11, 8]) == Scenario.paper(robots=2, goods=[11, 8])
    assert Scenario.paper().cells == list(multibots.PAPER_TASKS[1])
    with pytest.raises(ScenarioError, match=r"^Scenario.paper\(\): goods and tasks are the same field") as e:
        Scenario.paper(goods=[11, 8], tasks=[1, 2])
    assert "\n" not in str(e.value)


def test_check_many_names_the_fault_validate_names() -> None:
    """A sweep checks its planned runs in one engine call; where a scenario has several faults
    the call names the one `Scenario.validate` names (allocator, then values, then layout)."""
    import multibots
    from multibots import _core

    base = {"layout": "paper", "robots": 2, "tasks": [5]}
    faults = {"allocator": {"allocator": "fastest"}, "speed": {"robot": {"speed": -1.0}},
              "unload": {"unload": "nowhere"}, "cell": {"tasks": [81]}}
    cases = []
    for a in faults:
        for b in faults:
            if a < b:
                d = dict(base)
                d.update(faults[a])
                d.update(faults[b])
                cases.append(d)
    cases.append({**base, "allocator": "nope_module:Missing", "robot": {"speed": -1.0}})
    for d in cases:
        core = multibots.Scenario._parsed_only(d)._core
        with pytest.raises(multibots.MultibotsError) as alone:
            core.validate()
        failed = _core.check_many([multibots.Scenario.from_dict(base)._core, core], 1)
        assert failed is not None and failed[0] == 1, d
        assert type(failed[1]) is type(alone.value) and str(failed[1]) == str(alone.value), (d, failed[1], alone.value)


def _nested(depth: int) -> dict:
    d: dict = {"a": 1}
    for _ in range(depth):
        d = {"a": d}
    return d


@pytest.mark.parametrize(("data", "message"), [
    ({"robot": {"speed": float("inf")}}, "robot.speed = inf: must be a finite number"),
    ({"tasks": [1, float("nan")]}, "tasks[1] = nan: must be a finite number"),
    ({"robots": object}, "robots = <class 'object'>: expected a number, text, true or false, a list or a table, "
                         "not type"),
    ({"x": _nested(5000)}, "x" + ".a" * 29 + ".… (65 characters): nested deeper than 32 levels (docs/limits.md)"),
    ({"x": _nested(40)}, "scenario: a value nested deeper than 32 levels (docs/limits.md)"),
    ({"robots": 2**32}, "scenario: robots = 4294967296: expected a whole number from 0 to 4294967295"),
    ({"humans": {"count": 1, "tour": 2**32 - 1}}, "humans.tour = 4294967295: at most 100 cells per tour "
                                                  "(docs/limits.md)"),
])
def test_dictionaries_name_the_field_and_value(data: dict, message: str) -> None:
    """What JSON cannot carry (NaN, objects, nesting thousands deep) is named by its field,
    not in JSON's words (issue 28)."""
    with pytest.raises(ScenarioError) as e:
        Scenario.from_dict({"layout": "paper", "tasks": [1, 2], **data})
    assert str(e.value) == message
    with pytest.raises(ScenarioError, match=r"^collision\.margin = nan: must be a finite number$"):
        Scenario.paper(margin=float("nan"))
