//! The MultiBots engine: the paper model of "A Novel Swarm Robot Simulation Platform for
//! Warehousing Logistics" (ROBIO 2017), specified in `docs/model.md`, and what goes beyond it.
//!
//! ```
//! use multibots_core::{Scenario, Simulation};
//! // The spec's worked example: robot 0 alone fetches cell 42.
//! let result = Simulation::new(&Scenario::paper(1, &[42])).unwrap().run().unwrap();
//! assert_eq!(result.t, Some(726));
//! ```

pub mod alloc;
pub mod collision;
pub mod error;
pub mod fleet;
pub mod ids;
pub mod input;
pub mod learning;
pub mod output;
pub mod people;
pub mod record;
pub mod rules;
pub(crate) mod traffic;
pub mod world;

/// Deterministic pseudo-random numbers for the crate's own tests (xorshift; no dependency).
#[cfg(test)]
pub(crate) fn xorshift(s: &mut u64) -> u64 {
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    *s
}

pub use alloc::{AllocView, Allocator, Assignment, Decisions, Goods};
pub use error::{Error, Result};
pub use fleet::robot::{State, Target};
pub use ids::{CellId, GoodsId, NodeId, RobotId};
pub use input::layout_params::LayoutParams;
pub use input::scenario::{Rules, Scenario, Traffic, Unload};
pub use record::events::{Event, EventKind};
pub use record::metrics::{Outcome, RobotStats, RunResult};
pub use rules::original::Original;
pub use rules::Simulation;
pub use world::graph::HighwayGraph;
pub use world::layout::Layout;
pub use world::World;
