"""Side by side with two public multi-agent grid simulators, rware and pogema, like for like.

    .venv/bin/python benchmarks/peers.py [--agents 6 100 1000 10000] [--peers pogema rware] [--json PATH]

For each agent count N with a named size (paper 6, small 100, large 1,000, huge 10,000
robots; benchmarks/sizes/*.toml) it measures, interleaved on the same machine:

- ours: robot-steps per second and cell moves per second of that size, through the
  `scale` example (target/release/examples/scale, built here if missing), one thread,
  steps 101..1100 (the window of benchmarks/scale.py and the criterion bench);
- each peer with N agents at *our* density (the same free cells per agent), with its
  per-agent observations and without them, in agent-steps and cell moves per second
  (benchmarks/peer_worker.py, one subprocess per peer and agent count).

Definitions (docs/benchmarks.md, "Side by side with rware and pogema"):

- A cell is our layout's grid unit, 50 px: the cell size of the storage cells, the width
  of an aisle and the spacing of parking slots. Our free cells are the 50 x 50 px squares
  of aisle: the warehouse rectangle in cells minus the storage cells (chargers, 40 px
  outside it, are not counted). The named sizes give 16.0 (paper), 4.13 (small), 3.48
  (large) and 3.22 (huge) free cells per robot.
- Our robot-step moves a robot at most 4 px = 0.08 cell; a cell move is 50 px driven. Our
  cell moves per second = distance the fleet drove in the timed window / 50 px / wall
  seconds (the engine's per-robot distance, summed; waiting and parked robots add none).
- A peer's agent-step moves an agent by one cell or not at all; its cell moves are
  counted from positions before and after each step (see peer_worker.py).

The peers pin numpy<2, pydantic 1 and gymnasium 0.28, which clash with the project's own
dependencies, so they live in a separate virtual environment, .venv-peers at the
repository root, created (or reused) here with exact pins from PyPI. Every measurement
runs in its own subprocess of that environment, one at a time, so peers never share a
process, a heap or a core with each other or with us.

This module uses the standard library only (and the project's atomic writer, when it
writes its JSON); importing it has no side effects.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

import tomllib

ROOT = Path(__file__).resolve().parent.parent
WORKER = Path(__file__).resolve().parent / "peer_worker.py"
SIZES_DIR = ROOT / "benchmarks" / "sizes"
SCALE_BIN = ROOT / "target" / "release" / "examples" / "scale"
DEFAULT_VENV = ROOT / ".venv-peers"
DEFAULT_JSON = ROOT / "benchmarks" / "results" / "peers.json"

PEERS = ("pogema", "rware")
DEFAULT_AGENT_COUNTS = (6, 100, 1000, 10000)
SIZE_OF = {6: "paper", 100: "small", 1000: "large", 10000: "huge"}
# Our timed window, as benchmarks/scale.py and the criterion bench: steps 101..1100.
OUR_WARMUP, OUR_STEPS = 100, 1000

# Exact pins, checked with CPython 3.11 (networkx 3.6 needs Python >= 3.11). rware 2.0.0 and
# pogema 1.4.0 are the newest releases; the rest is the set pip resolves for them, pinned
# so that every run measures the same code. All are wheels on PyPI (--only-binary).
PEER_VERSIONS = {"rware": "2.0.0", "pogema": "1.4.0"}
PINS = (
    "rware==2.0.0",
    "pogema==1.4.0",
    "gymnasium==0.28.1",  # pogema pins it exactly
    "numpy==1.26.4",  # pogema: numpy<=1.26.4
    "pydantic==1.9.1",  # pogema: pydantic<=1.9.1
    "networkx==3.6.1",  # rware: collision resolution
    "pyglet==1.5.31",  # rware: pyglet<2 (rendering only, imported lazily)
    "cloudpickle==3.1.2",
    "Farama-Notifications==0.0.6",
    "jax-jumpy==1.0.0",
    "typing_extensions==4.16.0",
)
STAMP_NAME = "multibots-peers-pins.txt"

# Environment for the worker: one BLAS thread (the peers do small numpy operations; a
# thread pool would only add noise on a shared 2-core machine), no bytecode writes.
WORKER_ENV = {
    "OPENBLAS_NUM_THREADS": "1",
    "OMP_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "PYTHONDONTWRITEBYTECODE": "1",
    "PYTHONHASHSEED": "0",
}

Log = Callable[[str], None]


def _stderr(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _venv_python(venv: Path) -> Path:
    return venv / ("Scripts/python.exe" if os.name == "nt" else "bin/python")


def _pins_text() -> str:
    return "\n".join(PINS) + "\n"


def _venv_ok(venv: Path) -> bool:
    py = _venv_python(venv)
    if not py.exists():
        return False
    try:
        r = subprocess.run(
            [str(py), "-c", "import rware, pogema, numpy, gymnasium"],
            capture_output=True, timeout=120, env={**os.environ, **WORKER_ENV},
        )
    except (OSError, subprocess.TimeoutExpired):
        return False
    return r.returncode == 0


def ensure_peer_venv(venv: Path = DEFAULT_VENV, log: Log = _stderr) -> Path:
    """Create or reuse the peers' virtual environment; return its Python.

    Reused as is when its stamp file lists exactly PINS and the packages import;
    otherwise (re)created with `python -m venv` and filled with `pip install` of PINS
    from the ordinary package index (PyPI), wheels only.
    """
    venv = Path(venv)
    stamp = venv / STAMP_NAME
    py = _venv_python(venv)
    if stamp.exists() and stamp.read_text() == _pins_text() and _venv_ok(venv):
        return py
    if venv.exists() and not py.exists():
        shutil.rmtree(venv)  # a broken half-made environment
    if not py.exists():
        log(f"creating the peers' virtual environment {venv}")
        # From the project's venv, `-m venv` uses the base interpreter (sys._base_executable).
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    if stamp.exists():
        stamp.unlink()
    log(f"installing pinned peers into {venv}: {' '.join(PINS)}")
    subprocess.run(
        [str(py), "-m", "pip", "install", "--quiet", "--no-input", "--disable-pip-version-check",
         "--only-binary=:all:", *PINS],
        check=True,
    )
    if not _venv_ok(venv):
        raise RuntimeError(f"{venv}: rware/pogema do not import after installation")
    stamp.write_text(_pins_text())
    return py


def _loadavg() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except (AttributeError, OSError):
        return None


def _loadavg() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except (AttributeError, OSError):
        return None


# --- our layouts ---------------------------------------------------------------------------

# The generator's defaults are the paper's layout (docs/layout-format.md).
_GENERATOR_DEFAULTS = {"group_rows": 2, "group_cols": 5, "group_width": 2, "group_height": 4,
                       "aisle": 50.0, "cell": 50.0}


def our_layout(n_agents: int) -> dict[str, Any]:
    """Free cells of our layout for `n_agents`: the named size with that many robots, else
    the paper layout with `n_agents` robots.

    Free cells = 50 x 50 px squares of aisle = the warehouse rectangle in cells minus the
    storage cells; `warehouse` is (R, C, W, H) for the pogema map of the same layout.
    """
    size = SIZE_OF.get(n_agents)
    doc: dict[str, Any] = {}
    if size:
        doc = tomllib.loads((SIZES_DIR / f"{size}.toml").read_text(encoding="utf-8"))
    gen = {**_GENERATOR_DEFAULTS, **doc.get("layout_generate", {})}
    if gen["aisle"] != gen["cell"]:
        raise ValueError("free cells are counted for aisles one cell wide (aisle = cell)")
    r, c, w, h = gen["group_rows"], gen["group_cols"], gen["group_width"], gen["group_height"]
    width, height = c * (w + 1) + 1, r * (h + 1) + 1  # in cells
    storage = r * c * w * h
    free = width * height - storage
    speed = float(doc.get("robot", {}).get("speed", 4.0))
    return {
        "size": size, "robots": n_agents, "warehouse": [r, c, w, h],
        "grid": [height, width], "cell_px": gen["cell"], "speed_px": speed,
        "storage_cells": storage, "free_cells": free, "free_cells_per_agent": free / n_agents,
        "cells_per_robot_step": speed / gen["cell"],
    }


# --- ours ----------------------------------------------------------------------------------

def ensure_scale_binary(log: Log = _stderr) -> Path:
    """Build the `scale` example (release) unless cargo says it is up to date; return its path."""
    log("cargo build --release -p multibots-core --example scale")
    subprocess.run(["cargo", "build", "--quiet", "--release", "-p", "multibots-core", "--example", "scale"],
                   check=True, cwd=str(ROOT))
    return SCALE_BIN


def _scale_run(binary: Path, size: str, steps: int, warmup: int) -> dict[str, Any]:
    r = subprocess.run([str(binary), str(SIZES_DIR / f"{size}.toml"), str(steps), str(warmup)],
                       capture_output=True, text=True, check=True, env={**os.environ, "SCALE_STATES": "1"})
    rec = json.loads(r.stdout.strip().splitlines()[-1])
    # stderr: "states [...] queue Q wait share W mean distance D" (D: px per robot since step 0, rounded)
    tail = r.stderr.strip().splitlines()[-1]
    rec["mean_distance_px"] = float(tail.rsplit("mean distance", 1)[1])
    rec["wait_share"] = float(tail.split("wait share", 1)[1].split()[0])
    return rec


def measure_ours(size: str, repetitions: int, binary: Path, *, warmup: int = OUR_WARMUP,
                 steps: int = OUR_STEPS) -> list[dict[str, Any]]:
    """`repetitions` runs of a named size; each: robot-steps/s and cell moves/s of steps
    warmup+1 .. warmup+steps. Distance in the window = distance after it - distance after
    the warm-up (a run of 0 timed steps; runs are deterministic, checked by fingerprint)."""
    lay = our_layout(next(n for n, s in SIZE_OF.items() if s == size))
    base = _scale_run(binary, size, 0, warmup)
    out = []
    for _ in range(repetitions):
        rec = _scale_run(binary, size, steps, warmup)
        n, k, secs = rec["robots"], rec["steps"], rec["seconds"]
        cells = (rec["mean_distance_px"] - base["mean_distance_px"]) * n / lay["cell_px"]
        out.append({
            "size": size, "robots": n, "steps": k, "seconds": secs,
            "robot_steps_per_s": rec["robot_steps_per_s"],
            "cell_moves": cells, "cell_moves_per_s": cells / secs,
            "cell_moves_per_robot_step": cells / (n * k),
            "wait_share": rec["wait_share"], "fingerprint": rec["fingerprint"], "loadavg_1min": _loadavg(),
        })
    return out


def summarize_ours(runs: Sequence[dict[str, Any]]) -> dict[str, Any]:
    r0 = runs[0]
    rates = [r["robot_steps_per_s"] for r in runs]
    moves = [r["cell_moves_per_s"] for r in runs]
    lay = our_layout(r0["robots"])
    return {
        "size": r0["size"], "robots": r0["robots"], "repetitions": len(runs),
        "robot_steps_per_s": statistics.median(rates), "min": min(rates), "max": max(rates),
        "cell_moves_per_s": statistics.median(moves),
        "cell_moves_per_robot_step": r0["cell_moves_per_robot_step"],
        "same_results": len({r["fingerprint"] for r in runs}) == 1,
        "layout": lay, "runs": list(runs),
    }


# --- peers ---------------------------------------------------------------------------------

def _na(peer: str, n: int, reason: str, **extra: Any) -> dict[str, Any]:
    return {
        "peer": peer,
        "version": PEER_VERSIONS.get(peer),
        "agents": n,
        "status": "n/a",
        "reason": reason,
        "agent_steps_per_s": None,
        "repetitions": 0,
        **extra,
    }


def measure_one(
    peer: str,
    n_agents: int,
    *,
    python: Path,
    repetitions: int = 5,
    min_rep_seconds: float = 0.5,
    seed: int = 0,
    timeout_s: float = 300.0,
    cells_per_agent: float | None = None,
    log: Log = _stderr,
) -> dict[str, Any]:
    """One (peer, agent count) measurement in a fresh subprocess of the peers' venv.

    cells_per_agent None: our layout's density for that count (pogema gets our warehouse
    as its map); a number: that density (pogema on a random map).
    Returns the worker's record (status "ok"), or status "n/a" with the reason when the
    peer cannot build or step the environment within `timeout_s` or fails.
    """
    cmd = [
        str(python), str(WORKER), "--peer", peer, "--agents", str(n_agents),
        "--repetitions", str(repetitions), "--min-rep-seconds", str(min_rep_seconds),
        "--seed", str(seed),
    ]
    if cells_per_agent is None:
        lay = our_layout(n_agents)
        cmd += ["--cells-per-agent", repr(lay["free_cells_per_agent"]),
                "--warehouse", ",".join(map(str, lay["warehouse"]))]
    else:
        cmd += ["--cells-per-agent", repr(cells_per_agent)]
    load_before = _loadavg()
    t0 = time.perf_counter()
    try:
        r = subprocess.run(
            cmd, capture_output=True, text=True, timeout=timeout_s,
            env={**os.environ, **WORKER_ENV}, cwd=str(ROOT),
        )
    except subprocess.TimeoutExpired as e:
        err = e.stderr.decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or "")
        progress = [ln for ln in err.splitlines() if ln.startswith("[peer_worker]")]
        last = progress[-1].removeprefix("[peer_worker] ") if progress else "no progress reported"
        return _na(peer, n_agents, f"not finished within {timeout_s:.0f} s (last: {last})")
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        tail = (r.stderr or "").strip().splitlines()[-1:] or ["no output"]
        return _na(peer, n_agents, f"worker failed (exit {r.returncode}): {tail[0][:300]}")
    try:
        rec = json.loads(r.stdout.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        return _na(peer, n_agents, "worker printed no JSON result")
    rec["wall_seconds"] = wall
    # 1-minute load average before and after: a shared machine's noise, for the record.
    rec["loadavg_1min"] = [load_before, _loadavg()]
    log(f"  {peer:<7} n={n_agents:<6} {rec['agent_steps_per_s']:>10,.0f} agent-steps/s with observations, "
        f"{rec['agent_steps_per_s_no_obs']:>10,.0f} without; {rec['moves_per_agent_step']:.3f} cell moves "
        f"per agent-step (median of {rec['repetitions']}; build {rec['build_seconds']:.1f} s; wall {wall:.0f} s)")
    return rec


def measure_peers(
    agent_counts: Iterable[int] = DEFAULT_AGENT_COUNTS,
    peers: Sequence[str] = PEERS,
    *,
    repetitions: int = 5,
    min_rep_seconds: float = 0.5,
    seed: int = 0,
    timeout_s: float = 300.0,
    cells_per_agent: float | None = None,
    venv: Path = DEFAULT_VENV,
    log: Log = _stderr,
) -> list[dict[str, Any]]:
    """Measure every peer at every agent count; one dict per (peer, agent count).

    Each dict has at least: peer, version, agents, status ("ok" or "n/a"),
    agent_steps_per_s (with observations; median over the rounds; None when n/a),
    repetitions; when ok also agent_steps_per_s_no_obs, moves_per_agent_step,
    cell_moves_per_s(_no_obs), env (the environment's parameters), ...; else reason.
    Measurements run one at a time, agent count by agent count with the peers
    interleaved, so slow drifts of a shared machine hit both peers alike.
    """
    for p in peers:
        if p not in PEERS:
            raise ValueError(f"unknown peer {p!r}; known: {', '.join(PEERS)}")
    python = ensure_peer_venv(Path(venv), log=log)
    out: list[dict[str, Any]] = []
    for n in agent_counts:
        for p in peers:
            log(f"measuring {p} with {n} agents ...")
            out.append(measure_one(p, int(n), python=python, repetitions=repetitions,
                                   min_rep_seconds=min_rep_seconds, seed=seed, timeout_s=timeout_s,
                                   cells_per_agent=cells_per_agent, log=log))
    return out


def compare(
    agent_counts: Iterable[int] = DEFAULT_AGENT_COUNTS,
    peers: Sequence[str] = PEERS,
    *,
    repetitions: int = 5,
    min_rep_seconds: float = 0.5,
    our_repetitions: int = 6,
    seed: int = 0,
    timeout_s: float = 300.0,
    skip: Iterable[tuple[str, int]] = (),
    venv: Path = DEFAULT_VENV,
    log: Log = _stderr,
) -> dict[str, Any]:
    """Ours and the peers at each agent count, at our density, interleaved: for each count,
    half of our runs, then each peer (with and without observations, alternating inside
    its subprocess), then the other half of our runs. `skip`: (peer, count) pairs not
    measured (reported n/a with the reason "skipped")."""
    counts = [int(n) for n in agent_counts]
    for n in counts:
        if n not in SIZE_OF:
            raise ValueError(f"no named size with {n} robots; known: {sorted(SIZE_OF)}")
    python = ensure_peer_venv(Path(venv), log=log)
    binary = ensure_scale_binary(log)
    skip = set(skip)
    ours, out = [], []
    for n in counts:
        size = SIZE_OF[n]
        first = our_repetitions // 2
        log(f"ours: {size} ({n} robots) ...")
        runs = measure_ours(size, first, binary)
        for p in peers:
            if (p, n) in skip:
                out.append(_na(p, n, "skipped (--skip)"))
                continue
            log(f"measuring {p} with {n} agents ...")
            out.append(measure_one(p, n, python=python, repetitions=repetitions,
                                   min_rep_seconds=min_rep_seconds, seed=seed,
                                   timeout_s=timeout_s, log=log))
        runs += measure_ours(size, our_repetitions - first, binary)
        s = summarize_ours(runs)
        log(f"  ours    n={n:<6} {s['robot_steps_per_s']:>10,.0f} robot-steps/s, "
            f"{s['cell_moves_per_s']:>10,.0f} cell moves/s (median of {len(runs)})")
        ours.append(s)
    return {"ours": ours, "peers": out}


# --- tables --------------------------------------------------------------------------------

def _rate(x: float | None) -> str:
    if x is None:
        return "n/a"
    return f"{x / 1e6:.2f} M" if x >= 1e6 else f"{x:,.0f}"


def _ratio(a: float | None, b: float | None) -> str:
    if not a or not b:
        return "n/a"
    r = a / b
    return f"{r:,.0f}x" if r >= 10 else f"{r:.1f}x"


def _pair(a: str, b: str) -> str:
    return a if a == b == "n/a" else f"{a} / {b}"


def describe_env(rec: dict[str, Any]) -> str:
    env = rec.get("env") or {}
    if not env:
        return ""
    h, w = env["grid"]
    if rec["peer"] == "rware":
        return (f"{h}x{w} grid, {env['shelf_rows']}x{env['shelf_columns']} shelf blocks "
                f"(height {env['column_height']}), queue {env['request_queue_size']}")
    if rec["peer"] == "pogema":
        return f"{h}x{w} map, {env['layout']}, obs radius {env['obs_radius']}, lifelong"
    return ""


def format_table(results: Sequence[dict[str, Any]]) -> str:
    """The peers' details, one row per (peer, agent count)."""
    head = ("peer", "version", "agents", "free cells per agent", "agent-steps/s with observations (min..max)",
            "without (min..max)", "observation share", "cell moves per agent-step", "environment")
    rows = []
    for r in results:
        if r["status"] == "ok":
            rows.append((
                r["peer"], r["version"], f"{r['agents']:,}", f"{r['env']['free_cells_per_agent']:.2f}",
                f"{r['agent_steps_per_s']:,.0f} ({r['agent_steps_per_s_min']:,.0f}..{r['agent_steps_per_s_max']:,.0f})",
                f"{r['agent_steps_per_s_no_obs']:,.0f} ({r['agent_steps_per_s_no_obs_min']:,.0f}.."
                f"{r['agent_steps_per_s_no_obs_max']:,.0f})",
                f"{r['observation_share']:.0%}", f"{r['moves_per_agent_step']:.3f}", describe_env(r),
            ))
        else:
            rows.append((r["peer"], r.get("version") or "", f"{r['agents']:,}", "", "n/a", "", "", "",
                         r.get("reason", "")))
    return _md(head, rows, right={2, 3, 4, 5, 6, 7})


def _md(head: Sequence[str], rows: Sequence[Sequence[str]], right: set[int]) -> str:
    def fmt(row: Sequence[str]) -> str:
        return "| " + " | ".join(row) + " |"

    sep = "|" + "|".join("---:" if i in right else "---" for i in range(len(head))) + "|"
    return "\n".join([fmt(head), sep, *(fmt(r) for r in rows)])


def _machine() -> str:
    model = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{model or platform.machine()}, {os.cpu_count()} CPUs, {platform.platform()}"


HEADING = "## Side by side with rware and pogema"

MEANING = (
    "**Which figure means what.** *Agent-steps per second* (robot-steps for us) counts how many agent-ticks "
    "the simulator advances per second, whatever a tick contains. It is the figure these libraries usually "
    "quote, and the right one for the cost of a tick-by-tick loop, but it compares ticks of different sizes: "
    "a peer's tick moves an agent one whole cell (when it moves), ours moves a robot at most 4 px = 0.08 cell, "
    "so a 50 px cell takes 12.5 of our ticks. *Cell moves per second* counts distance actually covered, in "
    "cells, per second of wall time: how fast each simulator plays out the same amount of motion on the same "
    "floor space, which is the fair speed comparison of the worlds themselves. It still differs in what moves "
    "the agents: the peers' random agents often stand, turn or bump (0.09 to 0.41 cell moves per agent-step), "
    "our robots follow routes and traffic rules and drive most of the time (0.069 to 0.074 of at most 0.08). "
    "*With observations* is what a user of the peer pays per step (the peer always builds them; our figures "
    "build none); *without* is the peer's simulation alone, the like-for-like match for our engine's step, "
    "which in turn does more per tick than a grid move (continuous motion along routes, collision waiting, "
    "energy, orders and allocation)."
)


def _in_short(ours: dict[int, dict[str, Any]], peer: dict[tuple[str, int], dict[str, Any]],
              names: Sequence[str]) -> list[str]:
    """One sentence per peer: the ranges of our ratios over the agent counts."""
    out = []
    for p in names:
        def span(ours_key: str, key: str, p: str = p) -> str:
            rs = [o[ours_key] / r[key] for n, o in ours.items()
                  if (r := peer.get((p, n))) and r.get("status") == "ok" and r.get(key)]
            if not rs:
                return "n/a"
            lo, hi = _ratio(min(rs), 1), _ratio(max(rs), 1)
            return lo if lo == hi else f"{lo[:-1]}–{hi}"

        out.append(
            f"{'Against' if out else 'In short, against'} {p} over these agent counts: per agent-step "
            f"{span('robot_steps_per_s', 'agent_steps_per_s')} with its observations and "
            f"{span('robot_steps_per_s', 'agent_steps_per_s_no_obs')} without; per cell moved "
            f"{span('cell_moves_per_s', 'cell_moves_per_s')} with and "
            f"{span('cell_moves_per_s', 'cell_moves_per_s_no_obs')} without (the like-for-like figure).")
    return [" ".join(out)]


def markdown(d: dict[str, Any]) -> list[str]:
    """The section of docs/benchmarks.md, from `compare`'s result (plus 'created_utc', 'command',
    'load' and 'total_seconds' when main adds them)."""
    ours = {o["robots"]: o for o in d["ours"]}
    peer = {(r["peer"], r["agents"]): r for r in d["peers"]}
    names = [p for p in PEERS if any(r["peer"] == p for r in d["peers"])]
    reps = next((r["repetitions"] for r in d["peers"] if r["status"] == "ok"), 0)
    our_reps = next(iter(ours.values()))["repetitions"] if ours else 0
    lines = [HEADING, ""]
    if d.get("command"):
        load = d.get("load") or [None, None]
        lines += [
            f"- Command: `{d['command']}`",
            f"- Date (UTC): {d.get('created_utc', '?')}; total {d.get('total_seconds', 0):.0f} s; "
            f"machine: {_machine()}, "
            f"shared (1-minute load average {load[0]} at the start, {load[1]} at the end; other benchmarks may run "
            "at the same time). Every figure is a median of repeated runs, one thread; ours and the peers' "
            "interleave at each agent count (half of our runs before the peers, half after), and each peer "
            "alternates its rounds with and without observations.",
        ]
    lines += [
        f"- Ours: the named size with that many robots (`benchmarks/sizes/`), steps 101..1100 through the "
        f"`scale` example, median of {our_reps} runs. Peers: rware {PEER_VERSIONS['rware']} and pogema "
        f"{PEER_VERSIONS['pogema']} in their own virtual environment `.venv-peers` (their pins clash with ours), "
        f"one subprocess per peer and agent count, uniformly random actions, lifelong (pogema: a new goal on "
        f"arrival; rware: new requests), median of {reps} rounds of at least 0.5 s each with and without observations.",
        "- **Equal density.** A cell is our layout's grid unit, 50 px (a storage cell, the aisle width, the "
        "parking-slot spacing). Our free cells are the 50 × 50 px squares of aisle: the warehouse in cells minus "
        "the storage cells (e.g. large: 76 × 109 = 8,284 cells, 4,800 of them storage, 3,484 free for 1,000 "
        "robots). pogema gets the very same warehouse as its map (aisle cells free, storage cells obstacles), "
        "so the same free cells per agent in the same geometry (but two-way aisles). rware gets its own shelf "
        "layout sized to the same number of cells per agent, all of them free (rware's agents drive under "
        "shelves; rware's layouts come in steps, so the match is within a few per cent).",
        "- **Observations.** *With*: the peer's full `step`, which builds every agent's observation (pogema: "
        "a 3 × 11 × 11 window per agent, obs radius 5; rware: the flattened vector, sensor range 1). *Without*: "
        "the same `step` with the observation builder (pogema `Pogema._obs`, rware `Warehouse._make_obs`) "
        "replaced on the instance by one returning None, everything else (moves, collisions, goals, rewards, "
        "wrappers) unchanged: measured, not estimated. Neither peer has a cheaper legal setting.",
        "- **Cell moves.** Ours: distance the fleet drove in the window (the engine's per-robot distance) / "
        "50 px / wall time; waiting, loading and parked robots add nothing. Peers: agent-steps/s × the share of "
        "agent-steps that changed the agent's cell, counted from positions before and after each step in an "
        "untimed pass of the same episode (random actions include standing still, and for rware turns and "
        "load toggles; moves into walls, obstacles or other agents fail).",
        "",
        "Agent-steps (robot-steps) per second:",
        "",
    ]
    head = ["agents", "free cells per agent (ours = pogema; rware)", "MultiBots robot-steps/s"]
    for p in names:
        head += [f"{p} agent-steps/s, with / without observations", f"ours ÷ {p}, with / without"]
    rows = []
    for n, o in ours.items():
        rw = peer.get(("rware", n))
        rw_cells = f"{rw['env']['free_cells_per_agent']:.2f}" if rw and rw["status"] == "ok" else "n/a"
        row = [f"{n:,}", f"{o['layout']['free_cells_per_agent']:.2f}; {rw_cells}", _rate(o["robot_steps_per_s"])]
        for p in names:
            r = peer.get((p, n)) or {}
            on, off = r.get("agent_steps_per_s"), r.get("agent_steps_per_s_no_obs")
            row += [_pair(_rate(on), _rate(off)),
                    _pair(_ratio(o["robot_steps_per_s"], on), _ratio(o["robot_steps_per_s"], off))]
        rows.append(row)
    lines += [_md(head, rows, right=set(range(len(head)))), "", "Cell moves per second:", ""]
    head = ["agents", "cell moves per agent-step (ours" + "".join(f"; {p}" for p in names) + ")",
            "MultiBots cell moves/s"]
    for p in names:
        head += [f"{p} cell moves/s, with / without observations", f"ours ÷ {p}, with / without"]
    rows = []
    for n, o in ours.items():
        per = [f"{o['cell_moves_per_robot_step']:.3f}"]
        for p in names:
            r = peer.get((p, n)) or {}
            per.append(f"{r['moves_per_agent_step']:.3f}" if r.get("status") == "ok" else "n/a")
        row = [f"{n:,}", "; ".join(per), _rate(o["cell_moves_per_s"])]
        for p in names:
            r = peer.get((p, n)) or {}
            on, off = r.get("cell_moves_per_s"), r.get("cell_moves_per_s_no_obs")
            row += [_pair(_rate(on), _rate(off)),
                    _pair(_ratio(o["cell_moves_per_s"], on), _ratio(o["cell_moves_per_s"], off))]
        rows.append(row)
    lines += [_md(head, rows, right=set(range(len(head)))), "", MEANING, "", *_in_short(ours, peer, names), "",
              "Target (set before this comparison): at least 40x pogema's agent-steps per second at equal "
              "agent counts, i.e. the first ratio against pogema with its observations.", "", "Our details:", ""]
    rows = [(o["size"], f"{n:,}", "{}x{} cells".format(*o["layout"]["grid"]), f"{o['layout']['storage_cells']:,}",
             f"{o['layout']['free_cells']:,}", f"{o['layout']['free_cells_per_agent']:.2f}",
             f"{_rate(o['robot_steps_per_s'])} ({_rate(o['min'])}..{_rate(o['max'])})",
             _rate(o["cell_moves_per_s"]), f"{o['cell_moves_per_robot_step']:.3f}",
             f"{o['repetitions']}", "yes" if o["same_results"] else "NO")
            for n, o in ours.items()]
    lines += [_md(("size", "robots", "warehouse", "storage cells", "free cells", "free cells per robot",
                   "robot-steps/s (min..max)", "cell moves/s", "cell moves per robot-step", "runs",
                   "same results every run"), rows, right=set(range(1, 10))),
              "", "Peer details (observation share: 1 − (agent-steps/s with) / (agent-steps/s without), the share "
              "of the full step's time spent building observations):", "", format_table(d["peers"])]
    na = [r for r in d["peers"] if r["status"] != "ok"]
    if na:
        lines += ["", "n/a: " + "; ".join(f"{r['peer']} at {r['agents']:,}: {r.get('reason')}" for r in na)]
    return lines


def replace_section(doc: str, section: list[str]) -> str:
    """docs/benchmarks.md with the peers' section (from HEADING to the next '## ' heading) replaced."""
    lines = doc.splitlines()
    try:
        i = lines.index(HEADING)
    except ValueError:
        raise ValueError(f"no line {HEADING!r} in the document") from None
    j = next((k for k in range(i + 1, len(lines)) if lines[k].startswith("## ")), len(lines))
    return "\n".join([*lines[:i], *section, "", *lines[j:]]) + "\n"


def write_json_atomic(path: Path, data: Any) -> None:
    from multibots._io import atomic_write_text  # the project's one atomic writer

    atomic_write_text(path, json.dumps(data, indent=2, sort_keys=False) + "\n")


def _skip(text: str) -> tuple[str, int]:
    peer, _, n = text.partition(":")
    if peer not in PEERS or not n.isdigit():
        raise argparse.ArgumentTypeError(f"{text!r}: expected PEER:AGENTS, e.g. rware:10000")
    return peer, int(n)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--agents", type=int, nargs="+", default=list(DEFAULT_AGENT_COUNTS),
                    help=f"agent counts, each of {sorted(SIZE_OF)}")
    ap.add_argument("--peers", nargs="+", choices=PEERS, default=list(PEERS))
    ap.add_argument("--skip", type=_skip, nargs="*", default=[], metavar="PEER:AGENTS",
                    help="(peer, agent count) pairs not to measure, e.g. rware:10000")
    ap.add_argument("--repetitions", type=int, default=5, help="peer rounds (each with and without observations)")
    ap.add_argument("--min-rep-seconds", type=float, default=0.5)
    ap.add_argument("--our-repetitions", type=int, default=6)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=300.0,
                    help="seconds per (peer, agent count) before it is reported n/a")
    ap.add_argument("--venv", type=Path, default=DEFAULT_VENV)
    ap.add_argument("--json", type=Path, default=DEFAULT_JSON, dest="json_path")
    ap.add_argument("--write", type=Path, nargs="?", const=ROOT / "docs" / "benchmarks.md", default=None,
                    help="replace the section in this file (default docs/benchmarks.md)")
    ap.add_argument("--from-json", type=Path, default=None, metavar="PATH",
                    help="measure nothing: print (and --write) the tables of an earlier run's JSON")
    a = ap.parse_args(argv)

    if a.from_json:
        md = markdown(json.loads(a.from_json.read_text(encoding="utf-8")))
        print("\n".join(md))
        if a.write:
            from multibots._io import atomic_write_text

            atomic_write_text(a.write, replace_section(a.write.read_text(encoding="utf-8"), md))
        return 0
    started = time.perf_counter()
    load0 = _loadavg()
    d = compare(a.agents, a.peers, repetitions=a.repetitions, min_rep_seconds=a.min_rep_seconds,
                our_repetitions=a.our_repetitions, seed=a.seed, timeout_s=a.timeout, skip=a.skip, venv=a.venv)
    d = {
        "kind": "multibots-peer-benchmark",
        "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "command": " ".join([".venv/bin/python", "benchmarks/peers.py", *sys.argv[1:]]),
        "host": {"platform": platform.platform(), "machine": _machine(), "cpus": os.cpu_count()},
        "venv": str(a.venv),
        "pins": list(PINS),
        "settings": {k: v for k, v in vars(a).items() if k not in ("json_path", "write", "venv")},
        "load": [load0, _loadavg()],
        "total_seconds": time.perf_counter() - started,
        **d,
    }
    md = markdown(d)
    print("\n".join(md))
    write_json_atomic(a.json_path, d)
    print(f"\nwritten {a.json_path} in {d['total_seconds']:.0f} s", file=sys.stderr)
    if a.write:
        from multibots._io import atomic_write_text

        atomic_write_text(a.write, replace_section(a.write.read_text(encoding="utf-8"), md))
        print(f"replaced the section {HEADING!r} of {a.write}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
