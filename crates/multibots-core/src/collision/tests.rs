//! The collision phase against its definition: random fleets, kept state against fresh,
//! and which path decides each case.

use super::*;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

const ANGLE: f64 = PI / 6.0;

fn deg(d: f64) -> f64 {
    d.to_radians()
}

#[test]
fn angle_boundary_just_under_and_just_over_30_degrees() {
    // j at distance 20, bearing 0; i heading 29.9° or 30.1° away from it.
    assert!(blocks(0.0, 0.0, deg(29.9), 20.0, 0.0, 25.0, ANGLE));
    assert!(!blocks(0.0, 0.0, deg(30.1), 20.0, 0.0, 25.0, ANGLE));
    assert!(blocks(0.0, 0.0, deg(-29.9), 20.0, 0.0, 25.0, ANGLE));
    assert!(!blocks(0.0, 0.0, deg(-30.1), 20.0, 0.0, 25.0, ANGLE));
    // Exactly 30° is not "< 30°". A bearing of 30° exactly: j at (cos 30, sin 30)*20.
    assert!(!blocks(0.0, 0.0, 0.0, 20.0 * deg(30.0).cos(), 20.0 * deg(30.0).sin(), 25.0, deg(30.0) - 1e-15));
}

#[test]
fn distance_exactly_the_sum_of_radii_blocks_and_a_hair_more_does_not() {
    assert!(blocks(0.0, 0.0, 0.0, 25.0, 0.0, 12.5 + 12.5, ANGLE));
    assert!(!blocks(0.0, 0.0, 0.0, 25.0 + 1e-9, 0.0, 12.5 + 12.5, ANGLE));
    // 3-4-5: distance exactly 25 off the axis, bearing 36.87°: outside 30°, inside 40°.
    assert!(!blocks(0.0, 0.0, 0.0, 20.0, 15.0, 25.0, ANGLE));
    assert!(blocks(0.0, 0.0, 0.0, 20.0, 15.0, 25.0, deg(40.0)));
    // The margin widens the contact distance.
    assert!(blocks(0.0, 0.0, 0.0, 33.0, 0.0, 25.0 + 8.0, ANGLE));
    assert!(!blocks(0.0, 0.0, 0.0, 33.5, 0.0, 25.0 + 8.0, ANGLE));
}

#[test]
fn shortcuts_agree_with_the_library_bit_for_bit() {
    // Magnitudes from 1e-160 to 1e160 (past the range where the shortcuts apply), both
    // signs, with zeros of both signs in the other coordinate.
    let mut v = 1e-160_f64;
    while v < 1e160 {
        for a in [v, -v, v * 1.000_000_1, -v * 0.999_999_9] {
            for z in [0.0, -0.0] {
                for (dx, dy) in [(a, z), (z, a)] {
                    assert_eq!(crate::fleet::motion::axis_dist(dx, dy).to_bits(), (dx * dx + dy * dy).sqrt().to_bits(), "dist {dx} {dy}");
                    assert_eq!(bearing(dx, dy).to_bits(), dy.atan2(dx).to_bits(), "bearing {dx} {dy}");
                }
            }
        }
        v *= 7.3;
    }
    // The folded angle skips `fmod` only below a full turn, where `fmod` is the identity.
    for (a, b) in [(0.0, PI), (-PI, PI), (PI, -PI), (3.0, -3.2), (TAU, 0.0), (7.0, -0.5), (-20.0, 1.0)] {
        let d: f64 = (a - b).abs() % TAU;
        let expect = if d > PI { TAU - d } else { d };
        assert_eq!(folded_angle(a, b).to_bits(), expect.to_bits(), "{a} {b}");
    }
}

#[test]
fn a_nan_margin_or_radius_blocks_as_the_definition_says_in_a_tiny_fleet() {
    // Scenarios refuse them, but the public API takes them: the pass over pairs must
    // not drop a pair that the test itself would accept.
    for (radius, margin) in [([12.5, 12.5], f64::NAN), ([12.5, f64::NAN], 0.0)] {
        let mut c = Collisions::new([-100.0, -100.0, 900.0, 700.0], 25.0, 2);
        c.resolve(&[0.0, 100.0], &[0.0, 0.0], &radius, &[true, false], &[0.0, 0.0], &[], margin, ANGLE);
        let expect = blocks(0.0, 0.0, 0.0, 100.0, 0.0, radius[0] + radius[1] + margin, ANGLE);
        assert!(expect, "the definition lets a NaN contact distance block");
        assert_eq!(c.waits, vec![expect, false], "radius {radius:?}, margin {margin}");
    }
}

