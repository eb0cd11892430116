"""League of Robot Runners instances run in MultiBots: our score against the best-known one.

    python3 benchmarks/lorr.py --instances DIR [--steps 5000] [--best-known FILE.csv]
                               [--scheduler greedy] [--seed 0] [--no-write]

Runs every problem JSON under DIR (recursively; the archive's instance files have no licence
and are never committed) with the default planner and the given scheduler, checks each
result with the competition's independent checker (``../shared/tools/lorr_check.py`` beside
the repository, when it is there), and prints a table: robots, steps, our
``numTaskFinished``, the best-known count and our share of it, planning ms per step (mean
and max), wall seconds and peak memory of the process. ``--best-known`` is a CSV of
``problem,finished`` (the problem file's name without ``.json``); the best-known counts of
the archive (MAPF-Competition/Benchmark-Archive) go there. The table is written to the
``lorr`` section of docs/benchmarks.md unless ``--no-write``.

The Start-Kit's own default planner on the same instances (built with cmake and Debian's
Boost) is not run by this script yet.
"""

from __future__ import annotations

import argparse
import csv
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CHECKER = ROOT.parent / "shared" / "tools" / "lorr_check.py"


def problems(folder: Path) -> list[Path]:
    """Problem JSONs under ``folder``: files with a ``mapFile`` key."""
    out = []
    for p in sorted(folder.rglob("*.json")):
        try:
            if "mapFile" in json.loads(p.read_text()):
                out.append(p)
        except (ValueError, UnicodeDecodeError):
            continue
    return out


def best_known(path: Path | None) -> dict[str, int]:
    if path is None:
        return {}
    with path.open() as f:
        return {row["problem"]: int(row["finished"]) for row in csv.DictReader(f)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--instances", type=Path, required=True)
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--best-known", type=Path)
    ap.add_argument("--scheduler", default="nearest")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "python"))
    from multibots import lorr

    best = best_known(args.best_known)
    head = [
        "| instance | rules | robots | steps | finished | best known | share | plan ms/step mean | max "
        "| wall s | checker |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |",
    ]
    lines = []
    for problem in problems(args.instances):
        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / "result.json"
            began = time.monotonic()
            r = lorr.run(problem, steps=args.steps, out=out, scheduler=args.scheduler, seed=args.seed)
            wall = time.monotonic() - began
            verdict = "not run"
            if CHECKER.is_file():
                argv = [sys.executable, str(CHECKER), str(problem), str(out)]
                p = subprocess.run(argv, capture_output=True, text=True)
                v = json.loads(p.stdout.strip().splitlines()[-1])
                verdict = "valid, same count" if v["valid"] and v["finished"] == r.finished else f"REFUSED: {v}"
        known = best.get(problem.stem)
        share = f"{100 * r.finished / known:.0f} %" if known else ""
        known_text = f"{known:,}" if known else ""
        f = r.figures
        lines.append(
            f"| {problem.stem} | {r.version} | {r.team_size:,} | {r.steps:,} | {r.finished:,} | "
            f"{known_text} | {share} | {f['plan_ms_mean']:.1f} | {f['plan_ms_max']:.0f} | {wall:.0f} | {verdict} |"
        )
        print(lines[-1], flush=True)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    note = f"\nPeak memory of the run: {peak:,.0f} MB. Planner pibt, scheduler {args.scheduler}, seed {args.seed}."
    if not args.no_write:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        import sections

        body = ["## League of Robot Runners instances (`benchmarks/lorr.py`)", "", *head, *lines, note]
        sections.put("lorr", "\n".join(body))


if __name__ == "__main__":
    main()
