"""Scenarios: what to run. The schema lives in the engine; this class only carries it.

Every field, its default and its checks are defined once, in the engine's scenario module
(see ``docs/scenario-format.md``). Python builds a scenario from TOML, from a dictionary or
with :meth:`Scenario.paper`, and the engine validates it on the way in.
"""

from __future__ import annotations

import copy
import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from multibots import _args, _core
from multibots._io import read_input
from multibots._text import shown
from multibots.exceptions import ArgumentError, ScenarioError
from multibots.paper import PAPER_TASKS

__all__ = ["Scenario"]


def _merge(base: dict[str, Any], changes: Mapping[str, Any]) -> dict[str, Any]:
    out = copy.deepcopy(base)
    for key, value in changes.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = value
    return out


def _parsed(data: Mapping[str, Any]) -> _core.Scenario:
    try:
        text = json.dumps(data, allow_nan=False)
    except (TypeError, ValueError, RecursionError):
        # JSON's own words ("Out of range float values are not JSON compliant") name neither
        # the field nor the value: find them.
        raise ScenarioError(_unsendable(data)) from None
    return _core.Scenario.from_json(text)


#: Deepest nesting of a scenario (the engine's ``limits::MAX_NESTING``, docs/limits.md).
MAX_NESTING = 32


def _unsendable(data: Any) -> str:
    """The first value of ``data`` that JSON cannot carry, as ``FIELD = VALUE: reason``."""
    stack: list[tuple[str, Any, int]] = [("", data, 0)]
    while stack:
        path, value, depth = stack.pop()
        where = path or "scenario"
        if depth > MAX_NESTING:
            return f"{shown(where)}: nested deeper than {MAX_NESTING} levels (docs/limits.md)"
        if isinstance(value, float) and not math.isfinite(value):
            return f"{shown(where)} = {value}: must be a finite number"
        if isinstance(value, Mapping):
            for key, item in reversed(list(value.items())):
                if not isinstance(key, (str, int, float, bool)) and key is not None:
                    return f"{shown(where)}: key {shown(repr(key))} is not text"
                stack.append((f"{path}.{key}" if path else str(key), item, depth + 1))
        elif isinstance(value, (list, tuple)):
            stack.extend((f"{path}[{i}]", item, depth + 1) for i, item in reversed(list(enumerate(value))))
        elif not isinstance(value, (str, int, float, bool)) and value is not None:
            return (f"{shown(where)} = {shown(repr(value))}: expected a number, text, true or false, a list or a "
                    f"table, not {type(value).__name__}")
    return "scenario: cannot be written as a scenario"


