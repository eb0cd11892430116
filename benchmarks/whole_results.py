"""Whole results of 82 runs, hashed, for reviewers of engine changes that must not change
behaviour.

    .venv/bin/python benchmarks/whole_results.py > before.txt
    # change the engine, then `make develop`
    .venv/bin/python benchmarks/whole_results.py | diff before.txt -

Prints one line per run: its name and a hash of every field of its result (`Result.to_dict`),
so a change anywhere, not only in T, S and C, shows. The runs: small, large and huge with each
traffic policy (a few hundred to a few thousand steps), the small size's layout with 6, 20
and 32 robots and each policy (tiny fleets, with robots in bays), `scenarios/*.toml` with each policy,
the people size, the paper's 30 runs, and 24 random task lists at margins 0 and 8. It takes
about a minute. The fingerprints (`benchmarks/fingerprints.sh`) cover fewer runs but need no
Python build; `benchmarks/guard.py` compares speed.
"""

from __future__ import annotations

import hashlib
import json
import random
from pathlib import Path

import multibots as mb
from multibots import Scenario

ROOT = Path(__file__).resolve().parents[1]


def digest(result: mb.Result) -> str:
    return hashlib.sha256(json.dumps(result.to_dict(), sort_keys=True, default=str).encode()).hexdigest()[:16]


def cases() -> list[tuple[str, Scenario]]:
    out = []
    for size, limit in (("small", 3000), ("large", 600), ("huge", 150)):
        base = Scenario.from_toml(ROOT / "benchmarks" / "sizes" / f"{size}.toml")
        for traffic in ("wait", "gate", "reserve"):
            out.append((f"{size}-{traffic}", base.replace(traffic=traffic, step_limit=limit)))
    small = Scenario.from_toml(ROOT / "benchmarks" / "sizes" / "small.toml")
    for robots in (6, 20, 32):
        for traffic in ("wait", "gate", "reserve"):
            out.append((f"small{robots}-{traffic}", small.replace(robots=robots, traffic=traffic, step_limit=3000)))
    for name in ("paper", "people", "warehouse-1000"):
        base = Scenario.from_toml(ROOT / "scenarios" / f"{name}.toml")
        limit = 800 if name == "warehouse-1000" else 20000
        for traffic in ("wait", "gate", "reserve"):
            out.append((f"{name}-{traffic}", base.replace(traffic=traffic, step_limit=limit)))
    people = Scenario.from_toml(ROOT / "benchmarks" / "sizes" / "people.toml")
    out.append(("people-size", people.replace(step_limit=1500)))
    for group, goods in mb.PAPER_TASKS.items():
        for robots in mb.PAPER_ROBOTS:
            out.append((f"paper-{group}-{robots}", Scenario.paper(robots=robots, goods=list(goods))))
    rng = random.Random(7)
    for k in range(24):
        robots = rng.randint(1, 6)
        goods = rng.sample(range(80), rng.randint(5, 60))
        margin = float(rng.choice([0, 8]))
        scenario = Scenario.paper(robots=robots, goods=goods).replace(collision={"margin": margin, "angle": 30.0})
        out.append((f"random-{k}", scenario))
    return out


def main() -> None:
    for name, scenario in cases():
        print(name, digest(mb.simulate(scenario)), flush=True)


if __name__ == "__main__":
    main()
