"""Charging at scale: does a fleet that must charge keep the warehouse working?

    .venv/bin/python benchmarks/charging.py SCENARIO.toml [--set charging.policy=staggered ...]
        [--traffic reserve] [--horizon 20000] [--sample 10]

Runs the scenario step by step and prints, as one block: deliveries per 1,000-step window,
C, the longest queue for shared chargers (robots in WAIT_CHARGER, sampled every SAMPLE
steps), robots charging or driving to charge at most, stranded robots, the outcome and the
contacts. `--set key.sub=value` changes one field (numbers and strings as TOML reads them),
so that one shipped scenario serves for every variant. Prints figures; it is not a test.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import tomllib

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from multibots import STATE_NAMES, Scenario, Simulation  # noqa: E402


def with_changes(data: dict[str, Any], changes: list[str]) -> dict[str, Any]:
    """The scenario's dictionary with each `key.sub=value` applied."""
    for change in changes:
        key, _, text = change.partition("=")
        value = tomllib.loads(f"v = {text}")["v"]
        *path, last = key.split(".")
        table = data
        for part in path:
            table = table.setdefault(part, {})
        table[last] = value
    return data


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenario", type=Path)
    ap.add_argument("--set", dest="changes", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--traffic", default=None)
    ap.add_argument("--horizon", type=int, default=None)
    ap.add_argument("--sample", type=int, default=10)
    args = ap.parse_args()
    data = with_changes(Scenario.from_toml(args.scenario).to_dict(), args.changes)
    if args.traffic:
        data["traffic"] = args.traffic
    if args.horizon:
        data.setdefault("orders", {})["horizon"] = args.horizon
    sim = Simulation(Scenario.from_dict(data))
    wait, charging = STATE_NAMES.index("WAIT_CHARGER"), (STATE_NAMES.index("TO_CHARGER"), STATE_NAMES.index("CHARGING"))
    longest_queue = most_charging = 0
    start = time.perf_counter()
    while not sim.done:
        sim.step(args.sample)
        states = sim.states
        longest_queue = max(longest_queue, int((states == wait).sum()))
        most_charging = max(most_charging, int(((states == charging[0]) | (states == charging[1])).sum()))
    seconds = time.perf_counter() - start
    r = sim.result()
    print(f"scenario {args.scenario} {' '.join(args.changes)} traffic={data.get('traffic', 'wait')}")
    print(f"windows {r.windows}")
    print(f"C {r.C}  longest charger queue {longest_queue}  charging or going at most {most_charging}  "
          f"stranded {len(r.stranded) if isinstance(r.stranded, list) else r.stranded}  zero windows "
          f"{sum(1 for w in r.windows if w == 0)}  min window after 1,000 steps {min(r.windows[1:], default=None)}")
    print(f"outcome {r.outcome}  delivered {r.delivered}  contacts {r.contacts}  ({seconds:.0f} s)")


if __name__ == "__main__":
    main()
