"""What a Python strategy costs next to a Rust built-in.

The same rule (the paper's in-turn) runs as the Rust built-in and as a Python function, on
the paper's 30 runs (N = 1..6 x the five task lists of TABLE III), one thread. The engine
calls a strategy only at allocation events, so the Python overhead is per event: the script
prints the events per run, the cost per event and per run, and checks both give the same
T, S and C.

    python benchmarks/python_allocator_cost.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import time

from multibots import Scenario, simulate
from multibots.paper import PAPER_ROBOTS, PAPER_TASKS


def in_turn(view):
    return list(zip(view.idle.tolist(), view.goods.tolist()))


class Counting:
    """The Python in-turn, counting its calls."""

    name = "in-turn-py"

    def __init__(self) -> None:
        self.calls = 0

    def allocate(self, view):
        self.calls += 1
        return in_turn(view)


def heavier(view):
    """A Python rule that also queries the engine: the whole route-length matrix per event."""
    lengths = view.route_lengths()
    out, taken = {}, set()
    for i, robot in enumerate(view.idle.tolist()):
        free = [j for j in range(len(view.goods)) if j not in taken]
        if free:
            j = min(free, key=lambda j: lengths[i, j])
            taken.add(j)
            out[robot] = int(view.goods[j])
    return out


def time_runs(scenarios, allocator, repeat):
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        results = [simulate(s, allocator=allocator) for s in scenarios]
        best = min(best, time.perf_counter() - start)
    return best, results


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="repetitions; the fastest counts")
    args = ap.parse_args()
    scenarios = [Scenario.paper(robots=n, goods=cells) for n in PAPER_ROBOTS for cells in PAPER_TASKS.values()]
    counter = Counting()
    simulate(scenarios[0], allocator=counter)  # warm-up, and the import of everything
    counter.calls = 0
    for s in scenarios:
        simulate(s, allocator=counter)
    events = counter.calls
    rust, r1 = time_runs(scenarios, "in-turn", args.repeat)
    py, r2 = time_runs(scenarios, in_turn, args.repeat)
    heavy, _ = time_runs(scenarios, heavier, args.repeat)
    assert [(r.T, r.S, r.C) for r in r1] == [(r.T, r.S, r.C) for r in r2], "the Python in-turn must equal the built-in"
    runs = len(scenarios)
    steps = sum(r.steps for r in r1)
    print(f"{runs} runs (paper lists, N = 1..6), {steps} steps, {events} allocation events "
          f"({events / runs:.1f} per run, one per {steps / events:.0f} steps), best of {args.repeat}, one thread")
    print(f"{'strategy':<40} {'per run':>10} {'per event':>12} {'overhead per run':>17}")
    print(f"{'in-turn, Rust built-in':<40} {rust / runs * 1e3:>8.3f} ms {'-':>12} {'-':>17}")
    for label, t in (("in-turn, Python function", py), ("nearest-like, Python + route_lengths()", heavy)):
        over = (t - rust) / runs
        print(f"{label:<40} {t / runs * 1e3:>8.3f} ms {over * runs / events * 1e6:>9.1f} us {over * 1e3:>14.3f} ms")
    print(f"(same T, S and C for the Rust and Python in-turn on all {runs} runs; "
          f"median T = {statistics.median(r.T for r in r1)})")


if __name__ == "__main__":
    main()
