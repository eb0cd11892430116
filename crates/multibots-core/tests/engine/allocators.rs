//! The built-in strategies on hand-made situations whose right assignment is known, their
//! validation by the engine, determinism, and in-turn against the paper model.

use multibots_core::alloc::{self, AllocView, Auction, EnergyAware, EnergyModel, Goods, Hungarian, InTurn, MinCost, Nearest, TaskModel};
use multibots_core::fleet::robot::{Robots, State};
use multibots_core::input::scenario::{ChargingPolicy, CostWeights, Tasks};
use multibots_core::{Allocator, Assignment, CellId, Decisions, Error, GoodsId, HighwayGraph, Layout, NodeId, RobotId, Scenario, Simulation};

/// A hand-made fleet on the paper layout: robots standing on named nodes, idle.
struct Fixture {
    layout: Layout,
    graph: HighwayGraph,
    robots: Robots,
}

impl Fixture {
    /// `spots`: (node the robot stands on, its home charger, its energy).
    fn new(spots: &[(&str, &str, f64)]) -> Fixture {
        let layout = Layout::paper();
        let graph = HighwayGraph::new(&layout);
        let mut robots = Robots::default();
        for &(at, home, energy) in spots {
            let at = layout.node_named(at).unwrap();
            let home = layout.node_named(home).unwrap();
            robots.push(at, layout.pos(at), home, 12.5, 4.0, energy);
        }
        Fixture { layout, graph, robots }
    }

    fn run(&self, a: &mut dyn Allocator, idle: &[u32], cells: &[u32]) -> Vec<(u32, u32)> {
        let idle: Vec<RobotId> = idle.iter().map(|&i| RobotId(i)).collect();
        let goods: Vec<Goods> = cells.iter().enumerate().map(|(k, &c)| Goods { id: GoodsId(k as u32), cell: CellId(c) }).collect();
        let m = self.layout.node_named("M").unwrap();
        let energy = EnergyModel { energy_full: 10.0, threshold: 3.5, consumption: 0.005, speed: 4.0 };
        let view = AllocView::new(1, &idle, &goods, &self.robots, &self.layout, &self.graph, m, energy);
        let mut out = Decisions::new();
        a.allocate(&view, &mut out).unwrap();
        assert!(out.charge.is_empty(), "built-ins send no robot to charge");
        out.assign.iter().map(|x| (x.robot.0, x.goods.0)).collect()
    }

    fn view_len(&self, robot: u32, cell: u32) -> f64 {
        let idle = [RobotId(robot)];
        let m = self.layout.node_named("M").unwrap();
        let energy = EnergyModel { energy_full: 10.0, threshold: 3.5, consumption: 0.005, speed: 4.0 };
        AllocView::new(1, &idle, &[], &self.robots, &self.layout, &self.graph, m, energy).route_length(RobotId(robot), CellId(cell))
    }
}

fn model() -> TaskModel {
    TaskModel::of(&Scenario::paper(1, &[0]))
}

fn sorted(mut v: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    v.sort_unstable();
    v
}

#[test]
fn in_turn_pairs_robots_in_id_order_with_the_front_of_the_queue() {
    let f = Fixture::new(&[("CH0", "CH0", 10.0), ("CH1", "CH1", 10.0), ("CH2", "CH2", 10.0)]);
    assert_eq!(f.run(&mut InTurn, &[0, 2], &[79, 0, 5]), vec![(0, 0), (2, 1)]);
    assert_eq!(f.run(&mut InTurn, &[0, 1, 2], &[79]), vec![(0, 0)]);
}

#[test]
fn nearest_gives_the_front_goods_to_the_closest_robot() {
    // Robot 0 parks at CH5, far right; robot 1 at CH0, next to cell 1 (left column).
    let f = Fixture::new(&[("CH5", "CH5", 10.0), ("CH0", "CH0", 10.0)]);
    assert!(f.view_len(1, 1) < f.view_len(0, 1));
    assert_eq!(f.run(&mut Nearest, &[0, 1], &[1]), vec![(1, 0)]);
    // In-turn gives it to robot 0 regardless.
    assert_eq!(f.run(&mut InTurn, &[0, 1], &[1]), vec![(0, 0)]);
    // Ties go to the lower id: two robots on the same node.
    let g = Fixture::new(&[("M", "CH0", 10.0), ("M", "CH1", 10.0)]);
    assert_eq!(g.run(&mut Nearest, &[0, 1], &[40, 41]), vec![(0, 0), (1, 1)]);
}

