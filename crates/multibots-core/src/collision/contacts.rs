//! Contacts: pairs of robots closer than r_i + r_j after a move (docs/metrics.md), found
//! with the step's collision grid.

use super::Collisions;

impl Collisions {
    /// Contacts after this step's moves: pairs closer than `r_i + r_j` of which at least one
    /// robot moved (`moved`), counted once each, and the smallest centre distance among the
    /// pairs looked at (within `r_i + r_j + slack`, or `f64::INFINITY`). `x`, `y` are the
    /// positions after the moves; `slack` is at least the farthest any robot moved this step
    /// (twice a step), so this step's grid (built before the moves) still finds every pair.
    /// Robots in bays (spread placement's parked robots) stand beside the aisle and are not in
    /// the grid: they are not counted, as they do not block.
    /// Call it after [`Collisions::resolve`] in a step where someone wanted to move.
    #[must_use]
    pub fn contacts(&self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], slack: f64) -> (u64, f64) {
        let r_max = radius[..x.len()].iter().copied().fold(0.0, f64::max);
        self.contacts_within(x, y, radius, moved, r_max, slack)
    }

    /// [`Collisions::contacts`] with the fleet's largest radius `r_max` given (it is the
    /// same every step: the caller keeps it).
    #[must_use]
    pub fn contacts_within(&self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], r_max: f64, slack: f64) -> (u64, f64) {
        let n = x.len();
        let (y, radius, moved) = (&y[..n], &radius[..n], &moved[..n]);
        let grid = self.grid;
        let (by_cell, sx, sy) = (&self.by_cell[..], &self.sx[..], &self.sy[..]);
        let (mut count, mut closest) = (0u64, f64::INFINITY);
        for i in 0..n {
            if !moved[i] {
                continue;
            }
            let (xi, yi) = (x[i], y[i]);
            // A robot within contact of `i` after the moves stood within contact plus half the
            // slack of it before them: test the sorted (pre-move) positions first, read in
            // order, and only the few near ones by id.
            let near = radius[i] + r_max + 0.5 * slack;
            let near2 = near * near * 1.000_001;
            let ri = radius[i];
            let mut pair = |k: usize| {
                let j = by_cell[k] as usize;
                if moved[j] && j < i {
                    return;
                }
                let d = crate::route::axis_dist(x[j] - xi, y[j] - yi);
                closest = closest.min(d);
                count += u64::from(d < ri + radius[j]);
            };
            // Far is `d² > near2`, and the rest near (NaN included, as ever).
            let near_k = |k: usize| {
                let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                let far = dx * dx + dy * dy > near2;
                u64::from(!far) & u64::from(by_cell[k] as usize != i)
            };
            // Tiny fleets: every robot in the grid, in one pass. Others: the cells of a box
            // around `i`. Every position that passes the test above lies within `near` (and a
            // hair, from `near2`'s slack and rounding) of `i` along each axis; which cells the
            // box covers changes only what is read, never what is counted.
            let (c0, r0, c1, r1) = if self.tiny {
                (0, 0, 0, 0)
            } else {
                let hw = (near * 1.000_1 + 1e-9) * grid.inv_size + 1e-6;
                let (tx, ty) = grid.scaled(xi, yi);
                let (c0, r0) = grid.cell(tx - hw, ty - hw);
                let (c1, r1) = grid.cell(tx + hw, ty + hw);
                (c0 as usize, r0 as usize, c1 as usize, r1 as usize)
            };
            for row in r0..=r1 {
                let (mut k0, k1) = if self.tiny {
                    (0, self.placed)
                } else {
                    let base = row * grid.cols;
                    self.cells_run(base + c0, base + c1)
                };
                // Most candidates are far: flag the near ones without a branch each, 64 at a
                // time, then look at those.
                while k0 < k1 {
                    let end = k1.min(k0 + 64);
                    let mut mask = 0u64;
                    for k in k0..end {
                        mask |= near_k(k) << (k - k0);
                    }
                    while mask != 0 {
                        pair(k0 + mask.trailing_zeros() as usize);
                        mask &= mask - 1;
                    }
                    k0 = end;
                }
            }
        }
        (count, closest)
    }
}
