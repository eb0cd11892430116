//! `soonest`: `auction` on exact distances, the default under the 2026 rules.
//!
//! ## What it does
//! Every free robot bids on the free tasks its estimated completion: the distance to the first
//! errand, then errand to errand, counted in moves along free cells (a breadth-first search
//! from each errand cell, cached), where `auction` counts grid distance; the lowest bid over
//! all pairs wins, round after round. Robots bid first on the tasks nearest by grid distance
//! (a lower bound of the exact one), and the exact distances are only worked out for those.
//! The searches of a call expand at most [`SEARCH_CELLS_PER_CALL`] cells and the cache holds
//! at most [`TABLE_BUDGET`] bytes: past them, grid distance stands in (a count of cells, not a
//! clock, so a run is the same on every machine).
//!
//! ## When to use it
//! Under the 2026 rules, whose runs are short (500 ticks: a robot finishes one to three
//! tasks), so the tasks finished soonest are the ones that count, and on maps whose walls make
//! grid distance a poor guide (mazes, rooms with doors). On the 32 × 32 to 64 × 64 example maps
//! of the 2026 Start-Kit it finishes more than `auction` and far more than `spread`
//! (docs/lorr.md).
//!
//! ## Cost
//! O(free robots × free tasks) grid distances for the lower bounds, then at most
//! [`CANDIDATES`] exact bids per robot; a search of the map per errand cell first met.
//!
//! ## Options
//! None.
//!
//! ## Example
//! `multibots lorr problem.json --scheduler soonest`

use super::{ScheduleView, Scheduler};
use crate::rules::grid::planner::{Distances, FAR};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Cells the searches of one call may expand.
pub const SEARCH_CELLS_PER_CALL: u64 = 20_000_000;
/// The memory the tables may take.
pub const TABLE_BUDGET: usize = 512 << 20;
/// Exact bids per robot at a time (its nearest tasks by grid distance).
const CANDIDATES: usize = 8;

/// Sequential single-item auction on exact distances.
#[derive(Default)]
pub struct Soonest {
    dist: Option<Distances>,
    /// Each task's errand-to-errand length once known exactly, by task id.
    legs: Vec<u32>,
    /// The map's free cells.
    free: Option<usize>,
}

impl Soonest {
    /// A `soonest` scheduler.
    #[must_use]
    pub fn new() -> Soonest {
        Soonest::default()
    }
}

/// The distance between two cells: exact if `to`'s table is cached or fits the budget, else
/// the grid distance.
fn between(dist: &mut Distances, view: &ScheduleView<'_>, from: u32, to: u32, budget: &mut u64) -> u32 {
    match dist.search_within(to, budget) {
        Some(slot) => match dist.get(slot, from) {
            FAR => u32::from(FAR),
            d => u32::from(d),
        },
        None => view.manhattan(from, to),
    }
}

impl Scheduler for Soonest {
    fn name(&self) -> &'static str {
        "soonest"
    }

    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        // Free robots: those without a task in force and none proposed yet.
        let robots: Vec<usize> = view.free_robots().into_iter().filter(|&k| proposal[k] == -1).collect();
        let proposed: std::collections::HashSet<i64> = proposal.iter().copied().filter(|&id| id >= 0).collect();
        let tasks: Vec<u32> = view.free_tasks().into_iter().filter(|&id| !proposed.contains(&i64::from(id))).collect();
        if robots.is_empty() || tasks.is_empty() {
            return;
        }
        let free = *self.free.get_or_insert_with(|| view.map.free.iter().filter(|&&f| f).count().max(1));
        // On a map of millions of cells a search costs more than it gains: grid distance.
        let mut budget = if free > crate::rules::grid::planner::HUGE { 0 } else { SEARCH_CELLS_PER_CALL };
        let dist = self.dist.get_or_insert_with(|| Distances::new(view.map, (TABLE_BUDGET / (2 * free)).max(8)));
        dist.tick();
        if self.legs.len() < view.pool.tasks.len() {
            self.legs.resize(view.pool.tasks.len(), u32::MAX);
        }
        let mut shape: Vec<(u32, u32)> = Vec::with_capacity(tasks.len());
        for &id in &tasks {
            let errands = &view.lines[view.pool.tasks[id as usize].line as usize];
            if self.legs[id as usize] == u32::MAX {
                let mut exact = true;
                let mut sum = 0u32;
                for w in errands.windows(2) {
                    sum = sum.saturating_add(between(dist, view, w[0], w[1], &mut budget));
                    exact &= dist.cached(w[1]).is_some();
                }
                if exact {
                    self.legs[id as usize] = sum;
                }
                shape.push((errands[0], sum));
            } else {
                shape.push((errands[0], self.legs[id as usize]));
            }
        }
        if robots.len() * tasks.len() > RINGS_FROM {
            by_tasks(view, dist, &mut budget, &robots, &tasks, &shape, proposal);
            return;
        }
        let mut taken = vec![false; tasks.len()];
        let mut heap: BinaryHeap<Reverse<(u32, u32, u32)>> = BinaryHeap::new();
        let mut pending = vec![0usize; robots.len()];
        let mut bids_of = |r: usize, taken: &[bool], heap: &mut BinaryHeap<Reverse<(u32, u32, u32)>>, budget: &mut u64| -> usize {
            let at = view.loc[robots[r]];
            let mut near: Vec<(u32, u32)> =
                (0..tasks.len()).filter(|&i| !taken[i]).map(|i| (view.manhattan(at, shape[i].0).saturating_add(shape[i].1), i as u32)).collect();
            let keep = CANDIDATES.min(near.len());
            if keep == 0 {
                return 0;
            }
            near.select_nth_unstable(keep - 1);
            near.truncate(keep);
            near.sort_unstable();
            for &(_, i) in &near {
                let bid = between(dist, view, at, shape[i as usize].0, budget).saturating_add(shape[i as usize].1);
                heap.push(Reverse((bid, i, r as u32)));
            }
            keep
        };
        for (r, p) in pending.iter_mut().enumerate() {
            *p = bids_of(r, &taken, &mut heap, &mut budget);
        }
        let mut sold = vec![false; robots.len()];
        while let Some(Reverse((_, i, r))) = heap.pop() {
            let (i, r) = (i as usize, r as usize);
            if sold[r] {
                continue;
            }
            pending[r] -= 1;
            if taken[i] {
                if pending[r] == 0 {
                    pending[r] = bids_of(r, &taken, &mut heap, &mut budget);
                }
                continue;
            }
            taken[i] = true;
            sold[r] = true;
            proposal[robots[r]] = i64::from(tasks[i]);
        }
    }
}

