"""Steady flow: does a fleet's throughput hold over a long overloaded run, and why not?

    .venv/bin/python benchmarks/flow.py CASE [CASE ...] [--steps 20000] [--traffic reserve]
        [--sample 50] [--detail]

A CASE is a name from CASES (the traffic benchmark's 1,000- and 10,000-robot warehouses, and
warehouses generated with other aisles, unloading rows, chargers and sizes that the traffic
rules were not tuned on), or `key=value,...` over a case's fields (`base=NAME` to start from
one). Each runs through the Python API for STEPS steps and prints: the 1,000-step delivery
windows; the worst window after the first 3,000 steps over the best one there (the
no-decline target: at least 0.75); the mean of those windows over the best window of the
first 3,000 steps (the no-collapse target: at least 0.5); contacts; and robot-steps per
second of the engine (the time in `step`, the Python sampling outside it).

With `--detail`, per window: the share of robot-steps spent waiting, robots in each state at
the window's end, the order backlog (queued for allocation, waiting for stock), and where the
robots that stood still while under way stood, sampled every SAMPLE steps: in front of which
kind of node (an unloading zone, a charger, a crossing) and the busiest nodes. It is the
outside view; the engine's own (resources, the bottleneck) follows at the end.

Prints figures; it is not a test.
"""

from __future__ import annotations

import argparse
import bisect
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from multibots import STATE_NAMES, Scenario, Simulation  # noqa: E402

#: Fields of a case: fleet, orders per step, and the generator's parameters (None: the
#: generator's default, "auto" for aisles and unloading rows).
FIELDS = ("robots", "rate", "rows", "cols", "width", "height", "aisles", "unloading", "chargers", "walls",
          "restock", "seed", "allocator", "placement", "unload")

CASES: dict[str, dict[str, Any]] = {
    # benchmarks/traffic.py's overloaded cases (the targets of issue 30).
    "1k": {"robots": 1000, "rate": 1.0, "rows": 12, "cols": 25, "width": 2, "height": 8, "aisles": "alternate",
           "unloading": 3, "chargers": 26},
    "10k": {"robots": 10000, "rate": 5.0, "rows": 30, "cols": 60, "width": 2, "height": 8, "aisles": "alternate",
            "unloading": 8, "chargers": 61},
    # Warehouses the traffic rules were not tuned on: the generator's automatic aisles and
    # unloading rows, other shapes, chargers on more walls, other seeds, other allocators.
    "wide": {"robots": 800, "rate": 1.0, "rows": 8, "cols": 40, "width": 1, "height": 6, "aisles": None,
             "unloading": None, "chargers": 41, "walls": "top-bottom", "seed": 7},
    "tall": {"robots": 1500, "rate": 1.5, "rows": 20, "cols": 15, "width": 2, "height": 10, "aisles": None,
             "unloading": 2, "chargers": 31, "walls": "all", "seed": 3},
    "one-row": {"robots": 600, "rate": 1.0, "rows": 6, "cols": 30, "width": 2, "height": 6, "aisles": None,
                "unloading": 1, "chargers": 20, "seed": 11, "restock": 300},
    "dense": {"robots": 3000, "rate": 3.0, "rows": 16, "cols": 36, "width": 2, "height": 8, "aisles": None,
              "unloading": 6, "chargers": 73, "walls": "top-bottom", "seed": 5, "restock": 50},
}

MOVING = tuple(STATE_NAMES.index(s) for s in ("TO_PICKUP", "TO_DROP", "TO_CHARGER", "TO_HOME"))


def parse_case(text: str) -> tuple[str, dict[str, Any]]:
    if "=" not in text:
        return text, dict(CASES[text])
    pairs = dict(p.split("=", 1) for p in text.split(","))
    case = dict(CASES[pairs.pop("base")]) if "base" in pairs else {}
    for key, value in pairs.items():
        if key not in FIELDS:
            raise SystemExit(f"unknown case field {key!r}; fields: {', '.join(FIELDS)}")
        case[key] = None if value == "auto" else value if not value.replace(".", "").isdigit() else (
            float(value) if "." in value else int(value))
    return text, case


def scenario(case: dict[str, Any], traffic: str, steps: int) -> Scenario:
    gen: dict[str, Any] = {"group_rows": case["rows"], "group_cols": case["cols"], "group_width": case["width"],
                           "group_height": case["height"], "chargers": case["chargers"]}
    if case.get("aisles"):
        gen["aisles"] = case["aisles"]
    if case.get("unloading"):
        gen["unloading_rows"] = case["unloading"]
    if case.get("walls"):
        gen["charger_walls"] = case["walls"]
    return Scenario.from_dict({
        "robots": case["robots"], "tasks": [], "placement": case.get("placement", "spread"),
        "unload": case.get("unload", "nearest"), "allocator": case.get("allocator", "nearest"), "traffic": traffic,
        "layout_generate": gen, "charging": {"chargers": "shared"}, "robot": {"consumption": 0.00002},
        "orders": {"rate": case["rate"], "horizon": steps, "restock": case.get("restock", 100),
                   "seed": case.get("seed", 1)},
    })


