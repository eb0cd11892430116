//! Prints the paper's 30-run table (N = 1..6 × TABLE III) from the engine alone.
use multibots_core::{Scenario, Simulation};

use multibots_core::input::scenario::PAPER_TASKS as GROUPS;

fn main() {
    let margin: f64 = std::env::args().nth(1).map_or(0.0, |s| s.parse().expect("margin"));
    println!("N group     T    S  C");
    for n in 1..=6 {
        for (g, cells) in GROUPS.iter().enumerate() {
            let mut s = Scenario::paper(n, cells);
            s.collision.margin = margin;
            let r = Simulation::new(&s).unwrap().run().unwrap();
            println!("{n} {:5} {:5} {:4} {:2} {}", g + 1, r.t.map_or(-1, |t| t as i64), r.s, r.c, r.outcome.unwrap().as_str());
        }
    }
}
