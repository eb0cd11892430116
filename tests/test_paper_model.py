"""The paper model through the Python API: the formula, the worked example, the trends."""

from __future__ import annotations

import random
import statistics

import numpy as np
import pytest

import multibots
from multibots import PAPER_TASKS, STATE_NAMES, Scenario, Simulation, simulate, simulate_many

from oracle.geometry import bfs_path, cell, charger_xy, formula_t, node_xy, single_robot_legs


def test_worked_example_legs_from_geometry():
    assert single_robot_legs(42) == (1290.0, 950.0, 540.0)
    assert formula_t(42) == 726


CELLS = [0, 1, 6, 11, 17, 23, 28, 39, 42, 47, 53, 60, 65, 69, 74, 79]


@pytest.mark.parametrize("cell_id", CELLS)
@pytest.mark.parametrize("start", ["A", "D", "F"])
def test_single_robot_formula(cell_id, start):
    s = Scenario.paper(robots=1, goods=[cell_id], starts=[start])
    r = simulate(s)
    assert r.outcome == "complete"
    assert r.T == formula_t(cell_id, start)
    d1, d2, d3 = single_robot_legs(cell_id, start)
    assert r.distance[0] == d1 + d2 + d3
    assert (r.S, r.C, r.delivered) == (0, 0, 1)


@pytest.mark.parametrize("unload", ["M", "O", "R"])
def test_single_robot_formula_other_unloading_zones(unload):
    for cell_id in (3, 42, 77):
        assert simulate(Scenario.paper(robots=1, goods=[cell_id], unload=unload)).T == formula_t(cell_id, "A", unload)


def _xy(names):
    return [node_xy(n) for n in names]


def test_worked_example_route_through_the_api():
    sim = Simulation(Scenario.paper(robots=1, goods=[42]))
    assert STATE_NAMES[sim.states[0]] == "IDLE"
    assert tuple(sim.positions[0]) == charger_xy(0)
    sim.step()
    assert STATE_NAMES[sim.states[0]] == "TO_PICKUP"
    assert sim.task_cells[0] == 42 and sim.carrying[0] == -1
    # After one step the robot is 4 px down the spur; the rest of the route is A B C D J P O, then the point.
    expected = [(25.0, -11.0)] + _xy(bfs_path("A", "O")) + [cell(42)["service"]]
    assert bfs_path("A", "O") == list("ABCDJPO")
    assert [tuple(p) for p in sim.route(0)] == expected
    # It reaches the point after ceil(1290 / 4) steps and loads for 10.
    sim.step(322)
    assert sim.t == 323 and STATE_NAMES[sim.states[0]] == "LOADING"
    assert tuple(sim.positions[0]) == (325.0, 375.0)
    assert sim.cells[42] == 1
    sim.step(10)
    assert STATE_NAMES[sim.states[0]] == "TO_DROP" and sim.carrying[0] == 42 and sim.cells[42] == 0
    assert [tuple(p) for p in sim.route(0)] == [(325.0, 375.0)] + _xy(list("IJPONM"))
    sim.step(238)
    assert STATE_NAMES[sim.states[0]] == "UNLOADING" and tuple(sim.positions[0]) == node_xy("M")
    sim.step(20)
    assert STATE_NAMES[sim.states[0]] == "IDLE" and sim.delivered == 1
    sim.step()
    assert STATE_NAMES[sim.states[0]] == "TO_HOME"
    assert [tuple(p) for p in sim.route(0)][1:] == _xy(list("GA")) + [charger_xy(0)]
    result = sim.run()
    assert result.T == 726 and sim.T == 726 and STATE_NAMES[sim.states[0]] == "PARKED"
    assert result.state_steps[0, STATE_NAMES.index("LOADING")] == 10
    assert result.state_steps[0, STATE_NAMES.index("UNLOADING")] == 20


def test_determinism_results_and_replay_bytes(tmp_path):
    s = Scenario.paper(robots=6, goods=PAPER_TASKS[2], margin=8)
    a = simulate(s, record=tmp_path / "a.mbr")
    b = simulate(s, record=tmp_path / "b.mbr")
    assert a.to_dict() == b.to_dict()
    assert (tmp_path / "a.mbr").read_bytes() == (tmp_path / "b.mbr").read_bytes()
    # A stepped run is the same run.
    sim = Simulation(s)
    while not sim.done:
        sim.step(7)
    assert sim.result().to_dict() == a.to_dict()


