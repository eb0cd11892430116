//! Prints every built-in strategy's results on the paper's 30 runs, under both charging
//! policies, plus 10 seeded random lists of 10 goods: a fingerprint of the strategies'
//! behaviour (benchmarks/fingerprints.sh hashes it).
use multibots_core::alloc::BUILT_INS;
use multibots_core::input::scenario::{ChargingPolicy, Tasks, PAPER_TASKS};
use multibots_core::{Scenario, Simulation};

fn main() {
    println!("strategy policy N list T S C delivered distance outcome");
    for name in BUILT_INS {
        for policy in [ChargingPolicy::Threshold, ChargingPolicy::Opportunistic] {
            for n in 1..=6 {
                let lists = PAPER_TASKS
                    .iter()
                    .map(|g| Tasks::Cells(g.iter().map(|&c| i64::from(c)).collect()))
                    .chain((1..=10).map(|seed| Tasks::Random { random: 10, seed }));
                for (k, tasks) in lists.enumerate() {
                    let mut s = Scenario::paper(n, &[]);
                    s.tasks = tasks;
                    s.allocator = (*name).to_string();
                    s.charging.policy = policy;
                    let r = Simulation::new(&s).unwrap().run().unwrap();
                    let d: f64 = r.robots.distance.iter().sum();
                    println!("{name} {policy:?} {n} {k} {:?} {} {} {} {d:.6} {}", r.t, r.s, r.c, r.delivered, r.outcome.unwrap().as_str());
                }
            }
        }
    }
}
