//! `in-turn`: the paper's rule, and the default.
//!
//! # What it does
//! Idle robots, in ascending id, take the goods at the front of the queue ("the robots
//! fetch in turn according to the order of the goods", paper section III). It reproduces the
//! paper model's T, S and C exactly (`docs/model.md`, phase 1).
//!
//! # When to use it
//! To reproduce the paper, and as the baseline every other strategy is compared with.
//!
//! # Cost
//! O(min(idle, goods)) per event; no route queries.
//!
//! # Options
//! None.
//!
//! # Example
//! ```toml
//! allocator = "in-turn"
//! ```

use super::{AllocView, Allocator, Assignment, Decisions};
use crate::error::Result;

/// The paper's allocation rule, and the default.
#[derive(Clone, Copy, Debug, Default)]
pub struct InTurn;

impl Allocator for InTurn {
    fn name(&self) -> &'static str {
        "in-turn"
    }

    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> Result<()> {
        out.assign.extend(view.idle.iter().zip(view.goods).map(|(&robot, g)| Assignment { robot, goods: g.id }));
        Ok(())
    }
}
