//! The paper model end to end: the single-robot formula on every cell, the worked example,
//! the 30-run experiment's trends and recorded values, determinism and stranding.

use crate::common;

use common::PAPER_TASKS;
use multibots_core::fleet::robot::Target;
use multibots_core::fleet::route::{self, Place};
use multibots_core::{HighwayGraph, Layout, Outcome, Scenario, Simulation};

fn ceil4(d: f64) -> u64 {
    (d / 4.0).ceil() as u64
}

#[test]
fn single_robot_formula_on_every_cell_and_start() {
    let l = Layout::paper();
    let g = HighwayGraph::new(&l);
    let m = l.node_named("M").unwrap();
    for (k, start) in ["A", "B", "C", "D", "E", "F"].iter().enumerate() {
        let home = l.charger_at(l.node_named(start).unwrap()).unwrap();
        for cell in 0..80u32 {
            let c = &l.cells[cell as usize];
            let point = Target::Point { u: c.edge.0, v: c.edge.1, x: c.service.0, y: c.service.1 };
            let at_point = Place { x: c.service.0, y: c.service.1, at_node: u32::MAX, edge_u: c.edge.0 .0, edge_v: c.edge.1 .0 };
            let d1 = route::length(&g, Place::node(&g, home), point);
            let d2 = route::length(&g, at_point, Target::Node(m));
            let d3 = route::length(&g, Place::node(&g, m), Target::Node(home));
            let expect = ceil4(d1) + 10 + ceil4(d2) + 20 + ceil4(d3);
            let mut s = Scenario::paper(1, &[cell]);
            s.starts = Some(vec![(*start).to_string()]);
            let r = Simulation::new(&s).unwrap().run().unwrap();
            assert_eq!(r.t, Some(expect), "cell {cell} from {start} (robot home CH{k})");
            assert_eq!(r.robots.distance[0], d1 + d2 + d3);
        }
    }
}

#[test]
fn worked_example() {
    let r = Simulation::new(&Scenario::paper(1, &[42])).unwrap().run().unwrap();
    assert_eq!(r.t, Some(726));
    assert_eq!(r.robots.distance[0], 1290.0 + 950.0 + 540.0);
    assert_eq!((r.s, r.c, r.delivered), (0, 0, 1));
}

fn paper_runs() -> Vec<(u32, usize, multibots_core::RunResult)> {
    let mut out = Vec::new();
    for n in 1..=6 {
        for (g, cells) in PAPER_TASKS.iter().enumerate() {
            out.push((n, g + 1, Simulation::new(&Scenario::paper(n, cells)).unwrap().run().unwrap()));
        }
    }
    out
}

#[test]
fn paper_experiment_trends_and_recorded_values() {
    let runs = paper_runs();
    let mean = |n: u32, f: &dyn Fn(&multibots_core::RunResult) -> f64| runs.iter().filter(|r| r.0 == n).map(|r| f(&r.2)).sum::<f64>() / 5.0;
    let t: Vec<f64> = (1..=6).map(|n| mean(n, &|r| r.t.unwrap() as f64)).collect();
    let s: Vec<f64> = (1..=6).map(|n| mean(n, &|r| r.s as f64)).collect();
    let c: Vec<f64> = (1..=6).map(|n| mean(n, &|r| r.c as f64)).collect();
    assert!(t.windows(2).all(|w| w[0] > w[1]), "T falls strictly: {t:?}");
    assert!(s.windows(2).all(|w| w[0] <= w[1]), "S never falls: {s:?}");
    assert!(c[5] < c[0], "C at N = 6 below N = 1: {c:?}");
    // Recorded values: a change here is a change of the model.
    let get = |n: u32, g: usize| runs.iter().find(|r| r.0 == n && r.1 == g).map(|r| (r.2.t.unwrap(), r.2.s, r.2.c)).unwrap();
    assert_eq!(get(1, 1), (6619, 0, 3));
    assert_eq!(get(3, 1), (1719, 3, 3));
    assert_eq!(get(6, 2), (1333, 7, 0));
}

#[test]
fn runs_are_deterministic() {
    let mut s = Scenario::paper(6, &PAPER_TASKS[3]);
    s.collision.margin = 8.0;
    let a = Simulation::new(&s).unwrap().run().unwrap();
    let b = Simulation::new(&s).unwrap().run().unwrap();
    assert_eq!(a, b);
}

#[test]
fn a_robot_without_reserve_is_stranded_and_the_run_ends_so() {
    let mut s = Scenario::paper(1, &PAPER_TASKS[0]);
    s.unload = "R".into();
    s.robot.threshold = 0.3;
    s.step_limit = 20_000;
    let r = Simulation::new(&s).unwrap().run().unwrap();
    assert_eq!(r.outcome, Some(Outcome::Stranded));
    assert_eq!(r.t, None);
    assert_eq!(r.stranded, vec![0]);
    // Ended the step the last robot stranded, not at the step limit: 10 energy at 0.005 per
    // step lasts 2,000 steps.
    assert_eq!(r.steps, 2000);
    assert!(r.robots.state_steps[0][multibots_core::State::Stranded as usize] == 1);
    // When and where: the step it ran out, and the node it stood at or drove towards.
    let c = r.collapse.as_ref().unwrap();
    assert_eq!((c.step, c.first_stranded, c.stranded, c.collapsed), (2000, Some(2000), 1, false));
    assert_eq!(c.crossings.len(), 1);
    assert_eq!(c.crossings[0].1, 1);
}

#[test]
fn charging_happens_and_is_counted_at_the_charger() {
    // One robot, ten goods: it must charge on the way (the paper's N = 1 runs charge 3–4 times).
    let r = Simulation::new(&Scenario::paper(1, &PAPER_TASKS[0])).unwrap().run().unwrap();
    assert!(r.c >= 3);
    assert_eq!(u64::from(r.robots.charges[0]), r.c);
    assert!(r.robots.state_steps[0][multibots_core::State::Charging as usize] > 0);
}
