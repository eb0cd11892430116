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
pub mod batch;
pub mod charging;
pub mod codec;
pub mod collision;
mod cruise;
pub mod decision_point;
pub mod energy;
pub mod error;
pub mod events;
pub mod files;
pub mod goods_queue;
pub mod graph;
pub mod ids;
pub mod layout;
pub mod layout_file;
pub mod learning;
pub mod lifelong;
pub mod limits;
pub mod metrics;
pub mod original;
pub mod people;
pub mod placement;
pub mod replay;
pub mod robot;
pub mod route;
pub mod scenario;
pub mod schema;
pub mod sim;
pub mod simulation;
pub mod tasks;
pub mod traffic;
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
pub use events::{Event, EventKind};
pub use graph::HighwayGraph;
pub use ids::{CellId, GoodsId, NodeId, RobotId};
pub use layout::{Layout, LayoutParams};
pub use metrics::{Outcome, RobotStats, RunResult};
pub use original::Original;
pub use robot::{State, Target};
pub use scenario::{Rules, Scenario, Traffic, Unload};
pub use simulation::Simulation;
pub use world::World;
