"""The docs' examples run (docs/*.md and the README), and what they print is checked.

The convention: every fenced ```sh and ```python block of a page is an example, and this test
runs it. In a ```sh block, each ``multibots ...`` command (``\\`` continues a line, ``#``
starts a comment) runs as ``python -m multibots`` and must exit 0. The blocks of a page run
in order in one temporary folder, so a later block may use what an earlier one wrote; the
folder holds the repository's ``scenarios/`` and ``examples/`` and a small ``my-warehouse.toml``.

Every example that runs asserts what it gives: a ```python block holds at least one
``assert``; a ```sh block is followed by ``<!-- output: TEXT; TEXT -->``, each TEXT a piece of
what its commands print (stdout, all commands together).

An HTML comment on the line before a block's fence says how it runs:
- ``<!-- not run: REASON -->``: not run (it serves until stopped, or takes minutes);
- ``<!-- test with: COMMAND FLAGS; ... -->``: FLAGS are added to each ``multibots COMMAND``
  of the block, so that the example runs in seconds (short horizons, fewer seeds); the last
  of a repeated flag wins.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parent.parent
DOCS = [*sorted((ROOT / "docs").glob("*.md")), ROOT / "README.md"]
FENCE = re.compile(r"^(?:<!-- (not run|test with): ?(.*?) -->\n)?```(sh|python)\n(.*?)^```\n"
                   r"(?:<!-- output: (.*?) -->\n)?", re.M | re.S)

# A warehouse for the examples that name "my-warehouse.toml": 30 robots, short lifelong runs.
MY_WAREHOUSE = """\
robots = 30
tasks = []
placement = "spread"
unload = "nearest"
allocator = "nearest"

[layout_generate]
group_rows = 3
group_cols = 5
group_width = 2
group_height = 6
chargers = 4
unloading_rows = 2

[charging]
chargers = "shared"

[robot]
consumption = 0.00002

[orders]
rate = 0.02
horizon = 2000
restock = 100
seed = 1
"""


def blocks(page: Path) -> list[tuple[str, str, str, str, list[str]]]:
    """(how, argument, language, code, expected output pieces) of each example of a page;
    ``how`` is "" when plain."""
    return [(m[0] or "", m[1], m[2], m[3], [t.strip() for t in m[4].split(";") if t.strip()])
            for m in FENCE.findall(page.read_text())]


def commands(code: str) -> list[list[str]]:
    """The ``multibots`` commands of a shell block, as argument lists."""
    out = []
    for line in code.replace("\\\n", " ").splitlines():
        line = line.split(" #")[0].strip()
        if line.startswith("multibots "):
            out.append(shlex.split(line)[1:])
    return out


def quick_flags(text: str) -> dict[tuple[str, ...], list[str]]:
    """``run --horizon 500; compare --seeds 2`` as the flags to add to each command, by the
    words that start it (``run scenarios/people.toml --horizon 500``: only that run)."""
    out = {}
    for part in text.split(";"):
        words = shlex.split(part)
        k = next((i for i, w in enumerate(words) if w.startswith("--")), len(words))
        if words:
            out[tuple(words[:k])] = words[k:]
    return out


def flags_for(flags: dict[tuple[str, ...], list[str]], args: list[str]) -> list[str]:
    """The quick flags of the longest start that ``args`` begins with."""
    starts = [k for k in flags if tuple(args[:len(k)]) == k]
    return flags[max(starts, key=len)] if starts else []


def test_the_convention_is_kept() -> None:
    # Every example block is seen, and every "not run" says why.
    seen = 0
    for page in DOCS:
        text = page.read_text()
        n = len(re.findall(r"^```(?:sh|python)\n", text, re.M))
        found = blocks(page)
        assert len(found) == n, page.name
        for how, why, language, code, output in found:
            assert how != "not run" or len(why) > 10, (page.name, why)
            if how != "not run":
                # What it gives is asserted, not only that it runs.
                if language == "python":
                    assert re.search(r"^\s*assert ", code, re.M), (page.name, code[:80])
                else:
                    assert output, (page.name, code[:80])
            if how == "test with":
                named = quick_flags(why)
                started = [tuple(a) for a in commands(code)]
                assert named and all(any(a[:len(k)] == k for a in started) for k in named), (page.name, why)
        seen += n
    assert seen > 10


@pytest.mark.parametrize("page", [p for p in DOCS if blocks(p)], ids=lambda p: p.name)
def test_the_examples_of_a_page_run(page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("scenarios", "examples"):
        (tmp_path / name).symlink_to(ROOT / name)
    (tmp_path / "my-warehouse.toml").write_text(MY_WAREHOUSE)
    monkeypatch.chdir(tmp_path)
    env = {**os.environ, "MULTIBOTS_ALLOW_CODE": "1"}
    for how, extra, language, code, output in blocks(page):
        if how == "not run":
            continue
        if language == "python":
            exec(compile(code, f"{page.name} example", "exec"), {"__name__": "__doc_example__"})
            continue
        flags = quick_flags(extra) if how == "test with" else {}
        cmds = commands(code)
        assert cmds, f"{page.name}: a sh block with no multibots command"
        printed = ""
        for args in cmds:
            more = flags_for(flags, args)
            p = subprocess.run([sys.executable, "-m", "multibots", *args, *more], capture_output=True, text=True,
                               env=env, timeout=300)
            assert p.returncode == 0, (page.name, args, p.stderr[-2000:])
            printed += p.stdout
        for piece in output:
            assert piece in printed, (page.name, piece, printed[-3000:])
