//! Charging at scale (docs/charging.md): chargers on every wall of a generated warehouse, and
//! staggered charging, which keeps an overloaded fleet that must charge delivering without a
//! charging wave. Judged from the layout's coordinates and from the windows, states and
//! positions a run reports.

use crate::common;

use common::lifelong;
use multibots_core::fleet::robot::State;
use multibots_core::input::layout_params::{Aisles, ChargerWalls, LayoutParams};
use multibots_core::input::scenario::{ChargingPolicy, Scenario};
use multibots_core::record::metrics::RunResult;
use multibots_core::world::layout::Layout;
use multibots_core::{Simulation, Traffic};

#[test]
fn chargers_stand_on_spurs_out_of_every_wall_at_right_angles() {
    let (rows, cols, spur) = (4u32, 6u32, 40.0);
    let most = 2 * (cols + 1) + 2 * (rows + 1);
    let p = LayoutParams { group_rows: rows, group_cols: cols, chargers: most, charger_walls: ChargerWalls::All, ..LayoutParams::paper() };
    let l = Layout::generate(&p, "walls").unwrap();
    assert_eq!(l.chargers.len(), most as usize);
    let [x0, y0, x1, y1] = l.bounds;
    let (mut top, mut bottom, mut left, mut right) = (0, 0, 0, 0);
    for &c in &l.chargers {
        let (cx, cy) = l.pos(c);
        let (nx, ny) = l.pos(l.spur_node(c).unwrap());
        let (dx, dy) = (cx - nx, cy - ny);
        // Straight out of the warehouse, one spur long, along an axis.
        assert!((dx.abs() + dy.abs() - spur).abs() < 1e-9 && (dx == 0.0 || dy == 0.0), "{dx}, {dy}");
        assert!(!(cx > x0 && cx < x1 && cy > y0 && cy < y1), "charger at ({cx}, {cy}) inside the warehouse");
        if dy < 0.0 {
            top += 1;
        } else if dy > 0.0 {
            bottom += 1;
        } else if dx < 0.0 {
            left += 1;
        } else {
            right += 1;
        }
    }
    assert_eq!((top, bottom, left, right), (cols + 1, cols + 1, rows + 1, rows + 1));
    // No two chargers at one place, and fewer chargers are spread over every wall.
    let half = LayoutParams { chargers: most / 2, ..p.clone() };
    let l = Layout::generate(&half, "half").unwrap();
    let mut places: Vec<(i64, i64)> = l.chargers.iter().map(|&c| (l.pos(c).0 as i64, l.pos(c).1 as i64)).collect();
    places.sort_unstable();
    places.dedup();
    assert_eq!(places.len(), (most / 2) as usize);
    assert!(l.chargers.iter().any(|&c| l.pos(c).0 < x0) && l.chargers.iter().any(|&c| l.pos(c).1 > y1));
}

#[test]
fn the_top_wall_alone_is_the_paper_layout_and_too_many_chargers_are_named() {
    assert_eq!(Layout::generate(&LayoutParams { charger_walls: ChargerWalls::Top, ..LayoutParams::paper() }, "paper").unwrap(), Layout::paper());
    let bad = |walls, chargers| Layout::generate(&LayoutParams { charger_walls: walls, chargers, ..LayoutParams::paper() }, "x").unwrap_err().to_string();
    assert_eq!(
        bad(ChargerWalls::Top, 12),
        "layout.chargers = 12: must be between 1 and 11 (one per top-aisle crossing and one midway between two; charger_walls = \"top-bottom\" or \"all\" places more)"
    );
    assert_eq!(
        bad(ChargerWalls::TopBottom, 23),
        "layout.chargers = 23: must be between 1 and 22 (one per crossing of the top and bottom rows and one midway between two; charger_walls = \"all\" places more)"
    );
    assert_eq!(
        bad(ChargerWalls::All, 29),
        "layout.chargers = 29: must be between 1 and 28 (one per crossing along each wall, two at the corners, and one midway between two crossings of the top and bottom rows)"
    );
    assert!(Layout::generate(&LayoutParams { charger_walls: ChargerWalls::All, chargers: 28, ..LayoutParams::paper() }, "x").is_ok());
}

