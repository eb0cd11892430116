//! Traffic policies (docs/traffic.md): `wait` (what `auto` is for the paper's fleets) is the
//! paper's rule unchanged; `reserve` never
//! lets two robots come closer than r_i + r_j and keeps warehouses moving under overload;
//! `gate` takes crossings one robot at a time.

use crate::common;

use common::PAPER_TASKS;
use multibots_core::input::layout_params::Aisles;
use multibots_core::record::metrics::Outcome;
use multibots_core::{Scenario, Simulation, Traffic};

#[allow(clippy::too_many_arguments)]
fn lifelong(rows: u32, cols: u32, unloading_rows: u32, aisles: Aisles, robots: u32, rate: f64, steps: u64, traffic: Traffic) -> Scenario {
    common::lifelong(rows, cols, unloading_rows, cols + 1, aisles, robots, rate, steps, traffic)
}

#[test]
fn auto_is_wait_for_the_paper_and_the_paper_rule_unchanged() {
    for (n, g) in [(1, 0), (3, 2), (6, 4)] {
        let s = Scenario::paper(n, &PAPER_TASKS[g]);
        let mut explicit = s.clone();
        explicit.traffic = Traffic::Wait;
        assert_eq!(Simulation::new(&s).unwrap().run().unwrap(), Simulation::new(&explicit).unwrap().run().unwrap());
    }
    let s = lifelong(4, 6, 1, Aisles::Paper, 80, 1.0, 1500, Traffic::Auto);
    assert_eq!(Scenario::from_toml(&s.to_toml(), "s.toml").unwrap(), s);
    assert!(!s.to_toml().contains("traffic"), "the default is not written");
    let wait = lifelong(4, 6, 1, Aisles::Paper, 80, 1.0, 1500, Traffic::Wait);
    assert!(wait.to_toml().contains("traffic = \"wait\""), "a choice is written");
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

/// Robots under way that stood still over the last `steps` steps of a run of `sim`, counted
/// from positions.
fn frozen(sim: &mut Simulation, steps: u64) -> usize {
    let r = sim.robots();
    let before: Vec<(f64, f64)> = r.x.iter().copied().zip(r.y.iter().copied()).collect();
    let mut moved = vec![false; before.len()];
    for _ in 0..steps {
        sim.step().unwrap();
        let r = sim.robots();
        for (i, m) in moved.iter_mut().enumerate() {
            *m |= (r.x[i], r.y[i]) != before[i];
        }
    }
    let r = sim.robots();
    (0..before.len()).filter(|&i| !moved[i] && r.state[i].travels()).count()
}

#[test]
fn reserve_lets_no_ring_of_full_lanes_freeze() {
    // Six rows of groups, one unloading row, a long restock: robots bound north from the
    // bottom row circle a block at the west wall, where the crossings have one way out. The
    // four lanes round the block fill and each head waits for the next lane. A detour through
    // a crossing with one way out (at the wall, or on the unloading row), as a last resort,
    // breaks the ring; when detours avoided every such crossing as if it were a charger's dead
    // end, 103 robots stood frozen in such rings from step 12,000 (and more every few thousand
    // steps after). (Taken as soon as any detour, it cost a single busy unloading zone a
    // quarter of its deliveries: `tests/engine/bottleneck.rs`.)
    let mut s = common::lifelong(6, 30, 1, 20, Aisles::Auto, 600, 1.0, 20_000, Traffic::Reserve);
    let params = s.layout_generate.as_mut().unwrap();
    (params.group_width, params.group_height) = (2, 6);
    s.robot.consumption = 0.00002;
    s.orders.as_mut().unwrap().restock = 300;
    s.orders.as_mut().unwrap().seed = 11;
    let mut sim = Simulation::new(&s).unwrap();
    sim.steps(12_000).unwrap();
    let stuck = frozen(&mut sim, 500);
    assert!(stuck < 20, "{stuck} robots under way stood still for 500 steps");
}
