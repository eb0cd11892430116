"""Task-allocation strategies from Python: the plug-in API, the view, validation, the TOML
form, the built-ins by name, random task lists and the charging policy."""

from __future__ import annotations

import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import multibots
from multibots import AllocatorError, Scenario, ScenarioError, Simulation, simulate, simulate_many
from multibots.paper import PAPER_TASKS
from multibots.strategies import BUILT_INS

from oracle import reference_model as ref

ROOT = pathlib.Path(__file__).resolve().parents[2]


def indicators(r):
    return (r.T, r.S, r.C)


# --- the docs example --------------------------------------------------------------------


def test_the_docs_example_runs():
    text = (ROOT / "docs" / "strategies.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    example = blocks[0]
    # The strategy and its run fit 15 lines (the example's own check aside).
    assert len([line for line in example.strip().splitlines() if not line.startswith("assert ")]) <= 15
    namespace: dict = {}
    exec(compile(example, "docs/strategies.md", "exec"), namespace)
    result = namespace["result"]
    assert result.complete and result.delivered == 10
    assert namespace["ShortestTrip"].name == "shortest-trip"


# --- in-turn is the paper model ----------------------------------------------------------


@pytest.mark.parametrize("n,group", [(1, 1), (2, 2), (3, 3), (4, 4), (6, 5)])
def test_in_turn_built_in_and_in_python_give_the_paper_models_T_S_C(n, group):
    goods = PAPER_TASKS[group]
    want = ref.run(list(goods), robots=n)
    s = Scenario.paper(robots=n, goods=goods)
    built_in = simulate(s, allocator="in-turn")
    from strategies_example.closest import InTurnPy

    python = simulate(s, allocator=InTurnPy())
    function = simulate(s, allocator=lambda view: dict(zip(view.idle.tolist(), view.goods.tolist())))
    assert indicators(built_in) == (want["T"], want["S"], want["C"])
    assert built_in == simulate(s) == python == function


# --- plugging in -------------------------------------------------------------------------


def test_a_subclass_plugs_in_through_the_api_and_through_toml():
    from strategies_example.closest import Closest

    s = Scenario.paper(robots=3, goods=PAPER_TASKS[2])
    by_object = simulate(s, allocator=Closest())
    assert by_object.complete
    toml = s.to_toml().replace('allocator = "in-turn"', 'allocator = "strategies_example.closest:Closest"')
    assert 'strategies_example.closest:Closest' in toml
    from_file = Scenario.from_toml_str(toml, "closest.toml")
    assert simulate(from_file) == by_object
    # By name through allocator=, and stepping through Simulation.
    assert simulate(s, allocator="strategies_example.closest:Closest") == by_object
    sim = Simulation(s, allocator=Closest())
    assert sim.run() == by_object
    assert sim._sim.allocator == "closest"
    # simulate_many runs Python strategies one after another, same results.
    assert simulate_many([s, s], allocator=Closest()) == [by_object, by_object]
    assert simulate_many([from_file]) == [by_object]


def test_the_scenario_file_form_is_checked_when_the_scenario_is_read(tmp_path):
    base = Scenario.paper(robots=2, goods=[11, 8]).to_toml()
    cases = {
        "no_such_pkg.mod:Cls": "cannot import no_such_pkg.mod",
        "strategies_example.closest:Nope": "module strategies_example.closest has no attribute Nope",
        ":Cls": 'expected "package.module:Class"',
        "strategies_example.closest:": 'expected "package.module:Class"',
    }
    for name, why in cases.items():
        with pytest.raises(ScenarioError) as e:
            Scenario.from_toml_str(base.replace('"in-turn"', f'"{name}"'), "s.toml")
        assert str(e.value).startswith(f'allocator = "{name}": ') and why in str(e.value), str(e.value)
    s = Scenario.from_toml_str(base.replace('"in-turn"', '"strategies_example.closest:NeedsArgument"'), "s.toml")
    with pytest.raises(
        ScenarioError,
        match=r'allocator = "strategies_example.closest:NeedsArgument": calling it with no arguments failed: TypeError',
    ):
        simulate(s)


def test_built_ins_by_name_everywhere():
    assert BUILT_INS == ("in-turn", "nearest", "hungarian", "auction", "energy-aware", "min-cost")
    s = Scenario.paper(robots=3, goods=PAPER_TASKS[1])
    for name in BUILT_INS:
        a = simulate(s, allocator=name)
        b = simulate(s.replace(allocator=name))
        assert a == b and a.complete, name
    assert simulate_many([s, s], allocator="hungarian") == [simulate(s, allocator="hungarian")] * 2
    with pytest.raises(
        ScenarioError,
        match=r'^allocator = "greedy": unknown strategy '
        r"\(built-ins: in-turn, nearest, hungarian, auction, energy-aware, min-cost; or module:Class for a Python "
        r"strategy\)$",
    ):
        simulate(s, allocator="greedy")
    with pytest.raises(ScenarioError, match='allocator = "greedy": unknown strategy'):
        s.replace(allocator="greedy")


def test_a_class_instead_of_an_instance_or_a_non_callable_is_a_clear_error():
    from strategies_example.closest import Closest

    s = Scenario.paper(robots=1, goods=[42])
    with pytest.raises(TypeError, match=r"got the class Closest; pass an instance, such as Closest\(\)"):
        simulate(s, allocator=Closest)
    with pytest.raises(
        TypeError, match="expected a multibots.Allocator, a function f\\(view\\) or a strategy name, got int"
    ):
        simulate(s, allocator=3)


# --- the view ----------------------------------------------------------------------------


def test_the_view_shows_the_fleet_and_answers_route_queries():
    seen = []

    def look(view):
        if not seen:
            n = view.robot_count
            assert view.step == 1
            assert view.idle.tolist() == [0, 1, 2]
            assert view.goods.tolist() == list(range(10))
            assert view.goods_cells.tolist() == list(PAPER_TASKS[1])
            assert view.positions.shape == (n, 2) and view.positions.dtype == np.float64
            assert view.energy.tolist() == [10.0] * n
            assert view.states.tolist() == [0] * n  # IDLE
            assert view.task_cells.tolist() == [-1] * n
            assert (view.energy_full, view.threshold, view.consumption, view.speed) == (10.0, 3.5, 0.005, 4.0)
            assert (view.loading, view.unloading, view.charge_rate) == (10, 20, 0.05)
            assert view.cost_weights == (0.25, 1.0, 50.0)
            with pytest.raises(ValueError):
                view.positions[0, 0] = 1.0  # read-only
            m = view.route_lengths()
            assert m.shape == (3, 10)
            assert m[0, 7] == view.route_length(0, 42) == 1290.0  # the spec's worked example
            assert view.cell_to_unload(42) == 950.0
            assert view.unload_to_home(0) == 540.0
            assert view.task_steps(0, 42) == 323 + 10 + 238 + 20
            assert view.energy_after(0, 42) == pytest.approx(10.0 - 591 * 0.005)
            assert view.traffic(0, 42) == 0  # nobody else is moving yet
            with pytest.raises(ValueError, match=r"robot = 7: out of range 0..2"):
                view.route_length(7, 42)
            with pytest.raises(ValueError, match=r"cell = 80: out of range 0..79"):
                view.route_length(0, 80)
        else:
            busy = [i for i in range(view.robot_count) if i not in view.idle.tolist()]
            for i in busy:
                assert view.states[i] != 0 and view.task_cells[i] >= 0
        seen.append(view)
        return list(zip(view.idle.tolist(), view.goods.tolist()))

    r = simulate(Scenario.paper(robots=3, goods=PAPER_TASKS[1]), allocator=look)
    assert r == simulate(Scenario.paper(robots=3, goods=PAPER_TASKS[1]))
    # Called at allocation events only, not every step.
    assert 1 < len(seen) < 30 < r.T
    with pytest.raises(RuntimeError, match="expired"):
        seen[0].route_length(0, 42)


# --- validation --------------------------------------------------------------------------


class Answer(multibots.Allocator):
    name = "answer-test"

    def __init__(self, fn):
        self.fn = fn

    def allocate(self, view):
        return self.fn(view)


def run_with(fn, robots=2, goods=(11, 8, 39)):
    return simulate(Scenario.paper(robots=robots, goods=list(goods)), allocator=Answer(fn))


def test_invalid_assignments_are_rejected_naming_the_strategy():
    def busy(view):
        # First event: everyone works; then hand goods to a robot that is still busy.
        if len(view.idle) == view.robot_count:
            return list(zip(view.idle.tolist(), view.goods.tolist()))
        other = next(i for i in range(view.robot_count) if i not in view.idle.tolist())
        return {other: int(view.goods[0])}

    cases = [
        (busy, r"robot \d is not idle \(it is [A-Z_]+\)"),
        (lambda v: [(0, 0), (1, 0)], r"goods 0 handed out twice"),
        (lambda v: [(9, 0)], r"unknown robot id 9"),
        (lambda v: [(0, 77)], r"unknown or taken goods id 77"),
        (lambda v: [(0, 0), (0, 1)], r"robot 0 is given two decisions"),
        (lambda v: "0,1", r"must return a dict \{robot: goods\} or a list of \(robot, goods\) pairs, got str"),
        (lambda v: [(0,)], r"assignment 0: expected a \(robot, goods\) pair, got \(0,\)"),
        (lambda v: {-1: 0}, r"assignment 0: robot id must be an integer 0 or more, got -1"),
        (lambda v: {0: 1.5}, r"assignment 0: goods id must be an integer 0 or more, got 1.5"),
        (lambda v: 42, r"must return a dict"),
    ]
    for fn, why in cases:
        with pytest.raises(AllocatorError) as e:
            run_with(fn)
        msg = str(e.value)
        assert msg.startswith("allocator 'answer-test': ") and re.search(why, msg), msg
        assert "\n" not in msg
    # None, empty answers and NumPy integers are fine.
    assert run_with(lambda v: None if v.step > 10**9 else [(np.int64(v.idle[0]), v.goods[0])]).complete


def test_an_exception_inside_the_strategy_surfaces_in_python_with_its_cause():
    def broken(view):
        return {0: 1 // 0}

    with pytest.raises(
        AllocatorError, match=r"^allocator 'broken': raised ZeroDivisionError: integer division or modulo by zero$"
    ) as e:
        simulate(Scenario.paper(robots=1, goods=[42]), allocator=broken)
    assert isinstance(e.value.__cause__, ZeroDivisionError)
    # The next run is not affected by the earlier failure.
    assert simulate(Scenario.paper(robots=1, goods=[42]), allocator=lambda v: {0: 0}).T == 726
    with pytest.raises(AllocatorError):
        Simulation(Scenario.paper(robots=1, goods=[42]), allocator=broken).run()

    def interrupted(view):
        raise KeyboardInterrupt

    # Ctrl-C inside a strategy interrupts like anywhere else.
    with pytest.raises(KeyboardInterrupt):
        simulate(Scenario.paper(robots=1, goods=[42]), allocator=interrupted)


def test_leaving_robots_idle_is_allowed():
    # Only robot 0 ever works: robot 1 stays idle (then parks when the queue is empty).
    def only_zero(view):
        return {0: int(view.goods[0])} if 0 in view.idle.tolist() else {}

    r = run_with(only_zero)
    assert r.complete and r.robot_delivered.tolist() == [3, 0]


def test_seeded_runs_are_deterministic_for_python_and_built_in_strategies():
    from strategies_example.closest import Closest

    s = Scenario.from_dict({"robots": 4, "tasks": {"random": 12, "seed": 5}})
    for allocator in (*BUILT_INS, Closest()):
        assert simulate(s, allocator=allocator) == simulate(s, allocator=allocator)


# --- random task lists -------------------------------------------------------------------


def test_random_task_lists_are_pinned_and_the_same_in_another_process():
    s = Scenario.from_dict({"tasks": {"random": 10, "seed": 7}})
    golden = [75, 1, 65, 50, 12, 43, 45, 59, 13, 70]
    assert s.cells == golden
    assert Scenario.from_dict({"tasks": {"random": 10, "seed": 8}}).cells != golden
    code = "from multibots import Scenario; print(Scenario.from_dict({'tasks': {'random': 10, 'seed': 7}}).cells)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == str(golden)
    from_toml = Scenario.from_toml_str("tasks = { random = 10, seed = 7 }", "r.toml")
    assert from_toml.cells == golden
    assert simulate(from_toml) == simulate(Scenario.paper(robots=3, goods=golden))


# --- charging policy ---------------------------------------------------------------------


def test_charging_policies():
    s = Scenario.paper(robots=1, goods=[42, 11])
    threshold = simulate(s)
    assert threshold.C == 0
    opportunistic = simulate(s.replace(charging={"policy": "opportunistic", "level": 9.9}))
    assert opportunistic.C >= 1 and opportunistic.T > threshold.T
    assert simulate(s.replace(charging={"policy": "opportunistic", "level": 3.6})) == threshold
    with pytest.raises(ScenarioError, match=r"charging.level = 3: must be above robot.threshold \(3.5\)"):
        s.replace(charging={"policy": "opportunistic", "level": 3.0})
    with pytest.raises(ScenarioError, match="charging.policy"):
        s.replace(charging={"policy": "sometimes"})


# --- the command line --------------------------------------------------------------------


def test_run_with_an_allocator_flag(cli):
    r = cli("run", "--robots", "3", "--goods", "11,8,39,28,53", "--allocator", "hungarian", "--json")
    assert r.returncode == 0, r.stderr
    import json

    got = json.loads(r.stdout)
    want = simulate(Scenario.paper(robots=3, goods=[11, 8, 39, 28, 53]), allocator="hungarian")
    assert (got["T"], got["S"], got["C"]) == indicators(want)
    bad = cli("run", "--robots", "3", "--goods", "11,8", "--allocator", "greedy")
    assert bad.returncode == 2
    assert bad.stderr.strip().count("\n") == 0 and 'allocator = "greedy": unknown strategy' in bad.stderr