#[test]
fn chargers_beyond_the_crossings_stand_midway_on_nodes_that_split_the_wall_aisles() {
    let (rows, cols) = (4u32, 6u32);
    let at_crossings = 2 * (cols + 1) + 2 * (rows + 1);
    let most = at_crossings + 2 * cols;
    for chargers in [at_crossings + 1, at_crossings + cols, most] {
        let p = LayoutParams { group_rows: rows, group_cols: cols, chargers, charger_walls: ChargerWalls::All, ..LayoutParams::paper() };
        let l = Layout::generate(&p, "rows").unwrap();
        let crossings = ((rows + 1) * (cols + 1)) as usize;
        let mids = (chargers - at_crossings) as usize;
        assert_eq!(l.highway_nodes(), crossings + mids);
        assert_eq!(l.chargers.len(), chargers as usize);
        // One charger to a place.
        let mut places: Vec<(i64, i64)> = l.chargers.iter().map(|&c| (l.pos(c).0 as i64, l.pos(c).1 as i64)).collect();
        places.sort_unstable();
        places.dedup();
        assert_eq!(places.len(), chargers as usize);
        let [_, y0, _, y1] = l.bounds;
        for k in crossings..crossings + mids {
            let m = multibots_core::ids::NodeId(k as u32);
            let (mx, my) = l.pos(m);
            // On the top or bottom aisle, midway between the two crossings its one edge in and
            // its one edge out join, in a straight line, with its charger straight out.
            let ins: Vec<_> = l.edges.iter().filter(|e| e.1 == m).collect();
            let outs: Vec<_> = l.edges.iter().filter(|e| e.0 == m).collect();
            assert_eq!((ins.len(), outs.len()), (1, 1));
            let (a, b) = (l.pos(ins[0].0), l.pos(outs[0].1));
            assert!(a.1 == my && b.1 == my && (a.0 + b.0) / 2.0 == mx, "{a:?} {b:?} ({mx}, {my})");
            assert!(!l.edges.contains(&(ins[0].0, outs[0].1)), "the aisle's edge is split, not kept");
            let c = l.charger_at(m).expect("a charger on each midway node");
            let (cx, cy) = l.pos(c);
            assert!(cx == mx && (cy - my).abs() == p.spur && (cy < y0 || cy > y1));
        }
        // A run on it: the graph is checked (strongly connected, every charger reachable).
        let mut s = lifelong(rows, cols, 1, chargers, Aisles::Paper, 20, 0.1, 200, Traffic::Reserve);
        s.layout_generate.as_mut().unwrap().charger_walls = ChargerWalls::All;
        let sim = Simulation::new(&s).unwrap();
        let w = &sim.world().layout;
        assert_eq!((&w.nodes, &w.edges, &w.spurs), (&l.nodes, &l.edges, &l.spurs));
    }
}

/// 200 robots, overloaded (one order per step), a battery of 20,000 steps of driving, over
/// 16,000 steps: the whole fleet drains together and reaches the threshold near step 13,000.
fn fleet(chargers: u32, walls: ChargerWalls, policy: ChargingPolicy) -> Scenario {
    let mut s = lifelong(6, 10, 2, chargers, Aisles::Alternate, 200, 1.0, 16_000, Traffic::Reserve);
    s.layout_generate.as_mut().unwrap().charger_walls = walls;
    s.robot.consumption = 0.0005;
    s.charging.policy = policy;
    s.charging.level = 9.0;
    s.charging.reach = Some(1000.0);
    s
}

/// The run's result, the robots stranded at its end, and the longest charger queue seen.
fn run(s: &Scenario) -> (RunResult, usize, usize) {
    let mut sim = Simulation::new(s).unwrap();
    let mut queue = 0;
    while !sim.done() {
        sim.step().unwrap();
        queue = queue.max(sim.robots().state.iter().filter(|&&st| st == State::WaitCharger).count());
    }
    let stranded = sim.robots().state.iter().filter(|&&st| st == State::Stranded).count();
    (sim.result(), stranded, queue)
}

/// The worst window after the first three, as a share of the best one there.
fn worst_share(r: &RunResult) -> f64 {
    let after = &r.windows[3..];
    *after.iter().min().unwrap() as f64 / *after.iter().max().unwrap() as f64
}

#[test]
fn staggered_charging_at_chargers_on_every_wall_keeps_an_overloaded_fleet_delivering() {
    // The threshold rule at one charger per top crossing: the fleet goes to charge together,
    // queues, and the warehouse nearly stops (windows down to a third of the best).
    let (wave, stranded, queue) = run(&fleet(11, ChargerWalls::Top, ChargingPolicy::Threshold));
    assert_eq!(stranded, 0);
    assert!(worst_share(&wave) < 0.5, "{:?}", wave.windows);
    assert!(queue > 100, "{queue}");
    // Staggered, at chargers on every wall (at every crossing of them and midway between
    // those of the top and bottom rows): robots charge early, a few at a time, when a charger
    // near them is free.
    let (r, stranded, queue) = run(&fleet(56, ChargerWalls::All, ChargingPolicy::Staggered));
    assert_eq!(stranded, 0);
    assert!(r.c > 0);
    assert!(r.windows.iter().all(|&w| w > 0), "{:?}", r.windows);
    assert!(worst_share(&r) >= 0.75, "{:?}", r.windows);
    assert!(queue < 20, "{queue}");
    assert_eq!(r.contacts, 0);
}
