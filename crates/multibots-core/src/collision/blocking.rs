//! The "blocked by" graph of the collision phase (spec phase 3): which robots block which
//! this step, who of the blocked is released (`cycles.rs`), and so who waits.

use super::grid::{self, span};
use super::{blocks, Collisions};
use std::f64::consts::{FRAC_PI_2, PI};

/// "Blocked by" graph in compressed rows, over the blocked robots only: row `s` is robot
/// `blocked[s]`'s blockers, `edge_to[edge_start[s]..edge_start[s + 1]]` (robot ids), with
/// the scratch of the search for cycles.
#[derive(Clone, Debug, Default)]
pub(super) struct Blocking {
    pub(super) edge_start: Vec<u32>,
    pub(super) edge_to: Vec<u32>,
    /// The blocked robots as bits of their ids (all clear between steps), and for each byte
    /// of bits how many are blocked in the bytes before it: a robot's place in `blocked`
    /// is a count of bits (`place`), with no per-robot column.
    pub(super) blocked_bits: Vec<u8>,
    pub(super) rank: Vec<u32>,
    /// "Blocked by" edges from the pairs, `(from, to)`, before they are sorted into rows.
    pub(super) pair_edges: Vec<(u32, u32)>,
    /// Where the next edge of each row goes, while they are sorted into rows.
    pub(super) cursor: Vec<u32>,
    // Tarjan's algorithm, iterative, by place in `blocked`.
    pub(super) index: Vec<u32>,
    pub(super) low: Vec<u32>,
    pub(super) on_stack: Vec<bool>,
    pub(super) stack: Vec<u32>,
    pub(super) call: Vec<(u32, u32)>,
    pub(super) released: Vec<bool>,
    /// Robots with at least one blocker this step, ascending.
    pub(super) blocked: Vec<u32>,
}

/// Robot `i`'s place among the robots marked in `bits`, with `rank` counting the marks of
/// the bytes before each; `u32::MAX` if `i` is not marked. Bytes and a table rather than
/// words and `count_ones`: without a CPU feature the build does not assume, that is a
/// dozen instructions, and the release asks once for every edge.
#[inline]
pub(super) fn place(bits: &[u8], rank: &[u32], i: usize) -> u32 {
    let (b, bit) = (bits[i >> 3], 1u8 << (i & 7));
    if b & bit == 0 {
        u32::MAX
    } else {
        rank[i >> 3] + u32::from(ONES[usize::from(b & (bit - 1))])
    }
}

/// The number of bits set in each byte.
const ONES: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut b = 0;
    while b < 256 {
        t[b] = (b as u8).count_ones() as u8;
        b += 1;
    }
    t
};

impl Collisions {
    /// Who of the blocked robots waits: all but the released, from this step's edges (and
    /// the places that [`Collisions::rank_blocked`] counted for them).
    pub(super) fn release_blocked(&mut self) {
        if self.graph.edge_to.is_empty() {
            return;
        }
        // Only robots that are blocked can wait, or lie on a cycle: the rest of the step's
        // work is in proportion to them, not to the fleet.
        self.release_cycles();
        for (&i, &released) in self.graph.blocked.iter().zip(&self.graph.released) {
            let i = i as usize;
            self.waits[i] = !released;
            // Back to the resting state for the next step.
            self.graph.blocked_bits[i >> 3] = 0;
        }
    }

    /// Counts the blocked robots byte by byte of `blocked_bits`, for [`Collisions::place`].
    pub(super) fn rank_blocked(&mut self) {
        let mut total = 0;
        for (r, &b) in self.graph.rank.iter_mut().zip(&self.graph.blocked_bits) {
            *r = total;
            total += u32::from(ONES[usize::from(b)]);
        }
    }

    /// Robot `i`'s place in `blocked` (ascending ids), `u32::MAX` if it is not blocked.
    /// Needs [`Collisions::rank_blocked`] after the last robot was marked.
    #[inline]
    pub(super) fn place(&self, i: usize) -> u32 {
        place(&self.graph.blocked_bits, &self.graph.rank, i)
    }
}

impl Collisions {
    /// The "blocked by" edges of robots that want to move, each found from its own search
    /// box in the sorted order (tiny fleets: from the flags of the pass over pairs), where
    /// the pairs of `pairs.rs` do not stand in for the boxes; then the places of the blocked.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn edges_from_boxes(&mut self, x: &[f64], y: &[f64], radius: &[f64], wants: &[bool], alpha: &[f64], uniform: bool, margin: f64, angle: f64) {
        let n = x.len();
        let (y, radius, wants, alpha) = (&y[..n], &radius[..n], &wants[..n], &alpha[..n]);
        let (grid, tiny) = (self.space.grid, self.space.tiny);
        // Borrowed field by field: the edges below are written while the runs are read.
        let runs = grid::Runs { first: &self.space.first, stamp: &self.space.stamp, start: &self.space.start, end: &self.space.end, epoch: self.space.epoch };
        let cell_of = &self.space.cell_of[..n];
        let (by_cell, sx, sy, sr) = (&self.space.by_cell[..n], &self.space.sx[..n], &self.space.sy[..n], &self.space.sr[..if uniform { 0 } else { n }]);

