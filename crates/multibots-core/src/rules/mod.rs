//! A run, under either rule set: the paper rules ([`crate::rules::paper::Paper`], the default) or the
//! authors' original rules ([`crate::rules::original::Original`]). Bindings, replays, batches and
//! viewers use this type and never ask which rules run.
//!
//! Both rule sets report the same figures (`docs/metrics.md`): under the original rules the
//! throughput windows, steady figures and contacts are measured here, from what the rules
//! expose after each tick.

pub mod batch;
pub mod original;
pub mod paper;

use crate::alloc::{self, Allocator};
use crate::error::{Error, Result};
use crate::fleet::robot::{Robots, Target};
use crate::ids::NodeId;
use crate::input::scenario::{CostWeights, MetricsParams, Rules, Scenario};
use crate::output::events::Event;
use crate::output::metrics::{Outcome, RobotStats, RunResult, Tally};
use crate::rules::original::Original;
use crate::rules::paper::Paper;
use crate::world::World;
use std::sync::Arc;

/// A run in progress.
pub struct Simulation {
    rules: RuleSet,
}

enum RuleSet {
    Paper(Box<Paper>),
    Original(Box<OriginalRun>),
}

/// The original rules with the figures they do not count themselves.
struct OriginalRun {
    o: Original,
    world: Arc<World>,
    tally: Tally,
    weights: CostWeights,
    /// Positions after the previous tick, to know who moved.
    last: Vec<(f64, f64)>,
}

impl Simulation {
    /// A run of `scenario` with its named built-in allocator.
    pub fn new(scenario: &Scenario) -> Result<Simulation> {
        // The allocator first, as the Python `Scenario.validate` names it first.
        let allocator = alloc::built_in(scenario)?;
        scenario.check_values()?;
        Simulation::with_world(World::of(scenario)?, scenario, allocator)
    }

