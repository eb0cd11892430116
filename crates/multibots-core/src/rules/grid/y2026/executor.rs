//! The built-in executor, `tpg`: the order in which robots enter each cell, kept as a queue per
//! cell (a temporal plan graph: Hönig et al. 2016; Ma, Kumar and Koenig 2017, the idea of the
//! Start-Kit's default executor), so that delays only make robots wait, never collide or
//! deadlock.
//!
//! ## What it does
//! When a plan arrives, each robot's next `window` planned actions (waits left out) are staged
//! after its queue, and each forward move adds the robot to the queue of the cell it enters,
//! in the plan's order. Then the next `window` steps are played without delays from where the
//! robots are, a robot entering a cell only when it is first in that cell's queue, and a robot
//! held by a delay not moving at all; each queue of staged actions is cut to what that play
//! carried out (an action under way is always finished), the cell queues are rebuilt from it,
//! and where each robot ends is the prediction the next planner call starts from. So a robot stuck behind a held one keeps no
//! plan through it, and the planner routes it anew from where it stands.
//!
//! Every tick, a robot whose cell changed leaves the front of its old cell's queue; then a
//! robot with nothing staged stops, a turn goes, and a forward move goes when the robot is
//! first in the queue of the cell ahead, or second behind a robot that is already on its way
//! out of it (the squares then slide one behind the other, which the model allows; should the
//! first stop, the model makes the second wait).
//!
//! ## When to use it
//! Always with the built-in planner; with any planner whose plans are free of collisions in
//! steps of one action.
//!
//! ## Cost
//! O(N · window) per plan, O(N) per tick; a queue entry per cell a staged move enters.

use super::entries::{ExecEnv, Executor};
use super::footprint::Pose;
use crate::error::Result;
use crate::rules::grid::action::{ahead, Action};
use std::collections::VecDeque;

/// A queue per cell, found by the cell's number in a table as large as the map (4 bytes a
/// cell), not hashed: on a map of millions of cells a robot's look-up is one read. Emptied,
/// the queues keep their memory for the next cells.
#[derive(Default)]
struct CellQueues {
    /// Per cell, its queue's index plus one (0: no queue).
    slot: Vec<u32>,
    queues: Vec<VecDeque<u32>>,
    /// The cell of each queue in use.
    cells: Vec<u32>,
}

impl CellQueues {
    fn get(&self, cell: u32) -> Option<&VecDeque<u32>> {
        match self.slot.get(cell as usize) {
            Some(&s) if s > 0 => Some(&self.queues[s as usize - 1]),
            _ => None,
        }
    }

    fn get_mut(&mut self, cell: u32) -> Option<&mut VecDeque<u32>> {
        match self.slot.get(cell as usize) {
            Some(&s) if s > 0 => Some(&mut self.queues[s as usize - 1]),
            _ => None,
        }
    }

    /// The cell's queue, made if it has none.
    fn entry(&mut self, cell: u32) -> &mut VecDeque<u32> {
        if self.slot.len() <= cell as usize {
            self.slot.resize(cell as usize + 1, 0);
        }
        if self.slot[cell as usize] == 0 {
            let used = self.cells.len();
            if used == self.queues.len() {
                self.queues.push(VecDeque::new());
            }
            self.cells.push(cell);
            // A queue's index fits: there are fewer queues than cells.
            #[allow(clippy::cast_possible_truncation)]
            {
                self.slot[cell as usize] = used as u32 + 1;
            }
        }
        &mut self.queues[self.slot[cell as usize] as usize - 1]
    }

    /// No queue for any cell (their memory kept).
    fn clear(&mut self) {
        for (k, &c) in self.cells.iter().enumerate() {
            self.slot[c as usize] = 0;
            self.queues[k].clear();
        }
        self.cells.clear();
    }

    /// Every queue emptied, each cell keeping its queue.
    fn empty_all(&mut self) {
        for q in &mut self.queues[..self.cells.len()] {
            q.clear();
        }
    }
}

/// The `tpg` executor's state.
#[derive(Default)]
pub struct Tpg {
    /// Per cell, the robots that will enter it, in order; the front is in it or entering it.
    /// Emptied queues are kept, so that their memory serves again.
    order: CellQueues,
    /// The queues of the last play, emptied, for the next.
    spare: CellQueues,
    /// Each robot's cell when last seen.
    seen: Vec<u32>,
    /// Where each robot's staged actions end.
    tail: Vec<Pose>,
    /// Planned actions staged per plan.
    window: usize,
    /// Actions of the current play, per robot (scratch).
    done: Vec<usize>,
    /// Per robot, a cell whose queue it is known to head (or which has no queue), or
    /// `u32::MAX`: it stays so until the robot moves or the queues are rebuilt, since only
    /// a queue's front leaves it, and only when it moves. A robot on its way into a cell asks
    /// for it every tick of the move; this spares most of those look-ups in `order`, which on
    /// a large fleet is out of cache.
    heads: Vec<u32>,
    /// Scratch of `next_command`: the gates, and `resolve`'s marks and chain.
    gates: Vec<Gate>,
    marks: Vec<u8>,
    chain: Vec<usize>,
}

