"""Running scenarios: all at once with :func:`simulate`, or step by step with :class:`Simulation`."""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from multibots import _args, _core
from multibots._io import check_outputs
from multibots.exceptions import ArgumentError
from multibots.result import Result
from multibots.scenario import Scenario

__all__ = ["Simulation", "check_record", "simulate", "simulate_many", "layout_json"]

#: The most worker threads a batch may ask for.
MAX_WORKERS = 1024


def _scenario(s: Scenario | str | os.PathLike[str], name: str = "scenario") -> Scenario:
    if isinstance(s, Scenario):
        return s
    return Scenario.from_toml(_args.path(name, s))  # type: ignore[arg-type]


def simulate(
    scenario: Scenario | str | os.PathLike[str],
    record: str | os.PathLike[str] | None = None,
    allocator: Any = None,
) -> Result:
    """Runs a scenario to its end.

    Args:
        scenario: a :class:`Scenario`, or the path of a scenario file.
        record: if given, the path of a replay file to write (see ``docs/replay-format.md``).
        allocator: the task-allocation strategy, overriding the scenario's: a built-in's
            name (``"hungarian"``), ``"package.module:Class"``, ``"path/to/file.py:Class"``, a
            :class:`multibots.Allocator` or a function ``f(view)`` (``docs/strategies.md``).

    Example:
        >>> simulate(Scenario.paper(robots=1, goods=[42])).T
        726
    """
    s = _scenario(scenario)
    out = _args.path("record", record, optional=True)
    allocator = _args.allocator("allocator", allocator)
    check_record(s, out)
    return Result(_core.simulate(s._core, None if out is None else os.fspath(out), allocator))


def check_record(scenario: Scenario, record: Path | None, label: str = "record") -> None:
    """Before a run: the replay (``record``, named ``label``) is none of the files the run
    reads (:meth:`Scenario.files`) and can be written.

    Raises:
        OutputError: one line naming the option, the path and the file it would replace.
    """
    check_outputs([(label, record)], scenario.files())


def _built_in_name(allocator: Any) -> bool:
    return isinstance(allocator, str) and ":" not in allocator


def simulate_many(scenarios: Sequence[Scenario], workers: int = 0, allocator: Any = None) -> list[Result]:
    """Runs scenarios in parallel on ``workers`` threads (0: one per core), in order.

    ``allocator`` is as for :func:`simulate`. Built-in strategies run on the engine's threads;
    a Python strategy needs the interpreter, so those runs go one after another.
    """
    scenarios = _args.sequence("scenarios", scenarios, Scenario, "Scenario")
    workers = _args.whole("workers", workers, 0, MAX_WORKERS)
    allocator = _args.allocator("allocator", allocator)
    if allocator is not None and _built_in_name(allocator):
        scenarios = [s.replace(allocator=allocator) for s in scenarios]
        allocator = None
    if allocator is None and all(_built_in_name(s._core.allocator) for s in scenarios):
        return [Result(r) for r in _core.simulate_many([s._core for s in scenarios], workers)]
    return [Result(_core.simulate(s._core, None, allocator)) for s in scenarios]


def layout_json(name: str = "paper") -> dict[str, Any]:
    """The layout JSON (``docs/replay-format.md``) of a named layout."""
    if not isinstance(name, (str, os.PathLike)) or not os.fspath(name):
        raise ArgumentError(f"name: expected \"paper\" or a layout file's path, got {name!r:.60}")
    return json.loads(_core.layout_json(os.fspath(name)))


