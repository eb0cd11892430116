"""Read MultiBots replay files (``.mbr``, docs/replay-format.md) lazily.

``Replay(path)`` reads only the header and the footer. Chunks are read, inflated and
decoded on demand (a few are kept in a small cache), so a replay of 1,000 robots x
10,000 steps is never held in memory at once. The reader is safe to share between
threads (it reads with ``os.pread`` and guards its caches with a lock).
"""

from __future__ import annotations

import bisect
import json
import math
import os
import struct
import threading
from collections import OrderedDict
from typing import Any, Dict, Iterator, List, Optional

import numpy as np

from multibots import _args, _core
from multibots._io import regular_file
from multibots._text import shown
from multibots.exceptions import MultibotsError, ReplayError
from multibots.replay_resources import ResourceLog
from multibots.replay_state import EVENT_NAMES, MOVING_STATES, STATE_NAMES, ReplayState

__all__ = ["Replay", "ReplayError", "STATE_NAMES", "EVENT_NAMES", "MOVING_STATES"]

# The format's numbers, from the engine's codec (docs/replay-format.md).
MAGIC = _core.REPLAY_MAGIC
VERSION = _core.REPLAY_VERSION

# A header or footer larger than this is not a replay we wrote.
_MAX_JSON = 256 * 1024 * 1024
# Fleets and frame counts past these are not replays the engine can write (docs/limits.md).
_MAX_ROBOTS: int = _core.LIMITS["robots"]
_MAX_FRAMES = 1 << 40
_MISSING = object()


def _chunk_limit(frames: int, robots: int, people: int = 0) -> int:
    """The most bytes a chunk of ``frames`` frames of ``robots`` robots may inflate to, for
    replays whose footer does not record it: every section, and up to 4 events per robot and
    64 more per frame, with room to spare. A small stream that inflates past it is refused
    (a decompression bomb), before it can fill the memory."""
    return 16 + frames * (12 + robots * _core.BYTES_PER_ROBOT_STEP + 8 * people + 16 * (4 * robots + 64)) + (1 << 20)


