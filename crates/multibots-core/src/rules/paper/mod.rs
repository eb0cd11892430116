//! The paper rules (`rules = "paper"`, `docs/model.md`): the engine [`Paper`], and the step,
//! the phases of the model in their order (spec section 4). The step is a pipeline
//! (`pipeline.rs`): one function calls the phases in this order, each taking as arguments
//! the parts of the run's state it touches (`state.rs` splits them by concern).
//!
//! | spec | `Phase` | what | where |
//! | --- | --- | --- | --- |
//! | 0 | `Arrive` | the step count; lifelong orders and restocks arrive | `goods_queue.rs`, `lifelong.rs` |
//! | 1 | `HandOut` | idle robots get goods or go to charge, or go home | `goods_queue.rs`, [`crate::alloc`] (or a caller, `decision_point.rs`) |
//! | 2 | `Intend` | who wants to move, and where each is heading; who stands in a bay | `intend.rs`, [`crate::fleet::bay`] |
//! | – | `PeopleGuard` | robots stop, or slow down, for people near them | [`crate::people`] |
//! | 3 | `Decide` | collision waiting, or a traffic policy; robots step into and out of bays | `moves.rs`, [`crate::collision`], [`crate::traffic`] |
//! | 4–6 | `Travel` | the count S; travel along the routes; dwell counters, charging and consumption | `moves.rs`, [`crate::fleet::route`], `params.rs` |
//! | – | `Contacts` | contacts after the moves | `moves.rs`, [`crate::collision`] |
//! | – | `PeopleWalk` | people walk, pick or rest; the safety figures | [`crate::people`] |
//! | – | `PeopleAloneWalk` | the same people on a floor with no robot (output only) | [`crate::people`] |
//! | 7 | `Tasks` | the task cycle, then the charging rules | `tasks.rs`, `charging.rs` |
//! | 8 | `End` | completion, stalls, then the step limit; the result | `end.rs` |
//!
//! Stretches of quiet steps run in one pass (`cruise.rs`). Start positions, parking and
//! unloading zones are in [`crate::fleet::placement`]; what T, S, C and the other figures mean
//! in [`crate::record::metrics`].

pub(crate) mod balance;
pub(crate) mod charging;
mod cruise;
pub mod decision_point;
mod end;
pub(crate) mod goods_queue;
mod intend;
pub mod lifelong;
mod moves;
mod params;
mod pipeline;
#[cfg(feature = "profiling")]
pub mod profile;
mod state;
mod tasks;

use params::livelock_after;
pub(crate) use params::Params;

use crate::alloc::Allocator;
use crate::error::{Error, Result};
use crate::fleet::placement;
use crate::fleet::robot::Robots;
use crate::fleet::route;
use crate::input::csv::Tables;
use crate::input::scenario::Scenario;
use crate::people::People;
use crate::record::events::Event;
use crate::record::metrics::{Outcome, RobotStats, RunResult, Tally};
use crate::rules::paper::goods_queue::GoodsQueue;
use crate::rules::Engine;
use crate::world::World;
use charging::{Asked, Chargers};
use pipeline::Pipeline;
use state::{Crowd, Record, Stations};
use std::sync::Arc;

/// The cells a scenario can ask for: its task list, and with Poisson orders every cell (CSV
/// orders are checked row by row when read).
fn asked_cells(scenario: &Scenario, tasks: &[u32], cell_count: usize) -> Vec<Asked> {
    let mut out: Vec<Asked> =
        tasks.iter().enumerate().map(|(i, &c)| Asked { field: format!("tasks[{i}]"), value: c.to_string(), note: String::new(), cell: c }).collect();
    if let Some(o) = scenario.orders.as_ref().filter(|o| o.rate > 0.0) {
        out.extend((0..cell_count as u32).map(|c| Asked {
            field: "orders.rate".into(),
            value: o.rate.to_string(),
            note: format!("orders may ask for cell {c}: "),
            cell: c,
        }));
    }
    out
}

/// A run under the paper rules (`rules = "paper"`), in progress, its state split by concern
/// (`state.rs`). Users drive it through [`crate::Simulation`], which also runs the original
/// rules.
pub(crate) struct Paper {
    world: Arc<World>,
    p: Params,
    robots: Robots,
    goods: GoodsQueue,
    stations: Stations,
    record: Record,
    crowd: Crowd,
    allocator: Box<dyn Allocator>,
    /// Set when a step failed part-way: the run cannot go on.
    failure: Option<String>,
    pipeline: Pipeline,
}

