"""Scale: a 10,000-robot fleet runs 1,000 steps inside the test suite (no time assertion)."""

from __future__ import annotations

from pathlib import Path

from multibots import Scenario, Simulation

HUGE = Path(__file__).resolve().parent.parent / "benchmarks" / "sizes" / "huge.toml"


def test_ten_thousand_robots_run_a_thousand_steps():
    sim = Simulation(Scenario.from_toml(HUGE))
    assert sim.robot_count == 10_000
    assert sim.step(1000) == 1000
    raw = sim._sim.result()
    ll = raw["lifelong"]
    assert ll["ordered"] == raw["delivered"] + ll["in_flight"] + ll["queued"] + ll["waiting"]
    assert raw["distance"].sum() > 0
    # Robots start on distinct parking slots and stay on the warehouse's aisles.
    pos = sim.positions
    assert pos.shape == (10_000, 2)
    bounds = sim.layout["bounds"]
    assert (pos[:, 0] >= bounds[0]).all() and (pos[:, 0] <= bounds[2]).all()
