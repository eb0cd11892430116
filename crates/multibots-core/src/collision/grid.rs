//! The collision phase's uniform grid: positions to cells, and the robots sorted by cell so
//! that the cells a search box covers in one grid row are one contiguous run.

use super::Collisions;

/// The uniform grid's geometry: a cheap map from positions to cells.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Grid {
    pub(super) x0: f64,
    pub(super) y0: f64,
    /// `1 / size`: a multiplication instead of a division per coordinate. Any monotonic map
    /// of coordinates to cells finds every neighbour, as long as insertion and search use
    /// the same one.
    pub(super) inv_size: f64,
    pub(super) cols: usize,
    pub(super) last_col: i32,
    pub(super) last_row: i32,
}

impl Grid {
    /// A point in grid units: its cell is the integer part.
    #[inline]
    pub(super) fn scaled(&self, x: f64, y: f64) -> (f64, f64) {
        ((x - self.x0) * self.inv_size, (y - self.y0) * self.inv_size)
    }

    /// The cell column and row of a point in grid units, clamped into the grid (robots never
    /// leave it: it has a free cell around everything they can reach). `as i32` truncates
    /// like `floor` for the non-negative values that occur, and saturates on the rest.
    #[inline]
    pub(super) fn cell(&self, tx: f64, ty: f64) -> (u32, u32) {
        ((tx as i32).clamp(0, self.last_col) as u32, (ty as i32).clamp(0, self.last_row) as u32)
    }
}

/// The range of cells from `c` (the cell of `t`, in grid units) that a box from `t - lo` to
/// `t + hi` overlaps, with `lo, hi` at most one cell: one comparison on each side instead of
/// two float-to-integer conversions. These are the cells `floor` gives for the box's ends,
/// so every robot inside the box is found.
#[inline]
pub(super) fn span(t: f64, c: u32, lo: f64, hi: f64) -> (usize, usize) {
    let (c, cf) = (c as usize, f64::from(c));
    (c - usize::from(t - lo < cf), c + usize::from(t + hi >= cf + 1.0))
}

/// The sorted order's runs by cell, borrowed apart from the rest of [`Collisions`]: the
/// collision test reads them while it writes its edges. Dense grids: `first`; sparse grids:
/// `stamp`, `start`, `end` (non-empty only for them).
#[derive(Clone, Copy)]
pub(super) struct Runs<'a> {
    pub(super) first: &'a [u32],
    pub(super) stamp: &'a [u64],
    pub(super) start: &'a [u32],
    pub(super) end: &'a [u32],
    pub(super) epoch: u64,
}

impl Runs<'_> {
    /// The robots in cells `c0..=c1` of one grid row, as a range of the sorted order (the
    /// runs of adjacent cells are adjacent).
    #[inline]
    pub(super) fn of(&self, c0: usize, c1: usize) -> (usize, usize) {
        if !self.stamp.is_empty() {
            let (mut k0, mut k1) = (u32::MAX, 0);
            for c in c0..=c1 {
                if self.stamp[c] == self.epoch {
                    k0 = k0.min(self.start[c]);
                    k1 = self.end[c];
                }
            }
            return if k0 == u32::MAX { (0, 0) } else { (k0 as usize, k1 as usize) };
        }
        (self.first[c0] as usize, self.first[c1 + 1] as usize)
    }
}

