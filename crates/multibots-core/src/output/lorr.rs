//! What a LoRR run records, and the competition's result file written from it (the
//! Start-Kit's `saveResults`, read by PlanViz and the competition's checkers): for both
//! years `actionModel`, `version`, `teamSize`, `start`, `numTaskFinished`, `sumOfCost`,
//! `makespan`, `actualPaths`, `plannerPaths`, `plannerTimes`, `errors`, `events`, `tasks`;
//! 2023 adds `AllValid`, 2024 adds `numPlannerErrors`, `numScheduleErrors`,
//! `numEntryTimeouts`, `actualSchedule`, `plannerSchedule` and `scheduleErrors`. `events`
//! and `tasks` follow each year's own layout. Beside it, MultiBots' figures
//! ([`Figures`]): tasks finished per window of 1,000 steps, and planning time per step.

use crate::error::{Error, Result};
use crate::rules::grid::action::{Action, ActionError};
use crate::rules::grid::{LorrRun, Tasks};
use std::fmt::Write as _;
use std::path::Path;

/// A run's record, step by step.
#[derive(Default)]
pub struct Record {
    n: usize,
    /// The planner's actions, step-major (`step * N + robot`), as `Action as u8`.
    pub planned: Vec<u8>,
    /// The actions carried out, step-major.
    pub actual: Vec<u8>,
    /// Seconds each planning round took.
    pub planner_times: Vec<f64>,
    /// Refused joint actions.
    pub errors: Vec<ActionError>,
    /// Steps lost to the plan time limit.
    pub timeouts: u32,
    /// Steps each robot had a goal.
    pub costs: Vec<u32>,
    /// (step, tasks finished in it), one per planned step.
    pub finished_at: Vec<(u32, u32)>,
    /// (step, milliseconds its plan took), one per planned step.
    pub plan_ms: Vec<(u32, f64)>,
}

impl Record {
    pub(crate) fn new(n: usize) -> Record {
        Record { n, costs: vec![0; n], ..Record::default() }
    }

    pub(crate) fn push_timeout(&mut self, y2023: bool, t: u32) {
        self.planned.extend(std::iter::repeat(Action::T as u8).take(self.n));
        let carried = if y2023 { Action::W } else { Action::T };
        self.actual.extend(std::iter::repeat(carried as u8).take(self.n));
        if y2023 {
            // The 2023 system checks an empty action vector and records its size as wrong.
            self.errors.push(ActionError { kind: "incorrect vector size", agent: -1, other: -1, timestep: t });
        }
    }

    /// Steps recorded.
    #[must_use]
    pub fn steps(&self) -> usize {
        self.actual.len().checked_div(self.n).unwrap_or(0)
    }
}

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
}

impl LorrRun {
    /// MultiBots' figures so far.
    #[must_use]
    pub fn figures(&self) -> Figures {
        let r = self.record();
        let mut windows = vec![0u64; (self.t() as usize).div_ceil(1000)];
        for &(t, k) in &r.finished_at {
            windows[(t as usize - 1) / 1000] += u64::from(k);
        }
        let times = &r.planner_times;
        Figures {
            steps: self.t(),
            finished: self.finished(),
            finished_per_1000: windows,
            plan_ms_mean: if times.is_empty() { 0.0 } else { times.iter().sum::<f64>() * 1e3 / times.len() as f64 },
            plan_ms_max: times.iter().copied().fold(0.0, f64::max) * 1e3,
            plan_rounds_over_1s: times.iter().filter(|&&s| s > 1.0).count() as u32,
            action_errors: r.errors.len() as u32,
            schedule_errors: match self.tasks() {
                Tasks::Pool(p) => p.errors.len() as u32,
                Tasks::RoundRobin(_) => 0,
            },
            timeouts: r.timeouts,
        }
    }

