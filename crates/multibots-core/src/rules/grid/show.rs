//! How a League of Robot Runners run shows itself (the run contract's frames and description,
//! which `multibots lorr --record` writes and the viewer draws), in the replay format of
//! `docs/replay-format.md`, version 1, unchanged: a grid world is a layout with no
//! highway graph and a `grid` key (its rows, `@` for an obstacle and `.` for a free cell),
//! and a cell is [`CELL_PX`] px square (cell `(row, col)` has its centre at `((col + 0.5) ·
//! 16, (row + 0.5) · 16)` px, y down), so that the viewer and `multibots render` draw a grid
//! at the sizes they draw a warehouse. What differs from a replay of the paper rules is only
//! what the values mean:
//!
//! | column | meaning in a grid replay |
//! | --- | --- |
//! | heading | the robot's heading: east 0, south 64, west 128, north 192 |
//! | state | `IDLE` without a goal, `TO_PICKUP` on the way to an errand that is not its task's last, `TO_DROP` to the last |
//! | energy | always full (the competition has no batteries) |
//! | counters | S: refused joint actions so far; C: 0; delivered: the score so far |
//! | events | `ASSIGN` (robot, its new goal cell), `DELIVER` (robot, the errand cell that finished its task), `PUT_BACK` (robot; its goal taken away) |
//!
//! Goals are written only when they change (events), so each robot's goal at any frame is
//! the chunk's starting state plus the events up to that frame, as readers already derive
//! the paper rules' tasks. A step lost to the plan time limit is a frame in which every
//! robot stood still. What a frame shows is noted after every planning round
//! ([`Shown`]): the goals the last frame showed, and the events that changed them.

use crate::error::Result;
use crate::fleet::robot::State;
use crate::input::lorr::Version;
use crate::record::events::EventKind;
use crate::record::frame::{Frame, FrameSink, Summary};
use crate::rules::grid::{LorrRun, Tasks};
use crate::rules::run::Run;
use serde_json::{json, Value};

/// A grid cell's side, in px: robots of 0.4 cells (6.4 px) are legible at the viewer's and
/// the exporter's scales, and the largest LoRR map (500 cells) is 8,000 px wide.
pub const CELL_PX: f64 = 16.0;
/// A robot's radius, in px.
const RADIUS: f64 = 0.4 * CELL_PX;
/// "No robot" or "no cell" in an event.
const NONE: u32 = u32::MAX;

/// What the run's frames show beyond positions and headings: each robot's goal and state,
/// and the events of the last planning round that changed them.
#[derive(Clone, Debug, Default)]
pub(crate) struct Shown {
    goals: Vec<u32>,
    state: Vec<u8>,
    pub(crate) events: Vec<[u32; 3]>,
    /// Whether each robot finished a task in the round just played.
    delivered: Vec<bool>,
}

impl LorrRun {
    /// Notes what the frame after this round shows: each robot's goal and state, with an
    /// event where a task finished (DELIVER) or the goal changed (ASSIGN, PUT_BACK). At step
    /// 0, the first goals.
    pub(crate) fn note_shown(&mut self) {
        let n = self.loc.len();
        let t = self.t;
        let lines = &self.problem.tasks;
        let sh = &mut self.shown;
        if sh.goals.len() != n {
            sh.goals = vec![NONE; n];
        }
        sh.state.clear();
        sh.events.clear();
        sh.delivered.clear();
        sh.delivered.resize(n, false);
        if t > 0 {
            match &self.tasks {
                Tasks::Pool(pool) => pool.new_free.iter().for_each(|&k| sh.delivered[k as usize] = true),
                Tasks::RoundRobin(rr) => {
                    for (k, events) in rr.events.iter().enumerate() {
                        // This step's events are the last ones: a finish, then the errands revealed.
                        sh.delivered[k] = events.iter().rev().take_while(|e| e.1 == t).any(|e| e.2);
                    }
                }
            }
        }
        for k in 0..n {
            let (goal, last) = match &self.tasks {
                Tasks::RoundRobin(rr) => (rr.goal(k), true),
                Tasks::Pool(pool) => {
                    let id = pool.current[k];
                    if pool.is_open(id) {
                        let task = &pool.tasks[id as usize];
                        (pool.next_errand(id as u32, lines), task.done as usize + 1 == lines[task.line as usize].len())
                    } else {
                        (NONE, false)
                    }
                }
            };
            let was = sh.goals[k];
            if sh.delivered[k] {
                sh.events.push([EventKind::Deliver.code(), k as u32, was]);
                if goal != NONE {
                    sh.events.push([EventKind::Assign.code(), k as u32, goal]);
                }
            } else if goal != was {
                sh.events.push(if goal == NONE { [EventKind::PutBack.code(), k as u32, NONE] } else { [EventKind::Assign.code(), k as u32, goal] });
            }
            sh.goals[k] = goal;
            sh.state.push(match (goal == NONE, last) {
                (true, _) => State::Idle,
                (false, false) => State::ToPickup,
                (false, true) => State::ToDrop,
            } as u8);
        }
    }
}

