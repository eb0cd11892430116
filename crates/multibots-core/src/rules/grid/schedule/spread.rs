//! `spread`: the nearest first errand, where every robot already bound for an errand cell
//! makes that cell count as further away.
//!
//! ## What it does
//! Each free robot, in id order, takes the free task of least cost: the grid distance to its
//! first errand, plus [`QUEUE_CELLS`] for every robot whose task has that first errand and
//! that has not reached it yet, the robots given one earlier in the same round included; the
//! lowest id on a tie. The first round of a big fleet (every robot free, over a million
//! robot-task pairs: step 0 of 10,000 robots and 15,000 tasks) goes as `nearest` does, by
//! rings round each robot, for speed: there nobody is bound yet, and robots given a task in
//! that round do not count for each other.
//!
//! ## Why
//! `nearest` sends every robot to the station nearest it, whatever waits there. On
//! `MR24-WAREHOUSE` (10,000 robots), the pockets of a few stations filled, robots that had
//! been served could not leave them, and the jam grew over the band in front of the
//! stations until it held 2,000 robots (measured from the result file at steps 1,000-3,000).
//! Counting the robots on their way turns the extra robots to the next stations, which were
//! idle.
//!
//! ## Cost
//! O(cells + robots + free robots × free tasks) per step: a few hundred thousand pairs at
//! 10,000 robots after the first round.
//!
//! ## Options
//! None.
//!
//! ## Example
//! `multibots lorr problem.json --scheduler spread`

use super::greedy::{assign, RINGS_FROM};
use super::{ScheduleView, Scheduler};

/// Grid cells a robot bound for the same errand adds to a task's cost.
pub const QUEUE_CELLS: u32 = 10;

/// The nearest first errand, counting the robots bound for it.
pub struct Spread {
    bound: Vec<u32>,
}

impl Spread {
    /// A scheduler with nobody bound.
    #[must_use]
    pub fn new() -> Spread {
        Spread { bound: Vec::new() }
    }
}

impl Default for Spread {
    fn default() -> Self {
        Spread::new()
    }
}

impl Scheduler for Spread {
    fn name(&self) -> &'static str {
        "spread"
    }

    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        let robots = view.free_robots();
        if robots.is_empty() {
            return;
        }
        if robots.len() == view.loc.len() && robots.len() * view.pool.open().len() > RINGS_FROM {
            assign(view, proposal, false);
            return;
        }
        self.bound.clear();
        self.bound.resize(view.map.cells(), 0);
        for &id in view.pool.current.iter().filter(|&&id| id >= 0) {
            let task = &view.pool.tasks[id as usize];
            if task.done == 0 {
                self.bound[view.lines[task.line as usize][0] as usize] += 1;
            }
        }
        let tasks = view.free_tasks();
        let cols = view.map.cols;
        // Rows and columns once, not per pair.
        let first: Vec<(u32, u32, u32)> = tasks
            .iter()
            .map(|&id| {
                let cell = view.lines[view.pool.tasks[id as usize].line as usize][0];
                (cell / cols, cell % cols, cell)
            })
            .collect();
        let mut taken = vec![false; tasks.len()];
        for k in robots {
            let (r, c) = (view.loc[k] / cols, view.loc[k] % cols);
            let mut best = (u32::MAX, usize::MAX);
            for (i, &(fr, fc, cell)) in first.iter().enumerate() {
                if taken[i] {
                    continue;
                }
                let cost = r.abs_diff(fr) + c.abs_diff(fc) + QUEUE_CELLS * self.bound[cell as usize];
                if cost < best.0 {
                    best = (cost, i);
                }
            }
            if best.1 == usize::MAX {
                break;
            }
            taken[best.1] = true;
            self.bound[first[best.1].2 as usize] += 1;
            proposal[k] = i64::from(tasks[best.1]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::greedy::Nearest;
    use super::*;
    use crate::input::lorr::GridMap;
    use crate::rules::grid::pool::TaskPool;

    #[test]
    fn a_robot_bound_for_an_errand_sends_the_next_one_elsewhere() {
        let map = GridMap::parse("type octile\nheight 1\nwidth 20\nmap\n....................\n").unwrap();
        // Tasks 0 and 1 start at cell 5, task 2 at cell 9. Robot 0 (at 4) holds task 0 and
        // has not reached cell 5; robot 1 (at 3) is free.
        let lines = vec![vec![5, 12], vec![5, 12], vec![9, 12]];
        let mut pool = TaskPool::new(2, 3, lines.len());
        pool.current[0] = 0;
        pool.tasks[0].agent = 0;
        let loc = [4, 3];
        let view = ScheduleView { map: &map, loc: &loc, heading: &[0; 3][..loc.len()], pool: &pool, lines: &lines, t: 1 };
        let mut proposal = vec![0, -1];
        Spread::new().schedule(&view, &mut proposal);
        assert_eq!(proposal, vec![0, 2], "cell 5 is 2 away and 1 robot bound (12), cell 9 is 6 away");
        let mut proposal = vec![0, -1];
        Nearest.schedule(&view, &mut proposal);
        assert_eq!(proposal, vec![0, 1], "nearest takes cell 5");
    }

    #[test]
    fn robots_given_an_errand_in_the_same_round_count_and_reached_errands_do_not() {
        let map = GridMap::parse("type octile\nheight 1\nwidth 20\nmap\n....................\n").unwrap();
        // Tasks 0-2 start at cell 5, task 3 at cell 9. Robot 0 holds task 0 and stands on
        // cell 5 (its first errand done); robots 1 and 2 (at 4 and 3) are free.
        let lines = vec![vec![5, 12], vec![5, 12], vec![5, 12], vec![9, 12]];
        let mut pool = TaskPool::new(3, 4, lines.len());
        pool.current[0] = 0;
        pool.tasks[0].agent = 0;
        pool.tasks[0].done = 1;
        let loc = [5, 4, 3];
        let view = ScheduleView { map: &map, loc: &loc, heading: &[0; 3][..loc.len()], pool: &pool, lines: &lines, t: 1 };
        let mut proposal = vec![0, -1, -1];
        Spread::new().schedule(&view, &mut proposal);
        // Robot 1: cell 5 costs 1 (robot 0 has reached it), so task 1. Robot 2: cell 5 costs
        // 2 + 10 for robot 1, cell 9 costs 6: task 3.
        assert_eq!(proposal, vec![0, 1, 3]);
    }
}
