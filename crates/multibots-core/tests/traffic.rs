//! Traffic policies (docs/traffic.md): `wait` is the paper's rule unchanged; `reserve` never
//! lets two robots come closer than r_i + r_j and keeps warehouses moving under overload;
//! `gate` takes crossings one robot at a time.

mod common;

use common::PAPER_TASKS;
use multibots_core::output::metrics::Outcome;
use multibots_core::world::layout::Aisles;
use multibots_core::{Scenario, Simulation, Traffic};

#[allow(clippy::too_many_arguments)]
fn lifelong(rows: u32, cols: u32, unloading_rows: u32, aisles: Aisles, robots: u32, rate: f64, steps: u64, traffic: Traffic) -> Scenario {
    common::lifelong(rows, cols, unloading_rows, cols + 1, aisles, robots, rate, steps, traffic)
}

#[test]
fn wait_is_the_default_and_the_paper_rule_unchanged() {
    for (n, g) in [(1, 0), (3, 2), (6, 4)] {
        let s = Scenario::paper(n, &PAPER_TASKS[g]);
        let mut explicit = s.clone();
        explicit.traffic = Traffic::Wait;
        assert_eq!(Simulation::new(&s).unwrap().run().unwrap(), Simulation::new(&explicit).unwrap().run().unwrap());
    }
    let s = lifelong(4, 6, 1, Aisles::Paper, 80, 1.0, 1500, Traffic::Wait);
    assert_eq!(Scenario::from_toml(&s.to_toml(), "s.toml").unwrap(), s);
    assert!(!s.to_toml().contains("traffic"), "the default is not written");
}

#[test]
fn reserve_runs_the_paper_experiment_without_a_contact() {
    for n in 1..=6 {
        for g in &PAPER_TASKS {
            let mut s = Scenario::paper(n, g);
            s.traffic = Traffic::Reserve;
            let r = Simulation::new(&s).unwrap().run().unwrap();
            assert_eq!((r.outcome, r.contacts), (Some(Outcome::Complete), 0), "N = {n}");
            assert!(r.closest.unwrap_or(f64::INFINITY) >= 25.0);
        }
    }
}

/// (group rows, group columns, unloading rows, aisles, robots): 100 to 2,000 robots, each
/// warehouse asked for an order per robot every 100 steps (far past what it can serve).
const OVERLOADED: [(u32, u32, u32, Aisles, u32); 6] = [
    (4, 6, 1, Aisles::Paper, 100),
    (6, 10, 2, Aisles::Alternate, 300),
    (10, 4, 1, Aisles::Paper, 211),
    (8, 14, 3, Aisles::Paper, 600),
    (12, 20, 3, Aisles::Alternate, 1200),
    (16, 24, 4, Aisles::Alternate, 2000),
];

#[test]
fn reserve_has_no_gridlock_under_overload() {
    for (rows, cols, ur, aisles, robots) in OVERLOADED {
        let s = lifelong(rows, cols, ur, aisles, robots, f64::from(robots) / 100.0, 4000, Traffic::Reserve);
        let r = Simulation::new(&s).unwrap().run().unwrap();
        let label = format!("{rows}x{cols} {aisles:?}, {robots} robots: {:?}", r.windows);
        assert_eq!(r.outcome, Some(Outcome::Horizon), "{label}");
        // Still delivering at the end: no window without a delivery.
        assert!(r.windows.iter().all(|&w| w > 0), "{label}");
    }
}

/// Counted from positions (every pair, whatever the robots do: parked in a bay, waiting for
/// a charger, queued at a place), no two robots come closer than r_i + r_j under `reserve`.
#[test]
fn reserve_has_no_contact_under_overload() {
    for (rows, cols, ur, aisles, robots) in OVERLOADED {
        let s = lifelong(rows, cols, ur, aisles, robots, f64::from(robots) / 100.0, 4000, Traffic::Reserve);
        let r = Simulation::new(&s).unwrap().run().unwrap();
        let label = format!("{rows}x{cols} {aisles:?}, {robots} robots");
        assert_eq!(r.contacts, 0, "{label}");
        assert!(r.closest.unwrap() >= 25.0, "{label}");
    }
}

#[test]
fn reserve_is_deterministic() {
    let s = lifelong(6, 10, 2, Aisles::Alternate, 300, 3.0, 2000, Traffic::Reserve);
    let a = Simulation::new(&s).unwrap().run().unwrap();
    let b = Simulation::new(&s).unwrap().run().unwrap();
    assert_eq!(a, b);
}

#[test]
fn reserve_keeps_moving_where_waiting_collapses() {
    // An overloaded 400-robot warehouse: collision waiting jams (its last windows deliver
    // almost nothing, with robots driving through each other); reserve sustains its rate.
    let wait = Simulation::new(&lifelong(8, 12, 2, Aisles::Alternate, 400, 4.0, 8000, Traffic::Wait)).unwrap().run().unwrap();
    let reserve = Simulation::new(&lifelong(8, 12, 2, Aisles::Alternate, 400, 4.0, 8000, Traffic::Reserve)).unwrap().run().unwrap();
    assert!(wait.contacts > 0);
    let (w, r) = (wait.sustained_throughput.unwrap(), reserve.sustained_throughput.unwrap());
    assert!(r > 1.5 * w, "reserve {r} vs wait {w}: {:?} {:?}", reserve.windows, wait.windows);
}

#[test]
fn gate_takes_crossings_one_robot_at_a_time() {
    // Side by side at crossings is where collision waiting lets robots overlap: the gate
    // lets fewer robots touch (a fifth fewer here; the rest are queues closing up under
    // collision waiting, which the gate does not change).
    let wait = Simulation::new(&lifelong(6, 10, 2, Aisles::Alternate, 200, 0.5, 4000, Traffic::Wait)).unwrap().run().unwrap();
    let gate = Simulation::new(&lifelong(6, 10, 2, Aisles::Alternate, 200, 0.5, 4000, Traffic::Gate)).unwrap().run().unwrap();
    assert!(gate.contacts * 5 < wait.contacts * 4, "gate {} vs wait {}", gate.contacts, wait.contacts);
    assert!(gate.delivered > 0);
}

#[test]
fn the_original_rules_refuse_a_traffic_policy() {
    let mut s = Scenario::paper(3, &PAPER_TASKS[0]);
    s.rules = multibots_core::Rules::Original;
    s.traffic = Traffic::Reserve;
    assert_eq!(Simulation::new(&s).err().unwrap().to_string(), "traffic = \"reserve\": the original rules have their own collision rule");
}
