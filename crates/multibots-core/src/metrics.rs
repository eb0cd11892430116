//! The indicators T, S and C (spec section 6), Cost_total, the lifelong figures, and what
//! the engine counts per robot.
//!
//! - **T**, task time: the step in which the run completed (every goods delivered, every
//!   robot back home); none for a run that did not complete.
//! - **S**, collisions: waits begun (phase 3).
//! - **C**, charging count: arrivals at a charger to charge (phase 7).
//! - **Cost_total** = w_d · distance + w_t · T + w_c · S, with the scenario's `[cost]`
//!   weights; none where T is none.

use crate::lifelong::{self, Lifelong};
use crate::robot::State;
use crate::scenario::CostWeights;
use crate::sim::Simulation;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every goods delivered and every robot back at its home charger.
    Complete,
    /// The step limit came first.
    Incomplete,
    /// A lifelong run reached its horizon (the only way a lifelong run ends).
    Horizon,
}

impl Outcome {
    /// `"complete"` or `"incomplete"`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Complete => "complete",
            Outcome::Incomplete => "incomplete",
            Outcome::Horizon => "horizon",
        }
    }
}

/// Per-robot counters, one column each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RobotStats {
    /// Distance travelled, px.
    pub distance: Vec<f64>,
    /// Steps spent waiting at collisions.
    pub wait_steps: Vec<u64>,
    /// Collisions S of this robot (waits begun).
    pub collisions: Vec<u64>,
    /// Steps ending in each state, indexed by the state code.
    pub state_steps: Vec<[u64; State::COUNT]>,
    /// Energy consumed.
    pub energy_used: Vec<f64>,
    /// Goods delivered.
    pub delivered: Vec<u64>,
    /// Charges C of this robot.
    pub charges: Vec<u64>,
    /// Steps spent waiting while on an order (TO_PICKUP or TO_DROP).
    pub order_waits: Vec<u64>,
}

impl RobotStats {
    /// Zeroed counters for `n` robots.
    #[must_use]
    pub fn new(n: usize) -> RobotStats {
        RobotStats {
            distance: vec![0.0; n],
            wait_steps: vec![0; n],
            collisions: vec![0; n],
            state_steps: vec![[0; State::COUNT]; n],
            energy_used: vec![0.0; n],
            delivered: vec![0; n],
            charges: vec![0; n],
            order_waits: vec![0; n],
        }
    }
}

/// What a run produced.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// Task time T: the step in which the run completed; `None` when incomplete.
    pub t: Option<u64>,
    /// Collisions S.
    pub s: u64,
    /// Charging count C.
    pub c: u64,
    /// `None` only while the run is still going.
    pub outcome: Option<Outcome>,
    /// Steps run.
    pub steps: u64,
    pub delivered: u64,
    pub goods_total: u64,
    /// Robots that ran out of energy.
    pub stranded: Vec<u32>,
    /// Cost_total = w_d · distance + w_t · T + w_c · S; `None` where T is `None`.
    pub cost: Option<f64>,
    pub robots: RobotStats,
    /// Lifelong runs only: throughput, latency, utilisation, energy per delivery.
    pub lifelong: Option<LifelongStats>,
}

/// The figures of a lifelong run (docs/model.md section 7).
#[derive(Clone, Debug, PartialEq)]
pub struct LifelongStats {
    /// Orders that arrived (the task list's count as arriving at step 0).
    pub ordered: u64,
    /// Orders a robot is fetching or carrying.
    pub in_flight: u64,
    /// Orders in the allocation queue.
    pub queued: u64,
    /// Orders waiting for their cell to restock.
    pub waiting: u64,
    /// Deliveries per 1,000 steps.
    pub throughput: f64,
    /// Order-to-delivery latency, steps: nearest-rank percentiles and the mean.
    pub latency_p50: Option<u64>,
    pub latency_p95: Option<u64>,
    pub latency_p99: Option<u64>,
    pub latency_mean: Option<f64>,
    /// Share of robot-steps spent working on orders: in TO_PICKUP, LOADING, TO_DROP or
    /// UNLOADING and not waiting at a collision.
    pub utilisation: f64,
    /// Energy the fleet used per delivery.
    pub energy_per_delivery: Option<f64>,
}

/// The running counts of a simulation: the step, S, C and deliveries, and per-robot counters.
#[derive(Clone, Debug)]
pub(crate) struct Tally {
    /// The current step (0 before the first).
    pub t: u64,
    pub s: u64,
    pub c: u64,
    pub delivered: u64,
    /// Goods in the task list (orders so far, in lifelong runs).
    pub goods_total: u64,
    pub stats: RobotStats,
}

impl Tally {
    pub fn new(robots: usize, goods_total: u64) -> Tally {
        Tally { t: 0, s: 0, c: 0, delivered: 0, goods_total, stats: RobotStats::new(robots) }
    }
}

/// Cost_total of a complete run with task time `t`, fleet distance `distance` and `s`
/// collisions.
#[must_use]
pub fn cost_total(w: &CostWeights, t: Option<u64>, distance: f64, s: u64) -> Option<f64> {
    t.map(|t| w.distance * distance + w.time * t as f64 + w.collision * s as f64)
}

impl Simulation {
    /// The indicators and per-robot statistics so far.
    #[must_use]
    pub fn result(&self) -> RunResult {
        let r = &self.robots;
        let stranded = (0..r.len()).filter(|&i| r.state[i] == State::Stranded).map(|i| i as u32).collect();
        let tally = &self.tally;
        let t = (self.outcome == Some(Outcome::Complete)).then_some(tally.t);
        RunResult {
            t,
            s: tally.s,
            c: tally.c,
            outcome: self.outcome,
            steps: tally.t,
            delivered: tally.delivered,
            goods_total: tally.goods_total,
            stranded,
            cost: cost_total(&self.cost_weights, t, tally.stats.distance.iter().sum(), tally.s),
            robots: tally.stats.clone(),
            lifelong: self.lifelong.as_ref().map(|ll| self.lifelong_stats(ll)),
        }
    }

    fn lifelong_stats(&self, ll: &Lifelong) -> LifelongStats {
        let mut lat = ll.latencies.clone();
        lat.sort_unstable();
        let tally = &self.tally;
        let steps = tally.t.max(1);
        let on_orders: u64 = tally.stats.state_steps.iter().map(|s| s[State::ToPickup as usize] + s[State::Loading as usize] + s[State::ToDrop as usize] + s[State::Unloading as usize]).sum();
        let order_waits: u64 = tally.stats.order_waits.iter().sum();
        let energy: f64 = tally.stats.energy_used.iter().sum();
        let r = &self.robots;
        LifelongStats {
            ordered: ll.ordered(),
            in_flight: (0..r.len()).filter(|&i| r.goods[i] != crate::ids::NONE).count() as u64,
            queued: self.goods.queue.len() as u64,
            waiting: ll.waiting,
            throughput: tally.delivered as f64 * 1000.0 / steps as f64,
            latency_p50: lifelong::percentile(&lat, 50.0),
            latency_p95: lifelong::percentile(&lat, 95.0),
            latency_p99: lifelong::percentile(&lat, 99.0),
            latency_mean: (!lat.is_empty()).then(|| lat.iter().sum::<u64>() as f64 / lat.len() as f64),
            utilisation: on_orders.saturating_sub(order_waits) as f64 / (steps * r.len() as u64) as f64,
            energy_per_delivery: (tally.delivered > 0).then(|| energy / tally.delivered as f64),
        }
    }
}
