//! The authors' original rules (`rules = "original"`): the code behind the paper's published
//! figures, reproduced tick for tick, quirks included.
//!
//! The reference is the authors' Python 2 code (github.com/liuyandong1988/Robio2017-MultiBots,
//! MIT licence): `WorldController.Controller.update()` is one tick of its 50 ms wx timer. This
//! module is our own implementation of what that code does, checked against it on the 30 paper
//! runs and on thousands of random goods lists (`tests/original_rules.rs`,
//! `tests/oracle/compare_original.py`); `docs/original-rules.md` lists how it differs from the
//! paper rules of `docs/model.md`.
//!
//! One tick, in the original's order (`Controller.update`):
//!
//! 1. **Drive** (`strategy.rs`, `Strategy.computeStartToGood`): every robot that is neither
//!    stopped nor at its charger follows its plan, loads, unloads, or turns back to charge.
//! 2. **Collisions** (`collision.rs`, `Controller.checkCollisionsAndStop`): stop and count
//!    robots in contact, release stopped robots first in, first out.
//! 3. **Charge and consume** (`charging.rs`, `Controller.chargeController`): robots at their
//!    charger charge, and once released go back to work (C counts here); the others use
//!    energy and the threshold rule marks them.
//! 4. **Readiness** (`dispatch.rs`, `Controller.agentsRunagain`): how many charged robots
//!    waiting at their chargers are released.
//! 5. **End** (`Controller.TimerController`): the run is complete on the tick on which every
//!    goods is delivered and every robot is at its charger; T is that tick.
//!
//! `responsemodel` sets `Strategy.num_agents_threshold = 10` on every tick, before anything
//! reads it (the first tick reads it as 0 only in `takeoffgoods`, which cannot run before
//! tick 20); with at most six robots the branches it guards never fire, and are left out.
//!
//! Where the original cannot go on, the run ends with an outcome that says so instead of
//! hanging: [`Outcome::Deadlock`] when stopped robots can never be released (`collision.rs`),
//! [`Outcome::Fault`] on the tick on which the original raises an exception ([`Fault`]).
//! `step_limit` is a safety stop ([`Outcome::Incomplete`]).

mod agent;
mod charging;
mod collision;
mod dispatch;
mod map;
pub(crate) mod measured;
mod strategy;
mod validate;
mod view;

use crate::error::{Error, Result};
use crate::fleet::robot::Robots;
use crate::ids::NONE;
use crate::input::scenario::Scenario;
use crate::record::events::{Event, EventKind};
use crate::record::metrics::{Outcome, RobotStats, RunResult};
use agent::Agent;
use map::Routes;
use std::collections::VecDeque;

/// The original rules take no strategy: the authors' code dispatches in turn. Any other
/// `allocator` is refused, as soon as it is named.
pub fn check_allocator(name: &str) -> Result<()> {
    if name == "in-turn" {
        Ok(())
    } else {
        Err(Error::scenario("allocator", format!("\"{name}\""), "the original rules dispatch in turn only (in-turn)"))
    }
}

/// Distance a robot moves in a tick: `(TIME_RATE / FRAME_PER_SECOND) * agent_speed`.
const STEP: f64 = (2.0 / 20.0) * 40.0;
/// Ticks at the shelf (`Strategy.pickupgoods`) and at M (`Strategy.takeoffgoods`).
const LOAD_TICKS: u32 = 10;
const UNLOAD_TICKS: u32 = 20;
/// `agent.fullenergy`, and the arguments of `ChargeThreshold.AgentCharge`.
const FULL: f64 = 10.0;
const THRESHOLD: f64 = 3.5;
const CONSUMPTION: f64 = 0.005;
const CHARGE_RATE: f64 = 0.05;
/// `agent.r = L / 4` with Python 2's integer division: 12, not 12.5.
const RADIUS: f64 = 12.0;
/// Most goods the original can deliver: `takeoffgoods` marks `boxes[goodscurrentcnt]`, and
/// there are 50 boxes.
const MAX_GOODS: usize = 50;

/// Where the original raises an exception, so that it has no answer from there on. Under
/// its GUI the exception repeats on every later tick and the run never ends; its headless
/// driver stops with a traceback.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// `Strategy.takeoffgoods`: after a delivery the counts say another goods is needed, but
    /// `GOOD_NUM` is empty (`IndexError`). A robot about to put its goods back for charging
    /// is counted neither as fetching nor as carrying.
    EmptyQueueAfterDelivery,
    /// `Controller.chargeController`: a released robot takes `GOOD_NUM[0]` from an empty list
    /// (`IndexError`).
    EmptyQueueAtRedispatch,
    /// `Strategy.computeStartToGood`: a robot turns back to charge on the tick after it reached
    /// the last crossing of its plan, and plans its way home from `'x'` (`KeyError: 'x'`).
    ChargeRouteFromNowhere,
}

