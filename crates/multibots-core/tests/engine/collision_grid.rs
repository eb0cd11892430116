//! The collision grid's search boxes (cone boxes for axis-parallel headings, 2 x 2 cells)
//! against the spec's definition computed by brute force, on crowded aisles.

use multibots_core::collision::{blocks, Collisions};
use std::f64::consts::{FRAC_PI_2, PI};

/// Phase 3 by the book: O(N²) "blocked by", strongly connected components by reachability,
/// the smallest id of each component of two or more released.
fn brute(x: &[f64], y: &[f64], radius: &[f64], margin: f64, wants: &[bool], alpha: &[f64], angle: f64) -> Vec<bool> {
    brute_with_bays(x, y, radius, margin, wants, alpha, angle, &vec![false; x.len()])
}

/// [`brute`] with robots standing in bays, which neither block nor wait.
#[allow(clippy::too_many_arguments)]
fn brute_with_bays(x: &[f64], y: &[f64], radius: &[f64], margin: f64, wants: &[bool], alpha: &[f64], angle: f64, bay: &[bool]) -> Vec<bool> {
    let n = x.len();
    let edge: Vec<Vec<bool>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| i != j && wants[i] && !bay[i] && !bay[j] && blocks(x[i], y[i], alpha[i], x[j], y[j], radius[i] + radius[j] + margin, angle))
                .collect()
        })
        .collect();
    let mut reach_of = edge.clone();
    for k in 0..n {
        let via = reach_of[k].clone();
        for row in &mut reach_of {
            if row[k] {
                for (cell, &v) in row.iter_mut().zip(&via) {
                    *cell |= v;
                }
            }
        }
    }
    (0..n)
        .map(|i| {
            let blocked = edge[i].iter().any(|&e| e);
            let in_cycle_with_smaller = (0..n).any(|j| j != i && reach_of[i][j] && reach_of[j][i] && j < i);
            let in_cycle = (0..n).any(|j| j != i && reach_of[i][j] && reach_of[j][i]);
            let released = in_cycle && !in_cycle_with_smaller;
            blocked && !released
        })
        .collect()
}

/// A small deterministic generator (xorshift; no dependency for a test).
fn xorshift(mut s: u64) -> impl FnMut() -> u64 {
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    }
}

#[test]
fn grid_agrees_with_the_definition_on_crowded_aisles() {
    crowded_aisles(|_| 12.5, 0.0);
}

#[test]
fn tiny_fleets_agree_with_the_definition_with_robots_in_bays() {
    // At most 32 robots: the pass over pairs, not the grid. Two steps each, so the second
    // one flags pairs as wide as contacts asked for.
    let mut rnd = xorshift(1_234_567);
    let headings = [0.0, -0.0, PI, -PI, FRAC_PI_2, -FRAC_PI_2, 0.3, 2.0];
    for round in 0..300 {
        let n = [1, 2, 6, 17, 32][round % 5];
        let (x, y): (Vec<f64>, Vec<f64>) = (0..n)
            .map(|_| {
                let (along, lane) = ((rnd() % 120) as f64, (rnd() % 3) as f64 * 50.0);
                if rnd() % 2 == 0 {
                    (along, lane)
                } else {
                    (lane, along)
                }
            })
            .unzip();
        let alpha: Vec<f64> = (0..n).map(|_| headings[(rnd() % headings.len() as u64) as usize]).collect();
        let wants: Vec<bool> = (0..n).map(|_| rnd() % 5 != 0).collect();
        let radius: Vec<f64> = (0..n).map(|_| if round % 2 == 0 { 12.5 } else { [8.0, 10.0, 12.5][(rnd() % 3) as usize] }).collect();
        let bay: Vec<bool> = (0..n).map(|_| round % 3 == 0 && rnd() % 4 == 0).collect();
        let margin = if round % 4 == 0 { 8.0 } else { 0.0 };
        let reach = 2.0 * radius.iter().copied().fold(0.0, f64::max) + margin;
        let mut c = Collisions::new([-50.0, -50.0, 200.0, 200.0], reach, n);
        for shift in [0.0, 1.0] {
            let x: Vec<f64> = x.iter().map(|v| v + shift).collect();
            c.resolve(&x, &y, &radius, &wants, &alpha, &bay, margin, 30f64.to_radians());
            let _ = c.contacts(&x, &y, &radius, &wants, 8.0);
            assert_eq!(c.waits, brute_with_bays(&x, &y, &radius, margin, &wants, &alpha, 30f64.to_radians(), &bay), "round {round}, shift {shift}");
        }
    }
}

#[test]
fn grid_agrees_with_the_definition_with_mixed_radii_and_a_margin() {
    crowded_aisles(|k| [8.0, 10.0, 12.5][(k % 3) as usize], 3.0);
}

