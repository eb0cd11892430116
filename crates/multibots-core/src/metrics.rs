//! The indicators T, S and C, and what the engine counts per robot.

use crate::robot::State;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every goods delivered and every robot back at its home charger.
    Complete,
    /// The step limit came first.
    Incomplete,
}

impl Outcome {
    /// `"complete"` or `"incomplete"`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Complete => "complete",
            Outcome::Incomplete => "incomplete",
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
}
