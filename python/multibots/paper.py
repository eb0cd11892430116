"""The paper's experiment (section IV): five task lists of ten goods, N = 1..6 robots."""

from __future__ import annotations

__all__ = ["PAPER_TASKS", "PAPER_ROBOTS"]

#: TABLE III of the paper: the goods of each group, fetched in this order.
PAPER_TASKS: dict[int, tuple[int, ...]] = {
    1: (11, 8, 39, 28, 53, 1, 69, 42, 79, 6),
    2: (74, 50, 62, 15, 49, 34, 14, 72, 31, 37),
    3: (68, 79, 56, 47, 48, 75, 23, 50, 76, 16),
    4: (59, 6, 74, 2, 67, 49, 53, 28, 25, 79),
    5: (14, 65, 41, 75, 22, 36, 54, 74, 9, 48),
}

#: Fleet sizes of the experiment.
PAPER_ROBOTS: tuple[int, ...] = (1, 2, 3, 4, 5, 6)
