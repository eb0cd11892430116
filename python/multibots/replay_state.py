"""What a replay's events say beyond its frames: which cells hold goods, each robot's S, C,
task and load at any step, and where a robot drives next; and the codes of states and events
(docs/replay-format.md).

:class:`ReplayState` is a part of :class:`multibots.Replay`: the state after any step is the
snapshot before its chunk (built once, in order, and kept) with the chunk's events up to that
step applied.
"""

from __future__ import annotations

from typing import Dict, List, Optional

import numpy as np

from multibots import _core

__all__ = ["EVENT_NAMES", "MOVING_STATES", "NONE32", "ReplayState", "STATE_NAMES"]

#: "No robot" or "no cell" in an event.
NONE32 = 0xFFFFFFFF

#: State codes and names, event codes and names: the engine's own (docs/replay-format.md).
STATE_NAMES: Dict[int, str] = dict(enumerate(_core.STATE_NAMES))
MOVING_STATES = tuple(_core.MOVING_STATES)
EVENT_NAMES: Dict[int, str] = dict(_core.EVENT_NAMES)
_EVENT_CODES = {name: code for code, name in EVENT_NAMES.items()}
EV_ASSIGN, EV_PUT_BACK, EV_PICKUP, EV_DELIVER, EV_WAIT, EV_CHARGE, EV_STRAND, EV_RESTOCK, EV_ORDER = (
    _EVENT_CODES[name]
    for name in ("ASSIGN", "PUT_BACK", "PICKUP", "DELIVER", "WAIT", "CHARGE", "STRAND", "RESTOCK", "ORDER")
)


