//! The rules on hand-made maps: conflicts make every robot wait and are recorded, schedules
//! that break the 2024 rules are refused, and runs are the same for a seed.

use super::action::Action::{self, C, F, R, W};
use super::planner::{PlanView, Planner};
use super::schedule::{ScheduleView, Scheduler};
use super::*;
use crate::input::lorr::GridMap;

/// Plays fixed actions, one row per step, then waits.
struct Script(Vec<Vec<Action>>);

impl Planner for Script {
    fn name(&self) -> &'static str {
        "script"
    }
    fn plan(&mut self, view: &PlanView<'_>, actions: &mut [Action]) {
        let row = self.0.get(view.t as usize).cloned().unwrap_or_else(|| vec![W; actions.len()]);
        actions.copy_from_slice(&row);
    }
}

/// Proposes fixed schedules, one per step, then keeps the one in force.
struct Plan(Vec<Vec<i64>>);

impl Scheduler for Plan {
    fn name(&self) -> &'static str {
        "plan"
    }
    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        if let Some(row) = self.0.get(view.t as usize) {
            proposal.copy_from_slice(row);
        }
    }
}

fn problem(map: &str, starts: &[u32], tasks: &[&[u32]], version: Version, reveal: f64) -> Arc<Problem> {
    Arc::new(Problem {
        path: "test.json".into(),
        map: GridMap::parse(map).unwrap(),
        starts: starts.to_vec(),
        tasks: tasks.iter().map(|t| t.to_vec()).collect(),
        num_tasks_reveal: reveal,
        version,
        y2026: None,
    })
}

const ROW: &str = "type octile\nheight 2\nwidth 4\nmap\n....\n.@..\n";

fn scripted(p: Arc<Problem>, steps: Vec<Vec<Action>>, schedules: Vec<Vec<i64>>) -> LorrRun {
    LorrRun::with(p, LorrOptions::default(), Box::new(Script(steps)), Box::new(Plan(schedules))).unwrap()
}

fn letters(run: &LorrRun, actual: bool) -> Vec<String> {
    let r = run.record();
    let n = run.problem().team_size();
    let rows = if actual { &r.actual } else { &r.planned };
    (0..n).map(|k| (0..r.steps()).map(|t| ['F', 'R', 'C', 'W', 'T'][rows[t * n + k] as usize]).collect()).collect()
}

#[test]
fn a_swap_makes_every_robot_wait_and_is_recorded() {
    // Robots 0 and 1 face each other (1 turned west first); 2 is elsewhere and would move.
    let p = problem(ROW, &[0, 1, 7], &[&[3]], Version::Y2023, 1.0);
    let mut run = scripted(p, vec![vec![W, R, W], vec![W, R, W], vec![F, F, C]], vec![]);
    run.run_to(3);
    assert_eq!(run.locations(), &[0, 1, 7]);
    assert_eq!(run.headings(), &[0, 2, 0], "the refused step's turns are not made");
    assert_eq!(letters(&run, true), vec!["WWW", "RRW", "WWW"]);
    assert_eq!(letters(&run, false), vec!["WWF", "RRF", "WWC"]);
    assert_eq!(run.record().errors, vec![crate::record::grid::ActionError { kind: "edge conflict", agent: 1, other: 0, timestep: 3 }]);
}

#[test]
fn a_vertex_conflict_makes_every_robot_wait() {
    // 0 at (0,0) facing east, 1 at (1,0) turned north... both into cell 0? Use (0,1): 0 goes
    // east into 1, robot 2 at (0,2) turned west goes into 1 too.
    let p = problem(ROW, &[0, 2, 4], &[&[3]], Version::Y2023, 1.0);
    let mut run = scripted(p, vec![vec![W, R, W], vec![W, R, W], vec![F, F, W]], vec![]);
    run.run_to(3);
    assert_eq!(run.locations(), &[0, 2, 4]);
    assert_eq!(run.record().errors, vec![crate::record::grid::ActionError { kind: "vertex conflict", agent: 1, other: 0, timestep: 3 }]);
}

#[test]
fn a_move_into_an_obstacle_or_off_the_map_makes_every_robot_wait() {
    // Robot 0 at (0,1) turns south into the obstacle at (1,1); robot 1 at (0,3) goes east off.
    let p = problem(ROW, &[1, 3], &[&[0]], Version::Y2023, 1.0);
    let mut run = scripted(p, vec![vec![R, W], vec![F, W], vec![W, F], vec![C, W]], vec![]);
    run.run_to(4);
    assert_eq!(run.locations(), &[1, 3]);
    assert_eq!(run.headings(), &[0, 0]);
    let kinds: Vec<_> = run.record().errors.iter().map(|e| (e.kind, e.agent, e.timestep)).collect();
    assert_eq!(kinds, vec![("unallowed move", 0, 2), ("unallowed move", 1, 3)]);
    assert_eq!(letters(&run, true), vec!["RWWC", "WWWW"]);
}

