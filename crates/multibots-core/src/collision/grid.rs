//! The uniform grid that builds the neighbour list: the robots counting-sorted by cell, with
//! their positions copied alongside, so that the three cells of a grid row around a robot
//! are one contiguous run.

/// Robots binned into square cells over the box their positions span.
#[derive(Clone, Debug, Default)]
pub(super) struct Bins {
    x0: f64,
    y0: f64,
    /// `1 / size`: a multiplication instead of a division per coordinate.
    inv_size: f64,
    cols: usize,
    rows: usize,
    /// Each robot's cell; `u32::MAX` for a position that is not finite (it is near nothing).
    pub(super) cell: Vec<u32>,
    /// The robots of cell `c` are `order[first[c]..first[c + 1]]`.
    first: Vec<u32>,
    pub(super) order: Vec<u32>,
    pub(super) sx: Vec<f64>,
    pub(super) sy: Vec<f64>,
}

impl Bins {
    /// Bins the robots into cells at least `size` wide (a hair more: two points within `size`
    /// of each other along an axis then lie in the same or adjacent columns, rounding
    /// included), over the box their finite positions span, so no position is ever clamped.
    pub(super) fn sort(&mut self, x: &[f64], y: &[f64], size: f64) {
        let n = x.len();
        let y = &y[..n];
        let (mut x0, mut y0, mut x1, mut y1) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
        for i in 0..n {
            if x[i].is_finite() && y[i].is_finite() {
                (x0, y0, x1, y1) = (x0.min(x[i]), y0.min(y[i]), x1.max(x[i]), y1.max(y[i]));
            }
        }
        let (w, h) = ((x1 - x0).max(0.0), (y1 - y0).max(0.0));
        // Robots spread thinly over a vast floor would want too many cells: past the limit the
        // cells grow, which only adds candidates (each is tested).
        let max = crate::limits::MAX_GRID_CELLS as f64;
        let size = (size * (1.0 + 1e-6)).max((w * h / max).sqrt() * 1.01).max((w + h) / max * 1.01).max(f64::MIN_POSITIVE);
        (self.x0, self.y0, self.inv_size) = (x0, y0, 1.0 / size);
        if x0 > x1 {
            // No finite position at all.
            (self.cols, self.rows) = (1, 1);
        } else {
            self.cols = ((w * self.inv_size) as usize).saturating_add(1);
            self.rows = ((h * self.inv_size) as usize).saturating_add(1);
        }
        let (cols, rows) = (self.cols, self.rows);
        self.cell.resize(n, 0);
        for i in 0..n {
            self.cell[i] = if x[i].is_finite() && y[i].is_finite() {
                let cx = (((x[i] - x0) * self.inv_size) as usize).min(cols - 1);
                let cy = (((y[i] - y0) * self.inv_size) as usize).min(rows - 1);
                (cy * cols + cx) as u32
            } else {
                u32::MAX
            };
        }
        let first = &mut self.first;
        first.clear();
        first.resize(cols * rows + 1, 0);
        for &c in &self.cell {
            if c != u32::MAX {
                first[c as usize] += 1;
            }
        }
        // Running totals: `first[c]` is the end of cell `c`; placing robots from the last back
        // to the first turns it into the start.
        let mut total = 0;
        for f in first.iter_mut() {
            total += *f;
            *f = total;
        }
        let placed = total as usize;
        self.order.resize(placed, 0);
        self.sx.resize(placed, 0.0);
        self.sy.resize(placed, 0.0);
        for i in (0..n).rev() {
            let c = self.cell[i];
            if c != u32::MAX {
                first[c as usize] -= 1;
                let k = first[c as usize] as usize;
                (self.order[k], self.sx[k], self.sy[k]) = (i as u32, x[i], y[i]);
            }
        }
    }

    /// The runs of the sorted order (at most three) that hold the robots of the 3 × 3 cells
    /// around cell `c`: one per grid row, the cells of a row being adjacent in the order.
    pub(super) fn around(&self, c: u32) -> impl Iterator<Item = (usize, usize)> + '_ {
        let (cols, c) = (self.cols, c as usize);
        let (cx, cy) = (c % cols, c / cols);
        let (c0, c1) = (cx.saturating_sub(1), (cx + 1).min(cols - 1));
        let (r0, r1) = (cy.saturating_sub(1), (cy + 1).min(self.rows - 1));
        (r0..=r1).map(move |r| (self.first[r * cols + c0] as usize, self.first[r * cols + c1 + 1] as usize))
    }
}
