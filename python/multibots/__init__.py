"""MultiBots: warehouse robot fleets, simulated with the MultiBots paper's model (ROBIO 2017).

Example:
    >>> import multibots
    >>> r = multibots.simulate(multibots.Scenario.paper(robots=3, goods=[11, 8, 39, 28]))
    >>> r.outcome
    'complete'

The submodules (``multibots.plots``, ``multibots.render``, ``multibots.replay``, ...) are
attributes of the package, imported the first time they are used, so that ``import multibots``
stays quick:

    >>> multibots.stats.t_ppf(0.975, 4)
    2.776445105...
"""

from __future__ import annotations

import importlib
from typing import Any

from multibots.exceptions import (
    AllocatorError,
    ArgumentError,
    DecisionError,
    EngineError,
    InputError,
    LayoutError,
    MissingExtraError,
    MultibotsError,
    OutputError,
    RenderError,
    ReplayError,
    ScenarioError,
)
from multibots.paper import PAPER_ROBOTS, PAPER_TASKS
from multibots.replay import Replay
from multibots.result import STATE_NAMES, Result
from multibots.scenario import Scenario
from multibots.simulation import Simulation, layout_json, simulate, simulate_many
from multibots.strategies import Allocator

__all__ = [
    "Allocator",
    "AllocatorError",
    "ArgumentError",
    "DecisionError",
    "EngineError",
    "InputError",
    "LayoutError",
    "MissingExtraError",
    "MultibotsError",
    "OutputError",
    "PAPER_ROBOTS",
    "PAPER_TASKS",
    "RenderError",
    "Replay",
    "ReplayError",
    "Result",
    "STATE_NAMES",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "capacity",
    "layout_json",
    "simulate",
    "simulate_many",
    "sweep",
]

__version__ = "0.1.0"

#: Submodules reachable as attributes of the package, imported on first use.
SUBMODULES: tuple[str, ...] = (
    "cli",
    "envs",
    "exceptions",
    "experiments",
    "layouts",
    "lorr",
    "paper",
    "plots",
    "render",
    "replay",
    "result",
    "scenario",
    "simulation",
    "stats",
    "strategies",
    "sweeps",
    "viewer",
)


def capacity(scenario: Any, *, allocators: Any = None, traffic: Any = None, **kwargs: Any) -> Any:
    """The highest order rate a scenario's warehouse and fleet sustain, with the throughput
    against demand (:func:`multibots.sweeps.capacity.capacity`, docs/capacity.md). Given
    ``allocators`` or ``traffic`` (lists of names), one answer per strategy and policy: a
    list of :class:`multibots.sweeps.capacity.Combination`."""
    from multibots.sweeps.capacity import capacities
    from multibots.sweeps.capacity import capacity as search

    if allocators is not None or traffic is not None:
        return capacities(scenario, allocators, traffic, **kwargs)
    return search(scenario, **kwargs)


def sweep(spec: Any, out: Any, **kwargs: Any) -> Any:
    """Runs a sweep and returns its runs as a polars DataFrame (:func:`multibots.sweeps.sweep`,
    docs/sweeps.md)."""
    from multibots.sweeps import sweep as run

    return run(spec, out, **kwargs)


def __getattr__(name: str) -> Any:
    if name in SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *SUBMODULES})
