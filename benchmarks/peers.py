"""Peer benchmark: agent-steps per second of two public multi-agent grid simulators.

    .venv/bin/python benchmarks/peers.py [--agents 6 100 1000 10000] [--json PATH]

Measures `rware` (the multi-robot warehouse) and `pogema` (partially observable
multi-agent pathfinding) from PyPI with uniformly random, seeded actions, at the given
agent counts, so that our engine's figures can be put beside them (see `measure_peers`).

The peers pin numpy<2, pydantic 1 and gymnasium 0.28, which clash with the project's own
dependencies, so they live in a separate virtual environment, .venv-peers at the
repository root, created (or reused) here with exact pins from PyPI. Every measurement
runs in its own subprocess of that environment (benchmarks/peer_worker.py), one at a
time, so peers never share a process, a heap or a core with each other or with us.

This module uses the standard library only (and the project's atomic writer, when it writes its
JSON); importing it has no side effects.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

ROOT = Path(__file__).resolve().parent.parent
WORKER = Path(__file__).resolve().parent / "peer_worker.py"
DEFAULT_VENV = ROOT / ".venv-peers"
DEFAULT_JSON = ROOT / "benchmarks" / "results" / "peers.json"

PEERS = ("rware", "pogema")
DEFAULT_AGENT_COUNTS = (6, 100, 1000, 10000)

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
    min_rep_seconds: float = 1.0,
    seed: int = 0,
    timeout_s: float = 300.0,
    log: Log = _stderr,
) -> dict[str, Any]:
    """One (peer, agent count) measurement in a fresh subprocess of the peers' venv.

    Returns the worker's record (status "ok"), or status "n/a" with the reason when the
    peer cannot build or step the environment within `timeout_s` or fails.
    """
    cmd = [
        str(python), str(WORKER), "--peer", peer, "--agents", str(n_agents),
        "--repetitions", str(repetitions), "--min-rep-seconds", str(min_rep_seconds),
        "--seed", str(seed),
    ]
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
    log(f"  {peer:<7} n={n_agents:<6} {rec['agent_steps_per_s']:>12,.0f} agent-steps/s "
        f"(median of {rec['repetitions']}; build {rec['build_seconds']:.1f} s; wall {wall:.0f} s)")
    return rec


def measure_peers(
    agent_counts: Iterable[int] = DEFAULT_AGENT_COUNTS,
    peers: Sequence[str] = PEERS,
    *,
    repetitions: int = 5,
    min_rep_seconds: float = 1.0,
    seed: int = 0,
    timeout_s: float = 300.0,
    venv: Path = DEFAULT_VENV,
    log: Log = _stderr,
) -> list[dict[str, Any]]:
    """Measure every peer at every agent count; one dict per (peer, agent count).

    Each dict has at least: peer, version, agents, status ("ok" or "n/a"),
    agent_steps_per_s (median over the repetitions; None when n/a), repetitions, and
    either env (the environment's parameters), reps, build_seconds ... or reason.
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
                                   min_rep_seconds=min_rep_seconds, seed=seed,
                                   timeout_s=timeout_s, log=log))
    return out


def describe_env(rec: dict[str, Any]) -> str:
    env = rec.get("env") or {}
    if not env:
        return ""
    h, w = env["grid"]
    if rec["peer"] == "rware":
        return (f"{h}x{w} grid, {env['shelf_rows']}x{env['shelf_columns']} shelf blocks "
                f"(height {env['column_height']}), queue {env['request_queue_size']}")
    if rec["peer"] == "pogema":
        return f"{h}x{w} map, obstacles {env['density']:.0%}, obs radius {env['obs_radius']}, lifelong"
    return ""


def _sig(x: float) -> str:
    return f"{x:,.1f}" if x >= 100 else f"{x:.3g}"