/// Robot-task pairs above which the auction is run from the tasks' side: each task takes bids
/// from its [`CANDIDATES`] nearest free robots, found in rings of buckets of [`BUCKET`] cells
/// (a fleet fills the map, so a few rings hold them), rather than every robot scanning every
/// task (at step 0 of 10,000 robots and 10,000 tasks: 0.1 s rather than 8 s).
const RINGS_FROM: usize = 1_000_000;
/// A bucket's side, in cells.
const BUCKET: u32 = 16;

/// The auction from the tasks' side; the same rule (the least bid over all pairs wins, round
/// after round), each task's bids coming from the robots nearest its first errand.
fn by_tasks(view: &ScheduleView<'_>, dist: &mut Distances, budget: &mut u64, robots: &[usize], tasks: &[u32], shape: &[(u32, u32)], proposal: &mut [i64]) {
    let (rows, cols) = (view.map.rows.div_ceil(BUCKET), view.map.cols.div_ceil(BUCKET));
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); (rows * cols) as usize];
    for (r, &k) in robots.iter().enumerate() {
        let (y, x) = view.map.row_col(view.loc[k]);
        buckets[((y / BUCKET) * cols + x / BUCKET) as usize].push(r as u32);
    }
    let mut sold = vec![false; robots.len()];
    // The nearest unsold robots to task `i`'s first errand, by grid distance: `CANDIDATES`, or
    // all of them once fewer are left (`left`), so that the rings stop as soon as they are
    // found rather than sweep the whole map.
    let nearest = |i: usize, sold: &[bool], left: usize| -> Vec<(u32, u32)> {
        let want = CANDIDATES.min(left);
        if want == 0 {
            return Vec::new();
        }
        let first = shape[i].0;
        let (y, x) = view.map.row_col(first);
        let (by, bx) = (i64::from(y / BUCKET), i64::from(x / BUCKET));
        let mut best: Vec<(u32, u32)> = Vec::with_capacity(CANDIDATES + 1);
        for k in 0..=i64::from(rows.max(cols)) {
            let floor = ((k - 1).max(0) as u32) * BUCKET;
            if best.len() == want && floor > best[want - 1].0 {
                break;
            }
            for dy in -k..=k {
                for dx in -k..=k {
                    if dy.abs() != k && dx.abs() != k {
                        continue;
                    }
                    let (qy, qx) = (by + dy, bx + dx);
                    if qy < 0 || qx < 0 || qy >= i64::from(rows) || qx >= i64::from(cols) {
                        continue;
                    }
                    for &r in &buckets[(qy * i64::from(cols) + qx) as usize] {
                        if sold[r as usize] {
                            continue;
                        }
                        let key = (view.manhattan(view.loc[robots[r as usize]], first), r);
                        if best.len() < CANDIDATES || key < best[best.len() - 1] {
                            let at = best.partition_point(|&b| b < key);
                            best.insert(at, key);
                            best.truncate(CANDIDATES);
                        }
                    }
                }
            }
        }
        best
    };
    let mut heap: BinaryHeap<Reverse<(u32, u32, u32)>> = BinaryHeap::new();
    let mut pending = vec![0usize; tasks.len()];
    let mut left = robots.len();
    let mut bids_for = |i: usize, sold: &[bool], left: usize, heap: &mut BinaryHeap<Reverse<(u32, u32, u32)>>, budget: &mut u64| -> usize {
        let near = nearest(i, sold, left);
        for &(_, r) in &near {
            let bid = between(dist, view, view.loc[robots[r as usize]], shape[i].0, budget).saturating_add(shape[i].1);
            heap.push(Reverse((bid, i as u32, r)));
        }
        near.len()
    };
    for (i, p) in pending.iter_mut().enumerate() {
        *p = bids_for(i, &sold, left, &mut heap, budget);
    }
    let mut taken = vec![false; tasks.len()];
    while let Some(Reverse((_, i, r))) = heap.pop() {
        let (i, r) = (i as usize, r as usize);
        if taken[i] {
            continue;
        }
        pending[i] -= 1;
        if sold[r] {
            if pending[i] == 0 {
                pending[i] = bids_for(i, &sold, left, &mut heap, budget);
            }
            continue;
        }
        taken[i] = true;
        sold[r] = true;
        left -= 1;
        proposal[robots[r]] = i64::from(tasks[i]);
        if left == 0 {
            break;
        }
    }
}