    /// A run of `scenario` with a given allocator (such as one written in Python).
    pub fn with_allocator(scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Simulation> {
        scenario.check_values()?;
        Simulation::with_world(World::of(scenario)?, scenario, allocator)
    }

    /// A run on an already built world, with any allocator.
    pub fn with_world(world: Arc<World>, scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Simulation> {
        let rules = match scenario.rules {
            Rules::Paper => RuleSet::Paper(Box::new(Paper::with_world(world, scenario, allocator)?)),
            Rules::Original => {
                if allocator.name() != "in-turn" {
                    return Err(Error::scenario("allocator", format!("\"{}\"", allocator.name()), "the original rules dispatch in turn only (in-turn)"));
                }
                let o = Original::new(scenario)?;
                let last = o.robots().x.iter().zip(&o.robots().y).map(|(&x, &y)| (x, y)).collect();
                let metrics = MetricsParams { gridlock: 0, ..scenario.metrics.clone() };
                let tally = Tally::new(o.robots().len(), o.result().goods_total, &metrics);
                RuleSet::Original(Box::new(OriginalRun { o, world, tally, weights: scenario.cost.clone(), last }))
            }
        };
        Ok(Simulation { rules })
    }

    /// Runs until the run ends.
    pub fn run(&mut self) -> Result<RunResult> {
        self.steps(u64::MAX)?;
        Ok(self.result())
    }

    /// Runs up to `max` steps, fewer if the run ends first; returns how many ran. The same
    /// as calling [`Simulation::step`] that often, to the bit, and faster where the paper
    /// rules can cruise through quiet steps (see [`Paper::steps`]).
    pub fn steps(&mut self, max: u64) -> Result<u64> {
        match &mut self.rules {
            RuleSet::Paper(p) => p.steps(max),
            RuleSet::Original(_) => {
                let mut k = 0;
                while k < max && !self.done() {
                    self.step()?;
                    k += 1;
                }
                Ok(k)
            }
        }
    }

    /// Runs one step (one timer tick under the original rules). Does nothing once the run has
    /// ended.
    pub fn step(&mut self) -> Result<()> {
        match &mut self.rules {
            RuleSet::Paper(p) => p.step(),
            RuleSet::Original(r) => {
                if r.o.done() {
                    return Ok(());
                }
                r.o.step();
                r.measure();
                Ok(())
            }
        }
    }

    /// The indicators and per-robot statistics so far.
    #[must_use]
    pub fn result(&self) -> RunResult {
        match &self.rules {
            RuleSet::Paper(p) => p.result(),
            RuleSet::Original(r) => r.result(),
        }
    }

    /// The rule set running.
    #[must_use]
    pub fn rules(&self) -> Rules {
        match &self.rules {
            RuleSet::Paper(_) => Rules::Paper,
            RuleSet::Original(_) => Rules::Original,
        }
    }

    /// The paper rules' engine, when they run (for the engine's own tests and tools).
    #[must_use]
    pub fn paper(&self) -> Option<&Paper> {
        match &self.rules {
            RuleSet::Paper(p) => Some(p),
            RuleSet::Original(_) => None,
        }
    }

    /// The paper rules' engine, mutable, when they run (decision points, `decision_point.rs`).
    pub(crate) fn paper_mut(&mut self) -> Option<&mut Paper> {
        match &mut self.rules {
            RuleSet::Paper(p) => Some(p),
            RuleSet::Original(_) => None,
        }
    }

    /// The original rules' engine, when they run.
    #[must_use]
    pub fn original(&self) -> Option<&Original> {
        match &self.rules {
            RuleSet::Paper(_) => None,
            RuleSet::Original(r) => Some(&r.o),
        }
    }

    /// The current step (0 before the first).
    #[must_use]
    pub fn t(&self) -> u64 {
        match &self.rules {
            RuleSet::Paper(p) => p.t(),
            RuleSet::Original(r) => r.o.t(),
        }
    }
    /// Whether the run has ended.
    #[must_use]
    pub fn done(&self) -> bool {
        self.outcome().is_some()
    }
    /// The run's outcome, once it has ended.
    #[must_use]
    pub fn outcome(&self) -> Option<Outcome> {
        match &self.rules {
            RuleSet::Paper(p) => p.outcome(),
            RuleSet::Original(r) => r.o.outcome(),
        }
    }
    /// Collisions S so far.
    #[must_use]
    pub fn s(&self) -> u64 {
        match &self.rules {
            RuleSet::Paper(p) => p.s(),
            RuleSet::Original(r) => r.o.s(),
        }
    }
    /// Charging count C so far.
    #[must_use]
    pub fn c(&self) -> u64 {
        match &self.rules {
            RuleSet::Paper(p) => p.c(),
            RuleSet::Original(r) => r.o.c(),
        }
    }
    /// Goods delivered so far.
    #[must_use]
    pub fn delivered(&self) -> u64 {
        match &self.rules {
            RuleSet::Paper(p) => p.delivered(),
            RuleSet::Original(r) => r.o.delivered(),
        }
    }
    /// Goods in the task list (orders so far, in lifelong runs).
    #[must_use]
    pub fn goods_total(&self) -> u64 {
        match &self.rules {
            RuleSet::Paper(p) => p.goods_total(),
            RuleSet::Original(r) => r.tally.goods_total,
        }
    }
    /// The fleet's columns.
    #[must_use]
    pub fn robots(&self) -> &Robots {
        match &self.rules {
            RuleSet::Paper(p) => p.robots(),
            RuleSet::Original(r) => r.o.robots(),
        }
    }
    /// The people on the floor (docs/people.md), if the scenario has any.
    #[must_use]
    pub fn people(&self) -> Option<&crate::people::People> {
        match &self.rules {
            RuleSet::Paper(p) => p.people.as_deref(),
            RuleSet::Original(_) => None,
        }
    }

    /// Per-robot statistics so far.
    #[must_use]
    pub fn stats(&self) -> &RobotStats {
        match &self.rules {
            RuleSet::Paper(p) => p.stats(),
            RuleSet::Original(r) => r.o.stats(),
        }
    }
    /// Which cells hold goods.
    #[must_use]
    pub fn cells_full(&self) -> &[bool] {
        match &self.rules {
            RuleSet::Paper(p) => p.cells_full(),
            RuleSet::Original(r) => r.o.cells_full(),
        }
    }
    /// The cells of the goods not yet taken, front first.
    #[must_use]
    pub fn queue_cells(&self) -> Vec<u32> {
        match &self.rules {
            RuleSet::Paper(p) => p.queue().iter().map(|g| g.cell.0).collect(),
            RuleSet::Original(r) => r.o.queue_cells(),
        }
    }
    /// Events of the last step.
    #[must_use]
    pub fn events(&self) -> &[Event] {
        match &self.rules {
            RuleSet::Paper(p) => p.events(),
            RuleSet::Original(r) => r.o.events(),
        }
    }
    /// The layout and graph.
    #[must_use]
    pub fn world(&self) -> &Arc<World> {
        match &self.rules {
            RuleSet::Paper(p) => p.world(),
            RuleSet::Original(r) => &r.world,
        }
    }
    /// Full energy and the threshold.
    #[must_use]
    pub fn energy_levels(&self) -> (f64, f64) {
        match &self.rules {
            RuleSet::Paper(p) => p.energy_levels(),
            RuleSet::Original(r) => r.o.energy_levels(),
        }
    }
    /// The allocator's name.
    #[must_use]
    pub fn allocator_name(&self) -> &str {
        match &self.rules {
            RuleSet::Paper(p) => p.allocator_name(),
            RuleSet::Original(_) => "in-turn",
        }
    }
    /// Robot `i`'s remaining route as waypoints, starting at its position.
    #[must_use]
    pub fn route_of(&self, i: usize) -> Vec<(f64, f64)> {
        match &self.rules {
            RuleSet::Paper(p) => p.route_of(i),
            RuleSet::Original(r) => r.o.route_of(i),
        }
    }
    /// Route length from a node to a target under the paper's routing, for callers outside
    /// the step loop.
    #[must_use]
    pub fn route_length_from_node(&self, from: NodeId, target: Target) -> f64 {
        crate::fleet::route::length(&self.world().graph, crate::fleet::route::Place::node(&self.world().graph, from), target)
    }
    /// Whether a node is a charger.
    #[must_use]
    pub fn is_charger(&self, n: NodeId) -> bool {
        self.world().is_charger(n)
    }
}

impl OriginalRun {
    /// After a tick: the counters, windows, warm-up and contacts.
    fn measure(&mut self) {
        let (o, t) = (&self.o, &mut self.tally);
        t.t = o.t();
        t.s = o.s();
        t.c = o.c();
        t.delivered = o.delivered();
        if t.t == t.warmup() {
            t.stats.clone_from(o.stats());
        }
        t.end_step(true, false);
        // Contacts: at most six robots, so every pair.
        let r = o.robots();
        let n = r.len();
        for i in 0..n {
            let moved_i = (r.x[i], r.y[i]) != self.last[i];
            for j in i + 1..n {
                if !moved_i && (r.x[j], r.y[j]) == self.last[j] {
                    continue;
                }
                let d = crate::fleet::route::dist(r.x[i], r.y[i], r.x[j], r.y[j]);
                let contact = r.radius[i] + r.radius[j];
                if d <= contact + 8.0 {
                    t.closest = t.closest.min(d);
                }
                t.contacts += u64::from(d < contact);
            }
        }
        for (i, p) in self.last.iter_mut().enumerate() {
            *p = (r.x[i], r.y[i]);
        }
    }

    fn result(&self) -> RunResult {
        let mut tally = self.tally.clone();
        tally.stats.clone_from(self.o.stats());
        let own = self.o.result();
        tally.result(self.o.outcome(), own.stranded, self.o.robots().len(), &self.weights, None)
    }
}