impl Fault {
    /// A one-line description naming the original's function and exception.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Fault::EmptyQueueAfterDelivery => "Strategy.takeoffgoods: IndexError (GOOD_NUM[0] on an empty list)",
            Fault::EmptyQueueAtRedispatch => "Controller.chargeController: IndexError (GOOD_NUM[0] on an empty list)",
            Fault::ChargeRouteFromNowhere => "Strategy.computeStartToGood: KeyError 'x' (BFS from no crossing)",
        }
    }
}

/// A run under the original rules.
pub struct Original {
    agents: Vec<Agent>,
    routes: &'static Routes,
    /// `GOOD_NUM`: cells not yet handed out, front first.
    queue: VecDeque<u8>,
    /// `cillioned`: (stopped robot, robot it touched), first in, first out.
    pairs: VecDeque<(u8, u8)>,
    /// `goodstotal` and `goodscurrentcnt`.
    total: u64,
    delivered: u64,
    /// Index of each cell's goods in the task list (`NONE` when not listed).
    goods_of_cell: [u32; 80],
    cells_full: [bool; 80],
    t: u64,
    step_limit: u64,
    outcome: Option<Outcome>,
    fault: Option<Fault>,
    events: Vec<Event>,
    view: Robots,
    stats: RobotStats,
    /// Robots whose energy reached 0 (the original asks for Enter and carries on).
    ran_flat: Vec<bool>,
}

impl Original {
    /// Validates that the scenario is within what the original code supports, and sets the
    /// robots out as `Controller.__init__` and `Strategy.__init__` do: each robot takes the
    /// next goods in turn, stands at its charger heading 270°, and plans from its start
    /// crossing.
    pub fn new(scenario: &Scenario) -> Result<Original> {
        let cells = validate::check(scenario)?;
        let n = scenario.robots as usize;
        let mut o = Original {
            agents: (0..n).map(|k| Agent::new(k as u8, FULL)).collect(),
            routes: Routes::get(),
            queue: VecDeque::with_capacity(80),
            pairs: VecDeque::with_capacity(n * n),
            total: cells.len() as u64,
            delivered: 0,
            goods_of_cell: [NONE; 80],
            cells_full: [false; 80],
            t: 0,
            step_limit: scenario.step_limit,
            outcome: None,
            fault: None,
            events: Vec::with_capacity(64),
            view: Robots::default(),
            stats: RobotStats::new(n),
            ran_flat: vec![false; n],
        };
        for (k, &c) in cells.iter().enumerate() {
            o.queue.push_back(c as u8);
            o.goods_of_cell[c as usize] = k as u32;
            o.cells_full[c as usize] = true;
        }
        for i in 0..n {
            let g = o.queue.pop_front().expect("validated: at least one goods per robot");
            let a = &mut o.agents[i];
            a.goods = g;
            a.holds = true;
            let theta = a.theta;
            a.teleport(a.charger, theta);
            a.plan = o.routes.plan(a.start, map::shelf(g).forward);
            o.event(EventKind::Assign, i, u32::from(g));
        }
        o.init_view();
        Ok(o)
    }

    /// One timer tick (`Controller.update`); a no-op once the run has ended.
    pub fn step(&mut self) {
        if self.outcome.is_some() {
            return;
        }
        self.t += 1;
        self.events.clear();
        let ticked = self.tick();
        self.sync_view();
        self.outcome = match ticked {
            Err(fault) => {
                self.fault = Some(fault);
                Some(Outcome::Fault)
            }
            Ok(()) if self.delivered == self.total && self.agents.iter().all(|a| a.at_charger) => Some(Outcome::Complete),
            Ok(()) if self.deadlocked() => Some(Outcome::Deadlock),
            Ok(()) if self.t >= self.step_limit => Some(Outcome::Incomplete),
            Ok(()) => None,
        };
    }

    fn tick(&mut self) -> std::result::Result<(), Fault> {
        self.drive()?;
        self.check_collisions();
        self.charge_and_consume()?;
        self.release_ready();
        Ok(())
    }

    /// Runs until the run ends; returns the result.
    pub fn run(&mut self) -> RunResult {
        while self.outcome.is_none() {
            self.step();
        }
        self.result()
    }