impl Paper {
    /// A run of `scenario` with its named built-in allocator (the crate's tests; users go
    /// through [`crate::Simulation`]).
    #[cfg(test)]
    pub(crate) fn new(scenario: &Scenario) -> Result<Paper> {
        scenario.check_values()?;
        let allocator = crate::alloc::built_in(scenario)?;
        Paper::build(World::of(scenario)?, &Tables::default(), scenario, allocator)
    }

    /// A run of `scenario` with a given allocator (the crate's tests).
    #[cfg(test)]
    pub(crate) fn with_allocator(scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Paper> {
        scenario.check_values()?;
        Paper::build(World::of(scenario)?, &Tables::default(), scenario, allocator)
    }

    /// A run on an already built world, with any allocator, for a scenario whose values
    /// [`Scenario::check_values`] has passed: [`crate::Simulation`]'s one way in, and the
    /// learning environments'.
    pub(crate) fn build(world: Arc<World>, tables: &Tables, scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Paper> {
        let scenario = &scenario.resolved(world.layout.departure.len());
        let layout = &world.layout;
        let unload = placement::unload_zone(layout, &scenario.unload)?;
        let starts = placement::start_nodes(layout, scenario)?;
        let cells = scenario.cells(layout.cells.len())?;
        let (robots, homes) = placement::place(&world, scenario, &starts, unload)?;
        charging::check_reach(&world, scenario, &homes, &asked_cells(scenario, &cells, layout.cells.len()))?;
        let csv = match scenario.orders.as_ref().and_then(|o| o.csv.as_ref()) {
            Some(path) => lifelong::orders_csv(tables, std::path::Path::new(path), layout.cells.len())?,
            None => Vec::new(),
        };
        let n = robots.len();
        let goods = GoodsQueue::new(layout.cells.len(), &cells, scenario.orders.as_ref(), csv);
        let people = match &scenario.humans {
            Some(h) => People::new(h, &world, tables, &robots, scenario.collision.margin)?.map(Box::new),
            None => None,
        };
        let alone = people.as_ref().map(|p| Box::new(p.alone()));
        let record = Record {
            tally: Tally::new(n, goods.queue.len() as u64, &scenario.metrics).with_livelock_after(livelock_after(scenario)),
            events: Vec::new(),
            outcome: None,
            usage: crate::record::resources::Usage::new(&world.layout),
            service_nodes: {
                let mut v = vec![false; world.layout.nodes.len()];
                for n in world.layout.unloading.iter().chain(&world.layout.chargers) {
                    v[n.index()] = true;
                }
                v
            },
            setting: crate::record::resources::Setting {
                generated: scenario.layout_generate.clone(),
                shared_chargers: scenario.charging.chargers == crate::input::scenario::ChargerUse::Shared,
                staggered: scenario.charging.policy == crate::input::scenario::ChargingPolicy::Staggered,
                unload_nearest: scenario.unload == crate::input::scenario::Unload::Nearest,
                reserve: scenario.traffic == crate::input::scenario::Traffic::Reserve,
            },
            cost_weights: scenario.cost.clone(),
        };
        Ok(Paper {
            pipeline: Pipeline::new(&world, scenario, &robots, homes.spread()),
            p: Params::of(scenario),
            stations: Stations { chargers: Chargers::new(&world, scenario), homes },
            crowd: Crowd { people, alone },
            goods,
            record,
            allocator,
            failure: None,
            robots,
            world,
        })
    }

    /// Runs until the run completes or reaches the step limit (the crate's tests).
    #[cfg(test)]
    pub(crate) fn run(&mut self) -> Result<RunResult> {
        self.steps(u64::MAX)?;
        Ok(self.result())
    }

    /// Runs up to `max` steps, fewer if the run ends first; returns how many ran. The same as
    /// calling [`Paper::step`] that often, to the bit, but stretches of steps in which nothing
    /// can happen but travel, dwelling, charging and consumption run in one pass
    /// (`crate::rules::paper::cruise`).
    pub fn steps(&mut self, max: u64) -> Result<u64> {
        let mut done = 0;
        while done < max && self.record.outcome.is_none() {
            let k = self.cruise(max - done);
            if k == 0 {
                self.step()?;
                done += 1;
            } else {
                done += k;
            }
        }
        Ok(done)
    }

    /// Runs one step (every phase, `pipeline.rs`). Does nothing once the run has ended.
    pub fn step(&mut self) -> Result<()> {
        if !self.may_step()? {
            return Ok(());
        }
        let stepped = self.pipeline.step(
            &mut *self.allocator,
            &self.p,
            &self.world,
            &mut self.robots,
            &mut self.goods,
            &mut self.stations,
            &mut self.record,
            &mut self.crowd,
        );
        if let Err(e) = &stepped {
            self.failure = Some(e.to_string());
        }
        stepped
    }

    /// A new step up to phase 1: the step count, then phase 0. Returns `false` once the run
    /// has ended. Decisions from outside the engine make phase 1 (`decision_point.rs`).
    pub(crate) fn begin_step(&mut self) -> Result<bool> {
        if !self.may_step()? {
            return Ok(false);
        }
        self.pipeline.begin(&mut self.goods, &mut self.record);
        Ok(true)
    }

    /// Whether a new step may begin: `false` once the run has ended; an error after a failed
    /// step, or while decisions are pending.
    fn may_step(&self) -> Result<bool> {
        if self.record.outcome.is_some() {
            return Ok(false);
        }
        if let Some(failure) = &self.failure {
            // Phases after the allocator's error never ran: carrying on would skip them.
            return Err(Error::Allocator {
                strategy: self.allocator.name().to_string(),
                reason: format!("the run stopped at step {}: {failure}", self.record.tally.t),
            });
        }
        if self.goods.pending {
            return Err(Error::Decision { step: self.record.tally.t, reason: "decisions are pending: decide() finishes this step first".into() });
        }
        Ok(true)
    }

    /// Phase 1, first half (see [`GoodsQueue::begin_hand_out`]).
    pub(crate) fn begin_hand_out(&mut self) -> bool {
        self.goods.begin_hand_out(&mut self.robots)
    }

    /// Phase 1, second half (see [`GoodsQueue::finish_hand_out`]).
    pub(crate) fn finish_hand_out(&mut self) -> std::result::Result<(), String> {
        self.goods.finish_hand_out(&self.p, &self.world, &mut self.robots, &mut self.stations, &mut self.record)
    }

    /// Phases 2 to 8, after phase 1.
    pub(crate) fn finish_step(&mut self) {
        self.pipeline.finish(&self.p, &self.world, &mut self.robots, &mut self.goods, &mut self.stations, &mut self.record, &mut self.crowd);
    }

    /// What deciders see between the two halves of phase 1 (the queue is contiguous then).
    pub(crate) fn pending_view_unchecked(&self) -> crate::alloc::AllocView<'_> {
        self.goods.view(&self.robots, &self.world, self.stations.homes.unload, &self.p, self.record.tally.t).with_people(self.crowd.people.as_deref())
    }
}

impl Paper {
    // What the learning environments read beyond [`Engine`].

