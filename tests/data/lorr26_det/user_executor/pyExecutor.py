"""Deterministic test executor (MultiBots LoRR-2026 end-to-end golden; not from the Start-Kit).
Stages every non-W/NA plan action (queue capped at 8), predicts by replaying the staged queue from
the true state, and says GO to every agent with something staged. An agent whose true (cell,
heading) did not change since the previous plan gets its queue cleared and this plan dropped (the
Start-Kit only accepts a prefix of old queue + plan: clearing and then appending is refused)."""
import MAPF

MAX_STAGED = 8

class pyExecutor:
    def __init__(self):
        self.env = None

    def initialize(self, preprocess_time_limit: int):
        c = self.env.cols
        self.delta = [1, c, -1, -c]
        self.last = [None] * self.env.num_of_agents

    def process_new_plan(self, sync_time_limit: int, plan, staged_actions) -> list:
        for i in range(len(plan.actions)):
            q = staged_actions[i]
            s = self.env.system_states[i]
            now = (s.location, s.orientation)
            stuck = now == self.last[i] and len(q) > 0
            self.last[i] = now
            if stuck:
                del q[:]
                continue
            for a in plan.actions[i]:
                if a != MAPF.Action.W and a != MAPF.Action.NA:
                    q.append(a)
            if len(q) > MAX_STAGED:
                del q[MAX_STAGED:]
        pred = []
        for i in range(self.env.num_of_agents):
            s = self.env.system_states[i]
            loc, ori = s.location, s.orientation
            for a in staged_actions[i]:
                if a == MAPF.Action.FW:
                    loc += self.delta[ori]
                elif a == MAPF.Action.CR:
                    ori = (ori + 1) % 4
                elif a == MAPF.Action.CCR:
                    ori = (ori + 3) % 4
            pred.append(MAPF.State(loc, -1, ori))
        return pred

    def next_command(self, exec_time_limit: int) -> list:
        st = self.env.staged_actions
        return [MAPF.ExecutionCommand.GO if len(st[i]) > 0 else MAPF.ExecutionCommand.STOP
                for i in range(self.env.num_of_agents)]
