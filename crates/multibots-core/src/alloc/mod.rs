//! Task allocation: the [`Allocator`] trait and the built-in strategies.
//!
//! The engine calls an allocator at allocation events only: when robots became idle or goods
//! joined the queue, and goods are open. It sees a read-only [`AllocView`] and answers with
//! [`Decisions`]: goods for some idle robots, and idle robots to send to charge now. A robot it
//! leaves out stays idle (or, when no goods are open, goes home to park).
//!
//! The built-ins, by the kebab-case names used in TOML, on the command line and in Python:
//!
//! | name | rule |
//! | --- | --- |
//! | `in-turn` | the paper's: idle robots in id order take the goods in queue order |
//! | `nearest` | goods in queue order, each to the nearest idle robot by route length |
//! | `hungarian` | the batch assignment with the least total route length to the goods |
//! | `auction` | sequential single-item auction on estimated completion time |
//! | `energy-aware` | never a task a robot cannot finish above the threshold; charged robots first |
//! | `min-cost` | the batch assignment with the least estimated Cost_total (distance, time, collisions) |

mod auction;
mod energy_aware;
pub mod hungarian;
mod in_turn;
mod min_cost;
mod nearest;

pub use auction::Auction;
pub use energy_aware::EnergyAware;
pub use hungarian::Hungarian;
pub use in_turn::InTurn;
pub use min_cost::MinCost;
pub use nearest::Nearest;

use crate::error::{Error, Result};
use crate::fleet::robot::{Robots, State, Target};
use crate::fleet::route::{self, route_nodes, service_place, service_target, Place};
use crate::ids::{CellId, GoodsId, NodeId, RobotId, NONE};
use crate::input::scenario::{CostWeights, Scenario};
use crate::world::graph::HighwayGraph;
use crate::world::layout::{Layout, NodeKind};

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

/// What an allocator answers at an allocation event. The engine checks the whole answer
/// before it carries any of it out (`goods_queue.rs`): every robot must be idle and appear at
/// most once (in `assign` or in `charge`), every goods must be open and appear at most once,
/// and a robot sent to charge must not be full. Robots in neither list stay idle until the
/// next allocation event (or go home when no goods are left).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Decisions {
    /// Goods for idle robots.
    pub assign: Vec<Assignment>,
    /// Idle robots sent to charge now, through the charging rule (`charging.rs`): to their
    /// home charger, or with shared chargers to the nearest free one (or its queue).
    pub charge: Vec<RobotId>,
}

impl Decisions {
    /// No decision: every idle robot waits.
    #[must_use]
    pub fn new() -> Decisions {
        Decisions::default()
    }

    /// Empties both lists, keeping their memory.
    pub fn clear(&mut self) {
        self.assign.clear();
        self.charge.clear();
    }

    /// Whether nothing was decided.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.assign.is_empty() && self.charge.is_empty()
    }
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
    /// People on the floor (docs/people.md): their x and y, px; empty without people.
    pub people_x: &'a [f64],
    pub people_y: &'a [f64],
}

/// The energy model a view reports: full, threshold, consumption per step, speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyModel {
    pub energy_full: f64,
    pub threshold: f64,
    pub consumption: f64,
    pub speed: f64,
}