#[test]
fn hungarian_beats_greedy_on_a_crafted_three_by_three_case() {
    // Robots at CH0, CH1, CH2; goods at cells 3, 10, 1. Route lengths (px), robot × goods:
    //   robot 0: 290  990  240
    //   robot 1: 140  840   90
    //   robot 2: 1890 1290 1840
    // Greedy in queue order gives goods 0 to robot 1 (140), goods 1 to robot 0 (990) and
    // goods 2 to robot 2 (1840): 2970 px. The optimum is 1670 px, reached two ways
    // (290 + 90 + 1290 and 240 + 140 + 1290); the solver's tie-break picks the second.
    let f = Fixture::new(&[("CH0", "CH0", 10.0), ("CH1", "CH1", 10.0), ("CH2", "CH2", 10.0)]);
    let cells = [3, 10, 1];
    let want = [[290.0, 990.0, 240.0], [140.0, 840.0, 90.0], [1890.0, 1290.0, 1840.0]];
    for r in 0..3 {
        for (j, &c) in cells.iter().enumerate() {
            assert_eq!(f.view_len(r, c), want[r as usize][j], "robot {r} cell {c}");
        }
    }
    let total = |pairs: &[(u32, u32)]| pairs.iter().map(|&(r, g)| f.view_len(r, cells[g as usize])).sum::<f64>();
    let greedy = f.run(&mut Nearest, &[0, 1, 2], &cells);
    assert_eq!(sorted(greedy.clone()), vec![(0, 1), (1, 0), (2, 2)]);
    assert_eq!(total(&greedy), 2970.0);
    let best = f.run(&mut Hungarian, &[0, 1, 2], &cells);
    assert_eq!(sorted(best.clone()), vec![(0, 2), (1, 0), (2, 1)]);
    assert_eq!(total(&best), 1670.0);
}

#[test]
fn hungarian_with_more_goods_than_robots_picks_the_nearest_goods() {
    let f = Fixture::new(&[("CH0", "CH0", 10.0)]);
    // Cell 79 is far (bottom right), cell 1 is next to CH0's aisle.
    assert_eq!(f.run(&mut Hungarian, &[0], &[79, 1]), vec![(0, 1)]);
    // More robots than goods: only the nearest robot goes.
    let g = Fixture::new(&[("CH5", "CH5", 10.0), ("CH0", "CH0", 10.0)]);
    assert_eq!(g.run(&mut Hungarian, &[0, 1], &[1]), vec![(1, 0)]);
}

#[test]
fn auction_sells_the_shortest_task_first_and_low_robots_bid_high() {
    let f = Fixture::new(&[("CH0", "CH0", 10.0)]);
    // One robot, a far and a near goods: the near one is the lower bid.
    assert_eq!(f.run(&mut Auction::new(model()), &[0], &[79, 1]), vec![(0, 1)]);
    // Robot 0 is nearer but would end below the threshold: its bid carries the recharge time,
    // so robot 1 (full, a little farther) wins.
    let g = Fixture::new(&[("CH1", "CH1", 3.6), ("CH0", "CH0", 10.0)]);
    assert!(g.view_len(0, 1) < g.view_len(1, 1));
    assert_eq!(g.run(&mut Nearest, &[0, 1], &[1]), vec![(0, 0)]);
    assert_eq!(g.run(&mut Auction::new(model()), &[0, 1], &[1]), vec![(1, 0)]);
}

