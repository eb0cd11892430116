//! The step: the phases of the model in their order (spec section 4).
//!
//! | phase | what | where |
//! | --- | --- | --- |
//! | 0 | lifelong orders and restocks arrive | [`crate::rules::paper::goods_queue`], [`crate::rules::paper::lifelong`] |
//! | 1 | idle robots get goods, or go home | [`crate::rules::paper::goods_queue`], [`crate::alloc`] |
//! | 2 | who wants to move, and where each is heading | here |
//! | 3 | collision waiting, and the count S | [`crate::collision`] |
//! | 4 | robots that may move travel along their routes | [`crate::fleet::route`] |
//! | 5, 6 | dwell counters; charging and consumption | [`crate::fleet::energy`] |
//! | 7 | the task cycle, then the charging rules | [`crate::rules::paper::tasks`], [`crate::rules::paper::charging`] |
//! | 8 | completion, then the step limit | here |
//!
//! Start positions, parking and unloading zones are in [`crate::world::placement`]; T, S, C and the
//! run's result in [`crate::output::metrics`].

pub(crate) mod charging;
mod cruise;
pub mod decision_point;
pub(crate) mod goods_queue;
pub mod lifelong;
mod tasks;

use crate::alloc::{self, Allocator, Goods};
use crate::collision::{bearing, Collisions};
use crate::error::{Error, Result};
use crate::fleet::energy;
use crate::fleet::robot::{Robots, State, Target};
use crate::fleet::route::{self, Place};
use crate::ids::{NodeId, NONE};
use crate::input::scenario::{ChargingPolicy, CostWeights, Scenario, Traffic};
use crate::output::events::{Event, EventKind};
use crate::output::metrics::{Outcome, RobotStats, RunResult, Tally};
use crate::people::People;
use crate::rules::paper::goods_queue::GoodsQueue;
use crate::traffic::TrafficState;
use crate::world::placement::{self, Homes};
use crate::world::World;
use charging::{Asked, Chargers};
use lifelong::Lifelong;
use std::collections::VecDeque;
use std::sync::Arc;

/// The model's numbers, taken from a validated scenario.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Params {
    pub speed: f64,
    pub energy_full: f64,
    pub threshold: f64,
    pub consumption: f64,
    pub charge_rate: f64,
    pub loading: u32,
    pub unloading: u32,
    pub margin: f64,
    /// The collision angle, radians.
    pub angle: f64,
    pub step_limit: u64,
    /// Opportunistic charging: idle robots below this level go to charge.
    pub opportunistic: Option<f64>,
}

impl Params {
    /// Whether phase 7 has anything to do for a robot in `state`, after this step's phases
    /// 2 to 6. Most robots have nothing due: under way, dwelling or charging, with energy to
    /// spare. Only the others take the full rules.
    #[inline]
    pub(crate) fn due(&self, state: State, routing: bool, dwell: u32, e: f64) -> bool {
        self.task_done(state, routing, dwell, e) || energy::below(e, self.threshold) || self.energy_acts(state, e)
    }

    /// A trip, a dwell or a charge that ended: the task cycle's transition is due.
    #[inline]
    fn task_done(&self, state: State, routing: bool, dwell: u32, e: f64) -> bool {
        match state {
            State::ToPickup | State::ToDrop | State::ToCharger | State::ToHome => !routing,
            State::Loading => dwell >= self.loading,
            State::Unloading => dwell >= self.unloading,
            State::Charging => energy::is_full(e, self.energy_full),
            _ => false,
        }
    }

    /// Stranding, or opportunistic charging, for a robot with energy `e`.
    #[inline]
    fn energy_acts(&self, state: State, e: f64) -> bool {
        energy::exhausted(e) || self.opportunistic.is_some_and(|level| state == State::Idle && energy::below(e, level))
    }