    /// Records an event of this tick; `cell` is `NONE` where none applies.
    fn event(&mut self, kind: EventKind, robot: usize, cell: u32) {
        self.events.push(Event { step: self.t, kind, robot: robot as u32, cell });
    }

    /// Goods not yet delivered (`Strategy.goodsremain`).
    fn remaining(&self) -> i64 {
        (self.total - self.delivered) as i64
    }

    /// Whether the run has ended.
    #[must_use]
    pub fn done(&self) -> bool {
        self.outcome.is_some()
    }

    /// Ticks so far.
    #[must_use]
    pub fn t(&self) -> u64 {
        self.t
    }

    /// How the run ended, once it has.
    #[must_use]
    pub fn outcome(&self) -> Option<Outcome> {
        self.outcome
    }

    /// Where the original raised an exception, when the outcome is [`Outcome::Fault`].
    #[must_use]
    pub fn fault(&self) -> Option<Fault> {
        self.fault
    }

    /// Collisions S so far (`colltotalcnt`, the sum of `collisioncnt`).
    #[must_use]
    pub fn s(&self) -> u64 {
        self.agents.iter().map(|a| a.collisions).sum()
    }

    /// Charging count C so far (the sum of `chargecnts`).
    #[must_use]
    pub fn c(&self) -> u64 {
        self.agents.iter().map(|a| a.charges).sum()
    }

    /// Goods delivered so far.
    #[must_use]
    pub fn delivered(&self) -> u64 {
        self.delivered
    }

    /// The indicators and per-robot statistics so far; `t` is set once the run is complete.
    #[must_use]
    pub fn result(&self) -> RunResult {
        RunResult {
            t: (self.outcome == Some(Outcome::Complete)).then_some(self.t),
            s: self.s(),
            c: self.c(),
            outcome: self.outcome,
            steps: self.t,
            delivered: self.delivered,
            goods_total: self.total,
            stranded: (0..self.agents.len()).filter(|&i| self.ran_flat[i]).map(|i| i as u32).collect(),
            robots: self.stats.clone(),
            lifelong: None,
            people: None,
            // The flow figures are measured by `crate::Simulation`, which runs these rules.
            cost: None,
            window: 1000,
            windows: Vec::new(),
            throughput: None,
            sustained_throughput: None,
            wait_share: 0.0,
            utilisation: 0.0,
            contacts: 0,
            closest: None,
            gridlock: None,
            collapse: None,
            resources: Vec::new(),
            bottleneck: None,
        }
    }

    /// The fleet in the paper layout's frame, kept current for viewers and replays.
    #[must_use]
    pub fn robots(&self) -> &Robots {
        &self.view
    }

    /// Per-robot statistics so far.
    #[must_use]
    pub fn stats(&self) -> &RobotStats {
        &self.stats
    }

    /// The 80 cells of the paper layout, true while goods are there.
    #[must_use]
    pub fn cells_full(&self) -> &[bool] {
        &self.cells_full
    }

    /// This tick's events (after [`Original::new`]: the first assignments, at step 0).
    #[must_use]
    pub fn events(&self) -> &[Event] {
        &self.events
    }

    /// Goods not yet handed out, front first (`GOOD_NUM`).
    #[must_use]
    pub fn queue_cells(&self) -> Vec<u32> {
        self.queue.iter().map(|&c| u32::from(c)).collect()
    }

    /// Robot `i`'s remaining waypoints in the paper layout's frame, starting at its position:
    /// the crossings of its plan, or the loading point while it drives to the shelf.
    #[must_use]
    pub fn route_of(&self, i: usize) -> Vec<(f64, f64)> {
        let a = &self.agents[i];
        let shift = |(x, y): (f64, f64)| (x - map::FRAME_DX, y - map::FRAME_DY);
        let mut out = vec![shift((a.x, a.y))];
        if a.at_charger {
            return out;
        }
        if a.to_shelf {
            let s = map::shelf(a.goods);
            out.push(shift((s.x, s.y)));
            return out;
        }
        if a.stepping && a.next != map::NOWHERE && a.plan.front() != a.next {
            out.push(shift(map::point(a.next)));
        }
        out.extend(a.plan.remaining().iter().map(|&p| shift(map::point(p))));
        out
    }

    /// Full energy and the threshold, in the original's units.
    #[must_use]
    pub fn energy_levels(&self) -> (f64, f64) {
        (FULL, THRESHOLD)
    }
}
