//! The paper rules' step, phase by phase (needs `--features profiling`):
//! `cargo run --release -p multibots-core --features profiling --example phases -- benchmarks/sizes/large.toml 1000 100`
//! runs the warm-up steps, then the measured ones, and prints one JSON line: each phase's
//! wall time and calls over the measured steps. Under
//! `valgrind --tool=callgrind --toggle-collect='*phases::measured*'` only the measured steps
//! are counted, and each phase is the inclusive count of its function `phase_<name>`
//! (`benchmarks/phases.py` runs both and prints the table).
use multibots_core::rules::profile;
use multibots_core::{Scenario, Simulation};
use std::time::Instant;

/// The measured steps, in a function of their own for callgrind's `--toggle-collect`.
#[inline(never)]
fn measured(sim: &mut Simulation, steps: u64) -> u64 {
    let mut k = 0;
    while k < steps && !sim.done() {
        sim.step().unwrap();
        k += 1;
    }
    k
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: phases SCENARIO.toml [STEPS] [WARMUP]");
    let steps: u64 = args.next().map_or(1000, |s| s.parse().expect("steps"));
    let warmup: u64 = args.next().map_or(100, |s| s.parse().expect("warm-up steps"));
    let text = std::fs::read_to_string(&path).expect("read scenario");
    let s = Scenario::from_toml(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Simulation::new(&s).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..warmup {
        sim.step().unwrap();
    }
    let _ = profile::take();
    let t0 = Instant::now();
    let k = measured(&mut sim, steps);
    let secs = t0.elapsed().as_secs_f64();
    let phases: Vec<String> =
        profile::take().iter().map(|p| format!("{{\"phase\":\"{}\",\"seconds\":{},\"calls\":{}}}", p.phase, p.wall.as_secs_f64(), p.calls)).collect();
    println!("{{\"robots\":{},\"steps\":{k},\"seconds\":{secs},\"phases\":[{}]}}", sim.robots().len(), phases.join(","));
}