#[test]
fn distance_zero_always_blocks() {
    assert!(blocks(5.0, 5.0, deg(135.0), 5.0, 5.0, 25.0, ANGLE));
}

#[test]
fn angles_fold_across_the_seam() {
    // 359° and 1° are 2° apart, not 358°.
    assert!((folded_angle(deg(359.0), deg(1.0)) - deg(2.0)).abs() < 1e-12);
    assert!((folded_angle(deg(-179.0), deg(179.0)) - deg(2.0)).abs() < 1e-12);
    assert!((folded_angle(deg(10.0), deg(190.0)) - PI).abs() < 1e-12);
    // Heading just below +180°, j just past -180° (the same direction, west).
    assert!(blocks(0.0, 0.0, deg(179.0), -20.0, -0.5, 25.0, ANGLE));
}

fn run(x: &[f64], y: &[f64], wants: &[bool], alpha: &[f64]) -> Vec<bool> {
    let mut c = Collisions::new([-100.0, -100.0, 900.0, 700.0], 25.0, x.len());
    c.resolve(x, y, &vec![12.5; x.len()], wants, alpha, &[], 0.0, ANGLE);
    c.waits.clone()
}

#[test]
fn head_on_pair_releases_the_smaller_id() {
    // 0 heads east towards 1, 1 heads west towards 0.
    assert_eq!(run(&[100.0, 120.0], &[50.0, 50.0], &[true, true], &[0.0, PI]), vec![false, true]);
    assert_eq!(run(&[120.0, 100.0], &[50.0, 50.0], &[true, true], &[PI, 0.0]), vec![false, true]);
}

#[test]
fn release_is_a_single_pass() {
    // 0 and 1 block each other and 0 is released; 2 is blocked only by 0 (the released
    // one) and still waits; 3 is blocked by 2, which waits, so 3 waits too.
    let x = [120.0, 100.0, 140.0, 160.0];
    let y = [50.0; 4];
    let alpha = [PI, 0.0, PI, PI];
    assert_eq!(run(&x, &y, &[true; 4], &alpha), vec![false, true, true, true]);
}

#[test]
fn three_cycle_releases_its_smallest_id_only() {
    // Three robots around a point, each heading at the next: 2 -> 0 -> 1 -> 2.
    let x: [f64; 3] = [100.0, 120.0, 110.0];
    let y: [f64; 3] = [100.0, 100.0, 100.0 + 17.32];
    let to = |i: usize, j: usize| f64::atan2(y[j] - y[i], x[j] - x[i]);
    let alpha = [to(0, 1), to(1, 2), to(2, 0)];
    assert_eq!(run(&x, &y, &[true; 3], &alpha), vec![false, true, true]);
}

#[test]
fn a_robot_that_does_not_want_to_move_blocks_but_never_waits() {
    let w = run(&[100.0, 120.0], &[50.0, 50.0], &[true, false], &[0.0, PI]);
    assert_eq!(w, vec![true, false]);
}

/// Deterministic numbers in [0, 1) (xorshift; no dependency for a test).
fn uniform(mut s: u64) -> impl FnMut() -> f64 {
    move || (crate::xorshift(&mut s) % 10_000) as f64 / 10_000.0
}

