"""``benchmarks/lorr.py`` on 2026 problems: it finds them in the Start-Kit's ``*.domain/``
folders, runs each for its ticks with the Start-Kit build of its rules (told by the binary's
``--help``) and the 2026 checker, and puts ours beside the Start-Kit's row. A stand-in
``lifelong`` (a script that plays the problem with MultiBots) shows what the script hands the
Start-Kit; the real one is measured in docs/benchmarks.md, not here."""

from __future__ import annotations

import importlib.util
import json
import shutil
import stat
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = ROOT / "benchmarks" / "lorr.py"
TINY = ROOT / "examples" / "lorr26"
CHECKER26 = ROOT.parent / "shared" / "tools" / "lorr_check26.py"

_spec = importlib.util.spec_from_file_location("lorr_benchmark", SCRIPT)
assert _spec is not None and _spec.loader is not None
bench: Any = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench)


def problem(folder: Path, name: str, **spec: Any) -> Path:
    """A problem file ``name`` with its map, agents and tasks files beside it."""
    folder.mkdir(parents=True, exist_ok=True)
    for ext in ("map", "agents", "tasks"):
        shutil.copy(TINY / f"tiny.{ext}", folder / f"tiny.{ext}")
    body = {"mapFile": "tiny.map", "agentFile": "tiny.agents", "taskFile": "tiny.tasks", "teamSize": 3, **spec}
    path = folder / f"{name}.json"
    path.write_text(json.dumps(body))
    return path


def test_2026_problems_are_found_in_domain_folders_with_their_rules(tmp_path: Path) -> None:
    new = problem(tmp_path / "maze.domain", "maze-example_40", version="2026 LoRR")
    old = problem(tmp_path / "2024 Competition" / "Main Round", "CITY-01", version="2024 LoRR")
    (tmp_path / "maze.domain" / "notes.json").write_text('{"not": "a problem"}')
    found = bench.problems(tmp_path)
    assert [(name, path, why) for name, path, why in found] == [
        ("MR24-CITY-01", old, ""), ("maze-example_40", new, "")]
    assert [n for n, _, _ in bench.chosen(found, [], ["maze"])] == ["maze-example_40"]
    assert bench.rules_of(json.loads(new.read_text())) == "2026"
    assert bench.rules_of(json.loads(old.read_text())) == "2024"
    # A delay model alone makes a problem 2026, as multibots.lorr tells it.
    assert bench.rules_of({"delayConfig": {}}) == "2026"
    assert bench.rules_of({"version": "LoRR 2023"}) == "2023"


def test_ticks_default_to_the_issue_targets_and_steps_to_the_best_known() -> None:
    assert bench.default_steps("fulfill-example_2500", "2026") == 1500
    assert bench.default_steps("iron-example_10000", "2026") == 500
    assert bench.default_steps("someone-elses_7", "2026") == bench.DEFAULT_TICKS_2026
    assert bench.default_steps("MR24-RANDOM-01", "2024") == 600
    assert bench.default_steps("unknown", "2024") == 5000


def test_the_start_kit_build_and_its_command_line_follow_the_rules(tmp_path: Path) -> None:
    assert bench.rules_from_help("  -t [ --planCommTimeLimit ] arg (=1000)") == "2026"
    assert bench.rules_from_help("  --planTimeLimit arg (=1000)") == "2024"
    kit = tmp_path / "startkit" / "build" / "lifelong"
    p = tmp_path / "p.json"
    argv = bench.kit_argv(kit, "2026", p, 1500, 1000)
    assert argv[1:] == ["-i", str(p.resolve()), "-o", "{out}", "-s", "1500", "-c", "1"]
    assert "--planTimeLimit" in bench.kit_argv(kit, "2024", p, 600, 1000)
    assert bench.kit_argv(kit, "2023", p, 600, 2500)[-1] == "2"
    assert bench.kit_home(kit) == (tmp_path / "startkit").resolve()


def test_ours_plays_auto_under_2026_and_pibt_before() -> None:
    assert bench.our_choice("2026", None, None) == ("ours", "auto", "auto")
    assert bench.our_choice("2024", None, None) == ("ours", "pibt", "spread")
    assert bench.our_choice("2026", "pibt", None) == ("ours:pibt", "pibt", "auto")
    assert bench.our_choice("2024", "rpibt-pp", "soonest") == ("ours:rpibt-pp", "rpibt-pp", "soonest")


def test_the_checker_verdict_keeps_refusals_and_warnings() -> None:
    ok = json.dumps({"valid": True, "finished": 44, "claimed": 44, "warnings": ["1 ticks were skipped"]})
    assert bench.verdict(ok, "", 44) == "valid, same count (warns: 1 ticks were skipped)"
    assert bench.verdict(ok, "", 45).startswith("REFUSED")
    refused = json.dumps({"valid": False, "finished": 3, "claimed": 9, "error": "collision"})
    assert bench.verdict(refused, "", 9).startswith("REFUSED")
    assert bench.verdict("", "Traceback: boom", 9) == "checker failed: Traceback: boom"


