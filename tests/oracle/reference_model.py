"""A plain, pure-Python reference implementation of the MultiBots "paper" model.

This file follows docs/model.md (the specification) line by line. It is written to be
read, not to be fast: it uses only the standard library, plain lists and dicts, and no
tricks. It serves two purposes:

* a cross-check of the Rust engine: both must give identical T, S and C;
* the baseline that benchmarks compare the engine's speed against.

Usage (with ``tests/`` on ``sys.path``, as pytest and the benchmarks put it)::

    from oracle.reference_model import run
    result = run([11, 8, 39], robots=3)   # -> dict with T, S, C, outcome, ...

Running the file (``python tests/oracle/reference_model.py``) prints the paper's 30-run table
(N = 1..6 robots x five task lists).
"""

import math
from collections import deque

# ---------------------------------------------------------------------------------------
# 1. Layout "paper"
# ---------------------------------------------------------------------------------------

LETTERS = "ABCDEFGHIJKLMNOPQR"
NUM_HIGHWAY_NODES = 18
NUM_CHARGERS = 6

# Node ids: 0..17 are the highway nodes A..R, 18..23 the chargers CH0..CH5.
NODE_NAMES = list(LETTERS) + ["CH%d" % k for k in range(NUM_CHARGERS)]


def node_id(name):
    """Node id from a letter ("A".."R") or a charger name ("CH0".."CH5")."""
    return NODE_NAMES.index(name)


def charger_id(k):
    return NUM_HIGHWAY_NODES + k


NODE_XY = []
for _m in range(3):
    for _k in range(6):
        NODE_XY.append((25.0 + 150.0 * _k, 25.0 + 250.0 * _m))
for _k in range(NUM_CHARGERS):
    NODE_XY.append((25.0 + 150.0 * _k, -15.0))

# Out-neighbours in the order a search expands them (the table of section 1), then the
# spur down/up to the charger for the top-row nodes, and the spur out of each charger.
_OUT_TABLE = {
    "A": "B", "B": "CH", "C": "D", "D": "EJ", "E": "F", "F": "L",
    "G": "HA", "H": "IN", "I": "JC", "J": "KP", "K": "LE", "L": "R",
    "M": "G", "N": "M", "O": "NI", "P": "O", "Q": "PK", "R": "Q",
}
OUT = {}
for _name, _outs in _OUT_TABLE.items():
    OUT[node_id(_name)] = [node_id(_c) for _c in _outs]
for _k in range(NUM_CHARGERS):
    OUT[_k].append(charger_id(_k))      # top-row node (0, k) -> CHk, after the highway edges
    OUT[charger_id(_k)] = [_k]          # CHk -> node (0, k)

DEPARTURE_ZONES = "ABCDEF"
UNLOADING_ZONES = "MNOPQR"


def cell_service_point(cell):
    """Return ((x, y), (u, v)): a cell's service point and the directed edge u->v it is on."""
    g = cell // 8
    c = g // 2
    r = g % 2
    b = (cell % 8) // 2
    a = cell % 2
    k = c + a
    point = (25.0 + 150.0 * k, 75.0 + 250.0 * r + 50.0 * b)
    upper = 6 * r + k            # node (r, k)
    lower = 6 * (r + 1) + k      # node (r + 1, k)
    if k % 2 == 0:               # aisles 0, 2, 4 run north
        edge = (lower, upper)
    else:                        # aisles 1, 3, 5 run south
        edge = (upper, lower)
    return point, edge


# ---------------------------------------------------------------------------------------
# 3. Paths
# ---------------------------------------------------------------------------------------

_PATH_CACHE = {}