#[test]
fn energy_aware_never_hands_out_a_task_that_ends_below_the_threshold() {
    // Robot 0 has 3.6: cell 1 takes well over 20 steps, so it would end below 3.5.
    let f = Fixture::new(&[("CH0", "CH0", 3.6)]);
    assert_eq!(f.run(&mut EnergyAware::new(model()), &[0], &[1, 79]), vec![]);
    // In-turn hands it out anyway.
    assert_eq!(f.run(&mut InTurn, &[0], &[1, 79]), vec![(0, 0)]);
    // A goods no robot can finish is skipped; a shorter later one goes to the robot that can.
    let m = model();
    let g = Fixture::new(&[("M", "CH0", 6.0)]);
    let steps = |c: u32| {
        let idle = [RobotId(0)];
        let energy = EnergyModel { energy_full: 10.0, threshold: 3.5, consumption: 0.005, speed: 4.0 };
        let v = AllocView::new(1, &idle, &[], &g.robots, &g.layout, &g.graph, g.layout.node_named("M").unwrap(), energy);
        m.task_steps(&v, RobotId(0), CellId(c))
    };
    // From M with 6.0: cell 78 (far right) needs more than (6.0 - 3.5 - 0.1) / 0.005 = 480
    // steps, cell 5 (left, near M) fewer.
    assert!(steps(78) > 480.0 && steps(5) < 480.0, "{} {}", steps(78), steps(5));
    assert_eq!(g.run(&mut EnergyAware::new(model()), &[0], &[78, 5]), vec![(0, 1)]);
}

#[test]
fn energy_aware_prefers_the_more_charged_robot() {
    // Robot 0 (at CH1) is nearer to cell 1 but robot 1 has more energy.
    let f = Fixture::new(&[("CH1", "CH1", 8.0), ("CH0", "CH0", 10.0)]);
    assert!(f.view_len(0, 1) < f.view_len(1, 1));
    assert_eq!(f.run(&mut EnergyAware::new(model()), &[0, 1], &[1]), vec![(1, 0)]);
    // Equal energy: the shorter route wins (robot 1, at CH1).
    let g = Fixture::new(&[("CH0", "CH0", 9.0), ("CH1", "CH1", 9.0)]);
    assert_eq!(g.run(&mut EnergyAware::new(model()), &[0, 1], &[1]), vec![(1, 0)]);
}

#[test]
fn traffic_counts_where_other_robots_paths_meet_the_route() {
    let layout = Layout::paper();
    let graph = HighwayGraph::new(&layout);
    let mut robots = Robots::default();
    let ch0 = layout.node_named("CH0").unwrap();
    let ch5 = layout.node_named("CH5").unwrap();
    robots.push(ch0, layout.pos(ch0), ch0, 12.5, 4.0, 10.0);
    robots.push(ch5, layout.pos(ch5), ch5, 12.5, 4.0, 10.0);
    let m = layout.node_named("M").unwrap();
    let energy = EnergyModel { energy_full: 10.0, threshold: 3.5, consumption: 0.005, speed: 4.0 };
    // Robot 1 charging at CH5 is off the highways: no traffic anywhere.
    robots.state[1] = State::Charging;
    let idle = [RobotId(0)];
    let v = AllocView::new(1, &idle, &[], &robots, &layout, &graph, m, energy);
    assert_eq!(v.traffic(RobotId(0), CellId(1)), 0);
    // Robot 1 heading for cell 1 too: both will drive to the unloading zone M the same way.
    robots.state[1] = State::ToPickup;
    robots.cell[1] = 1;
    robots.goods[1] = 0;
    multibots_core::fleet::route::assign(&mut robots, &graph, 1, multibots_core::fleet::route::service_target(&layout, CellId(1)));
    let v = AllocView::new(1, &idle, &[], &robots, &layout, &graph, m, energy);
    let shared = v.traffic(RobotId(0), CellId(1));
    assert!(shared >= 2, "{shared}");
    // min-cost weighing only collisions avoids the busy goods when a quiet one exists.
    let mut s = Scenario::paper(2, &[0]);
    s.cost = CostWeights { distance: 0.0, time: 0.0, collision: 1.0 };
    let t: Vec<u32> = (0..80).map(|c| v.traffic(RobotId(0), CellId(c))).collect();
    let quiet = (0..80).min_by_key(|&c| t[c as usize]).unwrap();
    let busy = (0..80).max_by_key(|&c| (t[c as usize], std::cmp::Reverse(c))).unwrap();
    assert!(t[busy as usize] > t[quiet as usize], "{t:?}");
    let goods = [Goods { id: GoodsId(0), cell: CellId(busy) }, Goods { id: GoodsId(1), cell: CellId(quiet) }];
    let v = AllocView::new(1, &idle, &goods, &robots, &layout, &graph, m, energy);
    let mut out = Decisions::new();
    MinCost::new(TaskModel::of(&s)).allocate(&v, &mut out).unwrap();
    assert_eq!(out.assign, vec![Assignment { robot: RobotId(0), goods: GoodsId(1) }]);
}

