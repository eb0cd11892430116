"""League of Robot Runners problems: our planner, and the Start-Kit's, against the best-known score.

    python3 benchmarks/lorr.py --instances DIR [--only NAME ...] [--domain warehouse ...]
                               [--steps N] [--startkit PATH/lifelong ...] [--startkit-2023 PATH/lifelong]
                               [--startkit-steps N] [--scheduler NAME] [--planner NAME] [--seed 0]
                               [--rows ROWS.json] [--no-check] [--no-ours] [--no-write]

``DIR`` is a folder of problems: one the user fetched from MAPF-Competition/Benchmark-Archive
(2023 and 2024), or the Start-Kit v3's examples (2026, one ``*.domain/`` folder per domain).
The instance files have no licence and are never committed. Every problem JSON under it (or
those named by ``--only``, shell patterns allowed) is run in a child process of its own, under
the rules its file names (``"version"``: ``2026 LoRR`` or a ``delayConfig`` is 2026, ``2024``
is 2024, anything else 2023; as ``multibots.lorr`` tells them):

- with our planner (``multibots.lorr.run``) for ``--steps`` steps. 2023 and 2024: by default
  the instance's own simulation time (the steps its best-known count was made in), planner
  ``pibt`` (not the command's ``auto``, so that rows keyed ``ours`` keep meaning ``pibt``),
  scheduler ``spread``. 2026: steps are ticks, by default those of issue 40's targets
  (:data:`TICKS_2026`: 500, 1,500 for ``fulfill-example_2500``), planner and scheduler
  ``auto`` (the row names the planner that played);
- with ``--startkit BIN``, the Start-Kit's ``lifelong`` (its default entry, built by the user)
  on the problems of the rules it was built for, which its ``--help`` tells: a v3 build
  (2026 rules; it has ``--planCommTimeLimit``) runs ``lifelong -i P -o OUT -s TICKS -c 1``, a
  2024 build ``--inputFile P --output OUT --simulationTime N --planTimeLimit MS``. Give it
  twice for both; ``--startkit-2023 BIN`` is the 2023 Start-Kit, for the 2023 problems. Each
  runs for ``--startkit-steps`` (default: as ours), in the Start-Kit's own folder (the
  ``build/`` folder's parent), from where its Python entries are imported.

Each result is checked by the independent checker beside the repository
(``../shared/tools/lorr_check.py`` for 2023 and 2024, ``lorr_check26.py`` for 2026, when it is
there; ``--no-check`` skips it), and the table gives the score, its share of the best-known count
(only when run for the same number of steps), planning ms per step (mean and max, from the
result's ``plannerTimes``), and peak memory (the child's maximum RSS from ``wait4``). The 2026
table gives instead the wall time, the load when the run began, and for ours the tasks and the
wall time against the Start-Kit's row of the same problem and ticks, with the targets of issue
40 (tasks at least the Start-Kit's, wall at most a tenth of its, at most 4 GB, valid with the
same count). Rows are kept in ``--rows`` (JSON, merged by instance, entry and steps), so that
runs made in several invocations land in one table (``--table-only`` runs nothing and writes
it). The 2023 and 2024 rows go to the ``lorr`` section of docs/benchmarks.md and the 2026 rows
to the ``lorr26`` section, each with the commands that made its rows and the machine, unless
``--no-write``; a section is written only when the rows have some of its rules.
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
from typing import Any, Optional

ROOT = Path(__file__).resolve().parent.parent
TOOLS = ROOT.parent / "shared" / "tools"
#: The independent checker of each rule set's results.
CHECKERS = {"2023": TOOLS / "lorr_check.py", "2024": TOOLS / "lorr_check.py", "2026": TOOLS / "lorr_check26.py"}

# Ticks of the 2026 examples (Start-Kit v3.1.0, `example_problems`) in issue 40's targets, where
# the Start-Kit's reference runs were made; any other 2026 problem runs DEFAULT_TICKS_2026.
TICKS_2026: dict[str, int] = {
    "maze-example_40": 500,
    "room-example_150": 500,
    "random-example_400": 500,
    "bos-example_600": 500,
    "orz-example_1800": 500,
    "fulfill-example_2500": 1500,
    "iron-example_10000": 500,
}
DEFAULT_TICKS_2026 = 500
# Issue 40's targets for ours against the Start-Kit's default entry on the same problem and ticks.
WALL_SHARE_2026 = 0.1
MEMORY_GB_2026 = 4.0

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


def rules_of(spec: dict[str, Any]) -> str:
    """The rules a problem plays under, as ``multibots.lorr`` tells them: "2023", "2024" or "2026"."""
    version = str(spec.get("version", ""))
    if "2026" in version or "delayConfig" in spec:
        return "2026"
    return "2024" if "2024" in version else "2023"


def default_steps(name: str, rules: str) -> int:
    """Steps (2026: ticks) a problem runs for when ``--steps`` is not given."""
    if rules == "2026":
        return TICKS_2026.get(name, DEFAULT_TICKS_2026)
    return BEST_KNOWN.get(name, (0, 5000))[1]


def rules_from_help(text: str) -> str:
    """The rules a Start-Kit build plays, from its ``--help``: only v3 (2026) has a communication
    time limit (the planner is called on a clock, not every step). 2023 builds are not told
    from 2024 ones (``--startkit-2023``)."""
    return "2026" if "planCommTimeLimit" in text else "2024"


def kit_rules(binary: Path) -> str:
    """The rules of a Start-Kit binary (:func:`rules_from_help` on its ``--help``)."""
    p = subprocess.run([str(binary), "--help"], capture_output=True, text=True, timeout=60)
    return rules_from_help(p.stdout + p.stderr)


def kit_home(binary: Path) -> Path:
    """Where a Start-Kit runs: its source folder (it imports its Python entries from
    ``python/user_*`` relative to the working directory), the parent of ``build/``."""
    binary = binary.resolve()
    return binary.parent.parent if binary.parent.name == "build" else binary.parent


def kit_argv(kit: Path, rules: str, problem: Path, steps: int, time_limit_ms: int) -> list[str]:
    """The Start-Kit's command line for one problem (``{out}`` stands for the result file)."""
    argv = [str(kit.resolve())]
    if rules == "2026":
        # v3.1.0 keeps its own clock (100 ms a tick, a planner call per 1,000 ms): issue 40's command.
        return [*argv, "-i", str(problem.resolve()), "-o", "{out}", "-s", str(steps), "-c", "1"]
    # The 2023 Start-Kit takes its limit in whole seconds, the 2024 one in ms.
    limit = time_limit_ms if rules == "2024" else max(1, time_limit_ms // 1000)
    return [*argv, "--inputFile", str(problem.resolve()), "--output", "{out}", "--simulationTime", str(steps),
            "--planTimeLimit", str(limit)]


def our_choice(rules: str, planner: Optional[str], scheduler: Optional[str]) -> tuple[str, str, str]:
    """(entry, planner, scheduler) of our run: by default ``pibt`` and ``spread`` under the 2023
    and 2024 rules (rows keyed ``ours`` keep meaning ``pibt``), ``auto`` under the 2026 rules
    (the row then names the planner that played); another planner is entry ``ours:NAME``."""
    default = "auto" if rules == "2026" else "pibt"
    planner = planner or default
    scheduler = scheduler or ("auto" if rules == "2026" else "spread")
    return ("ours" if planner == default else f"ours:{planner}"), planner, scheduler


def chosen(found: list[tuple[str, Path, str]], only: list[str], domains: list[str]) -> list[tuple[str, Path, str]]:
    keep = []
    for name, path, why in found:
        if only and not any(fnmatch.fnmatchcase(name, pat) for pat in only):
            continue
        if domains and not any(f"{d}.domain" in path.as_posix() for d in domains):
            continue
        keep.append((name, path, why))
    return keep


def child(argv: list[str], log: Path, cwd: Optional[Path] = None) -> tuple[int, float, float]:
    """Runs ``argv`` (output to ``log``): exit code, wall seconds, peak RSS in MB of that child."""
    began = time.monotonic()
    with log.open("wb") as out:
        proc = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT, cwd=cwd)
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
                  "planner": r.planner, "scheduler": r.scheduler,
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


