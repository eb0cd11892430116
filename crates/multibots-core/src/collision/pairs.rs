//! Dense grids: the pairs of neighbouring robots, found once a step from the sorted order
//! and shared by the collision test and the contact count.
//!
//! Two robots within a cell's width of each other stand in the same cell or in two
//! neighbouring ones. Each pair is found once, from the cell of the first in grid order: the
//! rest of its cell, the next cell of its row and the three cells below. A robot's own
//! search box costs more than its share of these reads when, as in a crowded warehouse, it
//! holds one or two others: it is computed for every robot that wants to move, in rows that
//! each need their own run.

use super::{blocks, grid::max_radius, Collisions};

/// Pairs kept per robot in the grid (and a few more for small fleets) before a step gives
/// up on the list and falls back to the search boxes: a pile of robots on one spot has
/// pairs in the square of its size, which the boxes test without keeping.
const PAIRS_PER_ROBOT: usize = 32;

/// Dense grids: this step's pairs of neighbouring robots, by place in the sorted order.
#[derive(Clone, Debug, Default)]
pub(super) struct Near {
    /// The pairs of places within `sqrt(pairs_r2)`, `pairs[..pairs_len]` (the buffer only
    /// grows), collected by [`Collisions::resolve`] or by the contact count, and kept until
    /// the next grid is built. `pairs_r2` is 0 when there are none to read (every distance
    /// asked for is wider).
    pub(super) pairs: Vec<(u32, u32)>,
    pub(super) pairs_len: usize,
    pub(super) pairs_r2: f64,
    /// The widest squared distance the contact count has ever looked at, so that the
    /// collision test collects its pairs wide enough for the count to reuse them
    /// (`Collisions::contact_need` is the same for tiny fleets, as a distance).
    pub(super) contact_span2: f64,
}

impl Collisions {
    /// Whether the pairs of this step's grid can stand in for the search boxes, and how wide
    /// to collect them (squared): a dense grid, with every contact distance (the radii and
    /// `margin`) within the boxes' `reach` (wider ones the boxes miss, and so must the
    /// pairs), and the cells wider than that and than the contact count's widest look, with
    /// room for rounding.
    pub(super) fn pair_reach2(&self, radius: &[f64], uniform: bool, margin: f64) -> Option<f64> {
        if !self.space.dense {
            return None;
        }
        let r_max = if uniform { radius[0] } else { max_radius(radius) };
        // The widest contact distance `blocks` is given, and the collision test's filter on
        // it (`d² > r² · 1.000001` is far): contact distances are sums of two radii and the
        // margin, and for values that can block rounding keeps their order.
        let widest = r_max + r_max + margin;
        if widest.is_nan() || widest * (1.0 + 1e-9) + 1e-9 > self.space.reach {
            // NaN: every contact test passes, and the boxes look only so far.
            return None;
        }
        let r2 = (widest * widest * 1.000_001).max(self.near.contact_span2);
        let size = 1.0 / self.space.grid.inv_size;
        (r2.sqrt() * 1.001 < size).then_some(r2)
    }

    /// Collects the pairs of places `k < m` in the sorted order whose positions are not
    /// farther apart than `sqrt(r2)` (a NaN distance counts as near): every pair within the
    /// cell size, less rounding, is among them. They stay for the contact count after the
    /// moves, until the next grid is built. `false`, with no pairs kept, where there would
    /// be more than `PAIRS_PER_ROBOT` a robot.
    pub(super) fn collect_pairs(&mut self, r2: f64) -> bool {
        self.near.pairs_r2 = 0.0;
        let placed = self.space.placed;
        let cols = self.space.grid.cols;
        let (first, by_cell, sx, sy, cell_of) =
            (&self.space.first[..], &self.space.by_cell[..placed], &self.space.sx[..placed], &self.space.sy[..placed], &self.space.cell_of[..]);
        // Written in place at `len`, which grows by one for a near pair: no branch per
        // candidate (whether it is near is hard to predict). `pairs` only grows.
        let pairs = &mut self.near.pairs;
        let mut len = 0;
        for k in 0..placed {
            let c = cell_of[by_cell[k] as usize] as usize;
            let (px, py) = (sx[k], sy[k]);
            // The grid keeps a free cell on every side: `c + cols + 2` is still a cell index.
            for (m0, m1) in [(k + 1, first[c + 2] as usize), (first[c + cols - 1] as usize, first[c + cols + 2] as usize)] {
                let need = len + m1.saturating_sub(m0);
                if pairs.len() < need {
                    let limit = PAIRS_PER_ROBOT * placed + 1024;
                    if need > limit {
                        return false;
                    }
                    pairs.resize(need.max(2 * pairs.len()).min(limit), (0, 0));
                }
                for m in m0..m1 {
                    let (dx, dy) = (sx[m] - px, sy[m] - py);
                    let far = dx * dx + dy * dy > r2;
                    pairs[len] = (k as u32, m as u32);
                    len += usize::from(!far);
                }
            }
        }
        self.near.pairs_len = len;
        self.near.pairs_r2 = r2;
        true
    }

