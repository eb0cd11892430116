"""The viewer: a server (:mod:`.handler`) with what it shows, a replay (:class:`ReplaySource`)
or a live run (:class:`LiveSource`), started and stopped by :class:`Viewer`."""

from __future__ import annotations

import math
import os
import threading
import urllib.parse
from typing import Any, Dict, List, Optional, Tuple

from multibots import _core
from multibots.replay import Replay
from multibots.result import bottleneck_line
from multibots.viewer.handler import ViewerHTTPServer, load_assets

__all__ = ["LiveSource", "ReplaySource", "Viewer"]


def _codec() -> Dict[str, int]:
    """The replay codec's numbers the page decodes frames with (docs/replay-format.md): the
    engine's, sent in the meta of a replay and of a live run alike, so the page has no copy."""
    return {
        "marked": _core.MARKED,
        "state_mask": _core.STATE_MASK,
        "heading_steps": _core.HEADING_STEPS,
        "energy_scale": _core.ENERGY_SCALE,
    }


def _zones(header: Dict[str, Any]) -> Optional[List[float]]:
    z = (header.get("humans") or {}).get("zones")
    number = (int, float)
    ok = isinstance(z, list) and len(z) == 2 and all(isinstance(v, number) and math.isfinite(v) and v > 0 for v in z)
    return [float(v) for v in z] if ok else None


def _lorr(header: Dict[str, Any]) -> Optional[Dict[str, Any]]:
    """The header's ``lorr`` object, if it is one; ``agentSize`` only if it is a positive
    finite number (the page draws each robot's square with it)."""
    lorr = header.get("lorr")
    if not isinstance(lorr, dict):
        return None
    out = dict(lorr)
    size = out.get("agentSize")
    if size is not None and not (isinstance(size, (int, float)) and math.isfinite(size) and size > 0):
        del out["agentSize"]
    return out


class ReplaySource:
    """What the server needs from a replay."""

    mode = "replay"

    def __init__(self, replay: Replay) -> None:
        self.replay = replay
        self.file_name = os.path.basename(replay.path)
        r = replay
        self.meta = {
            "mode": "replay",
            "name": self.file_name,
            "replay_url": "/replay/" + urllib.parse.quote(self.file_name),
            "robots": r.robots,
            "radius": [float(v) for v in r.radius],
            "home": [int(v) for v in r.home],
            "energy_full": r.energy_full,
            "threshold": r.threshold,
            "goods_total": r.goods_total,
            "cells_full": [int(v) for v in r.cells_full],
            "layout": r.layout,
            "frames": r.frames,
            "summary": r.summary,
            "chunk_steps": r.chunk_steps,
            "chunks": [[r.chunk_info(i)["first_frame"], r.chunk_info(i)["frames"]] for i in range(r.chunk_count)],
            "scenario": r.header.get("scenario", ""),
            # A League of Robot Runners replay's inputs (docs/lorr.md): the rules ("2023",
            # "2024", "2026") and, under the 2026 rules, agentSize and agentCounter.
            "lorr": _lorr(r.header),
            # The engine's names of the codes (also in new replays' headers).
            "state_names": list(_core.STATE_NAMES),
            "event_names": {str(k): v for k, v in _core.EVENT_NAMES.items()},
            "codec": _codec(),
            # People (docs/people.md): their number and radius, checked by the reader; the zones
            # only if they are two finite numbers.
            "humans": None if not r.humans else {
                "count": r.humans, "radius": r.human_radius, "zones": _zones(r.header),
            },
            # The run's report of its resources (docs/metrics.md), each one's queue as the
            # frames where it changed, and the bottleneck as `multibots run` prints it.
            "resources": r.resources,
            "queues": r.queue_changes(),
            "bottleneck": r.bottleneck,
            "bottleneck_line": None if r.bottleneck is None else bottleneck_line(r.bottleneck),
        }

    def start_index(self) -> None:
        """Build the replay's per-chunk cell index in the background."""
        def run() -> None:
            try:
                self.replay.build_index()
            except Exception:  # a broken chunk is reported when it is asked for
                pass

        threading.Thread(target=run, name="multibots-replay-index", daemon=True).start()

    def robot(self, i: int, frame: int) -> Dict[str, Any]:
        r = self.replay
        if not 0 <= i < r.robots:
            raise IndexError(f"robot {i} out of range 0..{r.robots - 1}")
        fr = r.frame(frame)
        st = r.state_at(frame)
        task = int(st["task"][i])
        marked = bool(fr["marked"][i])
        info = {
            "id": i,
            "frame": int(frame),
            "state": int(fr["state"][i]),
            "marked": marked,
            "energy": float(fr["energy"][i]),
            "energy_full": r.energy_full,
            "task_cell": task if task >= 0 else None,
            "S": int(st["robot_S"][i]),
            "C": int(st["robot_C"][i]),
            "route": r.trajectory(i, frame).round(2).tolist(),
        }
        if self.meta["lorr"] is not None and self.meta["lorr"].get("rules") == "2026":
            # Under the 2026 rules the marked bit says "held by a delay" (docs/lorr.md), and
            # its WAIT event the tick the delay ends.
            info["held"] = marked
            info["held_until"] = r.delay_end(i, frame) if marked else None
        return info


