//! Collision waiting (spec phase 3, paper III-C).
//!
//! Robot `i`, wanting to move with heading α, is blocked by robot `j` when
//! `dist(i, j) <= r_i + r_j + margin` and the angle between α and the bearing to `j`, folded
//! into [0°, 180°], is under the collision angle (30°); `dist = 0` always blocks. In each
//! strongly connected component of two or more robots of the "blocked by" graph, the robot
//! with the smallest id is released. Everyone else who is blocked waits.
//!
//! Candidates come from a uniform grid whose cells are as wide as the largest contact
//! distance, so the cost grows with N, not N². All buffers live in [`Collisions`] and are
//! reused from step to step.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Whether a robot at `(xi, yi)` heading `alpha` is blocked by one at `(xj, yj)`.
#[inline]
#[must_use]
pub fn blocks(xi: f64, yi: f64, alpha: f64, xj: f64, yj: f64, reach: f64, angle: f64) -> bool {
    let (dx, dy) = (xj - xi, yj - yi);
    let d = (dx * dx + dy * dy).sqrt();
    if d > reach {
        return false;
    }
    if d == 0.0 {
        return true;
    }
    folded_angle(alpha, dy.atan2(dx)) < angle
}

/// The angle between two directions, folded into [0, π].
#[inline]
#[must_use]
pub fn folded_angle(a: f64, b: f64) -> f64 {
    let d = (a - b).abs() % TAU;
    if d > PI {
        TAU - d
    } else {
        d
    }
}

/// Reusable state of the collision phase.
#[derive(Clone, Debug, Default)]
pub struct Collisions {
    // Grid geometry.
    x0: f64,
    y0: f64,
    /// `1 / size`: a multiplication instead of a division per coordinate. Any monotonic map
    /// of coordinates to cells finds every neighbour, as long as insertion and search use
    /// the same one.
    inv_size: f64,
    /// Half-width of the box searched around a robot: the contact distance, a hair wider.
    reach: f64,
    cols: usize,
    rows: usize,
    // Robots by grid cell, as singly linked lists: `head[cell]`, then `link[robot]`. Built
    // and cleared in O(N), so a step never sweeps the whole grid.
    cell_of: Vec<u32>,
    head: Vec<u32>,
    link: Vec<u32>,
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
}

impl Collisions {
    /// A grid over the rectangle `[x0, x1] × [y0, y1]` that robots never leave, with cells
    /// of side `reach` (the largest contact distance).
    #[must_use]
    pub fn new(bounds: [f64; 4], reach: f64, robots: usize) -> Collisions {
        // Cells twice the contact distance wide: the box of half-width `reach` around a robot
        // then overlaps at most 2 × 2 cells (4 list heads to read instead of 9), and the grid
        // is 4 times smaller, so it stays in cache.
        let size = 2.0 * reach.max(1e-6);
        let cols = (((bounds[2] - bounds[0]) / size).ceil() as usize).max(1) + 1;
        let rows = (((bounds[3] - bounds[1]) / size).ceil() as usize).max(1) + 1;
        Collisions {
            x0: bounds[0],
            y0: bounds[1],
            reach: reach.max(1e-6) * (1.0 + 1e-9) + 1e-9,
            inv_size: 1.0 / size,
            cols,
            rows,
            cell_of: vec![0; robots],
            head: vec![u32::MAX; cols * rows],
            link: vec![u32::MAX; robots],
            edge_start: vec![0; robots + 1],
            edge_to: Vec::with_capacity(robots),
            waits: vec![false; robots],
            index: vec![u32::MAX; robots],
            low: vec![0; robots],
            on_stack: vec![false; robots],
            stack: Vec::with_capacity(robots),
            call: Vec::with_capacity(robots),
            released: vec![false; robots],
            bay: Vec::new(),
        }
    }

    #[inline]
    fn grid_cell(&self, x: f64, y: f64) -> (usize, usize) {
        let cx = (((x - self.x0) * self.inv_size).max(0.0) as usize).min(self.cols - 1);
        let cy = (((y - self.y0) * self.inv_size).max(0.0) as usize).min(self.rows - 1);
        (cx, cy)
    }