impl<'a> AllocView<'a> {
    /// A view over a fleet outside a running simulation: for the Python adapter, which
    /// answers route queries from its own snapshot, and for tests of hand-made situations.
    #[must_use]
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        step: u64,
        idle: &'a [RobotId],
        goods: &'a [Goods],
        robots: &'a Robots,
        layout: &'a Layout,
        graph: &'a HighwayGraph,
        unload: NodeId,
        energy: EnergyModel,
    ) -> AllocView<'a> {
        AllocView {
            step,
            idle,
            goods,
            robots,
            layout,
            graph,
            unload,
            energy_full: energy.energy_full,
            threshold: energy.threshold,
            consumption: energy.consumption,
            speed: energy.speed,
            people_x: &[],
            people_y: &[],
        }
    }

    /// The same view with the people on the floor, so a strategy can steer robots away from
    /// busy aisles.
    #[must_use]
    pub fn with_people(mut self, people: Option<&'a crate::people::People>) -> AllocView<'a> {
        if let Some(p) = people {
            self.people_x = &p.x;
            self.people_y = &p.y;
        }
        self
    }
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

    /// The same numbers as [`AllocView::energy_model`], named.
    #[must_use]
    pub fn energy_params(&self) -> EnergyModel {
        EnergyModel { energy_full: self.energy_full, threshold: self.threshold, consumption: self.consumption, speed: self.speed }
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

    /// The highway graph and its routing table.
    #[must_use]
    pub fn graph(&self) -> &HighwayGraph {
        self.graph
    }

    /// The whole fleet's columns (read-only), for strategies that look at other robots.
    #[must_use]
    pub fn robots(&self) -> &Robots {
        self.robots
    }

    /// Where a robot is, for route planning.
    #[must_use]
    pub fn place(&self, r: RobotId) -> Place {
        Place::of(self.robots, r.index())
    }

    /// Whether the threshold rule marked a robot to charge after it unloads.
    #[must_use]
    pub fn marked(&self, r: RobotId) -> bool {
        self.robots.marked[r.index()]
    }

    /// Length in px of the rest of a robot's current route (0 when it is not travelling).
    #[must_use]
    pub fn remaining_length(&self, r: RobotId) -> f64 {
        let pts = route::remaining(self.robots, self.graph, r.index());
        pts.windows(2).map(|w| route::dist(w[0].0, w[0].1, w[1].0, w[1].1)).sum()
    }

    /// Route length in px from a robot's position to a cell's service point.
    #[must_use]
    pub fn route_length(&self, r: RobotId, cell: CellId) -> f64 {
        route::length(self.graph, Place::of(self.robots, r.index()), service_target(self.layout, cell))
    }

    /// Route length in px from a cell's service point to the unloading zone.
    #[must_use]
    pub fn cell_to_unload(&self, cell: CellId) -> f64 {
        route::length(self.graph, service_place(self.layout, cell), Target::Node(self.unload))
    }

    /// Route length in px from the unloading zone to a robot's home charger.
    #[must_use]
    pub fn unload_to_home(&self, r: RobotId) -> f64 {
        self.graph.path_length(self.unload, self.robots.home[r.index()])
    }

    /// Traffic on the route of a task: how many times another robot's expected path meets
    /// the route robot `r` would drive to fetch `cell` and bring it to the unloading zone.
    ///
    /// It counts (other robot, highway node) pairs where the node is on `r`'s route and on
    /// the other robot's footprint: the rest of its current route, plus its way from its
    /// service point to the unloading zone if it has not loaded yet, plus the node it stands
    /// on (or, standing inside an edge to load, the node at the edge's head, since robots
    /// driving that edge queue behind it). Collisions in the paper model happen where paths
    /// meet, so this is a cheap proxy for the waits a task will cause. Chargers do not count.
    #[must_use]
    pub fn traffic(&self, r: RobotId, cell: CellId) -> u32 {
        let n = self.graph.len();
        let mut mine = vec![false; n];
        let mut buf = Vec::with_capacity(32);
        route_nodes(self.graph, Place::of(self.robots, r.index()), service_target(self.layout, cell), &mut buf);
        route_nodes(self.graph, service_place(self.layout, cell), Target::Node(self.unload), &mut buf);
        for &u in &buf {
            if self.layout.nodes[u as usize].kind == NodeKind::Highway {
                mine[u as usize] = true;
            }
        }
        let mut seen = vec![u32::MAX; n];
        let mut count = 0;
        for j in 0..self.robots.len() {
            if j == r.index() {
                continue;
            }
            buf.clear();
            self.footprint(j, &mut buf);
            for &u in &buf {
                // Each node counts once per other robot.
                if mine[u as usize] && seen[u as usize] != j as u32 {
                    seen[u as usize] = j as u32;
                    count += 1;
                }
            }
        }
        count
    }

    /// The highway nodes robot `j` is expected to occupy before it next becomes idle.
    pub(crate) fn footprint(&self, j: usize, out: &mut Vec<u32>) {
        let rb = self.robots;
        match rb.state[j] {
            State::Charging | State::Parked | State::Stranded | State::WaitCharger => return,
            _ => {}
        }
        if rb.at_node[j] != NONE {
            out.push(rb.at_node[j]);
        } else if rb.edge_v[j] != NONE {
            out.push(rb.edge_v[j]);
        }
        if rb.routing[j] && rb.wp_node[j] != NONE {
            let goal = NodeId(rb.goal[j]);
            let mut at = NodeId(rb.wp_node[j]);
            out.push(at.0);
            while at != goal {
                match self.graph.next_hop(at, goal) {
                    Some(v) => at = v,
                    None => break,
                }
                out.push(at.0);
            }
        }
        if matches!(rb.state[j], State::ToPickup | State::Loading) && rb.cell[j] != NONE {
            route_nodes(self.graph, service_place(self.layout, CellId(rb.cell[j])), Target::Node(self.unload), out);
        }
        out.retain(|&u| self.layout.nodes[u as usize].kind == NodeKind::Highway);
    }
}

/// A task-allocation strategy.
pub trait Allocator: Send + Sync {
    /// The strategy's kebab-case name, as in TOML, the command line and Python.
    fn name(&self) -> &str;

    /// Fills `out` (which the engine has cleared) with this event's decisions: assignments,
    /// and robots to send to charge. Each idle robot and each goods item may appear at most
    /// once.
    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> Result<()>;
}

/// What the built-ins take from the scenario beyond the view: dwell times, the charge rate
/// and the cost weights.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskModel {
    /// Steps at the service point.
    pub loading: u32,
    /// Steps on the unloading node.
    pub unloading: u32,
    /// Energy gained per step of charging.
    pub charge_rate: f64,
    /// w_d, w_t and w_c of Cost_total.
    pub weights: CostWeights,
}

