//! MultiBots' figures of a LoRR run, beside the competition's score: tasks finished per
//! window of 1,000 steps, planning time per round, errors and lost steps.

use crate::rules::grid::{Lorr26, LorrRun, Tasks};

/// MultiBots' figures of a run.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Figures {
    /// Steps run.
    pub steps: u32,
    /// The score: tasks (2024) or errands (2023) finished.
    pub finished: u64,
    /// Tasks finished in each window of 1,000 steps (the last may be shorter).
    pub finished_per_1000: Vec<u64>,
    /// Mean planning time per planning round, in milliseconds.
    pub plan_ms_mean: f64,
    /// The longest planning round, in milliseconds.
    pub plan_ms_max: f64,
    /// Planning rounds past 1 s.
    pub plan_rounds_over_1s: u32,
    /// Refused joint actions.
    pub action_errors: u32,
    /// Refused schedules (2024).
    pub schedule_errors: u32,
    /// Steps lost to the plan time limit.
    pub timeouts: u32,
    /// 2026 rules: delays drawn, and robot-ticks held by them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delays: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_ticks: Option<u64>,
    /// 2026 rules: the scheduler's part of a planner call, mean and longest, in milliseconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub schedule_ms_mean: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub schedule_ms_max: Option<f64>,
}

/// Tasks finished per window of 1,000 steps (ticks), from (step, finished in it).
fn windows(t: u32, finished_at: &[(u32, u32)]) -> Vec<u64> {
    let mut w = vec![0u64; (t as usize).div_ceil(1000)];
    for &(t, k) in finished_at {
        w[(t as usize - 1) / 1000] += u64::from(k);
    }
    w
}

fn mean(ms: &[f64]) -> f64 {
    if ms.is_empty() {
        0.0
    } else {
        ms.iter().sum::<f64>() / ms.len() as f64
    }
}

impl Lorr26 {
    /// MultiBots' figures so far: steps are ticks; a planning round is a planner call;
    /// `action_errors` counts the action model's messages over the run.
    #[must_use]
    pub fn figures(&self) -> Figures {
        let r = self.record();
        let ms: Vec<f64> = r.plan_ms.iter().map(|&(_, ms)| ms).collect();
        Figures {
            steps: self.t(),
            finished: self.finished(),
            finished_per_1000: windows(self.t(), &r.finished_at),
            plan_ms_mean: mean(&ms),
            plan_ms_max: ms.iter().copied().fold(0.0, f64::max),
            plan_rounds_over_1s: ms.iter().filter(|&&m| m > 1000.0).count() as u32,
            action_errors: r.messages.min(u64::from(u32::MAX)) as u32,
            schedule_errors: self.pool().errors.len() as u32,
            timeouts: 0,
            delays: Some(r.delays.iter().map(|d| d.len() as u64).sum()),
            held_ticks: Some(r.held_ticks),
            schedule_ms_mean: Some(mean(&r.schedule_ms)),
            schedule_ms_max: Some(r.schedule_ms.iter().copied().fold(0.0, f64::max)),
        }
    }
}

impl LorrRun {
    /// MultiBots' figures so far.
    #[must_use]
    pub fn figures(&self) -> Figures {
        let r = self.record();
        let times = &r.planner_times;
        Figures {
            steps: self.t(),
            finished: self.finished(),
            finished_per_1000: windows(self.t(), &r.finished_at),
            plan_ms_mean: if times.is_empty() { 0.0 } else { times.iter().sum::<f64>() * 1e3 / times.len() as f64 },
            plan_ms_max: times.iter().copied().fold(0.0, f64::max) * 1e3,
            plan_rounds_over_1s: times.iter().filter(|&&s| s > 1.0).count() as u32,
            action_errors: r.errors.len() as u32,
            schedule_errors: match self.tasks() {
                Tasks::Pool(p) => p.errors.len() as u32,
                Tasks::RoundRobin(_) => 0,
            },
            timeouts: r.timeouts,
            delays: None,
            held_ticks: None,
            schedule_ms_mean: None,
            schedule_ms_max: None,
        }
    }
}
