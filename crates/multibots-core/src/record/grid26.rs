//! What a run under the League of Robot Runners' 2026 rules records, tick by tick, as
//! `crate::rules::grid::y2026` writes it and the competition's result file
//! (`crate::output::lorr26`) reads it: the actions asked for and carried out, each robot's
//! state at the start of every segment of the result's paths, the delays drawn, the action
//! model's messages, and the planner's calls.

/// The ticks a segment of the result file's paths covers (the Start-Kit's fixed
/// `outputSegmentSize`).
pub const SEGMENT: u32 = 100;

/// One message of the action model, as the result file's `errors` lists them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelMessage {
    /// The robot that waits, or that closed a cycle.
    pub agent: i64,
    /// The robot the cycle was closed on, or -1.
    pub other: i64,
    /// The model's step count (the tick played, from 1).
    pub time: u32,
    /// What happened, in the Start-Kit's words.
    pub message: String,
}

/// A robot's state at the start of a segment: cell, heading, ticks done of its action.
pub type Snapshot = (u32, u8, u32);

/// A 2026 run's record.
#[derive(Default)]
pub struct Record26 {
    n: usize,
    /// The action each robot asked for at each tick, after the executor's STOP and the delays
    /// (a held robot asks for a wait), as `Action as u8`, tick-major (`tick * N + robot`).
    pub planned: Vec<u8>,
    /// The action each robot carried out at each tick (its request, or the wait the model
    /// made of it), tick-major.
    pub actual: Vec<u8>,
    /// Each robot's state at ticks 0, 100, 200, ..., segment-major.
    pub snapshots: Vec<Snapshot>,
    /// Each robot's delays, `[start, end)` in ticks, in the order drawn.
    pub delays: Vec<Vec<(u32, u32)>>,
    /// The action model's messages of the last tick played (the result file keeps those).
    pub last_messages: Vec<ModelMessage>,
    /// Messages over the whole run.
    pub messages: u64,
    /// Robot-ticks in which a robot was held by a delay.
    pub held_ticks: u64,
    /// (tick, milliseconds) of every planner call: scheduler and planner together.
    pub plan_ms: Vec<(u32, f64)>,
    /// Milliseconds of the scheduler's part of each planner call (what a Python scheduler
    /// costs, its conversions included, is read here).
    pub schedule_ms: Vec<f64>,
    /// (tick, tasks finished in the tick that led to it), one per tick.
    pub finished_at: Vec<(u32, u32)>,
}

impl Record26 {
    /// An empty record for `n` robots.
    #[must_use]
    pub fn new(n: usize) -> Record26 {
        Record26 { n, delays: vec![Vec::new(); n], ..Record26::default() }
    }

    /// Ticks recorded.
    #[must_use]
    pub fn ticks(&self) -> usize {
        self.actual.len().checked_div(self.n).unwrap_or(0)
    }

    /// Robots.
    #[must_use]
    pub fn robots(&self) -> usize {
        self.n
    }
}
