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
use std::collections::{HashMap, VecDeque};

/// The `tpg` executor's state.
#[derive(Default)]
pub struct Tpg {
    /// Per cell, the robots that will enter it, in order; the front is in it or entering it.
    order: HashMap<u32, VecDeque<u32>>,
    /// Each robot's cell when last seen.
    seen: Vec<u32>,
    /// Where each robot's staged actions end.
    tail: Vec<Pose>,
    /// Planned actions staged per plan.
    window: usize,
    /// Actions of the current play, per robot (scratch).
    done: Vec<usize>,
}

impl Tpg {
    /// A `tpg` executor.
    #[must_use]
    pub fn new() -> Tpg {
        Tpg::default()
    }

    fn pop_front(&mut self, cell: u32, robot: u32) {
        if let Some(q) = self.order.get_mut(&cell) {
            if q.front() == Some(&robot) {
                q.pop_front();
            }
            if q.is_empty() {
                self.order.remove(&cell);
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
    fn name(&self) -> &str {
        "tpg"
    }

    fn process_new_plan(&mut self, env: &ExecEnv<'_>, plan: &[Vec<Action>], staged: &mut [Vec<Action>], predicted: &mut Vec<Pose>) -> Result<()> {
        let n = env.system.len();
        if self.seen.len() != n {
            self.window = window(env.interval, env.floor.m);
            self.seen = env.system.iter().map(|p| p.loc).collect();
            self.tail = env.system.to_vec();
            self.order.clear();
            for (i, p) in env.system.iter().enumerate() {
                self.order.entry(p.loc).or_default().push_back(i as u32);
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
                            self.order.entry(c).or_default().push_back(i as u32);
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
        Ok(())
    }

    fn next_command(&mut self, env: &ExecEnv<'_>, staged: &[Vec<Action>], go: &mut [bool]) -> Result<()> {
        for (i, p) in env.system.iter().enumerate() {
            if p.loc != self.seen[i] {
                let was = self.seen[i];
                self.pop_front(was, i as u32);
                self.seen[i] = p.loc;
            }
        }
        for (i, p) in env.system.iter().enumerate() {
            go[i] = match staged[i].first() {
                None => false,
                Some(&a) if a != Action::F => true,
                Some(_) => match ahead(env.map, p.loc, p.heading) {
                    None => true,
                    Some(c) => match self.order.get(&c) {
                        None => true,
                        Some(q) => q.front() == Some(&(i as u32)) || (q.get(1) == Some(&(i as u32)) && leaving(env, q[0], c)),
                    },
                },
            };
        }
        Ok(())
    }
}

/// Whether robot `j`, in `cell`, is on its way out of it (a forward move under way).
fn leaving(env: &ExecEnv<'_>, j: u32, cell: u32) -> bool {
    let p = &env.system[j as usize];
    p.loc == cell && p.doing == Action::F && p.count > 0 && !env.held[j as usize]
}

impl Tpg {
    /// Plays `window` steps without delays from where the robots are; cuts the staged queues
    /// to what the play carried out, rebuilds the cell queues from it, and writes where each
    /// robot ends.
    fn play(&mut self, env: &ExecEnv<'_>, staged: &mut [Vec<Action>], predicted: &mut Vec<Pose>) {
        let n = env.system.len();
        let mut order = std::mem::take(&mut self.order);
        let mut rebuilt: HashMap<u32, VecDeque<u32>> = HashMap::with_capacity(order.len());
        let mut now: Vec<Pose> = env.system.iter().map(|p| Pose { count: 0, doing: Action::T, ..*p }).collect();
        for (i, p) in now.iter().enumerate() {
            rebuilt.entry(p.loc).or_default().push_back(i as u32);
        }
        self.done.clear();
        self.done.resize(n, 0);
        let mut moved: Vec<(u32, u32)> = Vec::new();
        for step in 0..self.window {
            moved.clear();
            for i in 0..n {
                // An action under way is finished first, whatever happens: the queues granted
                // it when it started.
                let under_way = step == 0 && env.system[i].busy();
                if env.held[i] && !under_way {
                    continue;
                }
                let Some(&a) = staged[i].get(self.done[i]) else { continue };
                let p = &mut now[i];
                match a {
                    Action::F => {
                        let Some(c) = ahead(env.map, p.loc, p.heading) else { continue };
                        if !under_way && order.get(&c).and_then(|q| q.front().copied()) != Some(i as u32) {
                            continue;
                        }
                        moved.push((i as u32, p.loc));
                        p.loc = c;
                    }
                    Action::R | Action::C => p.heading = a.turned(p.heading),
                    _ => {}
                }
                self.done[i] += 1;
            }
            for &(i, from) in &moved {
                if let Some(q) = order.get_mut(&from) {
                    if q.front() == Some(&i) {
                        q.pop_front();
                    }
                }
                rebuilt.entry(now[i as usize].loc).or_default().push_back(i);
            }
        }
        order.clear();
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
