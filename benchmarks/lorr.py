"""League of Robot Runners instances: our planner, and the Start-Kit's, against the best-known score.

    python3 benchmarks/lorr.py --instances DIR [--only NAME ...] [--domain warehouse ...]
                               [--steps N] [--startkit PATH/lifelong] [--startkit-2023 PATH/lifelong]
                               [--startkit-steps N] [--scheduler spread] [--planner pibt] [--seed 0]
                               [--rows ROWS.json] [--no-check] [--no-ours] [--no-write]

``DIR`` is a folder the user fetched from MAPF-Competition/Benchmark-Archive (the instance
files have no licence and are never committed). Every problem JSON under it (or those named
by ``--only``, shell patterns allowed) is run in a child process of its own:

- with our planner (``multibots.lorr.run``; ``--planner``, by default ``pibt``, not the command's ``auto``, so
  that rows keyed ``ours`` keep meaning ``pibt``) for ``--steps`` steps, by default the
  instance's own simulation time (the steps its best-known count was made in);
- with ``--startkit``, the Start-Kit's ``lifelong`` (its default planner and scheduler, built
  by the user; 2024 rules) for ``--startkit-steps`` steps (default: the same), and with
  ``--startkit-2023`` the 2023 Start-Kit's for the 2023 instances.

Each result is checked by the independent checker (``../shared/tools/lorr_check.py`` beside the
repository, when it is there; ``--no-check`` skips it), and the table gives the score, its
share of the best-known count (only when run for the same number of steps), planning ms per
step (mean and max, from the result's ``plannerTimes``), and peak memory (the child's maximum
RSS from ``wait4``). Rows are kept in ``--rows`` (JSON, merged by instance, entry and steps), so
that runs made in several invocations land in one table (``--table-only`` runs nothing and
writes it), which goes to the ``lorr`` section of docs/benchmarks.md with the commands that
made its rows and the machine unless ``--no-write``.
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import os
import platform
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
CHECKER = ROOT.parent / "shared" / "tools" / "lorr_check.py"

ARCHIVE = (
    "MAPF-Competition/Benchmark-Archive at commit 25ffd5b, the tables of `2023 Competition/README.md` "
    "and `2024 Competition/README.md`"
)

# Best-known counts of the archive (see ARCHIVE): instance -> (finished, simulation steps).
# 2023: errands finished; 2024: tasks. TR23-warehouse_large's row says 5,000 agents, its
# problem file has teamSize 1,000.
BEST_KNOWN: dict[str, tuple[int, int]] = {
    "MR23-I-01": (10385, 1500),
    "MR23-I-02": (49186, 3500),
    "MR23-I-03": (3042, 500),
    "MR23-I-04": (1741, 500),
    "MR23-I-05": (7432, 1000),
    "MR23-I-06": (197275, 5000),
    "MR23-I-07": (5914, 1000),
    "MR23-I-08": (6059, 2000),
    "MR23-I-09": (28954, 5000),
    "MR23-I-10": (194677, 5000),
    "TR23-Paris": (6094, 5000),
    "TR23-brc202d": (6543, 5000),
    "TR23-random": (15609, 5000),
    "TR23-sortation_large": (24577, 5000),
    "TR23-warehouse_large": (19758, 5000),
    "MR24-CITY-01": (8445, 3000),
    "MR24-CITY-02": (17010, 3000),
    "MR24-GAME": (23274, 5000),
    "MR24-RANDOM-01": (696, 600),
    "MR24-RANDOM-02": (1260, 600),
    "MR24-RANDOM-03": (2368, 800),
    "MR24-RANDOM-04": (2585, 1000),
    "MR24-RANDOM-05": (3050, 2000),
    "MR24-SORTATION": (152714, 5000),
    "MR24-WAREHOUSE": (154834, 5000),
    "TR-24-brc202d_500": (1020, 1000),
    "TR-24-paris_1_256_250": (456, 500),
    "TR-24-random_32_32_20_100": (1186, 500),
    "TR-24-sortation_large_2000": (15508, 2000),
    "TR-24-warehouse_large_5000": (94232, 5000),
}


def instance_name(path: Path) -> str:
    """The archive's name of a problem file (as its README tables spell it)."""
    where = path.as_posix()
    if "2024 Competition/Main Round" in where:
        return f"MR24-{path.stem}"
    if "2024 Competition/Test Round" in where:
        return f"TR-24-{path.stem}"
    if "Example Instances" in where:
        return f"EX{'24' if '2024' in where else '23'}-{path.stem}"
    return path.stem