def node_path(start, goal):
    """The first path a breadth-first search over simple paths finds (paper Algorithm 1)."""
    key = (start, goal)
    if key in _PATH_CACHE:
        return _PATH_CACHE[key]
    queue = deque()
    queue.append([start])
    found = None
    while queue:
        path = queue.popleft()
        last = path[-1]
        if last == goal:
            found = path
            break
        for nxt in OUT[last]:
            if nxt not in path:
                queue.append(path + [nxt])
    if found is None:
        raise RuntimeError("no path from %s to %s" % (NODE_NAMES[start], NODE_NAMES[goal]))
    _PATH_CACHE[key] = found
    return found


# A location is ("node", node_id) or ("edge", (u, v)) meaning strictly inside edge u->v.
# A target is ("node", node_id) (an unloading node or a charger) or
# ("point", (x, y), (u, v)) (a service point on edge u->v).


def _segment_edge(loc_a, loc_b):
    """The directed edge that the segment between two consecutive waypoints lies on."""
    if loc_a[0] == "edge":
        return loc_a[1]
    if loc_b[0] == "edge":
        return loc_b[1]
    return (loc_a[1], loc_b[1])


def _strictly_ahead(edge, pos, point):
    """Is point strictly ahead of pos along the directed edge u->v?"""
    u, v = edge
    ux, uy = NODE_XY[u]
    vx, vy = NODE_XY[v]
    dx = vx - ux
    dy = vy - uy
    s_pos = (pos[0] - ux) * dx + (pos[1] - uy) * dy
    s_pt = (point[0] - ux) * dx + (point[1] - uy) * dy
    return s_pt > s_pos


def make_route(pos, loc, target):
    """Waypoints, their locations and segment edges of the route from pos/loc to target."""
    points = [pos]
    locs = [loc]

    if target[0] == "node":
        target_xy = NODE_XY[target[1]]
    else:
        target_xy = target[1]
    if pos == target_xy:                      # already standing at the target
        return points, locs, []

    if loc[0] == "node":
        start = loc[1]
    else:
        edge = loc[1]
        if target[0] == "point" and target[2] == edge and _strictly_ahead(edge, pos, target[1]):
            points.append(target[1])
            locs.append(("edge", edge))
            return points, locs, [edge]
        start = edge[1]
        points.append(NODE_XY[start])
        locs.append(("node", start))

    if target[0] == "node":
        for n in node_path(start, target[1])[1:]:
            points.append(NODE_XY[n])
            locs.append(("node", n))
    else:
        point, edge = target[1], target[2]
        for n in node_path(start, edge[0])[1:]:
            points.append(NODE_XY[n])
            locs.append(("node", n))
        points.append(point)
        locs.append(("edge", edge))

    seg_edges = []
    for i in range(len(points) - 1):
        seg_edges.append(_segment_edge(locs[i], locs[i + 1]))
    return points, locs, seg_edges


def route_length(points):
    total = 0.0
    for i in range(len(points) - 1):
        dx = points[i + 1][0] - points[i][0]
        dy = points[i + 1][1] - points[i][1]
        total += math.sqrt(dx * dx + dy * dy)
    return total


# ---------------------------------------------------------------------------------------
# 2. Robots
# ---------------------------------------------------------------------------------------

IDLE = "IDLE"
TO_PICKUP = "TO_PICKUP"
LOADING = "LOADING"
TO_DROP = "TO_DROP"
UNLOADING = "UNLOADING"
TO_CHARGER = "TO_CHARGER"
CHARGING = "CHARGING"
TO_HOME = "TO_HOME"
PARKED = "PARKED"
STRANDED = "STRANDED"

MOVING_STATES = (TO_PICKUP, TO_DROP, TO_CHARGER, TO_HOME)
EPS = 1e-9