/// 200 rounds of 60 robots on aisles, radii from `radius_of(random)`.
fn crowded_aisles(radius_of: impl Fn(u64) -> f64, margin: f64) {
    let mut rnd = xorshift(987_654_321);
    let headings = [0.0, -0.0, PI, -PI, FRAC_PI_2, -FRAC_PI_2, 0.3, 2.0];
    for round in 0..200 {
        let n = 60;
        // Robots on a lattice of aisles (x or y a multiple of 50), 1 px apart along them, so
        // that contact distances and cone edges are hit exactly.
        let mut x = Vec::with_capacity(n);
        let mut y = Vec::with_capacity(n);
        for _ in 0..n {
            let along = (rnd() % 300) as f64;
            let lane = (rnd() % 4) as f64 * 50.0;
            if rnd() % 2 == 0 {
                x.push(along);
                y.push(lane);
            } else {
                x.push(lane);
                y.push(along);
            }
        }
        let alpha: Vec<f64> = (0..n).map(|_| headings[(rnd() % headings.len() as u64) as usize]).collect();
        let wants: Vec<bool> = (0..n).map(|_| rnd() % 5 != 0).collect();
        let radius: Vec<f64> = (0..n).map(|_| radius_of(rnd())).collect();
        let reach = 2.0 * radius.iter().copied().fold(0.0, f64::max) + margin;
        for angle in [30f64.to_radians(), 90f64.to_radians(), 120f64.to_radians()] {
            // A grid with few cells per robot (counting sort) and one with many (the order
            // kept from step to step); two steps each, so the kept order is used.
            for far_corner in [350.0, 2000.0] {
                let mut c = Collisions::new([-50.0, -50.0, far_corner, far_corner], reach, n);
                for shift in [0.0, 1.0] {
                    let x: Vec<f64> = x.iter().map(|v| v + shift).collect();
                    c.resolve(&x, &y, &radius, &wants, &alpha, &[], margin, angle);
                    assert_eq!(
                        c.waits,
                        brute(&x, &y, &radius, margin, &wants, &alpha, angle),
                        "round {round}, angle {angle}, grid to {far_corner}, shift {shift}"
                    );
                }
            }
        }
    }
}

#[test]
fn grid_agrees_with_the_definition_in_a_pile_of_more_than_64_robots() {
    // 150 robots within 40 px: a grid cell holds more than the 64 candidates flagged at once.
    let mut next = xorshift(42);
    let mut rnd = move || (next() % 4001) as f64 / 100.0;
    let n = 150;
    let x: Vec<f64> = (0..n).map(|_| 100.0 + rnd()).collect();
    let y: Vec<f64> = (0..n).map(|_| 100.0 + rnd()).collect();
    let alpha: Vec<f64> = (0..n).map(|_| rnd() / 40.0 * 2.0 * PI - PI).collect();
    let wants: Vec<bool> = (0..n).map(|i| i % 4 != 0).collect();
    let mut c = Collisions::new([-50.0, -50.0, 350.0, 350.0], 25.0, n);
    c.resolve(&x, &y, &vec![12.5; n], &wants, &alpha, &[], 0.0, 30f64.to_radians());
    assert_eq!(c.waits, brute(&x, &y, &vec![12.5; n], 0.0, &wants, &alpha, 30f64.to_radians()));
    assert!(c.waits.iter().any(|&w| w), "the pile must block someone");
}

#[test]
fn a_dense_grid_kept_from_step_to_step_agrees_with_the_definition() {
    // One `Collisions` over several steps of a crowded floor (a dense grid: its neighbour
    // pairs stand in for the search boxes): robots walk a few px a step, some step into bays
    // and out again, and in some steps a pile forms on one spot, with more pairs than the
    // list keeps (the boxes decide that step). No step may see another step's pairs.
    let mut rnd = xorshift(20_261_123);
    let n = 300;
    let (side, reach) = (400.0, 25.0);
    let headings = [0.0, PI, FRAC_PI_2, -FRAC_PI_2, 1.0, -2.5];
    let mut x: Vec<f64> = (0..n).map(|_| (rnd() % 400) as f64).collect();
    let mut y: Vec<f64> = (0..n).map(|_| (rnd() % 8) as f64 * 50.0).collect();
    let radius = vec![12.5; n];
    let mut c = Collisions::new([-50.0, -50.0, side + 50.0, side + 50.0], reach, n);
    let mut waited = 0;
    for step in 0..12 {
        let alpha: Vec<f64> = (0..n).map(|_| headings[(rnd() % headings.len() as u64) as usize]).collect();
        let wants: Vec<bool> = (0..n).map(|_| rnd() % 4 != 0).collect();
        let bay: Vec<bool> = (0..n).map(|_| step % 3 == 1 && rnd() % 10 == 0).collect();
        let (mut px, mut py) = (x.clone(), y.clone());
        if step % 4 == 2 {
            // 200 robots on one spot: 19,900 pairs, past the list's limit for 300 robots.
            for i in 0..200 {
                (px[i], py[i]) = (200.0, 200.0);
            }
        }
        c.resolve(&px, &py, &radius, &wants, &alpha, &bay, 0.0, 30f64.to_radians());
        let want = brute_with_bays(&px, &py, &radius, 0.0, &wants, &alpha, 30f64.to_radians(), &bay);
        assert_eq!(c.waits, want, "step {step}");
        waited += want.iter().filter(|&&w| w).count();
        for i in 0..n {
            if wants[i] && !c.waits[i] {
                x[i] = (x[i] + 4.0 * alpha[i].cos()).clamp(0.0, side);
                y[i] = (y[i] + 4.0 * alpha[i].sin()).clamp(0.0, side);
            }
        }
    }
    assert!(waited > 300, "the floor is crowded enough to block: {waited}");
}
