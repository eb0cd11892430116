//! The collision phase's uniform grid: positions to cells, and the robots sorted by cell so
//! that the cells a search box covers in one grid row are one contiguous run, and so that
//! the pairs of neighbouring robots can be read from it (`pairs.rs`).

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
    /// like `floor` for the non-negative values that positions in bounds give; any other
    /// value (out of bounds; NaN goes to 0) ends in a border cell.
    #[inline]
    pub(super) fn cell(&self, tx: f64, ty: f64) -> (u32, u32) {
        ((tx as i32).clamp(0, self.last_col) as u32, (ty as i32).clamp(0, self.last_row) as u32)
    }
}

/// The spatial index: the robots (bays aside) sorted into a uniform grid by their positions,
/// with their positions and radii copied alongside in that order.
#[derive(Clone, Debug, Default)]
pub(super) struct Space {
    pub(super) grid: Grid,
    /// Half-width of the box searched around a robot: the contact distance, a hair wider.
    pub(super) reach: f64,
    /// Each robot's cell (`u32::MAX`: in a bay, out of the grid). Its column and row are
    /// computed again where needed: two conversions are cheaper than 8 bytes a robot read
    /// from memory.
    pub(super) cell_of: Vec<u32>,
    // Robots sorted by cell: the cells of a grid row that a search box covers are one
    // contiguous run, read without chasing links. Two ways to sort, chosen by the grid's
    // size per robot:
    // - dense (a big fleet): a counting sort each step; the robots of cell `c` are
    //   `first[c]..first[c + 1]`. It costs O(cells) per step, cheap when cells are few per
    //   robot.
    // - sparse (a small fleet in a big grid): last step's `order` repaired by insertion sort
    //   (robots seldom change cells), O(N) per step. A cell's run is `start[c]..end[c]`,
    //   valid only when `stamp[c]` is this step's `epoch`; other cells are empty.
    pub(super) dense: bool,
    // - tiny (a handful of robots, such as the paper's six): no cells at all. Each step one
    //   pass over the pairs of robots in the grid flags, for each, the others within
    //   `cover` of it (`bits`); the collision test and the contact count look only at those.
    //   Robots far apart, as they mostly are, then cost one distance per pair and step. The
    //   tests decide, not the flags, so the results are the same.
    pub(super) tiny: bool,
    /// Tiny fleets: for the robot in place `k` of `by_cell`, the places of the others that
    /// stood within `cover` of it (a relative slack far above rounding included), as bits.
    pub(super) bits: Vec<u32>,
    pub(super) cover: f64,
    /// Tiny fleets: whether the pass over pairs can be skipped (see [`Apart`]).
    pub(super) apart: Apart,
    /// Tiny fleets: no two robots in the grid stand within `cover` (every flag is clear), so
    /// none blocks another this step.
    pub(super) clear: bool,
    /// The farthest a coordinate can be from 0 (robots never leave the bounds): rounding
    /// in a move is at most a few units in the last place of it.
    pub(super) far_coordinate: f64,
    /// Robots in the grid (bays aside): `by_cell[..placed]`.
    pub(super) placed: usize,
    pub(super) first: Vec<u32>,
    pub(super) order: Vec<u32>,
    pub(super) epoch: u64,
    pub(super) stamp: Vec<u64>,
    pub(super) start: Vec<u32>,
    pub(super) end: Vec<u32>,
    pub(super) by_cell: Vec<u32>,
    pub(super) sx: Vec<f64>,
    pub(super) sy: Vec<f64>,
    /// Radii, copied only for a fleet of mixed sizes (empty for one radius: then every
    /// contact distance is the same, and no robot reads it).
    pub(super) sr: Vec<f64>,
}

