//! PIBT's unit tests: small maps where the rule at stake decides.

use super::*;
use crate::input::lorr::GridMap;
use crate::rules::grid::planner::highway_costs;

fn plan(map: &str, loc: &[u32], heading: &[u8], goals: &[u32]) -> Vec<Action> {
    plan_with(map, loc, heading, goals, true)
}

fn plan_with(map: &str, loc: &[u32], heading: &[u8], goals: &[u32], lanes: bool) -> Vec<Action> {
    let map = GridMap::parse(map).unwrap();
    let mut p = Pibt::build(&map, loc.len(), 7, false, lanes, false);
    let mut actions = vec![Action::W; loc.len()];
    p.plan(&PlanView { map: &map, loc, heading, goals, t: 0, tasks: None }, &mut actions);
    actions
}

#[test]
fn a_robot_without_goal_is_pushed_ahead() {
    let map = "type octile\nheight 1\nwidth 4\nmap\n....\n";
    assert_eq!(plan(map, &[0, 1], &[0, 0], &[3, NO_GOAL]), vec![Action::F, Action::F]);
}

#[test]
fn of_two_equally_short_moves_a_robot_takes_the_emptier_lane() {
    let map = "type octile\nheight 6\nwidth 6\nmap\n......\n......\n......\n......\n......\n......\n";
    // Robot 0 at the corner, facing east, bound for (3, 3): east and south are as short.
    // East, robots stand on the lane (on their own errands); it turns south (clockwise)
    // rather than go ahead.
    let a = plan(map, &[0, 2, 3, 4], &[0, 0, 0, 0], &[21, 2, 3, 4]);
    assert_eq!(a, vec![Action::R, Action::W, Action::W, Action::W]);
    // With the lane empty, it goes straight ahead.
    let a = plan(map, &[0, 32, 33, 34], &[0, 0, 0, 0], &[21, 32, 33, 34]);
    assert_eq!(a[0], Action::F);
    // Without the lane count (`pibt-no-lanes`) it goes straight ahead, robots or not.
    let a = plan_with(map, &[0, 2, 3, 4], &[0, 0, 0, 0], &[21, 2, 3, 4], false);
    assert_eq!(a, vec![Action::F, Action::W, Action::W, Action::W]);
}

#[test]
fn a_pushed_robot_does_not_step_into_an_aisle_against_its_lane() {
    // Column 1 is an aisle three cells long whose lane runs south (highways). Robot 1,
    // without an errand, stands at its foot facing north, in the way of robot 0.
    let text = "type octile\nheight 5\nwidth 3\nmap\n...\n@.@\n@.@\n@.@\n..@\n";
    let map = GridMap::parse(text).unwrap();
    let (loc, heading, goals) = ([12, 13], [0, 3], [13, NO_GOAL]);
    let mut actions = vec![Action::W; 2];
    let mut p = Pibt::new(&map, 2, 7, Variant::Highways);
    p.plan(&PlanView { map: &map, loc: &loc, heading: &heading, goals: &goals, t: 0, tasks: None }, &mut actions);
    assert_eq!(actions, vec![Action::W, Action::W], "it waits rather than go up the aisle the wrong way");
    // Without highways there is no wrong way: it makes room.
    assert_eq!(plan(text, &loc, &heading, &goals), vec![Action::F, Action::F]);
}

#[test]
fn one_way_never_steps_against_a_lane_the_lanes_can_go_round() {
    // An open 5×8 block. Row 0 runs east; robot 0 at (0, 3) faces west, bound for
    // (0, 2) next to it. `pibt-no-lanes` steps back against the lane (it is nearer);
    // `pibt-one-way` goes round along the lanes and gets there without such a step.
    let text = "type octile\nheight 5\nwidth 8\nmap\n........\n........\n........\n........\n........\n";
    let map = GridMap::parse(text).unwrap();
    let (loc, heading, goals) = ([3u32], [2u8], [2u32]);
    let view = PlanView { map: &map, loc: &loc, heading: &heading, goals: &goals, t: 0, tasks: None };
    let mut actions = vec![Action::W];
    Pibt::new(&map, 1, 7, Variant::StraightTies).plan(&view, &mut actions);
    assert_eq!(actions, vec![Action::F], "pibt-no-lanes steps against the lane");
    let mut one_way = Pibt::new(&map, 1, 7, Variant::OneWay);
    let costs = highway_costs(&map);
    let (mut at, mut facing) = (3u32, 2u8);
    for t in 0..40 {
        if at == 2 {
            return;
        }
        let (loc, heading) = ([at], [facing]);
        one_way.plan(&PlanView { map: &map, loc: &loc, heading: &heading, goals: &goals, t, tasks: None }, &mut actions);
        match actions[0] {
            Action::F => {
                assert_ne!(costs[at as usize][facing as usize], crate::rules::grid::planner::AGAINST, "step {t}: against the lane");
                at = ahead(&map, at, facing).expect("on the map");
            }
            Action::R => facing = (facing + 1) % 4,
            Action::C => facing = (facing + 3) % 4,
            other => panic!("step {t}: a lone robot does {other:?}"),
        }
    }
    panic!("not there in 40 steps");
}

#[test]
fn a_pushed_robot_that_must_turn_holds_up_the_pusher() {
    let map = "type octile\nheight 2\nwidth 3\nmap\n...\n@@.\n";
    // Robot 1 leaves 2 southwards (to 5) but faces east: it turns, and robot 0, which
    // would enter 2, waits.
    let a = plan(map, &[1, 2], &[0, 0], &[2, 5]);
    assert_eq!(a, vec![Action::W, Action::R]);
}