def row(entry: str, finished: int, wall: float, rss_mb: float = 100.0, **more: Any) -> dict[str, Any]:
    return {"instance": "maze-example_40", "robots": 40, "entry": entry, "steps": 500, "rules": "2026",
            "finished": finished, "wall_s": wall, "rss_mb": rss_mb, "load": "1.5",
            "checker": "valid, same count", **more}


def test_the_2026_table_puts_ours_against_the_start_kit_and_names_missed_targets() -> None:
    rows = {"maze-example_40/startkit/500": row("startkit", 48, 44.0, kit_version="v3.1.0"),
            "maze-example_40/ours/500": row("ours", 50, 0.5, planner="rpibt-pp")}
    lines = bench.table26(rows)
    ours, kit = lines[2], lines[3]
    assert "MultiBots `rpibt-pp`" in ours and "Start-Kit v3.1.0 default" in kit
    assert "| 1.04 |" in ours and "| 0.011 |" in ours and ours.endswith("| met |")
    rows["maze-example_40/ours/500"] = row("ours", 47, 5.0, rss_mb=5000.0, planner="rpibt-pp")
    assert bench.table26(rows)[2].endswith("| missed: memory > 4 GB, tasks, wall |")
    rows["maze-example_40/ours/500"]["checker"] = "REFUSED: {}"
    assert "missed: checker" in bench.table26(rows)[2]
    del rows["maze-example_40/startkit/500"]
    assert "no Start-Kit row" in bench.table26(rows)[2]
    # 2024 rows stay in the other table.
    rows["x/ours/600"] = {**row("ours", 1, 1.0), "instance": "x", "rules": "2024"}
    assert len(bench.table26(rows)) == 3


FAKE_KIT = """#!{python}
# A stand-in for the Start-Kit v3's lifelong: it says it is v3, records how it was called,
# and plays the problem with MultiBots so that the checker has a real result to replay.
import json, os, sys
if sys.argv[1:] == ["--help"]:
    print("  -t [ --planCommTimeLimit ] arg (=1000)")
    sys.exit(0)
a = sys.argv[1:]
with open({calls!r}, "a") as f:
    f.write(json.dumps({{"argv": a, "cwd": os.getcwd()}}) + "\\n")
from multibots import lorr
lorr.run(a[a.index("-i") + 1], steps=int(a[a.index("-s") + 1]), out=a[a.index("-o") + 1])
"""


@pytest.mark.skipif(not CHECKER26.is_file(), reason=f"no 2026 checker at {CHECKER26}")
def test_a_2026_problem_runs_end_to_end_beside_a_start_kit(tmp_path: Path) -> None:
    tiny = problem(tmp_path / "problems" / "tiny.domain", "tiny", **json.loads((TINY / "tiny.json").read_text()))
    home = tmp_path / "kit"
    (home / "build").mkdir(parents=True)
    calls = tmp_path / "calls.jsonl"
    kit = home / "build" / "lifelong"
    kit.write_text(FAKE_KIT.format(python=sys.executable, calls=str(calls)))
    kit.chmod(kit.stat().st_mode | stat.S_IXUSR)
    (home / "version.txt").write_text("3.1.0\n")
    rows_file = tmp_path / "rows.json"
    p = subprocess.run(
        [sys.executable, str(SCRIPT), "--instances", str(tmp_path / "problems"), "--steps", "120",
         "--startkit", str(kit), "--rows", str(rows_file), "--no-write"],
        capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    call = json.loads(calls.read_text())
    assert call["argv"][:2] == ["-i", str(tiny.resolve())] and call["argv"][4:] == ["-s", "120", "-c", "1"]
    assert Path(call["cwd"]) == home.resolve()
    rows = json.loads(rows_file.read_text())
    assert set(rows) == {"tiny/ours/120", "tiny/startkit/120"}
    ours, theirs = rows["tiny/ours/120"], rows["tiny/startkit/120"]
    assert ours["rules"] == theirs["rules"] == "2026"
    assert ours["checker"] == theirs["checker"] == "valid, same count"
    assert ours["planner"] == "rpibt-pp"  # `auto` on a small map, the name of what played
    assert theirs["kit_version"] == "v3.1.0"
    assert ours["rss_mb"] > 0 and theirs["wall_s"] > 0
    # The same problem and ticks: ours is set against the stand-in's count.
    line = next(x for x in bench.table26(rows) if "MultiBots" in x)
    assert f"| {bench.ratio(ours['finished'], theirs['finished'])} |" in line
