//! How a 2026 run shows itself: the grid replay of `rules/grid/show.rs` (replay format version
//! 1, unchanged), a frame per tick, with what the 2026 rules add:
//!
//! | column | meaning in a 2026 replay |
//! | --- | --- |
//! | x, y | the centre of the robot's square, sliding `count / agentCounter` of a cell along its heading during a move |
//! | state | as in a 2024 replay, `+ MARKED` (bit 7) while the robot is held by a delay |
//! | counters | S: the action model's messages so far; C: delays drawn so far; delivered: tasks finished |
//! | events | as in a 2024 replay, and `WAIT` (robot, the tick its delay ends) when a delay starts |
//!
//! The header's `lorr` object names the rules (`"2026"`), `agentSize` and `agentCounter`: the
//! viewer draws each robot as its square.

use super::footprint::corner;
use super::Lorr26;
use crate::error::Result;
use crate::fleet::robot::State;
use crate::record::events::EventKind;
use crate::record::frame::{Frame, FrameSink, Summary, MARKED};
use crate::rules::grid::CELL_PX;
use crate::rules::run::Run;
use serde_json::{json, Value};

/// "No cell" in an event.
const NONE: u32 = u32::MAX;

/// What the frames show beyond positions and headings.
#[derive(Clone, Debug, Default)]
pub(crate) struct Shown {
    goals: Vec<u32>,
    state: Vec<u8>,
    events: Vec<[u32; 3]>,
    delays: u32,
}

impl Lorr26 {
    /// Notes what the frame after this tick shows: goals, states, and the tick's events.
    #[allow(clippy::needless_range_loop)] // robot k across several arrays
    pub(super) fn note_shown(&mut self) {
        let n = self.states.len();
        let lines = &self.problem.tasks;
        let sh = &mut self.shown;
        if sh.goals.len() != n {
            sh.goals = vec![NONE; n];
        }
        sh.state.clear();
        sh.events.clear();
        let mut delivered = vec![false; n];
        if self.t > 0 {
            for &k in &self.pool.new_free {
                delivered[k as usize] = true;
            }
        }
        for k in 0..n {
            let id = self.pool.current[k];
            let (goal, last) = if self.pool.is_open(id) {
                let task = &self.pool.tasks[id as usize];
                (self.pool.next_errand(id as u32, lines), task.done as usize + 1 == lines[task.line as usize].len())
            } else {
                (NONE, false)
            };
            let was = sh.goals[k];
            if delivered[k] {
                sh.events.push([EventKind::Deliver.code(), k as u32, was]);
                if goal != NONE {
                    sh.events.push([EventKind::Assign.code(), k as u32, goal]);
                }
            } else if goal != was {
                sh.events.push(if goal == NONE { [EventKind::PutBack.code(), k as u32, NONE] } else { [EventKind::Assign.code(), k as u32, goal] });
            }
            sh.goals[k] = goal;
            let state = match (goal == NONE, last) {
                (true, _) => State::Idle,
                (false, false) => State::ToPickup,
                (false, true) => State::ToDrop,
            } as u8;
            sh.state.push(if self.held[k] { state | MARKED } else { state });
        }
        if self.t > 0 {
            let tick = self.t - 1;
            for (k, ds) in self.record.delays.iter().enumerate() {
                if let Some(&(from, to)) = ds.last() {
                    if from == tick {
                        sh.events.push([EventKind::Wait.code(), k as u32, to]);
                        sh.delays += 1;
                    }
                }
            }
        }
    }
}

impl Run for Lorr26 {
    fn advance(&mut self, max: u64, mut sink: Option<&mut dyn FrameSink>) -> Result<u64> {
        let start = self.t;
        let until = u64::from(start).saturating_add(max).min(u64::from(u32::MAX)) as u32;
        let mut frame = Frame::default();
        while self.t < until {
            self.tick()?;
            if let Some(sink) = sink.as_deref_mut() {
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
        let (cols, m, half) = (self.floor.cols, self.floor.m, self.floor.size / 2.0);
        for p in &self.states {
            let (x, y) = corner(p, cols, m);
            f.x.push((f64::from(x + half) * CELL_PX) as f32);
            f.y.push((f64::from(y + half) * CELL_PX) as f32);
            f.heading.push(p.heading.wrapping_mul(64));
        }
        f.energy.extend(std::iter::repeat(u16::MAX).take(self.states.len()));
        f.state.extend_from_slice(&self.shown.state);
        if events {
            f.events.extend_from_slice(&self.shown.events);
        }
        f.counters = [self.record.messages.min(u64::from(u32::MAX)) as u32, self.shown.delays, self.finished() as u32];
    }

    fn describe(&self) -> Value {
        let mut v = crate::rules::grid::show::describe_grid(&self.problem, self.states.len());
        let (planner, scheduler, executor) = self.names();
        let o = &self.options;
        let mut inputs = json!({
            "problem": v["layout"]["name"], "rules": "2026", "teamSize": self.states.len(), "planner": planner,
            "scheduler": scheduler, "executor": executor, "seed": o.seed, "planTimeLimitMs": o.plan_time_limit_ms,
            "agentSize": self.floor.size, "agentCounter": self.floor.m,
        });
        if !o.staged_validation {
            inputs["stagedActionValidation"] = json!(false);
        }
        // The robot's radius: half its square, at most the cell's 0.4.
        v["radius"] = json!(vec![f64::from(self.floor.size).min(1.0) * 0.4 * CELL_PX; self.states.len()]);
        v["scenario"] = json!(serde_json::to_string_pretty(&inputs).expect("JSON serialises"));
        v["lorr"] = inputs;
        v
    }

    fn summary(&self) -> Summary {
        let f = self.figures();
        Summary {
            t: None,
            s: f.action_errors.into(),
            c: u64::from(self.shown.delays),
            outcome: "horizon",
            delivered: f.finished,
            window: 1000,
            windows: f.finished_per_1000,
            resources: Vec::new(),
            bottleneck: None,
        }
    }
}
