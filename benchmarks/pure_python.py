"""The engine against a plain pure-Python implementation of the same model, on the paper.

    .venv/bin/python benchmarks/pure_python.py [--repetitions 5]

Two figures. The paper's whole 30-run experiment (N = 1..6 x TABLE III's five lists), the
pure-Python model's runs one after the other against the Python API's
``simulate_many(..., workers=1)``, interleaved, every run's T, S and C checked equal; the
ratio of the median times (issue 15's target: 100x). And one run (N = 6, group 1), in
robot-steps per second (6 x T per run) against the engine's `scale` figure. tests/oracle/reference_model.py is
written to be read, not to be fast: the ratio measures what the Rust engine buys over a
straightforward Python program of the spec, not over the best possible Python.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
# The reference model is one of the tests' oracles (tests/oracle/).
sys.path.insert(0, str(HERE.parent / "tests"))

ROBOTS = 6


def measure(repetitions: int = 5) -> dict[str, Any]:
    from multibots import PAPER_TASKS, Scenario, simulate
    from scale import robot_steps_per_s

    from oracle import reference_model

    GOODS = list(PAPER_TASKS[1])
    engine = simulate(Scenario.paper(robots=ROBOTS, goods=GOODS))
    ref = reference_model.run(GOODS, robots=ROBOTS)
    same = (ref["T"], ref["S"], ref["C"]) == (engine.T, engine.S, engine.C)
    if not same:
        raise RuntimeError(
            f"the models disagree: reference {ref['T'], ref['S'], ref['C']}, engine {engine.T, engine.S, engine.C}"
        )
    rates = []
    for _ in range(repetitions):
        t0 = time.perf_counter()
        r = reference_model.run(GOODS, robots=ROBOTS)
        rates.append(ROBOTS * r["T"] / (time.perf_counter() - t0))
    py = statistics.median(rates)
    eng = robot_steps_per_s("paper", repetitions)["robot_steps_per_s"]
    return {
        "T": engine.T,
        "S": engine.S,
        "C": engine.C,
        "python_robot_steps_per_s": py,
        "engine_robot_steps_per_s": eng,
        "ratio": eng / py,
        "repetitions": repetitions,
    }


def measure_experiment(repetitions: int = 3, engine_calls: int = 7) -> dict[str, Any]:
    """The 30-run experiment both ways, interleaved: each repetition runs the pure-Python
    model once (about a second) and the Python API ``engine_calls`` times around it."""
    from multibots import PAPER_TASKS, Scenario, simulate, simulate_many

    from oracle import reference_model

    runs = [(n, list(g)) for n in range(1, 7) for g in PAPER_TASKS.values()]
    scenarios = [Scenario.paper(robots=n, goods=g) for n, g in runs]
    py_s: list[float] = []
    eng_s: list[float] = []
    # Each run a separate `simulate` call, as a study that runs one at a time does (issue 44):
    # with the scenarios made beforehand, and with each made in the call's turn.
    one_s: list[float] = []
    made_s: list[float] = []

    def engine() -> list[Any]:
        t0 = time.perf_counter()
        out = simulate_many(scenarios, workers=1)
        eng_s.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        for sc in scenarios:
            simulate(sc)
        one_s.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        for n, g in runs:
            simulate(Scenario.paper(robots=n, goods=g))
        made_s.append(time.perf_counter() - t0)
        return out

    for _ in range(repetitions):
        for _ in range(engine_calls // 2):
            results = engine()
        t0 = time.perf_counter()
        refs = [reference_model.run(g, robots=n) for n, g in runs]
        py_s.append(time.perf_counter() - t0)
        for _ in range(engine_calls - engine_calls // 2):
            results = engine()
        for (n, g), ref, r in zip(runs, refs, results):
            if (ref["T"], ref["S"], ref["C"]) != (r.T, r.S, r.C):
                raise RuntimeError(f"N = {n}, goods {g}: reference {ref['T'], ref['S'], ref['C']}, "
                                   f"engine {r.T, r.S, r.C}")
    py, eng = statistics.median(py_s), statistics.median(eng_s)
    robot_steps = sum(n * r.steps for (n, _), r in zip(runs, results))
    return {"runs": len(runs), "robot_steps": robot_steps, "python_ms": py * 1000, "engine_ms": eng * 1000,
            "engine_min_ms": min(eng_s) * 1000, "ratio": py / eng, "best_ratio": py / min(eng_s),
            "separate_ms": statistics.median(one_s) * 1000, "separate_ratio": py / statistics.median(one_s),
            "made_ms": statistics.median(made_s) * 1000, "made_ratio": py / statistics.median(made_s),
            "repetitions": repetitions, "engine_calls": engine_calls * repetitions}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repetitions", type=int, default=5)
    a = ap.parse_args(argv)
    e = measure_experiment(max(1, a.repetitions // 2 + 1))
    print(f"the paper's {e['runs']}-run experiment ({e['robot_steps']:,} robot-steps), T, S and C equal on every run: "
          f"pure Python {e['python_ms']:,.0f} ms, Python API {e['engine_ms']:.1f} ms (median; best "
          f"{e['engine_min_ms']:.1f}): ratio {e['ratio']:,.0f}x (with the best engine time {e['best_ratio']:,.0f}x)")
    print(f"  each run a separate simulate call: {e['separate_ms']:.1f} ms, {e['separate_ratio']:,.0f}x; with each "
          f"Scenario.paper made in its turn: {e['made_ms']:.1f} ms, {e['made_ratio']:,.0f}x")
    r = measure(a.repetitions)
    print(f"paper scenario (N = 6, group 1): T = {r['T']}, S = {r['S']}, C = {r['C']} in both")
    print(
        f"pure Python {r['python_robot_steps_per_s']:,.0f} robot-steps/s, "
        f"engine {r['engine_robot_steps_per_s']:,.0f}: ratio {r['ratio']:,.0f}x"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