class LiveSource:
    mode = "live"

    def __init__(self, runner: Any, name: str = "live") -> None:
        self.runner = runner
        self.meta = dict(runner.meta)
        self.meta["name"] = name
        self.meta["codec"] = _codec()

    def robot(self, i: int) -> Dict[str, Any]:
        return self.runner.robot(i)


class Viewer:
    """A running viewer server. ``Viewer.for_replay(path)`` or ``Viewer.for_simulation(sim)``,
    then ``start()`` (background thread) or ``serve_forever()``; ``close()`` stops it."""

    def __init__(self, source: Any, host: str = "127.0.0.1", port: int = 0, verbose: bool = False,
                 allow_hosts: Tuple[str, ...] = ()) -> None:
        self.source = source
        self.httpd = ViewerHTTPServer((host, port), source, load_assets(), verbose=verbose,
                                      allow_hosts=tuple(allow_hosts))
        self.host = host
        self.port = self.httpd.server_address[1]
        self._thread: Optional[threading.Thread] = None

    @classmethod
    def for_replay(cls, path: str, **kw: Any) -> "Viewer":
        return cls(ReplaySource(Replay(path)), **kw)

    @classmethod
    def for_simulation(cls, sim: Any, name: str = "live", speed: float = 1.0, paused: bool = False,
                       **kw: Any) -> "Viewer":
        from .live import LiveRunner

        runner = LiveRunner(sim, speed=speed, paused=paused)
        runner.start()
        try:
            return cls(LiveSource(runner, name=name), **kw)
        except BaseException:
            runner.stop()
            raise

    @property
    def url(self) -> str:
        host = self.host
        if ":" in host:
            host = f"[{host}]"
        if host in ("0.0.0.0", "[::]"):
            host = "127.0.0.1"
        return f"http://{host}:{self.port}/"

    def start(self) -> "Viewer":
        self._start_background()
        self._thread = threading.Thread(target=self.httpd.serve_forever, kwargs={"poll_interval": 0.2},
                                        name="multibots-viewer", daemon=True)
        self._thread.start()
        return self

    def _start_background(self) -> None:
        if hasattr(self.source, "start_index"):
            self.source.start_index()

    def serve_forever(self) -> None:
        self._start_background()
        self.httpd.serve_forever(poll_interval=0.2)

    def close(self) -> None:
        self.httpd.stopping.set()
        runner = getattr(self.source, "runner", None)
        if runner is not None:
            runner.stop()
        if self._thread is not None:
            self.httpd.shutdown()
            self._thread.join(timeout=10)
            self._thread = None
        self.httpd.server_close()
        replay = getattr(self.source, "replay", None)
        if replay is not None:
            replay.close()

    def __enter__(self) -> "Viewer":
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()