class Simulation:
    """A run to step through and inspect; enough to drive a viewer or a learning environment.

    Every array is a fresh, read-only copy of the engine's state at the current step.

    Example:
        >>> sim = Simulation(Scenario.paper(robots=2, goods=[11, 8]))
        >>> sim.step(10)
        10
        >>> sim.positions.shape
        (2, 2)
    """

    def __init__(self, scenario: Scenario | str | os.PathLike[str], allocator: Any = None) -> None:
        self.scenario = _scenario(scenario)
        self._sim = _core.Simulation(self.scenario._core, _args.allocator("allocator", allocator))

    def step(self, n: int = 1) -> int:
        """Runs ``n`` steps, fewer if the run ends first; returns how many ran."""
        return self._sim.step(_args.whole("n", n))

    def run(self) -> Result:
        """Runs to the end and returns the result."""
        return Result(self._sim.run())

    def result(self) -> Result:
        """The result so far (outcome "running" until the run ends)."""
        return Result(self._sim.result())

    @staticmethod
    def _frozen(a: np.ndarray) -> np.ndarray:
        a.setflags(write=False)
        return a

    @property
    def t(self) -> int:
        """Steps run so far."""
        return self._sim.t

    @property
    def done(self) -> bool:
        """Whether the run has ended."""
        return self._sim.done

    @property
    def outcome(self) -> str | None:
        """"complete" or "incomplete" once done, else None."""
        return self._sim.outcome

    @property
    def T(self) -> int | None:
        """Task time, once the run has completed."""
        return self._sim.t if self._sim.outcome == "complete" else None

    @property
    def S(self) -> int:
        """Collisions so far."""
        return self._sim.S

    @property
    def C(self) -> int:
        """Charging count so far."""
        return self._sim.C

    @property
    def delivered(self) -> int:
        return self._sim.delivered

    @property
    def goods_total(self) -> int:
        return self._sim.goods_total

    @property
    def robot_count(self) -> int:
        return self._sim.robot_count

    @property
    def energy_full(self) -> float:
        return self._sim.energy_full

    @property
    def threshold(self) -> float:
        return self._sim.threshold

    @property
    def positions(self) -> np.ndarray:
        """(N, 2) robot centres, px, screen coordinates (y down)."""
        return self._frozen(self._sim.positions)

    @property
    def human_positions(self) -> np.ndarray:
        """(P, 2) centres of the people on the floor, px, screen coordinates (``[humans]``,
        docs/people.md); (0, 2) without people."""
        return self._frozen(self._sim.human_positions)

    @property
    def human_radii(self) -> np.ndarray:
        """(P,) radii of the people, px."""
        return self._frozen(self._sim.human_radii)

    @property
    def headings(self) -> np.ndarray:
        """(N,) heading angles, radians, ``atan2(dy, dx)`` in screen coordinates."""
        return self._frozen(self._sim.headings)

    @property
    def states(self) -> np.ndarray:
        """(N,) state codes; names in :data:`multibots.STATE_NAMES`."""
        return self._frozen(self._sim.states)

    @property
    def marked(self) -> np.ndarray:
        """(N,) whether each robot is marked to charge after unloading."""
        return self._frozen(self._sim.marked)

    @property
    def energy(self) -> np.ndarray:
        return self._frozen(self._sim.energy)

    @property
    def radius(self) -> np.ndarray:
        return self._frozen(self._sim.radius)

    @property
    def home(self) -> np.ndarray:
        """(N,) node id of each robot's home charger."""
        return self._frozen(self._sim.home)

    @property
    def carrying(self) -> np.ndarray:
        """(N,) cell each robot carries, or -1."""
        return self._frozen(self._sim.carrying)

    @property
    def task_cells(self) -> np.ndarray:
        """(N,) cell each robot fetches or carries, or -1."""
        return self._frozen(self._sim.task_cells)

    @property
    def cells(self) -> np.ndarray:
        """(cells,) 1 where a storage cell holds goods."""
        return self._frozen(self._sim.cells)

    @property
    def robot_S(self) -> np.ndarray:
        return self._frozen(self._sim.robot_s)

    @property
    def robot_C(self) -> np.ndarray:
        return self._frozen(self._sim.robot_c)

    @property
    def queue(self) -> list[int]:
        """Cells of the goods not yet taken, front first."""
        return self._sim.queue

    @property
    def events(self) -> np.ndarray:
        """(E, 4) events of the last step: step, kind, robot, cell (-1 where none)."""
        return self._frozen(self._sim.events)

    @cached_property
    def layout(self) -> dict[str, Any]:
        """The layout JSON (``docs/replay-format.md``)."""
        return json.loads(self._sim.layout_json)

    def route(self, robot: int) -> np.ndarray:
        """(K, 2) waypoints of a robot's remaining route, starting at its position."""
        return self._frozen(self._sim.route(_args.whole("robot", robot, 0, max(0, self.robot_count - 1))))

    def frame_chunk(self) -> bytes:
        """The current state as one frame of the replay codec (a decompressed one-frame chunk
        numbered by the step, ``docs/replay-format.md``), encoded by the engine."""
        return self._sim.frame_chunk()

    def queues(self) -> tuple[dict[int, int], int]:
        """The robots queued in the last step, counted as the result's ``resources`` count them
        (docs/metrics.md): ``{node: robots}`` for each node with a queue (node ids index
        ``layout["nodes"]``), and the robots queued for a shared charger."""
        nodes, chargers, _ = self._sim.queues()
        return dict(nodes), chargers

    def lane_queues(self) -> dict[tuple[int, int], int]:
        """The robots held in the last step on each lane with a queue, ``{(from, to): robots}``
        (node ids index ``layout["nodes"]``): the part of a crossing's queue that stands on
        the lane leading to it, as the result's ``resources`` count lanes."""
        return {(u, v): c for u, v, c in self._sim.queues()[2]}

    def viewer_header(self) -> dict[str, Any]:
        """What a viewer needs before the first frame: the replay header's fields (fleet,
        energy scale, stock, layout, scenario, state and event names), from the engine."""
        return json.loads(self._sim.viewer_header(self.scenario.to_toml()))

    def __repr__(self) -> str:
        return (
            f"Simulation(t={self.t}, robots={self.robot_count}, S={self.S}, C={self.C}, "
            f"delivered={self.delivered}/{self.goods_total})"
        )
