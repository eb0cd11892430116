//! The built-in planner under the 2026 rules: a planner of `planner/` (one action per robot per
//! step, PIBT on the highways by default) played a few steps ahead from where the executor says
//! the robots will be, its actions the plan.
//!
//! ## What it does
//! From the predicted states, the 2024 planner is asked for `window` steps (the executor's
//! window: the actions that fit between two planner calls, and one more), each step's actions
//! applied before the next is asked for. A robot reaching its goal goes on to its task's next
//! errand, so that a plan does not stop at the first. A robot held by a delay when the call is
//! made is a wall for the others (its cell taken off the map for this call) and plans nothing:
//! the others are routed round it rather than queued behind it, and it gets a plan at the next
//! call.
//!
//! ## When to use it
//! With the `tpg` executor, which keeps the steps' order when delays break their timing.
//!
//! ## Cost
//! `window` steps of the 2024 planner per call (four at the competition's defaults), every
//! `interval` ticks: less than half a planning step per tick.

use super::entries::{PlanEnv, Planner26};
use super::executor::window;
use crate::error::Result;
use crate::input::lorr::GridMap;
use crate::rules::grid::action::{ahead, Action};
use crate::rules::grid::planner::{PlanView, Planner, NO_GOAL};

/// A 2024 planner played `window` steps ahead.
pub struct Rollout {
    inner: Box<dyn Planner>,
    name: String,
    /// The map with held robots' cells taken off, when some are held.
    walled: Option<GridMap>,
    loc: Vec<u32>,
    heading: Vec<u8>,
    goals: Vec<u32>,
    /// Errands done of each robot's task, as the rollout goes.
    done: Vec<u32>,
    actions: Vec<Action>,
}

impl Rollout {
    /// `inner` played ahead, under the name `name`.
    #[must_use]
    pub fn new(inner: Box<dyn Planner>, name: &str) -> Rollout {
        Rollout { inner, name: name.to_string(), walled: None, loc: Vec::new(), heading: Vec::new(), goals: Vec::new(), done: Vec::new(), actions: Vec::new() }
    }
}

impl Planner26 for Rollout {
    fn name(&self) -> &str {
        &self.name
    }

    #[allow(clippy::needless_range_loop)] // robot i across several arrays
    fn plan(&mut self, env: &PlanEnv<'_>, plan: &mut [Vec<Action>]) -> Result<()> {
        let n = env.predicted.len();
        self.loc.clear();
        self.loc.extend(env.predicted.iter().map(|p| p.loc));
        self.heading.clear();
        self.heading.extend(env.predicted.iter().map(|p| p.heading));
        self.goals.clear();
        self.goals.extend_from_slice(env.goals);
        self.done.clear();
        self.done.extend(env.schedule.iter().map(|&id| if env.pool.is_open(id) { env.pool.tasks[id as usize].done } else { 0 }));
        self.actions.clear();
        self.actions.resize(n, Action::W);
        let any_held = env.held.iter().any(|&h| h);
        let map = if any_held {
            let walled = self.walled.get_or_insert_with(|| env.map.clone());
            walled.free.copy_from_slice(&env.map.free);
            for (i, p) in env.predicted.iter().enumerate() {
                if env.held[i] {
                    walled.free[p.loc as usize] = false;
                    self.goals[i] = NO_GOAL;
                }
            }
            &*walled
        } else {
            env.map
        };
        for step in 0..window(env.interval, env.floor.m) {
            let view = PlanView { map, loc: &self.loc, heading: &self.heading, goals: &self.goals, t: env.tick + step as u32, tasks: None };
            self.inner.plan(&view, &mut self.actions);
            for i in 0..n {
                let a = if env.held[i] { Action::W } else { self.actions[i] };
                plan[i].push(a);
                match a {
                    Action::F => self.loc[i] = ahead(env.map, self.loc[i], self.heading[i]).expect("the planner keeps robots on the map"),
                    Action::R | Action::C => self.heading[i] = a.turned(self.heading[i]),
                    _ => {}
                }
                if self.goals[i] != NO_GOAL && self.loc[i] == self.goals[i] {
                    // On to the task's next errand, if it has one.
                    self.done[i] += 1;
                    let id = env.schedule[i];
                    let errands = &env.lines[env.pool.tasks[id as usize].line as usize];
                    self.goals[i] = errands.get(self.done[i] as usize).copied().unwrap_or(NO_GOAL);
                }
            }
        }
        Ok(())
    }
}
