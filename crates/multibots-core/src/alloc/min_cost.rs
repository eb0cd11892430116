//! `min-cost`: the batch assignment with the least estimated Cost_total.
//!
//! # What it does
//! The paper's future work asks for strategies that minimise
//! Cost_total = w_d · distance + w_t · time + w_c · collisions. For every idle robot and open
//! goods it estimates what *this choice* adds to each term:
//! - distance: the empty drive to the service point (px);
//! - time: the steps of that drive, plus the recharge time if the robot would end the task
//!   below the threshold (the task's steps estimated as for `auction`);
//! - collisions: `collision_rate` × the traffic on the task's route, to the goods and on to
//!   the unloading zone ([`AllocView::traffic`](super::AllocView::traffic): how often other
//!   robots' expected paths meet it);
//!
//! The goods' own trip (loading, the drive to the unloading zone, unloading) is paid whichever
//! robot fetches it and whenever, so it does not enter the choice; counting it would favour
//! goods near the unloading zone and leave the long trips to the end, which lengthens T.
//! weights them with the scenario's `[cost]` weights and gives out the assignment with the
//! least total, solved exactly with the Hungarian method (`hungarian`'s solver). Every open
//! goods is a candidate; ties go the same way on every run.
//!
//! # When to use it
//! When collisions are expensive (a large w_c) or the fleet is dense: it trades a longer
//! drive for a quieter route. With w_c = 0 and robots far from the threshold it is
//! `hungarian`.
//!
//! # Cost
//! O(idle × goods × N × path length) for the traffic estimates plus the O(k² · m) solver per
//! event; microseconds on the paper layout.
//!
//! # Options
//! The weights are the scenario's `[cost] distance, time, collision` (defaults 0.25, 1, 50).
//! `collision_rate`, expected collisions per meeting, default 0.1; set with
//! [`MinCost::with_collision_rate`].
//!
//! # Example
//! ```toml
//! allocator = "min-cost"
//! [cost]
//! distance = 0.25
//! time = 1.0
//! collision = 200.0
//! ```

use super::hungarian::push_solution;
use super::{AllocView, Allocator, Decisions, TaskModel};
use crate::error::Result;
use crate::ids::{CellId, RobotId};

/// Least estimated Cost_total, batch-optimal.
#[derive(Clone, Debug)]
pub struct MinCost {
    model: TaskModel,
    collision_rate: f64,
}

impl MinCost {
    /// With the scenario's weights and dwell times.
    #[must_use]
    pub fn new(model: TaskModel) -> MinCost {
        MinCost { model, collision_rate: 0.1 }
    }

    /// The same with another number of expected collisions per meeting of paths.
    #[must_use]
    pub fn with_collision_rate(mut self, rate: f64) -> MinCost {
        self.collision_rate = rate;
        self
    }

    /// The estimated Cost_total that robot `r` taking `cell` adds, beyond the goods' own trip.
    #[must_use]
    pub fn cost(&self, view: &AllocView<'_>, r: RobotId, cell: CellId) -> f64 {
        let w = &self.model.weights;
        let distance = view.route_length(r, cell);
        let speed = view.robots().speed[r.index()];
        let time = (distance / speed).ceil() + self.model.charge_penalty(view, r, cell);
        let collisions = if w.collision > 0.0 { self.collision_rate * f64::from(view.traffic(r, cell)) } else { 0.0 };
        w.distance * distance + w.time * time + w.collision * collisions
    }
}

impl Allocator for MinCost {
    fn name(&self) -> &'static str {
        "min-cost"
    }

    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> Result<()> {
        let mut cost = Vec::with_capacity(view.idle.len() * view.goods.len());
        for &r in view.idle {
            cost.extend(view.goods.iter().map(|g| self.cost(view, r, g.cell)));
        }
        push_solution(view, &cost, out);
        Ok(())
    }
}