def check(problem: Path, out: Path, finished: int, rules: str = "2024") -> str:
    checker = CHECKERS[rules]
    if not checker.is_file():
        return "no checker"
    p = subprocess.run([sys.executable, str(checker), str(problem), str(out)], capture_output=True, text=True)
    return verdict(p.stdout, p.stderr, finished)


def verdict(stdout: str, stderr: str, finished: int) -> str:
    """The checker's last line, in a table's words (its first warning kept: a valid result can still
    carry one, such as a tick the Start-Kit left unrecorded)."""
    try:
        v = json.loads(stdout.strip().splitlines()[-1])
    except (IndexError, ValueError):
        return f"checker failed: {stderr.strip()[-200:]}"
    if v["valid"] and v["finished"] == finished:
        warnings = v.get("warnings") or []
        return "valid, same count" + (f" (warns: {warnings[0]})" if warnings else "")
    return f"REFUSED: {v}"


def load() -> str:
    """The 1-minute load average (other engineers' builds share the machine)."""
    try:
        return Path("/proc/loadavg").read_text().split()[0]
    except (OSError, IndexError):
        return ""


def run_one(entry: str, argv: list[str], problem: Path, steps: int, do_check: bool, rules: str = "2024",
            cwd: Optional[Path] = None) -> dict[str, Any]:
    """One run of ``entry`` in a child process; its row."""
    with tempfile.TemporaryDirectory(prefix="lorr-bench-") as tmp:
        out, log = Path(tmp) / "result.json", Path(tmp) / "log.txt"
        argv = [a.replace("{out}", str(out)) for a in argv]
        began_load = load()
        code, wall, rss = child(argv, log, cwd)
        row: dict[str, Any] = {"entry": entry, "steps": steps, "wall_s": wall, "rss_mb": rss, "rules": rules,
                               "load": began_load}
        if code != 0 or not out.is_file():
            tail = log.read_text(errors="replace").strip().splitlines()[-3:]
            return {**row, "failed": f"exit {code}: {' / '.join(tail)}"}
        row.update(result_figures(out))
        if entry.startswith("ours"):
            row.update(json.loads(log.read_text().strip().splitlines()[-1]))
        else:
            row["by_1000"] = row["finished"] if steps == 1000 else None
        row["checker"] = check(problem, out, row["finished"], rules) if do_check else "not run"
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


