//! Schedulers (2024 rules): each step a scheduler proposes a task (or none) per robot from
//! the pool. It plugs in as allocators and planners do: the [`Scheduler`] trait, and
//! [`built_in`] maps the names the command line and Python use. The rules check the
//! proposal (`pool.rs`); a refused one is recorded and the last valid one kept.
//!
//! The built-in ones but `reassign` only give tasks to free robots and never take one back;
//! `reassign` takes back only tasks whose robot has not reached their first errand, which the
//! rules allow. So every proposal they make is valid. Costs are grid (Manhattan) distances between cells: exact
//! distances would need a search per task revealed, which at 10,000 robots costs more than
//! the difference is worth in the warehouse maps, whose aisles make the two close.
//!
//! | name | what it does |
//! | --- | --- |
//! | `auto` (default) | `reassign` under the 2024 rules, `soonest` under the 2026 rules ([`resolve`]) |
//! | `spread` | as `nearest`, counting every robot already bound for a first errand as 10 cells more to it (`spread.rs`) |
//! | `nearest` | each free robot, in id order, takes the free task whose first errand is nearest (MultiBots' `nearest`) |
//! | `greedy` | each free robot, in id order, takes the free task it would finish soonest (to its first errand, then errand to errand): the rule of the Start-Kit's 2024 default scheduler, without its time cut-off (`greedy.rs`) |
//! | `hungarian` | the free robots and free tasks matched at least total cost (MultiBots' `hungarian`), in batches of 256 robots (`hungarian.rs`) |
//! | `auction` | the lowest bid (estimated completion time) over all free pairs wins, round after round (MultiBots' `auction`, `auction.rs`) |
//! | `soonest` | `auction` on exact distances (a search per errand cell, within a budget): the default under the 2026 rules (`soonest.rs`) |
//! | `reassign` | every step, every task not opened yet put up again among the robots without an opened task, each bid 20 × the exact distance to its first errand + its length + 30 cells a robot already sent there (`soonest.rs`) |
//!
//! `reassign` is the 2024 default: on every 2024 instance of the archive but one it finishes
//! more than `spread` (docs/benchmarks.md, "Issue 41: the 2024 scheduler"). Of those that
//! never take a task back, `spread` finishes the most: scoring whole tasks (`greedy`,
//! `hungarian`) takes the short ones first, the pool fills with long ones and throughput
//! falls over the run (5,000 robots on `warehouse_large`, 5,000 steps: `nearest` 38,889
//! tasks, `greedy` 32,013; `docs/lorr.md`), and `nearest` crowds the stations nearest the
//! robots until the fleet jams in front of them (`MR24-WAREHOUSE`, 10,000 robots, 3,000
//! steps: `spread` 78,269 and 77,842 tasks for planner seeds 0 and 1, `nearest` 59,326 and
//! 51,858).

mod auction;
mod greedy;
mod hungarian;
mod soonest;
mod spread;

pub use auction::Auction;
pub use greedy::{Greedy, Nearest};
pub use hungarian::Hungarian;
pub use soonest::Soonest;
pub use spread::Spread;

use super::pool::TaskPool;
use crate::error::{Error, Result};
use crate::input::lorr::GridMap;

/// What a scheduler sees at a step.
pub struct ScheduleView<'a> {
    /// The grid.
    pub map: &'a GridMap,
    /// Each robot's cell.
    pub loc: &'a [u32],
    /// Each robot's heading (0 east, 1 south, 2 west, 3 north).
    pub heading: &'a [u8],
    /// The pool and the schedule in force.
    pub pool: &'a TaskPool,
    /// The task file's lines (a task's errands are `lines[task.line]`).
    pub lines: &'a [Vec<u32>],
    /// The current step.
    pub t: u32,
}