class Where:
    """Which node each robot drives towards, from its position and heading (aisles are
    axis-aligned): the first node ahead on its line."""

    def __init__(self, layout: dict[str, Any]) -> None:
        nodes = layout["nodes"]
        self.xy = np.array([(n["x"], n["y"]) for n in nodes])
        self.name = [n["name"] for n in nodes]
        self.kind = ["crossing"] * len(nodes)
        for k in layout["unloading"]:
            self.kind[k] = "unloading"
        for k in layout["chargers"]:
            self.kind[k] = "charger"
        self.rows: dict[int, tuple[list[float], list[int]]] = {}
        self.cols: dict[int, tuple[list[float], list[int]]] = {}
        for lines, key, along in ((self.rows, 1, 0), (self.cols, 0, 1)):
            for k in np.lexsort((self.xy[:, along], self.xy[:, key])):
                coords, ids = lines.setdefault(round(self.xy[k, key]), ([], []))
                coords.append(float(self.xy[k, along]))
                ids.append(int(k))

    def next_node(self, x: float, y: float, heading: float) -> int:
        dx, dy = round(np.cos(heading)), round(np.sin(heading))
        # Along a row (moving in x) or a column (moving in y): the line, the position on it,
        # and the direction along it.
        for lines, key, pos, step in ((self.rows, y, x, dx), (self.cols, x, y, dy)):
            if step == 0 or (dx != 0 and dy != 0):
                continue
            line = lines.get(round(key))
            if line is not None:
                coords, ids = line
                k = bisect.bisect_left(coords, pos - 1e-6) if step > 0 else bisect.bisect_right(coords, pos + 1e-6) - 1
                if 0 <= k < len(ids):
                    return ids[k]
        rel = self.xy - (x, y)
        return int(np.argmin(np.hypot(rel[:, 0], rel[:, 1])))


def run(label: str, case: dict[str, Any], traffic: str, steps: int, sample: int, detail: bool) -> dict[str, Any]:
    sim = Simulation(scenario(case, traffic, steps))
    where = Where(sim.layout) if detail else None
    n = sim.robot_count
    engine = 0.0
    rows = []
    last_wait = 0
    while not sim.done:
        waiters: Counter[int] = Counter()
        kinds: Counter[str] = Counter()
        still = 0
        for _ in range(1000 // sample):
            if sim.done:
                break
            t0 = time.perf_counter()
            sim.step(sample - 1 if detail else sample)
            engine += time.perf_counter() - t0
            if not detail:
                continue
            before = sim.positions.copy()
            t0 = time.perf_counter()
            sim.step(1)
            engine += time.perf_counter() - t0
            after, states, heads = sim.positions, sim.states, sim.headings
            stood = np.all(np.abs(after - before) < 1e-9, axis=1) & np.isin(states, MOVING)
            still += int(stood.sum())
            assert where is not None
            for i in np.flatnonzero(stood):
                v = where.next_node(after[i, 0], after[i, 1], heads[i])
                waiters[v] += 1
                kinds[where.kind[v]] += 1
        if not detail:
            continue
        r = sim.result()
        wait = int(r.wait_steps.sum())
        states = sim.states
        life = r.lifelong or {}
        samples = 1000 // sample
        assert where is not None
        rows.append({
            "t": sim.t, "window": r.windows[-1] if r.windows else None, "wait": (wait - last_wait) / (n * 1000),
            "states": {STATE_NAMES[s]: int((states == s).sum()) for s in np.unique(states)},
            "queued": life.get("queued"), "waiting": life.get("waiting"), "still": still / samples,
            "kinds": {k: round(v / samples, 1) for k, v in kinds.most_common()},
            "top": [(where.name[v], where.kind[v], round(c / samples, 1)) for v, c in waiters.most_common(4)],
        })
        last_wait = wait
    r = sim.result()
    w = r.windows
    early, after = w[:3], w[3:]
    best = max(after) if after else 0
    out = {
        "label": label, "robots": n, "windows": w, "worst/best": min(after) / best if best else 0.0,
        "mean/early": float(np.mean(after)) / max(early) if after and early and max(early) else 0.0,
        "contacts": r.contacts, "speed": n * r.steps / engine / 1e6, "wait": r.wait_share,
        "delivered": r.delivered, "bottleneck": r.bottleneck, "resources": r.resources,
    }
    print(f"== {label}  ({traffic}, {steps:,} steps, {n:,} robots)  {case}")
    print(f"windows {w}")
    print(f"worst/best after 3k {out['worst/best']:.2f}  mean-after-3k/best-first-3k {out['mean/early']:.2f}  "
          f"delivered {r.delivered:,}  waiting {r.wait_share:.1%}  contacts {r.contacts:,}  "
          f"{out['speed']:.2f} M robot-steps/s{' (sampling steps included)' if detail else ''}")
    for row in rows:
        print(f"  t={row['t']:>6} win={row['window']:>5} wait={row['wait']:.1%} still={row['still']:.0f} "
              f"queued={row['queued']} backlog={row['waiting']} {row['kinds']} top={row['top']} {row['states']}")
    if detail:
        # A lane's queue is part of its crossing's: the places themselves, not counted twice.
        busiest = sorted((u for u in r.resources if u["kind"] != "lane"), key=lambda x: -x["mean_queue"])[:6]
        print(f"  bottleneck {r.bottleneck}")
        print(f"  longest mean queues {busiest}")
    sys.stdout.flush()
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cases", nargs="+")
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--traffic", default="reserve")
    ap.add_argument("--sample", type=int, default=50)
    ap.add_argument("--detail", action="store_true")
    args = ap.parse_args()
    summary = []
    for text in args.cases:
        label, case = parse_case(text)
        summary.append(run(label, case, args.traffic, args.steps, args.sample, args.detail))
    print("\n| case | robots | worst/best after 3k | mean after 3k / best first 3k | delivered | waiting | contacts "
          "| robot-steps/s |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for s in summary:
        print(f"| {s['label']} | {s['robots']:,} | {s['worst/best']:.2f} | {s['mean/early']:.2f} | {s['delivered']:,} "
              f"| {s['wait']:.1%} | {s['contacts']:,} | {s['speed']:.2f} M |")


if __name__ == "__main__":
    main()