class Replay(ReplayState):
    """A replay file opened for lazy reading.

    Attributes: ``header`` (dict), ``layout`` (layout JSON dict), ``robots`` (N),
    ``frames`` (steps run + 1), ``summary`` (footer indicators: T, S, C, outcome,
    delivered), ``resources`` and ``bottleneck`` (as in ``Result``; empty and None in
    replays that predate them), ``chunk_count``, ``chunk_steps``, ``path``.
    """

    def __init__(self, path: "os.PathLike[str] | str", cache_chunks: int = 8,
                 cache_bytes: int = 96 * 1024 * 1024) -> None:
        self.path = os.fspath(_args.path("path", path))  # type: ignore[arg-type]
        self._name = self.path
        regular_file(self.path, ReplayError, "replay file")
        try:
            self._fd = os.open(self.path, os.O_RDONLY | getattr(os, "O_BINARY", 0))
        except FileNotFoundError:
            raise ReplayError(f"{self._name}: no such replay file") from None
        except IsADirectoryError:
            raise ReplayError(f"{self._name}: is a directory, not a replay file") from None
        except OSError as exc:
            raise ReplayError(f"{self._name}: cannot open ({exc.strerror})") from None
        try:
            self._open()
        except BaseException:
            os.close(self._fd)
            self._fd = -1
            raise
        self._lock = threading.RLock()
        self._index_lock = threading.Lock()
        self._cache: "OrderedDict[int, Dict[str, Any]]" = OrderedDict()
        self._cache_size = max(1, int(cache_chunks))
        self._cache_bytes = int(cache_bytes)
        # _snapshots[i]: state before chunk i's first frame's events (see _snapshot).
        self._snapshots: List[Dict[str, np.ndarray]] = []

    # ------------------------------------------------------------------ opening
    def _fail(self, what: str) -> "ReplayError":
        return ReplayError(f"{self._name}: {what}")

    def _pread(self, n: int, off: int, what: str) -> bytes:
        if n < 0 or off < 0 or off + n > self._size:
            raise self._fail(f"{what} lies outside the file (truncated?)")
        data = b""
        while len(data) < n:
            part = os.pread(self._fd, n - len(data), off + len(data))
            if not part:
                raise self._fail(f"{what} is truncated")
            data += part
        return data

    def _json(self, raw: bytes, what: str) -> Dict[str, Any]:
        try:
            value = json.loads(raw.decode("utf-8"))
        except (UnicodeDecodeError, ValueError, RecursionError):
            raise self._fail(f"{what} is not valid UTF-8 JSON") from None
        if not isinstance(value, dict):
            raise self._fail(f"{what} is not a JSON object")
        return value

    def _open(self) -> None:
        self._size = os.fstat(self._fd).st_size
        if self._size < 32:
            raise self._fail(f"not a MultiBots replay (only {self._size} bytes)")
        start = self._pread(16, 0, "file start")
        if start[:8] != MAGIC:
            raise self._fail("not a MultiBots replay (bad magic)")
        version, hlen = struct.unpack("<II", start[8:16])
        if version != VERSION:
            raise self._fail(f"unsupported replay format version {version} (this reader knows {VERSION})")
        if hlen > _MAX_JSON or 16 + hlen > self._size - 16:
            raise self._fail(f"header length {hlen} does not fit the file (truncated?)")
        header = self._json(self._pread(hlen, 16, "header"), "header")
        foot_off, foot_len = struct.unpack("<QQ", self._pread(16, self._size - 16, "footer pointer"))
        if foot_len > _MAX_JSON or foot_off < 16 + hlen or foot_off + foot_len > self._size - 16:
            raise self._fail("footer pointer lies outside the file (truncated or not finished)")
        footer = self._json(self._pread(foot_len, foot_off, "footer"), "footer")

        if header.get("format") != "multibots-replay":
            raise self._fail("header 'format' is not 'multibots-replay'")
        self.robots = self._int(header, "robots", "header", 1, _MAX_ROBOTS)
        self.chunk_steps = self._int(header, "chunk_steps", "header", 1, _MAX_FRAMES)
        self.energy_full = self._float(header, "energy_full", "header")
        self.threshold = self._float(header, "threshold", "header")
        self.goods_total = self._int(header, "goods_total", "header", 0, _MAX_FRAMES)
        self.layout = self._get(header, "layout", "header")
        if not isinstance(self.layout, dict):
            raise self._fail("header 'layout' is not a JSON object")
        self.radius = self._array(header, "radius", np.float64, 0, math.inf, self.robots)
        self.home = self._array(header, "home", np.int64, 0, _MAX_FRAMES, self.robots)
        self.cells_full = self._array(header, "cells_full", np.uint8, 0, 1)
        # A League of Robot Runners grid (docs/lorr.md): goals are grid cells, not storage cells.
        grid = self.layout.get("grid")
        if grid is not None and not isinstance(grid, dict):
            raise self._fail("header layout 'grid' is not a JSON object")
        self.grid = grid
        self.goal_cells = len(self.cells_full)
        if grid is not None:
            size = self._int(grid, "rows", "header layout grid", 1, 1 << 20) * self._int(
                grid, "cols", "header layout grid", 1, 1 << 20)
            self.goal_cells = size
        # People on the floor (docs/people.md): absent in replays without them.
        humans = header.get("humans")
        if humans is not None and not isinstance(humans, dict):
            raise self._fail("header 'humans' is not a JSON object")
        self.humans = 0 if humans is None else self._int(humans, "count", "header humans", 0, _MAX_ROBOTS)
        self.human_radius = 0.0 if humans is None else self._float(humans, "radius", "header humans")

        self.frames = self._int(footer, "frames", "footer", 1, _MAX_FRAMES)
        table = self._get(footer, "chunks", "footer")
        if not isinstance(table, list) or not all(isinstance(c, dict) for c in table):
            raise self._fail("footer 'chunks' is not a list of JSON objects")
        what = "footer chunk"
        self._offsets = [self._int(c, "offset", what, 0, self._size) for c in table]
        self._lengths = [self._int(c, "length", what, 1, self._size) for c in table]
        self._firsts = [self._int(c, "first_frame", what, 0, _MAX_FRAMES) for c in table]
        self._counts = [self._int(c, "frames", what, 1, _MAX_FRAMES) for c in table]
        self._limits = [
            self._int(c, "raw_length", what, 16, 1 << 40, _chunk_limit(n, self.robots, self.humans))
            for c, n in zip(table, self._counts)
        ]
        expect = 0
        for i, (off, ln, first, cnt) in enumerate(zip(self._offsets, self._lengths, self._firsts, self._counts)):
            if first != expect:
                raise self._fail(f"chunk {i} holds frames {first}..{first + cnt - 1}; expected to start at {expect}")
            if off < 16 + hlen or off + ln > foot_off:
                raise self._fail(f"chunk {i} lies outside the data area (truncated?)")
            expect = first + cnt
        if expect != self.frames:
            raise self._fail(f"the chunks hold {expect} frames but the footer says {self.frames}")
        self.header = header
        self.footer = footer
        self.chunk_count = len(table)
        outcome = footer.get("outcome", "incomplete")
        if not isinstance(outcome, str):
            raise self._fail(f"footer 'outcome' is {shown(json.dumps(outcome))}; expected text")
        windows = footer.get("windows", [])
        if not isinstance(windows, list):
            raise self._fail(f"footer 'windows' is {shown(json.dumps(windows))}; expected a list")
        self.summary = {
            "T": None if footer.get("T") is None else self._int(footer, "T", "footer", 0, _MAX_FRAMES),
            "S": self._int(footer, "S", "footer", 0, 1 << 62, 0),
            "C": self._int(footer, "C", "footer", 0, 1 << 62, 0),
            "outcome": shown(outcome, 40),
            "delivered": self._int(footer, "delivered", "footer", 0, 1 << 62, 0),
            "window": self._int(footer, "window", "footer", 1, _MAX_FRAMES, 1000),
            "windows": [self._int({"windows": w}, "windows", "footer", 0, 1 << 62) for w in windows],
            "frames": self.frames,
        }
        # The run's report of its resources and bottleneck, and their queues frame by frame.
        self._resources = ResourceLog(footer, self.frames, self._fail)
        self.resources = self._resources.resources
        self.bottleneck = self._resources.bottleneck

    # Checked reads of header and footer values: a file from elsewhere may hold text, lists,
    # 1e400 (inf once parsed) or ragged arrays where numbers belong; each gets one line.
    def _get(self, table: Dict[str, Any], key: str, what: str) -> Any:
        if key not in table:
            raise self._fail(f"{what} lacks the key {key!r}")
        return table[key]

    def _bad(self, key: str, what: str, value: Any, expected: str) -> "ReplayError":
        try:
            text = json.dumps(value)
        except (TypeError, ValueError):
            text = repr(value)
        return self._fail(f"{what} {key!r} is {shown(text)}; expected {expected}")

    def _int(self, table: Dict[str, Any], key: str, what: str, lo: int, hi: int, default: Any = _MISSING) -> int:
        if default is not _MISSING and key not in table:
            return default
        v = self._get(table, key, what)
        ok = isinstance(v, int) or (isinstance(v, float) and v.is_integer())
        if isinstance(v, bool) or not ok or not lo <= v <= hi:
            raise self._bad(key, what, v, f"an integer from {lo} to {hi}")
        return int(v)

    def _float(self, table: Dict[str, Any], key: str, what: str) -> float:
        v = self._get(table, key, what)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise self._bad(key, what, v, "a finite number")
        return float(v)

    def _array(self, table: Dict[str, Any], key: str, dtype: Any, lo: float, hi: float,
               length: Optional[int] = None) -> np.ndarray:
        v = self._get(table, key, "header")
        if not isinstance(v, list) or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
            raise self._bad(key, "header", v, "a list of numbers")
        a = np.asarray(v, dtype=np.float64)
        if not (np.isfinite(a).all() and ((a >= lo) & (a <= hi)).all()):
            raise self._fail(f"header {key!r} holds a value outside {lo}..{hi}")
        if np.dtype(dtype).kind in "iu" and not (a == np.floor(a)).all():
            raise self._fail(f"header {key!r} holds a value that is not an integer")
        if length is not None and len(a) != length:
            raise self._fail(f"header {key!r} lists {len(a)} values; expected one per robot ({length})")
        return a.astype(dtype)

    def queues_at(self, frame: int) -> List[int]:
        """The robots queued at each of ``resources`` in ``frame`` (after its step), counted
        as the run's report counts them (docs/metrics.md)."""
        return self._resources.queues_at(self._check_frame(frame))

    def queue_changes(self) -> List[List[int]]:
        """Each of ``resources``' queue as ``[frame, robots, ...]``: the frames where it
        changed and its length from then on (the footer's ``queues``)."""
        return self._resources.changes()

    @property
    def file_size(self) -> int:
        """The file's size in bytes when it was opened."""
        return self._size

    def file_blocks(self, block: int = 1 << 20) -> Iterator[bytes]:
        """The file's bytes, as it was opened: read from the open descriptor, never through
        its path again, so a file renamed or replaced (by a symlink to another file) since
        then is still the one served.

        Raises:
            ReplayError: the file shrank since it was opened.
        """
        for off in range(0, self._size, block):
            yield self._pread(min(block, self._size - off), off, "the replay file")

    # ------------------------------------------------------------------ lifetime
    def close(self) -> None:
        if getattr(self, "_fd", -1) >= 0:
            os.close(self._fd)
            self._fd = -1

    def __enter__(self) -> "Replay":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:  # pragma: no cover - best effort
        try:
            self.close()
        except Exception:
            pass

    def __repr__(self) -> str:
        return f"Replay({self.path!r}, robots={self.robots}, frames={self.frames}, chunks={self.chunk_count})"

    # ------------------------------------------------------------------ chunks
    def _check_chunk(self, i: int) -> int:
        i = int(i)
        if not 0 <= i < self.chunk_count:
            raise IndexError(f"chunk {i} out of range 0..{self.chunk_count - 1}")
        return i

    def chunk_info(self, i: int) -> Dict[str, int]:
        i = self._check_chunk(i)
        return {"offset": self._offsets[i], "length": self._lengths[i],
                "first_frame": self._firsts[i], "frames": self._counts[i]}

    def chunk_of(self, frame: int) -> int:
        """Index of the chunk that holds frame ``frame``."""
        frame = self._check_frame(frame)
        return bisect.bisect_right(self._firsts, frame) - 1

    def _check_frame(self, frame: int) -> int:
        f = int(frame)
        if not 0 <= f < self.frames:
            raise IndexError(f"frame {f} out of range 0..{self.frames - 1}")
        return f

    def chunk_raw(self, i: int) -> bytes:
        """The chunk's zlib stream exactly as stored in the file."""
        i = self._check_chunk(i)
        return self._pread(self._lengths[i], self._offsets[i], f"chunk {i}")

    def _codec_error(self, i: int, exc: Exception) -> "ReplayError":
        msg = str(exc)
        verb = msg.split(" ", 1)[0] in ("holds", "inflates", "sizes")
        return self._fail(f"chunk {i} {msg}" if verb else f"chunk {i} is {msg}")

    def _check_head(self, i: int, first: int, count: int, robots: int) -> None:
        if first != self._firsts[i] or count != self._counts[i] or robots != self.robots:
            raise self._fail(
                f"chunk {i} head says frames {first}+{count} of {robots} robots; "
                f"the footer says {self._firsts[i]}+{self._counts[i]} of {self.robots}")

    def chunk_bytes(self, i: int) -> bytes:
        """The chunk decompressed (raw sections, as described in the format), checked by the
        engine's codec."""
        i = self._check_chunk(i)
        try:
            raw = _core.inflate_chunk(self.chunk_raw(i), self._limits[i])
        except MultibotsError as exc:
            raise self._codec_error(i, exc) from None
        first, count, robots, _ = struct.unpack_from("<4I", raw, 0)
        self._check_head(i, first, count, robots)
        return raw

    def _views(self, i: int) -> Dict[str, Any]:
        """Chunk ``i`` decoded by the engine's codec into arrays (cached by size)."""
        i = self._check_chunk(i)
        with self._lock:
            hit = self._cache.get(i)
            if hit is not None:
                self._cache.move_to_end(i)
                return hit
        try:
            views = _core.decode_chunk(self.chunk_raw(i), self._limits[i])
        except MultibotsError as exc:
            raise self._codec_error(i, exc) from None
        self._check_head(i, views["first_frame"], views["frames"], views["robots"])
        if views["people_x"].shape[1] != self.humans:
            raise self._fail(f"chunk {i} holds {views['people_x'].shape[1]} people; the header says {self.humans}")
        for v in views.values():
            if isinstance(v, np.ndarray):
                v.setflags(write=False)
        views["nbytes"] = sum(v.nbytes for v in views.values() if isinstance(v, np.ndarray))
        with self._lock:
            self._cache[i] = views
            self._cache.move_to_end(i)
            total = sum(v["nbytes"] for v in self._cache.values())
            while len(self._cache) > 1 and (len(self._cache) > self._cache_size or total > self._cache_bytes):
                _, old = self._cache.popitem(last=False)
                total -= old["nbytes"]
        return views

    @staticmethod
    def _heading(u8: np.ndarray) -> np.ndarray:
        h = u8.astype(np.float64) * (2.0 * math.pi / _core.HEADING_STEPS)
        h[h > math.pi] -= 2.0 * math.pi
        return h

    def _energy(self, u16: np.ndarray) -> np.ndarray:
        return u16.astype(np.float64) * (self.energy_full / _core.ENERGY_SCALE)

    def chunk(self, i: int) -> Dict[str, Any]:
        """Decoded arrays of chunk ``i`` (treat them as read-only).

        Keys: ``first_frame``, ``frames`` (K'), ``counters`` (K', 3) uint32 S, C, delivered;
        ``x``, ``y`` (K', N) float32; ``events`` (E, 4) uint32 frame, kind, robot, cell;
        ``energy`` (K', N) float64 in energy units; ``energy_u16`` (K', N) raw;
        ``heading`` (K', N) float64 radians in (-pi, pi]; ``heading_u8`` raw;
        ``state`` (K', N) uint8 state codes; ``marked`` (K', N) bool; ``people_x``,
        ``people_y`` (K', P) float32 (P = 0 without people).
        """
        v = self._views(i)
        keys = ("first_frame", "frames", "counters", "x", "y", "events", "energy_u16", "heading_u8",
                "people_x", "people_y")
        out = {k: v[k] for k in keys}
        out["energy"] = self._energy(v["energy_u16"])
        out["heading"] = self._heading(v["heading_u8"])
        out["state"] = v["state_raw"] & _core.STATE_MASK
        out["marked"] = (v["state_raw"] & _core.MARKED) != 0
        return out

    # ------------------------------------------------------------------ frames
    def frame(self, f: int) -> Dict[str, Any]:
        """The state after step ``f``: arrays of one value per robot, and the counters."""
        f = self._check_frame(f)
        ch = self._views(self.chunk_of(f))
        k = f - ch["first_frame"]
        s, c, d = (int(v) for v in ch["counters"][k])
        st = ch["state_raw"][k]
        return {
            "frame": f,
            "x": ch["x"][k],
            "y": ch["y"][k],
            "heading": self._heading(ch["heading_u8"][k]),
            "state": st & _core.STATE_MASK,
            "marked": (st & _core.MARKED) != 0,
            "energy": self._energy(ch["energy_u16"][k]),
            "S": s,
            "C": c,
            "delivered": d,
            "counters": {"S": s, "C": c, "delivered": d},
            "people_x": ch["people_x"][k],
            "people_y": ch["people_y"][k],
        }

    def events(self, f0: int = 0, f1: Optional[int] = None) -> np.ndarray:
        """Events of frames f0 <= frame < f1, as an (E, 4) uint32 array (frame, kind, robot, cell)."""
        f1 = self.frames if f1 is None else int(f1)
        f0 = max(0, int(f0))
        f1 = min(self.frames, f1)
        if f1 <= f0:
            return np.zeros((0, 4), dtype=np.uint32)
        parts = []
        for i in range(self.chunk_of(f0), self.chunk_of(f1 - 1) + 1):
            ev = self._views(i)["events"]
            if len(ev):
                sel = (ev[:, 0] >= f0) & (ev[:, 0] < f1)
                parts.append(ev[sel])
        if not parts:
            return np.zeros((0, 4), dtype=np.uint32)
        return np.concatenate(parts).astype(np.uint32, copy=False)

    def chunk_events(self, i: int) -> np.ndarray:
        """Chunk ``i``'s events (E, 4) uint32."""
        return self._views(i)["events"]
