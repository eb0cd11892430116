//! `greedy` and `nearest`: each free robot, in id order, takes the best free task.
//!
//! ## What it does
//! `greedy` scores a task by the path to finish it: from the robot to the first errand,
//! then errand to errand, the rule of the Start-Kit's 2024 default scheduler
//! (`default_planner/scheduler.cpp`), which stops when half the planning time is gone; this
//! one always finishes. `nearest` scores a task by its first errand only.
//!
//! ## When to use it
//! `nearest` is the default: it finishes the most tasks. `greedy` to play the Start-Kit's
//! default scheduler's rule; it prefers short tasks, so long ones pile up in the pool.
//!
//! ## Cost
//! O(free robots × free tasks) per step: 50 million pairs at step 0 of 5,000 robots and a
//! pool of 7,500 tasks, then a few thousand a step.
//!
//! ## Options
//! None.
//!
//! ## Example
//! `multibots lorr problem.json --scheduler greedy`

use super::{ScheduleView, Scheduler};

/// The Start-Kit default's rule, run to the end.
pub struct Greedy;
/// The nearest first errand.
pub struct Nearest;

pub(super) fn assign(view: &ScheduleView<'_>, proposal: &mut [i64], with_legs: bool) {
    let tasks = view.free_tasks();
    // Rows and columns once, not per pair: at step 0 of 10,000 robots there are 150 million.
    let cols = view.map.cols;
    let shape: Vec<(u32, u32, u32)> = tasks
        .iter()
        .map(|&id| {
            let (first, legs) = view.task_shape(id);
            (first / cols, first % cols, if with_legs { legs } else { 0 })
        })
        .collect();
    let mut taken = vec![false; tasks.len()];
    for k in view.free_robots() {
        let (r, c) = (view.loc[k] / cols, view.loc[k] % cols);
        let mut best = (u32::MAX, usize::MAX);
        for (i, &(fr, fc, legs)) in shape.iter().enumerate() {
            if taken[i] {
                continue;
            }
            let cost = r.abs_diff(fr) + c.abs_diff(fc) + legs;
            if cost < best.0 {
                best = (cost, i);
            }
        }
        if best.1 == usize::MAX {
            break;
        }
        taken[best.1] = true;
        proposal[k] = i64::from(tasks[best.1]);
    }
}

impl Scheduler for Greedy {
    fn name(&self) -> &'static str {
        "greedy"
    }
    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        assign(view, proposal, true);
    }
}

impl Scheduler for Nearest {
    fn name(&self) -> &'static str {
        "nearest"
    }
    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        assign(view, proposal, false);
    }
}
