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
        let n = x.len();
        let (y, radius, moved) = (&y[..n], &radius[..n], &moved[..n]);
        let r_max = radius.iter().copied().fold(0.0, f64::max);
        let grid = self.grid;
        let (by_cell, sx, sy) = (&self.by_cell[..], &self.sx[..], &self.sy[..]);
        let (mut count, mut closest) = (0u64, f64::INFINITY);
        for i in 0..n {
            if !moved[i] {
                continue;
            }
            let (xi, yi) = (x[i], y[i]);
            let hw = (radius[i] + r_max + slack) * grid.inv_size;
            let (tx, ty) = grid.scaled(xi, yi);
            let (c0, r0) = grid.cell(tx - hw, ty - hw);
            let (c1, r1) = grid.cell(tx + hw, ty + hw);
            // A robot within contact of `i` after the moves stood within contact plus half the
            // slack of it before them: test the sorted (pre-move) positions first, read in
            // order, and only the few near ones by id.
            let near = radius[i] + r_max + 0.5 * slack;
            let near2 = near * near * 1.000_001;
            for row in r0..=r1 {
                let base = row as usize * grid.cols;
                let (k0, k1) = self.cells_run(base + c0 as usize, base + c1 as usize);
                for k in k0..k1.max(k0) {
                    let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                    if dx * dx + dy * dy > near2 {
                        continue;
                    }
                    let j = by_cell[k] as usize;
                    if j == i || (moved[j] && j < i) {
                        continue;
                    }
                    let d = crate::route::axis_dist(x[j] - xi, y[j] - yi);
                    closest = closest.min(d);
                    count += u64::from(d < radius[i] + radius[j]);
                }
            }
        }
        (count, closest)
    }
}
