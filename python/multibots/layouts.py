"""Layouts as data: generate layout files and check them (``multibots layout generate|check``).

The layout file's schema belongs to the engine (``docs/layout-format.md``); this module only
passes parameters in and text out.

Example:
    >>> text = generate_layout(group_rows=2, group_cols=5, group_size="2x4")
    >>> text.startswith("# MultiBots layout file")
    True
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any, Optional, Union

from multibots import _core
from multibots._io import read_input
from multibots._text import shown
from multibots.exceptions import ScenarioError

__all__ = ["MAX_GROUPS", "generate_layout", "parse_group_size", "check_layout_file", "check_layout_text"]


#: The most groups, or cells down a group, a generated layout may have: a layout has at most
#: 1,000,000 storage cells (docs/limits.md).
MAX_GROUPS = 1_000_000


def parse_group_size(value: str) -> tuple[int, int]:
    """``"2x4"`` -> (2, 4): cells across and down a storage group."""
    parts = value.lower().replace(" ", "").split("x")
    try:
        w, h = (int(p) for p in parts)
    except ValueError:
        raise ScenarioError(f"--group-size = {shown(value)!r}: expected WxH, such as 2x4") from None
    if max(w, h) > MAX_GROUPS:
        raise ScenarioError(f"--group-size = {shown(value)}: layout too large: at most {MAX_GROUPS:,} cells down a "
                            "group (docs/limits.md)")
    return w, h


def generate_layout(
    group_rows: int = 2,
    group_cols: int = 5,
    group_size: str = "2x4",
    aisle: float = 50.0,
    cell: float = 50.0,
    chargers: Optional[int] = None,
    spur: float = 40.0,
    name: str = "generated",
    unloading_rows: Union[int, str] = "auto",
    aisles: str = "auto",
    charger_walls: str = "top",
) -> str:
    """The layout file text of a generated grid warehouse (checked by the engine): every
    field of a scenario's ``[layout_generate]`` (docs/layout-format.md).

    The defaults are the paper's warehouse; ``chargers`` defaults to one per top-aisle
    crossing (``group_cols + 1``), spread over the walls ``charger_walls`` names (``"top"``,
    ``"top-bottom"`` or ``"all"``); ``unloading_rows`` and ``aisles`` default to ``"auto"``,
    which the generator chooses for the warehouse's size (the paper's for the paper's size).
    """
    w, h = parse_group_size(group_size)
    params = {
        "group_rows": group_rows,
        "group_cols": group_cols,
        "group_width": w,
        "group_height": h,
        "aisle": float(aisle),
        "cell": float(cell),
        "chargers": group_cols + 1 if chargers is None else chargers,
        "spur": float(spur),
        "unloading_rows": unloading_rows,
        "aisles": aisles,
        "charger_walls": charger_walls,
    }
    for key in ("group_rows", "group_cols", "group_width", "group_height", "chargers", "unloading_rows"):
        if params[key] != "auto" and params[key] < 0:
            raise ScenarioError(f"layout.{key} = {params[key]}: must be at least 1")
    for key in ("aisle", "cell", "spur"):
        if not math.isfinite(params[key]):
            raise ScenarioError(f"layout.{key} = {params[key]}: must be a finite number")
    return _core.generate_layout_toml(json.dumps(params), name)


def check_layout_file(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Reads and checks a layout file; returns its layout JSON (``docs/replay-format.md``)."""
    p = Path(path)
    return check_layout_text(read_input(p, ScenarioError, "layout file"), str(p))


def check_layout_text(text: str, source: str = "<layout>") -> dict[str, Any]:
    """Checks layout file text; returns its layout JSON. ``source`` names it in errors."""
    return json.loads(_core.layout_file_json(text, source))
