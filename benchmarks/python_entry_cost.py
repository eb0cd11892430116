"""What a Start-Kit Python scheduler costs beyond its own work, at 10,000 robots.

The Start-Kit's own default Python scheduler (``examples/lorr26/pyTaskScheduler.py``, v3.1.0,
MIT) schedules the 2026 example ``iron-example_10000`` (10,000 robots) through ``multibots
lorr --scheduler-py``. Its ``plan`` is timed from inside (its own work: its reads of ``env``
included), and the engine times the whole scheduler call (``schedule_ms`` of the run's
figures: the engine's copies, the call into Python, the answer read back and checked). The
difference, per call, is what MultiBots adds.

A second scheduler reads every field of ``env`` once per call and keeps the schedule: the
time each read takes at 10,000 robots (the fields are made Python objects on first read; the
Start-Kit copies them at each read too).

    python benchmarks/python_entry_cost.py [--problem P.json] [--ticks 300] [--repeat 3] [--write]

``--write`` puts the figures in docs/benchmarks.md (section ``python-entry``). Prints figures;
it is not a test.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from multibots import lorr

ROOT = Path(__file__).resolve().parent.parent
PROBLEM = ROOT.parent / "shared" / "reference" / "lorr" / "2026" / "iron_harvest.domain" / "iron-example_10000.json"
TEMPLATE = ROOT / "examples" / "lorr26" / "pyTaskScheduler.py"

# The template's class, its plan timed from inside; the times go to the file OWN_TIMES.
TIMED = """
import importlib.util, json, time

_spec = importlib.util.spec_from_file_location("start_kit_template", {template!r})
_template = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_template)


class pyTaskScheduler(_template.pyTaskScheduler):
    def plan(self, time_limit):
        began = time.perf_counter()
        out = super().plan(time_limit)
        with open({times!r}, "a") as f:
            f.write(json.dumps(time.perf_counter() - began) + "\\n")
        return out
"""

# Reads every field once per call and times each read; keeps the schedule in force.
READS = """
import json, time

FIELDS = ("curr_states", "system_states", "task_pool", "curr_task_schedule", "goal_locations",
          "new_tasks", "new_freeagents", "staged_actions")


class pyTaskScheduler:
    def initialize(self, preprocess_time_limit):
        pass

    def plan(self, time_limit):
        row = {{}}
        for name in FIELDS:
            began = time.perf_counter()
            value = getattr(self.env, name)
            row[name] = [time.perf_counter() - began, len(value)]
        with open({times!r}, "a") as f:
            f.write(json.dumps(row) + "\\n")
        return self.env.curr_task_schedule
"""


def run(problem: Path, ticks: int, source: str) -> tuple[dict, list]:
    with tempfile.TemporaryDirectory() as tmp:
        times = Path(tmp) / "times.jsonl"
        entry = Path(tmp) / "pyTaskScheduler.py"
        entry.write_text(source.format(template=str(TEMPLATE), times=str(times)), encoding="utf-8")
        result = lorr.run(problem, steps=ticks, scheduler_py=entry)
        rows = [json.loads(line) for line in times.read_text(encoding="utf-8").splitlines()]
    return result.figures, rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--problem", type=Path, default=PROBLEM)
    ap.add_argument("--ticks", type=int, default=300)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--write", action="store_true", help="put the figures in docs/benchmarks.md")
    args = ap.parse_args()
    team = json.loads(args.problem.read_text(encoding="utf-8")).get("teamSize")
    load = " ".join(f"{x:.1f}" for x in os.getloadavg())
    lines = [f"{args.problem.name}: {team} robots, {args.ticks} ticks, the Start-Kit's pyTaskScheduler.py"]
    print(lines[0])
    overheads, owns, calls = [], [], []
    for k in range(args.repeat):
        began = time.perf_counter()
        figures, own = run(args.problem, args.ticks, TIMED)
        wall = time.perf_counter() - began
        engine_ms = figures["schedule_ms_mean"]
        own_ms = statistics.mean(own) * 1e3
        overheads.append(engine_ms - own_ms)
        owns.append(own_ms)
        calls.append(len(own))
        lines.append(f"- run {k + 1}: {len(own)} calls, scheduler call {engine_ms:.3f} ms (engine-timed), its own "
                     f"plan {own_ms:.3f} ms, beyond its own work {engine_ms - own_ms:.3f} ms; "
                     f"{figures['finished']} tasks, wall {wall:.1f} s")
        print(lines[-1])
    lines.append(f"\n**Beyond its own work, median of {args.repeat} runs: {statistics.median(overheads):.2f} ms a "
                 f"call** (its own work {statistics.median(owns):.1f} ms).\n")
    print(lines[-1])
    _, reads = run(args.problem, args.ticks, READS)
    lines += ["First read of each field in a call, median over calls:", "",
              "| field | ms | length |", "| --- | ---: | ---: |"]
    for name in reads[0]:
        ms = statistics.median(r[name][0] for r in reads) * 1e3
        lines.append(f"| `env.{name}` | {ms:.2f} | {reads[-1][name][1]:,} |")
    print("\n".join(lines[-len(reads[0]) - 4:]))
    if args.write:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        import sections
        from run_all import describe, machine

        head = ["## A Start-Kit Python scheduler at 10,000 robots (docs/lorr.md)", "",
                f"- Command: `.venv/bin/python benchmarks/python_entry_cost.py --ticks {args.ticks} --repeat "
                f"{args.repeat} --write`",
                f"- Machine: {describe(machine())}; load {load} at the start.", ""]
        sections.put("python-entry", "\n".join(head + lines))


if __name__ == "__main__":
    main()