    /// Goods not yet taken, front first.
    pub(crate) fn queue(&self) -> &std::collections::VecDeque<crate::alloc::Goods> {
        &self.goods.queue
    }

    /// The unloading zone that goods from `cell` go to.
    pub(crate) fn unload_of(&self, cell: u32) -> crate::ids::NodeId {
        self.stations.homes.unload_of(cell)
    }
}

impl Engine for Paper {
    fn steps(&mut self, max: u64) -> Result<u64> {
        Paper::steps(self, max)
    }
    fn step(&mut self) -> Result<()> {
        Paper::step(self)
    }
    fn result(&self) -> RunResult {
        Paper::result(self)
    }
    fn t(&self) -> u64 {
        self.record.tally.t
    }
    fn outcome(&self) -> Option<Outcome> {
        self.record.outcome
    }
    fn s(&self) -> u64 {
        self.record.tally.s
    }
    fn c(&self) -> u64 {
        self.record.tally.c
    }
    fn delivered(&self) -> u64 {
        self.record.tally.delivered
    }
    fn goods_total(&self) -> u64 {
        self.record.tally.goods_total
    }
    fn robots(&self) -> &Robots {
        &self.robots
    }
    fn people(&self) -> Option<&People> {
        self.crowd.people.as_deref()
    }
    fn stats(&self) -> &RobotStats {
        &self.record.tally.stats
    }
    fn cells_full(&self) -> &[bool] {
        &self.goods.cells_full
    }
    fn queue_cells(&self) -> Vec<u32> {
        self.goods.queue.iter().map(|g| g.cell.0).collect()
    }
    fn events(&self) -> &[Event] {
        &self.record.events
    }
    fn world(&self) -> &Arc<World> {
        &self.world
    }
    fn energy_levels(&self) -> (f64, f64) {
        (self.p.energy_full, self.p.threshold)
    }
    fn allocator_name(&self) -> &str {
        self.allocator.name()
    }
    fn route_of(&self, i: usize) -> Vec<(f64, f64)> {
        route::remaining(&self.robots, &self.world.graph, i)
    }
    fn queues(&self) -> crate::record::resources::Queues {
        self.record.usage.queues(&self.world.layout)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fleet::robot::State;
    use crate::fleet::route::service_target;
    use crate::fleet::route::Place;
    use crate::ids::CellId;
    use crate::ids::NONE;

    #[test]
    fn a_robot_behind_a_stranded_one_is_a_gridlock_that_says_where() {
        let mut s = Scenario::paper(2, &[42]);
        s.metrics.gridlock = 500;
        let mut sim = Paper::new(&s).unwrap();
        let g = &sim.world.graph;
        let from = Place::node(g, sim.robots.home[0]);
        let pts = route::waypoints(g, from, service_target(&sim.world.layout, CellId(42)));
        // Robot 1 stands stranded half-way along the third leg of robot 0's route.
        let ((ax, ay), (bx, by)) = (pts[2], pts[3]);
        let r = &mut sim.robots;
        (r.x[1], r.y[1], r.at_node[1], r.state[1], r.energy[1]) = ((ax + bx) / 2.0, (ay + by) / 2.0, NONE, State::Stranded, 0.0);
        let res = sim.run().unwrap();
        assert_eq!(res.outcome, Some(Outcome::Gridlock));
        let gl = res.gridlock.unwrap();
        assert_eq!((gl.waiting, gl.step), (vec![0], res.steps));
        let layout = &sim.world.layout;
        let ahead = layout.nodes.iter().find(|n| (n.x, n.y) == (bx, by)).unwrap().name.clone();
        assert_eq!(gl.crossings, vec![(ahead, 1)]);
        // Robot 0 reached robot 1 within a few dozen steps; then 500 steps without progress.
        assert!(res.steps > 500 && res.steps < 700, "{}", res.steps);
        assert_eq!(res.delivered, 0);
    }

    #[test]
    fn a_strategy_that_hands_out_nothing_stalls_the_run() {
        struct Never;
        impl Allocator for Never {
            fn name(&self) -> &'static str {
                "never"
            }
            fn allocate(&mut self, _: &crate::AllocView<'_>, _: &mut crate::alloc::Decisions) -> Result<()> {
                Ok(())
            }
        }
        let mut s = Scenario::paper(2, &[42]);
        s.metrics.gridlock = 300;
        let mut sim = Paper::with_allocator(&s, Box::new(Never)).unwrap();
        let res = sim.run().unwrap();
        assert_eq!((res.outcome, res.steps, res.gridlock), (Some(Outcome::Stalled), 300, None));
        // Off: the run goes on to its step limit.
        s.metrics.gridlock = 0;
        s.step_limit = 5000;
        let res = Paper::with_allocator(&s, Box::new(Never)).unwrap().run().unwrap();
        assert_eq!((res.outcome, res.steps), (Some(Outcome::Incomplete), 5000));
    }