@pytest.fixture(scope="module")
def paper_runs():
    runs = [(n, g, Scenario.paper(robots=n, goods=cells)) for n in range(1, 7) for g, cells in PAPER_TASKS.items()]
    results = simulate_many([s for _, _, s in runs])
    return {(n, g): r for (n, g, _), r in zip(runs, results)}


def test_paper_trends(paper_runs):
    assert all(r.outcome == "complete" for r in paper_runs.values())
    mean = {
        k: [statistics.fmean(getattr(paper_runs[(n, g)], k) for g in range(1, 6)) for n in range(1, 7)] for k in "TSC"
    }
    assert all(a > b for a, b in zip(mean["T"], mean["T"][1:])), mean["T"]
    assert all(a <= b for a, b in zip(mean["S"], mean["S"][1:])), mean["S"]
    assert mean["C"][5] < mean["C"][0], mean["C"]


def test_paper_golden_values(paper_runs):
    """Recorded values: a change to any of them is a change of the model."""
    golden = {
        (1, 1): (6619, 0, 3),
        (3, 1): (1719, 3, 3),
        (4, 4): (2361, 4, 3),
        (6, 2): (1333, 7, 0),
        (6, 5): (1407, 4, 0),
    }
    for key, tsc in golden.items():
        r = paper_runs[key]
        assert (r.T, r.S, r.C) == tsc, key


def test_simulate_many_equals_simulate(paper_runs):
    for key in [(2, 3), (5, 1)]:
        n, g = key
        assert simulate(Scenario.paper(robots=n, goods=PAPER_TASKS[g])).to_dict() == paper_runs[key].to_dict()


def _random_scenarios(count: int, margin: float):
    rng = random.Random(20171205 + int(margin))
    out = []
    for _ in range(count):
        n = rng.randint(1, 6)
        cells = rng.sample(range(80), rng.randint(1, 10))
        out.append(Scenario.paper(robots=n, goods=cells, margin=margin))
    return out


@pytest.mark.parametrize("margin", [0.0, 8.0])
def test_no_deadlock_in_500_random_scenarios(margin):
    scenarios = _random_scenarios(500, margin)
    results = simulate_many(scenarios)
    stuck = [(s, r) for s, r in zip(scenarios, results) if r.outcome != "complete"]
    assert not stuck, stuck[:3]
    assert all(r.delivered == len(s.cells) for s, r in zip(scenarios, results))


def test_stranded_robots_end_the_run_stranded():
    # A low threshold leaves no reserve: a robot marked to charge still carries its goods to R,
    # far from its home at A, and runs out of energy on the way. Once both are stranded nothing
    # more can happen, and the run ends then, not at the step limit.
    s = Scenario.paper(robots=2, goods=PAPER_TASKS[1], unload="R", step_limit=20_000, robot={"threshold": 0.3})
    r = simulate(s)
    assert r.outcome == "stranded" and r.T is None
    assert r.steps == 2000
    assert r.stranded, "some robot must be stranded"
    assert r.delivered < 10
    sim = Simulation(s)
    sim.run()
    assert [i for i in range(2) if STATE_NAMES[sim.states[i]] == "STRANDED"] == r.stranded
    assert all(sim.energy[i] == 0.0 for i in r.stranded)


def test_margin_8_changes_collisions_not_work():
    a = simulate(Scenario.paper(robots=6, goods=PAPER_TASKS[1]))
    b = simulate(Scenario.paper(robots=6, goods=PAPER_TASKS[1], margin=8))
    assert a.delivered == b.delivered == 10
    assert b.S >= a.S


def test_state_arrays_are_read_only_copies():
    sim = Simulation(Scenario.paper(robots=3, goods=[1, 2, 3]))
    sim.step(5)
    pos = sim.positions
    with pytest.raises(ValueError):
        pos[0, 0] = 1.0
    assert pos.dtype == np.float64 and pos.shape == (3, 2)
    assert sim.states.dtype == np.uint8 and sim.cells.shape == (80,)
    assert sim.layout["name"] == "paper" and len(sim.layout["cells"]) == 80


def test_layout_json_matches_geometry():
    lay = multibots.layout_json("paper")
    for c in lay["cells"]:
        info = cell(c["id"])
        assert (c["x"] + c["w"] / 2, c["y"] + c["h"] / 2) == info["centre"]
        assert tuple(c["service"]) == info["service"]
        names = [lay["nodes"][i]["name"] for i in c["edge"]]
        assert tuple(names) == info["edge"]
    assert len(lay["edges"]) == 27
