"""The paper's experiment (section IV): five task lists of ten goods, N = 1..6 robots."""

from __future__ import annotations

from multibots import _core

__all__ = ["PAPER_TASKS", "PAPER_ROBOTS"]

#: TABLE III of the paper: the goods of each group (numbered from 1), fetched in this order.
#: The engine's own copy (``scenario::PAPER_TASKS``).
PAPER_TASKS: dict[int, tuple[int, ...]] = {g: tuple(cells) for g, cells in enumerate(_core.PAPER_TASKS, start=1)}

#: Fleet sizes of the experiment.
PAPER_ROBOTS: tuple[int, ...] = (1, 2, 3, 4, 5, 6)
