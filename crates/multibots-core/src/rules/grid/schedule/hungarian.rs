//! `hungarian`: free robots and free tasks matched at least total cost.
//!
//! ## What it does
//! The cost of a robot and a task is the `greedy` score (to the first errand, then errand
//! to errand). Free robots are matched in batches of 256 in id order; each batch sees the 8
//! best tasks of each of its robots (at most 2,048 columns), so that a batch is solved in
//! milliseconds by MultiBots' Hungarian method (`alloc::hungarian::solve`). Within a batch
//! the matching is optimal; across batches it is greedy.
//!
//! ## When to use it
//! When many robots are free at once (the start of a run, a burst of finished tasks) and
//! a robot's best task is also another's.
//!
//! ## Cost
//! O(free robots × free tasks) to find candidates, plus O(256² × 2,048) per batch.
//!
//! ## Options
//! None.
//!
//! ## Example
//! `multibots lorr problem.json --scheduler hungarian`

use super::{ScheduleView, Scheduler};

const BATCH: usize = 256;
const PER_ROBOT: usize = 8;

/// Least-cost matching in batches.
pub struct Hungarian;

impl Scheduler for Hungarian {
    fn name(&self) -> &'static str {
        "hungarian"
    }

    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        let tasks = view.free_tasks();
        let shape: Vec<(u32, u32)> = tasks.iter().map(|&id| view.task_shape(id)).collect();
        let mut taken = vec![false; tasks.len()];
        let cost = |p: u32, i: usize| f64::from(view.manhattan(p, shape[i].0) + shape[i].1);
        for batch in view.free_robots().chunks(BATCH) {
            let mut columns: Vec<usize> = Vec::new();
            for &k in batch {
                let mut best: Vec<(f64, usize)> = (0..tasks.len()).filter(|&i| !taken[i]).map(|i| (cost(view.loc[k], i), i)).collect();
                let keep = PER_ROBOT.min(best.len());
                if keep == 0 {
                    break;
                }
                best.select_nth_unstable_by(keep - 1, |a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                columns.extend(best[..keep].iter().map(|b| b.1));
            }
            columns.sort_unstable();
            columns.dedup();
            if columns.is_empty() {
                break;
            }
            let matrix: Vec<f64> = batch.iter().flat_map(|&k| columns.iter().map(move |&i| (k, i))).map(|(k, i)| cost(view.loc[k], i)).collect();
            let solution = crate::alloc::hungarian::solve(&matrix, batch.len(), columns.len());
            for (&k, col) in batch.iter().zip(solution) {
                if let Some(c) = col {
                    let i = columns[c];
                    taken[i] = true;
                    proposal[k] = i64::from(tasks[i]);
                }
            }
        }
    }
}
