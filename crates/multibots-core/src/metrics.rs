//! The indicators T, S and C, and what the engine counts per robot.

use crate::robot::State;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every goods delivered and every robot back at its home charger.
    Complete,
    /// The step limit came first.
    Incomplete,
    /// A lifelong run reached its horizon (the only way a lifelong run ends).
    Horizon,
    /// Original rules only: robots block each other for good, where the authors' code would
    /// wait forever ([`crate::original`]). T is undefined.
    Deadlock,
    /// Original rules only: the authors' code raises an exception in this step, so it has no
    /// answer from here on ([`crate::original`]). T is undefined.
    Fault,
}

impl Outcome {
    /// `"complete"`, `"incomplete"`, `"horizon"`, `"deadlock"` or `"fault"`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Complete => "complete",
            Outcome::Incomplete => "incomplete",
            Outcome::Horizon => "horizon",
            Outcome::Deadlock => "deadlock",
            Outcome::Fault => "fault",
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
    /// Share of robot-steps spent on orders (TO_PICKUP, LOADING, TO_DROP, UNLOADING).
    pub utilisation: f64,
    /// Energy the fleet used per delivery.
    pub energy_per_delivery: Option<f64>,
}