    /// The competition's result file, as text.
    #[must_use]
    pub fn result_json(&self) -> String {
        let r = self.record();
        let p = self.problem();
        let n = p.team_size();
        let steps = r.steps();
        let y2024 = matches!(self.tasks(), Tasks::Pool(_));
        let js = |v: &serde_json::Value| v.to_string();
        let mut out = String::with_capacity(2 * n * steps + (1 << 20));
        out.push_str("{\n");
        let mut field = |key: &str, value: &str| {
            if out.len() > 2 {
                out.push_str(",\n");
            }
            let _ = write!(out, "    \"{key}\": {value}");
        };
        field("actionModel", "\"MAPF_T\"");
        field("version", if y2024 { "\"2024 LoRR\"" } else { "\"2023 LoRR\"" });
        if !y2024 {
            field("AllValid", if r.errors.is_empty() { "\"Yes\"" } else { "\"No\"" });
        }
        field("teamSize", &n.to_string());
        let start: Vec<serde_json::Value> = p.starts.iter().map(|&c| serde_json::json!([c / p.map.cols, c % p.map.cols, "E"])).collect();
        field("start", &js(&serde_json::Value::from(start)));
        field("numTaskFinished", &self.finished().to_string());
        field("sumOfCost", &r.costs.iter().map(|&c| u64::from(c)).sum::<u64>().to_string());
        field("makespan", &r.costs.iter().max().copied().unwrap_or(0).to_string());
        if y2024 {
            field("numPlannerErrors", &r.errors.len().to_string());
            field("numScheduleErrors", &self.figures().schedule_errors.to_string());
            field("numEntryTimeouts", &r.timeouts.to_string());
        }
        field("actualPaths", &paths(&r.actual, n, steps));
        field("plannerPaths", &paths(&r.planned, n, steps));
        field("plannerTimes", &js(&serde_json::Value::from(r.planner_times.clone())));
        let errors: Vec<serde_json::Value> = r.errors.iter().map(|e| serde_json::json!([e.agent, e.other, e.timestep, e.kind])).collect();
        field("errors", &js(&serde_json::Value::from(errors)));
        match self.tasks() {
            Tasks::RoundRobin(rr) => {
                let events: Vec<serde_json::Value> = rr
                    .events
                    .iter()
                    .map(|evs| {
                        serde_json::Value::from(
                            evs.iter().map(|&(id, t, done)| serde_json::json!([id, t, if done { "finished" } else { "assigned" }])).collect::<Vec<_>>(),
                        )
                    })
                    .collect();
                field("events", &js(&serde_json::Value::from(events)));
                let tasks: Vec<serde_json::Value> = rr.all.iter().map(|e| serde_json::json!([e.id, e.cell / p.map.cols, e.cell % p.map.cols])).collect();
                field("tasks", &js(&serde_json::Value::from(tasks)));
            }
            Tasks::Pool(pool) => {
                let events: Vec<serde_json::Value> = pool.events.iter().map(|&(t, k, id, seq)| serde_json::json!([t, k, id, seq])).collect();
                field("events", &js(&serde_json::Value::from(events)));
                let tasks: Vec<serde_json::Value> = pool
                    .tasks
                    .iter()
                    .enumerate()
                    .map(|(id, task)| {
                        let locs: Vec<u32> = p.tasks[task.line as usize].iter().flat_map(|&c| [c / p.map.cols, c % p.map.cols]).collect();
                        serde_json::json!([id, task.revealed, locs])
                    })
                    .collect();
                field("tasks", &js(&serde_json::Value::from(tasks)));
                field("actualSchedule", &schedules(&pool.actual_schedule));
                field("plannerSchedule", &schedules(&pool.planner_schedule));
                let errors: Vec<serde_json::Value> = pool.errors.iter().map(|e| serde_json::json!([e.task, e.agent, e.other, e.timestep, e.kind])).collect();
                field("scheduleErrors", &js(&serde_json::Value::from(errors)));
            }
        }
        out.push_str("\n}\n");
        out
    }

    /// Writes the result file atomically (a temporary file, then a rename).
    pub fn write_result(&self, path: &Path) -> Result<()> {
        crate::input::layout_file::write(path, &self.result_json())
    }

    /// Writes MultiBots' figures as JSON, atomically.
    pub fn write_figures(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(&self.figures()).map_err(|e| Error::Io { path: path.display().to_string(), message: e.to_string() })?;
        crate::input::layout_file::write(path, &(text + "\n"))
    }
}

/// One string of comma-separated letters per robot, from step-major actions.
fn paths(actions: &[u8], n: usize, steps: usize) -> String {
    let mut out = String::with_capacity(actions.len() * 2 + n * 8);
    out.push('[');
    for k in 0..n {
        if k > 0 {
            out.push(',');
        }
        out.push('"');
        for t in 0..steps {
            if t > 0 {
                out.push(',');
            }
            out.push(['F', 'R', 'C', 'W', 'T'][actions[t * n + k] as usize]);
        }
        out.push('"');
    }
    out.push(']');
    out
}

fn schedules(per_robot: &[Vec<(u32, i64)>]) -> String {
    let v: Vec<String> = per_robot.iter().map(|s| s.iter().map(|(t, id)| format!("{t}:{id}")).collect::<Vec<_>>().join(",")).collect();
    serde_json::Value::from(v).to_string()
}
