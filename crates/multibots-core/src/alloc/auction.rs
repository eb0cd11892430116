//! `auction`: a sequential single-item auction on estimated completion time.
//!
//! # What it does
//! In each round every idle robot still without a task bids on every open goods still
//! unsold; the bid is the robot's estimated completion time for that goods, in steps:
//! the drive to the service point, loading, the drive to the unloading zone and unloading
//! (each leg rounded up to whole steps, as the engine moves), plus the time to recharge to
//! full if the robot would end the task below the threshold. The lowest bid over all pairs
//! wins; ties go to the goods nearer the front of the queue, then to the lower robot id.
//! Rounds repeat until robots or goods run out. This is the auction scheme of the paper's
//! references [2] and [23] with completion time as the bid.
//!
//! # When to use it
//! When tasks differ in length and robots differ in energy: short tasks go first to the
//! robots that finish them soonest, and a robot close to the threshold bids high. It does not
//! keep the queue order.
//!
//! # Cost
//! O(k · idle · goods) bid evaluations per event, k = min(idle, goods); the bids are computed
//! once per event and reused across rounds.
//!
//! # Options
//! Dwell times and the charge rate come from the scenario (`[dwell]`, `[robot]`).
//!
//! # Example
//! ```toml
//! allocator = "auction"
//! ```

use super::{AllocView, Allocator, Assignment, Decisions, TaskModel};
use crate::error::Result;

/// Sequential single-item auction; bids are estimated completion times.
#[derive(Clone, Debug)]
pub struct Auction {
    model: TaskModel,
}

impl Auction {
    /// An auction with the scenario's dwell times and charge rate.
    #[must_use]
    pub fn new(model: TaskModel) -> Auction {
        Auction { model }
    }

    /// Robot `r`'s bid for `cell`, in steps.
    #[must_use]
    pub fn bid(&self, view: &AllocView<'_>, r: crate::ids::RobotId, cell: crate::ids::CellId) -> f64 {
        self.model.task_steps(view, r, cell) + self.model.charge_penalty(view, r, cell)
    }
}

impl Allocator for Auction {
    fn name(&self) -> &'static str {
        "auction"
    }

    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> Result<()> {
        let (n, m) = (view.idle.len(), view.goods.len());
        let mut bids = Vec::with_capacity(n * m);
        for &r in view.idle {
            bids.extend(view.goods.iter().map(|g| self.bid(view, r, g.cell)));
        }
        let mut robot_sold = vec![false; n];
        let mut goods_sold = vec![false; m];
        for _ in 0..n.min(m) {
            let mut best: Option<(f64, usize, usize)> = None;
            // Goods outer, robots inner, strict improvement: ties keep the front goods and
            // then the lower robot id.
            for j in 0..m {
                if goods_sold[j] {
                    continue;
                }
                for i in 0..n {
                    if robot_sold[i] {
                        continue;
                    }
                    let b = bids[i * m + j];
                    if best.map_or(true, |(bb, _, _)| b < bb) {
                        best = Some((b, i, j));
                    }
                }
            }
            let (_, i, j) = best.expect("a robot and a goods are left");
            robot_sold[i] = true;
            goods_sold[j] = true;
            out.assign.push(Assignment { robot: view.idle[i], goods: view.goods[j].id });
        }
        Ok(())
    }
}