    /// Whether phase 7 would change anything for a robot (`marked` by the threshold rule):
    /// [`Params::due`] less robots below the threshold that the threshold rule has nothing
    /// left to do for (`Paper::energy_rules`): marked already, or going to charge, charging,
    /// waiting for a charger, parked or going home. A robot fetching goods below it counts as
    /// acting (whether it puts them back depends on where it is). A charging robot below the
    /// threshold is due every step until it is full: without this, no run of steps could
    /// cruise through a charge.
    #[inline]
    pub(crate) fn acts(&self, state: State, routing: bool, dwell: u32, e: f64, marked: bool) -> bool {
        let threshold = energy::below(e, self.threshold)
            && match state {
                State::Idle | State::ToPickup => true,
                State::Loading | State::ToDrop | State::Unloading => !marked,
                _ => false,
            };
        // A stranded robot stays stranded.
        self.task_done(state, routing, dwell, e) || threshold || (state != State::Stranded && self.energy_acts(state, e))
    }

    /// Phases 5 and 6 for one robot in `state`: its dwell counter, charging, and consumption
    /// (counted in `energy_used`).
    #[inline]
    pub(crate) fn dwell_and_energy(&self, state: State, dwell: &mut u32, energy: &mut f64, energy_used: &mut f64) {
        match state {
            State::Loading | State::Unloading => *dwell += 1,
            State::Charging => *energy = energy::charge(*energy, self.charge_rate, self.energy_full),
            _ => {}
        }
        if !matches!(state, State::Charging | State::Parked | State::Stranded) {
            let e = energy::consume(*energy, self.consumption);
            *energy_used += *energy - e;
            *energy = e;
        }
    }

    fn of(scenario: &Scenario) -> Params {
        let r = &scenario.robot;
        Params {
            speed: r.speed,
            energy_full: r.energy_full,
            threshold: r.threshold,
            consumption: r.consumption,
            charge_rate: r.charge_rate,
            loading: scenario.dwell.loading,
            unloading: scenario.dwell.unloading,
            margin: scenario.collision.margin,
            angle: scenario.collision.angle.to_radians(),
            step_limit: scenario.step_limit,
            opportunistic: (scenario.charging.policy == ChargingPolicy::Opportunistic).then_some(scenario.charging.level),
        }
    }
}

/// Steps without a pickup or a delivery that make a livelock: two full battery cycles (a
/// full charge used up, and a full charge), with gridlock detection; 0 without it.
fn livelock_after(scenario: &Scenario) -> u64 {
    let r = &scenario.robot;
    if scenario.metrics.gridlock == 0 {
        return 0;
    }
    (2.0 * (r.energy_full / r.consumption + r.energy_full / r.charge_rate)).ceil().min(1e15) as u64
}

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

/// A run under the paper rules (`rules = "paper"`), in progress. Users drive it through
/// [`crate::Simulation`], which also runs the original rules.
pub struct Paper {
    pub(crate) world: Arc<World>,
    pub(crate) p: Params,
    pub(crate) cost_weights: CostWeights,
    pub(crate) robots: Robots,
    pub(crate) goods: GoodsQueue,
    pub(crate) homes: Homes,
    pub(crate) chargers: Chargers,
    pub(crate) lifelong: Option<Lifelong>,
    pub(crate) tally: Tally,
    pub(crate) outcome: Option<Outcome>,
    pub(crate) allocator: Box<dyn Allocator>,
    /// An allocation event is due: robots became idle or goods joined the queue.
    pub(crate) alloc_due: bool,
    /// Set when a step failed part-way: the run cannot go on.
    pub(crate) failure: Option<String>,
    pub(crate) collisions: Collisions,
    /// The `gate` and `reserve` traffic policies (`None`: the paper's collision waiting).
    pub(crate) traffic: Option<TrafficState>,
    /// Phase 2's answer: who wants to move (the heading it wants is `robots.heading`).
    pub(crate) wants: Vec<bool>,
    /// Whether anything happened this step: a robot moved, dwelt or charged, or stock
    /// changed (no progress for long while work remains is a gridlock).
    pub(crate) progress: bool,
    /// The fleet's largest radius and twice its top speed, for counting contacts (robots
    /// keep both for the whole run).
    pub(crate) contact_reach: (f64, f64),
    pub(crate) events: Vec<Event>,
    /// People on the floor (docs/people.md); `None`: none, and every rule as without them.
    pub(crate) people: Option<Box<People>>,
}