#[test]
fn min_cost_on_distance_alone_is_optimal_on_task_length() {
    let f = Fixture::new(&[("CH0", "CH0", 10.0), ("CH1", "CH1", 10.0), ("CH2", "CH2", 10.0)]);
    let mut s = Scenario::paper(3, &[0]);
    s.cost = CostWeights { distance: 1.0, time: 0.0, collision: 0.0 };
    let cells = [3, 10, 1];
    let got = f.run(&mut MinCost::new(TaskModel::of(&s)), &[0, 1, 2], &cells);
    // Each goods' way to the unloading zone is the same for every robot, so the optimum has
    // hungarian's total route length (1670 px, see above).
    let total: f64 = got.iter().map(|&(r, g)| f.view_len(r, cells[g as usize])).sum();
    assert_eq!(total, 1670.0);
    assert_eq!(got.len(), 3);
}

/// A strategy that answers with whatever it is told to, for the validation tests:
/// assignments, and robots to send to charge.
struct Fixed(Vec<(u32, u32)>, Vec<u32>);

impl Allocator for Fixed {
    fn name(&self) -> &'static str {
        "fixed-test"
    }
    fn allocate(&mut self, _view: &AllocView<'_>, out: &mut Decisions) -> multibots_core::Result<()> {
        out.assign.extend(self.0.iter().map(|&(r, g)| Assignment { robot: RobotId(r), goods: GoodsId(g) }));
        out.charge.extend(self.1.iter().map(|&r| RobotId(r)));
        Ok(())
    }
}

fn run_fixed(answer: Vec<(u32, u32)>) -> Error {
    run_fixed_charging(answer, vec![])
}

fn run_fixed_charging(answer: Vec<(u32, u32)>, charge: Vec<u32>) -> Error {
    let s = Scenario::paper(2, &[11, 8, 39]);
    Simulation::with_allocator(&s, Box::new(Fixed(answer, charge))).unwrap().run().unwrap_err()
}

#[test]
fn invalid_charge_decisions_are_rejected_naming_the_strategy() {
    // At the first event both robots are full: charging one is refused.
    let e = run_fixed_charging(vec![], vec![1]).to_string();
    assert_eq!(e, "allocator 'fixed-test': charge 0: robot 1 is full (energy 10)");
    let e = run_fixed_charging(vec![(0, 0)], vec![0]).to_string();
    assert_eq!(e, "allocator 'fixed-test': charge 0: robot 0 is given two decisions");
    let e = run_fixed_charging(vec![], vec![7]).to_string();
    assert_eq!(e, "allocator 'fixed-test': charge 0: unknown robot id 7");
}

#[test]
fn invalid_assignments_are_rejected_naming_the_strategy() {
    let e = run_fixed(vec![(5, 0)]).to_string();
    assert!(e.starts_with("allocator 'fixed-test': ") && e.contains("unknown robot id 5"), "{e}");
    let e = run_fixed(vec![(0, 0), (1, 0)]).to_string();
    assert!(e.starts_with("allocator 'fixed-test': ") && e.contains("goods 0 handed out twice"), "{e}");
    let e = run_fixed(vec![(0, 9)]).to_string();
    assert!(e.starts_with("allocator 'fixed-test': ") && e.contains("unknown or taken goods id 9"), "{e}");
    let e = run_fixed(vec![(0, 0), (0, 1)]).to_string();
    assert!(e.starts_with("allocator 'fixed-test': ") && e.contains("robot 0"), "{e}");
}

#[test]
fn a_robot_that_is_not_idle_is_rejected() {
    // At the first event both robots take goods; at the next one (one robot idle again) the
    // strategy hands goods to the robot that is still busy.
    struct Busy;
    impl Allocator for Busy {
        fn name(&self) -> &'static str {
            "busy-test"
        }
        fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> multibots_core::Result<()> {
            if view.idle.len() == view.robot_count() {
                InTurn.allocate(view, out)
            } else {
                let busy = (0..view.robot_count() as u32).map(RobotId).find(|r| !view.idle.contains(r)).unwrap();
                out.assign.push(Assignment { robot: busy, goods: view.goods[0].id });
                Ok(())
            }
        }
    }
    let s = Scenario::paper(2, &[11, 8, 39]);
    let e = Simulation::with_allocator(&s, Box::new(Busy)).unwrap().run().unwrap_err().to_string();
    assert!(e.starts_with("allocator 'busy-test': ") && e.contains("is not idle"), "{e}");
}

