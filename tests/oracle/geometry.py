"""The paper layout's geometry, computed here from the spec's formulas (docs/model.md section 1),
independently of the engine, so that tests can check the engine's routes against it."""

from __future__ import annotations

import math
from collections import deque

LETTERS = "ABCDEFGHIJKLMNOPQR"

# Out-neighbours in expansion order: the spec's table.
OUT = {
    "A": "B", "B": "CH", "C": "D", "D": "EJ", "E": "F", "F": "L",
    "G": "HA", "H": "IN", "I": "JC", "J": "KP", "K": "LE", "L": "R",
    "M": "G", "N": "M", "O": "NI", "P": "O", "Q": "PK", "R": "Q",
}


def node_xy(name: str) -> tuple[float, float]:
    i = LETTERS.index(name)
    m, k = divmod(i, 6)
    return 25.0 + 150 * k, 25.0 + 250 * m


def charger_xy(k: int) -> tuple[float, float]:
    return 25.0 + 150 * k, -15.0


def bfs_path(start: str, goal: str) -> list[str]:
    """Algorithm 1: breadth-first over simple paths, expanding in table order."""
    queue = deque([[start]])
    while queue:
        path = queue.popleft()
        if path[-1] == goal:
            return path
        for nxt in OUT[path[-1]]:
            if nxt not in path:
                queue.append(path + [nxt])
    raise AssertionError(f"no path {start} -> {goal}")


def dist(a: tuple[float, float], b: tuple[float, float]) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])


def path_length(nodes: list[str]) -> float:
    return sum(dist(node_xy(a), node_xy(b)) for a, b in zip(nodes, nodes[1:]))


def cell(cell_id: int) -> dict:
    """Group, row, column, service point and service edge of a cell (spec section 1)."""
    g, rest = divmod(cell_id, 8)
    b, a = divmod(rest, 2)
    c, r = divmod(g, 2)
    k = c + a
    service = (25.0 + 150 * (c + a), 75.0 + 250 * r + 50 * b)
    upper, lower = LETTERS[6 * r + k], LETTERS[6 * (r + 1) + k]
    # Vertical aisles 0, 2, 4 run north; 1, 3, 5 run south.
    edge = (lower, upper) if k % 2 == 0 else (upper, lower)
    return {"service": service, "edge": edge, "centre": (75.0 + 150 * c + 50 * a, 75.0 + 250 * r + 50 * b)}


def single_robot_legs(cell_id: int, start: str = "A", unload: str = "M") -> tuple[float, float, float]:
    """D1 (charger to service point), D2 (service point to unloading zone), D3 (back home)."""
    k = LETTERS.index(start)
    home = charger_xy(k)
    info = cell(cell_id)
    u, v = info["edge"]
    sp = info["service"]
    d1 = dist(home, node_xy(start)) + path_length(bfs_path(start, u)) + dist(node_xy(u), sp)
    d2 = dist(sp, node_xy(v)) + path_length(bfs_path(v, unload))
    d3 = path_length(bfs_path(unload, start)) + dist(node_xy(start), home)
    return d1, d2, d3


def formula_t(cell_id: int, start: str = "A", unload: str = "M") -> int:
    d1, d2, d3 = single_robot_legs(cell_id, start, unload)
    return math.ceil(d1 / 4) + 10 + math.ceil(d2 / 4) + 20 + math.ceil(d3 / 4)
