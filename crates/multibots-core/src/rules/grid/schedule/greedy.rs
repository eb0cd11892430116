//! `greedy` and `nearest`: each free robot, in id order, takes the best free task.
//!
//! ## What it does
//! `greedy` scores a task by the path to finish it: from the robot to the first errand,
//! then errand to errand, the rule of the Start-Kit's 2024 default scheduler
//! (`default_planner/scheduler.cpp`), which stops when half the planning time is gone; this
//! one always finishes. `nearest` scores a task by its first errand only.
//!
//! ## When to use it
//! `spread` (the 2024 default before `reassign`) is `nearest` counting the robots already bound for an errand.
//! `greedy` to play the Start-Kit's default scheduler's rule; it prefers short tasks, so long
//! ones pile up in the pool.
//!
//! ## Cost
//! O(free robots × free tasks) per step: 50 million pairs at step 0 of 5,000 robots and a
//! pool of 7,500 tasks, then a few thousand a step. `nearest` on more than a million pairs
//! (the first steps) looks around each robot instead, in rings of growing grid distance,
//! for the first cell holding a free task: the same choice (the nearest, then the lowest
//! id), in 10-20 ms rather than 0.1-0.3 s at step 0 of 10,000 robots and 15,000 tasks.
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
    let robots = view.free_robots();
    let at: Vec<(u32, u32)> = robots.iter().map(|&k| (view.loc[k] / cols, view.loc[k] % cols)).collect();
    let picks = if !with_legs && robots.len() * tasks.len() > RINGS_FROM { by_rings(view.map.rows, cols, &at, &shape) } else { by_scan(&at, &shape) };
    for (&k, pick) in robots.iter().zip(picks) {
        if let Some(i) = pick {
            proposal[k] = i64::from(tasks[i as usize]);
        }
    }
}

/// Each robot (row, column), in order, takes the untaken task of least cost: grid distance
/// to its first errand plus its legs, the lowest index on a tie.
fn by_scan(at: &[(u32, u32)], shape: &[(u32, u32, u32)]) -> Vec<Option<u32>> {
    let mut taken = vec![false; shape.len()];
    let mut picks = Vec::with_capacity(at.len());
    for &(r, c) in at {
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
        picks.push(Some(best.1 as u32));
    }
    picks
}

/// Robot-task pairs above which `nearest` searches in rings (the first steps of a big fleet).
pub(super) const RINGS_FROM: usize = 1_000_000;

/// [`by_scan`] without legs for many pairs: tasks bucketed by their first errand's cell, each
/// robot takes the lowest untaken index in the cells of the first ring (grid distance 0, 1,
/// 2...) that has one. Within a cell, tasks are taken in index order (whoever reaches the
/// cell takes its lowest untaken one), so a cursor per cell is enough.
fn by_rings(rows: u32, cols: u32, at: &[(u32, u32)], shape: &[(u32, u32, u32)]) -> Vec<Option<u32>> {
    let cells = (rows * cols) as usize;
    let mut start = vec![0u32; cells + 1];
    for &(r, c, _) in shape {
        start[(r * cols + c) as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut cursor = start.clone();
    let mut by_cell = vec![0u32; shape.len()];
    for (i, &(r, c, _)) in shape.iter().enumerate() {
        let cell = (r * cols + c) as usize;
        by_cell[cursor[cell] as usize] = i as u32;
        cursor[cell] += 1;
    }
    cursor.copy_from_slice(&start);
    let (rows, cols) = (i64::from(rows), i64::from(cols));
    let mut left = shape.len();
    let mut picks = Vec::with_capacity(at.len());
    for &(r, c) in at {
        if left == 0 {
            break;
        }
        let (r, c) = (i64::from(r), i64::from(c));
        for d in 0..=rows + cols {
            let mut best: Option<(u32, usize)> = None;
            for rr in (r - d).max(0)..=(r + d).min(rows - 1) {
                let dc = d - (rr - r).abs();
                for cc in [c - dc, c + dc] {
                    if (0..cols).contains(&cc) {
                        let cell = (rr * cols + cc) as usize;
                        if cursor[cell] < start[cell + 1] {
                            let i = by_cell[cursor[cell] as usize];
                            if best.map_or(true, |(b, _)| i < b) {
                                best = Some((i, cell));
                            }
                        }
                    }
                    if dc == 0 {
                        break;
                    }
                }
            }
            if let Some((i, cell)) = best {
                cursor[cell] += 1;
                left -= 1;
                picks.push(Some(i));
                break;
            }
        }
    }
    picks
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn rings_choose_as_the_scan_does() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for round in 0..40 {
            let (rows, cols) = (rng.random_range(1..30u32), rng.random_range(1..30u32));
            let cell = |rng: &mut ChaCha8Rng| (rng.random_range(0..rows), rng.random_range(0..cols));
            // Few cells for many tasks in some rounds, so that ties and shared cells abound.
            let tasks = rng.random_range(0..if round % 2 == 0 { 60 } else { 400 });
            let shape: Vec<(u32, u32, u32)> = (0..tasks).map(|_| cell(&mut rng)).map(|(r, c)| (r, c, 0)).collect();
            let at: Vec<(u32, u32)> = (0..rng.random_range(0..300)).map(|_| cell(&mut rng)).collect();
            assert_eq!(by_rings(rows, cols, &at, &shape), by_scan(&at, &shape), "round {round}");
        }
    }
}
