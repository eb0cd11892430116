//! The original rules as a [`crate::rules::Simulation`] runs them: the authors' engine
//! ([`Original`]) with the figures it does not count itself (throughput windows, steady
//! figures, contacts), measured from what it exposes after each tick.

use crate::error::Result;
use crate::fleet::robot::Robots;
use crate::input::scenario::{CostWeights, MetricsParams, Scenario};
use crate::record::events::Event;
use crate::record::metrics::{Outcome, RobotStats, RunResult, Tally};
use crate::rules::original::Original;
use crate::rules::Engine;
use crate::world::World;
use std::sync::Arc;

/// The original rules with the figures they do not count themselves.
pub(crate) struct OriginalRun {
    o: Original,
    world: Arc<World>,
    tally: Tally,
    weights: CostWeights,
}

impl OriginalRun {
    /// The original rules on `scenario`, whose world is `world` (for viewers and replays).
    pub(crate) fn new(world: Arc<World>, scenario: &Scenario) -> Result<OriginalRun> {
        let o = Original::new(scenario)?;
        let metrics = MetricsParams { gridlock: 0, ..scenario.metrics.clone() };
        let tally = Tally::new(o.robots().len(), o.result().goods_total, &metrics);
        Ok(OriginalRun { o, world, tally, weights: scenario.cost.clone() })
    }

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
        // Contacts: every pair closer than r_i + r_j after the tick, moved or not, as under
        // the paper rules (docs/metrics.md); at most six robots, so every pair.
        let r = o.robots();
        let n = r.len();
        for i in 0..n {
            for j in i + 1..n {
                let d = crate::fleet::route::dist(r.x[i], r.y[i], r.x[j], r.y[j]);
                let contact = r.radius[i] + r.radius[j];
                if d <= contact + 8.0 {
                    t.closest = t.closest.min(d);
                }
                t.contacts += u64::from(d < contact);
            }
        }
    }

    fn measured_result(&self) -> RunResult {
        let mut tally = self.tally.clone();
        tally.stats.clone_from(self.o.stats());
        let own = self.o.result();
        tally.result(self.o.outcome(), own.stranded, self.o.robots().len(), &self.weights, None)
    }
}

impl Engine for OriginalRun {
    fn steps(&mut self, max: u64) -> Result<u64> {
        let mut k = 0;
        while k < max && self.outcome().is_none() {
            self.step()?;
            k += 1;
        }
        Ok(k)
    }
    fn step(&mut self) -> Result<()> {
        if !self.o.done() {
            self.o.step();
            self.measure();
        }
        Ok(())
    }
    fn result(&self) -> RunResult {
        self.measured_result()
    }
    fn t(&self) -> u64 {
        self.o.t()
    }
    fn outcome(&self) -> Option<Outcome> {
        self.o.outcome()
    }
    fn s(&self) -> u64 {
        self.o.s()
    }
    fn c(&self) -> u64 {
        self.o.c()
    }
    fn delivered(&self) -> u64 {
        self.o.delivered()
    }
    fn goods_total(&self) -> u64 {
        self.tally.goods_total
    }
    fn robots(&self) -> &Robots {
        self.o.robots()
    }
    fn stats(&self) -> &RobotStats {
        self.o.stats()
    }
    fn cells_full(&self) -> &[bool] {
        self.o.cells_full()
    }
    fn queue_cells(&self) -> Vec<u32> {
        self.o.queue_cells()
    }
    fn events(&self) -> &[Event] {
        self.o.events()
    }
    fn world(&self) -> &Arc<World> {
        &self.world
    }
    fn energy_levels(&self) -> (f64, f64) {
        self.o.energy_levels()
    }
    fn allocator_name(&self) -> &'static str {
        "in-turn"
    }
    fn route_of(&self, i: usize) -> Vec<(f64, f64)> {
        self.o.route_of(i)
    }
}
