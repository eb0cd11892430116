//! Collision waiting (spec phase 3, paper III-C).
//!
//! Robot `i`, wanting to move with heading α, is blocked by robot `j` when
//! `dist(i, j) <= r_i + r_j + margin` and the angle between α and the bearing to `j`, folded
//! into [0°, 180°], is under the collision angle (30°); `dist = 0` always blocks. In each
//! strongly connected component of two or more robots of the "blocked by" graph, the robot
//! with the smallest id is released. Everyone else who is blocked waits.
//!
//! Candidates come from a neighbour list kept from step to step (`neighbours.rs`): each
//! robot's list holds every robot that stood within a radius of it when the list was built,
//! from a uniform grid. Robots move a few px per step, so a list built a little wider than a
//! step needs serves several steps; one pass over the positions each step measures how far
//! robots have moved since, and the list is built anew only when that could let a pair within
//! reach slip out of it. The cost grows with N, not N². The speed-ups are exact: the list
//! holds every pair within reach (a superset, with slack far above rounding), the "clearly
//! far" filter only skips pairs whose outcome is certain, and `blocks` decides every case near
//! a boundary, so results are bit-identical to the brute-force definition (tested in
//! `tests/collision_grid.rs`). All buffers live in [`Collisions`] and are reused from step to
//! step.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Whether a robot at `(xi, yi)` heading `alpha` is blocked by one at `(xj, yj)`.
#[inline]
#[must_use]
pub fn blocks(xi: f64, yi: f64, alpha: f64, xj: f64, yj: f64, reach: f64, angle: f64) -> bool {
    let (dx, dy) = (xj - xi, yj - yi);
    let d = crate::route::axis_dist(dx, dy);
    if d > reach {
        return false;
    }
    if d == 0.0 {
        return true;
    }
    folded_angle(alpha, bearing(dx, dy)) < angle
}

/// `atan2(dy, dx)`, with the axis-parallel directions of aisles answered without the library
/// call. The shortcuts return exactly what IEEE 754 specifies for `atan2` there (±0, ±π,
/// ±π/2, signs included), so headings are bit-identical either way.
#[inline]
#[must_use]
pub fn bearing(dx: f64, dy: f64) -> f64 {
    if dy == 0.0 && dx > 0.0 {
        dy
    } else if dy == 0.0 && dx < 0.0 {
        PI.copysign(dy)
    } else if dx == 0.0 && dy != 0.0 {
        FRAC_PI_2.copysign(dy)
    } else {
        dy.atan2(dx)
    }
}

/// The angle between two directions, folded into [0, π].
#[inline]
#[must_use]
pub fn folded_angle(a: f64, b: f64) -> f64 {
    // `x % TAU` is `x` below TAU: the common case skips the slow `fmod`.
    let d = (a - b).abs();
    let d = if d < TAU { d } else { d % TAU };
    if d > PI {
        TAU - d
    } else {
        d
    }
}

mod contacts;
mod cycles;
mod grid;
mod neighbours;

/// Fleets of at most this many robots use no neighbour list (see [`Collisions`]): with 32
/// robots a pass over all of them costs less than keeping the list.
const TINY: usize = 32;

use neighbours::Neighbours;

/// Reusable state of the collision phase.
#[derive(Clone, Debug, Default)]
pub struct Collisions {
    /// The largest contact distance, a hair wider.
    reach: f64,
    /// The margin of the last [`Collisions::resolve`] (0 before it).
    margin: f64,
    /// What [`Collisions::contacts`] needs listed: the widest distance it has looked at.
    contact_need: f64,
    // Two ways to find candidates:
    // - tiny (a handful of robots, such as the paper's six): each step, one pass over the
    //   pairs of robots in the traffic flags, for each, the others within `cover` of it
    //   (`bits`); the collision test and the contact count look only at those. Robots far
    //   apart, as they mostly are, then cost one distance per pair and step.
    // - otherwise, a neighbour list kept from step to step (see `neighbours.rs`).
    tiny: bool,
    /// Robots standing in a bay when the step's candidates were gathered (see `bay`); empty
    /// when nobody can be in a bay.
    out: Vec<bool>,
    /// The fleet's largest radius when the step's candidates were gathered.
    r_max: f64,
    /// Tiny fleets: robots in the traffic (bays aside), with positions and radii copied
    /// alongside: `by_cell[..placed]`.
    placed: usize,
    by_cell: Vec<u32>,
    sx: Vec<f64>,
    sy: Vec<f64>,
    sr: Vec<f64>,
    /// Tiny fleets: for the robot in place `k` of `by_cell`, the places of the others that
    /// stood within `cover` of it (a relative slack far above rounding included), as bits.
    bits: Vec<u32>,
    cover: f64,
    /// Others: the neighbour list, and the positions when candidates were gathered (before
    /// the step's moves, which contacts compare with).
    near: Neighbours,
    px: Vec<f64>,
    py: Vec<f64>,
    // "Blocked by" graph in compressed rows.
    edge_start: Vec<u32>,
    edge_to: Vec<u32>,
    /// Output: robots that wait this step.
    pub waits: Vec<bool>,
    /// Robots standing in a bay beside the aisle (an extension for large fleets, see
    /// docs/model.md section 7): they neither block nor wait. Empty: nobody (the paper).
    pub bay: Vec<bool>,
    // Tarjan's algorithm, iterative.
    index: Vec<u32>,
    low: Vec<u32>,
    on_stack: Vec<bool>,
    stack: Vec<u32>,
    call: Vec<(u32, u32)>,
    released: Vec<bool>,
    /// Robots with at least one blocker this step, ascending.
    blocked: Vec<u32>,
}

