//! A run, under any rule set: [`Simulation`] is the one façade that bindings, replays,
//! batches and viewers use, and never asks which rules run. Each rule set is a folder that
//! implements [`Engine`]: the paper rules (`paper/`, [`paper::Paper`], the default) and the
//! authors' original rules (`original/`, run with the figures they do not count themselves
//! by `original/measured.rs`). Batches of runs on worker threads are in `batch.rs`.
//!
//! Both rule sets report the same figures (`docs/metrics.md`).

pub mod batch;
pub mod grid;
pub mod original;
pub(crate) mod paper;
pub mod run;

pub use run::Run;

/// The paper rules' per-phase profile (`--features profiling`, `examples/phases.rs`).
#[cfg(feature = "profiling")]
pub use paper::profile;

use crate::alloc::{self, Allocator};
use crate::error::Result;
use crate::fleet::robot::Robots;
use crate::input::csv::Tables;
use crate::input::scenario::{Rules, Scenario};
use crate::people::People;
use crate::record::events::Event;
use crate::record::frame::{energy_word, heading_byte, Frame, FrameSink, Summary, MARKED};
use crate::record::metrics::{Outcome, RobotStats, RunResult};
use crate::record::resources::{QueueLog, Queues};
use crate::world::World;
use original::measured::OriginalRun;
use paper::Paper;
use serde_json::{json, Value};
use std::sync::Arc;

/// What a rule set's engine answers: how it steps, and what it shows of its state. A
/// [`Simulation`] forwards to it; nothing outside asks which rule set runs.
pub(crate) trait Engine: Send {
    /// Up to `max` steps, fewer if the run ends first; how many ran.
    fn steps(&mut self, max: u64) -> Result<u64>;
    /// One step; nothing once the run has ended.
    fn step(&mut self) -> Result<()>;
    /// The indicators and per-robot statistics so far.
    fn result(&self) -> RunResult;
    /// The current step (0 before the first).
    fn t(&self) -> u64;
    /// The run's outcome, once it has ended.
    fn outcome(&self) -> Option<Outcome>;
    /// Whether the run has ended.
    fn done(&self) -> bool {
        self.outcome().is_some()
    }
    /// Collisions S so far.
    fn s(&self) -> u64;
    /// Charging count C so far.
    fn c(&self) -> u64;
    /// Goods delivered so far.
    fn delivered(&self) -> u64;
    /// Goods in the task list (orders so far, in lifelong runs).
    fn goods_total(&self) -> u64;
    /// The fleet's columns.
    fn robots(&self) -> &Robots;
    /// The people on the floor, if the rules have any.
    fn people(&self) -> Option<&People> {
        None
    }
    /// Per-robot statistics so far.
    fn stats(&self) -> &RobotStats;
    /// Which cells hold goods.
    fn cells_full(&self) -> &[bool];
    /// The cells of the goods not yet taken, front first.
    fn queue_cells(&self) -> Vec<u32>;
    /// Events of the last step.
    fn events(&self) -> &[Event];
    /// The layout and graph.
    fn world(&self) -> &Arc<World>;
    /// Full energy and the threshold.
    fn energy_levels(&self) -> (f64, f64);
    /// The allocator's name.
    fn allocator_name(&self) -> &str;
    /// Robot `i`'s remaining route as waypoints, starting at its position.
    fn route_of(&self, i: usize) -> Vec<(f64, f64)>;
    /// The queues of the last step, as the resources report counts them (none where the
    /// rules report no resources).
    fn queues(&self) -> Queues {
        Queues::default()
    }
}

/// What a scenario should be told before it runs: one line each, with the numbers and what
/// would mend it (a fleet its chargers cannot keep charged, `rules/paper/balance.rs`). None
/// for a scenario that can run as it is.
pub fn warnings(scenario: &Scenario) -> Result<Vec<String>> {
    let world = World::of(scenario)?;
    let resolved = scenario.resolved(world.layout.departure.len());
    Ok(paper::balance::warnings(&resolved, &world))
}

/// The scenario with every "auto" choice made for the layout it names
/// ([`Scenario::resolved`]): what a run of it will do.
pub fn resolved(scenario: &Scenario) -> Result<Scenario> {
    let layout = crate::world::resolve_layout(scenario)?;
    Ok(scenario.resolved(layout.departure.len()))
}

/// A run in progress.
pub struct Simulation {
    rules: RuleSet,
}

enum RuleSet {
    Paper(Box<Paper>),
    Original(Box<OriginalRun>),
}

impl Simulation {
    /// A run of `scenario` with its named built-in allocator.
    pub fn new(scenario: &Scenario) -> Result<Simulation> {
        // The allocator first, as the Python `Scenario.validate` names it first.
        let allocator = alloc::built_in(scenario)?;
        Simulation::with_allocator(scenario, allocator)
    }