    #[test]
    fn windows_throughput_and_shares_add_up() {
        let mut s = Scenario::paper(6, &crate::input::scenario::PAPER_TASKS[0]);
        s.metrics.window = 100;
        let r = Paper::new(&s).unwrap().run().unwrap();
        let t = r.t.unwrap();
        assert_eq!(r.windows.len() as u64, t / 100);
        // Deliveries in the last, partial window are in no complete window.
        assert!(r.windows.iter().sum::<u64>() <= r.delivered);
        assert!((r.throughput.unwrap() - r.delivered as f64 * 1000.0 / t as f64).abs() < 1e-9);
        let waits: u64 = r.robots.wait_steps.iter().map(|&w| u64::from(w)).sum();
        assert!((r.wait_share - waits as f64 / (6 * t) as f64).abs() < 1e-12);
        assert!(r.utilisation > 0.0 && r.utilisation + r.wait_share <= 1.0);
        // A warm-up past the end leaves no steady figures.
        s.metrics.warmup = t + 1;
        let r2 = Paper::new(&s).unwrap().run().unwrap();
        assert_eq!((r2.throughput, r2.sustained_throughput, r2.wait_share), (None, None, 0.0));
        assert_eq!((r2.t, r2.s, r2.c), (r.t, r.s, r.c));
    }
}
