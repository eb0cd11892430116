"""Strategies written the way a user would, imported by name in the tests."""

import multibots


class Closest(multibots.Allocator):
    """Each idle robot, in id order, takes the open goods nearest to it."""

    name = "closest"

    def allocate(self, view):
        lengths = view.route_lengths()
        out, taken = {}, set()
        for i, robot in enumerate(view.idle):
            free = [j for j in range(len(view.goods)) if j not in taken]
            if not free:
                break
            j = min(free, key=lambda j: (lengths[i, j], j))
            taken.add(j)
            out[int(robot)] = int(view.goods[j])
        return out


class InTurnPy(multibots.Allocator):
    """The paper's rule in Python: must give exactly the engine's in-turn results."""

    def allocate(self, view):
        return list(zip(view.idle.tolist(), view.goods.tolist()))


class NeedsArgument(multibots.Allocator):
    """Cannot be built from a scenario file: its constructor needs an argument."""

    def __init__(self, k):
        self.k = k
