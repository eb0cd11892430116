//! Hostile and impossible input: every size the input controls is checked before anything is
//! allocated (docs/limits.md), layouts that cannot be real are refused, and work that cannot
//! be done is refused up front or ends the run with an outcome that says why.

use multibots_core::input::scenario::{Orders, Tasks};
use multibots_core::record::metrics::Outcome;
use multibots_core::world::layout_file;
use multibots_core::{Layout, LayoutParams, Scenario, Simulation};
use std::fmt::Write;

fn err(s: &Scenario) -> String {
    Simulation::new(s).err().expect("refused").to_string()
}

#[test]
fn generated_layouts_too_large_are_refused_before_any_allocation() {
    let p = LayoutParams { group_rows: 1, group_cols: 1, group_width: 1, group_height: 50_000_000, chargers: 2, ..LayoutParams::paper() };
    let e = Layout::generate(&p, "x").unwrap_err().to_string();
    // The field that makes it too large is named (issue 28: this said group_rows = 1).
    assert_eq!(e, "layout.group_height = 50000000: layout too large: 50000000 storage cells (at most 1000000)");
    let p = LayoutParams { aisle: 1e7, ..LayoutParams::paper() };
    let e = Layout::generate(&p, "x").unwrap_err().to_string();
    assert_eq!(e, "layout.aisle = 10000000: layout too large: 6.000e7 px across (at most 1e7)");
    // Aisles of 1e6 px fit, and a run on them is refused for what it is: no battery reaches
    // any goods (the collision grid, which would want billions of cells, stays bounded).
    let mut s = Scenario::paper(3, &[1, 2, 3]);
    s.layout_generate = Some(LayoutParams { aisle: 1e6, ..LayoutParams::paper() });
    assert!(err(&s).contains("a robot would turn back to charge before every pickup"), "{}", err(&s));
    let p = LayoutParams { cell: 1e308, ..LayoutParams::paper() };
    assert!(Layout::generate(&p, "x").unwrap_err().to_string().contains("layout too large"));
}

#[test]
fn scenario_sizes_are_limited() {
    let mut s = Scenario::paper(3, &[1]);
    s.robots = 2_000_000;
    assert_eq!(err(&s), "robots = 2000000: at most 1000000");
    let mut s = Scenario::paper(3, &[1]);
    s.orders = Some(Orders { rate: 1e300, ..Orders::default() });
    assert!(err(&s).starts_with("orders.rate = 1000000000000000000000000000"), "{}", err(&s));
    s.orders = Some(Orders { rate: 1e9, horizon: 1, ..Orders::default() });
    assert_eq!(err(&s), "orders.rate = 1000000000: at most 100000 orders per step");
    s.orders = Some(Orders { rate: 3.0, horizon: 1_000_000_000, ..Orders::default() });
    assert!(err(&s).contains("expects 3.000e9 orders"), "{}", err(&s));
    // Per-robot counters are 32-bit: no run may be longer than they count.
    s.orders = Some(Orders { rate: 0.001, horizon: 4_294_967_296, ..Orders::default() });
    assert_eq!(err(&s), "orders.horizon = 4294967296: at most 4294967295 steps");
    let mut s = Scenario::paper(3, &[1]);
    s.step_limit = 4_294_967_296;
    assert_eq!(err(&s), "step_limit = 4294967296: at most 4294967295");
    s.step_limit = 4_294_967_295;
    assert!(Simulation::new(&s).is_ok());
    let mut s = Scenario::paper(3, &[1]);
    s.charging.level = f64::NAN;
    assert_eq!(err(&s), "charging.level = NaN: must be a finite number");
}

#[test]
fn tiny_robots_run_on_a_bounded_grid() {
    // A contact distance of 0.002 px would want billions of grid cells: the grid's cells grow
    // instead, and the run goes on as before.
    let mut s = Scenario::paper(6, &[11, 8, 39, 28, 53, 1]);
    s.robot.radius = 0.001;
    let r = Simulation::new(&s).unwrap().run().unwrap();
    assert_eq!(r.outcome, Some(Outcome::Complete));
}