use multibots_core::input::scenario::PAPER_TASKS as PAPER;

#[test]
fn every_built_in_completes_the_paper_runs_and_is_deterministic() {
    for name in alloc::BUILT_INS {
        for n in 1..=6 {
            for cells in &PAPER {
                let mut s = Scenario::paper(n, cells);
                s.allocator = (*name).to_string();
                let a = Simulation::new(&s).unwrap().run().unwrap();
                assert!(a.t.is_some(), "{name} N={n} {cells:?} incomplete");
                assert_eq!(a.delivered, 10);
                let b = Simulation::new(&s).unwrap().run().unwrap();
                assert_eq!(a, b, "{name} N={n} not deterministic");
            }
        }
    }
}

#[test]
fn seeded_random_runs_are_deterministic_for_every_built_in() {
    for name in alloc::BUILT_INS {
        for seed in [1, 7, 99] {
            let mut s = Scenario::paper(4, &[0]);
            s.tasks = Tasks::Random { random: 12, seed };
            s.allocator = (*name).to_string();
            let a = Simulation::new(&s).unwrap().run().unwrap();
            let b = Simulation::new(&s).unwrap().run().unwrap();
            assert_eq!(a, b, "{name} seed {seed}");
        }
    }
}

#[test]
fn in_turn_is_the_paper_model() {
    // The spec's worked example, and the default allocator is in-turn, bit for bit.
    assert_eq!(Simulation::new(&Scenario::paper(1, &[42])).unwrap().run().unwrap().t, Some(726));
    for n in 1..=6 {
        for cells in &PAPER {
            let s = Scenario::paper(n, cells);
            assert_eq!(s.allocator, "in-turn");
            let by_name = Simulation::new(&s).unwrap().run().unwrap();
            let given = Simulation::with_allocator(&s, Box::new(InTurn)).unwrap().run().unwrap();
            assert_eq!(by_name, given);
        }
    }
    // One robot, one task: T = ⌈D1/4⌉ + 10 + ⌈D2/4⌉ + 20 + ⌈D3/4⌉ for every built-in
    // (with a single robot and a single goods every strategy must make the same choice).
    for name in alloc::BUILT_INS {
        let mut s = Scenario::paper(1, &[42]);
        s.allocator = (*name).to_string();
        assert_eq!(Simulation::new(&s).unwrap().run().unwrap().t, Some(726), "{name}");
    }
}

#[test]
fn unknown_and_python_strategy_names_are_clear_errors() {
    let mut s = Scenario::paper(1, &[42]);
    s.allocator = "greedy".into();
    let e = Simulation::new(&s).err().unwrap().to_string();
    assert!(e.starts_with("allocator = \"greedy\": unknown strategy (built-ins: in-turn, nearest, hungarian, auction, energy-aware, min-cost; or module:Class for a Python strategy)"), "{e}");
    s.allocator = "my_pkg.mod:Cls".into();
    let e = Simulation::new(&s).err().unwrap().to_string();
    assert!(e.contains("Python allocator"), "{e}");
}

#[test]
fn opportunistic_charging_sends_idle_robots_below_the_level_to_charge() {
    // One robot, two tasks: under the threshold rule it never charges; with an opportunistic
    // level of 9.9 it charges after its first delivery, while goods are still open.
    let s = Scenario::paper(1, &[42, 11]);
    let plain = Simulation::new(&s).unwrap().run().unwrap();
    assert_eq!(plain.c, 0);
    let mut o = s.clone();
    o.charging.policy = ChargingPolicy::Opportunistic;
    o.charging.level = 9.9;
    let opp = Simulation::new(&o).unwrap().run().unwrap();
    assert!(opp.c >= 1, "{}", opp.c);
    assert!(opp.t.unwrap() > plain.t.unwrap());
    // A level the robot never drops below changes nothing.
    o.charging.level = 3.6;
    assert_eq!(Simulation::new(&o).unwrap().run().unwrap(), plain);
}

#[test]
fn node_ids_used_above_exist() {
    let l = Layout::paper();
    for n in ["CH0", "CH1", "CH2", "CH5", "M"] {
        assert!(l.node_named(n).is_some(), "{n}");
    }
    let _ = NodeId(0);
}
