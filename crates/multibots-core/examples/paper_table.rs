//! Prints the paper's 30-run table (N = 1..6 × TABLE III) from the engine alone.
use multibots_core::{Scenario, Simulation};

const GROUPS: [[u32; 10]; 5] = [
    [11, 8, 39, 28, 53, 1, 69, 42, 79, 6],
    [74, 50, 62, 15, 49, 34, 14, 72, 31, 37],
    [68, 79, 56, 47, 48, 75, 23, 50, 76, 16],
    [59, 6, 74, 2, 67, 49, 53, 28, 25, 79],
    [14, 65, 41, 75, 22, 36, 54, 74, 9, 48],
];

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
