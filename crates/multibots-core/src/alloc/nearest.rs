//! `nearest`: goods in queue order, each to the nearest idle robot.
//!
//! # What it does
//! It walks the open goods from the front of the queue and gives each to the idle robot
//! with the shortest route to its service point, until it runs out of idle robots or goods.
//! Ties go to the lower robot id. Goods are still fetched in the order of the task list; only
//! the choice of robot changes from the paper's rule.
//!
//! # When to use it
//! As the simplest improvement on `in-turn` that keeps the queue order: robots that are
//! already close (for example at the unloading zone after a delivery) take the next goods.
//! It is myopic: an early choice can take the robot a later goods needed (see `hungarian`).
//!
//! # Cost
//! O(idle × goods taken) route-length queries per event.
//!
//! # Options
//! None.
//!
//! # Example
//! ```toml
//! allocator = "nearest"
//! ```

use super::{AllocView, Allocator, Assignment, Decisions};
use crate::error::Result;

/// Greedy: the nearest idle robot by route length takes the front goods.
#[derive(Clone, Copy, Debug, Default)]
pub struct Nearest;

impl Allocator for Nearest {
    fn name(&self) -> &'static str {
        "nearest"
    }

    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> Result<()> {
        let mut free: Vec<_> = view.idle.to_vec();
        for g in view.goods {
            if free.is_empty() {
                break;
            }
            // min_by keeps the first of equal elements: robots are in id order.
            let (k, _) =
                free.iter().enumerate().map(|(k, &r)| (k, view.route_length(r, g.cell))).min_by(|a, b| a.1.total_cmp(&b.1)).expect("free is not empty");
            out.assign.push(Assignment { robot: free.remove(k), goods: g.id });
        }
        Ok(())
    }
}