impl Paper {
    /// A run of `scenario` with its named built-in allocator.
    pub fn new(scenario: &Scenario) -> Result<Paper> {
        scenario.check_values()?;
        let allocator = alloc::built_in(scenario)?;
        Paper::with_world(World::of(scenario)?, scenario, allocator)
    }

    /// A run of `scenario` with a given allocator (such as one written in Python).
    pub fn with_allocator(scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Paper> {
        scenario.check_values()?;
        Paper::with_world(World::of(scenario)?, scenario, allocator)
    }

    /// A run on an already built world, with any allocator.
    pub fn with_world(world: Arc<World>, scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Paper> {
        scenario.check_values()?;
        let layout = &world.layout;
        let unload = placement::unload_zone(layout, &scenario.unload)?;
        let starts = placement::start_nodes(layout, scenario)?;
        let cells = scenario.cells(layout)?;
        let (robots, homes) = placement::place(&world, scenario, &starts, unload)?;
        charging::check_reach(&world, scenario, &homes, &asked_cells(scenario, &cells, layout.cells.len()))?;
        let csv = match scenario.orders.as_ref().and_then(|o| o.csv.as_ref()) {
            Some(path) => lifelong::read_csv(std::path::Path::new(path), layout.cells.len())?,
            None => Vec::new(),
        };
        let n = robots.len();
        let (goods, lifelong) = GoodsQueue::new(layout.cells.len(), &cells, scenario.orders.as_ref(), csv);
        let reach = 2.0 * scenario.robot.radius + scenario.collision.margin;
        let people = match &scenario.humans {
            Some(h) => People::new(h, &world, &robots)?.map(Box::new),
            None => None,
        };
        Ok(Paper {
            people,
            p: Params::of(scenario),
            cost_weights: scenario.cost.clone(),
            tally: Tally::new(n, goods.queue.len() as u64, &scenario.metrics).with_livelock_after(livelock_after(scenario)),
            progress: false,
            goods,
            homes,
            chargers: Chargers::new(&world, scenario),
            lifelong,
            outcome: None,
            allocator,
            alloc_due: true,
            failure: None,
            collisions: Collisions::new(world.reach_bounds(), reach, n),
            traffic: (scenario.traffic != Traffic::Wait)
                .then(|| TrafficState::new(scenario.traffic, &world.graph, n, scenario.robot.radius, scenario.collision.margin)),
            wants: vec![false; n],
            contact_reach: (robots.radius.iter().copied().fold(0.0, f64::max), 2.0 * robots.speed.iter().copied().fold(0.0, f64::max)),
            events: Vec::new(),
            robots,
            world,
        })
    }

    /// Runs until the run completes or reaches the step limit.
    pub fn run(&mut self) -> Result<RunResult> {
        self.steps(u64::MAX)?;
        Ok(self.result())
    }

    /// Runs up to `max` steps, fewer if the run ends first; returns how many ran. The same as
    /// calling [`Paper::step`] that often, to the bit, but stretches of steps in which nothing
    /// can happen but travel, dwelling, charging and consumption run in one pass
    /// (`crate::rules::paper::cruise`).
    pub fn steps(&mut self, max: u64) -> Result<u64> {
        let mut done = 0;
        while done < max && self.outcome.is_none() {
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

    /// Runs one step (all eight phases). Does nothing once the run has ended.
    pub fn step(&mut self) -> Result<()> {
        if !self.begin_step()? {
            return Ok(());
        }
        if let Err(e) = self.hand_out() {
            self.failure = Some(e.to_string());
            return Err(e);
        }
        self.finish_step();
        Ok(())
    }

    /// A new step up to phase 1: the step count, then phase 0. Returns `false` once the run
    /// has ended. Phase 1 comes next: [`Paper::hand_out`] with the allocator, or decisions
    /// from outside (`decision_point.rs`).
    pub(crate) fn begin_step(&mut self) -> Result<bool> {
        if self.outcome.is_some() {
            return Ok(false);
        }
        if let Some(failure) = &self.failure {
            // Phases after the allocator's error never ran: carrying on would skip them.
            return Err(Error::Allocator {
                strategy: self.allocator.name().to_string(),
                reason: format!("the run stopped at step {}: {failure}", self.tally.t),
            });
        }
        if self.goods.pending {
            return Err(Error::Decision { step: self.tally.t, reason: "decisions are pending: decide() finishes this step first".into() });
        }
        self.tally.t += 1;
        self.events.clear();
        self.progress = false;
        if self.lifelong.is_some() {
            self.orders();
            self.progress = !self.events.is_empty();
        }
        Ok(true)
    }

    /// Phases 2 to 8, after phase 1.
    pub(crate) fn finish_step(&mut self) {
        self.intend();
        if let Some(people) = self.people.as_mut() {
            people.guard(&self.robots, &self.wants);
        }
        self.block_and_move();
        if let Some(people) = self.people.as_mut() {
            people.step(&self.robots);
        }
        self.transitions();
        self.end();
    }

    pub(crate) fn event(&mut self, kind: EventKind, robot: usize, cell: u32) {
        self.events.push(Event { step: self.tally.t, kind, robot: robot as u32, cell });
    }

    pub(crate) fn route(&mut self, i: usize, target: Target) {
        route::assign(&mut self.robots, &self.world.graph, i, target);
    }

    /// Phase 0 (lifelong): restocks and arrivals of this step join the queue.
    fn orders(&mut self) {
        let Some(ll) = self.lifelong.as_mut() else { return };
        if self.goods.take_orders(ll, self.tally.t, &mut self.events) {
            self.alloc_due = true;
        }
        self.tally.goods_total = ll.ordered();
    }

    /// Phase 2: who wants to move, and where each is heading.
    fn intend(&mut self) {
        let n = self.robots.len();
        let r = &mut self.robots;
        // Slices of exactly `n` (here and in the phases below): indexing by `i < n` needs
        // no bounds checks.
        let (routing, state, x, y, wp_x, wp_y) = (&r.routing[..n], &r.state[..n], &r.x[..n], &r.y[..n], &r.wp_x[..n], &r.wp_y[..n]);
        // The heading is the collision test's direction too (`resolve` reads it only where
        // a robot wants to move, and so was set just now): no column of its own.
        let (wants, head) = (&mut self.wants[..n], &mut r.heading[..n]);
        for i in 0..n {
            let w = routing[i] && state[i].travels();
            wants[i] = w;
            if w {
                head[i] = bearing(wp_x[i] - x[i], wp_y[i] - y[i]);
            }
        }
        if self.homes.spread() {
            // Spread placement: parked robots and robots waiting for a charger stand in a
            // bay beside the aisle, out of the traffic (docs/model.md section 7).
            self.collisions.bay.resize(n, false);
            for (b, s) in self.collisions.bay.iter_mut().zip(state) {
                *b = matches!(s, State::Parked | State::WaitCharger);
            }
        }
    }

    /// Phases 3 to 6: collision waiting and the count S, then travel, dwell counters,
    /// charging and consumption. After the collision decision every robot's phases 3 to 6
    /// touch only that robot, so one pass does them all, robot by robot.
    fn block_and_move(&mut self) {
        let n = self.robots.len();
        let p = &self.p;
        let r = &self.robots;
        // Who waits and how far each robot may travel: the paper's collision waiting, or a
        // traffic policy (crate::traffic), which may also stop a robot short.
        match self.traffic.as_mut() {
            None => self.collisions.resolve(&r.x, &r.y, &r.radius, &self.wants, &r.heading, p.margin, p.angle),
            Some(ts) => {
                let cone = if ts.policy == Traffic::Gate {
                    self.collisions.resolve(&r.x, &r.y, &r.radius, &self.wants, &r.heading, p.margin, p.angle);
                    Some(&self.collisions.waits[..])
                } else {
                    None
                };
                let bays = &self.collisions.bay;
                for (o, k) in ts.out.iter_mut().zip(0..) {
                    *o = bays.get(k).copied().unwrap_or(false);
                }
                ts.decide(&mut self.robots, &self.world.graph, self.tally.t, &self.wants, cone);
                if ts.policy == Traffic::Reserve {
                    // Robots waiting to leave a bay are still in it; the grid serves to count
                    // contacts after the moves.
                    if !self.collisions.bay.is_empty() {
                        self.collisions.bay.copy_from_slice(&ts.out);
                    }
                    let r = &self.robots;
                    self.collisions.build_grid(&r.x, &r.y, &r.radius);
                }
            }
        }
        let (waits, budget) = match self.traffic.as_ref() {
            None => (&self.collisions.waits[..n], None),
            Some(ts) => (&ts.waits[..n], Some(&ts.budget[..n])),
        };
        // People: robots that stop for a person (not a collision) or slow down near one.
        let (halt, slow, slow_factor) = match self.people.as_deref() {
            Some(pp) => (Some(&pp.stop[..n]), Some(&pp.slow[..n]), pp.slow_factor),
            None => (None, None, 1.0),
        };
        let mut progress = false;
        let g = &self.world.graph;
        let wants = &self.wants[..n];
        let st = &mut self.tally.stats;
        let (wait_steps, collisions, distance, energy_used, order_waits) =
            (&mut st.wait_steps[..n], &mut st.collisions[..n], &mut st.distance[..n], &mut st.energy_used[..n], &mut st.order_waits[..n]);
        let (mut motion, r) = self.robots.split();
        let events = &mut self.events;
        let (t, s) = (self.tally.t, &mut self.tally.s);
        for i in 0..n {
            let state = r.state[i];
            // Phase 3: a wait that begins is a collision.
            let w = waits[i];
            if w {
                wait_steps[i] += 1;
                if matches!(state, State::ToPickup | State::ToDrop) {
                    order_waits[i] += 1;
                }
                if !r.waited[i] {
                    *s += 1;
                    collisions[i] += 1;
                    events.push(Event { step: t, kind: EventKind::Wait, robot: i as u32, cell: NONE });
                }
            }
            r.waited[i] = w;
            // Phase 4: robots that may move travel `speed` px along their routes (or what the
            // traffic policy allows).
            let moves = wants[i] && !w && !halt.is_some_and(|h| h[i]);
            if moves {
                let mut step = budget.map_or(r.speed[i], |b| b[i]);
                if slow.is_some_and(|s| s[i]) {
                    step = step.min(r.speed[i] * slow_factor);
                }
                distance[i] += motion.advance(g, i, step);
            }
            p.dwell_and_energy(state, &mut r.dwell[i], &mut r.energy[i], &mut energy_used[i]);
            progress |= moves | state.busy_in_place();
        }
        self.progress |= progress;
        if progress {
            self.count_contacts();
        }
    }

    /// Contacts after the moves of this step (see [`Collisions::contacts`]).
    fn count_contacts(&mut self) {
        let n = self.robots.len();
        // Robots that moved: wanted to and did not wait (reusing the phase's buffer).
        let waits = self.traffic.as_ref().map_or(&self.collisions.waits[..n], |ts| &ts.waits[..n]);
        for (w, &waited) in self.wants[..n].iter_mut().zip(waits) {
            *w &= !waited;
        }
        if !self.wants.contains(&true) {
            return;
        }
        let r = &self.robots;
        let (r_max, slack) = self.contact_reach;
        let (count, closest) = self.collisions.contacts_within(&r.x, &r.y, &r.radius, &self.wants, r_max, slack);
        self.tally.contacts += count;
        self.tally.closest = self.tally.closest.min(closest);
    }

    /// Phase 7: at most one state transition per robot, then the threshold and stranding rules.
    pub(crate) fn transitions(&mut self) {
        let p = self.p;
        for i in 0..self.robots.len() {
            let r = &self.robots;
            if p.due(r.state[i], r.routing[i], r.dwell[i], r.energy[i]) {
                self.task_transition(i);
                self.energy_rules(i);
            }
            self.tally.stats.state_steps[i][self.robots.state[i] as usize] += 1;
        }
    }

    /// Phase 8: completion first, then a fleet that can do nothing more (all stranded, or
    /// jammed), then the step limit (or the horizon).
    pub(crate) fn end(&mut self) {
        let complete =
            self.lifelong.is_none() && self.tally.delivered == self.tally.goods_total && (0..self.robots.len()).all(|i| self.homes.at_home(&self.robots, i));
        let work_remains = if self.lifelong.is_some() { self.tally.delivered < self.tally.goods_total } else { !complete };
        let jammed = self.tally.end_step(self.progress, work_remains);
        if complete {
            self.outcome = Some(Outcome::Complete);
        } else if work_remains && self.robots.state.iter().all(|&s| s == State::Stranded) {
            self.outcome = Some(Outcome::Stranded);
        } else if jammed {
            let waits = std::mem::take(&mut self.collisions.waits);
            self.declare_stall(&waits);
            self.collisions.waits = waits;
        } else if self.tally.livelocked(work_remains) {
            self.outcome = Some(Outcome::Livelock);
        } else if let Some(ll) = &self.lifelong {
            if self.tally.t >= ll.horizon {
                self.outcome = Some(Outcome::Horizon);
            }
        } else if self.tally.t >= self.p.step_limit {
            self.outcome = Some(Outcome::Incomplete);
        }
    }

    // Read-only state, for the bindings, viewers and replays.

    /// The current step (0 before the first).
    #[must_use]
    pub fn t(&self) -> u64 {
        self.tally.t
    }
    /// Whether the run has ended.
    #[must_use]
    pub fn done(&self) -> bool {
        self.outcome.is_some()
    }
    /// The run's outcome, once it has ended.
    #[must_use]
    pub fn outcome(&self) -> Option<Outcome> {
        self.outcome
    }
    /// Collisions S so far.
    #[must_use]
    pub fn s(&self) -> u64 {
        self.tally.s
    }
    /// Charging count C so far.
    #[must_use]
    pub fn c(&self) -> u64 {
        self.tally.c
    }
    /// Goods delivered so far.
    #[must_use]
    pub fn delivered(&self) -> u64 {
        self.tally.delivered
    }
    /// Goods in the task list.
    #[must_use]
    pub fn goods_total(&self) -> u64 {
        self.tally.goods_total
    }
    /// The fleet's columns.
    #[must_use]
    pub fn robots(&self) -> &Robots {
        &self.robots
    }
    /// Per-robot statistics so far.
    #[must_use]
    pub fn stats(&self) -> &RobotStats {
        &self.tally.stats
    }
    /// Which cells hold goods.
    #[must_use]
    pub fn cells_full(&self) -> &[bool] {
        &self.goods.cells_full
    }
    /// Goods not yet taken, front first.
    #[must_use]
    pub fn queue(&self) -> &VecDeque<Goods> {
        &self.goods.queue
    }
    /// Events of the last step.
    #[must_use]
    pub fn events(&self) -> &[Event] {
        &self.events
    }
    /// The layout and graph.
    #[must_use]
    pub fn world(&self) -> &Arc<World> {
        &self.world
    }
    /// Full energy and the threshold.
    #[must_use]
    pub fn energy_levels(&self) -> (f64, f64) {
        (self.p.energy_full, self.p.threshold)
    }
    /// The allocator's name.
    #[must_use]
    pub fn allocator_name(&self) -> &str {
        self.allocator.name()
    }
    /// Robot `i`'s remaining route as waypoints, starting at its position.
    #[must_use]
    pub fn route_of(&self, i: usize) -> Vec<(f64, f64)> {
        route::remaining(&self.robots, &self.world.graph, i)
    }
    /// Route length from a node to a target, for callers outside the step loop.
    #[must_use]
    pub fn route_length_from_node(&self, from: NodeId, target: Target) -> f64 {
        route::length(&self.world.graph, Place::node(&self.world.graph, from), target)
    }
    /// Whether a node is a charger.
    #[must_use]
    pub fn is_charger(&self, n: NodeId) -> bool {
        self.world.is_charger(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::alloc::service_target;
    use crate::ids::CellId;

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
