//! Task allocation: the [`Allocator`] trait and the built-in strategies.
//!
//! The engine calls an allocator at allocation events only: when robots became idle or goods
//! joined the queue. It sees a read-only [`AllocView`] and answers with assignments; a robot
//! it leaves out stays idle (or, when no goods are open, goes home to park).

mod in_turn;

pub use in_turn::InTurn;

use crate::error::{Error, Result};
use crate::graph::HighwayGraph;
use crate::ids::{CellId, GoodsId, NodeId, RobotId};
use crate::layout::Layout;
use crate::robot::{Robots, State, Target};
use crate::route::{self, Place};
use crate::scenario::Scenario;

/// One open goods item: its id and the cell that holds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Goods {
    pub id: GoodsId,
    pub cell: CellId,
}

/// "Give these goods to this robot."
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Assignment {
    pub robot: RobotId,
    pub goods: GoodsId,
}

/// What an allocator may look at. Everything is read-only.
pub struct AllocView<'a> {
    /// The current step.
    pub step: u64,
    /// Idle robots, ascending.
    pub idle: &'a [RobotId],
    /// Open goods, in queue order (the front first).
    pub goods: &'a [Goods],
    pub(crate) robots: &'a Robots,
    pub(crate) layout: &'a Layout,
    pub(crate) graph: &'a HighwayGraph,
    pub(crate) unload: NodeId,
    pub(crate) energy_full: f64,
    pub(crate) threshold: f64,
    pub(crate) consumption: f64,
    pub(crate) speed: f64,
}

impl AllocView<'_> {
    /// Number of robots in the fleet.
    #[must_use]
    pub fn robot_count(&self) -> usize {
        self.robots.len()
    }

    /// Position of a robot.
    #[must_use]
    pub fn position(&self, r: RobotId) -> (f64, f64) {
        (self.robots.x[r.index()], self.robots.y[r.index()])
    }

    /// Energy of a robot.
    #[must_use]
    pub fn energy(&self, r: RobotId) -> f64 {
        self.robots.energy[r.index()]
    }

    /// State of a robot.
    #[must_use]
    pub fn state(&self, r: RobotId) -> State {
        self.robots.state[r.index()]
    }

    /// A robot's home charger.
    #[must_use]
    pub fn home(&self, r: RobotId) -> NodeId {
        self.robots.home[r.index()]
    }

    /// The cell a robot is fetching or carrying, if any.
    #[must_use]
    pub fn task_cell(&self, r: RobotId) -> Option<CellId> {
        self.robots.goods_of(r.index()).map(|(_, c)| c)
    }

    /// Full energy, the threshold, consumption per step and speed (px per step).
    #[must_use]
    pub fn energy_model(&self) -> (f64, f64, f64, f64) {
        (self.energy_full, self.threshold, self.consumption, self.speed)
    }

    /// The unloading zone.
    #[must_use]
    pub fn unload(&self) -> NodeId {
        self.unload
    }

    /// The layout.
    #[must_use]
    pub fn layout(&self) -> &Layout {
        self.layout
    }

    /// Route length in px from a robot's position to a cell's service point.
    #[must_use]
    pub fn route_length(&self, r: RobotId, cell: CellId) -> f64 {
        route::length(self.graph, Place::of(self.robots, r.index()), service_target(self.layout, cell))
    }

    /// Route length in px from a cell's service point to the unloading zone.
    #[must_use]
    pub fn cell_to_unload(&self, cell: CellId) -> f64 {
        let c = &self.layout.cells[cell.index()];
        let at = Place { x: c.service.0, y: c.service.1, at_node: crate::ids::NONE, edge_u: c.edge.0 .0, edge_v: c.edge.1 .0 };
        route::length(self.graph, at, Target::Node(self.unload))
    }

    /// Route length in px from the unloading zone to a robot's home charger.
    #[must_use]
    pub fn unload_to_home(&self, r: RobotId) -> f64 {
        self.graph.path_length(self.unload, self.robots.home[r.index()])
    }
}

/// The service point of a cell as a route target.
#[must_use]
pub fn service_target(layout: &Layout, cell: CellId) -> Target {
    let c = &layout.cells[cell.index()];
    Target::Point { u: c.edge.0, v: c.edge.1, x: c.service.0, y: c.service.1 }
}

/// A task-allocation strategy.
pub trait Allocator: Send + Sync {
    /// The strategy's kebab-case name, as in TOML, the command line and Python.
    fn name(&self) -> &str;

    /// Appends assignments to `out` (which the engine has cleared). Each idle robot and each
    /// goods item may appear at most once.
    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Vec<Assignment>) -> Result<()>;
}

/// The built-in strategies' names.
pub const BUILT_INS: &[&str] = &["in-turn"];

/// The built-in strategy a scenario names, configured from the scenario (for example the
/// cost weights of `min-cost`).
pub fn built_in(scenario: &Scenario) -> Result<Box<dyn Allocator>> {
    let name = scenario.allocator.as_str();
    match name {
        "in-turn" => Ok(Box::new(InTurn)),
        _ => Err(Error::scenario("allocator", format!("\"{name}\""), format!("unknown strategy (built-ins: {})", BUILT_INS.join(", ")))),
    }
}
