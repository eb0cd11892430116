"""Cost per robot-step as fleets grow: the engine on one thread, from 30 to 30,000 robots.

    python3 benchmarks/curve.py [--repetitions 5] [--sizes 30 100 1000 3000 10000 30000]
                                [--steps 1000] [--warmup 100] [--perf]

Each size is a scenario file of benchmarks/sizes/ on a generated warehouse of matching size
(about 0.29 groups of 2 x 8 cells per robot, one order per 200 robots per step): curve-30,
small (100), large (1,000), curve-3000, huge (10,000), curve-30000. The largest layout
(60 x 144 groups, 8,845 crossings) stays under the generator's 10,000 crossings.

Every repetition runs each size once, in a fresh process of the `scale` example (warm-up
steps, then the timed window; the same window as benchmarks/scale.py and the criterion
bench), sizes interleaved so that a busy machine slows all of them alike. Prints the median
ns per robot-step of each size and its ratio to 1,000 robots.

With --perf, also `perf stat -e cache-misses,instructions,cycles` of the timed window per
robot-step: each size runs twice, with the window and without it (warm-up only), and the
difference is the window's.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SIZES = {30: "curve-30", 100: "small", 1000: "large", 3000: "curve-3000", 10000: "huge", 30000: "curve-30000"}
SCALE = ROOT / "target" / "release" / "examples" / "scale"
EVENTS = ("cache-misses", "instructions", "cycles")


def build() -> None:
    cmd = ["cargo", "build", "-q", "--release", "-p", "multibots-core", "--example", "scale"]
    subprocess.run(cmd, cwd=ROOT, check=True)


def scenario(n: int) -> str:
    return str(ROOT / "benchmarks" / "sizes" / f"{SIZES[n]}.toml")


def ns_per_robot_step(n: int, steps: int, warmup: int) -> float:
    """One timed window of size `n` in a fresh process."""
    out = subprocess.run([str(SCALE), scenario(n), str(steps), str(warmup)], capture_output=True, text=True, check=True)
    d = json.loads(out.stdout.strip().splitlines()[-1])
    return 1e9 / d["robot_steps_per_s"]


def perf_counts(n: int, steps: int, warmup: int) -> dict[str, float]:
    """Counter totals of one process (build, warm-up and `steps` timed steps)."""
    out = subprocess.run(
        ["perf", "stat", "-x,", "-e", ",".join(EVENTS), str(SCALE), scenario(n), str(steps), str(warmup)],
        capture_output=True,
        text=True,
        check=True,
    )
    counts = {}
    for line in out.stderr.splitlines():
        parts = line.split(",")
        if len(parts) > 2 and parts[2] in EVENTS and parts[0].strip().isdigit():
            counts[parts[2]] = float(parts[0])
    return counts


def perf_per_robot_step(n: int, steps: int, warmup: int, repetitions: int) -> dict[str, float]:
    """Medians of the window's counters per robot-step (with window minus without)."""
    per: dict[str, list[float]] = {e: [] for e in EVENTS}
    for _ in range(repetitions):
        full, base = perf_counts(n, steps, warmup), perf_counts(n, 0, warmup)
        for e in EVENTS:
            if e in full and e in base:
                per[e].append((full[e] - base[e]) / (n * steps))
    return {e: statistics.median(v) for e, v in per.items() if v}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--sizes", nargs="+", type=int, choices=sorted(SIZES), default=sorted(SIZES))
    ap.add_argument("--steps", type=int, default=1000, help="timed steps per window")
    ap.add_argument("--warmup", type=int, default=100)
    ap.add_argument("--perf", action="store_true", help="also perf stat counters per robot-step")
    a = ap.parse_args(argv)
    build()
    times: dict[int, list[float]] = {n: [] for n in a.sizes}
    for _ in range(a.repetitions):
        for n in a.sizes:
            times[n].append(ns_per_robot_step(n, a.steps, a.warmup))
    med = {n: statistics.median(v) for n, v in times.items()}
    ref = med.get(1000)
    print(f"steps {a.warmup + 1}..{a.warmup + a.steps}, one thread, median of {a.repetitions} interleaved repetitions")
    header = f"{'robots':>7} {'ns/robot-step':>14} {'min':>8} {'max':>8} {'vs 1,000':>9}"
    counters = {}
    if a.perf:
        counters = {n: perf_per_robot_step(n, a.steps, a.warmup, max(1, a.repetitions // 2)) for n in a.sizes}
    if a.perf:
        header += f" {'instr':>8} {'cycles':>8} {'IPC':>5} {'misses':>8}"
    print(header)
    for n in a.sizes:
        ratio = f"{med[n] / ref:9.2f}" if ref else f"{'-':>9}"
        line = f"{n:>7} {med[n]:14.1f} {min(times[n]):8.1f} {max(times[n]):8.1f} {ratio}"
        if a.perf:
            c = counters[n]
            ins, cyc, miss = c.get("instructions", 0.0), c.get("cycles", 0.0), c.get("cache-misses", 0.0)
            line += f" {ins:8.0f} {cyc:8.0f} {ins / cyc if cyc else 0:5.2f} {miss:8.2f}"
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