def problems(folder: Path) -> list[tuple[str, Path, str]]:
    """(name, problem JSON, why it cannot run or "") under ``folder``: files with a ``mapFile``."""
    out = []
    for p in sorted(folder.rglob("*.json")):
        try:
            spec = json.loads(p.read_text())
        except (ValueError, UnicodeDecodeError):
            continue
        if not isinstance(spec, dict) or "mapFile" not in spec:
            continue
        missing = [spec[k] for k in ("mapFile", "agentFile", "taskFile") if not (p.parent / spec[k]).is_file()]
        out.append((instance_name(p), p, f"missing {', '.join(missing)}" if missing else ""))
    return out


def chosen(found: list[tuple[str, Path, str]], only: list[str], domains: list[str]) -> list[tuple[str, Path, str]]:
    keep = []
    for name, path, why in found:
        if only and not any(fnmatch.fnmatchcase(name, pat) for pat in only):
            continue
        if domains and not any(f"{d}.domain" in path.as_posix() for d in domains):
            continue
        keep.append((name, path, why))
    return keep


def child(argv: list[str], log: Path) -> tuple[int, float, float]:
    """Runs ``argv`` (output to ``log``): exit code, wall seconds, peak RSS in MB of that child."""
    began = time.monotonic()
    with log.open("wb") as out:
        proc = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    return proc.returncode, time.monotonic() - began, usage.ru_maxrss / 1024


OURS = """
import json, sys
sys.path.insert(0, sys.argv[1])
from multibots import lorr
r = lorr.run(sys.argv[2], steps=int(sys.argv[3]), out=sys.argv[4], scheduler=sys.argv[5], seed=int(sys.argv[6]),
             planner=sys.argv[7])
print(json.dumps({"finished": r.finished, "rules": r.version, "robots": r.team_size,
                  "by_1000": r.figures["finished_per_1000"][0] if r.steps >= 1000 else None}))
"""


def result_figures(out: Path) -> dict[str, Any]:
    """Score, robots and planning ms per step from a result file (ours or the Start-Kit's)."""
    res = json.loads(out.read_text())
    times = [float(t) * 1e3 for t in res.get("plannerTimes", [])]
    return {
        "finished": int(res["numTaskFinished"]),
        "robots": int(res["teamSize"]),
        "ms_mean": sum(times) / len(times) if times else 0.0,
        "ms_max": max(times) if times else 0.0,
        "rounds_over_1s": sum(t > 1000 for t in times),
        "slowest": sorted(((round(t), step) for step, t in enumerate(times)), reverse=True)[:5],
        "timeouts": int(res.get("numEntryTimeouts", 0)),
    }


def check(problem: Path, out: Path, finished: int) -> str:
    if not CHECKER.is_file():
        return "no checker"
    p = subprocess.run([sys.executable, str(CHECKER), str(problem), str(out)], capture_output=True, text=True)
    try:
        v = json.loads(p.stdout.strip().splitlines()[-1])
    except (IndexError, ValueError):
        return f"checker failed: {p.stderr.strip()[-200:]}"
    if v["valid"] and v["finished"] == finished:
        return "valid, same count"
    return f"REFUSED: {v}"