#[test]
fn one_collisions_kept_from_step_to_step_decides_as_a_fresh_one() {
    // The release keeps its marks (`blocked_bits`) only for the step: a kept `Collisions`
    // must decide each step as a new one would, whichever robots were blocked before.
    // Dense clouds with random headings give cycles of every size.
    let mut rnd = uniform(99);
    // Tiny, dense and sparse grids (a few robots in a big box), one radius and mixed.
    for (n, side, mixed) in [(5, 200.0, false), (40, 200.0, false), (300, 200.0, true), (40, 2000.0, false), (60, 2000.0, true)] {
        let bounds = [0.0, 0.0, side, side];
        let mut kept = Collisions::new(bounds, 28.0, n);
        let mut released = 0;
        for step in 0..30 {
            // Every other step crowded into a corner: cycles; else spread out.
            let span = if step % 2 == 0 { 60.0 } else { side };
            let x: Vec<f64> = (0..n).map(|_| rnd() * span).collect();
            let y: Vec<f64> = (0..n).map(|_| rnd() * span).collect();
            let alpha: Vec<f64> = (0..n).map(|_| rnd() * TAU - PI).collect();
            let wants: Vec<bool> = (0..n).map(|_| rnd() < 0.8).collect();
            let radius: Vec<f64> = (0..n).map(|_| if mixed { 8.0 + 6.0 * rnd() } else { 12.5 }).collect();
            kept.resolve(&x, &y, &radius, &wants, &alpha, &[], 0.0, ANGLE);
            let mut fresh = Collisions::new(bounds, 28.0, n);
            fresh.resolve(&x, &y, &radius, &wants, &alpha, &[], 0.0, ANGLE);
            assert_eq!(kept.waits, fresh.waits, "{n} robots in {side} px, step {step}");
            released += kept.graph.released.len();
        }
        assert!(n < 40 || released > 0, "{n} robots in {side} px: some cycle was released");
    }
}

#[test]
fn a_tiny_fleet_that_skips_the_pass_over_pairs_decides_and_counts_as_a_fresh_one() {
    // Robots walk a few px a step towards random points on a small floor: mostly far
    // apart (a kept `Collisions` then skips the pass over pairs, see `grid::Apart`), now
    // and then near (blocked, touching), some stepping in and out of bays. The kept one
    // must decide and count contacts every step as a fresh one, which never skips.
    let mut rnd = uniform(2024);
    let speed = 4.0;
    let (mut skipped, mut waited, mut touched, mut steps) = (0, 0, 0, 0);
    for (n, side) in [(2, 150.0), (3, 250.0), (6, 400.0), (12, 600.0), (32, 1000.0)] {
        let bounds = [0.0, 0.0, side, side];
        let mut kept = Collisions::new(bounds, 28.0, n);
        let mut x: Vec<f64> = (0..n).map(|_| (rnd() * side).round()).collect();
        let mut y: Vec<f64> = (0..n).map(|_| (rnd() * side).round()).collect();
        let mut goal: Vec<(f64, f64)> = (0..n).map(|_| (rnd() * side, rnd() * side)).collect();
        let radius = vec![12.5; n];
        let mut bay: Vec<bool> = Vec::new();
        for step in 0..2000 {
            // Along one axis at a time, as on aisles (exact positions), else straight
            // (diagonals too: a proof that measured moves by their longer axis would fail).
            let axis = step % 400 < 200;
            let mut alpha = vec![0.0; n];
            for i in 0..n {
                let (dx, dy) = (goal[i].0 - x[i], goal[i].1 - y[i]);
                if dx.abs() + dy.abs() < speed {
                    goal[i] = ((rnd() * side).round(), (rnd() * side).round());
                }
                alpha[i] = if !axis {
                    dy.atan2(dx)
                } else if dx.abs() >= speed {
                    if dx > 0.0 {
                        0.0
                    } else {
                        PI
                    }
                } else if dy > 0.0 {
                    FRAC_PI_2
                } else {
                    -FRAC_PI_2
                };
            }
            let wants: Vec<bool> = (0..n).map(|_| rnd() < 0.9).collect();
            if step % 150 == 0 {
                // Robot 0 steps into a bay or out of it: a new set of robots in the grid.
                bay = (0..n).map(|i| i == 0 && step % 300 == 0).collect();
            }
            let anchor = kept.space.apart.x.clone();
            // A twin of the kept state without its proof makes the pass: everything the
            // pass leaves must come out the same, not only the decisions.
            let mut twin = kept.clone();
            twin.space.apart = grid::Apart::default();
            kept.resolve(&x, &y, &radius, &wants, &alpha, &bay, 0.0, ANGLE);
            twin.resolve(&x, &y, &radius, &wants, &alpha, &bay, 0.0, ANGLE);
            assert_eq!(
                (&kept.space.bits, kept.space.cover.to_bits(), kept.space.clear),
                (&twin.space.bits, twin.space.cover.to_bits(), twin.space.clear),
                "{n} robots, step {step}"
            );
            let mut fresh = Collisions::new(bounds, 28.0, n);
            fresh.resolve(&x, &y, &radius, &wants, &alpha, &bay, 0.0, ANGLE);
            assert_eq!(kept.waits, fresh.waits, "{n} robots, step {step}");
            assert_eq!(kept.waits, twin.waits, "{n} robots, step {step}");
            skipped += usize::from(kept.space.apart.x == anchor && step > 0);
            waited += kept.waits.iter().filter(|&&w| w).count();
            steps += 1;
            // Those that may move do, by `speed` along their heading.
            let moved: Vec<bool> = (0..n).map(|i| wants[i] && !kept.waits[i]).collect();
            for i in (0..n).filter(|&i| moved[i]) {
                x[i] += speed * alpha[i].cos();
                y[i] += speed * alpha[i].sin();
                if axis {
                    (x[i], y[i]) = (x[i].round(), y[i].round());
                }
            }
            let got = kept.contacts(&x, &y, &radius, &moved, 2.0 * speed);
            let want = fresh.contacts(&x, &y, &radius, &moved, 2.0 * speed);
            assert_eq!((got.0, got.1.to_bits()), (want.0, want.1.to_bits()), "{n} robots, step {step}");
            assert_eq!(twin.contacts(&x, &y, &radius, &moved, 2.0 * speed), got, "{n} robots, step {step}");
            touched += usize::from(got.0 > 0);
        }
    }
    // The test means something: the pass was skipped in many steps, and robots met.
    assert!(skipped * 3 > steps && waited > 100 && touched > 10, "skipped {skipped} of {steps}, waited {waited}, touched {touched}");
}

