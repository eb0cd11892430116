"""Task-allocation strategies: the :class:`Allocator` base class and the built-ins' names.

A strategy decides which idle robot fetches which open goods. The engine calls it at
allocation events only (robots became idle, goods joined the queue), never every step.
Write one in a few lines, either as a subclass::

    class Closest(multibots.Allocator):
        name = "closest"

        def allocate(self, view):
            lengths = view.route_lengths()          # (idle, goods) route lengths, px
            out, taken = {}, set()
            for i, robot in enumerate(view.idle):
                free = [j for j in range(len(view.goods)) if j not in taken]
                if free:
                    j = min(free, key=lambda j: lengths[i, j])
                    taken.add(j)
                    out[int(robot)] = int(view.goods[j])
            return out

or as a plain function ``f(view) -> {robot: goods}`` (or a list of ``(robot, goods)``
pairs), and pass it as ``simulate(scenario, allocator=...)``; a scenario file or the command
line can name it as ``allocator = "package.module:Class"`` (importable, or a module in the
current folder) or ``"path/to/file.py:Class"`` (:func:`load_strategy`). The view's fields are
listed in ``docs/strategies.md`` and on :class:`AllocView`.
"""

from __future__ import annotations

import re
from typing import Any, Union

from multibots import _core
from multibots.strategies.loading import is_python_allocator, load_strategy, strategy_labels, strategy_source

__all__ = ["Allocator", "AllocView", "BUILT_INS", "Answer", "is_python_allocator", "load_strategy", "strategy_labels",
           "strategy_source"]

#: The built-in strategies, by the names TOML, the command line and Python share.
BUILT_INS: tuple[str, ...] = tuple(_core.BUILT_INS)

#: What the engine hands a strategy: read-only, valid only during the ``allocate`` call.
#:
#: Arrays (NumPy, read-only): ``idle`` (idle robot ids, ascending), ``goods`` (open goods ids,
#: queue order), ``goods_cells`` (their cells), ``positions`` (N, 2), ``energy`` (N,),
#: ``states`` (N,) state codes (names in :data:`multibots.STATE_NAMES`), ``homes`` (N,) home
#: charger node ids, ``task_cells`` (N,) the cell each robot fetches or carries, or -1.
#: Numbers: ``step``, ``robot_count``, ``energy_full``, ``threshold``, ``consumption``,
#: ``charge_rate``, ``speed``, ``loading``, ``unloading``, ``unload`` (node id),
#: ``cost_weights`` (w_d, w_t, w_c). Methods: ``route_length(robot, cell)``,
#: ``route_lengths()`` (idle × goods array), ``cell_to_unload(cell)``,
#: ``unload_to_home(robot)``, ``remaining_length(robot)``, ``traffic(robot, cell)``,
#: ``task_steps(robot, cell)``, ``energy_after(robot, cell)``.
AllocView = _core.AllocView

#: What ``allocate`` returns: ``{robot: goods}``, pairs ``[(robot, goods), ...]`` or None.
Answer = Union[dict[int, int], list[tuple[int, int]], None]


def _kebab(name: str) -> str:
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "-", name).lower()


class Allocator:
    """Base class of a task-allocation strategy written in Python.

    Subclasses set ``name`` (kebab-case; the class name, kebab-cased, if not set) and
    implement :meth:`allocate`. The engine validates the answer: a robot that is not idle,
    goods handed out twice or an unknown id raise :class:`multibots.AllocatorError` naming
    the strategy; an exception raised inside ``allocate`` surfaces the same way, with the
    original exception as its ``__cause__``.
    """

    name: str = ""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if not cls.__dict__.get("name"):
            cls.name = _kebab(cls.__name__)

    def allocate(self, view: AllocView) -> Answer:
        """Returns the assignments for this event: robot id → goods id (not cell id).

        Robots left out stay idle until the next allocation event (or, when no goods are
        open, go home to park).
        """
        raise NotImplementedError(f"{type(self).__name__}.allocate(view) is not implemented")

    def __repr__(self) -> str:
        return f"<Allocator {self.name!r}>"