impl Run for LorrRun {
    fn advance(&mut self, max: u64, mut sink: Option<&mut dyn FrameSink>) -> Result<u64> {
        let start = self.t;
        let until = u64::from(start).saturating_add(max).min(u64::from(u32::MAX)) as u32;
        let mut frame = Frame::default();
        while self.t < until {
            let before = self.t;
            self.step(until);
            if let Some(e) = &self.failure {
                return Err(e.clone());
            }
            if let Some(sink) = sink.as_deref_mut() {
                // Steps lost to the plan time limit: every robot waited.
                for _ in before + 1..self.t {
                    sink.repeat()?;
                }
                self.emit(&mut frame, true);
                sink.frame(&frame)?;
            }
        }
        Ok(u64::from(self.t - start))
    }

    fn time(&self) -> u64 {
        u64::from(self.t)
    }

    fn done(&self) -> bool {
        false
    }

    fn emit(&self, f: &mut Frame, events: bool) {
        f.clear();
        let cols = self.problem.map.cols;
        for (&cell, &h) in self.loc.iter().zip(&self.heading) {
            f.x.push(((f64::from(cell % cols) + 0.5) * CELL_PX) as f32);
            f.y.push(((f64::from(cell / cols) + 0.5) * CELL_PX) as f32);
            f.heading.push(h.wrapping_mul(64));
        }
        f.energy.extend(std::iter::repeat(u16::MAX).take(self.loc.len()));
        f.state.extend_from_slice(&self.shown.state);
        if events {
            f.events.extend_from_slice(&self.shown.events);
        }
        f.counters = [self.record.errors.len() as u32, 0, self.finished() as u32];
    }

    fn describe(&self) -> Value {
        let p = &self.problem;
        let n = self.loc.len();
        let o = &self.options;
        let version = match p.version {
            Version::Y2023 => "2023",
            Version::Y2024 => "2024",
            Version::Y2026 => "2026",
        };
        let mut v = describe_grid(p, n);
        let inputs = json!({"problem": v["layout"]["name"], "rules": version, "teamSize": n, "planner": o.planner, "scheduler": o.scheduler, "seed": o.seed, "planTimeLimitMs": o.plan_time_limit_ms});
        v["scenario"] = json!(serde_json::to_string_pretty(&inputs).expect("JSON serialises"));
        v["lorr"] = inputs;
        v
    }

    fn summary(&self) -> Summary {
        let f = self.figures();
        Summary {
            t: None,
            s: u64::from(f.action_errors),
            c: 0,
            outcome: "horizon",
            delivered: f.finished,
            window: 1000,
            windows: f.finished_per_1000,
            resources: Vec::new(),
            bottleneck: None,
        }
    }
}

/// The header of a grid replay, but for the run's inputs (`scenario`, `lorr`): the fleet, the
/// grid as a layout.
pub(crate) fn describe_grid(p: &crate::input::lorr::Problem, n: usize) -> Value {
    let (rows, cols) = (p.map.rows, p.map.cols);
    let grid: Vec<String> =
        (0..rows as usize).map(|r| p.map.free[r * cols as usize..(r + 1) * cols as usize].iter().map(|&f| if f { '.' } else { '@' }).collect()).collect();
    let name = p.path.file_name().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    json!({
        "robots": n,
        "radius": vec![RADIUS; n],
        "home": p.starts,
        "energy_full": 1.0,
        "threshold": 0.0,
        "cells_full": [],
        "goods_total": p.tasks.len(),
        "layout": {
            "name": name,
            "bounds": [0.0, 0.0, f64::from(cols) * CELL_PX, f64::from(rows) * CELL_PX],
            "aisle_width": CELL_PX,
            "cell_size": CELL_PX,
            "nodes": [], "edges": [], "spurs": [], "cells": [],
            "departure": [], "unloading": [], "chargers": [],
            "grid": {"rows": rows, "cols": cols, "cells": grid},
        },
    })
}
