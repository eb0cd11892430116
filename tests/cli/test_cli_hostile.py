"""Hostile input, hostile files (issue 16): each case is one line on stderr and exit 2 (or a
clear outcome), never a traceback, a hang, an abort or runaway memory; nothing half-written.

Each case runs the real command in a fresh interpreter under a 1 GB address-space limit
(``ulimit -v``), so a runaway allocation fails the test instead of the machine.
"""

from __future__ import annotations

import json
import os
import resource
import signal
import stat
import struct
import subprocess
import sys
import time
from pathlib import Path

import pytest

# The repository (a `conftest` import would find whichever conftest.py was loaded first).
ROOT = Path(__file__).resolve().parents[2]
MB = 1 << 20
SMALL = 'layout = "paper"\nrobots = 2\ntasks = [11, 8]\n'


def limited(*args, cwd: Path, timeout: float = 60, env: dict | None = None) -> subprocess.CompletedProcess[str]:
    """``multibots ARGS`` with at most 1 GB of address space: a runaway allocation fails
    there, as a one-line error or a crash the assertions see, not on the machine."""

    def cap() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))

    return subprocess.run([sys.executable, "-m", "multibots", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout, preexec_fn=cap, env=env)


def one_line(p: subprocess.CompletedProcess[str], *fragments: str, code: int = 2) -> str:
    assert p.returncode == code, (p.returncode, p.stdout[-400:], p.stderr[-800:])
    err = p.stderr.strip()
    assert err and len(err.splitlines()) == 1, err[:800]
    assert "Traceback" not in err and "internal error" not in err, err
    assert "\x1b" not in err, "control characters reach the terminal"
    assert len(err) < 1000, len(err)
    for frag in fragments:
        assert frag in err, (frag, err)
    return err


@pytest.fixture()
def files(tmp_path: Path) -> Path:
    (tmp_path / "ok.toml").write_text(SMALL)
    os.mkfifo(tmp_path / "fifo.toml")
    (tmp_path / "zero.toml").symlink_to("/dev/zero")
    (tmp_path / "folder.toml").mkdir()
    (tmp_path / "exists.csv").write_text("keep me\n")
    return tmp_path


@pytest.mark.parametrize(("args", "fragments"), [
    (["run", "fifo.toml"], ["fifo.toml", "not a regular file"]),
    (["run", "zero.toml"], ["zero.toml", "not a regular file"]),
    (["run", "folder.toml"], ["folder.toml", "is a directory"]),
    (["layout", "check", "fifo.toml"], ["not a regular file"]),
    (["layout", "check", "zero.toml"], ["not a regular file"]),
    (["view", "fifo.toml", "--no-browser"], ["not a regular file"]),
    (["view", "folder.toml", "--no-browser"], ["is a directory"]),
    (["render", "folder.toml", "--out", "x.gif"], ["is a directory"]),
    (["render", "zero.toml", "--out", "x.gif"], ["not a regular file"]),
    (["compare", "--out", "exists.csv", "--robots", "1..2", "--quiet"], ["--out", "exists.csv", "not a folder"]),
    (["paper", "--out", "exists.csv"], ["--out", "exists.csv", "not a folder"]),
    (["run", "ok.toml", "--record", "fifo.toml"], ["fifo.toml", "not a regular file"]),
    (["run", "ok.toml", "--record", "folder.toml"], ["folder.toml", "is a directory"]),
    (["run", "--goods", "11", "--margin", "nan"], ["--margin", "nan"]),
    (["run", "--goods", "11", "--margin", "inf"], ["--margin", "inf"]),
    (["run", "--goods", "11", "--robots", "99999999999999999999"], ["--robots"]),
    (["run", "--goods", "11", "--step-limit", "1e400"], ["--step-limit"]),
    (["layout", "generate", "--cell", "1e308", "--out", "g.toml"], ["--cell"]),
    (["layout", "generate", "--aisle", "nan", "--out", "g.toml"], ["--aisle"]),
    (["layout", "generate", "--group-size", "1x50000000", "--out", "g.toml"], []),
    (["layout", "generate", "--name", "", "--out", "g.toml"], ["name"]),
    (["compare", "--robots", "1..1000000000000000000", "--quiet"], ["--robots"]),
    (["compare", "--seeds", "1000000000", "--tasks", "random:5", "--quiet"], ["--seeds"]),
])
def test_each_case_is_one_line_and_exit_2(files: Path, args: list[str], fragments: list[str]) -> None:
    one_line(limited(*args, cwd=files), *fragments)
    assert (files / "exists.csv").read_text() == "keep me\n"
    assert stat.S_ISFIFO((files / "fifo.toml").stat().st_mode), "a FIFO was replaced"
    assert not (files / "g.toml").exists(), "a refused layout was written"


@pytest.mark.parametrize("body", [
    "robot.radius = 0.001",
    "[orders]\nrate = 1e300",
    "[orders]\nrate = 1e9\nhorizon = 1",
    "[orders]\nrate = 100000\nhorizon = 30000000",
    "[charging]\nlevel = nan",
    '[layout_generate]\ngroup_rows = 1\ngroup_cols = 1\ngroup_width = 1\ngroup_height = 50000000',
    "[layout_generate]\ncell = 1e308",
    "robots = 4294967296",
    f'unload = "{"x" * 10_000_000}"',
    'unload = "\x1b[31mred"',
])
def test_scenarios_that_would_exhaust_memory_run_bounded_or_are_refused(tmp_path: Path, body: str) -> None:
    text = SMALL.replace("robots = 2\n", "") if body.startswith("robots") else SMALL
    lines = text.splitlines()
    # Top-level keys go before the tables.
    head = [body] if not body.startswith("[") else []
    tail = [body] if body.startswith("[") else []
    if body.startswith("robot."):
        head, tail = [], ["[robot]", body.split(".", 1)[1]]
    if body.startswith("[layout_generate]"):
        lines = [ln for ln in lines if not ln.startswith("layout")]
    (tmp_path / "s.toml").write_text("\n".join(head + lines + tail) + "\n")
    p = limited("run", "s.toml", cwd=tmp_path)
    if body.startswith("robot.radius"):  # tiny robots are fine: the collision grid stays bounded
        assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
        return
    err = one_line(p)
    assert len(err) < 400


def test_code_in_a_scenario_file_needs_allow_code(tmp_path: Path) -> None:
    (tmp_path / "s.toml").write_text(SMALL + 'allocator = "os:abort"\n')
    one_line(limited("run", "s.toml", cwd=tmp_path), "os:abort", "--allow-code")
    one_line(limited("view", "--live", "s.toml", "--no-browser", cwd=tmp_path), "--allow-code")
    # A file in the current folder, allowed: it runs.
    (tmp_path / "mine.py").write_text("from multibots.strategies import BUILT_INS\n\n"
                                      "class Mine:\n    def allocate(self, view):\n        return {}\n")
    (tmp_path / "t.toml").write_text(SMALL + 'allocator = "mine.py:Mine"\nstep_limit = 50\n')
    one_line(limited("run", "t.toml", cwd=tmp_path), "--allow-code")
    p = limited("run", "t.toml", "--allow-code", cwd=tmp_path)
    assert p.returncode == 3 and "Traceback" not in p.stderr, p.stderr  # allowed, and the idle fleet never finishes
    # --allocator on the command line is the user's own choice.
    p = limited("run", "s.toml", "--allocator", "nearest", cwd=tmp_path)
    assert p.returncode == 0, p.stderr


def test_refused_code_is_never_imported(tmp_path: Path) -> None:
    # Checking a scenario loads its strategy: the refusal must come before anything is loaded.
    (tmp_path / "evil.py").write_text("open('RAN', 'w').close()\n\nclass S:\n    def allocate(self, view):\n"
                                      "        return {}\n")
    (tmp_path / "s.toml").write_text(SMALL + 'allocator = "evil.py:S"\n')
    (tmp_path / "inline.toml").write_text('base = { layout = "paper", tasks = [1, 2], allocator = "evil.py:S" }\n'
                                          "[axes]\nrobots = [1, 2]\n")
    (tmp_path / "file.toml").write_text('base = "s.toml"\n[axes]\nrobots = [1, 2]\n')
    (tmp_path / "axis.toml").write_text('base = { layout = "paper", tasks = [1, 2] }\n'
                                        '[axes]\nallocator = ["nearest", "evil.py:S"]\n')
    for args in (["run", "s.toml"], ["view", "--live", "s.toml", "--no-browser"],
                 ["sweep", "inline.toml", "--out", "o"], ["sweep", "file.toml", "--out", "o"],
                 ["sweep", "axis.toml", "--out", "o"]):
        one_line(limited(*args, cwd=tmp_path), "evil.py:S", "--allow-code")
        assert not (tmp_path / "RAN").exists(), args
    # compare's --strategies replaces the file's allocator, which is then never loaded.
    p = limited("compare", "--scenario", "s.toml", "--strategies", "in-turn", "--robots", "1", "--out", "c",
                "--quiet", "--no-plots", cwd=tmp_path)
    assert p.returncode == 0 and not (tmp_path / "RAN").exists(), p.stderr


def test_a_strategy_that_exits_on_import_or_cannot_run_is_a_one_line_error(tmp_path: Path) -> None:
    (tmp_path / "bye.py").write_text("import sys\nsys.exit(5)\n")
    (tmp_path / "ok.py").write_text("class S:\n    def allocate(self, view):\n        return {}\n")
    (tmp_path / "bye.toml").write_text(SMALL + 'allocator = "bye.py:S"\n')
    one_line(limited("run", "bye.toml", "--allow-code", cwd=tmp_path), "bye.py", "SystemExit: 5")
    # The original rules dispatch in turn only: said when the file is checked, before any run.
    (tmp_path / "orig.toml").write_text(SMALL + 'rules = "original"\nallocator = "ok.py:S"\n')
    one_line(limited("run", "orig.toml", "--allow-code", cwd=tmp_path), 'allocator = "ok.py:S"', "in turn only")


def test_a_raising_strategy_in_a_worker_is_named(tmp_path: Path) -> None:
    (tmp_path / "bad.py").write_text("class Raises:\n    def allocate(self, view):\n"
                                     "        raise KeyError('boom \\x1b[31m')\n")
    err = one_line(limited("compare", "--strategies", "bad.py:Raises", "--robots", "1..2", "--out", "c",
                           "--quiet", "--no-plots", cwd=tmp_path))
    assert "Raises" in err and "KeyError" in err and "boom" in err


def test_stale_temporary_files_are_removed(tmp_path: Path) -> None:
    (tmp_path / "ok.toml").write_text(SMALL)
    # Left by writers killed long ago (a pid above the kernel's maximum never runs).
    stale = [tmp_path / ".r.mbr.4194399.tmp", tmp_path / ".x.csv.4194399.abcd.tmp"]
    for f in stale:
        f.write_bytes(b"half")
    assert limited("run", "ok.toml", "--record", "r.mbr", cwd=tmp_path).returncode == 0
    assert not stale[0].exists()
    from multibots._io import atomic_write_text

    atomic_write_text(tmp_path / "x.csv", "a\n")
    assert not stale[1].exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ok.toml", "r.mbr", "x.csv"]


def test_paper_outputs_are_all_or_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A failure while the figures are drawn (here: the disk refuses the third file) leaves
    the output folder as it was, and no staging folder behind."""
    from multibots._io import staged_folder
    from multibots.exceptions import OutputError

    out = tmp_path / "paper"
    out.mkdir()
    (out / "results.csv").write_text("old\n")
    with pytest.raises(OutputError):
        with staged_folder(out) as stage:
            (stage / "results.csv").write_text("new\n")
            (stage / "fig6.png").write_bytes(b"png")
            raise OutputError("disk full")
    assert [p.name for p in out.iterdir()] == ["results.csv"] and (out / "results.csv").read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["paper"]
    with staged_folder(out) as stage:
        (stage / "sub").mkdir()
        (stage / "sub" / "a.txt").write_text("a")
        (stage / "results.csv").write_text("new\n")
    assert (out / "results.csv").read_text() == "new\n" and (out / "sub" / "a.txt").read_text() == "a"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["paper"]


# ---------------------------------------------------------------- worker processes


STRATEGIES = """
import os, time, pathlib

def _mark():
    pathlib.Path(os.environ["MB_PIDS"], str(os.getpid())).touch()

class Spins:
    def allocate(self, view):
        _mark()
        while True:
            pass

class Sleeps:
    def allocate(self, view):
        _mark()
        time.sleep(300)
"""


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # A zombie of ours is gone for every purpose.
    try:
        return Path(f"/proc/{pid}/stat").read_text().split(") ", 1)[1][0] != "Z"
    except (OSError, IndexError):
        return True


def _study(tmp_path: Path, cls: str) -> tuple[subprocess.Popen[str], list[int]]:
    (tmp_path / "strats.py").write_text(STRATEGIES)
    marks = tmp_path / "pids"
    marks.mkdir()
    env = {**os.environ, "MB_PIDS": str(marks)}
    p = subprocess.Popen([sys.executable, "-m", "multibots", "compare", "--strategies", f"strats.py:{cls}",
                          "--robots", "1..2", "--workers", "2", "--out", "c", "--quiet", "--no-plots"],
                         cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 60
    while len(list(marks.iterdir())) < 2 and time.monotonic() < deadline:
        time.sleep(0.1)
    pids = [int(f.name) for f in marks.iterdir()]
    assert len(pids) == 2, "both workers should be inside the strategy"
    return p, pids


def _gone(pids: list[int], within: float) -> list[int]:
    deadline = time.monotonic() + within
    while time.monotonic() < deadline and any(map(_alive, pids)):
        time.sleep(0.1)
    left = [p for p in pids if _alive(p)]
    for p in left:
        os.kill(p, signal.SIGKILL)
    return left


@pytest.mark.parametrize("cls", ["Spins", "Sleeps"])
def test_ctrl_c_stops_a_study_whose_strategy_never_returns(tmp_path: Path, cls: str) -> None:
    p, workers = _study(tmp_path, cls)
    t0 = time.monotonic()
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=30)
    assert time.monotonic() - t0 < 10
    assert p.returncode == 130 and err.strip().endswith("interrupted"), err
    assert _gone(workers, 5) == []


def test_kill_9_of_a_study_leaves_no_workers(tmp_path: Path) -> None:
    p, workers = _study(tmp_path, "Spins")
    p.kill()
    p.communicate(timeout=30)
    assert _gone(workers, 10) == [], "workers outlived the study"


# ---------------------------------------------------------------- replay files


def _replay_parts(path: Path) -> tuple[bytes, dict, dict, int]:
    raw = path.read_bytes()
    hlen = struct.unpack("<I", raw[12:16])[0]
    foot_off, foot_len = struct.unpack("<QQ", raw[-16:])
    return raw, json.loads(raw[16:16 + hlen]), json.loads(raw[foot_off:foot_off + foot_len]), hlen


def _rebuild(raw: bytes, hlen: int, header: bytes, footer: bytes) -> bytes:
    foot_off = struct.unpack("<QQ", raw[-16:])[0]
    delta = len(header) - hlen
    f = json.loads(footer) if footer.startswith(b"{") else None
    if isinstance(f, dict) and isinstance(f.get("chunks"), list):
        for c in f["chunks"]:
            if isinstance(c, dict) and isinstance(c.get("offset"), int):
                c["offset"] += delta
        footer = json.dumps(f).encode()
    out = raw[:12] + struct.pack("<I", len(header)) + header + raw[16 + hlen:foot_off]
    return out + footer + struct.pack("<QQ", len(out), len(footer))


BAD_VALUES = ["text", [1, 2], {"a": 1}, None, -1, 1e300, [[1], [1, 2]], True]


def test_malformed_header_and_footer_values(tmp_path: Path) -> None:
    """Every header and footer key replaced by text, lists, objects, null, negatives, huge
    numbers, ragged arrays, booleans, 1e400, or removed: a ReplayError, or a replay that reads."""
    from multibots import MultibotsError
    from multibots.replay import Replay

    (tmp_path / "ok.toml").write_text(SMALL)
    assert limited("run", "ok.toml", "--record", "ok.mbr", cwd=tmp_path).returncode == 0
    raw, header, footer, hlen = _replay_parts(tmp_path / "ok.mbr")
    variants: list[tuple[str, bytes, bytes]] = []
    hb, fb = json.dumps(header).encode(), json.dumps(footer).encode()

    def huge(table: dict, key: str) -> bytes:  # 1e400: valid JSON, inf once parsed
        return json.dumps({**table, key: 7e77}).encode().replace(b"7e+77", b"1e400")

    for key in header:
        variants += [(f"header {key}={v!r}", json.dumps({**header, key: v}).encode(), fb) for v in BAD_VALUES]
        without = {k: v for k, v in header.items() if k != key}
        variants.append((f"header without {key}", json.dumps(without).encode(), fb))
        variants.append((f"header {key}=1e400", huge(header, key), fb))
    for key in footer:
        variants += [(f"footer {key}={v!r}", hb, json.dumps({**footer, key: v}).encode()) for v in BAD_VALUES]
        variants.append((f"footer {key}=1e400", hb, huge(footer, key)))
    variants.append(("header nested 3000 deep", b"[" * 3000 + b"]" * 3000, fb))
    variants.append(("footer chunk fields", hb, json.dumps({**footer, "chunks": [{"offset": "x"}]}).encode()))
    opened = 0
    for name, h, f in variants:
        (tmp_path / "m.mbr").write_bytes(_rebuild(raw, hlen, h, f))
        try:
            with Replay(tmp_path / "m.mbr") as r:
                for i in range(r.frames):
                    r.frame(i)
            opened += 1
        except MultibotsError as e:
            assert "\n" not in str(e) and len(str(e)) < 400, (name, str(e))
        except Exception as e:
            pytest.fail(f"{name}: {type(e).__name__}: {e}")
    assert opened < len(variants) / 2  # most of these are refused, not silently read
    # And through the command line: one line, exit 2.
    (tmp_path / "m.mbr").write_bytes(_rebuild(raw, hlen, json.dumps({**header, "robots": "x"}).encode(), fb))
    one_line(limited("render", "m.mbr", "--out", "m.gif", cwd=tmp_path), "m.mbr", "robots")


def test_docs_mention_the_code_flag() -> None:
    assert "--allow-code" in (ROOT / "docs" / "strategies.md").read_text()
