//! The competition's result file of a LoRR run, written from its record (the
//! Start-Kit's `saveResults`, read by PlanViz and the competition's checkers): for both
//! years `actionModel`, `version`, `teamSize`, `start`, `numTaskFinished`, `sumOfCost`,
//! `makespan`, `actualPaths`, `plannerPaths`, `plannerTimes`, `errors`, `events`, `tasks`;
//! 2023 adds `AllValid`, 2024 adds `numPlannerErrors`, `numScheduleErrors`,
//! `numEntryTimeouts`, `actualSchedule`, `plannerSchedule` and `scheduleErrors`. `events`
//! and `tasks` follow each year's own layout. Beside it, MultiBots' figures
//! ([`crate::rules::grid::Figures`]) as JSON.

use crate::error::{Error, Result};
use crate::rules::grid::{LorrRun, Tasks};
use std::fmt::Write as _;
use std::path::Path;

/// The competition's result file, as text.
#[must_use]
pub fn result_json(run: &LorrRun) -> String {
    let r = run.record();
    let p = run.problem();
    let n = p.team_size();
    let steps = r.steps();
    let y2024 = matches!(run.tasks(), Tasks::Pool(_));
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
    field("numTaskFinished", &run.finished().to_string());
    field("sumOfCost", &r.costs.iter().map(|&c| u64::from(c)).sum::<u64>().to_string());
    field("makespan", &r.costs.iter().max().copied().unwrap_or(0).to_string());
    if y2024 {
        field("numPlannerErrors", &r.errors.len().to_string());
        field("numScheduleErrors", &run.figures().schedule_errors.to_string());
        field("numEntryTimeouts", &r.timeouts.to_string());
    }
    field("actualPaths", &paths(&r.actual, n, steps));
    field("plannerPaths", &paths(&r.planned, n, steps));
    field("plannerTimes", &js(&serde_json::Value::from(r.planner_times.clone())));
    let errors: Vec<serde_json::Value> = r.errors.iter().map(|e| serde_json::json!([e.agent, e.other, e.timestep, e.kind])).collect();
    field("errors", &js(&serde_json::Value::from(errors)));
    match run.tasks() {
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
pub fn write_result(run: &LorrRun, path: &Path) -> Result<()> {
    crate::input::files::write_atomic(path, &result_json(run))
}

/// Writes MultiBots' figures as JSON, atomically.
pub fn write_figures(run: &LorrRun, path: &Path) -> Result<()> {
    let text = serde_json::to_string_pretty(&run.figures()).map_err(|e| Error::Io { path: path.display().to_string(), message: e.to_string() })?;
    crate::input::files::write_atomic(path, &(text + "\n"))
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