#[test]
fn round_robin_errands_follow_the_rule() {
    // Two robots, three task lines: robot k's j-th errand is line (j*2 + k) mod 3.
    let p = problem(ROW, &[0, 4], &[&[1], &[0], &[2]], Version::Y2023, 1.0);
    // Robot 0 goes east to 1 (line 0, done), then to 2 (line 2, done); robot 1 stays.
    let mut run = scripted(p, vec![vec![F, W], vec![F, W], vec![W, W]], vec![]);
    run.run_to(3);
    let Tasks::RoundRobin(rr) = run.tasks() else { panic!("2023 rules") };
    assert_eq!(rr.finished, 2);
    assert_eq!(rr.events[0], vec![(0, 0, false), (0, 1, true), (2, 1, false), (2, 2, true), (3, 2, false)]);
    assert_eq!(rr.all.iter().map(|e| e.cell).collect::<Vec<_>>(), vec![1, 0, 2, 0], "lines 0, 1, 2, 1 mod 3");
}

#[test]
fn schedules_that_break_the_rules_are_refused_and_the_last_valid_one_kept() {
    // Pool of int(1.5 * 2) = 3 tasks: 0 = [1, 3], 1 = [5], 2 = [6]; robot 0 at 0, robot 1 at 4.
    let p = problem(ROW, &[0, 4], &[&[1, 3], &[5], &[6]], Version::Y2024, 1.5);
    let schedules = vec![
        vec![0, -1], // step 0: robot 0 takes task 0 (valid)
        vec![0, 7],  // task 7 is not in the pool
        vec![1, 1],  // robot 0 leaves opened task 0 (it reached errand 1 at step 1), and task 1 twice
        vec![0, 1],  // valid
        vec![0, 0],  // one task for two robots
    ];
    let mut run = scripted(p, vec![vec![F, W], vec![W, W], vec![W, W], vec![F, W], vec![F, W]], schedules);
    run.run_to(5);
    let Tasks::Pool(pool) = run.tasks() else { panic!("2024 rules") };
    let errors: Vec<_> = pool.errors.iter().map(|e| (e.kind, e.task, e.agent, e.timestep)).collect();
    assert_eq!(
        errors,
        vec![
            ("task already finished", 7, 1, 3),
            ("task is already opened by the second agent", 1, 0, 4),
            ("task is already assigned by the second agent at the same time", 0, 1, 6),
        ]
    );
    // Robot 0 reached 1 (step 1), then 2 and 3 (steps 4, 5): task 0 done at step 5.
    assert_eq!(pool.finished, 1);
    // A finished task frees its robot, but `actualSchedule` only records what a schedule set.
    assert_eq!(pool.actual_schedule[0], vec![(1, 0)]);
    assert_eq!(pool.current[0], -1);
    assert_eq!(pool.actual_schedule[1], vec![(1, -1), (4, 1)]);
    assert_eq!(pool.events, vec![(1, 0, 0, 1), (5, 0, 0, 2)]);
    assert_eq!(pool.tasks.len(), 4, "a task revealed when task 0 finished");
}

fn pibt_run(seed: u64) -> LorrRun {
    let map = "type octile\nheight 6\nwidth 8\nmap\n........\n.@@..@@.\n........\n.@@..@@.\n........\n........\n";
    let p = problem(map, &[0, 7, 16, 23, 32, 39, 41, 46], &[&[7, 40], &[0], &[47, 2], &[20], &[44, 3], &[5], &[33], &[8, 15]], Version::Y2024, 1.5);
    let options = LorrOptions { planner: "pibt".into(), seed, ..LorrOptions::default() };
    let mut run = LorrRun::new(p, options).unwrap();
    run.run_to(300);
    run
}

#[test]
fn pibt_runs_are_the_same_for_a_seed_and_valid() {
    let (a, b) = (pibt_run(3), pibt_run(3));
    assert_eq!(letters(&a, true), letters(&b, true));
    assert_eq!(a.finished(), b.finished());
    assert!(a.finished() > 20, "finished {}", a.finished());
    assert!(a.record().errors.is_empty());
    let Tasks::Pool(pool) = a.tasks() else { panic!("2024 rules") };
    assert!(pool.errors.is_empty());
    let c = pibt_run(4);
    assert_ne!(letters(&a, true), letters(&c, true), "the seed matters");
}

