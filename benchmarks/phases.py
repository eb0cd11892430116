"""The paper rules' step phase by phase: instructions per robot-step (callgrind) and the share
of the wall time, per named size and window of steps.

    .venv/bin/python benchmarks/phases.py [--sizes large,huge] [--windows early,jam]
        [--repeats 5] [--label now] [--write]

Uses the `phases` example (`cargo build --release -p multibots-core --features profiling
--example phases`), whose step runs each phase of `rules/paper/pipeline.rs` through the
`run(Phase::X, ..)` hook: timed, and inside a function of its own (`profile.rs`).
- Instructions: `valgrind --tool=callgrind --toggle-collect='*phases::measured*'` over the
  window's first `cg` steps (only the measured steps are counted), each phase the inclusive
  count of its function, over the robot-steps.
- Wall share: each phase's median time over `--repeats` runs of the window, over the sum of
  the medians (the machine is shared: a run that another process interrupts loses time in
  whichever phase it was in, so the median, not the mean).

Windows: `early` is steps 101..1100 (guard.py's first window), `jam` steps 10,001..11,000 of
the large size (almost every robot blocked), `late` steps 15,001..16,000 (robots queued for
chargers, others stuck behind them; the end of guard.py's 20,000 steps). Results go to
benchmarks/phases.json under `--label`; `--write` puts every label's table in
docs/benchmarks.md (section `phases`). Prints figures; it is not a test.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TARGET = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
PHASES = TARGET / "release" / "examples" / "phases"
STORE = ROOT / "benchmarks" / "phases.json"
#: The phases in the order the step runs them (the stored figures are keyed by name).
ORDER = ["Arrive", "HandOut", "Intend", "PeopleGuard", "Decide", "Travel", "Contacts", "PeopleWalk",
         "PeopleAloneWalk", "Tasks", "End"]
#: name: (warm-up steps, timed steps, steps counted by callgrind)
WINDOWS = {"early": (100, 1000, 300), "jam": (10000, 1000, 300), "late": (15000, 1000, 300)}


def build() -> None:
    cmd = ["cargo", "build", "-q", "--release", "-p", "multibots-core", "--features", "profiling", "--example",
           "phases"]
    subprocess.run(cmd, check=True, cwd=ROOT)


def wall(size: str, warmup: int, steps: int) -> dict:
    path = ROOT / "benchmarks" / "sizes" / f"{size}.toml"
    out = subprocess.run([str(PHASES), str(path), str(steps), str(warmup)], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.splitlines()[-1])


def instructions(size: str, warmup: int, steps: int) -> dict[str, float]:
    """Instructions per robot-step of each phase, and of the whole step (`total`)."""
    path = ROOT / "benchmarks" / "sizes" / f"{size}.toml"
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "cg.out"
        run = subprocess.run(["valgrind", "--tool=callgrind", "--toggle-collect=*phases::measured*",
                              f"--callgrind-out-file={out}", str(PHASES), str(path), str(steps), str(warmup)],
                             capture_output=True, text=True, check=True)
        robots = json.loads(run.stdout.splitlines()[-1])["robots"]
        ran = json.loads(run.stdout.splitlines()[-1])["steps"]
        text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--auto=no", "--threshold=100", str(out)],
                              capture_output=True, text=True, check=True).stdout
    per: dict[str, float] = {}
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+) \([^)]*\)\s+\S*?(phase_\w+|phases::measured)\b", line)
        if m:
            name = m.group(2)
            per[name] = per.get(name, 0) + int(m.group(1).replace(",", "")) / (robots * ran)
    return {("total" if k == "phases::measured" else camel(k[len("phase_"):])): v for k, v in per.items()}


def camel(snake: str) -> str:
    return "".join(w.capitalize() for w in snake.split("_"))


def measure(size: str, window: str, repeats: int) -> dict:
    warmup, steps, cg = WINDOWS[window]
    runs = [wall(size, warmup, steps) for _ in range(repeats)]
    names = [p["phase"] for p in runs[0]["phases"]]
    med = {n: statistics.median(r["phases"][k]["seconds"] for r in runs) for k, n in enumerate(names)}
    step = statistics.median(r["seconds"] for r in runs)
    robots = runs[0]["robots"]
    return {"size": size, "window": window, "robots": robots, "steps": steps, "warmup": warmup,
            "robot_steps_per_s": robots * runs[0]["steps"] / step, "wall": med, "wall_step": step,
            "instructions": instructions(size, warmup, cg), "cg_steps": cg, "repeats": repeats}


def table(rows: list[dict]) -> list[str]:
    """One Markdown table: a column pair (instructions, wall share) per measured case."""
    phases = [p for p in sorted(rows[0]["wall"], key=ORDER.index)
              if any(r["instructions"].get(p, 0) >= 0.5 or r["wall"][p] > 0 for r in rows)]
    head = "| phase | " + " | ".join(f"{r['label']}: {r['size']} {r['window']}, instr. | share" for r in rows) + " |"
    out = [head, "| --- |" + " ---: | ---: |" * len(rows)]
    for p in phases:
        cells = []
        for r in rows:
            inst = r["instructions"].get(p, 0.0)
            share = r["wall"][p] / sum(r["wall"].values())
            cells += [f"{inst:,.0f}", f"{100 * share:.0f}%"]
        if any(c not in ("0", "0%") for c in cells):
            out.append(f"| {p} | " + " | ".join(cells) + " |")
    cells = []
    for r in rows:
        cells += [f"**{r['instructions'].get('total', 0):,.0f}**", f"{r['robot_steps_per_s'] / 1e6:.1f} M/s"]
    out.append("| whole step | " + " | ".join(cells) + " |")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="large,huge")
    ap.add_argument("--windows", default="early")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--label", default="now", help="stored under this name in benchmarks/phases.json")
    ap.add_argument("--write", action="store_true", help="put every stored label's tables in docs/benchmarks.md")
    ap.add_argument("--no-measure", action="store_true", help="only --write what is stored")
    a = ap.parse_args()
    store = json.loads(STORE.read_text()) if STORE.exists() else {}
    if not a.no_measure:
        build()
        load = os.getloadavg()[0]
        for size in [s for s in a.sizes.split(",") if s]:
            for window in [w for w in a.windows.split(",") if w]:
                r = measure(size, window, a.repeats)
                r.update(label=a.label, load=load, when=time.time())
                store[f"{a.label}/{size}/{window}"] = r
                print("\n".join(table([r])), "\n", flush=True)
        STORE.write_text(json.dumps(store, indent=1, sort_keys=True) + "\n")
    if a.write:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        import sections

        lines = ["## The step phase by phase (benchmarks/phases.py)", "",
                 "Instructions per robot-step of each phase (callgrind, inclusive, the first "
                 "`cg_steps` of the window) and its share of the step's wall time (medians over "
                 "the repetitions), from the `phases` example built with `--features profiling`. "
                 "Labels are builds; rows are the phases of `rules/paper/pipeline.rs` (a fused pass "
                 "counts where the pipeline runs it).", ""]
        by_case: dict[tuple[str, str], list[dict]] = {}
        for r in store.values():
            by_case.setdefault((r["size"], r["window"]), []).append(r)
        for (size, window), rows in sorted(by_case.items()):
            rows.sort(key=lambda r: r["when"])
            lines.append(f"**{size}, {window}** (steps {rows[0]['warmup'] + 1:,}.."
                         f"{rows[0]['warmup'] + rows[0]['steps']:,}; load average "
                         + ", ".join(f"{r['label']} {r['load']:.1f}" for r in rows) + "):")
            lines.append("")
            lines += table(rows)
            lines.append("")
        sections.put("phases", "\n".join(lines))


if __name__ == "__main__":
    main()
