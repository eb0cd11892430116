"""The journal of a study's finished runs (``runs.jsonl``): resume after a kill, reuse what
cannot have changed, re-run what can.

A run is keyed by everything that changes its result:

- the scenario, as the engine's JSON of it (every field, defaults filled in, in a fixed order,
  the strategy's name too);
- the strategy's code: for a Python strategy the SHA-256 of its module's source file, so an
  edited strategy runs again; a built-in's code is the engine's;
- the files it names (a layout file, an order or people CSV): the SHA-256 of their bytes;
- the engine: ``multibots.__version__`` and the SHA-256 of the ``_core`` extension file, so a
  rebuilt engine runs everything again.

The key is the SHA-256 of these, so a journal only ever answers for the very same run.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Optional

from multibots.scenario import Scenario
from multibots.strategies import is_python_allocator, strategy_source

__all__ = ["Journal", "engine_id", "run_key", "strategy_id"]


@functools.lru_cache(maxsize=1)
def engine_id() -> str:
    """The engine build: the package version and a hash of the compiled extension's bytes."""
    import multibots
    from multibots import _core

    digest = hashlib.sha256(Path(_core.__file__).read_bytes()).hexdigest()
    return f"{multibots.__version__}+{digest[:16]}"


def strategy_id(name: str) -> str:
    """What a strategy's code is: ``builtin:<name>``, or the hash of a Python strategy's source."""
    if not is_python_allocator(name):
        return f"builtin:{name}"
    return "python:" + hashlib.sha256(strategy_source(name)).hexdigest()


#: The scenario's fields that name a file the run reads: a layout file, an order or people CSV.
_FILES = re.compile(r'"(layout|csv)":"((?:[^"\\]|\\.)*)"')


def files_id(scenario_json: str) -> str:
    """What the files a scenario names hold: the hash of each one's bytes, so an edited
    layout or CSV runs again though the scenario names the same path."""
    out = []
    for field_name, raw in _FILES.findall(scenario_json):
        if field_name == "layout" and not raw.lower().endswith(".toml"):
            continue  # a built-in layout (paper)
        out.append(_file_hash(json.loads(f'"{raw}"')))
    return ",".join(out)


def _file_hash(path: str) -> str:
    try:
        st = os.stat(path)
    except OSError:
        return "missing"
    return _hash_of(os.path.abspath(path), st.st_mtime_ns, st.st_size)


@functools.lru_cache(maxsize=256)
def _hash_of(path: str, mtime_ns: int, size: int) -> str:
    # Keyed by modification time and size too: an edited file is read again.
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:32]
    except OSError:
        return "unreadable"


def run_key(scenario: Scenario, strategy: str, engine: str) -> str:
    """The journal key of a run: ``strategy`` and ``engine`` are :func:`strategy_id` and
    :func:`engine_id` (computed once per study, not per run)."""
    # The engine's JSON of the scenario (every field, defaults filled in, in a fixed order)
    # is as exact as its TOML and 15 times quicker to make: sweeps key millions of runs.
    text = scenario._core.to_json()
    blob = f"{strategy}\n{engine}\n{text}\n{files_id(text)}"
    return hashlib.sha256(blob.encode()).hexdigest()


class Journal:
    """Finished runs, appended one JSON line each and flushed to disk as they finish, so that
    a study that is killed loses no finished run: run it again and it resumes.

    A line cut short by a kill is ignored; lines of runs that no longer match (an edited
    strategy, another engine) stay in the file but are never read back for a new key.
    """

    #: Seconds a finished run may wait to be written (sweeps.runner): none, a line is cheap.
    flush_seconds = 0.0

    def __init__(self, path: Optional[str | os.PathLike[str]] = None) -> None:
        """``path``: the journal file; None keeps the runs in memory only."""
        self.path = Path(path) if path is not None else None
        self.existed = self.path is not None and self.path.exists()
        self.done: dict[str, dict[str, Any]] = {}
        if self.path is not None and self.existed:
            for line in self.path.read_text(encoding="utf-8").splitlines():
                try:
                    entry = json.loads(line)
                    self.done[entry["key"]] = entry["result"]
                except (ValueError, KeyError, TypeError):
                    continue

    def keys(self) -> set[str]:
        """The keys of the runs recorded (the store interface of ``sweeps.runner``)."""
        return set(self.done)

    def write(self, points: Sequence[Any], keys: Sequence[str], figures: Sequence[dict[str, Any]]) -> None:
        """Records a batch of runs as the sweep's runner hands them over (its store interface)."""
        self.record(list(zip(keys, figures)))

    def record(self, entries: Sequence[tuple[str, dict[str, Any]]]) -> None:
        """Appends (key, result) pairs and flushes them to disk."""
        if self.path is None:
            self.done.update(entries)
            return
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with self.path.open("a+b") as f:
            # A kill may have cut the last line short: start on a line of our own.
            if f.tell() > 0:
                f.seek(-1, os.SEEK_END)
                if f.read(1) != b"\n":
                    f.write(b"\n")
            for key, result in entries:
                self.done[key] = result
                f.write((json.dumps({"key": key, "result": result}, separators=(",", ":")) + "\n").encode())
            f.flush()
            os.fsync(f.fileno())
