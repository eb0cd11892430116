"""Engine speed and memory at the named sizes, through the Python API, on one thread.

    .venv/bin/python benchmarks/scale.py [--repetitions 5] [--sizes paper small large huge]

Named sizes (scenario files in benchmarks/sizes/, shared with the criterion bench
crates/multibots-bench/benches/step.rs): paper (N = 6, the paper scenario), small (100),
large (1,000), huge (10,000) robots on generated warehouses of matching size.

- robot-steps per second: paper: whole runs of the paper scenario (6 x T robot-steps per
  run); other sizes: steps 101..1100 of a fresh lifelong fleet (the same window as the
  criterion bench). Median over repetitions (a shared, noisy machine).
- the 30-run paper experiment: engine time on one thread (simulate_many, workers=1).
- memory per robot: a fresh subprocess per size builds the fleet and runs 100 steps;
  (resident memory at N - resident memory of the same layout with N/2 robots) / (N - N/2),
  the marginal cost of a robot (a fleet of one would also change how the collision grid
  sorts, see collision/grid.rs), and the process's peak (VmHWM), which the layout's table
  building sets.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
SIZES_DIR = ROOT / "benchmarks" / "sizes"
SIZES = ("paper", "small", "large", "huge")
WARMUP = 100
WINDOW = 1000



def size_scenario(name: str) -> Any:
    from multibots import Scenario

    return Scenario.from_toml(SIZES_DIR / f"{name}.toml")


def robot_steps_per_s(name: str, repetitions: int = 5) -> dict[str, Any]:
    """Median robot-steps per second of a named size (see the module docstring)."""
    from multibots import Simulation

    s = size_scenario(name)
    robots = s.to_dict()["robots"]
    rates = []
    for _ in range(repetitions):
        if name == "paper":
            # Whole runs, repeated for at least 0.2 s, from start to T.
            runs, steps, t0 = 0, 0, time.perf_counter()
            while True:
                sim = Simulation(s)
                sim.step(1_000_000)
                steps += sim.t
                runs += 1
                dt = time.perf_counter() - t0
                if dt > 0.2:
                    break
            rates.append(robots * steps / dt)
        else:
            sim = Simulation(s)
            sim.step(WARMUP)
            t0 = time.perf_counter()
            sim.step(WINDOW)
            rates.append(robots * WINDOW / (time.perf_counter() - t0))
    return {
        "size": name,
        "robots": robots,
        "robot_steps_per_s": statistics.median(rates),
        "min": min(rates),
        "max": max(rates),
        "repetitions": repetitions,
    }


def experiment_30_ms(repetitions: int = 7) -> dict[str, Any]:
    """Engine time of the paper's 30 runs on one thread, median over repetitions, ms."""
    from multibots import PAPER_TASKS, Scenario, simulate_many

    scenarios = [Scenario.paper(robots=n, goods=g) for n in range(1, 7) for g in PAPER_TASKS.values()]
    times = []
    for _ in range(repetitions):
        t0 = time.perf_counter()
        results = simulate_many(scenarios, workers=1)
        times.append((time.perf_counter() - t0) * 1000)
    robot_steps = sum(s.to_dict()["robots"] * r.steps for s, r in zip(scenarios, results))
    med = statistics.median(times)
    return {
        "ms": med,
        "min_ms": min(times),
        "max_ms": max(times),
        "robot_steps": robot_steps,
        "robot_steps_per_s": robot_steps / (med / 1000),
        "repetitions": repetitions,
    }


_MEMORY_CHILD = r"""
import json, sys
from multibots import Scenario, Simulation
from multibots import _core
s = Scenario.from_toml(sys.argv[1])
n = int(sys.argv[2])
if n != s.to_dict()["robots"]:
    s = s.replace(robots=n)
sim = Simulation(s)
sim.step(100)
status = {l.split(":")[0]: int(l.split()[1]) for l in open("/proc/self/status") if l.startswith(("VmHWM", "VmRSS"))}
table, nodes = _core.routing_table_bytes(s._core)
print(json.dumps({"hwm_kb": status["VmHWM"], "rss_kb": status["VmRSS"], "table_bytes": table, "nodes": nodes}))
"""


def memory_per_robot(name: str) -> dict[str, Any]:
    """Memory per robot of a named size, from two fresh subprocesses (N and N/2 robots)."""
    path = SIZES_DIR / f"{name}.toml"
    n = size_scenario(name).to_dict()["robots"]

    def child(k: int) -> dict[str, Any]:
        out = subprocess.run(
            [sys.executable, "-c", _MEMORY_CHILD, str(path), str(k)],
            capture_output=True,
            text=True,
            check=True,
            cwd=ROOT,
        )
        return json.loads(out.stdout.strip().splitlines()[-1])

    half = max(n // 2, 1)
    full, one = child(n), child(half)
    # Resident memory after 100 steps, not the peak: the peak is reached while the layout's
    # tables are built, before any robot exists, so it does not grow with the fleet.
    per_robot = (full["rss_kb"] - one["rss_kb"]) * 1024 / max(n - half, 1)
    return {
        "size": name,
        "robots": n,
        "peak_rss_mb": full["hwm_kb"] / 1024,
        "baseline_rss_mb": one["hwm_kb"] / 1024,
        "bytes_per_robot": per_robot,
        "routing_table_bytes": full["table_bytes"],
        "nodes": full["nodes"],
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--sizes", nargs="+", choices=SIZES, default=list(SIZES))
    a = ap.parse_args(argv)
    for name in a.sizes:
        r = robot_steps_per_s(name, a.repetitions)
        m = memory_per_robot(name)
        print(
            f"{name:<6} N={r['robots']:<6} {r['robot_steps_per_s'] / 1e6:8.2f} M robot-steps/s "
            f"(median of {a.repetitions})   peak {m['peak_rss_mb']:.0f} MB, {m['bytes_per_robot']:,.0f} B/robot"
        )
    e = experiment_30_ms()
    print(f"30-run paper experiment: {e['ms']:.1f} ms engine time on one thread (median)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
