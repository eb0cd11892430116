"""Sweep specs: a base scenario and the axes to vary (docs/sweeps.md).

```toml
base = "scenarios/paper.toml"   # a scenario file (relative to the spec), or a [base] table
product = "grid"                # every combination of the axes' values; "zip": element by element
repeats = 1                     # runs per point, seeds 1..repeats (see below)

[axes]
robots = [2, 4, 6]
"robot.threshold" = [2.5, 3.5]
allocator = ["in-turn", "nearest"]
traffic = ["wait", "reserve"]
seed = [1, 2, 3]
```

An axis is any scenario field, named by its dotted path (``charging.policy``,
``orders.rate``, ``humans.count``). ``seed`` is special: it sets every seed the scenario
draws with (``tasks.seed`` of random task lists, ``orders.seed``, ``humans.seed``).
``repeats = R`` without a ``seed`` axis runs each point with seeds 1..R.

A League of Robot Runners problem (a ``.json`` path, or a ``[base]`` table with ``lorr``) is a
base too: its axes are the run's options (``sweeps/lorr.py``, docs/lorr.md).
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional, Union

from multibots import _core
from multibots._io import load_toml, read_input
from multibots._text import shown
from multibots.exceptions import InputError, ScenarioError
from multibots.scenario import Scenario
from multibots.sweeps import lorr as lorr_sweep

__all__ = ["MAX_POINTS", "Point", "Spec", "load_spec", "parse_spec"]

#: The most runs a sweep may plan (docs/limits.md).
MAX_POINTS = 1_000_000


@dataclass(frozen=True)
class Point:
    """One run of a sweep: its index in the plan, the axis values and the scenario."""

    index: int
    values: tuple[tuple[str, Any], ...]
    scenario: Scenario
    #: The strategy the run uses (the scenario's ``allocator``).
    allocator: str = "in-turn"


@dataclass
class Spec:
    """A parsed sweep spec."""

    #: A scenario, or a League of Robot Runners problem and its run's options.
    base: Union[Scenario, lorr_sweep.LorrBase]
    axes: dict[str, list[Any]]
    product: str = "grid"
    repeats: int = 1
    source: str = "<spec>"
    names: list[str] = field(default_factory=list)

    def points(self, workers: int = 0) -> list[Any]:
        """Every run, in plan order (deterministic): the grid (or zip) of the axes, each
        point repeated with seeds 1..repeats when there is no seed axis. Every scenario is
        validated before this returns, on ``workers`` engine threads (0: one per core)."""
        names = list(self.axes)
        reps = [None] if self.repeats == 1 or "seed" in self.axes else list(range(1, self.repeats + 1))
        # Counted before anything is built: 10,000 × 10,000 values are a one-line refusal,
        # not a list of 10^8 tuples.
        sizes = [len(self.axes[n]) for n in names]
        combos_count = min(sizes, default=1) if self.product == "zip" else math.prod(sizes)
        total = combos_count * len(reps)
        if total > MAX_POINTS:
            raise InputError(f"{self.source}: the sweep plans {total:,} runs: at most {MAX_POINTS:,}")
        if self.product == "zip":
            combos: Sequence[tuple[Any, ...]] = list(zip(*(self.axes[n] for n in names)))
        else:
            combos = list(itertools.product(*(self.axes[n] for n in names)))
        if isinstance(self.base, lorr_sweep.LorrBase):
            return lorr_sweep.plan(self.base, self.axes, combos, reps, self.source)
        base = self.base.to_dict()
        out = []
        for combo in combos:
            for rep in reps:
                values = list(zip(names, combo)) + ([("seed", rep)] if rep is not None else [])
                scenario, allocator = _apply(dict(base), values, self.source)
                out.append(Point(len(out), tuple(values), scenario, allocator))
        # All at once: each layout is built once, not once per run (it is most of a check).
        failed = _core.check_many([p.scenario._core for p in out], workers)
        if failed is not None:
            k, e = failed
            if not isinstance(e, ScenarioError):
                raise e
            where = ", ".join(f"{n} = {shown(v)}" for n, v in out[k].values)
            raise ScenarioError(f"{self.source}: at {where}: {e}") from None
        return out

    @property
    def axis_names(self) -> list[str]:
        return list(self.axes) + (["seed"] if self.repeats > 1 and "seed" not in self.axes else [])


def _apply(d: dict[str, Any], values: Sequence[tuple[str, Any]], source: str) -> tuple[Scenario, str]:
    """The point's scenario (parsed, validated later with the others): ``d``, a shallow copy
    of the base, with the axis values set. Tables are copied on the way down to a value, never
    changed in place: the base's tables are shared by every point."""
    for name, value in values:
        if name != "seed":
            _set(d, name.split("."), value)
    # The seed last: an axis that sets a whole table (tasks = {random = 5}) must not undo it.
    for name, value in values:
        if name == "seed":
            _set_seed(d, value, source)
    try:
        return Scenario._parsed_only(d), str(d.get("allocator", "in-turn"))
    except ScenarioError as e:
        where = ", ".join(f"{n} = {shown(v)}" for n, v in values)
        raise ScenarioError(f"{source}: at {where}: {e}") from None


