//! The bottleneck, named (docs/metrics.md): each unloading zone's and charger's busy share
//! and queue, recomputed from outside (robot states, who waited, where each stands or
//! heads), and the bottleneck on constructed warehouses.

use crate::common;

use multibots_core::fleet::robot::State;
use multibots_core::input::layout_params::Aisles;
use multibots_core::input::scenario::{ChargerUse, Orders, Placement, Tasks};
use multibots_core::record::resources::ResourceKind;
use multibots_core::{LayoutParams, Scenario, Simulation, Traffic, Unload};

#[allow(clippy::too_many_arguments)]
fn lifelong(rows: u32, cols: u32, unloading_rows: u32, chargers: u32, robots: u32, rate: f64, steps: u64, traffic: Traffic) -> Scenario {
    common::lifelong(rows, cols, unloading_rows, chargers, Aisles::Alternate, robots, rate, steps, traffic)
}

#[test]
fn one_unloading_zone_for_a_busy_fleet_is_the_bottleneck_and_its_figures_hold() {
    // 200 robots, every goods to one unloading zone (the layout's first), far more orders
    // than it can take.
    for traffic in [Traffic::Wait, Traffic::Reserve] {
        let mut s = lifelong(6, 8, 1, 9, 200, 2.0, 3000, traffic);
        s.unload = Unload::First;
        let mut sim = Simulation::new(&s).unwrap();
        let zone = sim.world().layout.unloading[0];
        let name = sim.world().layout.nodes[zone.index()].name.clone();
        let (mut busy, mut queued, mut longest, mut steps) = (0u64, 0u64, 0u32, 0u64);
        let mut waited = sim.stats().wait_steps.clone();
        while !sim.done() {
            sim.step().unwrap();
            steps += 1;
            let r = sim.robots();
            // Robots that waited this step, standing at the zone or driving towards it.
            let now = &sim.stats().wait_steps;
            let q = (0..r.len())
                .filter(|&i| now[i] > waited[i])
                .filter(|&i| if r.at_node[i] == u32::MAX { r.edge_v[i] == zone.0 } else { r.at_node[i] == zone.0 })
                .count() as u32;
            // Busy: a robot unloads there, or robots wait to enter it.
            busy += u64::from(r.state.contains(&State::Unloading) || q > 0);
            waited.clone_from(now);
            // What viewers draw (Simulation::queues) is this same count, step by step.
            let shown = sim.queues().nodes.iter().find(|&&(n, _)| n == zone).map_or(0, |&(_, c)| c);
            assert_eq!(shown, q, "{traffic:?}: step {steps}");
            queued += u64::from(q);
            longest = longest.max(q);
        }
        let r = sim.result();
        let u = r.resources.iter().find(|u| u.kind == ResourceKind::Unloading).unwrap();
        assert_eq!(u.node, name);
        assert!((u.busy - busy as f64 / steps as f64).abs() < 1e-12, "{traffic:?}: {} vs {busy}/{steps}", u.busy);
        assert!((u.mean_queue - queued as f64 / steps as f64).abs() < 1e-12, "{traffic:?}");
        assert_eq!(u.longest_queue, longest, "{traffic:?}");
        assert!(u.busy > 0.5 && longest > 2, "{traffic:?}: a busy zone with a queue: {u:?}");
        let b = r.bottleneck.unwrap_or_else(|| panic!("{traffic:?}: {:?}", r.resources));
        assert_eq!((b.resource.kind, b.resource.node.as_str()), (ResourceKind::Unloading, name.as_str()), "{traffic:?}: {:?}", r.resources);
        assert!(b.relieve.contains("unloading_rows"), "{}", b.relieve);
    }
}

#[test]
fn too_few_shared_chargers_are_the_bottleneck() {
    // Three chargers for 150 robots whose battery lasts 5,000 steps, and plenty of
    // unloading zones: robots queue for a charger.
    let mut s = lifelong(6, 10, 3, 3, 150, 0.5, 6000, Traffic::Reserve);
    s.robot.consumption = 0.002;
    let mut sim = Simulation::new(&s).unwrap();
    let r = sim.run().unwrap();
    let layout = &sim.world().layout;
    let b = r.bottleneck.unwrap_or_else(|| panic!("{:?}", r.resources));
    assert_eq!(b.resource.kind, ResourceKind::ChargerQueue, "{:?}", r.resources);
    assert!(b.resource.longest_queue > 10 && b.relieve.contains("chargers"), "{b:?}");
    // Every charger is reported, and the unloading zones robots unloaded at.
    let zones = r.resources.iter().filter(|u| u.kind == ResourceKind::Unloading).count();
    assert!(zones > 1 && zones <= layout.unloading.len());
    assert_eq!(r.resources.iter().filter(|u| u.kind == ResourceKind::Charger).count(), 3);
}

#[test]
fn a_fleet_that_strands_has_no_bottleneck() {
    // 200 robots sharing 12 chargers, all else default (issue 42): out of energy from about
    // step 2,000; the zones they last queued at are not what held them up.
    let mut s = Scenario::paper(200, &[]);
    s.layout_generate = Some(LayoutParams { group_rows: 6, group_cols: 10, chargers: 12, ..LayoutParams::default() });
    s.tasks = Tasks::Cells(vec![]);
    s.orders = Some(Orders { rate: 0.2, horizon: 20_000, restock: 100, seed: 1, csv: None });
    let r = Simulation::new(&s).unwrap().run().unwrap();
    assert_eq!(r.outcome, Some(multibots_core::record::metrics::Outcome::Stranded));
    assert!(r.bottleneck.is_none(), "{:?}", r.bottleneck);
}

