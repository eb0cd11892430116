"""Lifelong operation through Python and the command line (docs/model.md section 7)."""

from __future__ import annotations

import json
from pathlib import Path

from multibots import Scenario, Simulation, _core

ROOT = Path(__file__).resolve().parent.parent

SMALL = {
    "robots": 30,
    "tasks": [],
    "placement": "spread",
    "unload": "nearest",
    "layout_generate": {"group_rows": 3, "group_cols": 4, "group_height": 6, "chargers": 5},
    "charging": {"chargers": "shared"},
    "robot": {"consumption": 0.001},
    "orders": {"rate": 0.2, "horizon": 2000, "restock": 50, "seed": 3},
}


def test_conservation_while_stepping():
    sim = Simulation(Scenario.from_dict(SMALL))
    while not sim.done:
        sim.step(100)
        raw = sim._sim.result()
        ll = raw["lifelong"]
        assert ll["ordered"] == raw["delivered"] + ll["in_flight"] + ll["queued"] + ll["waiting"]
    assert sim.outcome == "horizon" and sim.t == 2000
    assert raw["throughput"] == raw["delivered"] / 2.0
    assert sum(raw["windows"]) == raw["delivered"] and len(raw["windows"]) == 2
    assert ll["latency_p50"] <= ll["latency_p95"] <= ll["latency_p99"]
    assert 0 < raw["utilisation"] <= 1 and 0 <= raw["wait_share"] <= 1 - raw["utilisation"]


def test_same_scenario_same_bytes():
    a = _core.simulate(Scenario.from_dict(SMALL)._core)
    b = _core.simulate(Scenario.from_dict(SMALL)._core)
    assert a["lifelong"] == b["lifelong"]
    assert a["distance"].tobytes() == b["distance"].tobytes()
    assert a["energy_used"].tobytes() == b["energy_used"].tobytes()


def test_cli_runs_the_1000_robot_warehouse_and_prints_throughput(cli):
    p = cli("run", ROOT / "scenarios" / "warehouse-1000.toml", "--horizon", "300")
    assert p.returncode == 0, p.stderr
    assert "throughput" in p.stdout and "deliveries per 1,000 steps" in p.stdout
    assert "horizon after 300 steps, 1000 robots" in p.stdout
    p = cli("run", ROOT / "scenarios" / "warehouse-1000.toml", "--horizon", "200", "--json")
    out = json.loads(p.stdout)
    assert out["steps"] == 200 and out["lifelong"]["ordered"] >= out["delivered"]


def test_cli_lifelong_errors_exit_2(cli, tmp_path):
    p = cli("run", "--goods", "1,2", "--horizon", "100")
    assert p.returncode == 2 and "only for lifelong scenarios" in p.stderr
    bad = tmp_path / "bad.toml"
    bad.write_text('tasks = []\n[orders]\nrate = 1\nhorizon = 0\n', encoding="utf-8")
    p = cli("run", str(bad))
    assert p.returncode == 2 and "orders.horizon = 0: must be at least 1 step" in p.stderr
    # Runs are at most 2**32 - 1 steps: the engine's per-robot counters are 32-bit.
    bad.write_text('tasks = []\n[orders]\nrate = 0.001\nhorizon = 4294967296\n', encoding="utf-8")
    p = cli("run", str(bad))
    assert p.returncode == 2, p.stderr
    assert p.stderr.strip().endswith("orders.horizon = 4294967296: at most 4294967295 steps"), p.stderr
    assert p.stderr.count("\n") == 1
    for steps in ("4294967296", "10000000000000000000"):
        p = cli("run", "--goods", "1,2", "--step-limit", steps)
        expected = f"--step-limit = {steps}: at most 4,294,967,295 (docs/limits.md)"
        assert p.returncode == 2 and p.stderr.strip().endswith(expected), p.stderr
        assert p.stderr.count("\n") == 1
    bad.write_text('tasks = []\nplacement = "spread"\n[charging]\nchargers = "home"\n[orders]\nrate = 1\n',
                   encoding="utf-8")
    p = cli("run", str(bad))
    assert p.returncode == 2 and 'placement = "spread": robots placed on aisles share chargers' in p.stderr


def test_the_python_result_carries_the_lifelong_metrics():
    import multibots

    s = multibots.Scenario.from_toml(ROOT / "scenarios" / "warehouse-1000.toml").replace(
        robots=50, orders={"horizon": 300}
    )
    r = multibots.simulate(s)
    assert r.lifelong is not None and r.to_dict()["lifelong"] == r.lifelong
    ll = r.lifelong
    assert ll["ordered"] == ll["delivered"] + ll["in_flight"] + ll["queued"] + ll["waiting"]
    assert multibots.simulate(multibots.Scenario.paper(robots=1, goods=[42])).lifelong is None
