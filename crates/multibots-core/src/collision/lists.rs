//! Neighbour lists with a skin (Verlet lists, as molecular dynamics keeps them): the pairs of
//! robots that stood within the contact distance plus a skin of each other when the lists
//! were built, kept for as long as no robot has drifted more than half the skin from where it
//! stood then. Two robots within the contact distance of each other now stood within it plus
//! their two drifts then, so every pair the collision test or the contact count can find is
//! in the lists, and both judge the listed pairs by the robots' positions now: the lists only
//! spare the search, never decide.
//!
//! A fleet under way moves every robot a few px a step, so the sorted index (`index.rs`)
//! would have to follow every robot every step; the lists are built again from it only when
//! someone drifted too far (every few steps), and in between a step costs a pass over the
//! robots to check the drift and a pass over the listed pairs. The lists' grid has cells as
//! wide as their reach, so that the index's pass over neighbouring cells finds every pair.

use super::grid::Grid;
use super::index::Index;

/// The skin, as a share of the contact distance: each robot may drift half of it before the
/// lists are built again. Wider, they last longer but list more pairs. Measured (callgrind,
/// the large size's first 500 steps, instructions per robot-step): 384, 355, 358 and 359 for
/// 0.5, 1, 1.5 and 2.
const SKIN: f64 = 1.0;

/// The lists and what they were built from.
#[derive(Clone, Debug)]
pub(super) struct Lists {
    /// The rectangle robots never leave (for the grid).
    bounds: [f64; 4],
    grid: Grid,
    /// The robots as they stood at the last build (`Index::px`, `Index::py` by robot id).
    index: Index,
    /// Pairs of robots (ids) within the lists' reach of each other at the last build, each
    /// once.
    pub(super) pairs: Vec<(u32, u32)>,
    /// The contact distance (bits) and fleet size of the last build; `None` before it.
    built_for: Option<(u64, usize)>,
    /// The square of how far a robot may drift from where it stood at the last build.
    drift2: f64,
    /// Builds so far (tests read it).
    pub(super) builds: u64,
}

impl Lists {
    /// Lists for robots that never leave `bounds`, built at the first [`Lists::ready`].
    pub(super) fn new(bounds: [f64; 4]) -> Lists {
        Lists { bounds, grid: Grid::default(), index: Index::default(), pairs: Vec::new(), built_for: None, drift2: 0.0, builds: 0 }
    }

    /// Makes [`Lists::pairs`] hold every pair of robots at `x`, `y` whose distance is at most
    /// `reach` (a finite contact distance: the largest `r_i + r_j + margin`), building the
    /// lists again if a robot drifted too far since the last build (or the distance or the
    /// fleet changed). `false` where a position is not finite: no list holds the pairs the
    /// definition gives it (a NaN distance), and the caller takes the index's way.
    pub(super) fn ready(&mut self, x: &[f64], y: &[f64], reach: f64) -> bool {
        let n = x.len();
        if self.built_for == Some((reach.to_bits(), n)) && self.within_drift(x, &y[..n]) {
            return true;
        }
        if !x.iter().chain(&y[..n]).all(|v| v.is_finite()) {
            self.built_for = None;
            return false;
        }
        self.build(x, &y[..n], reach);
        true
    }

    /// Whether every robot stands within the drift of where it stood at the last build (a
    /// NaN is not).
    fn within_drift(&self, x: &[f64], y: &[f64]) -> bool {
        let n = x.len();
        let (y, px, py) = (&y[..n], &self.index.px[..n], &self.index.py[..n]);
        let mut ok = true;
        // No early exit: the pass then vectorises, and it nearly always runs to the end.
        for i in 0..n {
            let (dx, dy) = (x[i] - px[i], y[i] - py[i]);
            ok &= dx * dx + dy * dy <= self.drift2;
        }
        ok
    }

    fn build(&mut self, x: &[f64], y: &[f64], reach: f64) {
        let n = x.len();
        let drift = 0.5 * SKIN * reach;
        // A pair within `reach` (as the tests filter it, a hair wider) stands at most two
        // drifts farther apart at the build; the slack is far above rounding.
        let list_reach = (reach * 1.000_001 + 2.0 * drift) * 1.000_001 + 1e-9;
        if self.built_for.map(|(r, _)| r) != Some(reach.to_bits()) {
            // The index's pass finds every pair within a cell's width.
            self.grid = Grid::over(self.bounds, list_reach * 1.01);
            self.index = Index::default();
        }
        self.drift2 = drift * drift;
        self.index.place_all(&self.grid, x, y);
        let (pairs, slots) = (&mut self.pairs, &self.index.slots);
        pairs.clear();
        self.index.pairs(&self.grid, list_reach * list_reach, |k, m| pairs.push((slots[k].robot() as u32, slots[m].robot() as u32)));
        self.built_for = Some((reach.to_bits(), n));
        self.builds += 1;
    }
}
