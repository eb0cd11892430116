"""The results store: Parquet part files in ``OUT/runs/``, one per batch of finished runs,
each written whole (temporary file, fsync, rename) before it counts. A study killed at any
moment, ``kill -9`` included, keeps every batch that was written; run it again and the runs
whose key is in a part file are reused, not run again.

A run's key is a hash of everything that determines its result: the scenario (the engine's
JSON of it, every field with defaults filled in), the strategy's code (a built-in's name, or
the hash of a Python strategy's source) and the engine build (multibots.runs.journal).
An edited strategy or a rebuilt engine gives new keys, so stale results are never reused.
"""

from __future__ import annotations

import itertools
import os
import uuid
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from multibots._io import atomic_target
from multibots.exceptions import MissingExtraError, OutputError

__all__ = ["Store", "polars"]


def polars() -> Any:
    """The polars module, or an error naming the extra that installs it."""
    try:
        import polars as pl
    except ImportError:
        raise MissingExtraError("multibots sweep", "study") from None
    return pl


class Store:
    """The part files of one study folder."""

    #: Seconds a finished run may wait to be written (sweeps.runner): each write is a part
    #: file, so a study writes about one a second rather than one per engine call.
    flush_seconds = 1.0

    def __init__(self, out: str | os.PathLike[str]) -> None:
        self.folder = Path(out) / "runs"
        if self.folder.exists() and not self.folder.is_dir():
            raise OutputError(f"{self.folder}: exists and is not a folder")

    def parts(self) -> list[Path]:
        return sorted(self.folder.glob("part-*.parquet")) if self.folder.is_dir() else []

    def frame(self) -> Any:
        """Every stored run (a polars DataFrame; empty without parts). A part that cannot be
        read (not ours) is an error naming it."""
        pl = polars()
        frames = []
        for p in self.parts():
            try:
                frames.append(pl.read_parquet(p))
            except Exception as e:
                raise OutputError(f"{p}: not a readable part file ({type(e).__name__}); move it away") from None
        if not frames:
            return pl.DataFrame()
        return pl.concat(frames, how="diagonal_relaxed").unique(subset="key", keep="first", maintain_order=True)

    def keys(self) -> set[str]:
        df = self.frame()
        return set(df["key"].to_list()) if len(df) else set()

    def write(self, points: Sequence[Any], keys: Sequence[str], figures: Sequence[dict[str, Any]]) -> Path:
        """Writes one batch of runs (their points, keys and figures) as a new part file,
        whole or not at all. Columns: the key, the plan index, the axis values, the figures."""
        pl = polars()
        self.folder.mkdir(parents=True, exist_ok=True)
        path = self.folder / f"part-{uuid.uuid4().hex}.parquet"
        # Built column by column: several times faster than rows, or polars' inference over
        # a list of dicts, and this runs for every batch of a study.
        columns: dict[str, list[Any]] = {"key": list(keys), "index": [p.index for p in points]}
        for name, cells in _axis_columns(points).items():
            columns[name] = [_cell(v) for v in cells]
        first = list(figures[0]) if figures else []
        if all(list(f) == first for f in figures):
            # The usual case (every run's figures have the same names, in the same order): a
            # transpose at C speed.
            columns.update(zip(first, map(list, zip(*(f.values() for f in figures)))))
        else:
            for name in dict.fromkeys(itertools.chain.from_iterable(figures)):
                columns[name] = [f.get(name) for f in figures]
        with atomic_target(path) as tmp:
            pl.DataFrame(columns, strict=False).write_parquet(tmp)
        return path


def _axis_columns(points: Sequence[Any]) -> dict[str, list[Any]]:
    """The points' axis values by axis name (None where a point lacks the axis)."""
    width = {len(p.values) for p in points}
    if len(width) == 1:
        # The usual case (the points of one spec name the same axes in the same order).
        columns = list(zip(*(p.values for p in points)))
        if all(all(nv[0] == col[0][0] for nv in col) for col in columns):
            return {col[0][0]: [v for _, v in col] for col in columns}
    values = [dict(p.values) for p in points]
    return {n: [v.get(n) for v in values] for n in dict.fromkeys(itertools.chain.from_iterable(values))}


def _cell(value: Any) -> Any:
    """An axis value as a Parquet cell: a scalar as is, anything else (a list of task cells,
    a table) by its repr."""
    return value if value is None or isinstance(value, (int, float, str, bool)) else repr(value)