/// Who waits by the definition: O(N²) rows, components by reachability.
fn brute(x: &[f64], y: &[f64], radius: &[f64], wants: &[bool], alpha: &[f64], margin: f64) -> Vec<bool> {
    let n = x.len();
    let edge = |i: usize, j: usize| i != j && wants[i] && blocks(x[i], y[i], alpha[i], x[j], y[j], radius[i] + radius[j] + margin, ANGLE);
    let mut reach: Vec<Vec<bool>> = (0..n).map(|i| (0..n).map(|j| edge(i, j)).collect()).collect();
    for k in 0..n {
        let via = reach[k].clone();
        for row in &mut reach {
            if row[k] {
                for (c, &v) in row.iter_mut().zip(&via) {
                    *c |= v;
                }
            }
        }
    }
    (0..n)
        .map(|i| {
            let cycle = |j: usize| j != i && reach[i][j] && reach[j][i];
            (0..n).any(|j| edge(i, j)) && (!(0..n).any(cycle) || (0..i).any(cycle))
        })
        .collect()
}

#[test]
fn odd_inputs_of_the_public_api_decide_as_the_definition() {
    // A robot at a NaN coordinate, a contact distance wider than the grid's reach, a NaN
    // margin, a pile of robots on one spot: each as the definition decides, step after step
    // of one kept `Collisions`.
    let n = 120;
    let mut rnd = uniform(7);
    let x: Vec<f64> = (0..n).map(|_| (rnd() * 400.0).round()).collect();
    let y: Vec<f64> = (0..n).map(|_| (rnd() * 8.0).floor() * 50.0).collect();
    let (wants, radius) = (vec![true; n], vec![12.5; n]);
    let alpha: Vec<f64> = (0..n).map(|i| [0.0, PI, FRAC_PI_2, 1.0][i % 4]).collect();
    let mut nan_y = y.clone();
    nan_y[17] = f64::NAN;
    let (mut px, mut py) = (x.clone(), y.clone());
    for i in 0..80 {
        (px[i], py[i]) = (200.0, 200.0);
    }
    let mut c = Collisions::new([-50.0, -50.0, 450.0, 450.0], 25.0, n);
    for (x, y, margin) in [(&x, &y, 0.0), (&x, &nan_y, 0.0), (&x, &y, 30.0), (&x, &y, 0.0), (&px, &py, 0.0), (&x, &y, 0.0)] {
        c.resolve(x, y, &radius, &wants, &alpha, &[], margin, ANGLE);
        assert_eq!(c.waits, brute(x, y, &radius, &wants, &alpha, margin), "margin {margin}");
    }
    // A NaN margin: every pair whose angle fits blocks, however far apart.
    let few = 40;
    c = Collisions::new([-50.0, -50.0, 450.0, 450.0], 25.0, few);
    c.resolve(&x[..few], &y[..few], &radius[..few], &wants[..few], &alpha[..few], &[], f64::NAN, ANGLE);
    assert_eq!(c.waits, brute(&x[..few], &y[..few], &radius[..few], &wants[..few], &alpha[..few], f64::NAN));
}