impl Collisions {
    pub(super) fn runs(&self) -> Runs<'_> {
        Runs { first: &self.first, stamp: &self.stamp, start: &self.start, end: &self.end, epoch: self.epoch }
    }

    /// Tiny fleets: the robots in the grid in id order, with their positions (and radii).
    pub(super) fn copy_placed(&mut self, x: &[f64], y: &[f64], radius: &[f64], uniform: bool) {
        let n = x.len();
        let cell_of = &self.cell_of[..n];
        let (by_cell, sx, sy, sr) = (&mut self.by_cell[..n], &mut self.sx[..n], &mut self.sy[..n], &mut self.sr[..if uniform { 0 } else { n }]);
        let mut k = 0;
        for i in 0..n {
            if cell_of[i] != u32::MAX {
                (by_cell[k], sx[k], sy[k]) = (i as u32, x[i], y[i]);
                if !uniform {
                    sr[k] = radius[i];
                }
                k += 1;
            }
        }
        // Each pair once: flag, for each robot, the others within `cover` of it (wide
        // enough for the collision test, every contact distance plus the margin, and for the
        // widest contact count so far, see `contacts.rs`).
        // A NaN radius or margin (scenarios refuse them; the public API does not) makes every
        // contact test pass, as in the definition: then every pair is flagged.
        let r_max = radius[..n].iter().fold(0.0, |m: f64, &r| if m.is_nan() || r.is_nan() { f64::NAN } else { m.max(r) });
        let widest = 2.0 * r_max + self.margin;
        let cover = if widest.is_nan() { f64::INFINITY } else { (widest * (1.0 + 1e-9) + 1e-9).max(self.reach).max(self.contact_need) };
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

    /// Dense grids: a counting sort by cell into `first`, `by_cell`, `sx`, `sy` (and `sr`).
    pub(super) fn counting_sort(&mut self, x: &[f64], y: &[f64], radius: &[f64], uniform: bool) {
        let n = x.len();
        let cell_of = &self.cell_of[..n];
        let first = &mut self.first[..];
        first.fill(0);
        for &c in cell_of {
            if c != u32::MAX {
                first[c as usize] += 1;
            }
        }
        // Running totals: `first[c]` is the end of cell `c`; placing robots from the last
        // back to the first turns it into the start.
        let mut total = 0;
        for f in first.iter_mut() {
            total += *f;
            *f = total;
        }
        let (by_cell, sx, sy, sr) = (&mut self.by_cell[..n], &mut self.sx[..n], &mut self.sy[..n], &mut self.sr[..if uniform { 0 } else { n }]);
        for i in (0..n).rev() {
            let c = cell_of[i];
            if c != u32::MAX {
                first[c as usize] -= 1;
                let k = first[c as usize] as usize;
                (by_cell[k], sx[k], sy[k]) = (i as u32, x[i], y[i]);
                if !uniform {
                    sr[k] = radius[i];
                }
            }
        }
    }

    /// Sparse grids: last step's order repaired by insertion sort (robots out of the grid
    /// sort last), then the runs of the occupied cells stamped with a new epoch.
    pub(super) fn repair_order(&mut self, x: &[f64], y: &[f64], radius: &[f64], uniform: bool, placed: usize) {
        let n = x.len();
        let cell_of = &self.cell_of[..n];
        if self.order.len() != n {
            self.order.clear();
            self.order.extend(0..n as u32);
        }
        let order = &mut self.order[..];
        let mut moves = 0;
        for k in 1..n {
            let v = order[k];
            let key = cell_of[v as usize];
            let mut j = k;
            while j > 0 && cell_of[order[j - 1] as usize] > key {
                order[j] = order[j - 1];
                j -= 1;
            }
            order[j] = v;
            moves += k - j;
            if moves > 8 * n {
                // Far from sorted (the first step, a new fleet): sort outright.
                order.sort_unstable_by_key(|&i| (cell_of[i as usize], i));
                break;
            }
        }
        self.epoch += 1;
        let epoch = self.epoch;
        let (stamp, start, end) = (&mut self.stamp[..], &mut self.start[..], &mut self.end[..]);
        let (by_cell, sx, sy, sr) = (&mut self.by_cell[..n], &mut self.sx[..n], &mut self.sy[..n], &mut self.sr[..if uniform { 0 } else { n }]);
        let mut last = u32::MAX;
        for (k, &i) in order[..placed].iter().enumerate() {
            let i = i as usize;
            (by_cell[k], sx[k], sy[k]) = (i as u32, x[i], y[i]);
            if !uniform {
                sr[k] = radius[i];
            }
            let c = cell_of[i];
            if c != last {
                if last != u32::MAX {
                    end[last as usize] = k as u32;
                }
                stamp[c as usize] = epoch;
                start[c as usize] = k as u32;
                last = c;
            }
        }
        if last != u32::MAX {
            end[last as usize] = placed as u32;
        }
    }
}