class Robot:
    def __init__(self, rid, start_node, energy):
        self.id = rid
        self.home = charger_id(start_node)     # the charger joined to its start node
        self.x, self.y = NODE_XY[self.home]
        self.loc = ("node", self.home)
        self.state = IDLE
        self.energy = energy
        self.goods = None                        # cell being fetched or carried
        self.route = [(self.x, self.y)]
        self.route_locs = [self.loc]
        self.route_edges = []
        self.next_wp = 1                         # index of the next waypoint
        self.dwell = 0
        self.marked = False                      # marked to charge after unloading
        self.waited = False
        # statistics
        self.distance = 0.0
        self.wait_steps = 0
        self.charges = 0
        self.delivered = 0

    def set_route(self, target):
        pos = (self.x, self.y)
        self.route, self.route_locs, self.route_edges = make_route(pos, self.loc, target)
        self.next_wp = 1

    def route_finished(self):
        return self.next_wp >= len(self.route)

    def at_home(self):
        return (self.x, self.y) == NODE_XY[self.home]

    def move(self, speed):
        remaining = speed
        while remaining > 0 and self.next_wp < len(self.route):
            tx, ty = self.route[self.next_wp]
            dx = tx - self.x
            dy = ty - self.y
            d = math.sqrt(dx * dx + dy * dy)
            if remaining >= d:
                self.x, self.y = tx, ty
                self.distance += d
                remaining -= d
                self.loc = self.route_locs[self.next_wp]
                self.next_wp += 1
            else:
                self.x = self.x + dx / d * remaining
                self.y = self.y + dy / d * remaining
                self.distance += remaining
                self.loc = ("edge", self.route_edges[self.next_wp - 1])
                remaining = 0


# ---------------------------------------------------------------------------------------
# Blocking helpers (phase 3)
# ---------------------------------------------------------------------------------------


def _reachable(graph, start):
    seen = set([start])
    stack = [start]
    while stack:
        i = stack.pop()
        for j in graph[i]:
            if j not in seen:
                seen.add(j)
                stack.append(j)
    return seen


def _released_robots(blocked_by, n):
    """Smallest id of each strongly connected component of two or more robots."""
    reach = [_reachable(blocked_by, i) for i in range(n)]
    released = set()
    for i in range(n):
        component = [j for j in range(n) if j in reach[i] and i in reach[j]]
        if len(component) >= 2:
            released.add(min(component))
    return released


# ---------------------------------------------------------------------------------------
# The simulation
# ---------------------------------------------------------------------------------------


def _parse_node(value, allowed, what):
    if isinstance(value, str) and value in allowed:
        return node_id(value)
    raise ValueError("%s must be one of %s, got %r" % (what, ", ".join(allowed), value))


