"""The engine against a plain pure-Python implementation of the same model, on the paper.

    .venv/bin/python benchmarks/pure_python.py [--repetitions 5]

Both run the paper scenario (N = 6 robots, task list group 1) from start to T, and must give
the same T, S and C (checked here). Speed is robot-steps per second (6 x T per run), the
median over repetitions; the ratio is engine / pure Python. tests/oracle/reference_model.py is
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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repetitions", type=int, default=5)
    a = ap.parse_args(argv)
    r = measure(a.repetitions)
    print(f"paper scenario (N = 6, group 1): T = {r['T']}, S = {r['S']}, C = {r['C']} in both")
    print(
        f"pure Python {r['python_robot_steps_per_s']:,.0f} robot-steps/s, "
        f"engine {r['engine_robot_steps_per_s']:,.0f}: ratio {r['ratio']:,.0f}x"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
