"""Run a ``multibots.Simulation`` in a background thread and publish its frames to viewers."""

from __future__ import annotations

import base64
import json
import math
import threading
import time
from typing import Any, Dict, List, Optional

import numpy as np

from multibots.result import bottleneck_line

#: Simulation steps per second of wall time at speed 1x (the page and `render` agree on it).
STEPS_PER_SECOND = 30.0
MIN_SPEED = 0.25
MAX_SPEED = 64.0


def _jsonable(v: Any) -> Any:
    if isinstance(v, (np.integer,)):
        return int(v)
    if isinstance(v, (np.floating,)):
        return float(v)
    return v


def _flow(raw: Dict[str, Any]) -> Dict[str, Any]:
    """Deliveries per window so far, for the viewer's throughput bars."""
    return {"window": int(raw["window"]), "windows": [int(w) for w in raw["windows"]]}


def _resources(sim: Any, raw: Dict[str, Any], names: List[str]) -> Dict[str, Any]:
    """The resources reported so far (``Result.resources``), the robots queued at each now,
    and the bottleneck so far with its line as ``multibots run`` prints it."""
    nodes, chargers = sim.queues()
    by_name = {names[k]: c for k, c in nodes.items()}
    by_name.update({f"{names[u]}->{names[v]}": c for (u, v), c in sim.lane_queues().items()})
    resources = list(raw["resources"])
    b = raw["bottleneck"]
    return {
        "resources": resources,
        "queue": [chargers if u["kind"] == "charger-queue" else by_name.get(u["node"], 0) for u in resources],
        "bottleneck": b,
        "bottleneck_line": None if b is None else bottleneck_line(b),
    }