impl Tpg {
    /// A `tpg` executor.
    #[must_use]
    pub fn new() -> Tpg {
        Tpg::default()
    }

    fn pop_front(&mut self, cell: u32, robot: u32) {
        if let Some(q) = self.order.get_mut(cell) {
            if q.front() == Some(&robot) {
                q.pop_front();
            }
        }
    }
}

/// Actions staged per plan: the plan's actions that fit in one interval between planner
/// calls, and one more.
#[must_use]
pub fn window(interval: u32, counter: u32) -> usize {
    (interval / counter.max(1)) as usize + 1
}

impl Executor for Tpg {
    #[allow(clippy::unnecessary_literal_bound)]
    fn name(&self) -> &str {
        "tpg"
    }

    #[allow(clippy::single_match_else)]
    fn process_new_plan(&mut self, env: &ExecEnv<'_>, plan: &[Vec<Action>], staged: &mut [Vec<Action>], predicted: &mut Vec<Pose>) -> Result<()> {
        let n = env.system.len();
        if self.seen.len() != n {
            self.window = window(env.interval, env.floor.m);
            self.seen = env.system.iter().map(|p| p.loc).collect();
            self.tail = env.system.to_vec();
            self.order.clear();
            for (i, p) in env.system.iter().enumerate() {
                self.order.entry(p.loc).push_back(i as u32);
            }
        }
        // Stage the plan's first actions after each queue, step by step in robot order (the
        // order robots meeting in a cell were planned to enter it).
        let steps = plan.iter().map(|p| p.len().min(self.window)).max().unwrap_or(0);
        let mut stopped = vec![false; n];
        for s in 0..steps {
            for (i, row) in plan.iter().enumerate() {
                let Some(&a) = row.get(s) else { continue };
                if stopped[i] || matches!(a, Action::W | Action::T) {
                    continue;
                }
                let t = &mut self.tail[i];
                if a == Action::F {
                    match ahead(env.map, t.loc, t.heading).filter(|&c| env.map.free[c as usize]) {
                        Some(c) => {
                            t.loc = c;
                            self.order.entry(c).push_back(i as u32);
                        }
                        None => {
                            // Into a wall: nothing after it is staged.
                            stopped[i] = true;
                            continue;
                        }
                    }
                } else {
                    t.heading = a.turned(t.heading);
                }
                staged[i].push(a);
            }
        }
        self.play(env, staged, predicted);
        self.heads.clear();
        self.heads.resize(n, u32::MAX);
        Ok(())
    }

    fn next_command(&mut self, env: &ExecEnv<'_>, staged: &[Vec<Action>], go: &mut [bool]) -> Result<()> {
        if self.heads.len() != env.system.len() {
            self.heads = vec![u32::MAX; env.system.len()];
        }
        for (i, p) in env.system.iter().enumerate() {
            if p.loc != self.seen[i] {
                let was = self.seen[i];
                self.pop_front(was, i as u32);
                self.seen[i] = p.loc;
                self.heads[i] = u32::MAX;
            }
        }
        let Tpg { order, heads, gates, marks, chain, .. } = self;
        gates.clear();
        gates.extend(env.system.iter().enumerate().map(|(i, p)| match staged[i].first() {
            None => Gate::Stop,
            Some(&a) if a != Action::F => Gate::Go,
            Some(_) => ahead(env.map, p.loc, p.heading).map_or(Gate::Go, |c| {
                if heads[i] == c {
                    return Gate::Go;
                }
                let g = gate(order, i as u32, c, |j| env.system[j as usize].loc == c && !env.held[j as usize]);
                if g == Gate::Go {
                    heads[i] = c;
                }
                g
            }),
        }));
        resolve(gates, |j| staged[j as usize].first() == Some(&Action::F), go, marks, chain);
        Ok(())
    }
}

/// Whether a robot may go: yes, no, or if robot `j`, which is in the cell it would enter and
/// first in its queue, leaves it now (the two squares then slide one behind the other).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Gate {
    Go,
    Stop,
    After(u32),
}

/// The gate of robot `i` moving into `c` under the cell queues: first in the queue, or second
/// behind a robot that is in the cell and free to move (`can_leave`).
fn gate(order: &CellQueues, i: u32, c: u32, can_leave: impl Fn(u32) -> bool) -> Gate {
    match order.get(c) {
        None => Gate::Go,
        Some(q) if q.is_empty() || q.front() == Some(&i) => Gate::Go,
        Some(q) if q.get(1) == Some(&i) && can_leave(q[0]) => Gate::After(q[0]),
        Some(_) => Gate::Stop,
    }
}

