"""Small text helpers shared by the command line's outputs."""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["inert", "shown", "sparkline"]


def shown(value: object, limit: int = 60) -> str:
    """A value as it may appear in a message: at most ``limit`` characters (with the full
    length when cut) and control characters escaped, so that a huge or hostile value never
    floods or drives the terminal. The engine's ``limits::shown`` does the same."""
    text = str(value)
    cut = text[:limit]
    out = "".join(ch if ch.isprintable() else ch.encode("unicode_escape").decode("ascii") for ch in cut)
    return out + (f"… ({len(text)} characters)" if len(text) > limit else "")


def inert(message: object, limit: int = 600) -> str:
    """A whole message made one safe line: whitespace runs become one space, then as :func:`shown`."""
    return shown(" ".join(str(message).split()), limit)

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