/// Robots crossing a field of shelves (two-cell blocks, aisles between) back and forth, on
/// the 2024 rules, under planner `planner`; the run after 400 steps.
fn shelves_run(planner: &str) -> LorrRun {
    let mut rows = vec![".".repeat(24)];
    for _ in 0..4 {
        rows.push("..@@..@@..@@..@@..@@....".into());
        rows.push("..@@..@@..@@..@@..@@....".into());
        rows.push(".".repeat(24));
    }
    let map = format!("type octile\nheight {}\nwidth 24\nmap\n{}\n", rows.len(), rows.join("\n"));
    let cols = 24u32;
    let starts: Vec<u32> = (0..24).map(|k| (k % 5) * 3 * cols + (k * 7) % 24).collect();
    let tasks: Vec<Vec<u32>> = (0..200u32).map(|k| vec![((k * 37) % 5) * 3 * cols + (k * 11) % 24]).collect();
    let tasks: Vec<&[u32]> = tasks.iter().map(Vec::as_slice).collect();
    let p = problem(&map, &starts, &tasks, Version::Y2024, 1.5);
    let options = LorrOptions { planner: planner.into(), ..LorrOptions::default() };
    let mut run = LorrRun::new(p, options).unwrap();
    run.run_to(400);
    run
}

#[test]
fn on_highways_robots_mostly_move_with_the_lane_and_every_run_is_valid() {
    let along_share = |run: &LorrRun| {
        let r = run.record();
        let n = run.problem().team_size();
        let costs = super::planner::highway_costs(&run.problem().map);
        let map = &run.problem().map;
        let (mut loc, mut heading) = (run.problem().starts.clone(), vec![0u8; n]);
        let (mut along, mut moves) = (0u32, 0u32);
        for t in 0..r.steps() {
            for k in 0..n {
                match r.actual[t * n + k] {
                    0 => {
                        moves += 1;
                        along += u32::from(costs[loc[k] as usize][heading[k] as usize] == super::planner::WITH);
                        loc[k] = super::action::ahead(map, loc[k], heading[k]).unwrap();
                    }
                    1 => heading[k] = (heading[k] + 1) % 4,
                    2 => heading[k] = (heading[k] + 3) % 4,
                    _ => {}
                }
            }
        }
        f64::from(along) / f64::from(moves.max(1))
    };
    let (lanes, open) = (shelves_run("pibt"), shelves_run("pibt-no-highways"));
    for run in [&lanes, &open] {
        assert!(run.record().errors.is_empty());
        assert!(run.finished() > 30, "{} finished {}", run.options().planner, run.finished());
    }
    let (a, b) = (along_share(&lanes), along_share(&open));
    assert!(a > 0.8 && b < 0.7, "moves along the lane: {a:.2} on highways, {b:.2} without");
}

/// The map of `pibt_run` with 8 robots (sparse) or 30 (crowded, on highways under
/// `rpibt-pp`), under `planner`; the run after 300 steps.
fn new_planner_run(planner: &str, robots: u32, seed: u64) -> LorrRun {
    let map = "type octile\nheight 6\nwidth 8\nmap\n........\n.@@..@@.\n........\n.@@..@@.\n........\n........\n";
    let free: Vec<u32> = GridMap::parse(map).unwrap().free.iter().enumerate().filter(|x| *x.1).map(|x| x.0 as u32).collect();
    let starts: Vec<u32> = free.iter().copied().step_by(free.len() / robots as usize).take(robots as usize).collect();
    let tasks: Vec<Vec<u32>> = (0..100usize).map(|k| vec![free[(k * 7) % free.len()], free[(k * 13 + 5) % free.len()]]).collect();
    let tasks: Vec<&[u32]> = tasks.iter().map(Vec::as_slice).collect();
    let p = problem(map, &starts, &tasks, Version::Y2024, 1.5);
    let options = LorrOptions { planner: planner.into(), seed, ..LorrOptions::default() };
    let mut run = LorrRun::new(p, options).unwrap();
    run.run_to(300);
    run
}

#[test]
fn turn_counting_planners_are_valid_and_the_same_for_a_seed() {
    for planner in ["rpibt", "rpibt-pp", "lookahead"] {
        for robots in [8, 30] {
            let a = new_planner_run(planner, robots, 3);
            assert!(a.record().errors.is_empty(), "{planner}, {robots} robots: {:?}", a.record().errors.first());
            assert!(a.finished() > 10, "{planner}, {robots} robots: finished {}", a.finished());
            let b = new_planner_run(planner, robots, 3);
            assert_eq!(letters(&a, true), letters(&b, true), "{planner}, {robots} robots");
        }
    }
}

