//! The original rules against values measured with the authors' own code (the headless
//! Python 3 port of github.com/liuyandong1988/Robio2017-MultiBots, `run_authors.py`): the 30
//! paper runs and random goods lists, each (ticks, S, C, outcome) exact; the refusals; and
//! determinism. `tests/oracle/compare_original.py` compares any number of further cases.

use crate::common;

use common::PAPER_TASKS;
use multibots_core::record::metrics::Outcome::{self, Complete, Deadlock, Fault};
use multibots_core::EventKind;
use multibots_core::{Original, Rules, Scenario, State};

fn original(robots: u32, goods: &[u32]) -> Scenario {
    let mut s = Scenario::paper(robots, goods);
    s.rules = Rules::Original;
    s
}

/// (ticks, S, C) of the reference for N = 1..6 (rows) and task groups 1..5 (columns).
const PAPER_RUNS: [[(u64, u64, u64); 5]; 6] = [
    [(6383, 0, 3), (6221, 0, 3), (7110, 0, 4), (7789, 0, 4), (6893, 0, 3)],
    [(2893, 0, 2), (3273, 2, 2), (3342, 2, 2), (3937, 0, 3), (2997, 0, 2)],
    [(1777, 3, 0), (2708, 1, 3), (2520, 3, 2), (2617, 1, 3), (2125, 0, 1)],
    [(1453, 3, 0), (1737, 1, 0), (1815, 1, 0), (2385, 0, 1), (1664, 4, 0)],
    [(1335, 7, 0), (1572, 3, 0), (1576, 3, 0), (1498, 2, 0), (1557, 4, 0)],
    [(1167, 7, 0), (1344, 9, 0), (1448, 0, 0), (1470, 4, 0), (1448, 5, 0)],
];

#[test]
fn the_30_paper_runs() {
    for (n, row) in PAPER_RUNS.iter().enumerate() {
        for (g, &(ticks, s, c)) in row.iter().enumerate() {
            let r = Original::new(&original(n as u32 + 1, &PAPER_TASKS[g])).unwrap().run();
            assert_eq!((r.t, r.s, r.c, r.outcome), (Some(ticks), s, c, Some(Complete)), "N = {}, group {}", n + 1, g + 1);
            assert_eq!(r.steps, ticks);
            assert_eq!(r.delivered, 10);
        }
    }
}

