"""All benchmarks of the project in one run; prints the table and writes docs/benchmarks.md.

    .venv/bin/python benchmarks/run_all.py [--repetitions 5] [--no-peers] [--out docs/benchmarks.md]

`make bench` runs the criterion bench first (cargo bench -p multibots-bench --bench step --
--quick) and then this script, which also quotes criterion's medians when it finds them in
target/criterion. What it measures:

1. robot-steps per second at the named sizes paper (N = 6), small (100), large (1,000),
   huge (10,000), through the Python API on one thread (benchmarks/scale.py);
2. memory per robot at each size (fresh subprocesses, benchmarks/scale.py);
3. the engine time of the paper's 30-run experiment on one thread;
4. the paper scenario against the plain pure-Python model (benchmarks/pure_python.py);
5. the peers rware 2.0.0 and pogema 1.4.0 with random actions, in their own virtual
   environment .venv-peers, at the same agent counts and our free cells per agent, with and
   without their observations, in agent-steps and cell moves per second, interleaved with
   our own runs (benchmarks/peers.py), in the same run;
6. the learning environments' decisions per second beside the peers' env steps per second
   (benchmarks/envs.py).

The machine is shared and noisy: every speed is the median of repetitions, and the load
average is recorded next to the figures.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Optional

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

import envs  # noqa: E402
import peers  # noqa: E402
import pure_python  # noqa: E402
import scale  # noqa: E402
from multibots._io import atomic_write_text  # noqa: E402

AGENT_COUNTS = (6, 100, 1000, 10000)
SIZE_OF = {6: "paper", 100: "small", 1000: "large", 10000: "huge"}
TARGETS = {"large": 10e6, "huge": 5e6, "paper": 10e6}


def describe(m: dict[str, Any]) -> str:
    """One line for a machine from :func:`machine`."""
    return (f"{m.get('cpu_model')}, {m.get('lscpu_cpus')} CPUs ({m.get('cores_per_socket')} cores per socket, "
            f"{m.get('threads_per_core')} threads per core), {m['platform']}, Python {m['python']}")


def machine() -> dict[str, Any]:
    info: dict[str, Any] = {
        "platform": platform.platform(),
        "python": platform.python_version(),
        "cpus": os.cpu_count(),
    }
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        fields = {k.strip(): v.strip() for k, v in (ln.split(":", 1) for ln in out.splitlines() if ":" in ln)}
        info["cpu_model"] = fields.get("Model name", "unknown")
        info["cores_per_socket"] = fields.get("Core(s) per socket")
        info["threads_per_core"] = fields.get("Thread(s) per core")
        info["lscpu_cpus"] = fields.get("CPU(s)")
    except (OSError, subprocess.CalledProcessError):
        info["cpu_model"] = "unknown (lscpu missing)"
    return info


def loadavg() -> Optional[float]:
    try:
        return round(os.getloadavg()[0], 2)
    except OSError:
        return None


def criterion_medians() -> dict[str, float]:
    """Median times (ns) of the criterion bench, from target/criterion, where present."""
    out = {}
    base = ROOT / "target" / "criterion"
    for group, bench in [
        ("paper", "run"),
        ("paper", "experiment-30"),
        ("step", "small"),
        ("step", "large"),
        ("step", "huge"),
    ]:
        f = base / group / bench / "new" / "estimates.json"
        if f.exists():
            try:
                out[f"{group}/{bench}"] = json.loads(f.read_text())["median"]["point_estimate"]
            except (KeyError, ValueError):
                pass
    return out


def fmt_rate(x: Optional[float]) -> str:
    if x is None:
        return "n/a"
    return f"{x / 1e6:.2f} M" if x >= 1e6 else f"{x:,.0f}"


def fmt_ratio(a: Optional[float], b: Optional[float]) -> str:
    return "n/a" if not a or not b else f"{a / b:,.0f}x" if a / b >= 10 else f"{a / b:.1f}x"


def build_markdown(d: dict[str, Any]) -> str:
    m = d["machine"]
    lines = [
        "# Benchmarks",
        "",
        "Written by `benchmarks/run_all.py` (run by `make bench`); do not edit by hand.",
        "",
        f"- Command: `{d['command']}` (after `cargo bench -p multibots-bench --bench step -- --quick`)",
        f"- Date (UTC): {d['created_utc']}; total {d['total_seconds']:.0f} s",
        f"- Machine: {describe(m)}",
        f"- Load average (1 min) at start / end: {d['load'][0]} / {d['load'][1]}. The machine is shared: every speed is a median of {d['repetitions']} repetitions, one thread.",
        "",
        "## Engine speed and memory (named sizes, one thread)",
        "",
        "Sizes are the scenario files in `benchmarks/sizes/`, shared with the criterion bench. "
        "paper: whole runs of the paper scenario (N = 6, task list group 1), 6 × T robot-steps per run. "
        "small / large / huge: steps 101..1100 of a fresh lifelong fleet (spread placement, shared chargers, nearest unloading zone) on a generated warehouse of matching size. "
        "Memory per robot: resident memory after 100 steps with N robots minus the same layout with N/2 robots, over N/2 (the marginal cost of a robot); the routing table is shared by all robots of a layout.",
        "",
        "| size | robots | layout nodes | robot-steps/s (median, Python API) | criterion median | target | memory per robot | routing table | peak RSS of the process |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    crit = d.get("criterion", {})
    for r in d["scale"]:
        name = r["size"]
        mem = next(x for x in d["memory"] if x["size"] == name)
        key = "paper/run" if name == "paper" else f"step/{name}"
        c = crit.get(key)
        crit_rate = None
        if c:
            per_iter = d["paper_robot_steps"] if name == "paper" else r["robots"]
            crit_rate = per_iter / (c / 1e9)
        target = TARGETS.get(name)
        # Resident memory moves in 4 KiB pages, and the allocator reuses memory freed while
        # the layout's tables were built: below some 10,000 robots the fleet's growth is
        # within that noise (the difference can even come out negative).
        mem_txt = (
            "n/a (6 robots)"
            if name == "paper"
            else f"{mem['bytes_per_robot']:,.0f} B"
            if r["robots"] >= 10_000 and mem["bytes_per_robot"] > 0
            else "below allocator noise"
        )
        lines.append(
            f"| {name} | {r['robots']:,} | {mem['nodes']:,} | {fmt_rate(r['robot_steps_per_s'])} | {fmt_rate(crit_rate)} | "
            f"{'≥ ' + fmt_rate(target) if target else ''} | {mem_txt} | {mem['routing_table_bytes'] / 1e6:.2f} MB | {mem['peak_rss_mb']:.0f} MB |"
        )
    e = d["experiment_30"]
    c30 = crit.get("paper/experiment-30")
    lines += [
        "",
        f"**The paper's 30-run experiment** (N = 1..6 × TABLE III): {e['ms']:.1f} ms engine time on one thread (median of {e['repetitions']}; min {e['min_ms']:.1f}, max {e['max_ms']:.1f})"
        + (f", criterion median {c30 / 1e6:.1f} ms" if c30 else "")
        + f"; target < 50 ms. That is {e['robot_steps']:,} robot-steps, {fmt_rate(e['robot_steps_per_s'])} robot-steps/s.",
        "",
        "## Against a plain pure-Python implementation of the same model",
        "",
    ]
    p = d["pure_python"]
    e = d.get("pure_python_experiment")
    if e:
        lines += [
            f"**The paper's {e['runs']}-run experiment** (N = 1..6 × TABLE III, {e['robot_steps']:,} robot-steps; T, S and C "
            f"equal on every run): the pure-Python model {e['python_ms']:,.0f} ms, the Python API "
            f"(`simulate_many(..., workers=1)`) {e['engine_ms']:.1f} ms (median of {e['engine_calls']} calls interleaved "
            f"with {e['repetitions']} pure-Python runs; best {e['engine_min_ms']:.1f} ms): **{e['ratio']:,.0f}x** "
            f"({e['best_ratio']:,.0f}x with the best engine time); target ≥ 100x.",
            "",
        ]
    lines += [
        f"Paper scenario (N = 6, group 1; both give T = {p['T']}, S = {p['S']}, C = {p['C']}): `tests/oracle/reference_model.py` "
        f"{fmt_rate(p['python_robot_steps_per_s'])} robot-steps/s, the engine {fmt_rate(p['engine_robot_steps_per_s'])}: **{fmt_ratio(p['engine_robot_steps_per_s'], p['python_robot_steps_per_s'])}**.",
        "",
    ]
    if d.get("peers"):
        lines += peers.markdown(d["peers"])
    else:
        lines += ["## Side by side with rware and pogema", "", "Not measured in this run (`--no-peers`)."]
    if d.get("envs"):
        lines += ["", *envs.markdown(d["envs"])]
    lines += [
        "",
        "## How to reproduce",
        "",
        "```",
        "make bench                                   # criterion (--quick) + this script",
        "cargo bench -p multibots-bench --bench step   # the criterion bench alone, full length",
        ".venv/bin/python benchmarks/scale.py         # sizes and memory",
        ".venv/bin/python benchmarks/pure_python.py   # ratio to the pure-Python model",
        ".venv/bin/python benchmarks/peers.py         # rware and pogema alone",
        ".venv/bin/python benchmarks/envs.py          # the learning environments",
        ".venv/bin/python benchmarks/guard.py         # speed against an earlier build (docs: the issue 15 section)",
        ".venv/bin/python benchmarks/whole_results.py # every field of 82 runs, hashed: diff before and after a change",
        "```",
        "",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--no-peers", action="store_true", help="skip rware and pogema (about 3 minutes)")
    ap.add_argument("--peer-repetitions", type=int, default=5)
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks.md")
    ap.add_argument("--json", type=Path, default=ROOT / "benchmarks" / "results" / "run_all.json", dest="json_path")
    a = ap.parse_args(argv)

    started = time.perf_counter()
    d: dict[str, Any] = {
        "kind": "multibots-benchmarks",
        "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "command": " ".join([".venv/bin/python", os.path.relpath(Path(sys.argv[0]).resolve(), ROOT), *sys.argv[1:]]),
        "machine": machine(),
        "repetitions": a.repetitions,
    }
    load0 = loadavg()
    print("engine speed at the named sizes ...", file=sys.stderr, flush=True)
    d["scale"] = [scale.robot_steps_per_s(n, a.repetitions) for n in scale.SIZES]
    d["memory"] = [scale.memory_per_robot(n) for n in scale.SIZES]
    d["experiment_30"] = scale.experiment_30_ms()
    from multibots import PAPER_TASKS, Scenario, simulate

    d["paper_robot_steps"] = 6 * simulate(Scenario.paper(robots=6, goods=PAPER_TASKS[1])).steps
    print("pure-Python model ...", file=sys.stderr, flush=True)
    d["pure_python"] = pure_python.measure(a.repetitions)
    d["pure_python_experiment"] = pure_python.measure_experiment(3)
    d["criterion"] = criterion_medians()
    if not a.no_peers:
        print("peers (rware, pogema) in .venv-peers ...", file=sys.stderr, flush=True)
        d["peers"] = peers.compare(AGENT_COUNTS, repetitions=a.peer_repetitions)
    print("learning environments ...", file=sys.stderr, flush=True)
    d["envs"] = envs.measure(with_peers=not a.no_peers)
    d["load"] = [load0, loadavg()]
    d["total_seconds"] = time.perf_counter() - started
    md = build_markdown(d)
    # Sections other scripts write (traffic, studies, ...) are kept.
    import sections

    md = sections.keep(md, a.out.read_text(encoding="utf-8") if a.out.exists() else "")
    peers.write_json_atomic(a.json_path, d)
    atomic_write_text(a.out, md)
    print(md)
    print(f"\nwrote {a.out} and {a.json_path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
