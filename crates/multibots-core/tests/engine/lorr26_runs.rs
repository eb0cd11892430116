//! 2026 runs judged from outside: the built-in entries play the Start-Kit's example problems
//! for a few ticks, and `lorr_check26.py` (an independent replay of the 2026 rules beside the
//! repository, `../shared/tools/`) finds each result valid with the same count. Skipped
//! when the examples or the checker are not there.

use multibots_core::input::lorr::Problem;
use multibots_core::output::lorr26::write_result;
use multibots_core::rules::grid::{Lorr26, LorrOptions};
use std::path::PathBuf;
use std::sync::Arc;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared")
}

fn run_and_check(name: &str, ticks: u32) {
    let problem = shared().join("reference/lorr/2026").join(name);
    let checker = shared().join("tools/lorr_check26.py");
    if !problem.is_file() || !checker.is_file() {
        eprintln!("skipped: {} or {} missing", problem.display(), checker.display());
        return;
    }
    let mut run = Lorr26::new(Arc::new(Problem::load(&problem).unwrap()), LorrOptions::default()).unwrap();
    run.run_to(ticks).unwrap();
    let out = std::env::temp_dir().join(format!("mb-lorr26-{}-{}.json", std::process::id(), ticks));
    write_result(&run, &out).unwrap();
    let p = std::process::Command::new("python3").arg(&checker).arg(&problem).arg(&out).output().unwrap();
    let _ = std::fs::remove_file(&out);
    let text = String::from_utf8_lossy(&p.stdout);
    let verdict: serde_json::Value = serde_json::from_str(text.lines().last().unwrap_or("{}")).unwrap();
    assert_eq!(verdict["valid"], true, "{name}: {text} {}", String::from_utf8_lossy(&p.stderr));
    assert_eq!(verdict["finished"].as_u64(), Some(run.finished()), "{name}: {text}");
}

#[test]
fn maze_is_valid_under_the_checker() {
    run_and_check("maze.domain/maze-example_40.json", 200);
}

#[test]
fn room_is_valid_under_the_checker() {
    run_and_check("room.domain/room-example_150.json", 100);
}

#[test]
fn city_is_valid_under_the_checker() {
    run_and_check("city.domain/bos-example_600.json", 50);
}