def is_2026(row: dict[str, Any]) -> bool:
    return row.get("rules") == "2026"


def kit_row(rows: dict[str, dict[str, Any]], row: dict[str, Any]) -> Optional[dict[str, Any]]:
    """The Start-Kit's row of the same problem and steps as ``row``, when it ran and gave a result."""
    kit = rows.get(f"{row['instance']}/startkit/{row['steps']}")
    return kit if kit is not None and "failed" not in kit else None


def ratio(ours: float, theirs: float, digits: str = ".2f") -> str:
    """``ours ÷ theirs`` (a wall time's two significant digits with ``digits=".2g"``)."""
    return f"{ours / theirs:{digits}}" if theirs > 0 else ""


def targets_2026(row: dict[str, Any], kit: Optional[dict[str, Any]]) -> str:
    """Which of issue 40's targets a row of ours misses (against the Start-Kit's row ``kit``)."""
    missed = []
    if not row["checker"].startswith("valid, same count"):
        missed.append("checker")
    if row["rss_mb"] / 1024 > MEMORY_GB_2026:
        missed.append(f"memory > {MEMORY_GB_2026:.0f} GB")
    if kit is None:
        return ", ".join(["no Start-Kit row", *missed])
    if row["finished"] < kit["finished"]:
        missed.append("tasks")
    if row["wall_s"] > WALL_SHARE_2026 * kit["wall_s"]:
        missed.append("wall")
    return "missed: " + ", ".join(missed) if missed else "met"


def table26(rows: dict[str, dict[str, Any]]) -> list[str]:
    """The 2026 rows, ours beside the Start-Kit's, by fleet size."""
    head = [
        "| problem | robots | entry | ticks | tasks | tasks ÷ Start-Kit's | wall | wall ÷ Start-Kit's "
        "| peak memory | load | checker | targets |",
        "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- |",
    ]
    order = lambda r: (r.get("robots", 0), r["instance"], not r["entry"].startswith("ours"), r["entry"], r["steps"])  # noqa: E731
    return head + [line26(rows, r) for r in sorted(filter(is_2026, rows.values()), key=order)]