#[test]
fn auto_plans_ahead_on_a_small_floor_and_lets_a_jam_make_way() {
    // 40 free cells: 8 robots are 0.2 of them, 37 are 0.925.
    for (robots, chosen) in [(8, "rpibt-pp"), (37, "pibt-no-lanes")] {
        let auto = new_planner_run("auto", robots, 3);
        let named = new_planner_run(chosen, robots, 3);
        assert_eq!(auto.planner(), chosen, "{robots} robots");
        assert_eq!(named.planner(), chosen);
        assert!(auto.record().errors.is_empty());
        assert_eq!((auto.finished(), &auto.record().actual), (named.finished(), &named.record().actual), "{robots} robots: auto is {chosen}");
    }
    // The boundaries: 35 robots are under 90 % of the 40 free cells, 36 are 90 %; on a map of
    // over 2,000 free cells, 750 robots are 30 % of 2,500, 751 are more.
    let map = GridMap::parse("type octile\nheight 6\nwidth 8\nmap\n........\n.@@..@@.\n........\n.@@..@@.\n........\n........\n").unwrap();
    assert_eq!(super::planner::auto_choice(&map, 35), "rpibt-pp");
    assert_eq!(super::planner::auto_choice(&map, 36), "pibt-no-lanes");
    let large = GridMap { rows: 50, cols: 50, free: vec![true; 2500] };
    assert_eq!(super::planner::auto_choice(&large, 750), "pibt-one-way");
    assert_eq!(super::planner::auto_choice(&large, 751), "pibt");
}

#[test]
fn obstacles_in_blocks_are_told_from_scattered_ones_in_any_orientation() {
    // Shelves of 2×3 cells against single cells on a diagonal; each map and its transpose.
    let shelves = "type octile\nheight 5\nwidth 7\nmap\n.......\n.@@.@@.\n.@@.@@.\n.@@.@@.\n.......\n";
    let scattered = "type octile\nheight 5\nwidth 7\nmap\n@......\n..@....\n....@..\n......@\n.@.....\n";
    for (text, blocks) in [(shelves, true), (scattered, false)] {
        let map = GridMap::parse(text).unwrap();
        let (rows, cols) = (map.rows as usize, map.cols as usize);
        let free = (0..rows * cols).map(|i| map.free[(i % rows) * cols + i / rows]).collect();
        let transposed = GridMap { rows: map.cols, cols: map.rows, free };
        assert_eq!(super::planner::obstacles_in_blocks(&map), blocks);
        assert_eq!(super::planner::obstacles_in_blocks(&transposed), blocks);
    }
}

#[test]
fn reassign_takes_back_only_unopened_tasks_and_is_never_refused() {
    let map = "type octile\nheight 6\nwidth 8\nmap\n........\n.@@..@@.\n........\n.@@..@@.\n........\n........\n";
    let free: Vec<u32> = GridMap::parse(map).unwrap().free.iter().enumerate().filter(|x| *x.1).map(|x| x.0 as u32).collect();
    for (robots, seed) in [(6usize, 1u64), (20, 2), (30, 3)] {
        let starts: Vec<u32> = free.iter().copied().step_by(free.len() / robots).take(robots).collect();
        let tasks: Vec<Vec<u32>> = (0..100usize).map(|k| vec![free[(k * 7 + seed as usize) % free.len()], free[(k * 13 + 5) % free.len()]]).collect();
        let tasks: Vec<&[u32]> = tasks.iter().map(Vec::as_slice).collect();
        let run = |scheduler: &str| {
            let p = problem(map, &starts, &tasks, Version::Y2024, 1.5);
            let options = LorrOptions { planner: "pibt".into(), scheduler: scheduler.into(), seed, ..LorrOptions::default() };
            let mut run = LorrRun::new(p, options).unwrap();
            run.run_to(300);
            run
        };
        let a = run("reassign");
        let Tasks::Pool(pool) = a.tasks() else { panic!("2024 rules") };
        assert!(pool.errors.is_empty(), "{robots} robots: {:?}", pool.errors.first());
        assert!(a.record().errors.is_empty());
        assert!(a.finished() > 20, "{robots} robots: finished {}", a.finished());
        // Some task changed hands before it was opened: it is in two robots' schedules.
        let mut holders: std::collections::HashMap<i64, std::collections::BTreeSet<usize>> = std::collections::HashMap::new();
        for (k, s) in pool.actual_schedule.iter().enumerate() {
            for &(_, id) in s.iter().filter(|x| x.1 >= 0) {
                holders.entry(id).or_default().insert(k);
            }
        }
        assert!(holders.values().any(|h| h.len() > 1), "{robots} robots: no task changed hands");
        // Every opening is by the robot then holding the task, and a task is finished by the
        // robot that opened it.
        let mut opener = std::collections::HashMap::new();
        for &(_, k, id, done) in &pool.events {
            if done == 1 {
                opener.insert(id, k);
            } else {
                assert_eq!(opener.get(&id), Some(&k), "task {id} finished by robot {k}, not its opener");
            }
        }
        assert_eq!(letters(&a, true), letters(&run("reassign"), true), "the same for a seed");
    }
}
