//! Replays of League of Robot Runners runs, read back with the codec alone: what the grid's
//! frames (`rules/grid/show.rs`) show, written by the one recorder (`output/replay.rs`).

use multibots_core::input::lorr::{GridMap, Problem, Version};
use multibots_core::output::codec::{decode, inflate, Chunk};
use multibots_core::output::replay::ReplayWriter;
use multibots_core::rules::grid::action::Action;
use multibots_core::rules::grid::planner::{PlanView, Planner};
use multibots_core::rules::grid::{schedule, LorrOptions, LorrRun, Tasks};
use multibots_core::rules::Run;
use multibots_core::EventKind;
use serde_json::Value;
use std::path::Path;
use std::sync::Arc;

/// "No robot" or "no cell" in an event.
const NONE: u32 = u32::MAX;

const MAP: &str = "type octile\nheight 5\nwidth 6\nmap\n......\n.@..@.\n......\n.@@...\n......\n";

fn run(version: Version, limit: Option<u64>) -> LorrRun {
    let tasks: Vec<Vec<u32>> = match version {
        Version::Y2024 => vec![vec![0, 29], vec![5, 24, 12], vec![17], vec![26, 3], vec![14, 8]],
        Version::Y2023 => vec![vec![0], vec![29], vec![5], vec![24], vec![12], vec![17]],
        Version::Y2026 => unreachable!("LorrRun plays the 2023 and 2024 rules"),
    };
    let p = Problem { path: "t.json".into(), map: GridMap::parse(MAP).unwrap(), starts: vec![2, 13, 27], tasks, num_tasks_reveal: 1.0, version, y2026: None };
    LorrRun::new(Arc::new(p), LorrOptions { plan_time_limit_ms: limit, ..LorrOptions::default() }).unwrap()
}

/// The replay's header, footer and frames, decoded with the codec alone.
fn read(path: &Path) -> (Value, Value, Vec<Chunk>) {
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

impl Planner for Slow {
    fn name(&self) -> &'static str {
        "slow"
    }
    fn plan(&mut self, _: &PlanView<'_>, actions: &mut [Action]) {
        std::thread::sleep(std::time::Duration::from_millis(2));
        actions.fill(Action::F);
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
    let slow = LorrRun::with(Arc::new(base.problem().clone()), base.options().clone(), Box::new(Slow), schedule::built_in("nearest").unwrap()).unwrap();
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
