//! Outcomes that say what happened (docs/metrics.md): a lifelong run whose throughput
//! collapses ends `collapse`, or `stranded` when robots ran out of energy, with when and
//! where; a fleet that keeps delivering ends `horizon`. Judged from the windows the run
//! reports and from the robots' states.

use crate::common;

use common::lifelong;
use multibots_core::fleet::robot::State;
use multibots_core::input::layout_params::Aisles;
use multibots_core::input::scenario::Scenario;
use multibots_core::record::metrics::{Outcome, RunResult};
use multibots_core::{Simulation, Traffic};

/// Whether the last quarter of the windows (at least 2) each delivered under a tenth of the
/// best, and the first of the run of such windows at the end.
fn collapsed_from_windows(r: &RunResult) -> Option<usize> {
    let w = &r.windows;
    let best = *w.iter().max()?;
    let low: Vec<bool> = w.iter().map(|&d| (d as f64) < best as f64 / 10.0).collect();
    let tail = (w.len() / 4).max(2);
    if w.len() < 4 || best == 0 || !low[w.len() - tail..].iter().all(|&l| l) {
        return None;
    }
    let mut first = w.len();
    while first > 0 && low[first - 1] {
        first -= 1;
    }
    Some(first)
}

/// Runs `sim` to its end; the step after which a robot was first seen stranded.
fn run_to_the_end(sim: &mut Simulation) -> Option<u64> {
    let mut first = None;
    while !sim.done() {
        sim.step().unwrap();
        if first.is_none() && sim.robots().state.contains(&State::Stranded) {
            first = Some(sim.t());
        }
    }
    first
}

#[test]
fn a_jammed_fleet_ends_collapse_and_says_when_and_where() {
    // 600 robots under collision waiting, the paper's aisle directions: the fleet jams
    // (windows 355, 30, 9, 1, 38, 4, 2, 2).
    let s = lifelong(8, 12, 2, 13, Aisles::Paper, 600, 6.0, 8000, Traffic::Wait);
    let mut sim = Simulation::new(&s).unwrap();
    let r = sim.run().unwrap();
    let first = collapsed_from_windows(&r).unwrap_or_else(|| panic!("windows {:?}", r.windows));
    assert_eq!(r.outcome, Some(Outcome::Collapse), "{:?}", r.windows);
    let c = r.collapse.as_ref().unwrap();
    assert_eq!(c.step, first as u64 * r.window + 1);
    assert_eq!((c.best, c.last), (*r.windows.iter().max().unwrap(), *r.windows.last().unwrap()));
    assert_eq!((c.stranded, c.collapsed, c.first_stranded), (0, true, None));
    assert!(!c.crossings.is_empty() && c.crossings.windows(2).all(|p| p[0].1 >= p[1].1), "{:?}", c.crossings);
}

#[test]
fn a_fleet_that_keeps_delivering_ends_at_its_horizon() {
    let s = lifelong(8, 12, 2, 13, Aisles::Alternate, 400, 4.0, 8000, Traffic::Reserve);
    let r = Simulation::new(&s).unwrap().run().unwrap();
    assert!(collapsed_from_windows(&r).is_none(), "{:?}", r.windows);
    assert_eq!((r.outcome, r.collapse), (Some(Outcome::Horizon), None));
}

#[test]
fn a_fleet_stranding_robot_by_robot_ends_stranded() {
    // One shared charger for 150 robots whose battery lasts 5,000 steps: robots queue for
    // it (in their bays), drain there and strand one by one while a few still move.
    let mut s = lifelong(6, 10, 1, 1, Aisles::Alternate, 150, 1.5, 7000, Traffic::Reserve);
    s.robot.consumption = 0.002;
    // Queued robots draw what driving does (the scenario says so): they drain in the queue.
    s.robot.idle_consumption = Some(0.002);
    let mut sim = Simulation::new(&s).unwrap();
    let first = run_to_the_end(&mut sim);
    let r = sim.result();
    let stranded = sim.robots().state.iter().filter(|&&st| st == State::Stranded).count();
    let low_from = collapsed_from_windows(&r).unwrap_or_else(|| panic!("{:?}", r.windows));
    assert!(stranded > 0 && stranded < 150);
    assert_eq!(r.outcome, Some(Outcome::Stranded));
    let c = r.collapse.as_ref().unwrap();
    // When: the collapse's first step, and the step the first robot ran out.
    assert_eq!((c.stranded as usize, c.collapsed, c.step, c.first_stranded), (stranded, true, low_from as u64 * r.window + 1, first));
}