    /// A run of `scenario` with a given allocator (such as one written in Python).
    pub fn with_allocator(scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Simulation> {
        scenario.check_values()?;
        Simulation::build(World::of(scenario)?, &Tables::default(), scenario, allocator)
    }

    /// A run on an already built world, with any allocator.
    pub fn with_world(world: Arc<World>, scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Simulation> {
        scenario.check_values()?;
        Simulation::build(world, &Tables::default(), scenario, allocator)
    }

    /// The one way in, for a scenario whose values are checked, with the CSV tables its runs
    /// have read (`input/csv.rs`).
    pub(crate) fn build(world: Arc<World>, tables: &Tables, scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Simulation> {
        // Every "auto" choice made for this layout, once: the rules below see only choices.
        let scenario = &scenario.resolved(world.layout.departure.len());
        let rules = match scenario.rules {
            Rules::Paper => RuleSet::Paper(Box::new(Paper::build(world, tables, scenario, allocator)?)),
            Rules::Original => {
                original::check_allocator(allocator.name())?;
                RuleSet::Original(Box::new(OriginalRun::new(world, scenario)?))
            }
        };
        Ok(Simulation { rules })
    }

    /// The rule set's engine: every accessor below reads through it.
    fn engine(&self) -> &dyn Engine {
        match &self.rules {
            RuleSet::Paper(p) => &**p,
            RuleSet::Original(r) => &**r,
        }
    }

    fn engine_mut(&mut self) -> &mut dyn Engine {
        match &mut self.rules {
            RuleSet::Paper(p) => &mut **p,
            RuleSet::Original(r) => &mut **r,
        }
    }

    /// Runs until the run ends.
    pub fn run(&mut self) -> Result<RunResult> {
        self.steps(u64::MAX)?;
        Ok(self.result())
    }

    /// Runs up to `max` steps, fewer if the run ends first; returns how many ran. The same
    /// as calling [`Simulation::step`] that often, to the bit, and faster where the paper
    /// rules can cruise through quiet steps.
    pub fn steps(&mut self, max: u64) -> Result<u64> {
        self.engine_mut().steps(max)
    }

    /// Runs one step (one timer tick under the original rules). Does nothing once the run has
    /// ended.
    pub fn step(&mut self) -> Result<()> {
        self.engine_mut().step()
    }

    /// The indicators and per-robot statistics so far.
    #[must_use]
    pub fn result(&self) -> RunResult {
        self.engine().result()
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
    pub(crate) fn paper(&self) -> Option<&Paper> {
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

    /// The current step (0 before the first).
    #[must_use]
    pub fn t(&self) -> u64 {
        self.engine().t()
    }
    /// Whether the run has ended.
    #[must_use]
    pub fn done(&self) -> bool {
        self.engine().done()
    }
    /// The run's outcome, once it has ended.
    #[must_use]
    pub fn outcome(&self) -> Option<Outcome> {
        self.engine().outcome()
    }
    /// Collisions S so far.
    #[must_use]
    pub fn s(&self) -> u64 {
        self.engine().s()
    }
    /// Charging count C so far.
    #[must_use]
    pub fn c(&self) -> u64 {
        self.engine().c()
    }
    /// Goods delivered so far.
    #[must_use]
    pub fn delivered(&self) -> u64 {
        self.engine().delivered()
    }
    /// Goods in the task list (orders so far, in lifelong runs).
    #[must_use]
    pub fn goods_total(&self) -> u64 {
        self.engine().goods_total()
    }
    /// The fleet's columns.
    #[must_use]
    pub fn robots(&self) -> &Robots {
        self.engine().robots()
    }
    /// The people on the floor (docs/people.md), if the scenario has any.
    #[must_use]
    pub fn people(&self) -> Option<&People> {
        self.engine().people()
    }
    /// Per-robot statistics so far.
    #[must_use]
    pub fn stats(&self) -> &RobotStats {
        self.engine().stats()
    }
    /// Which cells hold goods.
    #[must_use]
    pub fn cells_full(&self) -> &[bool] {
        self.engine().cells_full()
    }
    /// The cells of the goods not yet taken, front first.
    #[must_use]
    pub fn queue_cells(&self) -> Vec<u32> {
        self.engine().queue_cells()
    }
    /// Events of the last step.
    #[must_use]
    pub fn events(&self) -> &[Event] {
        self.engine().events()
    }
    /// The layout and graph.
    #[must_use]
    pub fn world(&self) -> &Arc<World> {
        self.engine().world()
    }
    /// Full energy and the threshold.
    #[must_use]
    pub fn energy_levels(&self) -> (f64, f64) {
        self.engine().energy_levels()
    }
    /// The allocator's name.
    #[must_use]
    pub fn allocator_name(&self) -> &str {
        self.engine().allocator_name()
    }
    /// Robot `i`'s remaining route as waypoints, starting at its position.
    #[must_use]
    pub fn route_of(&self, i: usize) -> Vec<(f64, f64)> {
        self.engine().route_of(i)
    }
    /// The robots queued in the last step, at each node and for a shared charger, counted as
    /// the result's `resources` count them (`record/resources.rs`): what viewers draw.
    #[must_use]
    pub fn queues(&self) -> Queues {
        self.engine().queues()
    }
}

/// Every engine of the continuous model keeps the run contract through what it shows: the
/// paper rules' and the original rules' alike.
impl<E: Engine + ?Sized> Run for E {
    fn advance(&mut self, max: u64, sink: Option<&mut dyn FrameSink>) -> Result<u64> {
        let Some(sink) = sink else { return Engine::steps(self, max) };
        // Step by step: a frame of every step (no cruising past one).
        let mut frame = Frame::default();
        let mut k = 0;
        while k < max && !Engine::done(self) {
            Engine::step(self)?;
            self.emit(&mut frame, true);
            sink.frame(&frame)?;
            k += 1;
        }
        Ok(k)
    }

    fn time(&self) -> u64 {
        self.t()
    }

    fn done(&self) -> bool {
        Engine::done(self)
    }

    fn emit(&self, f: &mut Frame, events: bool) {
        f.clear();
        let r = self.robots();
        let full = self.energy_levels().0;
        f.counters = [self.s() as u32, self.c() as u32, self.delivered() as u32];
        f.x.extend(r.x.iter().map(|&v| v as f32));
        f.y.extend(r.y.iter().map(|&v| v as f32));
        f.energy.extend(r.energy.iter().map(|&e| energy_word(e, full)));
        f.heading.extend(r.heading.iter().map(|&a| heading_byte(a)));
        f.state.extend(r.state.iter().zip(&r.marked).map(|(&s, &m)| s as u8 | if m { MARKED } else { 0 }));
        if let Some(p) = self.people() {
            f.people_x.extend(p.x.iter().map(|&v| v as f32));
            f.people_y.extend(p.y.iter().map(|&v| v as f32));
        }
        // Events belong to a step: frame 0, before the first, shows none (the original rules'
        // dispatch at the start included).
        if events && self.t() > 0 {
            f.events.extend(self.events().iter().map(|e| [e.kind.code(), e.robot, e.cell]));
        }
        f.queues = Some(self.queues());
    }

    fn describe(&self) -> Value {
        let (energy_full, threshold) = self.energy_levels();
        let r = self.robots();
        let mut h = json!({
            "robots": r.len(),
            "radius": r.radius,
            "home": r.home.iter().map(|h| h.0).collect::<Vec<_>>(),
            "energy_full": energy_full,
            "threshold": threshold,
            "cells_full": self.cells_full().iter().map(|&f| u8::from(f)).collect::<Vec<_>>(),
            "goods_total": self.goods_total(),
            "layout": self.world().layout.to_json(),
        });
        if let Some(p) = self.people() {
            // The people section of each chunk (crate::output::codec), and what the viewer draws.
            h["humans"] = json!({"count": p.len(), "radius": p.radius, "zones": p.zone_radii()});
        }
        h
    }

    fn summary(&self) -> Summary {
        let r = self.result();
        Summary {
            t: r.t,
            s: r.s,
            c: r.c,
            outcome: r.outcome.map_or("running", Outcome::as_str),
            delivered: r.delivered,
            window: r.window,
            windows: r.windows,
            resources: r.resources,
            bottleneck: r.bottleneck,
        }
    }

    fn queue_log(&self) -> Option<QueueLog> {
        Some(QueueLog::new(&self.world().layout))
    }
}

/// A simulation keeps the run contract through the engine of its rules.
impl Run for Simulation {
    fn advance(&mut self, max: u64, sink: Option<&mut dyn FrameSink>) -> Result<u64> {
        self.engine_mut().advance(max, sink)
    }
    fn time(&self) -> u64 {
        self.engine().time()
    }
    fn done(&self) -> bool {
        Run::done(self.engine())
    }
    fn emit(&self, frame: &mut Frame, events: bool) {
        self.engine().emit(frame, events);
    }
    fn describe(&self) -> Value {
        self.engine().describe()
    }
    fn summary(&self) -> Summary {
        self.engine().summary()
    }
    fn queue_log(&self) -> Option<QueueLog> {
        self.engine().queue_log()
    }
}
