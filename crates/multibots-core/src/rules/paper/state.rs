//! The state of a run under the paper rules, split by concern so that each phase of the step
//! takes the parts it touches as arguments (`pipeline.rs`), and none can reach the rest:
//!
//! - the fleet's columns, [`crate::fleet::robot::Robots`];
//! - the goods: the queue, the stocked cells and lifelong orders, and the hand-out's buffers
//!   ([`super::goods_queue::GoodsQueue`]);
//! - where robots go besides the goods: homes and chargers ([`Stations`]);
//! - what the run records: the tally, this step's events, the resources' use, the outcome
//!   ([`Record`]);
//! - people on the floor ([`Crowd`]);
//! - the pipeline's own buffers, rebuilt or carried from step to step
//!   ([`super::pipeline::Pipeline`]).
//!
//! The world and the model's numbers ([`super::Params`]) never change during a run.

use crate::fleet::placement::Homes;
use crate::fleet::robot::Robots;
use crate::input::scenario::CostWeights;
use crate::people::People;
use crate::record::events::{Event, EventKind};
use crate::record::metrics::{Outcome, Tally};
use crate::rules::paper::charging::Chargers;

/// Where robots go besides the goods: where each parks (and each cell's unloading zone), and
/// the chargers.
#[derive(Clone, Debug)]
pub(crate) struct Stations {
    pub homes: Homes,
    pub chargers: Chargers,
}

/// What the run records, and how its result is reported.
pub(crate) struct Record {
    /// T, S, C and the rest, so far (the step count `tally.t` too).
    pub tally: Tally,
    /// This step's events.
    pub events: Vec<Event>,
    /// The verdict, once phase 8 gives one.
    pub outcome: Option<Outcome>,
    /// How busy each resource was, and its queues (`record/resources.rs`); the nodes that
    /// are unloading zones or chargers.
    pub usage: crate::record::resources::Usage,
    pub service_nodes: Vec<bool>,
    /// What the scenario chose, which the bottleneck's remedy depends on.
    pub setting: crate::record::resources::Setting,
    pub cost_weights: CostWeights,
}

impl Record {
    /// An event of robot `i` at this step.
    pub fn event(&mut self, kind: EventKind, robot: usize, cell: u32) {
        self.events.push(Event { step: self.tally.t, kind, robot: robot as u32, cell });
    }

    /// This step's use of the resources (`waits`: who waits, phase 3's answer), counted
    /// `times` times (runs of quiet steps).
    pub fn observe_resources(&mut self, robots: &Robots, waits: &[bool], times: u64) {
        self.usage.observe(robots, waits, &self.service_nodes, times);
    }
}

/// People on the floor (docs/people.md); `None`: none, and every rule as without them.
pub(crate) struct Crowd {
    pub people: Option<Box<People>>,
    /// The same people with the fleet removed, stepped beside the run: output only (what
    /// robots cost people, docs/people.md); nothing of the run reads it.
    pub alone: Option<Box<People>>,
}

impl Crowd {
    /// The people guard, before robots move: robots with a person ahead stop, or slow down
    /// ([`People::guard`]; `wants`: who wants to move).
    pub fn guard(&mut self, robots: &Robots, wants: &[bool]) {
        if let Some(people) = self.people.as_deref_mut() {
            people.guard(robots, wants);
        }
    }

    /// After the robots moved: people walk, pick or rest ([`People::step`]).
    pub fn walk(&mut self, robots: &Robots) {
        if let Some(people) = self.people.as_deref_mut() {
            people.step(robots);
        }
    }

    /// The same people on a floor with no robot take their step ([`People::step_alone`]).
    pub fn walk_alone(&mut self) {
        if let Some(alone) = self.alone.as_deref_mut() {
            alone.step_alone();
        }
    }
}
