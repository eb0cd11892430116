//! `energy-aware`: never a task a robot cannot finish above the threshold; charged robots
//! first.
//!
//! # What it does
//! It walks the open goods from the front of the queue. For each, the candidates are the
//! idle robots still free whose energy after the task (estimated as for `auction`: the two
//! drives rounded up to whole steps, loading and unloading, all at the consumption rate,
//! plus a reserve for collision waits) stays at or above the threshold. Among them it picks
//! the one with the most energy; ties go to the shorter route, then the lower id. A goods no
//! candidate can carry is skipped, so a later, shorter one may go first. A robot that can
//! finish no open goods is left idle.
//!
//! # When to use it
//! To avoid the paper rule's put-backs (a robot that drops below the threshold on its way to
//! the goods returns them to the queue and leaves to charge) and the long drives of robots
//! that must charge mid-task. Pair it with `[charging] policy = "opportunistic"`: a robot it
//! leaves idle then goes to charge at once. Under the default `threshold` policy such a robot
//! stands where it is, consuming energy, until it falls below the threshold or the next
//! allocation event gives it a shorter task.
//!
//! # Cost
//! O(idle × goods) energy estimates per event.
//!
//! # Options
//! `reserve`: energy kept in hand for collision waits, default 0.1 (20 steps at the
//! paper's consumption); set with [`EnergyAware::with_reserve`].
//!
//! # Example
//! ```toml
//! allocator = "energy-aware"
//! [charging]
//! policy = "opportunistic"
//! level = 7.0
//! ```

use super::{AllocView, Allocator, Assignment, Decisions, TaskModel};
use crate::error::Result;

/// Energy-aware allocation.
#[derive(Clone, Debug)]
pub struct EnergyAware {
    model: TaskModel,
    reserve: f64,
}

impl EnergyAware {
    /// With the scenario's dwell times and the default reserve.
    #[must_use]
    pub fn new(model: TaskModel) -> EnergyAware {
        EnergyAware { model, reserve: 0.1 }
    }

    /// The same with another reserve (energy units).
    #[must_use]
    pub fn with_reserve(mut self, reserve: f64) -> EnergyAware {
        self.reserve = reserve;
        self
    }
}

impl Allocator for EnergyAware {
    fn name(&self) -> &'static str {
        "energy-aware"
    }

    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> Result<()> {
        let mut free: Vec<_> = view.idle.to_vec();
        for g in view.goods {
            if free.is_empty() {
                break;
            }
            let mut best: Option<(usize, f64, f64)> = None;
            for (k, &r) in free.iter().enumerate() {
                if self.model.energy_after(view, r, g.cell) - self.reserve < view.threshold {
                    continue;
                }
                let (e, d) = (view.energy(r), view.route_length(r, g.cell));
                // More energy first, then the shorter route; robots are in id order, so a
                // full tie keeps the lower id.
                if best.map_or(true, |(_, be, bd)| e > be || (e == be && d < bd)) {
                    best = Some((k, e, d));
                }
            }
            if let Some((k, _, _)) = best {
                out.assign.push(Assignment { robot: free.remove(k), goods: g.id });
            }
        }
        Ok(())
    }
}