def run_one(entry: str, argv: list[str], problem: Path, steps: int, do_check: bool) -> dict[str, Any]:
    """One run of ``entry`` in a child process; its row."""
    with tempfile.TemporaryDirectory(prefix="lorr-bench-") as tmp:
        out, log = Path(tmp) / "result.json", Path(tmp) / "log.txt"
        argv = [a.replace("{out}", str(out)) for a in argv]
        code, wall, rss = child(argv, log)
        row: dict[str, Any] = {"entry": entry, "steps": steps, "wall_s": wall, "rss_mb": rss}
        if code != 0 or not out.is_file():
            tail = log.read_text(errors="replace").strip().splitlines()[-3:]
            return {**row, "failed": f"exit {code}: {' / '.join(tail)}"}
        row.update(result_figures(out))
        if entry.startswith("ours"):
            row.update(json.loads(log.read_text().strip().splitlines()[-1]))
        else:
            row["by_1000"] = row["finished"] if steps == 1000 else None
        row["checker"] = check(problem, out, row["finished"]) if do_check else "not run"
        return row


def share(row: dict[str, Any], name: str) -> str:
    known = BEST_KNOWN.get(name)
    if "failed" in row or known is None or known[1] != row["steps"]:
        return ""
    return f"{100 * row['finished'] / known[0]:.0f} %"


def planner_of(row: dict[str, Any]) -> str:
    """Our planner in a row: entry ``ours`` is ``pibt`` (this script's default), ``ours:NAME`` another."""
    return row["entry"].partition(":")[2] or "pibt"