impl ScheduleView<'_> {
    /// The robots without a task, in id order.
    #[must_use]
    pub fn free_robots(&self) -> Vec<usize> {
        (0..self.loc.len()).filter(|&k| self.pool.current[k] == -1).collect()
    }

    /// The pool's tasks no robot holds, in id order.
    #[must_use]
    pub fn free_tasks(&self) -> Vec<u32> {
        let mut v: Vec<u32> = self.pool.open().iter().copied().filter(|&id| self.pool.tasks[id as usize].agent == -1).collect();
        v.sort_unstable();
        v
    }

    /// The grid distance between two cells.
    #[must_use]
    pub fn manhattan(&self, a: u32, b: u32) -> u32 {
        let (ra, ca) = self.map.row_col(a);
        let (rb, cb) = self.map.row_col(b);
        ra.abs_diff(rb) + ca.abs_diff(cb)
    }

    /// A task's first errand and the length of its errand-to-errand legs.
    #[must_use]
    pub fn task_shape(&self, id: u32) -> (u32, u32) {
        let errands = &self.lines[self.pool.tasks[id as usize].line as usize];
        let legs = errands.windows(2).map(|w| self.manhattan(w[0], w[1])).sum();
        (errands[0], legs)
    }
}

/// A scheduler: proposes one task id (or -1) per robot.
pub trait Scheduler: Send + Sync {
    /// The scheduler's name, as [`built_in`] knows it.
    fn name(&self) -> &'static str;
    /// Fills `proposal`, which holds the schedule in force when called.
    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]);
    /// Why the last call failed, if it did (a Python scheduler that raised): the run then
    /// stops with this error. Built-in schedulers never fail.
    fn failure(&mut self) -> Option<crate::error::Error> {
        None
    }
}

/// A built-in scheduler: its name (the same on the command line and in Python), one line on
/// what it does (the command line's help), and how it is made.
pub struct BuiltIn {
    pub name: &'static str,
    pub about: &'static str,
    make: fn() -> Box<dyn Scheduler>,
}

/// The built-in schedulers; the first is the default.
pub const BUILT_INS: &[BuiltIn] = &[
    BuiltIn { name: "auto", about: "reassign under the 2024 rules, soonest under the 2026 rules", make: || Box::new(Soonest::reassign()) },
    BuiltIn { name: "spread", about: "nearest, counting robots already bound for an errand", make: || Box::new(Spread::new()) },
    BuiltIn { name: "nearest", about: "each free robot takes the free task whose first errand is nearest", make: || Box::new(Nearest) },
    BuiltIn { name: "greedy", about: "each free robot takes the task it would finish soonest (the Start-Kit's rule)", make: || Box::new(Greedy) },
    BuiltIn { name: "hungarian", about: "free robots and tasks matched at least total cost", make: || Box::new(Hungarian) },
    BuiltIn { name: "auction", about: "the lowest bid over all free pairs wins, round after round", make: || Box::new(Auction) },
    BuiltIn { name: "soonest", about: "auction on exact distances (the 2026 default)", make: || Box::new(Soonest::new()) },
    BuiltIn {
        name: "reassign",
        about: "every step, tasks not yet opened put up again: 20 x approach + task length + robots sent there",
        make: || Box::new(Soonest::reassign()),
    },
];

/// The built-in schedulers' names.
pub fn names() -> impl Iterator<Item = &'static str> {
    BUILT_INS.iter().map(|b| b.name)
}

/// The scheduler `auto` names under the task rules of `y2026`: `soonest` under the 2026
/// rules, `reassign` under the 2024 ones.
#[must_use]
pub fn resolve(name: &str, y2026: bool) -> &str {
    match (name, y2026) {
        ("auto", true) => "soonest",
        ("auto", false) => "reassign",
        _ => name,
    }
}

/// A built-in scheduler by name.
pub fn built_in(name: &str) -> Result<Box<dyn Scheduler>> {
    match BUILT_INS.iter().find(|b| b.name == name) {
        Some(b) => Ok((b.make)()),
        None => Err(Error::scenario("scheduler", name, format!("is not a scheduler; the built-in ones are {}", names().collect::<Vec<_>>().join(", ")))),
    }
}