def format_table(results: Sequence[dict[str, Any]]) -> str:
    head = ("peer", "version", "agents", "agent-steps/s (median)", "min..max", "per CPU-s", "steps/s",
            "reps", "environment")
    rows = []
    for r in results:
        if r["status"] == "ok":
            rows.append((
                r["peer"], r["version"], str(r["agents"]), f"{r['agent_steps_per_s']:,.0f}",
                f"{r['agent_steps_per_s_min']:,.0f}..{r['agent_steps_per_s_max']:,.0f}",
                f"{r['agent_steps_per_cpu_s']:,.0f}", _sig(r["steps_per_s"]), str(r["repetitions"]), describe_env(r),
            ))
        else:
            rows.append((r["peer"], r.get("version") or "", str(r["agents"]), "n/a", "", "", "", "0",
                         r.get("reason", "")))
    widths = [max(len(h), *(len(row[i]) for row in rows)) if rows else len(h) for i, h in enumerate(head)]
    right = {2, 3, 4, 5, 6, 7}

    def fmt(row: Sequence[str]) -> str:
        return "| " + " | ".join(c.rjust(widths[i]) if i in right else c.ljust(widths[i])
                                 for i, c in enumerate(row)) + " |"

    sep = "|" + "|".join(("-" * (w + 1) + ":") if i in right else ("-" * (w + 2))
                         for i, w in enumerate(widths)) + "|"
    return "\n".join([fmt(head), sep, *(fmt(r) for r in rows)])


def write_json_atomic(path: Path, data: Any) -> None:
    from multibots._io import atomic_write_text  # the project's one atomic writer

    atomic_write_text(path, json.dumps(data, indent=2, sort_keys=False) + "\n")


METHOD = (
    "Each (peer, agent count) runs in a fresh subprocess of .venv-peers. The environment is "
    "built and reset with seed 0 (build time reported separately, not timed as steps), "
    "warmed up for >= 0.2 s, then timed for R consecutive repetitions of the same episode; "
    "a repetition runs whole steps until >= min_rep_seconds of wall time (at least one "
    "step). Every step draws one uniformly random action per agent from "
    "numpy.random.default_rng(seed) inside the timed loop and calls the peer's own step(), "
    "which includes the peer's per-agent observations and rewards. agent_steps_per_s is the "
    "median over repetitions of agents * steps / wall seconds (agent_steps_per_cpu_s: the "
    "same per second of the worker's CPU time, a check against other load). Episodes have no time limit, so no "
    "reset is timed. Both peers get ~29.3 traversable cells per agent (the paper warehouse: "
    "16 x 11 cells of 50 px for 6 robots)."
)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--agents", type=int, nargs="+", default=list(DEFAULT_AGENT_COUNTS))
    ap.add_argument("--peers", nargs="+", choices=PEERS, default=list(PEERS))
    ap.add_argument("--repetitions", type=int, default=5)
    ap.add_argument("--min-rep-seconds", type=float, default=1.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=300.0,
                    help="seconds per (peer, agent count) before it is reported n/a")
    ap.add_argument("--venv", type=Path, default=DEFAULT_VENV)
    ap.add_argument("--json", type=Path, default=DEFAULT_JSON, dest="json_path")
    a = ap.parse_args(argv)

    started = time.perf_counter()
    results = measure_peers(a.agents, a.peers, repetitions=a.repetitions,
                            min_rep_seconds=a.min_rep_seconds, seed=a.seed,
                            timeout_s=a.timeout, venv=a.venv)
    total = time.perf_counter() - started
    print(format_table(results))
    data = {
        "kind": "multibots-peer-benchmark",
        "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "command": " ".join([Path(sys.executable).name, *sys.argv]),
        "host": {
            "platform": platform.platform(),
            "machine": platform.machine(),
            "cpus": os.cpu_count(),
        },
        "venv": str(a.venv),
        "pins": list(PINS),
        "settings": {
            "agent_counts": a.agents,
            "repetitions": a.repetitions,
            "min_rep_seconds": a.min_rep_seconds,
            "seed": a.seed,
            "timeout_s": a.timeout,
        },
        "method": METHOD,
        "total_seconds": total,
        "results": results,
    }
    write_json_atomic(a.json_path, data)
    print(f"\nwritten {a.json_path} in {total:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