def run(goods, robots=3, starts=None, unload="M", margin=0.0, step_limit=100000,
        radius=12.5, speed=4.0, energy_full=10.0, threshold=3.5, consumption=0.005,
        charge_rate=0.05, loading_steps=10, unloading_steps=20, angle_deg=30.0,
        gridlock=2000, trace=None):
    """Run one scenario of the paper model and return its indicators as a dict.

    A run ends complete; or ``stranded`` the step every robot has run out of energy with
    work left; or, after ``gridlock`` steps in a row in which no robot moved, dwelt or
    charged while work was left, ``gridlock`` (robots wait at collisions), ``stranded``
    (some robot is stranded) or ``stalled``; or ``livelock`` after two battery cycles
    (``2 * (energy_full / consumption + energy_full / charge_rate)`` steps, rounded up) without a
    pickup or a delivery while work was left; or ``incomplete`` at the step limit.

    If ``trace`` is a list, one entry is appended after every step (for debugging):
    ``(t, S, C, delivered, [(x, y, state, marked, energy) for each robot])``.
    """
    # --- validation -------------------------------------------------------------------
    goods = list(goods)
    if robots < 1:
        raise ValueError("need at least one robot, got %d" % robots)
    if starts is None:
        starts = list(DEPARTURE_ZONES)
    starts = list(starts)
    if robots > len(starts):
        raise ValueError("%d robots but only %d start nodes" % (robots, len(starts)))
    start_nodes = [_parse_node(s, DEPARTURE_ZONES, "a start node") for s in starts[:robots]]
    if len(set(start_nodes)) != len(start_nodes):
        raise ValueError("start nodes must be distinct, got %r" % (starts[:robots],))
    unload_node = _parse_node(unload, UNLOADING_ZONES, "the unloading node")
    if not goods:
        raise ValueError("the task list is empty")
    for cell in goods:
        if isinstance(cell, bool) or int(cell) != cell or cell < 0 or cell > 79:
            raise ValueError("cell id %r outside 0..79" % (cell,))
    goods = [int(cell) for cell in goods]
    if len(set(goods)) != len(goods):
        raise ValueError("the task list names a cell twice")

    # --- set-up -----------------------------------------------------------------------
    fleet = [Robot(i, start_nodes[i], energy_full) for i in range(robots)]
    queue = list(goods)                 # goods not yet taken, in order
    delivered = 0
    S = 0
    C = 0
    T = None
    contact = radius + radius + margin
    max_angle = math.radians(angle_deg)
    unload_target = ("node", unload_node)
    t = 0
    outcome = "incomplete"
    stalled = 0
    last_work = 0       # the last step goods were picked up or delivered
    livelock_after = math.ceil(2.0 * (energy_full / consumption + energy_full / charge_rate)) if gridlock else 0

    while t < step_limit:
        t += 1
        progress = False

        # 1. Allocate
        for r in fleet:
            if r.state == IDLE:
                if queue:
                    r.goods = queue.pop(0)
                    point, edge = cell_service_point(r.goods)
                    r.state = TO_PICKUP
                    r.set_route(("point", point, edge))
                else:
                    r.state = TO_HOME
                    r.set_route(("node", r.home))

        # 2. Intend
        wants = []
        heading = []
        for r in fleet:
            if r.state in MOVING_STATES and not r.route_finished():
                wants.append(True)
                tx, ty = r.route[r.next_wp]
                heading.append(math.atan2(ty - r.y, tx - r.x))
            else:
                wants.append(False)
                heading.append(0.0)

        # 3. Block
        blocked_by = []
        for i in range(robots):
            blockers = []
            if wants[i]:
                ri = fleet[i]
                for j in range(robots):
                    if j == i:
                        continue
                    rj = fleet[j]
                    dx = rj.x - ri.x
                    dy = rj.y - ri.y
                    dist = math.sqrt(dx * dx + dy * dy)
                    if dist <= contact:
                        if dist == 0:
                            blockers.append(j)
                        else:
                            beta = math.atan2(dy, dx)
                            d = math.fmod(abs(heading[i] - beta), 2 * math.pi)
                            if d > math.pi:
                                d = 2 * math.pi - d
                            if d < max_angle:
                                blockers.append(j)
            blocked_by.append(blockers)
        released = _released_robots(blocked_by, robots)
        waits = []
        for i in range(robots):
            waits.append(len(blocked_by[i]) > 0 and i not in released)
        for i in range(robots):
            r = fleet[i]
            if waits[i]:
                r.wait_steps += 1
                if not r.waited:
                    S += 1
            r.waited = waits[i]

        # 4. Move
        for i in range(robots):
            if wants[i] and not waits[i]:
                fleet[i].move(speed)
                progress = True

        # 5. Dwell
        for r in fleet:
            if r.state == LOADING or r.state == UNLOADING:
                r.dwell += 1
                progress = True
            elif r.state == CHARGING:
                r.energy = min(energy_full, r.energy + charge_rate)
                progress = True

        # 6. Consume
        for r in fleet:
            if r.state != CHARGING and r.state != PARKED and r.state != STRANDED:
                r.energy = max(0.0, r.energy - consumption)

        # 7. Transitions
        for r in fleet:
            state = r.state
            if state in MOVING_STATES and r.route_finished():
                if state == TO_PICKUP:
                    r.state = LOADING
                    r.dwell = 0
                elif state == TO_DROP:
                    r.state = UNLOADING
                    r.dwell = 0
                elif state == TO_CHARGER:
                    r.state = CHARGING
                    C += 1
                    r.charges += 1
                else:
                    r.state = PARKED
            elif state == LOADING and r.dwell >= loading_steps:
                last_work = t
                r.state = TO_DROP           # the cell becomes empty
                r.set_route(unload_target)
            elif state == UNLOADING and r.dwell >= unloading_steps:
                last_work = t
                delivered += 1
                r.delivered += 1
                r.goods = None
                if r.marked:
                    r.marked = False
                    r.state = TO_CHARGER
                    r.set_route(("node", r.home))
                else:
                    r.state = IDLE
            elif state == CHARGING and r.energy >= energy_full - EPS:
                r.state = IDLE

            # threshold rule
            if r.energy < threshold - EPS:
                if r.state == IDLE:
                    r.state = TO_CHARGER
                    r.set_route(("node", r.home))
                elif r.state == TO_PICKUP:
                    point, edge = cell_service_point(r.goods)
                    if r.loc == ("edge", edge):
                        r.marked = True
                    else:
                        queue.insert(0, r.goods)
                        r.goods = None
                        r.state = TO_CHARGER
                        r.set_route(("node", r.home))
                elif r.state in (LOADING, TO_DROP, UNLOADING):
                    r.marked = True

            # stranding
            if r.state != STRANDED and r.energy <= EPS:
                r.state = STRANDED
                r.energy = 0.0

        if trace is not None:
            trace.append((t, S, C, delivered,
                          [(r.x, r.y, r.state, r.marked, r.energy) for r in fleet]))

        # 8. End
        if delivered == len(goods) and all(r.at_home() for r in fleet):
            T = t
            outcome = "complete"
            break
        if all(r.state == STRANDED for r in fleet):
            outcome = "stranded"
            break
        stalled = 0 if progress else stalled + 1
        if gridlock and stalled >= gridlock:
            if any(waits):
                outcome = "gridlock"
            elif any(r.state == STRANDED for r in fleet):
                outcome = "stranded"
            else:
                outcome = "stalled"
            break
        if livelock_after and t - last_work >= livelock_after:
            outcome = "livelock"
            break

    return {
        "T": T,
        "S": S,
        "C": C,
        "outcome": outcome,
        "steps": t,
        "delivered": delivered,
        "distance": [r.distance for r in fleet],
        "wait_steps": [r.wait_steps for r in fleet],
        "charges": [r.charges for r in fleet],
        "delivered_by_robot": [r.delivered for r in fleet],
        "stranded": [r.id for r in fleet if r.state == STRANDED],
    }