impl Collisions {
    /// The collision phase of `robots` robots whose largest contact distance is `reach`.
    /// `bounds`, the rectangle robots never leave, is not needed (candidates come from where
    /// the robots are) and is kept for callers.
    #[must_use]
    pub fn new(bounds: [f64; 4], reach: f64, robots: usize) -> Collisions {
        let _ = bounds;
        let tiny = robots <= TINY;
        Collisions {
            reach: reach.max(1e-6) * (1.0 + 1e-9) + 1e-9,
            tiny,
            by_cell: if tiny { vec![0; robots] } else { Vec::new() },
            sx: if tiny { vec![0.0; robots] } else { Vec::new() },
            sy: if tiny { vec![0.0; robots] } else { Vec::new() },
            sr: if tiny { vec![0.0; robots] } else { Vec::new() },
            bits: if tiny { vec![0; robots] } else { Vec::new() },
            edge_start: vec![0; robots + 1],
            edge_to: Vec::with_capacity(robots),
            waits: vec![false; robots],
            index: vec![u32::MAX; robots],
            low: vec![0; robots],
            on_stack: vec![false; robots],
            stack: Vec::with_capacity(robots),
            call: Vec::with_capacity(robots),
            released: vec![false; robots],
            blocked: Vec::with_capacity(robots),
            ..Collisions::default()
        }
    }

    /// Gathers the step's candidates from the robots' positions (bays aside); returns whether
    /// the fleet shares one radius. [`Collisions::resolve`] and [`Collisions::contacts`] read
    /// them.
    pub fn build_grid(&mut self, x: &[f64], y: &[f64], radius: &[f64]) -> bool {
        let n = x.len();
        let (y, radius) = (&y[..n], &radius[..n]);
        self.out.clear();
        if !self.bay.is_empty() {
            self.out.extend_from_slice(&self.bay[..n]);
        }
        // One radius for the whole fleet (the usual case): one contact distance.
        let uniform = radius.iter().all(|&r| r == radius[0]);
        self.r_max = radius.iter().copied().fold(0.0, f64::max);
        if self.tiny {
            self.copy_placed(x, y, radius, uniform);
        } else {
            self.px.clear();
            self.px.extend_from_slice(x);
            self.py.clear();
            self.py.extend_from_slice(y);
            let need = ((2.0 * self.r_max + self.margin) * (1.0 + 1e-9) + 1e-9).max(self.reach).max(self.contact_need);
            self.near.refresh(x, y, need);
        }
        uniform
    }

    /// Tiny fleets: the robots in the traffic in id order, with their positions (and radii).
    fn copy_placed(&mut self, x: &[f64], y: &[f64], radius: &[f64], uniform: bool) {
        let n = x.len();
        let out = &self.out[..];
        let (by_cell, sx, sy, sr) = (&mut self.by_cell[..n], &mut self.sx[..n], &mut self.sy[..n], &mut self.sr[..n]);
        let mut k = 0;
        for i in 0..n {
            if out.is_empty() || !out[i] {
                (by_cell[k], sx[k], sy[k]) = (i as u32, x[i], y[i]);
                if !uniform {
                    sr[k] = radius[i];
                }
                k += 1;
            }
        }
        self.placed = k;
        // Wide enough for the collision test (every contact distance plus the margin) and
        // for the widest contact count so far (see `contacts.rs`).
        let cover = ((2.0 * self.r_max + self.margin) * (1.0 + 1e-9) + 1e-9).max(self.reach).max(self.contact_need);
        let c2 = cover * cover * 1.000_01;
        let (sx, sy, bits) = (&self.sx[..k], &self.sy[..k], &mut self.bits[..k]);
        bits.fill(0);
        for a in 0..k {
            for b in a + 1..k {
                // The same squared distance, to the bit, as from either robot: a difference
                // only changes sign when its operands swap.
                let (dx, dy) = (sx[b] - sx[a], sy[b] - sy[a]);
                // Near unless clearly far (NaN included, as in the tests themselves).
                let far = dx * dx + dy * dy > c2;
                let m = u32::from(!far);
                bits[a] |= m << b;
                bits[b] |= m << a;
            }
        }
        self.cover = cover;
    }

