//! `auction`: MultiBots' sequential single-item auction as a LoRR scheduler.
//!
//! ## What it does
//! Every free robot bids on every free task its estimated completion time (the `greedy`
//! score: grid distance to the first errand, then errand to errand); the lowest bid over all
//! pairs wins, and rounds repeat until robots or tasks run out (ties: the lower task id, then
//! the lower robot id), as `allocator = "auction"` does with goods. The rounds are run as one
//! pass over the bids in increasing order: each robot's 16 lowest bids wait in a heap, and a
//! robot whose bids were all taken bids again on what is left, whose bids are no lower, so
//! the pass takes exactly the pairs the rounds would.
//!
//! ## When to use it
//! Beside `hungarian` (least total cost) and `nearest` (robot by robot): the auction gives
//! every task to the robot that finishes it soonest, short tasks first.
//!
//! ## Cost
//! O(free robots × free tasks) for the first bids, O(log) per bid taken from the heap.
//!
//! ## Options
//! None.
//!
//! ## Example
//! `multibots lorr problem.json --scheduler auction`

use super::{ScheduleView, Scheduler};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

const PER_ROBOT: usize = 16;

/// Sequential single-item auction on estimated completion time.
pub struct Auction;

impl Scheduler for Auction {
    fn name(&self) -> &'static str {
        "auction"
    }

    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        let robots = view.free_robots();
        let tasks = view.free_tasks();
        if robots.is_empty() || tasks.is_empty() {
            return;
        }
        let shape: Vec<(u32, u32)> = tasks.iter().map(|&id| view.task_shape(id)).collect();
        let bid = |k: usize, i: usize| view.manhattan(view.loc[k], shape[i].0) + shape[i].1;
        let mut taken = vec![false; tasks.len()];
        // (bid, task index, robot index): the heap's least is the round's winning bid.
        let mut heap: BinaryHeap<Reverse<(u32, u32, u32)>> = BinaryHeap::new();
        let mut pending = vec![0usize; robots.len()];
        let bids_of = |r: usize, taken: &[bool], heap: &mut BinaryHeap<Reverse<(u32, u32, u32)>>| -> usize {
            let k = robots[r];
            let mut best: Vec<(u32, u32)> = (0..tasks.len()).filter(|&i| !taken[i]).map(|i| (bid(k, i), i as u32)).collect();
            let keep = PER_ROBOT.min(best.len());
            if keep == 0 {
                return 0;
            }
            best.select_nth_unstable(keep - 1);
            for &(b, i) in &best[..keep] {
                heap.push(Reverse((b, i, r as u32)));
            }
            keep
        };
        for (r, p) in pending.iter_mut().enumerate() {
            *p = bids_of(r, &taken, &mut heap);
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
                    pending[r] = bids_of(r, &taken, &mut heap);
                }
                continue;
            }
            taken[i] = true;
            sold[r] = true;
            proposal[robots[r]] = i64::from(tasks[i]);
        }
    }
}
