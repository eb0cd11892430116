//! Replays of League of Robot Runners runs (`multibots lorr --record`), in the replay format
//! of `docs/replay-format.md`, version 1, unchanged: a grid world is a layout with no
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
//! robot stood still.

use crate::error::Result;
use crate::fleet::robot::State;
use crate::input::lorr::Version;
use crate::output::events::EventKind;
use crate::output::replay::{names, ReplayWriter};
use crate::rules::grid::{LorrRun, Tasks};
use serde_json::{json, Value};
use std::path::Path;

/// A grid cell's side, in px: robots of 0.4 cells (6.4 px) are legible at the viewer's and
/// the exporter's scales, and the largest LoRR map (500 cells) is 8,000 px wide.
pub const CELL_PX: f64 = 16.0;
/// A robot's radius, in px.
const RADIUS: f64 = 0.4 * CELL_PX;
/// "No robot" or "no cell" in an event.
const NONE: u32 = u32::MAX;

/// Writes a replay while a LoRR run goes: [`GridReplay::create`] at step 0,
/// [`GridReplay::run_to`] to play and record, [`GridReplay::finish`] at the end. Dropped
/// unfinished, it leaves nothing behind.
pub struct GridReplay {
    writer: ReplayWriter,
    cols: u32,
    /// Each robot's goal in the last frame, or [`NONE`].
    goals: Vec<u32>,
    /// Whether each robot finished a task in the step just run.
    delivered: Vec<bool>,
    /// The last frame, repeated for steps lost to the plan time limit.
    x: Vec<f32>,
    y: Vec<f32>,
    heading: Vec<u8>,
    state: Vec<u8>,
    counters: [u32; 3],
    events: Vec<u32>,
}

/// The header of a grid replay: the fleet, the grid as a layout, the run's inputs.
#[must_use]
pub fn header(run: &LorrRun) -> Value {
    let p = run.problem();
    let (rows, cols) = (p.map.rows, p.map.cols);
    let grid: Vec<String> =
        (0..rows as usize).map(|r| p.map.free[r * cols as usize..(r + 1) * cols as usize].iter().map(|&f| if f { '.' } else { '@' }).collect()).collect();
    let n = run.locations().len();
    let o = run.options();
    let version = match p.version {
        Version::Y2023 => "2023",
        Version::Y2024 => "2024",
    };
    let name = p.path.file_name().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let inputs = json!({"problem": name, "rules": version, "teamSize": n, "planner": o.planner, "scheduler": o.scheduler, "seed": o.seed, "planTimeLimitMs": o.plan_time_limit_ms});
    let mut h = json!({
        "format": "multibots-replay",
        "version": crate::output::codec::VERSION,
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
    });
    if let (Value::Object(h), Value::Object(names)) = (&mut h, names()) {
        h.extend(names);
    }
    h
}

impl GridReplay {
    /// Opens the replay at `path` and records frame 0 (the run's state before step 1).
    pub fn create(path: &Path, run: &LorrRun) -> Result<GridReplay> {
        let n = run.locations().len();
        let writer = ReplayWriter::open(path, header(run), n)?;
        let mut g = GridReplay {
            writer,
            cols: run.problem().map.cols,
            goals: vec![NONE; n],
            delivered: vec![false; n],
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            heading: Vec::with_capacity(n),
            state: Vec::with_capacity(n),
            counters: [0; 3],
            events: Vec::new(),
        };
        g.frame(run)?;
        Ok(g)
    }

    /// Plays `run` up to step `until` (as [`LorrRun::run_to`]), recording every step; the
    /// steps run.
    pub fn run_to(&mut self, run: &mut LorrRun, until: u32) -> Result<u32> {
        let start = run.t();
        while run.t() < until {
            run.step(until);
            // Steps lost to the plan time limit: every robot waited.
            while self.writer.frames() < u64::from(run.t()) {
                self.repeat()?;
            }
            self.frame(run)?;
        }
        Ok(run.t() - start)
    }

