//! One run under the original rules, as one JSON line, to compare with the authors' code
//! (`tests/oracle/compare_original.py`):
//!
//! `cargo run --release -p multibots-core --example original_run -- --robots 6 --goods 11,8,39,28,53,1,69,42,79,6`
//!
//! prints `{"ticks", "S", "C", "outcome", "steps", "fault", "delivered", "per_robot": [...]}`;
//! `ticks` is null unless the run is complete. `--max-ticks K` sets the step limit (default
//! 100000). A scenario the original rules refuse prints `{"error": "..."}` and exits with 2.
//! `--bench SECONDS` instead repeats the run for about that long and prints its speed in
//! robot-steps per second.
use multibots_core::EventKind;
use multibots_core::{Original, Rules, Scenario};
use std::fmt::Write as _;
use std::time::Instant;

fn main() {
    let mut robots = 6u32;
    let mut goods: Vec<u32> = vec![11, 8, 39, 28, 53, 1, 69, 42, 79, 6];
    let mut max_ticks = 100_000u64;
    let mut bench: Option<f64> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--robots" | "-N" => robots = value().parse().expect("--robots N"),
            "--goods" => goods = value().split(',').filter(|s| !s.trim().is_empty()).map(|s| s.trim().parse().expect("--goods a,b,c")).collect(),
            "--max-ticks" => max_ticks = value().parse().expect("--max-ticks K"),
            "--bench" => bench = Some(value().parse().expect("--bench SECONDS")),
            other => panic!("unknown argument {other} (--robots N --goods a,b,c [--max-ticks K] [--bench SECONDS])"),
        }
    }
    let mut scenario = Scenario::paper(robots, &goods);
    scenario.rules = Rules::Original;
    scenario.step_limit = max_ticks;
    let mut run = match Original::new(&scenario) {
        Ok(run) => run,
        Err(e) => {
            println!("{{\"error\":{}}}", json_string(&e.to_string()));
            std::process::exit(2);
        }
    };
    if let Some(seconds) = bench {
        let (mut ticks, mut runs) = (0u64, 0u64);
        let t0 = Instant::now();
        while t0.elapsed().as_secs_f64() < seconds {
            let mut r = Original::new(&scenario).expect("validated above");
            while !r.done() {
                r.step();
            }
            ticks += r.t();
            runs += 1;
        }
        let secs = t0.elapsed().as_secs_f64();
        println!(
            "{{\"robots\":{robots},\"runs\":{runs},\"ticks\":{ticks},\"seconds\":{secs},\"robot_steps_per_s\":{}}}",
            f64::from(robots) * ticks as f64 / secs
        );
        return;
    }
    let n = robots as usize;
    let mut deliveries: Vec<Vec<(u64, u32)>> = vec![Vec::new(); n];
    while !run.done() {
        run.step();
        for e in run.events() {
            if e.kind == EventKind::Deliver {
                deliveries[e.robot as usize].push((e.step, e.cell));
            }
        }
    }
    let r = run.result();
    let mut per = String::new();
    for (i, done) in deliveries.iter().enumerate() {
        let d: Vec<String> = done.iter().map(|(t, c)| format!("[{t},{c}]")).collect();
        let _ = write!(
            per,
            "{}{{\"collisions\":{},\"charges\":{},\"deliveries\":[{}]}}",
            if i > 0 { "," } else { "" },
            r.robots.collisions[i],
            r.robots.charges[i],
            d.join(",")
        );
    }
    let ticks = r.t.map_or("null".to_string(), |t| t.to_string());
    let outcome = r.outcome.map_or("running", multibots_core::Outcome::as_str);
    let fault = run.fault().map_or("null".to_string(), |f| json_string(f.as_str()));
    println!(
        "{{\"ticks\":{ticks},\"S\":{},\"C\":{},\"outcome\":\"{outcome}\",\"steps\":{},\"fault\":{fault},\"delivered\":{},\"per_robot\":[{per}]}}",
        r.s, r.c, r.steps, r.delivered
    );
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).expect("a string serialises")
}