/// Headings of the crowded floors: the four axes and one diagonal.
const HEADINGS: [f64; 5] = [0.0, PI, FRAC_PI_2, -FRAC_PI_2, 0.7];

/// `n` robots on a crowded floor `side` wide, on rows 50 px apart: positions, headings, and
/// who wants to move (nine in ten).
fn crowded(rnd: &mut impl FnMut() -> f64, n: usize, side: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<bool>) {
    let x = (0..n).map(|_| (rnd() * side).round()).collect();
    let y = (0..n).map(|_| (rnd() * side / 50.0).floor() * 50.0).collect();
    let alpha = (0..n).map(|_| HEADINGS[(rnd() * 5.0) as usize]).collect();
    let wants = (0..n).map(|_| rnd() < 0.9).collect();
    (x, y, alpha, wants)
}

#[test]
fn a_kept_graph_finds_again_only_what_changed_and_decides_as_a_fresh_one() {
    // Many steps of a crowded floor in which a few robots move, turn or stop wanting to move
    // (the kept rows are read again), and now and then most do (the pass over pairs), some
    // stepping into bays and out: the kept `Collisions` must decide as a fresh one.
    let mut rnd = uniform(31);
    let (mut released, mut swept, mut followed) = (0, 0, 0);
    for n in [33, 200, 800] {
        let side = (n as f64 * 3.0).sqrt() * 50.0;
        let bounds = [0.0, 0.0, side, side];
        let mut kept = Collisions::new(bounds, 25.0, n);
        let (mut x, mut y, mut alpha, mut wants) = crowded(&mut rnd, n, side);
        let radius = vec![12.5; n];
        let mut bay = vec![false; n];
        for step in 0..80 {
            let share = if step % 9 == 0 { 0.8 } else { 0.01 };
            for i in 0..n {
                if rnd() < share {
                    match (rnd() * 4.0) as usize {
                        0 => alpha[i] = HEADINGS[(rnd() * 5.0) as usize],
                        1 => wants[i] = !wants[i],
                        2 => bay[i] = !bay[i],
                        _ => x[i] = (x[i] + 4.0 * alpha[i].cos()).clamp(0.0, side),
                    }
                }
            }
            // Rewritten whole (after many moves) or followed robot by robot.
            if kept.index.sweeping {
                swept += 1;
            } else {
                followed += 1;
            }
            kept.resolve(&x, &y, &radius, &wants, &alpha, &bay, 0.0, ANGLE);
            let mut fresh = Collisions::new(bounds, 25.0, n);
            fresh.resolve(&x, &y, &radius, &wants, &alpha, &bay, 0.0, ANGLE);
            assert_eq!(kept.waits, fresh.waits, "{n} robots, step {step}");
            assert_eq!((&kept.graph.start, &kept.graph.blocked), (&fresh.graph.start, &fresh.graph.blocked), "{n} robots, step {step}");
            released += kept.graph.released.len();
            // Those that may move do, in runs of ten steps, then all stand for ten: the index
            // goes from rewriting every slot to following robot by robot, and back.
            for i in (0..n).filter(|_| (step / 10) % 2 == 0) {
                if wants[i] && !kept.waits[i] && !bay[i] && rnd() < 0.5 {
                    x[i] = (x[i] + 4.0 * alpha[i].cos()).clamp(0.0, side);
                    y[i] = (y[i] + 4.0 * alpha[i].sin()).clamp(0.0, side);
                }
            }
        }
    }
    assert!(released > 0, "some cycle was released");
    assert!(swept > 30 && followed > 30, "rewritten {swept} times, followed {followed}");
}