/// The largest radius, NaN if any is NaN (then every contact test passes, as in the
/// definition).
pub(super) fn max_radius(radius: &[f64]) -> f64 {
    radius.iter().fold(0.0, |m: f64, &r| if m.is_nan() || r.is_nan() { f64::NAN } else { m.max(r) })
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
        Runs { first: &self.space.first, stamp: &self.space.stamp, start: &self.space.start, end: &self.space.end, epoch: self.space.epoch }
    }

    /// Tiny fleets: the flags' reach for robots of radii `radius`: every contact distance
    /// plus the margin, for the collision test, and the widest contact count so far (see
    /// `contacts.rs`). A NaN radius or margin (scenarios refuse them; the public API does
    /// not) makes every contact test pass, as in the definition: then every pair is flagged.
    pub(super) fn cover_of(&self, radius: &[f64]) -> f64 {
        let r_max = max_radius(radius);
        let widest = 2.0 * r_max + self.margin;
        if widest.is_nan() {
            f64::INFINITY
        } else {
            (widest * (1.0 + 1e-9) + 1e-9).max(self.space.reach).max(self.contact_need)
        }
    }

    /// Tiny fleets: the robots in the grid in id order, with their positions (and radii).
    pub(super) fn copy_placed(&mut self, x: &[f64], y: &[f64], radius: &[f64], uniform: bool) {
        let n = x.len();
        let cell_of = &self.space.cell_of[..n];
        let (by_cell, sx, sy, sr) =
            (&mut self.space.by_cell[..n], &mut self.space.sx[..n], &mut self.space.sy[..n], &mut self.space.sr[..if uniform { 0 } else { n }]);
        let mut k = 0;
        // Which robots are in the grid, as bits of their ids (tiny fleets have at most 32).
        let mut placed = 0u32;
        for i in 0..n {
            if cell_of[i] != u32::MAX {
                (by_cell[k], sx[k], sy[k]) = (i as u32, x[i], y[i]);
                if !uniform {
                    sr[k] = radius[i];
                }
                placed |= 1 << i;
                k += 1;
            }
        }
        // Each pair once: flag, for each robot, the others within `cover` of it.
        let cover = self.cover_of(&radius[..n]);
        self.space.cover = cover;
        if self.space.apart.holds(placed, &self.space.sx[..k], &self.space.sy[..k], cover) {
            // No pair within `cover`: the flags are all clear, as the pass would leave them
            // (the last pass did; checked in the crate's own tests too, which run optimised).
            if cfg!(any(test, debug_assertions)) {
                assert!(self.space.bits[..k].iter().all(|&b| b == 0), "flags set under a proof that none is");
            }
            self.space.clear = true;
            return;
        }
        let c2 = cover * cover * 1.000_01;
        let (sx, sy, bits) = (&self.space.sx[..k], &self.space.sy[..k], &mut self.space.bits[..k]);
        bits.fill(0);
        let mut closest2 = f64::INFINITY;
        for a in 0..k {
            for b in a + 1..k {
                // The same squared distance, to the bit, as from either robot: a difference
                // only changes sign when its operands swap.
                let (dx, dy) = (sx[b] - sx[a], sy[b] - sy[a]);
                let d2 = dx * dx + dy * dy;
                closest2 = closest2.min(d2);
                // Near unless clearly far (NaN included, as in the tests themselves).
                let far = d2 > c2;
                let m = u32::from(!far);
                bits[a] |= m << b;
                bits[b] |= m << a;
            }
        }
        let clear = bits.iter().all(|&b| b == 0);
        self.space.apart.anchor(placed, sx, sy, clear, closest2);
        self.space.clear = clear;
    }

    /// Dense grids: a counting sort by cell into `first`, `by_cell`, `sx`, `sy` (and `sr`).
    pub(super) fn counting_sort(&mut self, x: &[f64], y: &[f64], radius: &[f64], uniform: bool) {
        let n = x.len();
        let cell_of = &self.space.cell_of[..n];
        let first = &mut self.space.first[..];
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
        let (by_cell, sx, sy, sr) =
            (&mut self.space.by_cell[..n], &mut self.space.sx[..n], &mut self.space.sy[..n], &mut self.space.sr[..if uniform { 0 } else { n }]);
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
        let cell_of = &self.space.cell_of[..n];
        if self.space.order.len() != n {
            self.space.order.clear();
            self.space.order.extend(0..n as u32);
        }
        let order = &mut self.space.order[..];
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
        self.space.epoch += 1;
        let epoch = self.space.epoch;
        let (stamp, start, end) = (&mut self.space.stamp[..], &mut self.space.start[..], &mut self.space.end[..]);
        let (by_cell, sx, sy, sr) =
            (&mut self.space.by_cell[..n], &mut self.space.sx[..n], &mut self.space.sy[..n], &mut self.space.sr[..if uniform { 0 } else { n }]);
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

/// Tiny fleets, most steps: a proof that no two robots stand within `cover`, from the last
/// pass over pairs, so that the pass can be skipped. In the paper's 30 runs robots stand
/// farther apart than that in 97% of the steps where one moves. Robots move a few px a step,
/// so two robots that stood `gap` apart are still farther apart than `gap` less both moves
/// since: when that exceeds `cover` (with a slack far above rounding), every pair's distance
/// would test far, and the flags would all be clear, exactly as the pass would leave them.
#[derive(Clone, Debug)]
pub(super) struct Apart {
    /// The positions of the robots in the grid at the last pass over pairs, in place order.
    pub(super) x: Vec<f64>,
    y: Vec<f64>,
    /// Which robots were in the grid then, as bits of their ids. The argument holds for any
    /// robots matched place by place; requiring the same robots keeps it plain to check.
    placed: u32,
    /// The smallest distance between two of them then, rounded down; negative: no proof
    /// (some pair was flagged, or a distance was not finite).
    gap: f64,
}

impl Default for Apart {
    /// No pass yet: no proof.
    fn default() -> Apart {
        Apart { x: Vec::new(), y: Vec::new(), placed: 0, gap: -1.0 }
    }
}

impl Apart {
    /// Whether the robots in the grid now (`placed`, at `sx`, `sy` in place order) are all
    /// farther than `cover` apart, by the last pass's positions and gap.
    fn holds(&self, placed: u32, sx: &[f64], sy: &[f64], cover: f64) -> bool {
        if self.gap < 0.0 || placed != self.placed || sx.len() != self.x.len() {
            return false;
        }
        // The farthest any robot has moved since, along both axes (at least its distance).
        // A NaN position stays NaN here and fails the test below, as it must.
        let mut moved = 0.0_f64;
        for ((&x, &y), (&ax, &ay)) in sx.iter().zip(sy).zip(self.x.iter().zip(&self.y)) {
            let d = (x - ax).abs() + (y - ay).abs();
            moved = if d > moved || d.is_nan() { d } else { moved };
        }
        self.gap - 2.0 * moved * (1.0 + 1e-9) > cover * 1.001 + 1e-6
    }

    /// Records a pass over pairs: the positions, and whether every pair tested far (`clear`),
    /// the smallest squared distance among them being `closest2`.
    fn anchor(&mut self, placed: u32, sx: &[f64], sy: &[f64], clear: bool, closest2: f64) {
        self.placed = placed;
        self.x.clear();
        self.x.extend_from_slice(sx);
        self.y.clear();
        self.y.extend_from_slice(sy);
        self.gap = if sx.len() < 2 {
            // No pairs: nothing can come near until the set of robots changes.
            f64::INFINITY
        } else if clear && closest2.is_finite() {
            closest2.sqrt() * (1.0 - 1e-9)
        } else {
            -1.0
        };
    }
}
