"""MultiBots: warehouse robot fleets, simulated with the MultiBots paper's model (ROBIO 2017).

Example:
    >>> import multibots
    >>> r = multibots.simulate(multibots.Scenario.paper(robots=3, goods=[11, 8, 39, 28]))
    >>> r.outcome
    'complete'
"""

from multibots.exceptions import AllocatorError, EngineError, LayoutError, MultibotsError, ScenarioError
from multibots.paper import PAPER_ROBOTS, PAPER_TASKS
from multibots.replay import Replay, ReplayError
from multibots.result import STATE_NAMES, Result
from multibots.scenario import Scenario
from multibots.simulation import Simulation, layout_json, simulate, simulate_many
from multibots.strategies import Allocator

__all__ = [
    "Allocator",
    "AllocatorError",
    "EngineError",
    "LayoutError",
    "MultibotsError",
    "PAPER_ROBOTS",
    "PAPER_TASKS",
    "Replay",
    "ReplayError",
    "Result",
    "STATE_NAMES",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "layout_json",
    "simulate",
    "simulate_many",
]

__version__ = "0.1.0"