#[test]
fn grid_finds_neighbours_across_cell_borders_and_agrees_with_brute_force() {
    // Pseudo-random cloud, compared with the O(N²) definition.
    let mut rnd = uniform(12345);
    let n = 400;
    let x: Vec<f64> = (0..n).map(|_| rnd() * 300.0).collect();
    let y: Vec<f64> = (0..n).map(|_| rnd() * 300.0).collect();
    let alpha: Vec<f64> = (0..n).map(|_| rnd() * TAU - PI).collect();
    let wants: Vec<bool> = (0..n).map(|i| i % 3 != 0).collect();
    let mut c = Collisions::new([0.0, 0.0, 300.0, 300.0], 25.0, n);
    c.resolve(&x, &y, &vec![12.5; n], &wants, &alpha, &[], 0.0, ANGLE);
    for i in 0..n {
        let brute: Vec<u32> = (0..n).filter(|&j| j != i && wants[i] && blocks(x[i], y[i], alpha[i], x[j], y[j], 25.0, ANGLE)).map(|j| j as u32).collect();
        let mut got = c.graph.to[c.graph.start[i] as usize..c.graph.start[i + 1] as usize].to_vec();
        got.sort_unstable();
        assert_eq!(got, brute, "robot {i}");
    }
}

#[test]
fn lists_decide_and_count_as_a_fresh_index_does() {
    // Runs of steps in which most robots move (the lists serve, built again as robots drift
    // half a contact distance) alternate with runs in which few do (the index takes over);
    // now and then a robot steps into a bay or out, a jump sideways past the drift. Every
    // step the kept `Collisions` with lists must decide as a fresh one without them, count
    // the same contacts after the moves, and keep the same closest approach over the run
    // (the index's way looks only at the pairs of robots that moved; the lists at every
    // listed pair); its public count of the moved robots' contacts must agree too.
    let mut rnd = uniform(57);
    let (mut listed, mut indexed) = (0, 0);
    for n in [40, 300, 900] {
        let side = (n as f64 * 3.0).sqrt() * 50.0;
        let bounds = [0.0, 0.0, side, side];
        let mut kept = Collisions::new(bounds, 25.0, n);
        kept.keep_lists(bounds);
        let (mut x, mut y, mut alpha, mut wants) = crowded(&mut rnd, n, side);
        let radius = vec![12.5; n];
        let mut bay = vec![false; n];
        let (mut kept_closest, mut fresh_closest) = (f64::INFINITY, f64::INFINITY);
        let builds = kept.lists.as_ref().map_or(0, |l| l.builds);
        let mut listed_here = 0;
        for step in 0..150 {
            // Robots want to move, and those free to do so move, in runs of twenty steps;
            // in the runs between, few even want to.
            let under_way = (step / 20) % 2 == 0;
            let share = if under_way { 0.95 } else { 0.05 };
            for i in 0..n {
                if !under_way && step % 20 == 0 {
                    wants[i] = rnd() < 0.05;
                } else if under_way && step % 20 == 0 {
                    wants[i] = rnd() < 0.9;
                }
                // About one change in five steps of each kind, whatever the fleet's size.
                if rnd() < 0.6 / n as f64 {
                    match (rnd() * 3.0) as usize {
                        0 => alpha[i] = HEADINGS[(rnd() * 5.0) as usize],
                        1 => wants[i] = !wants[i],
                        _ => {
                            bay[i] = !bay[i];
                            y[i] = (y[i] + if bay[i] { 25.0 } else { -25.0 }).clamp(0.0, side);
                        }
                    }
                }
            }
            let listing = kept.listing;
            listed_here += usize::from(listing);
            kept.resolve(&x, &y, &radius, &wants, &alpha, &bay, 0.0, ANGLE);
            let mut fresh = Collisions::new(bounds, 25.0, n);
            fresh.resolve(&x, &y, &radius, &wants, &alpha, &bay, 0.0, ANGLE);
            assert_eq!(kept.waits, fresh.waits, "{n} robots, step {step}, lists {listing}");
            let mut moved = vec![false; n];
            for i in 0..n {
                if wants[i] && !kept.waits[i] && !bay[i] && rnd() < share {
                    x[i] = (x[i] + 4.0 * alpha[i].cos()).clamp(0.0, side);
                    y[i] = (y[i] + 4.0 * alpha[i].sin()).clamp(0.0, side);
                    moved[i] = true;
                }
            }
            let (got, want) = (kept.contacts(&x, &y, &radius, &moved, 8.0), fresh.contacts(&x, &y, &radius, &moved, 8.0));
            assert_eq!((got.0, got.1.to_bits()), (want.0, want.1.to_bits()), "{n} robots, step {step}: contacts of the moved");
            let got = kept.contacts_of_every_pair(&x, &y, &radius, 12.5, 8.0, 0.0);
            let want = fresh.contacts_of_every_pair(&x, &y, &radius, 12.5, 8.0, 0.0);
            (kept_closest, fresh_closest) = (kept_closest.min(got.1), fresh_closest.min(want.1));
            assert_eq!((got.0, kept_closest.to_bits()), (want.0, fresh_closest.to_bits()), "{n} robots, step {step}, lists {listing}");
        }
        let built = kept.lists.as_ref().map_or(0, |l| l.builds) - builds;
        // The lists were built again as robots drifted, and served several steps a build.
        assert!(built > 3 && built * 2 < listed_here as u64, "{n} robots: {built} builds in {listed_here} steps");
        listed += listed_here;
        indexed += 150 - listed_here;
    }
    assert!(listed > 100 && indexed > 100, "lists served {listed} steps, the index {indexed}");
}