def table(rows: dict[str, dict[str, Any]]) -> list[str]:
    head = [
        "| instance | robots | entry | steps | finished | by step 1,000 | best known (steps) | share "
        "| ms/step mean | max | rounds > 1 s | peak memory | checker |",
        "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |",
    ]
    lines = []
    order = lambda r: (r["instance"], not r["entry"].startswith("ours"), r["entry"], r["steps"])  # noqa: E731
    for row in sorted(rows.values(), key=order):
        name = row["instance"]
        known = BEST_KNOWN.get(name)
        known_text = f"{known[0]:,} ({known[1]:,})" if known else ""
        year = " (2023)" if "23" in name.split("-")[0] else ""
        who = f"MultiBots `{planner_of(row)}`" if row["entry"].startswith("ours") else f"Start-Kit{year} default"
        if "failed" in row:
            lines.append(f"| {name} | | {who} | {row['steps']:,} | {row['failed']} | | {known_text} | | | | | | |")
            continue
        by = f"{row['by_1000']:,}" if row.get("by_1000") is not None else ""
        timeouts = f" ({row['timeouts']:,} timeouts)" if row.get("timeouts") else ""
        lines.append(
            f"| {name} | {row['robots']:,} | {who} | {row['steps']:,} | {row['finished']:,}{timeouts} | {by} | "
            f"{known_text} | {share(row, name)} | {row['ms_mean']:.1f} | {row['ms_max']:.0f} | "
            f"{row['rounds_over_1s']} | {row['rss_mb'] / 1024:.2f} GB | {row['checker']} |"
        )
    return head + lines


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    return f"{cpu}, {os.cpu_count()} cores, {mem:.0f} GB, {platform.system()} {platform.release()}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--instances", type=Path, help="a folder of the archive's problems")
    ap.add_argument("--only", nargs="*", default=[], help="instance names or patterns (MR24-WAREHOUSE, 'TR23-*')")
    ap.add_argument("--domain", nargs="*", default=[], help="warehouse, random, city, game")
    ap.add_argument("--steps", type=int, help="default: each instance's simulation time, else 5,000")
    ap.add_argument("--startkit", type=Path, help="the Start-Kit's lifelong binary (2024 rules)")
    ap.add_argument("--startkit-2023", type=Path, help="the 2023 Start-Kit's lifelong binary")
    ap.add_argument("--startkit-steps", type=int, help="default: as --steps")
    ap.add_argument("--startkit-time-limit", type=int, default=1000, help="ms per planning round (its default)")
    ap.add_argument("--scheduler", default="spread")
    ap.add_argument("--planner", default="pibt",
                    help="ours: pibt (rows named `ours`), pibt-one-way, rpibt-pp, ... (docs/lorr.md)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--rows", type=Path, help="a JSON file keeping the rows across invocations")
    ap.add_argument("--no-check", action="store_true")
    ap.add_argument("--no-ours", action="store_true", help="only the Start-Kit")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--table-only", action="store_true", help="run nothing: write the table of --rows")
    args = ap.parse_args()
    if args.instances is None and not args.table_only:
        ap.error("--instances DIR is needed (or --table-only)")
    command = shlex.join(["python3", "benchmarks/lorr.py", *sys.argv[1:]])

    rows: dict[str, dict[str, Any]] = {}
    if args.rows and args.rows.is_file():
        rows = json.loads(args.rows.read_text())
    found = [] if args.table_only else chosen(problems(args.instances), args.only, args.domain)
    for name, problem, why in found:
        if why:
            print(f"{name}: skipped, {why}", flush=True)
            continue
        steps = args.steps or BEST_KNOWN.get(name, (0, 5000))[1]
        y2024 = "2024" in str(json.loads(problem.read_text()).get("version", ""))
        runs = []
        if not args.no_ours:
            py = [sys.executable, "-c", OURS, str(ROOT / "python"), str(problem), str(steps), "{out}"]
            entry = "ours" if args.planner == "pibt" else f"ours:{args.planner}"
            runs.append((entry, [*py, args.scheduler, str(args.seed), args.planner], steps))
        kit = args.startkit if y2024 else args.startkit_2023
        if kit:
            kit_steps = args.startkit_steps or steps
            # The 2023 Start-Kit takes its limit in whole seconds, the 2024 one in ms.
            limit = args.startkit_time_limit if y2024 else max(1, args.startkit_time_limit // 1000)
            argv = [str(kit.resolve()), "--inputFile", str(problem.resolve()), "--output", "{out}"]
            argv += ["--simulationTime", str(kit_steps), "--planTimeLimit", str(limit)]
            runs.append(("startkit", argv, kit_steps))
        for entry, argv, n in runs:
            row = {"instance": name, **run_one(entry, argv, problem, n, not args.no_check), "command": command}
            rows[f"{name}/{entry}/{n}"] = row
            print(table({"x": row})[-1], flush=True)
            if args.rows:
                args.rows.write_text(json.dumps(rows, indent=1))
    if args.no_write:
        return
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import sections

    commands: list[str] = []
    for row in rows.values():
        if row.get("command") and row["command"] not in commands:
            commands.append(row["command"])
    body = [
        "## League of Robot Runners instances (`benchmarks/lorr.py`)",
        "",
        "The rows were made by these commands (a later run of an instance, entry and steps replaces "
        "an earlier one), with `--rows` keeping them between runs:",
        "",
        "```console",
        *(f"$ {c}" for c in commands),
        "```",
        "",
        f"On {machine()}, shared with other jobs (ms/step is noisy, memory is not).",
        "MultiBots: the planner each row names (`multibots lorr`'s default, `auto`, is `pibt-one-way` up to 30 % of "
        "the free cells taken, `pibt` above; this script's `--planner` stays `pibt`, so that rows keyed `ours` keep "
        f"meaning `pibt`), scheduler `{args.scheduler}` (2024), "
        f"seed {args.seed}, no time limit. "
        f"Start-Kit: its default planner and scheduler, {args.startkit_time_limit} ms per round. "
        f"Best known: {ARCHIVE}; a share only where the steps match.",
        "",
        *table(rows),
    ]
    sections.put("lorr", "\n".join(body))


if __name__ == "__main__":
    main()