def line26(rows: dict[str, dict[str, Any]], row: dict[str, Any]) -> str:
    """A 2026 row of :func:`table26`; one of ours is set against the Start-Kit's row in ``rows``."""
    name = f"`{row['instance']}`"
    ours = row["entry"].startswith("ours")
    who = f"MultiBots `{row.get('planner', planner_of(row))}`" if ours else \
        f"Start-Kit {row.get('kit_version', '')} default".replace("  ", " ")
    robots = f"{row['robots']:,}" if "robots" in row else ""
    if "failed" in row:
        return f"| {name} | {robots} | {who} | {row['steps']:,} | {row['failed']} | | | | | {row.get('load', '')} | | |"
    kit = kit_row(rows, row) if ours else None
    tasks_vs = ratio(row["finished"], kit["finished"]) if kit else ""
    wall_vs = ratio(row["wall_s"], kit["wall_s"], ".2g") if kit else ""
    goals = targets_2026(row, kit) if ours else ""
    return (
        f"| {name} | {robots} | {who} | {row['steps']:,} | {row['finished']:,} | {tasks_vs} | "
        f"{row['wall_s']:.1f} s | {wall_vs} | {row['rss_mb'] / 1024:.2f} GB | {row.get('load', '')} | "
        f"{row['checker']} | {goals} |"
    )


def kit_version(binary: Path) -> str:
    """The Start-Kit's ``version.txt`` (v3 has one), or ""."""
    try:
        return "v" + (kit_home(binary) / "version.txt").read_text().strip()
    except OSError:
        return ""


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
    ap.add_argument("--instances", type=Path, help="a folder of problems (the archive's, the 2026 examples)")
    ap.add_argument("--only", nargs="*", default=[], help="instance names or patterns (MR24-WAREHOUSE, 'TR23-*')")
    ap.add_argument("--domain", nargs="*", default=[], help="warehouse, random, city, game, maze, ...")
    ap.add_argument("--steps", type=int,
                    help="default: each instance's simulation time, else 5,000; 2026: ticks, TICKS_2026 or 500")
    ap.add_argument("--startkit", type=Path, action="append", default=[],
                    help="a Start-Kit's lifelong binary, run on the problems of its rules (2024 or 2026, "
                         "told by its --help); give it twice for both")
    ap.add_argument("--startkit-2023", type=Path, help="the 2023 Start-Kit's lifelong binary")
    ap.add_argument("--startkit-steps", type=int, help="default: as --steps")
    ap.add_argument("--startkit-time-limit", type=int, default=1000,
                    help="ms per planning round (its default; 2023 and 2024 only)")
    ap.add_argument("--scheduler", help="ours: default spread (2024), auto (2026)")
    ap.add_argument("--planner",
                    help="ours: default pibt (2023, 2024: rows named `ours`), auto (2026); pibt-one-way, "
                         "rpibt-pp, ... (docs/lorr.md)")
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
    kits: dict[str, Path] = {}
    for kit in args.startkit:
        try:
            rules = kit_rules(kit)
        except (OSError, subprocess.SubprocessError) as e:
            ap.error(f"--startkit {kit}: cannot run it ({e})")
        if rules in kits:
            ap.error(f"--startkit {kit} and {kits[rules]} are both {rules} Start-Kits")
        kits[rules] = kit
    if args.startkit_2023:
        kits["2023"] = args.startkit_2023

    rows: dict[str, dict[str, Any]] = {}
    if args.rows and args.rows.is_file():
        rows = json.loads(args.rows.read_text())
    found = [] if args.table_only else chosen(problems(args.instances), args.only, args.domain)
    for name, problem, why in found:
        if why:
            print(f"{name}: skipped, {why}", flush=True)
            continue
        spec = json.loads(problem.read_text())
        rules = rules_of(spec)
        steps = args.steps or default_steps(name, rules)
        runs: list[tuple[str, list[str], int, Optional[Path]]] = []
        if not args.no_ours:
            entry, planner, scheduler = our_choice(rules, args.planner, args.scheduler)
            py = [sys.executable, "-c", OURS, str(ROOT / "python"), str(problem), str(steps), "{out}"]
            runs.append((entry, [*py, scheduler, str(args.seed), planner], steps, None))
        kit = kits.get(rules)
        if kit:
            kit_steps = args.startkit_steps or steps
            argv = kit_argv(kit, rules, problem, kit_steps, args.startkit_time_limit)
            runs.append(("startkit", argv, kit_steps, kit))
        for entry, argv, n, binary in runs:
            cwd = kit_home(binary) if binary else None
            row = {"instance": name, "robots": int(spec.get("teamSize", 0)),
                   **run_one(entry, argv, problem, n, not args.no_check, rules, cwd), "command": command}
            if binary:
                row["kit_version"] = kit_version(binary)
            rows[f"{name}/{entry}/{n}"] = row
            print(line26(rows, row) if rules == "2026" else table({"x": row})[-1], flush=True)
            if args.rows:
                args.rows.write_text(json.dumps(rows, indent=1))
    if args.no_write:
        return
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import sections

    old = {k: r for k, r in rows.items() if not is_2026(r)}
    new = {k: r for k, r in rows.items() if is_2026(r)}
    if old:
        sections.put("lorr", "\n".join(body_2024(old, args)))
    if new:
        sections.put("lorr26", "\n".join(body_2026(new)))