impl TaskModel {
    /// The scenario's numbers.
    #[must_use]
    pub fn of(scenario: &Scenario) -> TaskModel {
        TaskModel {
            loading: scenario.dwell.loading,
            unloading: scenario.dwell.unloading,
            charge_rate: scenario.robot.charge_rate,
            weights: scenario.cost.clone(),
        }
    }

    /// Steps for robot `r` to fetch `cell` and unload it, if nothing is in its way: arrival
    /// ends a step, and each leg is rounded up to whole steps as the engine moves.
    #[must_use]
    pub fn task_steps(&self, view: &AllocView<'_>, r: RobotId, cell: CellId) -> f64 {
        let v = view.robots.speed[r.index()];
        (view.route_length(r, cell) / v).ceil() + f64::from(self.loading) + (view.cell_to_unload(cell) / v).ceil() + f64::from(self.unloading)
    }

    /// Robot `r`'s energy when it has unloaded `cell`, if nothing is in its way.
    #[must_use]
    pub fn energy_after(&self, view: &AllocView<'_>, r: RobotId, cell: CellId) -> f64 {
        view.energy(r) - self.task_steps(view, r, cell) * view.consumption
    }

    /// Steps lost to charging if robot `r` takes `cell`: none while it ends at or above the
    /// threshold; otherwise the time to charge from where it ends back to full (the threshold
    /// rule sends it to charge during or right after the task).
    #[must_use]
    pub fn charge_penalty(&self, view: &AllocView<'_>, r: RobotId, cell: CellId) -> f64 {
        let end = self.energy_after(view, r, cell);
        if end >= view.threshold {
            0.0
        } else {
            (view.energy_full - end.max(0.0)) / self.charge_rate
        }
    }
}

/// The built-in strategies' names.
pub const BUILT_INS: &[&str] = &["in-turn", "nearest", "hungarian", "auction", "energy-aware", "min-cost"];

/// The built-in strategy a scenario names, configured from the scenario (for example the
/// cost weights of `min-cost`).
pub fn built_in(scenario: &Scenario) -> Result<Box<dyn Allocator>> {
    let name = scenario.allocator.as_str();
    let model = TaskModel::of(scenario);
    match name {
        "in-turn" => Ok(Box::new(InTurn)),
        "nearest" => Ok(Box::new(Nearest)),
        "hungarian" => Ok(Box::new(Hungarian)),
        "auction" => Ok(Box::new(Auction::new(model))),
        "energy-aware" => Ok(Box::new(EnergyAware::new(model))),
        "min-cost" => Ok(Box::new(MinCost::new(model))),
        _ if name.contains(':') => Err(Error::scenario(
            "allocator",
            format!("\"{name}\""),
            "names a Python allocator (module:Class): run it through the Python package, not the engine alone",
        )),
        _ => {
            let hint = crate::error::did_you_mean(name, BUILT_INS).map_or(String::new(), |n| format!("did you mean \"{n}\"? "));
            Err(Error::scenario(
                "allocator",
                format!("\"{name}\""),
                format!("unknown strategy ({hint}built-ins: {}; or module:Class for a Python strategy)", BUILT_INS.join(", ")),
            ))
        }
    }
}
