"""Traffic policies at scale: sustained throughput against demand and fleet size, and speed.

    .venv/bin/python benchmarks/traffic.py [--sizes 100,1000,10000] [--steps 20000] [--policies wait,gate,reserve]

For each fleet size (a generated warehouse sized for it, built like scenarios/warehouse-1000.toml:
alternating aisles, unloading zones on several rows, nearest-robot allocation) and each order
rate from light load to overload, runs every traffic policy for STEPS steps and prints, as a
Markdown table: deliveries per 1,000 steps over the run and sustained over its last half,
the worst 1,000-step window after the first 3,000 steps as a share of the best one there,
the share of robot-steps spent waiting, contacts, and robot-steps per second (one thread,
wall clock, the machine's noise included). Prints figures; it is not a test.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from multibots import Scenario, simulate  # noqa: E402

#: Warehouse for each fleet size: (group rows, group columns, unloading rows), and the
#: order rates tried, orders per step (light load to overload).
SIZES = {
    100: ((4, 8, 2), (0.05, 0.1, 0.2, 0.4)),
    1000: ((12, 25, 3), (0.25, 0.5, 1.0, 2.0)),
    10000: ((30, 60, 8), (2.5, 5.0, 10.0, 20.0)),
}


def scenario(robots: int, rate: float, policy: str, steps: int) -> Scenario:
    (rows, cols, unloading), _ = SIZES[robots]
    return Scenario.from_dict({
        "robots": robots, "tasks": [], "placement": "spread", "unload": "nearest", "allocator": "nearest",
        "traffic": policy,
        "layout_generate": {"group_rows": rows, "group_cols": cols, "group_width": 2, "group_height": 8,
                            "chargers": cols + 1, "unloading_rows": unloading, "aisles": "alternate"},
        "charging": {"chargers": "shared"},
        "robot": {"consumption": 0.00002},
        "orders": {"rate": rate, "horizon": steps, "restock": 100, "seed": 1},
    })


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100,1000,10000")
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--policies", default="wait,gate,reserve")
    ap.add_argument("--write", action="store_true", help="also write the table into docs/benchmarks.md")
    args = ap.parse_args()
    lines = ["| robots | orders/step | policy | throughput | sustained | worst/best window after 3k | waiting "
             "| contacts | robot-steps/s |", "| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    print("\n".join(lines), flush=True)
    for robots in (int(s) for s in args.sizes.split(",")):
        for rate in SIZES[robots][1]:
            for policy in args.policies.split(","):
                s = scenario(robots, rate, policy, args.steps)
                t0 = time.perf_counter()
                r = simulate(s)
                secs = time.perf_counter() - t0
                after = r.windows[3:]
                ratio = min(after) / max(after) if after and max(after) > 0 else 0.0
                speed = robots * r.steps / secs / 1e6
                lines.append(f"| {robots:,} | {rate:g} | {policy} | {r.throughput:.1f} | {r.sustained_throughput:.1f} "
                             f"| {ratio:.2f} | {r.wait_share:.1%} | {r.contacts:,} | {speed:.2f} M |")
                print(lines[-1], flush=True)
    if args.write:
        import datetime

        import sections
        from run_all import describe, loadavg, machine

        head = [
            "## Traffic policies at scale (docs/traffic.md)",
            "",
            f"- Command: `.venv/bin/python benchmarks/traffic.py --sizes {args.sizes} --steps {args.steps} --write`",
            f"- Date (UTC): {datetime.datetime.now(datetime.timezone.utc).isoformat(timespec='seconds')}; machine: "
            f"{describe(machine())}; load average at the end: {loadavg():.2f}",
            f"- {args.steps:,} steps per run, one run each, one thread. Warehouses built like "
            "`scenarios/warehouse-1000.toml` for each fleet size; order rates from light load to overload. "
            "`throughput`: deliveries per 1,000 steps over the run; `sustained`: over the last half of its windows; "
            "`worst/best`: the worst 1,000-step window after the first 3,000 steps over the best one there. "
            "Speeds are single wall-clock runs on a shared machine: read them as orders of magnitude.",
            "",
        ]
        sections.put("traffic", "\n".join(head + lines))


if __name__ == "__main__":
    main()
