"""Sweeps at scale (docs/sweeps.md): the polling floor, workers, Ray and the store's cost.

    .venv/bin/python benchmarks/sweep.py [--runs 10000] [--write]

1. The paper's 30 runs through `simulate_many` (one thread) against the engine's own time
   (the same runs one `simulate` call each): target within 1.2x.
2. A sweep of RUNS paper-scenario runs (random task lists of 10 goods, N = 1..6): 1 worker
   against 2 (target at least 1.8x), and the Ray backend on this machine against the local
   one (target within 1.5x), with a cluster already running (as `--ray-address` uses one)
   and, for information, with the sweep starting its own.
3. The store's cost (keys, the reuse lookup, the part files, the read back) against
   `simulate_many` of the same runs on 1 thread (target below 5%); and, for information, the
   whole sweep on 1 worker (planning and validation too) against the same.
Medians of interleaved pairs (--repeats); prints figures, it is not a test.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

import multibots  # noqa: E402
from multibots import _core  # noqa: E402
from multibots.paper import PAPER_TASKS  # noqa: E402


def timed(f) -> float:
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


def median_of(f, n: int = 3) -> float:
    return statistics.median(timed(f) for _ in range(n))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=10_000)
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--repeats", type=int, default=5, help="interleaved pairs per ratio")
    a = ap.parse_args()
    paper = [multibots.Scenario.paper(robots=n, goods=list(g))._core for n in range(1, 7) for g in PAPER_TASKS.values()]
    engine = median_of(lambda: [_core.simulate(s) for s in paper], 5)
    many = median_of(lambda: _core.simulate_many(paper, 1), 5)
    seeds = max(1, a.runs // 6)
    spec = {"base": {"layout": "paper", "robots": 1, "tasks": {"random": 10, "seed": 1}},
            "axes": {"robots": [1, 2, 3, 4, 5, 6], "seed": list(range(1, seeds + 1))}}
    n = 6 * seeds
    points = multibots.sweeps.parse_spec(spec).points()
    cores = [p.scenario._core for p in points]
    bare = median_of(lambda: _core.simulate_many(cores, 1))

    def sweep(workers: int, backend: str = "local") -> float:
        out = Path(tempfile.mkdtemp(prefix="mb-sweep-bench-"))
        try:
            return timed(lambda: multibots.sweep(spec, out, workers=workers, backend=backend))
        finally:
            shutil.rmtree(out, ignore_errors=True)

    def store_alone() -> float:
        """What the store adds to running the same runs: their keys, the reuse lookup, the
        part files written in the sweep's batch sizes (the figures taken from the results too),
        the read back."""
        from multibots.sweeps.runner import figures_of, keys_of
        from multibots.sweeps.store import Store

        raws = _core.simulate_many(cores, 1)
        out = Path(tempfile.mkdtemp(prefix="mb-store-bench-"))
        try:
            t0 = time.perf_counter()
            store = Store(out)
            keys = keys_of(points)
            store.keys()
            batch = 2000  # about FLUSH_SECONDS of runs on one worker
            for b in range(0, len(points), batch):
                ks = range(b, min(b + batch, len(points)))
                store.write([points[k] for k in ks], [keys[k] for k in ks], [figures_of(raws[k]) for k in ks])
            store.frame()
            return time.perf_counter() - t0
        finally:
            shutil.rmtree(out, ignore_errors=True)

    store = statistics.median(store_alone() for _ in range(3))
    # Interleaved, so that a busy spell on the shared machine hits both sides alike.
    ones, twos, bare_ones, bare_twos = [], [], [], []
    for _ in range(a.repeats):
        ones.append(sweep(1))
        twos.append(sweep(2))
        # The ceiling: the engine alone on one thread and on two.
        bare_ones.append(timed(lambda: _core.simulate_many(cores, 1)))
        bare_twos.append(timed(lambda: _core.simulate_many(cores, 2)))
    one, two = statistics.median(ones), statistics.median(twos)
    bare1, bare2 = statistics.median(bare_ones), statistics.median(bare_twos)
    ray = cold = two_again = None
    try:
        import ray as _ray

        # Cold: the sweep starts a local cluster and stops it again.
        cold = sweep(2, "ray")
        # Running: a cluster already up (as with --ray-address), its workers started.
        _ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, _node_ip_address="127.0.0.1")
        sweep(2, "ray")
        rays, locals_ = [], []
        for _ in range(a.repeats):
            rays.append(sweep(2, "ray"))
            locals_.append(sweep(2))
        ray, two_again = statistics.median(rays), statistics.median(locals_)
        _ray.shutdown()
    except ImportError:
        pass
    lines = [
        "| figure | value | target |",
        "| --- | ---: | --- |",
        f"| paper's 30 runs: `simulate_many` (1 thread) / one `simulate` each | {many * 1e3:.1f} ms / "
        f"{engine * 1e3:.1f} ms = {many / engine:.2f} | at most 1.2 |",
        f"| {n:,}-run sweep, 1 worker / 2 workers | {one:.2f} s / {two:.2f} s = {one / two:.2f}x | at least 1.8x |",
        f"| the ceiling: `simulate_many` of the same runs alone, 1 thread / 2 threads | {bare1:.2f} s / {bare2:.2f} s "
        f"= {bare1 / bare2:.2f}x | – |",
        "| same, Ray on this machine, cluster running (2 CPUs) / local (2 workers) | "
        + (f"{ray:.2f} s / {two_again:.2f} s = {ray / two_again:.2f} |" if ray else "ray not installed |")
        + " at most 1.5 |",
        "| same, Ray starting and stopping its cluster in the sweep / local (2 workers) | "
        + (f"{cold:.2f} s / {two:.2f} s = {cold / two:.2f} |" if cold else "ray not installed |") + " – |",
        f"| store's cost: keys, lookup, part files, read back / `simulate_many` of the runs (1 thread) | "
        f"{store:.3f} s / {bare:.2f} s = {store / bare:.1%} | below 5% |",
        f"| everything: sweep (1 worker) / `simulate_many` of its scenarios (1 thread) | {one:.2f} s / "
        f"{bare:.2f} s = {one / bare:.3f} | – |",
    ]
    print("\n".join(lines))
    if a.write:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        import sections
        from run_all import describe, machine

        head = ["## Sweeps (docs/sweeps.md)", "",
                f"- Command: `.venv/bin/python benchmarks/sweep.py --runs {a.runs} --write`",
                f"- Machine: {describe(machine())}; medians of {a.repeats} interleaved pairs (3 for the store, "
                "5 for the 30 runs).", ""]
        sections.put("sweep", "\n".join(head + lines))


if __name__ == "__main__":
    main()