    /// Decides who waits. `alpha[i]` is used only where `wants[i]`; `margin` widens every
    /// contact distance and `angle` is the collision angle in radians. Fills `self.waits`.
    #[allow(clippy::too_many_arguments)]
    pub fn resolve(&mut self, x: &[f64], y: &[f64], radius: &[f64], wants: &[bool], alpha: &[f64], margin: f64, angle: f64) {
        let n = x.len();
        self.waits.fill(false);
        if !wants.iter().any(|&w| w) {
            return;
        }
        // Every robot can block, so every robot goes into the grid.
        let bays = !self.bay.is_empty();
        for i in 0..n {
            if bays && self.bay[i] {
                self.cell_of[i] = u32::MAX;
                continue;
            }
            let (cx, cy) = self.grid_cell(x[i], y[i]);
            let c = cy * self.cols + cx;
            self.cell_of[i] = c as u32;
            self.link[i] = self.head[c];
            self.head[c] = i as u32;
        }

        // Half-width of the cone's box across the heading, with slack above rounding.
        let narrow = angle <= FRAC_PI_2;
        let side = self.reach * angle.sin() * 1.000_001 + 1e-9;
        // Build the "blocked by" edges, in ascending j for each i.
        self.edge_to.clear();
        let mut any_edge = false;
        for i in 0..n {
            self.edge_start[i] = self.edge_to.len() as u32;
            if !wants[i] || self.cell_of[i] == u32::MAX {
                continue;
            }
            let first = self.edge_to.len();
            // Only robots in the cone ahead can block. Moving along an aisle (heading exactly
            // along an axis) with a cone of at most 90°, the cone lies in a box `reach` long
            // ahead and `reach · sin(angle)` to each side (the robot's own point included, for
            // dist = 0): fewer cells to read. Other headings search the whole square.
            let (h, w) = (self.reach, side);
            let a = alpha[i];
            let (lx, ly, hx, hy) = if !narrow {
                (x[i] - h, y[i] - h, x[i] + h, y[i] + h)
            } else if a == 0.0 {
                (x[i], y[i] - w, x[i] + h, y[i] + w)
            } else if a == PI || a == -PI {
                (x[i] - h, y[i] - w, x[i], y[i] + w)
            } else if a == FRAC_PI_2 {
                (x[i] - w, y[i], x[i] + w, y[i] + h)
            } else if a == -FRAC_PI_2 {
                (x[i] - w, y[i] - h, x[i] + w, y[i])
            } else {
                (x[i] - h, y[i] - h, x[i] + h, y[i] + h)
            };
            let (gx0, gy0) = self.grid_cell(lx, ly);
            let (gx1, gy1) = self.grid_cell(hx, hy);
            for gy in gy0..=gy1 {
                for gx in gx0..=gx1 {
                    let mut j = self.head[gy * self.cols + gx];
                    while j != u32::MAX {
                        let ju = j as usize;
                        let r = radius[i] + radius[ju] + margin;
                        let (dx, dy) = (x[ju] - x[i], y[ju] - y[i]);
                        // Clearly out of reach (with a relative slack far above rounding):
                        // skip the square root and the angle. Near the boundary, `blocks`
                        // decides exactly as before.
                        let far = dx.abs() > r * 1.000_001 || dy.abs() > r * 1.000_001 || dx * dx + dy * dy > r * r * 1.000_001;
                        if ju != i && !far && blocks(x[i], y[i], alpha[i], x[ju], y[ju], r, angle) {
                            self.edge_to.push(j);
                        }
                        j = self.link[ju];
                    }
                }
            }
            if self.edge_to.len() > first {
                self.edge_to[first..].sort_unstable();
                any_edge = true;
            }
        }
        self.edge_start[n] = self.edge_to.len() as u32;
        for i in 0..n {
            if self.cell_of[i] != u32::MAX {
                self.head[self.cell_of[i] as usize] = u32::MAX;
            }
        }
        if !any_edge {
            return;
        }
        self.release_cycles(n);
        for i in 0..n {
            self.waits[i] = self.edge_start[i] < self.edge_start[i + 1] && !self.released[i];
        }
    }

    /// Marks in `released` the smallest id of every strongly connected component of two or
    /// more robots (Tarjan's algorithm without recursion).
    fn release_cycles(&mut self, n: usize) {
        self.released.fill(false);
        self.index.fill(u32::MAX);
        self.on_stack.fill(false);
        self.stack.clear();
        let mut next_index = 0u32;
        for root in 0..n {
            if self.index[root] != u32::MAX || self.edge_start[root] == self.edge_start[root + 1] {
                continue;
            }
            self.call.push((root as u32, self.edge_start[root]));
            self.index[root] = next_index;
            self.low[root] = next_index;
            next_index += 1;
            self.stack.push(root as u32);
            self.on_stack[root] = true;
            while let Some(&mut (v, ref mut e)) = self.call.last_mut() {
                let v = v as usize;
                if *e < self.edge_start[v + 1] {
                    let w = self.edge_to[*e as usize] as usize;
                    *e += 1;
                    if self.index[w] == u32::MAX {
                        self.index[w] = next_index;
                        self.low[w] = next_index;
                        next_index += 1;
                        self.stack.push(w as u32);
                        self.on_stack[w] = true;
                        self.call.push((w as u32, self.edge_start[w]));
                    } else if self.on_stack[w] {
                        self.low[v] = self.low[v].min(self.index[w]);
                    }
                    continue;
                }
                self.call.pop();
                if let Some(&(parent, _)) = self.call.last() {
                    let p = parent as usize;
                    self.low[p] = self.low[p].min(self.low[v]);
                }
                if self.low[v] == self.index[v] {
                    let mut smallest = u32::MAX;
                    let mut size = 0;
                    loop {
                        let w = self.stack.pop().expect("the component is on the stack");
                        self.on_stack[w as usize] = false;
                        smallest = smallest.min(w);
                        size += 1;
                        if w as usize == v {
                            break;
                        }
                    }
                    if size >= 2 {
                        self.released[smallest as usize] = true;
                    }
                }
            }
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
            let got = &c.edge_to[c.edge_start[i] as usize..c.edge_start[i + 1] as usize];
            assert_eq!(got, brute.as_slice(), "robot {i}");
        }
    }
}
