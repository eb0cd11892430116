"""Deterministic test planner (MultiBots LoRR-2026 end-to-end golden; not from the Start-Kit).
Per agent: greedy multi-step walk toward goal_locations[i][0] on BFS distances (one BFS per goal
cell, cached): among the free neighbour cells (E,S,W,N order) pick the one with the smallest
distance to the goal that is closer than the current cell; turn toward it (CR, CCR, or CR for a U-turn) or go F. No collision avoidance:
the Start-Kit's action model resolves conflicts. An agent whose true cell has not changed for two
calls or more takes, as its first step, the (stuck % k)-th free neighbour in (distance, E/S/W/N)
order instead, to break deadlocks deterministically."""
import MAPF

class pyMAPFPlanner:
    def __init__(self):
        self.env = None

    def initialize(self, preprocess_time_limit: int):
        self.cols = self.env.cols
        self.rows = self.env.rows
        self.free = [v == 0 for v in self.env.map]
        self.last = [-1] * self.env.num_of_agents
        self.stuck = [0] * self.env.num_of_agents
        self.cache = {}

    def _detour(self, loc, ori, k):
        cols, rows = self.cols, self.rows
        r, c = divmod(loc, cols)
        cand = []
        for d, (dr, dc) in enumerate(((0, 1), (1, 0), (0, -1), (-1, 0))):
            nr, nc = r + dr, c + dc
            if 0 <= nr < rows and 0 <= nc < cols and self.free[nr * cols + nc]:
                cand.append(d)
        if not cand:
            return MAPF.Action.W, loc, ori
        d = cand[k % len(cand)]
        if d == ori:
            dr, dc = ((0, 1), (1, 0), (0, -1), (-1, 0))[ori]
            return MAPF.Action.FW, (r + dr) * cols + (c + dc), ori
        if d == (ori + 3) % 4:
            return MAPF.Action.CCR, loc, d
        return MAPF.Action.CR, loc, (ori + 1) % 4

    def _dist(self, goal):
        d = self.cache.get(goal)
        if d is None:
            cols, rows, free = self.cols, self.rows, self.free
            d = [-1] * (cols * rows)
            d[goal] = 0
            q = [goal]
            for v in q:
                r, c = divmod(v, cols)
                nd = d[v] + 1
                if c + 1 < cols and free[v + 1] and d[v + 1] < 0: d[v + 1] = nd; q.append(v + 1)
                if r + 1 < rows and free[v + cols] and d[v + cols] < 0: d[v + cols] = nd; q.append(v + cols)
                if c > 0 and free[v - 1] and d[v - 1] < 0: d[v - 1] = nd; q.append(v - 1)
                if r > 0 and free[v - cols] and d[v - cols] < 0: d[v - cols] = nd; q.append(v - cols)
            self.cache[goal] = d
        return d

    def _step(self, loc, ori, goal):
        cols, rows = self.cols, self.rows
        r, c = divmod(loc, cols)
        dist_to = self._dist(goal)
        here = dist_to[loc] if dist_to[loc] >= 0 else 1 << 30
        best, best_d = None, here
        for d, (dr, dc) in enumerate(((0, 1), (1, 0), (0, -1), (-1, 0))):
            nr, nc = r + dr, c + dc
            if 0 <= nr < rows and 0 <= nc < cols and self.free[nr * cols + nc]:
                dist = dist_to[nr * cols + nc]
                if 0 <= dist < best_d:
                    best, best_d = d, dist
        if best is None:
            return MAPF.Action.W, loc, ori
        if best == ori:
            dr, dc = ((0, 1), (1, 0), (0, -1), (-1, 0))[ori]
            return MAPF.Action.FW, (r + dr) * cols + (c + dc), ori
        if best == (ori + 3) % 4:
            return MAPF.Action.CCR, loc, best
        return MAPF.Action.CR, loc, (ori + 1) % 4

    def plan(self, time_limit: int) -> list:
        env = self.env
        steps = env.min_planner_communication_time // (env.action_time * env.max_counter) + 1
        out = []
        for i in range(env.num_of_agents):
            goals = env.goal_locations[i]
            if not goals:
                out.append([MAPF.Action.W])
                continue
            goal = MAPF.pair_first(goals[0])
            true_loc = env.system_states[i].location
            self.stuck[i] = self.stuck[i] + 1 if true_loc == self.last[i] else 0
            self.last[i] = true_loc
            s = env.curr_states[i]
            loc, ori = s.location, s.orientation
            if not 0 <= loc < self.rows * self.cols:     # the executor's prediction can leave the map
                out.append([MAPF.Action.W])
                continue
            acts = []
            if self.stuck[i] >= 2 and loc != goal:
                a, loc, ori = self._detour(loc, ori, self.stuck[i])
                if a != MAPF.Action.W:
                    acts.append(a)
            for _ in range(steps):
                if loc == goal:
                    break
                a, loc, ori = self._step(loc, ori, goal)
                if a == MAPF.Action.W:
                    break
                acts.append(a)
            out.append(acts if acts else [MAPF.Action.W])
        return out