class Scenario:
    """A validated scenario: layout, fleet, task list and model parameters.

    Example:
        >>> s = Scenario.paper(robots=2, goods=[11, 8, 39], margin=8)
        >>> s.to_dict()["collision"]["margin"]
        8.0
    """

    __slots__ = ("_core", "source")

    def __init__(self, core: _core.Scenario) -> None:
        core.validate()
        self._core = core
        #: The file the scenario was read from, if any (what no output of its run may be).
        self.source: Path | None = None

    @classmethod
    def from_toml(cls, path: str | os.PathLike[str]) -> Scenario:
        """Reads and validates a scenario file.

        Raises:
            ScenarioError: the file is missing, unreadable, not TOML, or a field is invalid.
        """
        p = _args.path("path", path)
        assert p is not None
        text = read_input(p, ScenarioError, "scenario file")
        out = cls.from_toml_str(text, source=str(p))
        out.source = p
        return out

    @classmethod
    def from_toml_str(cls, text: str, source: str = "<scenario>") -> Scenario:
        """Parses and validates TOML text; ``source`` names it in error messages."""
        if not isinstance(text, str):
            raise ArgumentError(f"text: expected the TOML text (str), got {type(text).__name__}")
        if not isinstance(source, str):
            raise ArgumentError(f"source: expected a name (str), got {type(source).__name__}")
        return cls(_core.Scenario.from_toml(text, source))

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Scenario:
        """Builds a scenario from a dictionary shaped like the TOML file."""
        return cls(_parsed(data))

    @classmethod
    def _parsed_only(cls, data: Mapping[str, Any]) -> Scenario:
        """Parsed but not yet validated: for callers that validate many at once
        (``_core.check_many``, which builds each layout once) before using any."""
        out = cls.__new__(cls)
        out._core = _parsed(data)
        out.source = None
        return out

    @classmethod
    def paper(
        cls,
        robots: int = 3,
        goods: Iterable[int] | None = None,
        starts: Iterable[str] | None = None,
        unload: str = "M",
        margin: float = 0.0,
        step_limit: int = 100_000,
        **fields: Any,
    ) -> Scenario:
        """A scenario on the paper's layout.

        Args:
            robots: number of robots N.
            goods: cell ids to fetch, in order (default: TABLE III's group 1). The same
                field as ``tasks``: give one or the other, not both.
            starts: start node of each robot, such as ``["A", "C"]``; default A, B, C, ….
            unload: the unloading zone.
            margin: added to the collision contact distance, px.
            step_limit: steps after which the run ends incomplete.
            **fields: any other scenario field, such as ``robot={"threshold": 2.0}``, or
                ``tasks={"random": 10, "seed": 1}`` instead of ``goods``.

        Raises:
            ScenarioError: a field is invalid, or both ``goods`` and ``tasks`` are given.
        """
        if goods is not None and "tasks" in fields:
            raise ScenarioError("Scenario.paper(): goods and tasks are the same field (the task list); give one")
        if goods is not None:
            goods = _args.sequence("goods", goods, int, "cell id")
        if starts is not None:
            starts = _args.sequence("starts", starts, str, "node name")
        data: dict[str, Any] = {
            "layout": "paper",
            "robots": robots,
            "unload": unload,
            "tasks": list(PAPER_TASKS[1] if goods is None else goods),
            "step_limit": step_limit,
            "collision": {"margin": margin},
        }
        if starts is not None:
            data["starts"] = list(starts)
        # `data` is this call's own: merged into a copy only when there is something to merge.
        return cls.from_dict(_merge(data, fields) if fields else data)

    def replace(self, **changes: Any) -> Scenario:
        """A copy with some fields changed; nested tables are merged."""
        out = Scenario.from_dict(_merge(self.to_dict(), changes))
        out.source = self.source
        return out

    def warnings(self) -> list[str]:
        """What to tell before a run, one line each, with the numbers and the fix: a fleet its
        chargers cannot keep charged. Empty for a scenario that can run as it is."""
        return self._core.warnings()

    def resolved(self) -> Scenario:
        """The scenario with every ``"auto"`` choice made for its layout (placement, chargers,
        charging policy, unloading, traffic; docs/scenario-format.md): what a run of it does."""
        out = Scenario(self._core.resolved())
        out.source = self.source
        return out

    def files(self) -> list[tuple[str, Path]]:
        """The files a run of this scenario reads, as (what, path): the scenario file itself
        (when read from one), a layout file, the orders' and people's CSV tables, and a
        strategy's source file (``allocator = "path/to/file.py:Class"``)."""
        out = [("scenario file", self.source)] if self.source is not None else []
        out += [(f"{f} file" if f == "layout" else f"{f} table", Path(p)) for f, p in self._core.files()]
        module = self._core.allocator.rpartition(":")[0]
        if module.endswith(".py"):
            out.append(("strategy file", Path(module)))
        return out

    def to_toml(self) -> str:
        """The scenario as TOML text, which :meth:`from_toml_str` reads back."""
        return self._core.to_toml()

    def to_dict(self) -> dict[str, Any]:
        """The scenario as a dictionary, defaults filled in."""
        return json.loads(self._core.to_json())

    @property
    def cells(self) -> list[int]:
        """The task list as cell ids (a random list drawn from its seed)."""
        return self._core.cells()

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Scenario) and self._core == other._core

    def __hash__(self) -> int:
        # Coarser than equality on purpose: equal scenarios (even 0.0 against -0.0) hash alike.
        d = self.to_dict()
        return hash((d["layout"] if isinstance(d["layout"], str) else "table", d["robots"], tuple(self.cells)))

    def __repr__(self) -> str:
        d = self.to_dict()
        return f"Scenario(layout={d['layout']!r}, robots={d['robots']}, tasks={d['tasks']!r})"