fn ring(n: usize) -> String {
    let mut t = String::from(
        "name = \"ring\"\nbounds = [0.0, 0.0, 1000000.0, 100.0]\naisle_width = 10.0\ncell_size = 10.0\ndeparture = [\"N0\"]\nunloading = [\"N1\"]\n",
    );
    for k in 0..n {
        let _ = write!(t, "[[nodes]]\nname = \"N{k}\"\nx = {}.0\ny = 50.0\nout = [\"N{}\"]\n", k * 20, (k + 1) % n);
    }
    t.push_str("[[chargers]]\nname = \"C\"\nx = 0.0\ny = 90.0\nnode = \"N0\"\n[[cells]]\nx = 5.0\ny = 60.0\nw = 10.0\nh = 10.0\nservice = [10.0, 50.0]\nedge = [\"N0\", \"N1\"]\n");
    t
}

#[test]
fn a_layout_with_too_many_nodes_is_refused_quickly() {
    let layout = layout_file::from_toml(&ring(40_000), "ring.toml").unwrap();
    let t0 = std::time::Instant::now();
    let e = layout_file::check_layout(&layout).unwrap_err().to_string();
    assert_eq!(e, "layout nodes: 40001 nodes: at most 12000 (the routing table takes one byte per pair of nodes)");
    assert!(t0.elapsed().as_secs() < 2);
}

#[test]
fn layouts_that_cannot_be_real_are_refused() {
    let good = layout_file::to_toml(&Layout::paper(), None);
    let check = |text: &str| layout_file::from_toml(text, "l.toml").and_then(|l| layout_file::check_layout(&l).map(drop)).unwrap_err().to_string();
    // The first cell (x = 50, y = 50, 50 × 50) moved onto the second, onto a crossing, out of
    // the bounds.
    let moved = |from: &str, to: &str| good.replacen(from, to, 1);
    let first = "[[cells]]\nx = 50.0\ny = 50.0\n";
    assert!(good.contains(first));
    assert!(
        check(&moved(first, "[[cells]]\nx = 75.0\ny = 50.0\n")).contains("overlaps cells[0]"),
        "{}",
        check(&moved(first, "[[cells]]\nx = 75.0\ny = 50.0\n"))
    );
    assert!(check(&moved(first, "[[cells]]\nx = 10.0\ny = 10.0\n")).contains("covers the node \"A\""));
    assert!(check(&moved(first, "[[cells]]\nx = -500.0\ny = 50.0\n")).contains("lies outside the bounds"));
    let no_cells = format!("cells = []\n{}", good.split("[[cells]]").next().unwrap());
    assert_eq!(check(&no_cells), "layout cells: no storage cell (at least one is needed)");
}

#[test]
fn work_no_battery_can_carry_is_refused_and_a_task_none_can_reach_ends_in_livelock() {
    // With a threshold of 9, a robot may spend 1 energy (200 steps) before it turns back.
    let single = |cell: u32| {
        let mut s = Scenario::paper(1, &[cell]);
        s.robot.threshold = 9.0;
        s
    };
    let (ok, bad): (Vec<u32>, Vec<u32>) = (0..80).partition(|&c| Simulation::new(&single(c)).is_ok());
    assert!(!ok.is_empty() && !bad.is_empty(), "{ok:?} {bad:?}");
    let e = err(&single(bad[0]));
    assert!(e.starts_with(&format!("tasks[0] = {}: reaching it takes", bad[0])) && e.ends_with("a robot would turn back to charge before every pickup"), "{e}");
    // One reachable task and one that is not: the run does the first, then livelocks.
    let mut s = single(ok[0]);
    s.tasks = Tasks::Cells(vec![i64::from(ok[0]), i64::from(bad[0])]);
    let r = Simulation::new(&s).unwrap().run().unwrap();
    assert_eq!((r.outcome, r.delivered), (Some(Outcome::Livelock), 1));
    // Two battery cycles: 2 × (10 / 0.005 + 10 / 0.05) = 4,400 steps after the last pickup
    // or delivery.
    assert!(r.steps < 6000, "{}", r.steps);
}

#[test]
fn values_in_messages_are_short_and_inert() {
    let mut s = Scenario::paper(1, &[1]);
    s.unload = multibots_core::Unload::Node(format!("\u{1b}[31m{}", "x".repeat(1_000_000)));
    let e = err(&s);
    assert!(e.len() < 200 && e.contains("\\u{1b}[31m") && e.contains("(1000007 characters)"), "{e}");
}