/// Decides every gate: a robot waiting on another goes if that one goes and its move leaves
/// the cell (`moves_on(j)`); a cycle of robots waiting on each other stays (the model forbids
/// a rotation). Chains are followed with an explicit stack: they can be as long as the fleet.
fn resolve(gate: &[Gate], moves_on: impl Fn(u32) -> bool, go: &mut [bool], mark: &mut Vec<u8>, chain: &mut Vec<usize>) {
    const UNKNOWN: u8 = 0;
    const OPEN: u8 = 1;
    const SET: u8 = 2;
    mark.clear();
    mark.resize(gate.len(), UNKNOWN);
    chain.clear();
    for start in 0..gate.len() {
        let mut i = start;
        // Walk down the chain to a decided robot, a robot that decides alone, or a cycle.
        let mut verdict = loop {
            if mark[i] == SET {
                break go[i] && moves_on(i as u32);
            }
            if mark[i] == OPEN {
                break false;
            }
            match gate[i] {
                Gate::Go => {
                    go[i] = true;
                    mark[i] = SET;
                    break moves_on(i as u32);
                }
                Gate::Stop => {
                    go[i] = false;
                    mark[i] = SET;
                    break false;
                }
                Gate::After(j) => {
                    mark[i] = OPEN;
                    chain.push(i);
                    i = j as usize;
                }
            }
        };
        while let Some(k) = chain.pop() {
            go[k] = verdict;
            mark[k] = SET;
            verdict = verdict && moves_on(k as u32);
        }
    }
}

impl Tpg {
    /// Plays `window` steps without delays from where the robots are, all robots acting
    /// together (a robot may follow another into the cell it leaves in the same step); cuts the
    /// staged queues to what the play carried out, rebuilds the cell queues from it, and writes
    /// where each robot ends.
    fn play(&mut self, env: &ExecEnv<'_>, staged: &mut [Vec<Action>], predicted: &mut Vec<Pose>) {
        let n = env.system.len();
        let mut order = std::mem::take(&mut self.order);
        let mut rebuilt = std::mem::take(&mut self.spare);
        // Queues of cells visited long ago go (an empty queue and none gate alike).
        rebuilt.clear();
        let mut now: Vec<Pose> = env.system.iter().map(|p| Pose { count: 0, doing: Action::T, ..*p }).collect();
        for (i, p) in now.iter().enumerate() {
            rebuilt.entry(p.loc).push_back(i as u32);
        }
        self.done.clear();
        self.done.resize(n, 0);
        let mut gates = vec![Gate::Stop; n];
        let mut go = vec![false; n];
        let mut moved: Vec<(u32, u32)> = Vec::new();
        for step in 0..self.window {
            for i in 0..n {
                // An action under way is finished first, whatever happens: the queues granted
                // it when it started.
                let under_way = step == 0 && env.system[i].busy();
                let p = &now[i];
                gates[i] = match staged[i].get(self.done[i]) {
                    _ if env.held[i] && !under_way => Gate::Stop,
                    None => Gate::Stop,
                    Some(&a) if a != Action::F || under_way => Gate::Go,
                    Some(_) => match ahead(env.map, p.loc, p.heading) {
                        None => Gate::Stop,
                        Some(c) => gate(&order, i as u32, c, |j| now[j as usize].loc == c),
                    },
                };
            }
            resolve(&gates, |j| staged[j as usize].get(self.done[j as usize]) == Some(&Action::F), &mut go, &mut self.marks, &mut self.chain);
            moved.clear();
            for i in 0..n {
                if !go[i] {
                    continue;
                }
                let a = staged[i][self.done[i]];
                let p = &mut now[i];
                match a {
                    Action::F => {
                        let c = ahead(env.map, p.loc, p.heading).expect("a gate opens on the map");
                        moved.push((i as u32, p.loc));
                        p.loc = c;
                    }
                    Action::R | Action::C => p.heading = a.turned(p.heading),
                    _ => {}
                }
                self.done[i] += 1;
            }
            for &(i, from) in &moved {
                if let Some(q) = order.get_mut(from) {
                    if q.front() == Some(&i) {
                        q.pop_front();
                    }
                }
                rebuilt.entry(now[i as usize].loc).push_back(i);
            }
        }
        order.empty_all();
        self.spare = order;
        self.order = rebuilt;
        for (i, q) in staged.iter_mut().enumerate() {
            q.truncate(self.done[i]);
        }
        self.tail.clone_from(&now);
        predicted.clone_from(&now);
    }
}

#[cfg(test)]
mod tests {
    use super::window;

    #[test]
    fn the_window_covers_an_interval_and_one_action_more() {
        assert_eq!(window(10, 3), 4);
        assert_eq!(window(10, 1), 11);
        assert_eq!(window(10, 10), 2);
    }
}
