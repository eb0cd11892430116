//! Memory of one scenario file: virtual and resident memory of the process, the bytes per
//! robot of the fleet's columns, column by column, and the marginal resident memory of a
//! robot.
//!
//! `cargo run --release -p multibots-core --example memory -- benchmarks/sizes/huge.toml [ROBOTS] [STEPS]`
//!
//! prints one JSON line: `VmPeak`, `VmSize`, `VmHWM` and `VmRSS` (kB, from `/proc/self/status`)
//! after building the run and after `STEPS` steps (default 1000), and `columns`: each
//! per-robot column the engine's public surface shows (`Robots`, `RobotStats`), with its
//! element size and capacity-based bytes per robot.
//!
//! With `--marginal` it runs itself twice, at N and N/2 robots on the same layout, and prints
//! the marginal resident memory of a robot, `(RSS(N) - RSS(N/2)) / (N - N/2)`, the measure of
//! `benchmarks/scale.py`, beside the columns' sum.
//!
//! With `MULTIBOTS_MEMORY_KEEP=1` the run is kept alive at exit, so that
//! `heaptrack target/release/examples/memory SCENARIO N 300` reports its live heap as
//! "leaked" (the bytes per robot of docs/benchmarks.md: two fleet sizes, the difference).
use multibots_core::{Scenario, Simulation};
use std::mem::size_of_val;

/// `VmPeak`, `VmSize`, `VmHWM`, `VmRSS` of this process, kB.
fn status() -> [u64; 4] {
    let text = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| text.lines().find(|l| l.starts_with(name)).and_then(|l| l.split_whitespace().nth(1)).and_then(|v| v.parse().ok()).unwrap_or(0);
    [field("VmPeak:"), field("VmSize:"), field("VmHWM:"), field("VmRSS:")]
}

fn status_json(s: [u64; 4]) -> String {
    format!("{{\"VmPeak\":{},\"VmSize\":{},\"VmHWM\":{},\"VmRSS\":{}}}", s[0], s[1], s[2], s[3])
}

/// Bytes per robot of a column: its capacity times its element size, over the fleet.
fn per_robot<T>(v: &Vec<T>, n: usize) -> f64 {
    (v.capacity() * v.first().map_or(0, size_of_val)) as f64 / n.max(1) as f64
}

/// The per-robot columns the public surface shows, with element size and bytes per robot.
fn columns(sim: &Simulation) -> Vec<(String, usize, f64)> {
    let r = sim.robots();
    let st = sim.stats();
    let n = r.len();
    let mut out = Vec::new();
    macro_rules! col {
        ($prefix:literal, $owner:ident . $($field:ident),*) => {
            $(out.push((format!(concat!($prefix, "{}"), stringify!($field)), $owner.$field.first().map_or(0, size_of_val), per_robot(&$owner.$field, n)));)*
        };
    }
    col!("robots.", r.x, y, radius, speed, heading, state, energy, home, at_node, edge_u, edge_v, routing, goal, has_final, final_x, final_y, final_v);
    col!("robots.", r.wp_x, wp_y, wp_node, goods, cell, carrying, dwell, marked, waited, charger, via);
    col!("stats.", st.distance, wait_steps, collisions, state_steps, energy_used, delivered, charges, order_waits);
    out
}

fn run(path: &str, robots: Option<u32>, steps: u64) -> String {
    let text = std::fs::read_to_string(path).expect("read scenario");
    let mut s = Scenario::from_toml(&text, path).unwrap_or_else(|e| panic!("{e}"));
    if let Some(n) = robots {
        s.robots = n;
    }
    let before = status();
    let mut sim = Simulation::new(&s).unwrap_or_else(|e| panic!("{e}"));
    let built = status();
    let mut k = 0;
    while k < steps && !sim.done() {
        sim.step().unwrap_or_else(|e| panic!("{e}"));
        k += 1;
    }
    let after = status();
    let cols = columns(&sim);
    let total: f64 = cols.iter().map(|c| c.2).sum();
    let cols_json: Vec<String> = cols.iter().map(|(name, size, b)| format!("[\"{name}\",{size},{b}]")).collect();
    let line = format!(
        "{{\"robots\":{},\"steps\":{k},\"ordered\":{},\"start\":{},\"built\":{},\"after\":{},\"columns_bytes_per_robot\":{total},\"columns\":[{}]}}",
        sim.robots().len(),
        sim.goods_total(),
        status_json(before),
        status_json(built),
        status_json(after),
        cols_json.join(",")
    );
    if std::env::var("MULTIBOTS_MEMORY_KEEP").is_ok_and(|v| v == "1") {
        // Heaptrack then reports the run's live heap at the end as "leaked".
        std::mem::forget(sim);
    }
    line
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let marginal = args.iter().any(|a| a == "--marginal");
    let rest: Vec<&String> = args.iter().filter(|a| *a != "--marginal").collect();
    let path = rest.first().expect("usage: memory SCENARIO.toml [ROBOTS] [STEPS] [--marginal]").as_str();
    let robots: Option<u32> = rest.get(1).map(|s| s.parse().expect("robots")).filter(|&n| n > 0);
    let steps: u64 = rest.get(2).map_or(1000, |s| s.parse().expect("steps"));
    if !marginal {
        println!("{}", run(path, robots, steps));
        return;
    }
    // Two fresh processes, so that neither inherits the other's heap.
    let child = |n: u32| -> String {
        let exe = std::env::current_exe().expect("current exe");
        let out = std::process::Command::new(exe).args([path, &n.to_string(), &steps.to_string()]).output().expect("run child");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).expect("utf-8").trim().to_string()
    };
    let n = robots.unwrap_or_else(|| {
        let text = std::fs::read_to_string(path).expect("read scenario");
        Scenario::from_toml(&text, path).unwrap_or_else(|e| panic!("{e}")).robots
    });
    let half = (n / 2).max(1);
    let (full, low) = (child(n), child(half));
    let rss = |json: &str| -> f64 {
        let v: serde_json::Value = serde_json::from_str(json).expect("child JSON");
        v["after"]["VmRSS"].as_f64().expect("VmRSS")
    };
    let per = (rss(&full) - rss(&low)) * 1024.0 / f64::from(n - half);
    println!("{{\"robots\":{n},\"half\":{half},\"marginal_rss_bytes_per_robot\":{per},\"full\":{full},\"half_run\":{low}}}");
}
