//! Decisions per second of the dispatcher engine alone (no Python): random valid actions on
//! the paper scenario, one thread. `cargo run --release --example decisions_speed [envs] [secs]`
use multibots_core::learning::observation::Observation;
use multibots_core::learning::{Dispatcher, Settings};
use multibots_core::Scenario;
use std::time::Instant;

fn main() {
    let envs: usize = std::env::args().nth(1).map_or(16, |s| s.parse().expect("envs"));
    let secs: f64 = std::env::args().nth(2).map_or(3.0, |s| s.parse().expect("secs"));
    let s = Scenario::paper(3, &multibots_core::input::scenario::PAPER_TASKS[0]);
    let mut ds: Vec<Dispatcher> = (0..envs).map(|_| Dispatcher::new(&s, Settings::of(&s)).unwrap()).collect();
    let mut obs = Observation::zeros(3, 10);
    let mut rng: u64 = 1;
    let (mut decisions, mut episodes, mut steps) = (0u64, 0u64, 0u64);
    let start = Instant::now();
    while start.elapsed().as_secs_f64() < secs {
        for d in &mut ds {
            if d.ended() {
                steps += d.progress().t;
                episodes += 1;
                d.reset(None).unwrap();
            }
            d.observe(obs.as_mut());
            let allowed: Vec<usize> = (0..12).filter(|&a| obs.mask[a] == 1).collect();
            rng = rng.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            d.step(allowed[(rng >> 33) as usize % allowed.len()] as i64).unwrap();
            decisions += 1;
        }
    }
    let el = start.elapsed().as_secs_f64();
    println!(
        "{:.0} decisions/s, {episodes} episodes, {:.1} decisions/episode, {:.0} steps/episode",
        decisions as f64 / el,
        decisions as f64 / episodes as f64,
        steps as f64 / episodes as f64
    );
}