#[test]
fn a_light_load_has_no_bottleneck() {
    let s = lifelong(4, 6, 1, 7, 10, 0.01, 3000, Traffic::Reserve);
    let r = Simulation::new(&s).unwrap().run().unwrap();
    assert!(r.delivered > 0);
    assert!(r.bottleneck.is_none(), "{:?}", r.bottleneck);
}

#[test]
fn a_warehouse_whose_goods_all_go_to_one_unloading_zone_is_held_up_by_it() {
    // The generator's aisle directions and one row of unloading zones, every goods to the
    // first, 1 order per step: robots jam on the way to that zone.
    let mut s = Scenario::paper(600, &[]);
    s.layout_generate = Some(LayoutParams { group_rows: 12, group_cols: 25, group_width: 2, group_height: 8, chargers: 26, ..LayoutParams::paper() });
    s.placement = Placement::Spread;
    s.charging.chargers = ChargerUse::Shared;
    s.unload = Unload::First;
    s.allocator = "nearest".into();
    s.robot.consumption = 0.00002;
    s.tasks = Tasks::Cells(vec![]);
    s.orders = Some(Orders { rate: 1.0, horizon: 3000, restock: 100, seed: 1, csv: None });
    let mut sim = Simulation::new(&s).unwrap();
    let r = sim.run().unwrap();
    let first = &sim.world().layout.nodes[sim.world().layout.unloading[0].index()].name;
    let b = r.bottleneck.unwrap_or_else(|| panic!("{:?}", r.resources));
    assert_eq!((b.resource.kind, &b.resource.node), (ResourceKind::Unloading, first), "{:?}", r.resources);
    assert!(b.relieve.contains("unloading_rows") && b.relieve.contains("nearest"), "{}", b.relieve);
}

#[test]
fn lanes_report_where_the_queues_stand_and_their_figures_hold() {
    // The one-zone warehouse of the first test under collision waiting: queues reach back
    // along the lanes into the zone. Each lane's figures, recomputed from outside: the
    // robots that waited this step standing on that edge (not at a node).
    let mut s = lifelong(6, 8, 1, 9, 200, 2.0, 3000, Traffic::Wait);
    s.unload = Unload::First;
    let mut sim = Simulation::new(&s).unwrap();
    let layout = sim.world().layout.clone();
    let lanes = layout.edges.len();
    let (mut busy, mut queued, mut longest, mut steps) = (vec![0u64; lanes], vec![0u64; lanes], vec![0u32; lanes], 0u64);
    let mut waited = sim.stats().wait_steps.clone();
    while !sim.done() {
        sim.step().unwrap();
        steps += 1;
        let r = sim.robots();
        let now = &sim.stats().wait_steps;
        let mut q = vec![0u32; lanes];
        for i in (0..r.len()).filter(|&i| now[i] > waited[i] && r.at_node[i] == u32::MAX) {
            let e = layout.edges.iter().position(|&(u, v)| (u.0, v.0) == (r.edge_u[i], r.edge_v[i])).unwrap();
            q[e] += 1;
        }
        waited.clone_from(now);
        // What viewers draw is this same count.
        let mut shown: Vec<(u32, u32, u32)> = sim.queues().lanes.iter().map(|&(u, v, c)| (u.0, v.0, c)).collect();
        shown.sort_unstable();
        let mut want: Vec<(u32, u32, u32)> = (0..lanes).filter(|&e| q[e] > 0).map(|e| (layout.edges[e].0 .0, layout.edges[e].1 .0, q[e])).collect();
        want.sort_unstable();
        assert_eq!(shown, want, "step {steps}");
        for e in 0..lanes {
            busy[e] += u64::from(q[e] > 0);
            queued[e] += u64::from(q[e]);
            longest[e] = longest[e].max(q[e]);
        }
    }
    let r = sim.result();
    let reported: Vec<_> = r.resources.iter().filter(|u| u.kind == ResourceKind::Lane).collect();
    assert_eq!(reported.len(), 10.min(queued.iter().filter(|&&q| q > 0).count()));
    // The ten with the longest mean queue, longest first.
    let mut means: Vec<u64> = queued.clone();
    means.sort_unstable_by(|a, b| b.cmp(a));
    for (k, u) in reported.iter().enumerate() {
        let e = layout.edges.iter().position(|&(a, b)| format!("{}->{}", layout.nodes[a.index()].name, layout.nodes[b.index()].name) == u.node).unwrap();
        assert!((u.mean_queue - queued[e] as f64 / steps as f64).abs() < 1e-12, "{}", u.node);
        assert!((u.busy - busy[e] as f64 / steps as f64).abs() < 1e-12, "{}", u.node);
        assert_eq!(u.longest_queue, longest[e], "{}", u.node);
        assert_eq!(queued[e], means[k], "{}: not among the longest", u.node);
    }
    assert!(reported[0].longest_queue > 2, "{reported:?}");
    // A lane's queue is part of its crossing's: never the bottleneck itself.
    assert_ne!(r.bottleneck.unwrap().resource.kind, ResourceKind::Lane);
}