def commands_of(rows: dict[str, dict[str, Any]]) -> list[str]:
    commands: list[str] = []
    for row in rows.values():
        if row.get("command") and row["command"] not in commands:
            commands.append(row["command"])
    return commands


def body_2024(rows: dict[str, dict[str, Any]], args: argparse.Namespace) -> list[str]:
    return [
        "## League of Robot Runners instances (`benchmarks/lorr.py`)",
        "",
        "The rows were made by these commands (a later run of an instance, entry and steps replaces "
        "an earlier one), with `--rows` keeping them between runs:",
        "",
        "```console",
        *(f"$ {c}" for c in commands_of(rows)),
        "```",
        "",
        f"On {machine()}, shared with other jobs (ms/step is noisy, memory is not).",
        "MultiBots: the planner each row names (`multibots lorr`'s default, `auto`, is `rpibt-pp` on maps of at most "
        "2,000 free cells, `pibt-no-lanes` there from 90 % of them taken; elsewhere `pibt-one-way` up to 30 % of "
        "the free cells taken, `pibt` above; this script's `--planner` stays `pibt`, so that rows keyed `ours` keep "
        f"meaning `pibt`), scheduler `{args.scheduler or 'spread'}` (2024), "
        f"seed {args.seed}, no time limit. "
        f"Start-Kit: its default planner and scheduler, {args.startkit_time_limit} ms per round. "
        f"Best known: {ARCHIVE}; a share only where the steps match.",
        "",
        *table(rows),
    ]


def body_2026(rows: dict[str, dict[str, Any]]) -> list[str]:
    loads = sorted(float(r["load"]) for r in rows.values() if r.get("load"))
    load_text = f"{loads[0]:.1f} to {loads[-1]:.1f}" if loads else "not recorded"
    return [
        "## League of Robot Runners 2026 problems (`benchmarks/lorr.py`)",
        "",
        "The Start-Kit v3.1.0's example problems under the 2026 rules, ours beside the Start-Kit's default "
        "entry (`lifelong -i P -o OUT -s TICKS -c 1`: its C++ scheduler, planner and executor, a 100 ms "
        "tick and a planner call per 1,000 ms, so its wall time is set by its clock). Made by these "
        "commands (a later run of a problem, entry and ticks replaces an earlier one):",
        "",
        "```console",
        *(f"$ {c}" for c in commands_of(rows)),
        "```",
        "",
        f"On {machine()}, shared with other engineers' builds and runs: the 1-minute load when a run "
        f"began was {load_text} (column `load`). It inflates our wall times; the Start-Kit's are set by "
        "its clock (about 45 s per 500 ticks), though a loaded one falls behind it and skips ticks "
        "(the checker's warnings), and its counts vary from run to run (docs/lorr.md, Measured (2026)). "
        "Ours: "
        "`multibots.lorr.run` in a child process (the wall includes "
        "starting Python and importing MultiBots), planner and scheduler `auto` (the row names the "
        "planner that played), no time limit. Every result is checked by `lorr_check26.py`; "
        "peak memory is the child's maximum RSS. Targets (issue 40): tasks at least the Start-Kit's, "
        f"wall at most {WALL_SHARE_2026:g} of its, at most {MEMORY_GB_2026:g} GB, valid with the same count.",
        "",
        *table26(rows),
    ]


if __name__ == "__main__":
    main()
