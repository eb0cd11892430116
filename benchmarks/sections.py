"""Sections of docs/benchmarks.md that other benchmark scripts write: each between
``<!-- section: NAME -->`` and ``<!-- end: NAME -->``. `run_all.py` rewrites the rest of the
file and keeps these; a script replaces its own with :func:`put`."""

from __future__ import annotations

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from multibots._io import atomic_write_text  # noqa: E402

DOC = ROOT / "docs" / "benchmarks.md"
_SECTION = re.compile(r"<!-- section: (?P<name>[\w-]+) -->\n.*?<!-- end: (?P=name) -->\n", re.S)


def blocks(text: str) -> dict[str, str]:
    """The sections of a document, by name."""
    return {m.group("name"): m.group(0) for m in _SECTION.finditer(text)}


def keep(new: str, old: str) -> str:
    """``new`` with every section of ``old`` that it lacks appended."""
    have = blocks(new)
    extra = [b for name, b in blocks(old).items() if name not in have]
    return new.rstrip("\n") + "\n\n" + "\n".join(extra) if extra else new


def put(name: str, body: str, path: Path = DOC) -> Path:
    """Replaces (or appends) section ``name`` of ``path`` with ``body``."""
    block = f"<!-- section: {name} -->\n{body.rstrip()}\n<!-- end: {name} -->\n"
    text = path.read_text(encoding="utf-8") if path.exists() else ""
    old = blocks(text).get(name)
    text = text.replace(old, block) if old else text.rstrip("\n") + "\n\n" + block
    return atomic_write_text(path, text)
