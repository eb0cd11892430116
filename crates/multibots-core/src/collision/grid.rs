//! The collision phase's uniform grid (positions to cells, for the index of `index.rs`), and
//! tiny fleets' pass over pairs, which needs no cells.

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
    /// A cell's key is its row shifted by this, plus its column (`2^shift >= cols`): keys
    /// follow the rows, and a key's row is one shift away.
    pub(super) shift: u32,
    pub(super) last_col: i32,
    pub(super) last_row: i32,
}

impl Grid {
    /// A grid over the rectangle `[x0, x1] × [y0, y1]` that robots never leave, with cells of
    /// side at least `side` (wider where the cell count would pass the limit), and one free
    /// cell on every side: a search box never reaches past it.
    pub(super) fn over(bounds: [f64; 4], side: f64) -> Grid {
        let (w, h) = ((bounds[2] - bounds[0]).max(0.0), (bounds[3] - bounds[1]).max(0.0));
        // Tiny robots in a big warehouse would want billions of cells: past the limit the
        // cells grow, which only adds candidates (every test is still exact).
        let size = side.max((w * h / crate::input::limits::MAX_GRID_CELLS as f64).sqrt() * 1.01);
        let cols = (((bounds[2] - bounds[0]) / size).ceil() as usize).max(1) + 3;
        let rows = (((bounds[3] - bounds[1]) / size).ceil() as usize).max(1) + 3;
        let last = |k: usize| i32::try_from(k - 2).unwrap_or(i32::MAX);
        Grid {
            x0: bounds[0] - size,
            y0: bounds[1] - size,
            inv_size: 1.0 / size,
            cols,
            shift: usize::BITS - (cols - 1).leading_zeros(),
            last_col: last(cols),
            last_row: last(rows),
        }
    }

    /// A point in grid units: its cell is the integer part.
    #[inline]
    pub(super) fn scaled(&self, x: f64, y: f64) -> (f64, f64) {
        ((x - self.x0) * self.inv_size, (y - self.y0) * self.inv_size)
    }

    /// The cell column and row of a point.
    #[inline]
    pub(super) fn cell_of(&self, x: f64, y: f64) -> (u32, u32) {
        let (tx, ty) = self.scaled(x, y);
        self.cell(tx, ty)
    }

    /// The key of the cell of a point (row-major: see `shift`).
    #[inline]
    pub(super) fn key(&self, x: f64, y: f64) -> u32 {
        let (c, r) = self.cell_of(x, y);
        (r << self.shift) | c
    }

    /// The key of column `c` of row `r`.
    #[inline]
    pub(super) fn key_at(&self, c: u32, r: u32) -> u32 {
        (r << self.shift) | c
    }

    /// Rows of cells (the last is always empty).
    pub(super) fn rows(&self) -> usize {
        self.last_row as usize + 2
    }

    /// The side of a cell.
    pub(super) fn size(&self) -> f64 {
        1.0 / self.inv_size
    }

    /// The cell column and row of a point in grid units, clamped into the grid (robots never
    /// leave it: it has a free cell around everything they can reach). `as i32` truncates
    /// like `floor` for the non-negative values that positions in bounds give; any other
    /// value (out of bounds; NaN goes to 0) ends in a border cell.
    #[inline]
    pub(super) fn cell(&self, tx: f64, ty: f64) -> (u32, u32) {
        // `max` then `min`, not `clamp`: the same for `last_* >= 0`, without `clamp`'s check of
        // its bounds on every call.
        ((tx as i32).max(0).min(self.last_col) as u32, (ty as i32).max(0).min(self.last_row) as u32)
    }
}

/// Tiny fleets (at most [`super::TINY`] robots, such as the paper's six): no cells at all.
/// Each step one pass over the pairs of robots out of bays flags, for each, the others within
/// `cover` of it (`bits`); the collision test and the contact count look only at those.
/// Robots far apart, as they mostly are, then cost one distance per pair and step. The tests
/// decide, not the flags, so the results are the same.
#[derive(Clone, Debug, Default)]
pub(super) struct Space {
    pub(super) grid: Grid,
    /// Half-width of the box searched around a robot: the contact distance, a hair wider.
    pub(super) reach: f64,
    /// Tiny fleets: `u32::MAX` for a robot in a bay, out of the pass; 0 for the others.
    pub(super) cell_of: Vec<u32>,
    pub(super) tiny: bool,
    /// For the robot in place `k` of `by_cell`, the places of the others that stood within
    /// `cover` of it (a relative slack far above rounding included), as bits.
    pub(super) bits: Vec<u32>,
    pub(super) cover: f64,
    /// Whether the pass over pairs can be skipped (see [`Apart`]).
    pub(super) apart: Apart,
    /// No two robots in the pass stand within `cover` (every flag is clear), so none blocks
    /// another this step.
    pub(super) clear: bool,
    /// The farthest a coordinate can be from 0 (robots never leave the bounds): rounding
    /// in a move is at most a few units in the last place of it.
    pub(super) far_coordinate: f64,
    /// Robots out of bays, `by_cell[..placed]`, in id order, with their positions (and
    /// radii, for a fleet of mixed sizes) copied alongside.
    pub(super) placed: usize,
    pub(super) by_cell: Vec<u32>,
    pub(super) sx: Vec<f64>,
    pub(super) sy: Vec<f64>,
    pub(super) sr: Vec<f64>,
}

/// The largest radius, NaN if any is NaN (then every contact test passes, as in the
/// definition).
pub(super) fn max_radius(radius: &[f64]) -> f64 {
    radius.iter().fold(0.0, |m: f64, &r| if m.is_nan() || r.is_nan() { f64::NAN } else { m.max(r) })
}

impl Collisions {
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
}

impl Collisions {
    /// Tiny fleets: the "blocked by" rows, from the flags of the pass over pairs, robot by
    /// robot in id order.
    pub(super) fn tiny_rows(&mut self, ask: &super::blocking::Ask<'_>) {
        let n = ask.x.len();
        let (x, y, radius, wants, alpha) = (&ask.x[..n], &ask.y[..n], &ask.radius[..n], &ask.wants[..n], &ask.alpha[..n]);
        let (uniform, margin, angle) = (ask.uniform, ask.margin, ask.angle);
        let space = &self.space;
        let (cell_of, by_cell, sx, sy, sr, bits) =
            (&space.cell_of[..n], &space.by_cell[..], &space.sx[..], &space.sy[..], &space.sr[..if uniform { 0 } else { n }], &space.bits[..]);
        let g = &mut self.graph;
        g.start.clear();
        g.to.clear();
        g.blocked.clear();
        // Every flag clear (most steps of the paper's runs): nobody stands within reach of
        // anybody, so nobody is blocked and there is nothing to test.
        let clear = space.clear;
        // Robots in the pass are placed in id order: `p` is the place of robot `i`.
        let mut p = 0;
        for i in 0..n {
            let before = g.to.len();
            g.start.push(before as u32);
            if cell_of[i] == u32::MAX {
                continue;
            }
            p += 1;
            if clear || !wants[i] {
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
                if near(k) && super::blocks(xi, yi, a, sx[k], sy[k], contact(k), angle) {
                    g.to.push(by_cell[k]);
                }
            }
            if g.to.len() > before {
                g.blocked.push(i as u32);
            }
        }
        g.start.push(g.to.len() as u32);
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
