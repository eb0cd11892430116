//! The "blocked by" graph of the collision phase (spec phase 3): which robots block which
//! this step, who of the blocked is released (`cycles.rs`), and so who waits.

use super::Collisions;

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
