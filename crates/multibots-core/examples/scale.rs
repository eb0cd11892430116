//! Robot-steps per second of one scenario file, on one thread:
//! `cargo run --release -p multibots-core --example scale -- benchmarks/sizes/large.toml 1000`
//! (warm-up steps first, then the timed steps; prints one JSON line).
use multibots_core::{Scenario, Simulation};
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: scale SCENARIO.toml [STEPS] [WARMUP]");
    let steps: u64 = args.next().map_or(1000, |s| s.parse().expect("steps"));
    let warmup: u64 = args.next().map_or(100, |s| s.parse().expect("warm-up steps"));
    let text = std::fs::read_to_string(&path).expect("read scenario");
    let s = Scenario::from_toml(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    let t0 = Instant::now();
    let mut sim = Simulation::new(&s).unwrap_or_else(|e| panic!("{e}"));
    let build = t0.elapsed().as_secs_f64();
    for _ in 0..warmup {
        sim.step().unwrap();
    }
    let t1 = Instant::now();
    let mut k = 0;
    while k < steps && !sim.done() {
        sim.step().unwrap();
        k += 1;
    }
    let secs = t1.elapsed().as_secs_f64();
    let n = sim.robots().len() as f64;
    if std::env::var_os("SCALE_STATES").is_some() {
        let mut hist = [0usize; multibots_core::State::COUNT];
        for st in &sim.robots().state {
            hist[*st as usize] += 1;
        }
        let waits: u64 = sim.stats().wait_steps.iter().map(|&w| u64::from(w)).sum();
        let dist: f64 = sim.stats().distance.iter().sum();
        eprintln!("states {hist:?} queue {} wait share {:.3} mean distance {:.0}", sim.queue_cells().len(), waits as f64 / (n * sim.t() as f64), dist / n);
    }
    // FNV-1a over positions, states and energies: a change of behaviour shows as a new
    // fingerprint, while optimisations must keep it.
    let r = sim.robots();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for i in 0..r.len() {
        for w in [r.x[i].to_bits(), r.y[i].to_bits(), r.energy[i].to_bits(), r.state[i] as u64] {
            h = (h ^ w).wrapping_mul(0x0100_0000_01b3);
        }
    }
    // People's positions too, where there are people (a run without them hashes as before).
    if let Some(p) = sim.people() {
        for (x, y) in p.x.iter().zip(&p.y) {
            for w in [x.to_bits(), y.to_bits()] {
                h = (h ^ w).wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    println!(
        "{{\"robots\":{},\"steps\":{k},\"seconds\":{secs},\"robot_steps_per_s\":{},\"build_seconds\":{build},\"delivered\":{},\"s\":{},\"c\":{},\"fingerprint\":\"{h:016x}\"}}",
        n,
        n * k as f64 / secs,
        sim.delivered(),
        sim.s(),
        sim.c()
    );
}