# ---------------------------------------------------------------------------------------
# 5. The paper's experiment
# ---------------------------------------------------------------------------------------

PAPER_GROUPS = {
    1: [11, 8, 39, 28, 53, 1, 69, 42, 79, 6],
    2: [74, 50, 62, 15, 49, 34, 14, 72, 31, 37],
    3: [68, 79, 56, 47, 48, 75, 23, 50, 76, 16],
    4: [59, 6, 74, 2, 67, 49, 53, 28, 25, 79],
    5: [14, 65, 41, 75, 22, 36, 54, 74, 9, 48],
}


def paper_table(margin=0.0):
    """The 30 runs of the paper's experiment: a list of (N, group, result dict)."""
    rows = []
    for n in range(1, 7):
        for group in sorted(PAPER_GROUPS):
            rows.append((n, group, run(PAPER_GROUPS[group], robots=n, margin=margin)))
    return rows


def main(argv=None):
    import argparse

    parser = argparse.ArgumentParser(description="The paper's 30-run table, pure Python.")
    parser.add_argument("--margin", type=float, default=0.0)
    args = parser.parse_args(argv)
    print("%3s %6s %7s %4s %4s" % ("N", "group", "T", "S", "C"))
    for n, group, res in paper_table(args.margin):
        print("%3d %6d %7s %4d %4d" % (n, group, res["T"], res["S"], res["C"]))


if __name__ == "__main__":
    main()