        // Half-width of the cone's box across the heading, with slack above rounding; both
        // in grid units, about half a cell (a hair more, so a box can touch three cells of a
        // row: `run` takes any number).
        let narrow = angle <= FRAC_PI_2;
        let h = self.space.reach * grid.inv_size;
        if self.sin_angle.0.to_bits() != angle.to_bits() {
            self.sin_angle = (angle, angle.sin());
        }
        let w = (self.space.reach * self.sin_angle.1 * 1.000_001 + 1e-9) * grid.inv_size;
        // Build the "blocked by" edges (in no particular order: the components, and so who
        // is released, do not depend on it).
        let (edge_to, edge_start, blocked, bits_of_blocked) =
            (&mut self.graph.edge_to, &mut self.graph.edge_start, &mut self.graph.blocked, &mut self.graph.blocked_bits[..]);
        edge_to.clear();
        edge_start.clear();
        blocked.clear();
        // Robot `i`, whose edges start at `before`, is blocked if it has any: it takes the next
        // place (robots come in id order, so `blocked` is ascending).
        let mut row = |i: usize, before: usize, after: usize| {
            if after > before {
                bits_of_blocked[i >> 3] |= 1 << (i & 7);
                blocked.push(i as u32);
                edge_start.push(before as u32);
            }
        };
        // Tiny fleets with every flag clear (most steps of the paper's runs): nobody stands
        // within reach of anybody, so nobody is blocked and there is nothing to test.
        if tiny && !self.space.clear {
            let bits = &self.space.bits[..];
            // Robots in the grid are placed in id order: `p` is the place of robot `i`.
            let mut p = 0;
            for i in 0..n {
                if cell_of[i] == u32::MAX {
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
                let before = edge_to.len();
                let mut mask = bits[p - 1];
                while mask != 0 {
                    let k = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if near(k) && blocks(xi, yi, a, sx[k], sy[k], contact(k), angle) {
                        edge_to.push(by_cell[k]);
                    }
                }
                row(i, before, edge_to.len());
            }
        } else if !tiny {
            for i in 0..n {
                if !wants[i] || cell_of[i] == u32::MAX {
                    continue;
                }
                // Only robots in the cone ahead can block. Moving along an aisle (heading exactly
                // along an axis) with a cone of at most 90°, the cone lies in a box `reach` long
                // ahead and `reach · sin(angle)` to each side (the robot's own point included, for
                // dist = 0): fewer cells to read. Other headings search the whole square.
                let (xi, yi, a) = (x[i], y[i], alpha[i]);
                // The box's reach left, right, down and up of the robot.
                let (l, r, d, u) = if !narrow {
                    (h, h, h, h)
                } else if a == 0.0 {
                    (0.0, h, w, w)
                } else if a == PI || a == -PI {
                    (h, 0.0, w, w)
                } else if a == FRAC_PI_2 {
                    (w, w, 0.0, h)
                } else if a == -FRAC_PI_2 {
                    (w, w, h, 0.0)
                } else {
                    (h, h, h, h)
                };
                let ri = radius[i];
                // Clearly out of reach (with a relative slack far above rounding): skip the
                // square root and the angle. Near the boundary, `blocks` decides exactly.
                let contact = |k: usize| if uniform { ri + ri + margin } else { ri + sr[k] + margin };
                let near = |k: usize| {
                    let r = contact(k);
                    let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                    let far = dx * dx + dy * dy > r * r * 1.000_001;
                    // 1 or 0, combined without a branch.
                    u64::from(!far) & u64::from(by_cell[k] as usize != i)
                };
                // One or two rows; in each, the box's one or two cells are one run of robots.
                let (tx, ty) = grid.scaled(xi, yi);
                let (cx, cy) = grid.cell(tx, ty);
                let (gx0, gx1) = span(tx, cx, l, r);
                let (gy0, gy1) = span(ty, cy, d, u);
                let before = edge_to.len();
                let (mut cells, last_cells) = (gy0 * grid.cols, gy1 * grid.cols);
                loop {
                    let (k0, k1) = runs.of(cells + gx0, cells + gx1);
                    if k1 - k0 <= 64 {
                        // Most candidates are far: flag the near ones without a branch each (the
                        // outcome is hard to predict), then test only those.
                        let mut mask = 0u64;
                        for k in k0..k1 {
                            mask |= near(k) << (k - k0);
                        }
                        while mask != 0 {
                            let k = k0 + mask.trailing_zeros() as usize;
                            mask &= mask - 1;
                            if blocks(xi, yi, a, sx[k], sy[k], contact(k), angle) {
                                edge_to.push(by_cell[k]);
                            }
                        }
                    } else {
                        for k in k0..k1 {
                            if near(k) == 1 && blocks(xi, yi, a, sx[k], sy[k], contact(k), angle) {
                                edge_to.push(by_cell[k]);
                            }
                        }
                    }
                    if cells == last_cells {
                        break;
                    }
                    cells += grid.cols;
                }
                row(i, before, edge_to.len());
            }
        }
        edge_start.push(edge_to.len() as u32);
        if !self.graph.edge_to.is_empty() {
            self.rank_blocked();
        }
    }
}
