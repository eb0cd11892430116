"""The results store: Parquet part files in ``OUT/runs/``, one per batch of finished runs,
each written whole (temporary file, fsync, rename) before it counts. A study killed at any
moment, ``kill -9`` included, keeps every batch that was written; run it again and the runs
whose key is in a part file are reused, not run again.

A run's key is a hash of everything that determines its result: the scenario (as TOML), the
strategy's code (a built-in's name, or the hash of a Python strategy's source) and the
engine build (multibots.experiments.journal). An edited strategy or a rebuilt engine gives
new keys, so stale results are never reused.
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterable, Sequence
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

    def write(self, rows: Sequence[dict[str, Any]]) -> Path:
        """Writes one batch as a new part file, whole or not at all."""
        pl = polars()
        self.folder.mkdir(parents=True, exist_ok=True)
        path = self.folder / f"part-{uuid.uuid4().hex}.parquet"
        # Column by column: much faster than polars' inference over a list of dicts.
        names = list(dict.fromkeys(k for r in rows for k in r))
        columns = {n: [r.get(n) for r in rows] for n in names}
        with atomic_target(path) as tmp:
            pl.DataFrame(columns, strict=False).write_parquet(tmp)
        return path


def rows_of(points: Iterable[Any], keys: Sequence[str], raws: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Store rows: the key, the plan index, the axis values and the run's figures."""
    out = []
    for point, key, raw in zip(points, keys, raws):
        row: dict[str, Any] = {"key": key, "index": point.index}
        for name, value in point.values:
            row[name] = value if isinstance(value, (int, float, str, bool)) else repr(value)
        row.update(raw)
        out.append(row)
    return out
