//! A uniform grid of points for neighbour queries: points sorted by cell (a counting sort),
//! so the points of one cell are one contiguous run: the people's neighbours, rebuilt every
//! step (nothing allocated after the first build of a given size), and the layout's cells,
//! for its geometry check.

/// Whether `dx.hypot(dy) >= r`, the answer `hypot` gives, bit for bit: the squares decide it
/// where they leave no doubt (beyond a margin a million times their rounding error), `hypot`
/// only near the circle. A neighbour query's square holds about four points outside its
/// circle for every three inside, and `hypot` costs far more than two products.
#[inline]
pub(crate) fn at_least(dx: f64, dy: f64, r: f64) -> bool {
    const MARGIN: f64 = 1e-9;
    let (s, r2) = (dx * dx + dy * dy, r * r);
    if r > 0.0 && r2.is_normal() {
        if s > r2 * (1.0 + MARGIN) {
            return true;
        }
        if s < r2 * (1.0 - MARGIN) {
            return false;
        }
    }
    dx.hypot(dy) >= r
}

/// Points bucketed by cell.
#[derive(Clone, Debug, Default)]
pub(crate) struct Buckets {
    x0: f64,
    y0: f64,
    inv: f64,
    cols: usize,
    rows: usize,
    /// `start[c]..start[c + 1]`: the range of `items` in cell `c`.
    start: Vec<u32>,
    /// Point indices, sorted by cell.
    items: Vec<u32>,
    cell_of: Vec<u32>,
    /// Where the next point of each cell goes while building (kept: no allocation a step).
    fill: Vec<u32>,
}

/// The most cells a grid may have; past it the cells grow (the answers do not change).
const MAX_CELLS: f64 = (1u64 << 20) as f64;

impl Buckets {
    /// A grid over `bounds` (`[x0, y0, x1, y1]`) with cells at least `size` wide.
    pub(crate) fn new(bounds: [f64; 4], size: f64) -> Buckets {
        let (w, h) = ((bounds[2] - bounds[0]).max(1.0), (bounds[3] - bounds[1]).max(1.0));
        let mut size = size.max(1.0);
        while (w / size + 1.0) * (h / size + 1.0) > MAX_CELLS {
            size *= 2.0;
        }
        // Truncation is intended: a cell count from a bounded, positive ratio.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let (cols, rows) = ((w / size) as usize + 1, (h / size) as usize + 1);
        Buckets {
            x0: bounds[0],
            y0: bounds[1],
            inv: 1.0 / size,
            cols,
            rows,
            start: vec![0; cols * rows + 1],
            items: Vec::new(),
            cell_of: Vec::new(),
            fill: Vec::new(),
        }
    }

    #[inline]
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss, clippy::cast_possible_wrap)]
    fn col_row(&self, x: f64, y: f64) -> (usize, usize) {
        // Points outside the bounds fall in the border cells: found all the same.
        // `max` then `min`: `clamp` would check its bounds on every call (`cols`, `rows` >= 1).
        let c = (((x - self.x0) * self.inv) as i64).max(0).min(self.cols as i64 - 1) as usize;
        let r = (((y - self.y0) * self.inv) as i64).max(0).min(self.rows as i64 - 1) as usize;
        (c, r)
    }

    /// Sorts the points `(x[k], y[k])` for which `keep(k)` holds into their cells.
    pub(crate) fn build(&mut self, x: &[f64], y: &[f64], keep: impl Fn(usize) -> bool) {
        self.start.iter_mut().for_each(|s| *s = 0);
        self.cell_of.clear();
        for k in 0..x.len() {
            // u32::MAX: not kept.
            let c = if keep(k) {
                let (c, r) = self.col_row(x[k], y[k]);
                r * self.cols + c
            } else {
                usize::MAX
            };
            if c != usize::MAX {
                self.start[c + 1] += 1;
            }
            #[allow(clippy::cast_possible_truncation)]
            self.cell_of.push(if c == usize::MAX { u32::MAX } else { c as u32 });
        }
        for c in 0..self.cols * self.rows {
            self.start[c + 1] += self.start[c];
        }
        let total = self.start[self.cols * self.rows] as usize;
        self.items.clear();
        self.items.resize(total, 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.start);
        for (k, &c) in self.cell_of.iter().enumerate() {
            if c != u32::MAX {
                #[allow(clippy::cast_possible_truncation)]
                {
                    self.items[self.fill[c as usize] as usize] = k as u32;
                }
                self.fill[c as usize] += 1;
            }
        }
    }

    /// Calls `f(k)` for every kept point in the cells a box of half-width `r` around
    /// `(x, y)` overlaps (a superset of the points within `r`).
    #[inline]
    pub(crate) fn near(&self, x: f64, y: f64, r: f64, mut f: impl FnMut(usize)) {
        let (c0, r0) = self.col_row(x - r, y - r);
        let (c1, r1) = self.col_row(x + r, y + r);
        for row in r0..=r1 {
            let a = self.start[row * self.cols + c0] as usize;
            let b = self.start[row * self.cols + c1 + 1] as usize;
            for &k in &self.items[a..b] {
                f(k as usize);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_least_answers_as_hypot_does() {
        // Random pairs, and pairs on and next to the circle, where only `hypot` can tell.
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..200_000 {
            let (dx, dy, r) = ((next() - 0.5) * 200.0, (next() - 0.5) * 200.0, next() * 120.0);
            let on = dx.hypot(dy);
            for rr in [r, on, f64::from_bits(on.to_bits() + 1), f64::from_bits(on.to_bits() - 1), on * (1.0 + 1e-12), 0.0, -1.0] {
                assert_eq!(at_least(dx, dy, rr), dx.hypot(dy) >= rr, "{dx} {dy} {rr}");
            }
        }
        for (dx, dy, r) in [(f64::NAN, 0.0, 1.0), (f64::INFINITY, 0.0, 1.0), (1e-170, 0.0, 1e-9), (3.0, 4.0, 5.0), (1e160, 1e160, 1e200)] {
            assert_eq!(at_least(dx, dy, r), dx.hypot(dy) >= r);
        }
    }

    #[test]
    fn finds_every_point_within_reach() {
        let xs: Vec<f64> = (0..200).map(|k| f64::from(k * 37 % 800)).collect();
        let ys: Vec<f64> = (0..200).map(|k| f64::from(k * 53 % 550)).collect();
        let mut b = Buckets::new([0.0, 0.0, 800.0, 550.0], 40.0);
        b.build(&xs, &ys, |k| k % 7 != 0);
        for (qx, qy) in [(0.0, 0.0), (400.0, 275.0), (799.0, 549.0), (-50.0, 600.0)] {
            let mut got = Vec::new();
            b.near(qx, qy, 40.0, |k| got.push(k));
            for k in 0..200 {
                let d = (xs[k] - qx).hypot(ys[k] - qy);
                if d <= 40.0 && k % 7 != 0 {
                    assert!(got.contains(&k), "missed {k} at {d}");
                }
                if k % 7 == 0 {
                    assert!(!got.contains(&k));
                }
            }
        }
    }
}