def _set(d: dict[str, Any], path: list[str], value: Any) -> None:
    for key in path[:-1]:
        nxt = d.get(key)
        nxt = d[key] = dict(nxt) if isinstance(nxt, dict) else {}
        d = nxt
    d[path[-1]] = value


def _set_seed(d: dict[str, Any], seed: Any, source: str) -> None:
    drawn = False
    for table in ("tasks", "orders", "humans"):
        if isinstance(d.get(table), dict):
            d[table] = {**d[table], "seed": seed}
            drawn = True
    if not drawn:
        raise InputError(f"{source}: axis seed: the scenario draws nothing at random (no random tasks, orders or "
                         "people)")


def load_spec(path: str | os.PathLike[str]) -> Spec:
    """Reads and checks a spec file."""
    p = Path(path)
    text = read_input(p, InputError, "sweep spec")
    data = load_toml(text, str(p), InputError)
    return parse_spec(data, source=str(p), folder=p.parent)


def parse_spec(data: Mapping[str, Any], source: str = "<spec>", folder: Optional[Path] = None) -> Spec:
    """A spec from a dictionary shaped like the file (``multibots.sweep`` accepts either)."""
    known = {"base", "axes", "product", "repeats"}
    for key in data:
        if key not in known:
            raise InputError(f"{source}: unknown key {shown(key)!r} (known: {', '.join(sorted(known))})")
    base_v = data.get("base")
    base: Union[Scenario, lorr_sweep.LorrBase]
    if lorr_sweep.is_lorr_base(base_v):
        base = lorr_sweep.parse_base(base_v, source, folder)
    elif isinstance(base_v, str):
        bp = Path(base_v)
        if not bp.is_absolute() and folder is not None and not bp.exists():
            bp = folder / bp
        base = Scenario.from_toml(bp)
    elif isinstance(base_v, Mapping):
        base = Scenario.from_dict(base_v)
    elif isinstance(base_v, Scenario):
        base = base_v
    else:
        raise InputError(f"{source}: base = {shown(base_v)}: expected a scenario file's path or a [base] table")
    axes_v = data.get("axes")
    if not isinstance(axes_v, Mapping) or not axes_v:
        raise InputError(f"{source}: [axes]: expected at least one axis, such as robots = [2, 4, 6]")
    axes: dict[str, list[Any]] = {}
    for name, values in axes_v.items():
        if not isinstance(name, str) or not name or any(not part for part in name.split(".")):
            raise InputError(f"{source}: axes: {shown(name)!r} is not a field path such as robot.threshold")
        if not isinstance(values, list) or not values:
            raise InputError(f"axes.{shown(name)} = {shown(values)}: expected a non-empty list of values")
        for v in values:
            if isinstance(v, float) and not math.isfinite(v):
                raise InputError(f"axes.{shown(name)} = {shown(v)}: must be a finite number")
        if len({repr(v) for v in values}) != len(values):
            raise InputError(f"axes.{shown(name)}: a value is named twice")
        axes[name] = list(values)
    product = data.get("product", "grid")
    if product not in ("grid", "zip"):
        raise InputError(f"{source}: product = {shown(product)!r}: expected grid or zip")
    if product == "zip" and len({len(v) for v in axes.values()}) > 1:
        lengths = ", ".join(f"{n}: {len(v)}" for n, v in axes.items())
        raise InputError(f"{source}: product = zip needs axes of one length ({lengths})")
    repeats = data.get("repeats", 1)
    if isinstance(repeats, bool) or not isinstance(repeats, int) or not 1 <= repeats <= 100_000:
        raise InputError(f"{source}: repeats = {shown(repeats)}: expected an integer from 1 to 100000")
    spec = Spec(base=base, axes=axes, product=product, repeats=repeats, source=source)
    if repeats > 1 and "seed" not in axes and isinstance(base, Scenario):
        _set_seed(base.to_dict(), 1, f"{source}: repeats = {repeats}")
    return spec
