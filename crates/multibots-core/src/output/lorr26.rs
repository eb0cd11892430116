//! The result file of a run under the 2026 rules: the Start-Kit `v3.1.0`'s `saveResults`
//! (read by PlanViz and `lorr_check26.py`), one line of JSON, its keys in the Start-Kit's order:
//! `actionModel`, `version`, `teamSize`, `numTaskFinished`, `makespan` (the ticks played),
//! `numPlannerErrors` (the action model's messages of the last tick), `numScheduleErrors`,
//! `numEntryTimeouts` (0: no call is timed), `agentMaxCounter`, `outputSegmentSize` (100),
//! `delayIntervals`, `start`, `actualPaths`, `events`, `tasks`, `plannerPaths`,
//! `plannerTimes` (`[]`, as the Start-Kit; the calls' times are in MultiBots' figures), `errors` (the last
//! tick's messages), `actualSchedule`, `plannerSchedule`, `scheduleErrors`.
//!
//! A path is one segment per 100 ticks, `[(tick,row,col,heading,counter):(A n,A n,...)]`, runs
//! of one letter never crossing a segment; each segment opens with the robot's state at its
//! first tick (the Start-Kit repeats the start state in every segment, which
//! `lorr_check26.py` accepts as it accepts the true state written here).

use crate::record::grid26::SEGMENT;
use crate::rules::grid::pool::TaskPool;
use crate::rules::grid::Lorr26;
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::Path;

/// The result file, as text.
#[must_use]
pub fn result_json(run: &Lorr26) -> String {
    let r = run.record();
    let p = run.problem();
    let pool = run.pool();
    let n = r.robots();
    let cols = p.map.cols;
    let mut out = String::with_capacity(4 * n * r.ticks() / 3 + (1 << 20));
    out.push('{');
    let mut field = |key: &str, value: &str| {
        if out.len() > 1 {
            out.push(',');
        }
        let _ = write!(out, "\"{key}\":{value}");
    };
    field("actionModel", "\"MAPF_T\"");
    field("version", "\"2026 LoRR\"");
    field("teamSize", &n.to_string());
    field("numTaskFinished", &run.finished().to_string());
    field("makespan", &run.t().to_string());
    field("numPlannerErrors", &r.last_messages.len().to_string());
    field("numScheduleErrors", &pool.errors.len().to_string());
    field("numEntryTimeouts", "0");
    field("agentMaxCounter", &run.floor().m.to_string());
    field("outputSegmentSize", &SEGMENT.to_string());
    let delays: Vec<Value> = r.delays.iter().map(|ds| Value::from(ds.iter().map(|&(a, b)| json!([a, b])).collect::<Vec<_>>())).collect();
    field("delayIntervals", &Value::from(delays).to_string());
    let start: Vec<Value> = p.starts.iter().map(|&c| json!([c / cols, c % cols, "E"])).collect();
    field("start", &Value::from(start).to_string());
    field("actualPaths", &paths(&r.actual, n, r.ticks(), &r.snapshots, cols));
    let events: Vec<Value> = pool.events.iter().map(|&(t, k, id, seq)| json!([t, k, id, seq])).collect();
    field("events", &Value::from(events).to_string());
    field("tasks", &tasks(pool, &p.tasks, cols).to_string());
    field("plannerPaths", &paths(&r.planned, n, r.ticks(), &r.snapshots, cols));
    // As the Start-Kit: the times are in MultiBots' figures, so that a result's bytes are the
    // same on every machine.
    field("plannerTimes", "[]");
    let errors: Vec<Value> = r.last_messages.iter().map(|e| json!([e.agent, e.other, e.time, e.message])).collect();
    field("errors", &Value::from(errors).to_string());
    field("actualSchedule", &schedules(&pool.actual_schedule));
    field("plannerSchedule", &schedules(&pool.planner_schedule));
    let errors: Vec<Value> = pool.errors.iter().map(|e| json!([e.task, e.agent, e.other, e.timestep, e.kind])).collect();
    field("scheduleErrors", &Value::from(errors).to_string());
    out.push('}');
    out
}

/// Writes the result file atomically.
pub fn write_result(run: &Lorr26, path: &Path) -> crate::error::Result<()> {
    crate::input::files::write_atomic(path, &result_json(run))
}

/// Writes MultiBots' figures beside it, atomically.
pub fn write_figures(run: &Lorr26, path: &Path) -> crate::error::Result<()> {
    let text =
        serde_json::to_string_pretty(&run.figures()).map_err(|e| crate::error::Error::Io { path: path.display().to_string(), message: e.to_string() })?;
    crate::input::files::write_atomic(path, &(text + "\n"))
}

/// Every revealed task in id order: `[id, tick revealed, [row, col, row, col, ...]]`.
fn tasks(pool: &TaskPool, lines: &[Vec<u32>], cols: u32) -> Value {
    let v: Vec<Value> = pool
        .tasks
        .iter()
        .enumerate()
        .map(|(id, t)| {
            let locs: Vec<u32> = lines[t.line as usize].iter().flat_map(|&c| [c / cols, c % cols]).collect();
            json!([id, t.revealed, locs])
        })
        .collect();
    Value::from(v)
}

/// One path string per robot from tick-major actions, in segments of [`SEGMENT`] ticks.
fn paths(actions: &[u8], n: usize, ticks: usize, snapshots: &[(u32, u8, u32)], cols: u32) -> String {
    const LETTER: [char; 5] = ['F', 'R', 'C', 'W', 'T'];
    let seg = SEGMENT as usize;
    let mut out = String::with_capacity(actions.len() / 2 + n * 40);
    out.push('[');
    for k in 0..n {
        if k > 0 {
            out.push(',');
        }
        out.push('"');
        for s in 0..ticks.div_ceil(seg) {
            let (loc, h, count) = snapshots.get(s * n + k).copied().unwrap_or_default();
            let _ = write!(out, "[({},{},{},{},{}):(", s * seg, loc / cols, loc % cols, h, count);
            let (mut run, mut len) = (u8::MAX, 0u32);
            let mut first = true;
            for t in s * seg..((s + 1) * seg).min(ticks) {
                let a = actions[t * n + k];
                if a == run {
                    len += 1;
                    continue;
                }
                if len > 0 {
                    let _ = write!(out, "{}{} {len}", if first { "" } else { "," }, LETTER[run as usize]);
                    first = false;
                }
                (run, len) = (a, 1);
            }
            if len > 0 {
                let _ = write!(out, "{}{} {len}", if first { "" } else { "," }, LETTER[run as usize]);
            }
            out.push_str(")]");
        }
        out.push('"');
    }
    out.push(']');
    out
}

fn schedules(per_robot: &[Vec<(u32, i64)>]) -> String {
    let v: Vec<String> = per_robot.iter().map(|s| s.iter().map(|(t, id)| format!("{t}:{id}")).collect::<Vec<_>>().join(",")).collect();
    Value::from(v).to_string()
}
