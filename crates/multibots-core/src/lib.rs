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
pub mod energy;
pub mod error;
pub mod graph;
pub mod ids;
pub mod layout;
pub mod layout_file;
pub mod lifelong;
pub mod metrics;
pub mod original;
pub mod replay;
pub mod robot;
pub mod route;
pub mod scenario;
pub mod sim;

pub use alloc::{Allocator, AllocView, Assignment, Goods};
pub use error::{Error, Result};
pub use graph::HighwayGraph;
pub use ids::{CellId, GoodsId, NodeId, RobotId};
pub use layout::{Layout, LayoutParams};
pub use metrics::{Outcome, RobotStats, RunResult};
pub use robot::{State, Target};
pub use original::Original;
pub use scenario::{Rules, Scenario};
pub use sim::{Event, EventKind, Simulation, World};