    /// Writes the last chunk and the footer (the score, refused actions, finished tasks per
    /// 1,000 steps) and moves the file into place.
    pub fn finish(self, run: &LorrRun) -> Result<()> {
        let f = run.figures();
        self.writer.finish_with(json!({
            "T": null,
            "S": f.action_errors,
            "C": 0,
            "outcome": "horizon",
            "delivered": f.finished,
            "window": 1000,
            "windows": f.finished_per_1000,
        }))
    }

    fn repeat(&mut self) -> Result<()> {
        self.push_frame(false)
    }

    /// The frame of the robots as they stand, with this step's events or none.
    fn push_frame(&mut self, with_events: bool) -> Result<()> {
        let Self { x, y, heading, state, events, .. } = self;
        self.writer.push_with(self.counters, |c| {
            c.x.extend_from_slice(x);
            c.y.extend_from_slice(y);
            c.energy.extend(std::iter::repeat(u16::MAX).take(x.len()));
            c.heading.extend_from_slice(heading);
            c.state.extend_from_slice(state);
            if with_events {
                c.events.extend_from_slice(events);
            }
        })
    }

    /// Which robots finished a task in the step that led to frame `frame` (none in frame 0).
    fn mark_delivered(&mut self, run: &LorrRun, frame: u32) {
        self.delivered.fill(false);
        if frame == 0 {
            return;
        }
        match run.tasks() {
            Tasks::Pool(pool) => pool.new_free.iter().for_each(|&k| self.delivered[k as usize] = true),
            Tasks::RoundRobin(rr) => {
                for (k, events) in rr.events.iter().enumerate() {
                    // This step's events are the last ones: a finish, then the errands revealed.
                    self.delivered[k] = events.iter().rev().take_while(|e| e.1 == run.t()).any(|e| e.2);
                }
            }
        }
    }

    /// Records the run's state now as the next frame, with the goals that changed.
    fn frame(&mut self, run: &LorrRun) -> Result<()> {
        let frame = self.writer.frames() as u32;
        let lines = &run.problem().tasks;
        self.x.clear();
        self.y.clear();
        self.heading.clear();
        self.state.clear();
        self.events.clear();
        self.mark_delivered(run, frame);
        for (k, (&cell, &h)) in run.locations().iter().zip(run.headings()).enumerate() {
            let (goal, last) = match run.tasks() {
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
            self.x.push(((f64::from(cell % self.cols) + 0.5) * CELL_PX) as f32);
            self.y.push(((f64::from(cell / self.cols) + 0.5) * CELL_PX) as f32);
            self.heading.push(h.wrapping_mul(64));
            let was = self.goals[k];
            if self.delivered[k] {
                self.events.extend_from_slice(&[frame, EventKind::Deliver.code(), k as u32, was]);
                if goal != NONE {
                    self.events.extend_from_slice(&[frame, EventKind::Assign.code(), k as u32, goal]);
                }
            } else if goal != was {
                let e = if goal == NONE { [frame, EventKind::PutBack.code(), k as u32, NONE] } else { [frame, EventKind::Assign.code(), k as u32, goal] };
                self.events.extend_from_slice(&e);
            }
            self.goals[k] = goal;
            self.state.push(match (goal == NONE, last) {
                (true, _) => State::Idle,
                (false, false) => State::ToPickup,
                (false, true) => State::ToDrop,
            } as u8);
        }
        self.counters = [run.record().errors.len() as u32, 0, run.finished() as u32];
        self.push_frame(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::lorr::{GridMap, Problem};
    use crate::output::codec::{decode, inflate};
    use crate::rules::grid::LorrOptions;
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
        let mut w = GridReplay::create(&path, &r).unwrap();
        assert_eq!(w.run_to(&mut r, steps / 2).unwrap() + w.run_to(&mut r, steps).unwrap(), steps);
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
        let e = GridReplay::create(&missing, &r).err().unwrap().to_string();
        assert!(e.contains("mb-no-such-folder-grid"), "{e}");
        // A folder of its own: other tests write to the temporary folder meanwhile.
        let dir = std::env::temp_dir().join(format!("mb-grid-replay-{}-dropped", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        drop(GridReplay::create(&dir.join("r.mbr"), &r).unwrap());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir(&dir).unwrap();
    }
}
