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
        let (rows, cols) = (p.map.rows, p.map.cols);
        let grid: Vec<String> =
            (0..rows as usize).map(|r| p.map.free[r * cols as usize..(r + 1) * cols as usize].iter().map(|&f| if f { '.' } else { '@' }).collect()).collect();
        let n = self.loc.len();
        let o = &self.options;
        let version = match p.version {
            Version::Y2023 => "2023",
            Version::Y2024 => "2024",
        };
        let name = p.path.file_name().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        let inputs = json!({"problem": name, "rules": version, "teamSize": n, "planner": o.planner, "scheduler": o.scheduler, "seed": o.seed, "planTimeLimitMs": o.plan_time_limit_ms});
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
            "scenario": serde_json::to_string_pretty(&inputs).expect("JSON serialises"),
            "lorr": inputs,
        })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::lorr::{GridMap, Problem};
    use crate::output::codec::{decode, inflate};
    use crate::output::replay::ReplayWriter;
    use crate::rules::grid::LorrOptions;
    use std::path::Path;
    use std::sync::Arc;

    const MAP: &str = "type octile\nheight 5\nwidth 6\nmap\n......\n.@..@.\n......\n.@@...\n......\n";

    fn run(version: Version, limit: Option<u64>) -> LorrRun {
        let tasks: Vec<Vec<u32>> = match version {
            Version::Y2024 => vec![vec![0, 29], vec![5, 24, 12], vec![17], vec![26, 3], vec![14, 8]],
            Version::Y2023 => vec![vec![0], vec![29], vec![5], vec![24], vec![12], vec![17]],
        };
        let p = Problem { path: "t.json".into(), map: GridMap::parse(MAP).unwrap(), starts: vec![2, 13, 27], tasks, num_tasks_reveal: 1.0, version };
        LorrRun::new(Arc::new(p), LorrOptions { plan_time_limit_ms: limit, ..LorrOptions::default() }).unwrap()
    }

    /// The replay's header, footer and frames, decoded with the codec alone.
    fn read(path: &Path) -> (Value, Value, Vec<crate::output::codec::Chunk>) {
        let b = std::fs::read(path).unwrap();
        let hlen = u32::from_le_bytes(b[12..16].try_into().unwrap()) as usize;
        let header: Value = serde_json::from_slice(&b[16..16 + hlen]).unwrap();
        let end = b.len();
        let at = u64::from_le_bytes(b[end - 16..end - 8].try_into().unwrap()) as usize;
        let flen = u64::from_le_bytes(b[end - 8..].try_into().unwrap()) as usize;
        let footer: Value = serde_json::from_slice(&b[at..at + flen]).unwrap();
        let chunks = footer["chunks"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                let (o, l) = (c["offset"].as_u64().unwrap() as usize, c["length"].as_u64().unwrap() as usize);
                decode(&inflate(&b[o..o + l], 1 << 24).unwrap()).unwrap()
            })
            .collect();
        (header, footer, chunks)
    }

    fn record(mut r: LorrRun, steps: u32, name: &str) -> (LorrRun, std::path::PathBuf) {
        let path = std::env::temp_dir().join(format!("mb-grid-replay-{}-{name}.mbr", std::process::id()));
        let mut w = ReplayWriter::create(&path, &r, Value::Null).unwrap();
        let half = u64::from(steps / 2);
        assert_eq!(r.advance(half, Some(&mut w)).unwrap() + r.advance(u64::from(steps) - half, Some(&mut w)).unwrap(), u64::from(steps));
        w.finish(&r).unwrap();
        (r, path)
    }

    /// The replay says what the run did: positions and headings of the last frame, the
    /// score in the counters, one DELIVER per finished task, and the goals the events leave
    /// are each robot's next errand.
    #[test]
    fn a_replay_holds_the_run() {
        for version in [Version::Y2024, Version::Y2023] {
            let (r, path) = record(run(version, None), 60, "holds");
            let (header, footer, chunks) = read(&path);
            assert_eq!(header["layout"]["grid"]["cells"][1], ".@..@.");
            assert_eq!(header["robots"], 3);
            assert_eq!(footer["frames"], 61);
            assert_eq!(footer["delivered"], r.finished());
            let last = chunks.last().unwrap();
            let k = (last.frames - 1) as usize;
            for (i, &cell) in r.locations().iter().enumerate() {
                assert_eq!((last.x[3 * k + i], last.y[3 * k + i]), (((cell % 6) as f32 + 0.5) * 16.0, ((cell / 6) as f32 + 0.5) * 16.0));
                assert_eq!(last.heading[3 * k + i], r.headings()[i] * 64);
            }
            assert_eq!(u64::from(last.counters[3 * k + 2]), r.finished());
            let events: Vec<&[u32]> = chunks.iter().flat_map(|c| c.events.chunks_exact(4)).collect();
            let deliver = EventKind::Deliver.code();
            assert!(r.finished() > 0);
            assert_eq!(events.iter().filter(|e| e[1] == deliver).count() as u64, r.finished(), "{version:?}");
            let mut goals = [NONE; 3];
            for e in &events {
                goals[e[2] as usize] = if e[1] == EventKind::Assign.code() { e[3] } else { NONE };
            }
            let expected: Vec<u32> = (0..3)
                .map(|k| match r.tasks() {
                    Tasks::RoundRobin(rr) => rr.goal(k),
                    Tasks::Pool(p) => {
                        if p.is_open(p.current[k]) {
                            p.next_errand(p.current[k] as u32, &r.problem().tasks)
                        } else {
                            NONE
                        }
                    }
                })
                .collect();
            assert_eq!(goals[..], expected[..], "{version:?}");
            std::fs::remove_file(&path).unwrap();
        }
    }

    /// A planner that takes at least 2 ms a round and goes east when it can.
    struct Slow;

    impl crate::rules::grid::planner::Planner for Slow {
        fn name(&self) -> &'static str {
            "slow"
        }
        fn plan(&mut self, _: &crate::rules::grid::planner::PlanView<'_>, actions: &mut [crate::rules::grid::action::Action]) {
            std::thread::sleep(std::time::Duration::from_millis(2));
            actions.fill(crate::rules::grid::action::Action::F);
        }
    }

    /// Two recordings of one seed are the same bytes; steps lost to the plan time limit are
    /// frames too, in which the robots stand still (a 1 ms limit and a 2 ms planner: each
    /// round loses at least two steps).
    #[test]
    fn recordings_are_deterministic_and_frame_every_step() {
        let (_, a) = record(run(Version::Y2024, None), 40, "a");
        let (_, b) = record(run(Version::Y2024, None), 40, "b");
        assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        let base = run(Version::Y2024, Some(1));
        let slow =
            LorrRun::with(Arc::new(base.problem().clone()), base.options().clone(), Box::new(Slow), crate::rules::grid::schedule::built_in("nearest").unwrap())
                .unwrap();
        let (r, c) = record(slow, 30, "c");
        assert!(r.record().timeouts >= 20, "{}", r.record().timeouts);
        let (_, footer, chunks) = read(&c);
        assert_eq!(footer["frames"], 31);
        let c0 = &chunks[0];
        assert_eq!(c0.frames, 31);
        // Robot 0 starts at (0, 2) facing east: at least frames 1 and 2 are waits, then it
        // moves one cell east.
        let xs: Vec<f32> = c0.x.iter().step_by(3).copied().collect();
        let moved = xs.iter().position(|&x| x != 40.0).unwrap();
        assert!(moved >= 3, "{xs:?}");
        assert_eq!(xs[moved], 56.0);
        for p in [a, b, c] {
            std::fs::remove_file(p).unwrap();
        }
    }

    /// A replay that cannot be opened is an error naming the path; one dropped unfinished
    /// leaves no file.
    #[test]
    fn nothing_half_written() {
        let r = run(Version::Y2024, None);
        let missing = std::env::temp_dir().join("mb-no-such-folder-grid").join("r.mbr");
        let e = ReplayWriter::create(&missing, &r, Value::Null).err().unwrap().to_string();
        assert!(e.contains("mb-no-such-folder-grid"), "{e}");
        // A folder of its own: other tests write to the temporary folder meanwhile.
        let dir = std::env::temp_dir().join(format!("mb-grid-replay-{}-dropped", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        drop(ReplayWriter::create(&dir.join("r.mbr"), &r, Value::Null).unwrap());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir(&dir).unwrap();
    }
}
