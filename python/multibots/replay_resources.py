"""A replay footer's resources (docs/replay-format.md): the run's report of each unloading
zone, charger, crossing and lane, its bottleneck, and each reported resource's queue frame by
frame. Replays written before the engine kept them have none."""

from __future__ import annotations

import bisect
import json
import math
from typing import Any, Callable, Dict, List, Optional, Tuple

from multibots._text import shown

__all__ = ["ResourceLog"]

_MAX_COUNT = 1 << 32
_KINDS = ("unloading", "charger", "charger-queue", "crossing", "lane")


class ResourceLog:
    """What a footer says of the run's resources, checked; ``fail(message)`` makes the error
    to raise for a footer that says it wrongly.

    Attributes: ``resources`` (list of dicts: kind, node, busy, mean_queue, longest_queue, as
    in ``Result.resources``), ``bottleneck`` (dict with ``relieve`` as well, or None).
    """

    def __init__(self, footer: Dict[str, Any], frames: int, fail: Callable[[str], Exception]) -> None:
        self._fail = fail
        raw = footer.get("resources")
        raw = [] if raw is None else raw
        if not isinstance(raw, list):
            raise fail(f"footer 'resources' is {shown(json.dumps(raw))}; expected a list")
        self.resources: List[Dict[str, Any]] = [self._resource(u, "footer resource") for u in raw]
        b = footer.get("bottleneck")
        self.bottleneck: Optional[Dict[str, Any]] = None
        if b is not None:
            self.bottleneck = self._resource(b, "footer bottleneck")
            relieve = b.get("relieve")
            if not isinstance(relieve, str):
                raise fail("footer bottleneck 'relieve' is not text")
            self.bottleneck["relieve"] = shown(relieve, 400)
        queues = footer.get("queues")
        if queues is None:
            queues = [[] for _ in self.resources]
        if not isinstance(queues, list) or len(queues) != len(self.resources):
            raise fail(f"footer 'queues' is not a list of one list per resource ({len(self.resources)})")
        self._changes: List[Tuple[List[int], List[int]]] = [self._changes_of(q, frames) for q in queues]

    def _resource(self, u: Any, what: str) -> Dict[str, Any]:
        if not isinstance(u, dict):
            raise self._fail(f"{what} is {shown(json.dumps(u))}; expected a JSON object")
        kind, node = u.get("kind"), u.get("node")
        if kind not in _KINDS:
            raise self._fail(f"{what} 'kind' is {shown(json.dumps(kind))}; expected one of {', '.join(_KINDS)}")
        if not isinstance(node, str):
            raise self._fail(f"{what} 'node' is not text")
        out: Dict[str, Any] = {"kind": kind, "node": shown(node, 80)}
        for key, hi in (("busy", 1.0), ("mean_queue", float(_MAX_COUNT))):
            v = u.get(key)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or not 0 <= v <= hi:
                raise self._fail(f"{what} {key!r} is {shown(json.dumps(v))}; expected a number from 0 to {hi:g}")
            out[key] = float(v)
        longest = u.get("longest_queue")
        if isinstance(longest, bool) or not isinstance(longest, int) or not 0 <= longest < _MAX_COUNT:
            raise self._fail(f"{what} 'longest_queue' is {shown(json.dumps(longest))}; expected a whole number")
        out["longest_queue"] = longest
        return out

    def _changes_of(self, q: Any, frames: int) -> Tuple[List[int], List[int]]:
        ok = isinstance(q, list) and len(q) % 2 == 0 and all(isinstance(v, int) and not isinstance(v, bool) for v in q)
        if not ok:
            raise self._fail("footer 'queues' holds a list that is not [frame, robots, ...] pairs")
        at, counts = q[0::2], q[1::2]
        if any(not 0 <= f < frames for f in at) or any(b <= a for a, b in zip(at, at[1:])):
            raise self._fail(f"footer 'queues' holds frames out of order or outside 0..{frames - 1}")
        if any(not 0 <= c < _MAX_COUNT for c in counts):
            raise self._fail("footer 'queues' holds a negative or oversized queue")
        return at, counts

    def queues_at(self, frame: int) -> List[int]:
        """The robots queued at each of ``resources`` in ``frame`` (after its step)."""
        out = []
        for at, counts in self._changes:
            k = bisect.bisect_right(at, frame) - 1
            out.append(counts[k] if k >= 0 else 0)
        return out

    def changes(self) -> List[List[int]]:
        """Each resource's queue as the footer keeps it: ``[frame, robots, ...]`` where it
        changed (empty before the first)."""
        return [[v for pair in zip(at, counts) for v in pair] for at, counts in self._changes]