#[test]
fn robots_stranding_while_the_throughput_holds_end_stranded_with_when_and_where() {
    // A layout nobody tuned (the generator's own aisles and unloading rows, chargers on two
    // walls) whose threshold charging strands robots one by one from step ~6,700, while the
    // rest keep delivering: the windows never fall to a tenth of the best for the last
    // quarter, so only the stranded robots say that the fleet is failing.
    let text = r#"
        robots = 900
        tasks = []
        placement = "spread"
        unload = "nearest"
        allocator = "nearest"
        traffic = "reserve"
        [layout_generate]
        group_rows = 14
        group_cols = 18
        group_width = 1
        group_height = 5
        chargers = 60
        charger_walls = "top-bottom"
        [charging]
        chargers = "shared"
        [robot]
        consumption = 0.0015
        [orders]
        rate = 1.2
        horizon = 12000
        restock = 150
        seed = 13
    "#;
    let s = Scenario::from_toml(text, "untuned.toml").unwrap();
    let mut sim = Simulation::new(&s).unwrap();
    let first = run_to_the_end(&mut sim);
    let r = sim.result();
    assert!(collapsed_from_windows(&r).is_none(), "{:?}", r.windows);
    assert_eq!(r.outcome, Some(Outcome::Stranded), "{:?}", r.windows);
    let robots = sim.robots();
    let stranded: Vec<usize> = (0..robots.len()).filter(|&i| robots.state[i] == State::Stranded).collect();
    let c = r.collapse.as_ref().unwrap();
    assert_eq!((c.stranded as usize, c.collapsed, c.first_stranded), (stranded.len(), false, first));
    assert!(stranded.len() > 100 && stranded.len() < 900, "{}", stranded.len());
    // When: the step the first robot ran out; and the windows as they are.
    assert_eq!(Some(c.step), first);
    assert_eq!((c.best, c.last), (*r.windows.iter().max().unwrap(), *r.windows.last().unwrap()));
    // Where: the crossings the stranded robots stand at or drive towards, and no others.
    let nodes = &sim.world().layout.nodes;
    let at = |i: usize| if robots.at_node[i] == u32::MAX { robots.edge_v[i] } else { robots.at_node[i] };
    for (name, k) in &c.crossings {
        let node = nodes.iter().position(|n| &n.name == name).unwrap() as u32;
        assert_eq!(stranded.iter().filter(|&&i| at(i) == node).count(), *k as usize, "{name}");
    }
    assert!(c.crossings.len() == 10 && c.crossings.windows(2).all(|p| p[0].1 >= p[1].1), "{:?}", c.crossings);
}

#[test]
fn a_stranded_robot_never_moves_again() {
    // Robots run flat in the charger queue, many in their bays: where a robot strands it
    // stays (it does not step back onto its lane), under every traffic policy.
    for traffic in [Traffic::Wait, Traffic::Reserve] {
        let mut s = lifelong(6, 10, 1, 3, Aisles::Alternate, 150, 1.5, 4000, traffic);
        s.robot.consumption = 0.004;
        s.robot.idle_consumption = Some(0.004);
        let mut sim = Simulation::new(&s).unwrap();
        let mut at: Vec<Option<(f64, f64)>> = vec![None; 150];
        let mut stranded = 0;
        while !sim.done() {
            sim.step().unwrap();
            let r = sim.robots();
            for (i, p) in at.iter_mut().enumerate() {
                if r.state[i] == State::Stranded {
                    match p {
                        None => {
                            *p = Some((r.x[i], r.y[i]));
                            stranded += 1;
                        }
                        Some(q) => assert_eq!(*q, (r.x[i], r.y[i]), "{traffic:?}: robot {i} moved at step {}", sim.t()),
                    }
                }
            }
        }
        assert!(stranded > 10, "{traffic:?}: {stranded}");
    }
}