class ReplayState:
    """The derived state of a :class:`multibots.Replay` (a base class of it, not used alone)."""

    def _initial_snapshot(self) -> Dict[str, np.ndarray]:
        n = self.robots
        return {
            "cells": self.cells_full.copy(),
            "robot_S": np.zeros(n, dtype=np.int64),
            "robot_C": np.zeros(n, dtype=np.int64),
            "task": np.full(n, -1, dtype=np.int64),
            "carrying": np.full(n, -1, dtype=np.int64),
        }

    def _apply(self, snap: Dict[str, np.ndarray], events: np.ndarray) -> None:
        n = self.robots
        cells = snap["cells"]
        ncell = len(cells)
        for _frame, kind, robot, cell in events.tolist():
            r_ok = robot != NONE32 and robot < n
            c_ok = cell != NONE32 and cell < ncell
            if kind == EV_WAIT and r_ok:
                snap["robot_S"][robot] += 1
            elif kind == EV_CHARGE and r_ok:
                snap["robot_C"][robot] += 1
            elif kind == EV_ASSIGN and r_ok:
                # A grid replay's goals are grid cells (goal_cells of them).
                snap["task"][robot] = cell if cell < self.goal_cells else -1
            elif kind == EV_PUT_BACK and r_ok:
                snap["task"][robot] = -1
            elif kind == EV_PICKUP:
                if c_ok:
                    cells[cell] = 0
                if r_ok:
                    snap["carrying"][robot] = cell if c_ok else -1
            elif kind == EV_DELIVER and r_ok:
                snap["task"][robot] = -1
                snap["carrying"][robot] = -1
            elif kind == EV_RESTOCK and c_ok:
                cells[cell] = 1

    def _snapshot(self, i: int) -> Dict[str, np.ndarray]:
        """Derived state before any event of chunk ``i`` (i.e. after all earlier chunks).

        Snapshots are built in order and kept (a few arrays per chunk); the work happens
        outside the lock so that readers of other chunks are not held up."""
        with self._lock:
            if len(self._snapshots) > i:
                return self._snapshots[i]
        with self._index_lock:  # one builder at a time; the others wait for its result
            while True:
                with self._lock:
                    if not self._snapshots:
                        self._snapshots.append(self._initial_snapshot())
                    if len(self._snapshots) > i:
                        return self._snapshots[i]
                    j = len(self._snapshots) - 1
                    base = self._snapshots[j]
                snap = {k: v.copy() for k, v in base.items()}
                self._apply(snap, self.chunk_events(j))
                with self._lock:
                    self._snapshots.append(snap)

    def build_index(self) -> None:
        """Compute every chunk's starting state now (the viewer does this in the background,
        so that a later jump to any frame is quick)."""
        self._snapshot(self.chunk_count - 1)

    def state_at(self, f: int) -> Dict[str, np.ndarray]:
        """Cells and per-robot derived state after step ``f``, from the events.

        Keys: ``cells`` (n_cells,) uint8 1 = full; ``robot_S``, ``robot_C`` (N,) waits and
        charges so far; ``task`` (N,) the cell each robot is fetching or carrying, -1 if none;
        ``carrying`` (N,) the cell whose goods it carries, -1 if none.
        """
        f = self._check_frame(f)
        i = self.chunk_of(f)
        snap = {k: v.copy() for k, v in self._snapshot(i).items()}
        ev = self._views(i)["events"]
        if len(ev):
            self._apply(snap, ev[ev[:, 0] <= f])
        return snap

    def cells_at(self, f: int) -> np.ndarray:
        """Which storage cells hold goods after step ``f`` (uint8, 1 = full)."""
        return self.state_at(f)["cells"]

    def base_cells(self, i: int) -> np.ndarray:
        """Cells before chunk ``i``'s events (what the viewer starts a chunk from)."""
        return self._snapshot(self._check_chunk(i))["cells"].copy()

    def base_goals(self, i: int) -> np.ndarray:
        """Each robot's task (in a grid replay, its goal cell; -1 if none) before chunk
        ``i``'s events (what the viewer starts a chunk from)."""
        return self._snapshot(self._check_chunk(i))["task"].copy()

    def delay_end(self, robot: int, f: int) -> Optional[int]:
        """In a League of Robot Runners 2026 replay (docs/lorr.md), the tick at which robot
        ``robot``'s latest delay started by frame ``f`` ends (the third column of its last
        ``WAIT`` event up to ``f``); None if it had none. Read chunk by chunk backwards from
        ``f``'s, so it is quick for a robot held now (its delay started a few frames ago).
        None in any other replay (there a WAIT event is a wait that began, with no end)."""
        robot = int(robot)
        if not 0 <= robot < self.robots:
            raise IndexError(f"robot {robot} out of range 0..{self.robots - 1}")
        f = self._check_frame(f)
        lorr = self.header.get("lorr")
        if not isinstance(lorr, dict) or lorr.get("rules") != "2026":
            return None
        for i in range(self.chunk_of(f), -1, -1):
            ev = self.chunk_events(i)
            hit = ev[(ev[:, 0] <= f) & (ev[:, 1] == EV_WAIT) & (ev[:, 2] == robot)]
            if len(hit):
                return int(hit[-1, 3])
        return None

    def trajectory(self, robot: int, f: int, limit: int = 3000) -> np.ndarray:
        """Where robot ``robot`` drives next from frame ``f``: its positions until the end of
        its current movement (or of the next one, if it is standing), at most ``limit`` frames.
        Returns a (K, 2) float64 array of points with collinear points removed."""
        robot = int(robot)
        if not 0 <= robot < self.robots:
            raise IndexError(f"robot {robot} out of range 0..{self.robots - 1}")
        f = self._check_frame(f)
        end = min(self.frames, f + int(limit))
        here = self.frame(f)
        xs: List[np.ndarray] = [np.array([float(here["x"][robot])])]
        ys: List[np.ndarray] = [np.array([float(here["y"][robot])])]
        started = False
        g = f
        while g < end:
            ch = self._views(self.chunk_of(g))
            first = ch["first_frame"]
            k0 = g - first
            k1 = min(ch["frames"], end - first)
            mv = np.isin(ch["state_raw"][k0:k1, robot] & _core.STATE_MASK, MOVING_STATES)
            if not started:
                idx = np.flatnonzero(mv)
                if not len(idx):
                    g = first + k1
                    continue
                k0 += int(idx[0])
                mv = mv[int(idx[0]):]
                started = True
            idle = np.flatnonzero(~mv)
            stop = int(idle[0]) + 1 if len(idle) else len(mv)
            xs.append(ch["x"][k0:k0 + stop, robot].astype(np.float64))
            ys.append(ch["y"][k0:k0 + stop, robot].astype(np.float64))
            g = first + k0 + stop
            if len(idle):
                break
        pts = np.stack([np.concatenate(xs), np.concatenate(ys)], axis=1)
        return _simplify(pts)


def _simplify(pts: np.ndarray, eps: float = 1e-3) -> np.ndarray:
    """Drop repeated and collinear points of a polyline."""
    if len(pts) <= 2:
        return pts
    keep = [0]
    for j in range(1, len(pts) - 1):
        a = pts[keep[-1]]
        b = pts[j]
        c = pts[j + 1]
        if np.hypot(*(b - a)) < eps:
            continue
        cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
        if abs(cross) > eps * max(1.0, np.hypot(*(c - b)) * np.hypot(*(b - a))):
            keep.append(j)
    keep.append(len(pts) - 1)
    return pts[keep]