#[test]
fn lists_answer_as_the_index_on_odd_inputs() {
    // With lists on, what the public API gives is what it gives without them: the contacts of
    // the moved robots, closest approach included, read the places before the moves (two
    // robots that closed in on each other); a robot at a NaN position (the lists stand aside
    // for the index); a margin below zero (likewise).
    let n = 40;
    let bounds = [0.0, 0.0, 2000.0, 2000.0];
    let mut x: Vec<f64> = (0..n).map(|i| 100.0 + 45.0 * i as f64).collect();
    let mut y = vec![1000.0; n];
    (x[0], y[0], x[1], y[1]) = (100.0, 100.0, 134.0, 100.0);
    let radius = vec![12.5; n];
    let wants: Vec<bool> = (0..n).map(|i| i < 2).collect();
    let alpha: Vec<f64> = (0..n).map(|i| if i == 1 { PI } else { 0.0 }).collect();
    let both = || {
        let mut kept = Collisions::new(bounds, 25.0, n);
        kept.keep_lists(bounds);
        (kept, Collisions::new(bounds, 25.0, n))
    };
    let (mut kept, mut fresh) = both();
    kept.resolve(&x, &y, &radius, &wants, &alpha, &[], 0.0, ANGLE);
    fresh.resolve(&x, &y, &radius, &wants, &alpha, &[], 0.0, ANGLE);
    let moved: Vec<bool> = (0..n).map(|i| i < 2).collect();
    (x[0], x[1]) = (104.0, 130.0);
    let (got, want) = (kept.contacts(&x, &y, &radius, &moved, 8.0), fresh.contacts(&x, &y, &radius, &moved, 8.0));
    assert_eq!((got.0, got.1.to_bits()), (want.0, want.1.to_bits()), "contacts of the moved");
    // A robot at a NaN height, another at its column heading towards it.
    let (mut x, mut y): (Vec<f64>, Vec<f64>) = ((0..n).map(|i| 20.0 * i as f64).collect(), vec![600.0; n]);
    (x[5], y[5], x[6]) = (300.0, f64::NAN, 300.0);
    let (wants, alpha) = (vec![true; n], vec![FRAC_PI_2; n]);
    for y6 in [40.0, 50.2, 60.0, 500.0] {
        y[6] = y6;
        let (mut kept, mut fresh) = both();
        kept.resolve(&x, &y, &radius, &wants, &alpha, &[], 0.0, ANGLE);
        fresh.resolve(&x, &y, &radius, &wants, &alpha, &[], 0.0, ANGLE);
        assert_eq!(kept.waits, fresh.waits, "a NaN neighbour, y {y6}");
    }
    // Robots 20 px apart in a row, a margin of -15 px.
    let (x, y): (Vec<f64>, Vec<f64>) = ((0..n).map(|i| 100.0 + 20.0 * i as f64).collect(), vec![100.0; n]);
    let (mut kept, mut fresh) = both();
    kept.build_grid(&x, &y, &radius, &[]);
    fresh.build_grid(&x, &y, &radius, &[]);
    let (got, want) = (kept.contacts_of_every_pair(&x, &y, &radius, 12.5, 8.0, -15.0), fresh.contacts_of_every_pair(&x, &y, &radius, 12.5, 8.0, -15.0));
    assert_eq!((got.0, got.1.to_bits()), (want.0, want.1.to_bits()), "a margin below zero");
}