/// Random goods lists: (robots, goods, ticks, S, C, outcome, steps). Deadlocks were measured
/// with the reference stopped on the tick the engine ends (its first stop pair is then two
/// stopped robots in contact); faults with the reference run until it raised, S and C as it
/// had counted them by then.
type Golden = (u32, &'static [u32], Option<u64>, u64, u64, Outcome, u64);
const RANDOM_RUNS: &[Golden] = &[
    (1, &[47, 39, 74, 79, 21], Some(3202), 0, 1, Complete, 3202),
    (1, &[73], Some(691), 0, 0, Complete, 691),
    (1, &[52, 17, 51, 31, 68, 53, 34, 21, 7, 26, 19], Some(6939), 0, 3, Complete, 6939),
    (1, &[46, 42, 47, 52, 20, 23, 74, 5, 66, 63, 69, 73, 21, 70, 12, 10, 15, 37, 11, 30, 14, 25, 49, 44], Some(14462), 0, 8, Complete, 14462),
    (
        1,
        &[2, 1, 49, 56, 46, 37, 65, 38, 68, 57, 11, 33, 28, 61, 30, 32, 9, 17, 22, 13, 25, 48, 21, 77, 60, 62, 23, 75, 27, 31, 14, 12, 19, 16, 70, 15, 55],
        Some(22260),
        0,
        12,
        Complete,
        22260,
    ),
    (2, &[71, 39, 46, 55, 63], Some(2395), 0, 1, Complete, 2395),
    (2, &[18, 47, 31, 63, 68], Some(1659), 0, 0, Complete, 1659),
    (2, &[50, 30, 54, 44, 56, 12, 49, 32, 70, 33, 48, 41, 40], Some(4278), 0, 3, Complete, 4278),
    (2, &[65, 11, 47, 19, 0, 13, 5], Some(1581), 0, 0, Complete, 1581),
    (2, &[50, 60, 62, 35, 68, 0, 70, 77, 21, 28, 40, 46, 10, 57, 24, 9, 51, 26, 37, 15, 47, 71, 1, 11, 59, 16, 79, 72], Some(8815), 5, 8, Complete, 8815),
    (
        2,
        &[
            46, 6, 16, 25, 45, 7, 44, 64, 61, 62, 66, 2, 68, 60, 73, 67, 63, 40, 51, 0, 11, 47, 77, 35, 9, 53, 14, 27, 34, 23, 31, 58, 70, 36, 4, 13, 75, 30,
            59, 78, 3, 42, 49, 26, 24, 54, 71,
        ],
        Some(15159),
        3,
        16,
        Complete,
        15159,
    ),
    (3, &[63, 75, 40], Some(897), 2, 0, Complete, 897),
    (3, &[22, 25, 65, 20, 79, 1, 53, 54, 40, 29, 6, 76, 59], Some(3082), 0, 3, Complete, 3082),
    (3, &[9, 78, 74, 30, 10, 66, 4, 31], Some(1606), 4, 0, Complete, 1606),
    (3, &[37, 39, 27, 64, 29, 10, 6, 25, 50, 58, 30, 31, 55, 48, 38, 19, 13, 72, 60, 52], Some(4189), 1, 5, Complete, 4189),
    (
        3,
        &[
            34, 25, 19, 30, 42, 31, 51, 17, 8, 7, 64, 36, 65, 43, 60, 59, 28, 9, 27, 37, 33, 63, 76, 11, 61, 26, 45, 57, 68, 18, 67, 62, 41, 15, 2, 44, 78, 50,
            23, 49, 35, 39, 48,
        ],
        Some(9653),
        2,
        14,
        Complete,
        9653,
    ),
    (4, &[79, 26, 54, 48], Some(691), 0, 0, Complete, 691),
    (4, &[30, 9, 28, 10, 47, 74, 50, 35, 72, 49, 41, 17, 69, 45], Some(2534), 4, 2, Complete, 2534),
    (4, &[50, 67, 7, 41, 62, 8], Some(961), 4, 0, Complete, 961),
    (4, &[32, 60, 75, 0, 18, 26, 12, 9, 17, 50, 30, 1, 77, 15, 59, 43, 45, 63, 3, 6, 33, 23, 13], Some(3070), 9, 4, Complete, 3070),
    (
        4,
        &[70, 28, 62, 44, 14, 47, 38, 3, 51, 10, 67, 75, 55, 53, 23, 17, 7, 35, 19, 9, 2, 61, 56, 16, 22, 21, 73, 32, 13, 68, 57, 31, 26, 42, 36, 41],
        Some(5458),
        12,
        9,
        Complete,
        5458,
    ),
    (5, &[61, 59, 9, 21, 75], Some(897), 0, 0, Complete, 897),
    (5, &[20, 64, 73, 2, 29, 40, 11, 36, 79, 58, 71, 53, 1, 76, 51], Some(2473), 5, 2, Complete, 2473),
    (5, &[67, 44, 38, 48, 27, 79, 56], Some(1086), 4, 0, Complete, 1086),
    (5, &[72, 74, 10, 28, 5, 12, 4, 48, 63, 69, 75, 45, 35, 1, 55, 61, 62], Some(2841), 11, 4, Complete, 2841),
    (
        5,
        &[
            45, 58, 25, 21, 9, 60, 73, 4, 13, 20, 68, 0, 51, 7, 70, 59, 16, 37, 79, 12, 38, 57, 24, 65, 66, 31, 76, 78, 36, 26, 62, 14, 39, 48, 32, 35, 49, 19,
            5, 29, 53, 17, 47,
        ],
        Some(6142),
        27,
        13,
        Complete,
        6142,
    ),
    (6, &[57, 63, 55, 5, 22, 65, 77, 42, 2, 7, 40, 3, 4, 23, 66], Some(2235), 6, 1, Complete, 2235),
    (6, &[69, 48, 58, 68, 15, 32, 41, 30], Some(1026), 10, 0, Complete, 1026),
    (6, &[51, 17, 44, 5, 37, 38, 58, 66, 8, 50, 31, 14, 75, 45, 78, 47, 72, 23, 55, 21, 26, 74, 33, 25, 53, 70], Some(3364), 11, 6, Complete, 3364),
    (
        6,
        &[
            39, 14, 21, 16, 9, 33, 75, 26, 74, 66, 1, 71, 31, 50, 49, 6, 0, 40, 36, 53, 57, 4, 68, 58, 30, 72, 76, 56, 23, 60, 19, 32, 20, 37, 54, 34, 77, 38,
            5, 44, 78, 64, 25, 43, 48, 15, 17, 22,
        ],
        Some(6031),
        36,
        13,
        Complete,
        6031,
    ),
    (
        5,
        &[
            3, 59, 77, 7, 37, 62, 71, 52, 18, 67, 26, 65, 66, 30, 76, 43, 11, 14, 42, 49, 22, 48, 36, 9, 32, 10, 15, 24, 1, 58, 21, 51, 16, 64, 70, 54, 29, 27,
            75, 25, 61, 2, 69, 4, 74, 0,
        ],
        None,
        26,
        14,
        Deadlock,
        5291,
    ),
    (
        4,
        &[
            52, 67, 65, 47, 73, 45, 20, 14, 39, 26, 36, 31, 33, 55, 3, 13, 41, 34, 62, 16, 58, 35, 11, 75, 72, 17, 51, 46, 29, 2, 21, 79, 27, 60, 78, 63, 61,
            8, 0, 12, 6,
        ],
        None,
        13,
        8,
        Deadlock,
        3596,
    ),
    (
        3,
        &[21, 46, 17, 12, 59, 1, 20, 62, 54, 75, 42, 49, 45, 29, 13, 70, 4, 27, 19, 61, 66, 38, 0, 52, 43, 16, 23, 31, 9, 10, 26, 79, 35, 5, 53],
        None,
        4,
        6,
        Fault,
        5039,
    ), // Strategy.computeStartToGood: KeyError 'x' (BFS from no crossing)
    (4, &[61, 49, 16, 25, 0, 62, 38, 79, 18, 19, 21, 74, 73, 10, 59, 64, 13, 26, 67, 23, 51, 11], None, 7, 4, Fault, 2940), // Strategy.computeStartToGood: KeyError 'x' (BFS from no crossing)
    (
        6,
        &[
            73, 19, 26, 51, 12, 38, 60, 27, 4, 39, 0, 33, 9, 41, 49, 54, 36, 61, 59, 72, 64, 1, 58, 34, 63, 52, 43, 18, 7, 42, 5, 14, 77, 65, 31, 68, 15, 17,
            23, 79, 45, 3, 47,
        ],
        None,
        19,
        6,
        Deadlock,
        2381,
    ),
    (
        3,
        &[
            73, 79, 18, 8, 23, 24, 75, 65, 72, 22, 50, 35, 42, 15, 41, 17, 31, 7, 1, 77, 69, 39, 27, 70, 3, 2, 10, 0, 5, 9, 28, 74, 21, 48, 36, 54, 32, 51, 52,
            38, 46, 16, 30, 25, 67, 20, 44, 76,
        ],
        None,
        12,
        15,
        Fault,
        9696,
    ), // Strategy.takeoffgoods: IndexError (GOOD_NUM[0] on an empty list)
    (
        4,
        &[
            2, 61, 10, 70, 58, 56, 55, 12, 14, 73, 32, 68, 25, 28, 48, 0, 20, 37, 3, 52, 62, 78, 6, 43, 67, 21, 72, 75, 53, 33, 29, 8, 19, 35, 13, 22, 5, 60,
            51, 31, 65, 74,
        ],
        None,
        13,
        12,
        Fault,
        6135,
    ), // Strategy.takeoffgoods: IndexError (GOOD_NUM[0] on an empty list)
    (
        6,
        &[
            6, 15, 46, 56, 2, 35, 17, 44, 33, 59, 68, 22, 66, 7, 32, 11, 77, 23, 39, 21, 41, 70, 53, 20, 16, 0, 40, 36, 52, 48, 51, 43, 9, 3, 12, 57, 26, 72,
            60, 37, 61, 75, 47, 71, 25, 69, 78,
        ],
        None,
        26,
        13,
        Fault,
        5036,
    ), // Controller.chargeController: IndexError (GOOD_NUM[0] on an empty list)
    (
        4,
        &[
            52, 11, 29, 75, 40, 68, 5, 67, 69, 44, 47, 30, 53, 12, 34, 48, 13, 31, 77, 61, 56, 70, 58, 6, 14, 37, 25, 49, 10, 27, 64, 24, 19, 23, 33, 1, 32,
            39, 45, 22, 0, 76, 54,
        ],
        None,
        22,
        13,
        Fault,
        6597,
    ), // Controller.chargeController: IndexError (GOOD_NUM[0] on an empty list)
    (
        3,
        &[
            50, 32, 7, 63, 8, 45, 29, 72, 78, 14, 4, 61, 58, 18, 28, 27, 54, 39, 25, 44, 77, 22, 75, 21, 40, 16, 38, 24, 26, 76, 43, 60, 48, 41, 64, 15, 62,
            23, 31, 52, 37, 79, 71, 9, 70, 56, 51, 12, 55, 10,
        ],
        None,
        5,
        8,
        Deadlock,
        5158,
    ),
    (
        2,
        &[
            76, 4, 74, 42, 6, 39, 26, 64, 69, 8, 60, 51, 12, 35, 49, 62, 56, 1, 33, 5, 38, 14, 46, 7, 54, 71, 17, 30, 13, 52, 67, 22, 29, 9, 15, 48, 2, 25, 0,
            3, 47, 11, 59, 10, 61, 65, 53, 63, 28, 41,
        ],
        None,
        2,
        10,
        Deadlock,
        8764,
    ),
    (1, &[42], Some(741), 0, 0, Complete, 741),
    (6, &[0, 10, 20, 30, 40, 50], Some(1025), 1, 0, Complete, 1025),
];

#[test]
fn random_goods_lists() {
    let mut seen = Vec::new();
    for &(n, goods, ticks, s, c, outcome, steps) in RANDOM_RUNS {
        let r = Original::new(&original(n, goods)).unwrap().run();
        assert_eq!((r.t, r.s, r.c, r.outcome, r.steps), (ticks, s, c, Some(outcome), steps), "--robots {n} --goods {goods:?}");
        seen.push(outcome);
    }
    // The table covers every way a run ends, and charging.
    for o in [Complete, Deadlock, Fault] {
        assert!(seen.contains(&o), "{o:?}");
    }
    assert!(RANDOM_RUNS.iter().any(|r| r.5 == Complete && r.4 > 5));
}

#[test]
fn every_fault_is_reached() {
    use multibots_core::rules::original::Fault as F;
    let mut kinds = Vec::new();
    for &(n, goods, _, _, _, outcome, _) in RANDOM_RUNS {
        if outcome == Fault {
            let mut o = Original::new(&original(n, goods)).unwrap();
            o.run();
            kinds.push(o.fault().unwrap());
        }
    }
    for f in [F::EmptyQueueAfterDelivery, F::EmptyQueueAtRedispatch, F::ChargeRouteFromNowhere] {
        assert!(kinds.contains(&f), "{f:?}");
    }
}

#[test]
fn step_limit_is_a_safety_stop() {
    let mut s = original(3, &PAPER_TASKS[0]);
    s.step_limit = 500;
    let r = Original::new(&s).unwrap().run();
    assert_eq!((r.t, r.outcome, r.steps), (None, Some(Outcome::Incomplete), 500));
    // A stopped run goes no further.
    let mut o = Original::new(&s).unwrap();
    o.run();
    o.step();
    assert_eq!(o.t(), 500);
}

#[test]
fn two_runs_agree_tick_by_tick() {
    for (n, goods) in [(6, &PAPER_TASKS[1][..]), (2, RANDOM_RUNS[RANDOM_RUNS.len() - 3].1)] {
        let (mut a, mut b) = (Original::new(&original(n, goods)).unwrap(), Original::new(&original(n, goods)).unwrap());
        while !a.done() {
            a.step();
            b.step();
            let (ra, rb) = (a.robots(), b.robots());
            assert_eq!((a.t(), &ra.x, &ra.y, &ra.heading, &ra.state, &ra.energy), (b.t(), &rb.x, &rb.y, &rb.heading, &rb.state, &rb.energy));
            assert_eq!(a.events(), b.events());
            assert_eq!(a.cells_full(), b.cells_full());
            assert_eq!(a.queue_cells(), b.queue_cells());
        }
        assert!(b.done());
        assert_eq!(a.result(), b.result());
    }
}

#[test]
fn the_view_follows_the_robots() {
    let mut o = Original::new(&original(2, &[42, 11])).unwrap();
    let r = o.robots();
    // At the chargers, in the paper layout's frame (CH0 and CH1, heading 270° = down).
    assert_eq!((r.x[0], r.y[0], r.x[1], r.y[1]), (25.0, -15.0, 175.0, -15.0));
    assert_eq!((r.at_node[0], r.home[0].0), (18, 18));
    assert!((r.heading[0] - (-270f64).to_radians()).abs() < 1e-12);
    assert_eq!(o.events().iter().filter(|e| e.kind == EventKind::Assign).count(), 2);
    assert_eq!(o.energy_levels(), (10.0, 3.5));
    let mut full_before = o.cells_full().iter().filter(|&&f| f).count();
    assert_eq!(full_before, 2);
    let mut picked = 0;
    while !o.done() {
        o.step();
        let r = o.robots();
        for i in 0..2 {
            assert!(r.x[i] >= 0.0 && r.x[i] <= 800.0 && r.y[i] >= -15.0 && r.y[i] <= 550.0, "inside the layout");
            assert_eq!(r.radius[i], 12.0);
        }
        let full = o.cells_full().iter().filter(|&&f| f).count();
        let pickups = o.events().iter().filter(|e| e.kind == EventKind::Pickup).count();
        assert_eq!(full_before - full, pickups);
        picked += pickups;
        full_before = full;
    }
    assert_eq!(picked, 2);
    assert!(o.robots().state.iter().all(|&s| s == State::Charging || s == State::Parked));
    assert!(o.queue_cells().is_empty());
    let r = o.result();
    assert_eq!(r.robots.delivered.iter().sum::<u32>(), 2);
    assert_eq!(u64::from(r.robots.state_steps[0].iter().sum::<u32>()), r.steps);
}

fn refusal(edit: impl FnOnce(&mut Scenario)) -> String {
    let mut s = original(3, &[11, 8, 39]);
    edit(&mut s);
    match Original::new(&s) {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn what_the_original_cannot_run_is_refused_in_one_line() {
    use multibots_core::input::scenario::{ChargerUse, ChargingPolicy, Orders, Placement};
    let cases: Vec<(String, &str)> = vec![
        (refusal(|s| s.robots = 7), "robots = 7: the original rules run at most 6 robots (one per start A..F)"),
        (
            refusal(|s| s.tasks = multibots_core::input::scenario::Tasks::Cells(vec![11, 8])),
            "tasks = 2 goods: the original rules need at least one goods per robot (3 robots)",
        ),
        (
            refusal(|s| s.tasks = multibots_core::input::scenario::Tasks::Cells((0..51).collect())),
            "tasks = 51 goods: the original rules deliver at most 50 goods (the code's cart has 50 boxes)",
        ),
        (refusal(|s| s.layout = "big.toml".into()), "layout = \"big.toml\": the original rules run only the paper layout"),
        (
            refusal(|s| s.layout_generate = Some(multibots_core::LayoutParams::paper())),
            "layout_generate = [layout_generate]: the original rules run only the paper layout",
        ),
        (refusal(|s| s.allocator = "nearest".into()), "allocator = \"nearest\": the original rules hand out goods in turn only (\"in-turn\")"),
        (
            refusal(|s| s.orders = Some(Orders { rate: 0.1, ..Orders::default() })),
            "orders = [orders]: the original rules fetch a fixed task list (no lifelong orders)",
        ),
        (
            refusal(|s| {
                s.placement = Placement::Spread;
                s.charging.chargers = ChargerUse::Shared;
            }),
            "placement = \"spread\": the original rules start robot k at the k-th of A..F",
        ),
        (refusal(|s| s.charging.chargers = ChargerUse::Shared), "charging.chargers = \"shared\": the original rules charge every robot at its own charger"),
        (
            refusal(|s| s.charging.policy = ChargingPolicy::Opportunistic),
            "charging.policy = \"opportunistic\": the original rules charge by the threshold rule only",
        ),
        (
            refusal(|s| s.starts = Some(vec!["B".into(), "C".into(), "D".into()])),
            "starts = [\"B\", \"C\", \"D\"]: the original rules start robot k at the k-th of A..F",
        ),
        (refusal(|s| s.unload = "N".into()), "unload = \"N\": the original rules unload at M"),
        (refusal(|s| s.robot.radius = 10.0), "robot.radius = 10: the original rules use the code's radius L/4 = 12 px (leave the default 12.5, or give 12)"),
        (refusal(|s| s.robot.speed = 5.0), "robot.speed = 5: the original rules move 4 px a tick"),
        (refusal(|s| s.robot.energy_full = 12.0), "robot.energy_full = 12: the original rules use full energy 10"),
        (refusal(|s| s.robot.threshold = 3.0), "robot.threshold = 3: the original rules use the threshold 3.5"),
        (refusal(|s| s.robot.consumption = 0.001), "robot.consumption = 0.001: the original rules use 0.005 a tick"),
        (refusal(|s| s.robot.charge_rate = 0.1), "robot.charge_rate = 0.1: the original rules charge 0.05 a tick"),
        (refusal(|s| s.collision.angle = 45.0), "collision.angle = 45: the original rules use a 30° cone"),
        (refusal(|s| s.collision.margin = 4.0), "collision.margin = 4: the original rules touch at r_i + r_j + 8 (leave the default 0, or give 8)"),
        (refusal(|s| s.dwell.loading = 5), "dwell.loading = 5: the original rules load for 10 ticks"),
        (refusal(|s| s.dwell.unloading = 30), "dwell.unloading = 30: the original rules unload for 20 ticks"),
        (refusal(|s| s.robots = 0), "robots = 0: must be at least 1"),
        (refusal(|s| s.tasks = multibots_core::input::scenario::Tasks::Cells(vec![11, 8, 80])), "tasks[2] = 80: cell id out of range 0..79"),
    ];
    for (got, want) in cases {
        assert_eq!(got, want);
        assert!(!got.contains('\n'));
    }
}

#[test]
fn the_codes_own_values_and_the_default_starts_are_accepted() {
    let mut s = original(3, &PAPER_TASKS[0]);
    s.robot.radius = 12.0;
    s.collision.margin = 8.0;
    s.starts = Some(vec!["A".into(), "B".into(), "C".into()]);
    s.cost.collision = 10.0;
    let r = Original::new(&s).unwrap().run();
    assert_eq!((r.t, r.s, r.c), (Some(PAPER_RUNS[2][0].0), PAPER_RUNS[2][0].1, PAPER_RUNS[2][0].2));
}

#[test]
fn rules_in_toml() {
    let s = Scenario::from_toml("rules = \"original\"\nrobots = 2\ntasks = [11, 8]", "s.toml").unwrap();
    assert_eq!(s.rules, Rules::Original);
    assert_eq!(Scenario::from_toml(&s.to_toml(), "t.toml").unwrap(), s);
    let p = Scenario::from_toml("tasks = [11]", "s.toml").unwrap();
    assert_eq!(p.rules, Rules::Paper);
    assert!(!p.to_toml().contains("rules"), "the default is not written out");
    let e = Scenario::from_toml("rules = \"authors\"\ntasks = [11]", "s.toml").unwrap_err().to_string();
    assert_eq!(e, "s.toml: rules = \"authors\": expected paper or original");
}

#[test]
fn the_simulation_runs_the_original_rules_with_every_figure() {
    use multibots_core::Simulation;
    let s = original(6, &PAPER_TASKS[0]);
    let mut sim = Simulation::new(&s).unwrap();
    assert_eq!(sim.rules(), Rules::Original);
    assert_eq!(sim.allocator_name(), "in-turn");
    let r = sim.run().unwrap();
    let own = Original::new(&s).unwrap().run();
    assert_eq!((r.t, r.s, r.c, r.outcome, r.steps, r.delivered), (own.t, own.s, own.c, own.outcome, own.steps, own.delivered));
    assert_eq!(r.windows.len() as u64, r.steps / 1000);
    assert!(r.windows.iter().sum::<u64>() <= 10);
    assert!((r.throughput.unwrap() - 10.0 * 1000.0 / r.steps as f64).abs() < 1e-9);
    assert!(r.cost.is_some() && r.closest.is_some());
    // A Python or other allocator cannot run the original rules.
    let e = Simulation::with_allocator(&s, Box::new(multibots_core::alloc::Nearest)).err().unwrap();
    assert_eq!(e.to_string(), "allocator = \"nearest\": the original rules dispatch in turn only (in-turn)");
}

#[test]
fn a_replay_of_the_original_rules_holds_every_tick() {
    use multibots_core::{output::replay, Simulation};
    let s = original(3, &PAPER_TASKS[1]);
    let path = std::env::temp_dir().join(format!("mb-original-{}.mbr", std::process::id()));
    let mut sim = Simulation::new(&s).unwrap();
    replay::run_recorded(&mut sim, &path, serde_json::json!({"scenario": s.to_toml()})).unwrap();
    let r = sim.result();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert!(bytes.starts_with(b"MBREPLAY"));
    assert_eq!(r.t, Original::new(&s).unwrap().run().t);
}
