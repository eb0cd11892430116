//! Criterion bench of the engine on one thread (`make bench` runs it with `--quick`).
//!
//! Named sizes, shared with `benchmarks/*.py` through the scenario files in
//! `benchmarks/sizes/`: paper (N = 6), small (100), large (1,000), huge (10,000).
//!
//! - `paper/run`: the paper scenario (N = 6, task list group 1) from start to T; throughput
//!   in robot-steps (6 × T per run).
//! - `paper/experiment-30`: the paper's whole 30-run experiment (N = 1..6 × TABLE III).
//! - `step/<size>`: one step of a working lifelong fleet, timed over steps 101..=1100 of
//!   fresh fleets (a fleet is rebuilt, untimed, when it reaches step 1100); throughput in
//!   robot-steps (N per step).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use multibots_core::{Scenario, Simulation};
use std::hint::black_box;
use std::time::{Duration, Instant};

const SIZES: [(&str, &str); 4] = [
    ("paper", include_str!("../../../benchmarks/sizes/paper.toml")),
    ("small", include_str!("../../../benchmarks/sizes/small.toml")),
    ("large", include_str!("../../../benchmarks/sizes/large.toml")),
    ("huge", include_str!("../../../benchmarks/sizes/huge.toml")),
];

use multibots_core::input::scenario::PAPER_TASKS as GROUPS;

fn scenario(name: &str) -> Scenario {
    let text = SIZES.iter().find(|s| s.0 == name).expect("a named size").1;
    Scenario::from_toml(text, name).expect("the size files are valid")
}

fn paper(c: &mut Criterion) {
    let s = scenario("paper");
    let t = Simulation::new(&s).unwrap().run().unwrap().t.expect("the paper run completes");
    let mut g = c.benchmark_group("paper");
    g.throughput(Throughput::Elements(u64::from(s.robots) * t));
    g.bench_function("run", |b| b.iter(|| black_box(Simulation::new(&s).unwrap().run().unwrap())));
    let all: Vec<Scenario> = (1..=6).flat_map(|n| GROUPS.iter().map(move |cells| Scenario::paper(n, cells))).collect();
    let robot_steps: u64 = all.iter().map(|s| u64::from(s.robots) * Simulation::new(s).unwrap().run().unwrap().steps).sum();
    g.throughput(Throughput::Elements(robot_steps));
    g.bench_function("experiment-30", |b| {
        b.iter(|| {
            for s in &all {
                black_box(Simulation::new(s).unwrap().run().unwrap());
            }
        });
    });
    g.finish();
}

/// Steps timed per fleet: 100 warm-up steps, then steps 101..=1100, then a fresh fleet. The
/// Python benchmarks time the same window.
const WARMUP: u64 = 100;
const WINDOW_END: u64 = 1100;

fn fresh(s: &Scenario) -> Simulation {
    let mut sim = Simulation::new(s).unwrap();
    for _ in 0..WARMUP {
        sim.step().unwrap();
    }
    sim
}

fn steps(c: &mut Criterion) {
    let mut g = c.benchmark_group("step");
    for name in ["small", "large", "huge"] {
        let s = scenario(name);
        let mut sim = fresh(&s);
        g.throughput(Throughput::Elements(u64::from(s.robots)));
        if name == "huge" {
            g.sample_size(10);
        }
        g.bench_function(name, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    if sim.t() >= WINDOW_END {
                        sim = fresh(&s); // untimed: the window starts again
                    }
                    let t0 = Instant::now();
                    sim.step().unwrap();
                    total += t0.elapsed();
                }
                total
            });
        });
    }
    g.finish();
}

criterion_group!(benches, paper, steps);
criterion_main!(benches);
