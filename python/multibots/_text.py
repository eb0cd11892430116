"""Small text helpers shared by the command line's outputs."""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["sparkline"]

_BARS = "▁▂▃▄▅▆▇█"


def sparkline(values: Sequence[float], width: int = 60) -> str:
    """Values as a line of bar characters scaled to the largest (at most ``width``: every k-th);
    a zero is a blank."""
    if not values:
        return ""
    step = -(-len(values) // width)
    shown = list(values)[::step]
    top = max(shown) or 1
    return "".join(_BARS[min(len(_BARS) - 1, int(v * (len(_BARS) - 1) // top))] if v else " " for v in shown)