    /// The "blocked by" edges from this step's pairs: in compressed rows over the blocked
    /// robots, ascending, as the search boxes build them (the order of a row's edges differs;
    /// the components, and so who is released, do not depend on it).
    pub(super) fn edges_from_pairs(&mut self, wants: &[bool], alpha: &[f64], radius: &[f64], margin: f64, angle: f64) {
        let n = wants.len();
        let (alpha, radius) = (&alpha[..n], &radius[..n]);
        let placed = self.space.placed;
        let (by_cell, sx, sy) = (&self.space.by_cell[..placed], &self.space.sx[..placed], &self.space.sy[..placed]);
        let edges = &mut self.graph.pair_edges;
        edges.clear();
        // Which robots have an edge: bits of their ids (all clear between steps).
        let bits = &mut self.graph.blocked_bits;
        for &(k, m) in &self.near.pairs[..self.near.pairs_len] {
            let (k, m) = (k as usize, m as usize);
            let (i, j) = (by_cell[k] as usize, by_cell[m] as usize);
            let (wi, wj) = (wants[i], wants[j]);
            if !(wi || wj) {
                continue;
            }
            // The same contact distance and "clearly far" filter as from either robot's box:
            // sums and squared differences do not depend on the order of their operands.
            let r = radius[i] + radius[j] + margin;
            let (dx, dy) = (sx[m] - sx[k], sy[m] - sy[k]);
            if dx * dx + dy * dy > r * r * 1.000_001 {
                continue;
            }
            if wi && blocks(sx[k], sy[k], alpha[i], sx[m], sy[m], r, angle) {
                edges.push((i as u32, j as u32));
                bits[i >> 3] |= 1 << (i & 7);
            }
            if wj && blocks(sx[m], sy[m], alpha[j], sx[k], sy[k], r, angle) {
                edges.push((j as u32, i as u32));
                bits[j >> 3] |= 1 << (j & 7);
            }
        }
        // The blocked robots in ascending order from the bits, then the edges counting-sorted
        // into their rows.
        self.graph.blocked.clear();
        for (w, &byte) in self.graph.blocked_bits.iter().enumerate() {
            let mut b = byte;
            while b != 0 {
                self.graph.blocked.push((w * 8 + b.trailing_zeros() as usize) as u32);
                b &= b - 1;
            }
        }
        self.rank_blocked();
        let mut edge_start = std::mem::take(&mut self.graph.edge_start);
        edge_start.clear();
        edge_start.resize(self.graph.blocked.len() + 1, 0);
        for &(i, _) in &self.graph.pair_edges {
            edge_start[self.place(i as usize) as usize + 1] += 1;
        }
        let mut total = 0;
        for e in &mut edge_start {
            total += *e;
            *e = total;
        }
        let mut cursor = std::mem::take(&mut self.graph.cursor);
        cursor.clear();
        cursor.extend_from_slice(&edge_start[..self.graph.blocked.len()]);
        let mut edge_to = std::mem::take(&mut self.graph.edge_to);
        edge_to.clear();
        edge_to.resize(self.graph.pair_edges.len(), 0);
        for &(i, j) in &self.graph.pair_edges {
            let s = self.place(i as usize) as usize;
            edge_to[cursor[s] as usize] = j;
            cursor[s] += 1;
        }
        (self.graph.edge_start, self.graph.cursor, self.graph.edge_to) = (edge_start, cursor, edge_to);
    }
}
