"""Arguments of the Python API, checked in one place: a bad one is an :class:`ArgumentError`
(a :class:`~multibots.MultibotsError`, and a ``ValueError`` and a ``TypeError`` too) whose
one line names the parameter and the value, with the bounds the command line uses (the
engine's, ``_core.LIMITS``). Every public function checks its arguments here before anything
reaches the engine, so the binding's conversions (``argument 'until'``, ``cannot be
converted to 'PyString'``) are never what a user reads.
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, Callable, Optional

from multibots._text import shown
from multibots.exceptions import ArgumentError

__all__ = ["allocator", "choice", "function", "number", "path", "sequence", "whole"]

#: The largest count the engine takes where it counts in 64 bits (steps of a run, seeds).
U64 = 2**64 - 1


def _bad(name: str, value: Any, expected: str) -> ArgumentError:
    return ArgumentError(f"{name} = {shown(repr(value))}: {expected}")


def whole(name: str, value: Any, low: int = 0, high: int = U64, *, optional: bool = False) -> Optional[int]:
    """A whole number from ``low`` to ``high`` (``True`` and ``2.0`` are not), or None when
    ``optional``."""
    if value is None and optional:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise _bad(name, value, f"expected a whole number from {low:,} to {high:,}")
    v = int(value)
    if not low <= v <= high:
        raise _bad(name, value, f"expected a whole number from {low:,} to {high:,}")
    return v


def number(name: str, value: Any, low: Optional[float] = None, high: Optional[float] = None, *,
           above: Optional[float] = None, optional: bool = False) -> Optional[float]:
    """A finite real number within the bounds (``above``: strictly greater), or None when
    ``optional``."""
    if value is None and optional:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(float(value)):
        raise _bad(name, value, "expected a finite number")
    v = float(value)
    if (above is not None and not v > above) or (low is not None and v < low) or (high is not None and v > high):
        if above is not None:
            words = f"above {above:g}" + ("" if high is None else f" and at most {high:g}")
        elif low is not None:
            words = f"from {low:g}" + ("" if high is None else f" to {high:g}")
        else:
            words = f"at most {high:g}"
        raise _bad(name, value, f"expected a number {words}")
    return v


def path(name: str, value: Any, *, optional: bool = False) -> Optional[Path]:
    """A file or folder path (text or ``os.PathLike``, not empty), or None when ``optional``."""
    if value is None and optional:
        return None
    if not isinstance(value, (str, os.PathLike)):
        raise _bad(name, value, "expected a path (text or a pathlib.Path)")
    text = os.fspath(value)
    if not isinstance(text, str) or not text or "\0" in text:
        raise _bad(name, value, "expected a path (text or a pathlib.Path)")
    return Path(text)


def choice(name: str, value: Any, known: Iterable[str]) -> str:
    """One of ``known`` names."""
    names = list(known)
    if not isinstance(value, str) or value not in names:
        raise _bad(name, value, f"expected one of {', '.join(names)}")
    return value


def function(name: str, value: Any, *, optional: bool = True) -> Optional[Callable[..., Any]]:
    """Something to call (a function, a method), or None when ``optional``."""
    if value is None and optional:
        return None
    if not callable(value):
        raise _bad(name, value, "expected a function")
    return value


def allocator(name: str, value: Any) -> Any:
    """A task-allocation strategy as ``simulate`` takes one: None (the scenario's), a name, a
    :class:`multibots.Allocator` (anything with an ``allocate`` method) or a function
    ``f(view)``."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, type):
        raise ArgumentError(f"{name}: got the class {value.__name__}; pass an instance, such as {value.__name__}()")
    if callable(getattr(value, "allocate", None)) or callable(value):
        return value
    raise ArgumentError(f"{name}: expected a multibots.Allocator, a function f(view) or a strategy name, "
                        f"got {type(value).__name__}")


def sequence(name: str, value: Any, kind: type, what: str) -> list[Any]:
    """The items of a list (a tuple, a range, a NumPy array) that are each a ``kind`` (for
    ``int``: any whole number but a bool), named ``what`` in the message."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
        raise _bad(name, value, f"expected a list of {what}")
    items = list(value)
    for k, item in enumerate(items):
        whole = isinstance(item, numbers.Integral) and not isinstance(item, bool)
        if not (whole if kind is int else isinstance(item, kind)):
            raise _bad(f"{name}[{k}]", item, f"expected a {what}")
    return [int(v) for v in items] if kind is int else items