class LiveRunner:
    """Steps a simulation at ``speed`` x 30 steps per second, paused or not, and keeps the
    latest frame as a ready-to-send JSON message (``message``, ``version``).

    The simulation only starts moving once ``begin()`` is called (the first page connects),
    so nothing is missed while the browser opens. Thread-safe: the server calls ``control``,
    ``robot`` and ``wait_message`` from its request threads.
    """

    def __init__(self, sim: Any, speed: float = 1.0, paused: bool = False, tick: float = 1 / 60) -> None:
        self.sim = sim
        self.lock = threading.Lock()  # guards the simulation
        self.cond = threading.Condition()  # guards the fields below
        self.paused = bool(paused)
        self.speed = float(speed)
        self.tick = float(tick)
        self.version = 0
        self.message = ""
        self._pending_steps = 0
        self._stop = threading.Event()
        self._go = threading.Event()
        self._thread: Optional[threading.Thread] = None
        self.error: Optional[str] = None
        with self.lock:
            self.meta = self._meta()
            self._names = [str(n["name"]) for n in self.meta["layout"].get("nodes", [])]
            self._publish_locked()

    # ------------------------------------------------------------------ state
    def _meta(self) -> Dict[str, Any]:
        # The engine's viewer header (the replay header's fields), with what a live run adds.
        meta = self.sim.viewer_header()
        meta.update({"mode": "live", "frames": None, "summary": None, "steps_per_second": STEPS_PER_SECOND})
        return meta

    def _publish_locked(self) -> None:
        """Snapshot the simulation (caller holds self.lock) into a message: one frame of the
        replay codec, encoded by the engine."""
        sim = self.sim
        raw = sim.frame_chunk()
        result = sim._sim.result()
        t = int(sim.t)
        S, C, D = int(sim.S), int(sim.C), int(sim.delivered)
        cells = np.asarray(sim.cells, dtype=np.uint8).tobytes()
        T = sim.T
        body = {
            "t": t,
            "S": S,
            "C": C,
            "delivered": D,
            "goods_total": int(sim.goods_total),
            "done": bool(sim.done),
            "T": None if T is None else int(T),
            "outcome": str(sim.outcome) if sim.done else None,
            "frame": base64.b64encode(raw).decode("ascii"),
            **_flow(result),
            **_resources(sim, result, self._names),
            "cells": base64.b64encode(cells).decode("ascii"),
        }
        with self.cond:
            body["paused"] = self.paused
            body["speed"] = self.speed
            body["error"] = self.error
            self.version += 1
            body["version"] = self.version
            self.message = json.dumps(body, separators=(",", ":"))
            self.cond.notify_all()

    def publish(self) -> None:
        with self.lock:
            self._publish_locked()

    # ------------------------------------------------------------------ control
    def control(self, action: str, speed: Optional[float] = None) -> Dict[str, Any]:
        """Apply a control message; raises ValueError on a bad one. Holds the simulation's
        lock, so once a pause is acknowledged no further step is taken."""
        with self.lock, self.cond:
            if action == "pause":
                self.paused = True
            elif action == "resume":
                self.paused = False
            elif action == "step":
                self.paused = True
                self._pending_steps += 1
            elif action == "speed":
                if speed is None or not isinstance(speed, (int, float)) or isinstance(speed, bool) \
                        or not math.isfinite(speed) or not MIN_SPEED <= speed <= MAX_SPEED:
                    raise ValueError(f"speed must be a number from {MIN_SPEED} to {MAX_SPEED}")
                self.speed = float(speed)
            else:
                raise ValueError(f"unknown action {action!r}")
            self.cond.notify_all()
            state = {"paused": self.paused, "speed": self.speed}
        self.publish()
        return state

    def robot(self, i: int) -> Dict[str, Any]:
        with self.lock:
            sim = self.sim
            n = len(np.asarray(sim.radius))
            if not 0 <= i < n:
                raise IndexError(f"robot {i} out of range 0..{n - 1}")
            try:
                route = np.asarray(sim.route(i), dtype=np.float64).reshape(-1, 2).tolist()
            except Exception:  # a route is a nicety; never fail the panel for it
                route = []
            task = int(np.asarray(sim.task_cells)[i])
            return {
                "id": i,
                "frame": int(sim.t),
                "state": int(np.asarray(sim.states)[i]),
                "marked": bool(np.asarray(sim.marked)[i]),
                "energy": float(np.asarray(sim.energy)[i]),
                "energy_full": float(sim.energy_full),
                "task_cell": task if task >= 0 else None,
                "S": int(np.asarray(sim.robot_S)[i]),
                "C": int(np.asarray(sim.robot_C)[i]),
                "route": route,
            }

    def wait_message(self, after: int, timeout: float) -> tuple:
        """Block until a message newer than ``after`` exists (or timeout); return (version, message)."""
        with self.cond:
            if self.version <= after and not self._stop.is_set():
                self.cond.wait(timeout)
            return self.version, self.message

    # ------------------------------------------------------------------ thread
    def begin(self) -> None:
        self._go.set()

    def start(self) -> None:
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="multibots-live", daemon=True)
            self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self._go.set()
        with self.cond:
            self.cond.notify_all()
        if self._thread is not None:
            self._thread.join(timeout=10)

    @property
    def stopped(self) -> bool:
        return self._stop.is_set()

    def _run(self) -> None:
        self._go.wait()
        acc = 0.0
        last = time.monotonic()
        was_paused = True
        while not self._stop.is_set():
            t0 = time.monotonic()
            dt = 0.0 if was_paused else t0 - last
            last = t0
            with self.cond:
                paused, speed = self.paused, self.speed
                pending, self._pending_steps = self._pending_steps, 0
            was_paused = paused
            if paused:
                acc = 0.0
                n = pending
            else:
                acc += dt * speed * STEPS_PER_SECOND
                n = int(acc)
                acc -= n
                cap = max(1, int(math.ceil(speed * STEPS_PER_SECOND * 0.1)))
                if n > cap:  # the engine is slower than asked: do not pile up a backlog
                    n, acc = cap, 0.0
            if n > 0:
                with self.lock:
                    with self.cond:  # a pause that came in meanwhile wins
                        if self.paused and not pending:
                            n = 0
                    if n > 0 and not self.sim.done:
                        try:
                            self.sim.step(n)
                        except Exception as exc:  # keep serving what we have
                            self.error = f"{type(exc).__name__}: {exc}"
                            with self.cond:
                                self.paused = True
                        self._publish_locked()
            spent = time.monotonic() - t0
            with self.cond:
                if not self._stop.is_set():
                    wake = self.tick - spent if not (self.paused and not self._pending_steps) else 0.5
                    if wake > 0:
                        self.cond.wait(wake)
