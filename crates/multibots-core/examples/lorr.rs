//! Runs a League of Robot Runners problem (2023, 2024 or 2026; under the 2026 rules STEPS are
//! ticks) and writes the competition's result file:
//! `cargo run --release -p multibots-core --example lorr -- PROBLEM.json STEPS RESULT.json [SCHEDULER [PLANNER [SEED]]]`.
//! Prints the score and MultiBots' figures.

use multibots_core::input::lorr::{Problem, Version};
use multibots_core::rules::grid::{Lorr26, LorrOptions, LorrRun};
use std::sync::Arc;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 4 {
        eprintln!("usage: lorr PROBLEM.json STEPS RESULT.json [SCHEDULER [PLANNER [SEED]]]");
        std::process::exit(2);
    }
    let problem = match Problem::load(args[1].as_ref()) {
        Ok(p) => Arc::new(p),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let steps: u32 = args[2].parse().expect("STEPS is a whole number");
    let mut options = LorrOptions::default();
    if let Some(s) = args.get(4) {
        options.scheduler.clone_from(s);
    }
    if let Some(p) = args.get(5) {
        options.planner.clone_from(p);
    }
    if let Some(s) = args.get(6) {
        options.seed = s.parse().expect("SEED is a whole number");
    }
    if problem.version == Version::Y2026 {
        // Steps are ticks under the 2026 rules.
        let mut run = Lorr26::new(problem, options).expect("built-in options");
        let began = std::time::Instant::now();
        run.run_to(steps).expect("built-in entries do not fail");
        let wall = began.elapsed().as_secs_f64();
        multibots_core::output::lorr26::write_result(&run, args[3].as_ref()).expect("result written");
        let f = run.figures();
        println!(
            "{}: finished {} in {} ticks; {:.1} s wall, plan {:.2} ms mean, {:.1} ms max; messages {}, schedule errors {}, delays {}; per 1000: {:?}",
            run.names().0,
            f.finished,
            f.steps,
            wall,
            f.plan_ms_mean,
            f.plan_ms_max,
            f.action_errors,
            f.schedule_errors,
            f.delays.unwrap_or(0),
            f.finished_per_1000
        );
        return;
    }
    let mut run = LorrRun::new(problem, options).expect("built-in options");
    let began = std::time::Instant::now();
    run.run_to(steps);
    let wall = began.elapsed().as_secs_f64();
    multibots_core::output::lorr::write_result(&run, args[3].as_ref()).expect("result written");
    let f = run.figures();
    println!(
        "{}: finished {} in {} steps; {:.2} ms/step wall, plan {:.2} ms mean, {:.1} ms max; errors {}; per 1000: {:?}",
        run.planner(),
        f.finished,
        f.steps,
        wall * 1e3 / f64::from(f.steps.max(1)),
        f.plan_ms_mean,
        f.plan_ms_max,
        f.action_errors + f.schedule_errors,
        f.finished_per_1000
    );
}