    /// Decides who waits. `alpha[i]` is used only where `wants[i]`; `margin` widens every
    /// contact distance and `angle` is the collision angle in radians. Fills `self.waits`.
    #[allow(clippy::too_many_arguments)]
    pub fn resolve(&mut self, x: &[f64], y: &[f64], radius: &[f64], wants: &[bool], alpha: &[f64], margin: f64, angle: f64) {
        let n = x.len();
        // Slices of exactly `n`: indexing by `i < n` then needs no bounds checks.
        let (y, radius, wants, alpha) = (&y[..n], &radius[..n], &wants[..n], &alpha[..n]);
        self.waits[..n].fill(false);
        if !wants.contains(&true) {
            return;
        }
        self.margin = margin;
        let uniform = self.build_grid(x, y, radius);
        // Build the "blocked by" edges, robot by robot (the components, and so who is
        // released, do not depend on their order).
        let edge_start = &mut self.edge_start[..=n];
        let edge_to = &mut self.edge_to;
        edge_to.clear();
        let out = &self.out[..];
        if self.tiny {
            let (placed, by_cell, sx, sy, sr, bits) = (self.placed, &self.by_cell[..], &self.sx[..], &self.sy[..], &self.sr[..], &self.bits[..]);
            // Robots in the traffic are placed in id order: `p` is the place of robot `i`.
            let mut p = 0;
            for i in 0..n {
                edge_start[i] = edge_to.len() as u32;
                if p == placed || by_cell[p] as usize != i {
                    // In a bay: neither blocks nor waits.
                    continue;
                }
                p += 1;
                if !wants[i] {
                    continue;
                }
                let (xi, yi, a, ri) = (x[i], y[i], alpha[i], radius[i]);
                let contact = |k: usize| if uniform { ri + ri + margin } else { ri + sr[k] + margin };
                // Clearly out of reach (with a relative slack far above rounding): skip the
                // square root and the angle. Near the boundary, `blocks` decides exactly.
                let near = |k: usize| {
                    let r = contact(k);
                    let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                    let far = dx * dx + dy * dy > r * r * 1.000_001;
                    !far
                };
                // `bits` holds every near one (and some that are not), in id order.
                let mut mask = bits[p - 1];
                while mask != 0 {
                    let k = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if near(k) && blocks(xi, yi, a, sx[k], sy[k], contact(k), angle) {
                        edge_to.push(by_cell[k]);
                    }
                }
            }
        } else {
            let (start, list) = (&self.near.start[..=n], &self.near.list[..]);
            for i in 0..n {
                edge_start[i] = edge_to.len() as u32;
                if !wants[i] || (!out.is_empty() && out[i]) {
                    continue;
                }
                let (xi, yi, a, ri) = (x[i], y[i], alpha[i], radius[i]);
                for &j in &list[start[i] as usize..start[i + 1] as usize] {
                    let j = j as usize;
                    if !out.is_empty() && out[j] {
                        continue;
                    }
                    // The same sum as `ri + ri + margin` when the fleet shares one radius.
                    let r = ri + radius[j] + margin;
                    let (dx, dy) = (x[j] - xi, y[j] - yi);
                    if dx * dx + dy * dy <= r * r * 1.000_001 && blocks(xi, yi, a, x[j], y[j], r, angle) {
                        edge_to.push(j as u32);
                    }
                }
            }
        }
        edge_start[n] = edge_to.len() as u32;
        if edge_to.is_empty() {
            return;
        }
        // Only robots that are blocked can wait, or lie on a cycle: the rest of the step's
        // work is in proportion to them, not to the fleet.
        self.blocked.clear();
        self.blocked.extend((0..n).filter(|&i| edge_start[i] < edge_start[i + 1]).map(|i| i as u32));
        self.release_cycles();
        for &i in &self.blocked {
            let i = i as usize;
            self.waits[i] = !self.released[i];
            // Back to the resting state for the next step.
            self.released[i] = false;
            self.index[i] = u32::MAX;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
                        assert_eq!(crate::route::axis_dist(dx, dy).to_bits(), (dx * dx + dy * dy).sqrt().to_bits(), "dist {dx} {dy}");
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
        c.resolve(x, y, &vec![12.5; x.len()], wants, alpha, 0.0, ANGLE);
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

    #[test]
    fn grid_finds_neighbours_across_cell_borders_and_agrees_with_brute_force() {
        // Pseudo-random cloud, compared with the O(N²) definition.
        let mut s = 12345u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % 10_000) as f64 / 10_000.0
        };
        let n = 400;
        let x: Vec<f64> = (0..n).map(|_| rnd() * 300.0).collect();
        let y: Vec<f64> = (0..n).map(|_| rnd() * 300.0).collect();
        let alpha: Vec<f64> = (0..n).map(|_| rnd() * TAU - PI).collect();
        let wants: Vec<bool> = (0..n).map(|i| i % 3 != 0).collect();
        let mut c = Collisions::new([0.0, 0.0, 300.0, 300.0], 25.0, n);
        c.resolve(&x, &y, &vec![12.5; n], &wants, &alpha, 0.0, ANGLE);
        for i in 0..n {
            let brute: Vec<u32> = (0..n).filter(|&j| j != i && wants[i] && blocks(x[i], y[i], alpha[i], x[j], y[j], 25.0, ANGLE)).map(|j| j as u32).collect();
            let mut got = c.edge_to[c.edge_start[i] as usize..c.edge_start[i + 1] as usize].to_vec();
            got.sort_unstable();
            assert_eq!(got, brute, "robot {i}");
        }
    }
}
