//! Collision waiting (spec phase 3, paper III-C), and the contact count after the moves.
//! The folder holds the rule (`blocks`, here), the grid and tiny fleets' pass over pairs
//! (`grid.rs`), the sorted index of larger fleets (`index.rs`), neighbour lists with a skin
//! for larger fleets under way (`lists.rs`), the "blocked by" graph and who of the blocked is
//! released (`blocking.rs`, `cycles.rs`), and the contacts (`contacts.rs`).
//!
//! Robot `i`, wanting to move with heading α, is blocked by robot `j` when
//! `dist(i, j) <= r_i + r_j + margin` and the angle between α and the bearing to `j`, folded
//! into [0°, 180°], is under the collision angle (30°); `dist = 0` always blocks. In each
//! strongly connected component of two or more robots of the "blocked by" graph, the robot
//! with the smallest id is released. Everyone else who is blocked waits.
//!
//! Candidates come from a uniform grid whose cells are twice the `reach` given to
//! [`Collisions::new`] wide (the largest contact distance; wider where the cell count is
//! capped), so the cost grows with N, not N². Fleets beyond [`TINY`] robots keep every robot
//! in an index sorted by cell and repaired from step to step (`index.rs`), and keep the
//! "blocked by" graph too, finding again only the rows of robots that changed or stand near
//! one that moved (`blocking.rs`); the contact count is kept the same way (`contacts.rs`).
//! In a jam, where most robots stand, that is most of the work saved. Where most robots move
//! (a fleet under way), a fleet that asked for them ([`Collisions::keep_lists`]: the paper
//! rules do) reads its pairs from neighbour lists instead, built again from an index only
//! every few steps (`lists.rs`), and goes back to the index once fewer than one robot in
//! eight moves. The speed-ups are
//! exact: shortcuts (distances along the axes, the "clearly far" filter) only skip work whose
//! outcome is certain, `blocks` decides every case near a boundary, and a kept graph or count
//! equals a fresh one, so results are bit-identical to the brute-force definition (tested in
//! `tests/collision_grid.rs` and `tests/contacts.rs`). All buffers live in [`Collisions`] and
//! are reused from step to step.

use crate::fleet::motion::{bearing, folded_angle};

/// Whether a robot at `(xi, yi)` heading `alpha` is blocked by one at `(xj, yj)`.
#[inline]
#[must_use]
pub fn blocks(xi: f64, yi: f64, alpha: f64, xj: f64, yj: f64, reach: f64, angle: f64) -> bool {
    let (dx, dy) = (xj - xi, yj - yi);
    let d = crate::fleet::motion::axis_dist(dx, dy);
    if d > reach {
        return false;
    }
    if d == 0.0 {
        return true;
    }
    folded_angle(alpha, bearing(dx, dy)) < angle
}

mod blocking;
mod contacts;
mod cycles;
mod grid;
mod index;
mod lists;

/// The lists give way to the index when fewer than one robot in this many moves (and take
/// over again when more than one in four does, `index.rs`).
const SWITCH: usize = 8;

/// Fleets of at most this many robots use no cells (see [`Collisions`]): with 32 robots a
/// pass over all of them is as cheap as reading a few cells.
const TINY: usize = 32;

use blocking::{Ask, Blocking};
use contacts::Touching;
use grid::{max_radius, Grid, Space};
use index::Index;
use lists::Lists;

/// Reusable state of the collision phase: tiny fleets' pass over pairs ([`Space`],
/// `grid.rs`) or larger fleets' sorted index ([`Index`], `index.rs`), the "blocked by" graph
/// with its release of cycles ([`Blocking`], `blocking.rs`, `cycles.rs`), and the contacts
/// kept from the last count (`contacts.rs`).
#[derive(Clone, Debug, Default)]
pub struct Collisions {
    space: Space,
    index: Index,
    graph: Blocking,
    touching: Touching,
    /// The margin of the last [`Collisions::resolve`] (0 before it).
    margin: f64,
    /// Tiny fleets: the widest distance [`Collisions::contacts`] has looked at.
    contact_need: f64,
    /// `closest` counts pairs within `r_i + r_j` plus this (infinite: every pair looked at).
    closest_within: f64,
    /// Tiny fleets, [`Collisions::contacts_of_every_pair`]: who is in the pass and who is in
    /// a bay, and the robots in bays by cell.
    in_grid: Vec<bool>,
    in_bay: Vec<bool>,
    bays_by_cell: Vec<(u64, u32)>,
    /// Neighbour lists with a skin, for larger fleets that asked for them
    /// ([`Collisions::keep_lists`]); `None`: the index's way alone.
    lists: Option<Box<Lists>>,
    /// With lists: whether they serve now. They do while most robots move, and the index
    /// (whose kept graph is cheaper where few move: queues, jams) while few do.
    listing: bool,
    /// With lists: the index has not followed the robots since the lists took over, and
    /// where they stood and who stood in a bay at the last [`Collisions::resolve`] or
    /// [`Collisions::build_grid`], which the index is to follow them to
    /// ([`Collisions::contacts_within`] reads the index as of then).
    index_behind: bool,
    seen_x: Vec<f64>,
    seen_y: Vec<f64>,
    bays_seen: Vec<bool>,
    /// Output: robots that wait this step.
    pub waits: Vec<bool>,
}

impl Collisions {
    /// A grid over the rectangle `[x0, x1] × [y0, y1]` that robots never leave, with cells
    /// of side `reach` (the largest contact distance).
    #[must_use]
    pub fn new(bounds: [f64; 4], reach: f64, robots: usize) -> Collisions {
        // Cells twice the contact distance wide: a box of half-width `reach` around a robot
        // then overlaps at most 2 × 2 cells, and a pair within reach stands in one cell or in
        // two neighbouring ones.
        let grid = Grid::over(bounds, 2.0 * reach.max(1e-6));
        let tiny = robots <= TINY;
        Collisions {
            space: Space {
                grid,
                reach: reach.max(1e-6) * (1.0 + 1e-9) + 1e-9,
                far_coordinate: bounds.iter().fold(0.0, |m: f64, b| m.max(b.abs())),
                cell_of: if tiny { vec![0; robots] } else { Vec::new() },
                tiny,
                bits: if tiny { vec![0; robots] } else { Vec::new() },
                cover: 0.0,
                apart: grid::Apart::default(),
                clear: false,
                placed: 0,
                by_cell: if tiny { vec![0; robots] } else { Vec::new() },
                sx: if tiny { vec![0.0; robots] } else { Vec::new() },
                sy: if tiny { vec![0.0; robots] } else { Vec::new() },
                sr: Vec::new(),
            },
            index: Index::default(),
            graph: Blocking::default(),
            touching: Touching::default(),
            margin: 0.0,
            contact_need: 0.0,
            closest_within: f64::INFINITY,
            in_grid: Vec::new(),
            in_bay: Vec::new(),
            bays_by_cell: Vec::new(),
            lists: None,
            listing: false,
            index_behind: false,
            seen_x: Vec::new(),
            seen_y: Vec::new(),
            bays_seen: Vec::new(),
            waits: vec![false; robots],
        }
    }

    /// Finds pairs from neighbour lists with a skin (`lists.rs`) rather than the index, for a
    /// fleet beyond a few dozen robots (tiny fleets keep their pass over pairs): cheaper where
    /// most robots move every step, and the same results. `bounds` as for
    /// [`Collisions::new`].
    pub fn keep_lists(&mut self, bounds: [f64; 4]) {
        if !self.space.tiny {
            self.lists = Some(Box::new(Lists::new(bounds)));
            self.listing = true;
        }
    }

    /// Whether neighbour lists serve now, for robots of radii up to `r_max` and this
    /// `margin` (a finite contact distance, and no margin below zero: the lists' reach is
    /// reckoned from the contact distance).
    fn listed(&self, r_max: f64, margin: f64) -> bool {
        self.listing && margin >= 0.0 && (2.0 * r_max + margin).is_finite()
    }

    /// With lists, the index is left behind: where the robots stand and who stands in a bay,
    /// for the index to follow them to when [`Collisions::contacts_within`] reads it.
    fn leave_index(&mut self, x: &[f64], y: &[f64], bay: &[bool]) {
        self.index_behind = true;
        self.seen_x.clear();
        self.seen_x.extend_from_slice(x);
        self.seen_y.clear();
        self.seen_y.extend_from_slice(y);
        self.bays_seen.clear();
        self.bays_seen.extend_from_slice(bay);
    }

    /// Where the lists served and the index was left behind, it follows the robots to where
    /// they stood then (before the moves, as without lists).
    fn catch_up_index(&mut self) {
        if std::mem::take(&mut self.index_behind) {
            self.index.refresh(&self.space.grid, &self.seen_x, &self.seen_y, Some(&self.bays_seen), None);
        }
    }

    /// Brings the robots' places up to date, robots in a bay (`bay[i]`; empty: nobody)
    /// aside; returns whether the fleet shares one radius. [`Collisions::resolve`] does it
    /// too; [`Collisions::contacts`] reads the places as they were before the moves.
    pub fn build_grid(&mut self, x: &[f64], y: &[f64], radius: &[f64], bay: &[bool]) -> bool {
        let n = x.len();
        let radius = &radius[..n];
        // One radius for the whole fleet (the usual case): one contact distance, and no
        // radii to copy or read per candidate.
        let uniform = radius.iter().all(|&r| r == radius[0]);
        if self.space.tiny {
            self.tiny_places(x, y, radius, bay, uniform);
        } else if self.listing {
            self.leave_index(x, &y[..n], bay);
        } else {
            self.index.refresh(&self.space.grid, x, y, Some(bay), None);
        }
        uniform
    }

    /// Tiny fleets: the robots out of bays in id order, and the pass over pairs.
    fn tiny_places(&mut self, x: &[f64], y: &[f64], radius: &[f64], bay: &[bool], uniform: bool) {
        let n = x.len();
        let bay: &[bool] = if bay.is_empty() { &[] } else { &bay[..n] };
        let cell_of = &mut self.space.cell_of[..n];
        let mut placed = 0;
        for i in 0..n {
            let aside = !bay.is_empty() && bay[i];
            // No cells: any mark but "in a bay" will do.
            cell_of[i] = if aside { u32::MAX } else { 0 };
            placed += usize::from(!aside);
        }
        if !uniform && self.space.sr.len() < n {
            self.space.sr.resize(n, 0.0);
        }
        self.space.placed = placed;
        self.copy_placed(x, y, radius, uniform);
    }

    /// For how many steps from now collision waiting surely blocks nobody and
    /// [`Collisions::contacts_within`] (with `r_max` and `slack`) surely finds no pair: steps
    /// in which nobody comes near anybody. The robots stand at `x`, `y` now; robot `i`
    /// travels at most `speed[i]` along its route a step where `moving[i]` and stands
    /// otherwise, and `slack` is at least twice every speed. A robot alone: always. Tiny
    /// fleets: by a pass over the pairs. 0 for any other fleet. Robots that step into or out
    /// of a bay move sideways, past `speed`: a fleet with bays must not ask (cruising, the
    /// one caller, never runs under spread placement).
    ///
    /// Two robots `d` apart now are at least `d - (j - 1) (speed_a + speed_b)` apart when
    /// step `j` starts (each speed with what rounding can add to a move). While that exceeds
    /// the flags' reach `cover` (as the step's own pass over pairs would set it, with a slack
    /// far above rounding), the step's pass would flag no pair, so nobody could block
    /// anybody; and every robot, moving less than the contact count allows for, would find
    /// nobody near after the moves either.
    #[must_use]
    #[allow(clippy::too_many_arguments)]
    pub fn quiet_steps(&self, x: &[f64], y: &[f64], radius: &[f64], speed: &[f64], moving: &[bool], r_max: f64, slack: f64) -> u64 {
        let n = x.len();
        if n < 2 {
            return u64::MAX;
        }
        // The contact count's reach has grown to what these moves need (it has once a count
        // has run), so the steps' counts look no wider than `cover`.
        let wide_enough = self.contact_need >= contacts::contact_need(r_max, slack);
        if !self.space.tiny || n > TINY || !wide_enough {
            return 0;
        }
        let (y, speed, moving) = (&y[..n], &speed[..n], &moving[..n]);
        // A move of `speed` lands on the nearest float: it can go a little farther, by up to
        // half a unit in the last place of each coordinate, the same way every step (far
        // from the origin with a tiny speed, that adds up over a long run of steps).
        let rounding = 4.0 * f64::EPSILON * self.space.far_coordinate;
        let travel = |i: usize| if moving[i] { speed[i] * (1.0 + 4.0 * f64::EPSILON) + rounding } else { 0.0 };
        let apart = self.cover_of(&radius[..n]) * 1.001 + 1e-6;
        let mut k = u64::MAX;
        for a in 0..n {
            for b in a + 1..n {
                let (dx, dy) = (x[b] - x[a], y[b] - y[a]);
                let d = (dx * dx + dy * dy).sqrt();
                // Near already, or a NaN.
                let far = d > apart;
                if !far {
                    return 0;
                }
                let closing = travel(a) + travel(b);
                if closing > 0.0 {
                    // Steps `j` with `(j - 1) closing` well short of the room: one more than
                    // the room allows for, a millionth of it kept back.
                    let room = ((d - apart) * (1.0 - 1e-6) - 1e-6).max(0.0);
                    let more = room / closing;
                    k = k.min(if more >= 1e18 { u64::MAX } else { 1 + more as u64 });
                }
            }
        }
        k
    }

    /// Decides who waits. `alpha[i]` is used only where `wants[i]`; robots in a bay (`bay[i]`,
    /// an extension for large fleets, docs/model.md section 7; empty: nobody, the paper)
    /// neither block nor wait; `margin` widens every contact distance and `angle` is the
    /// collision angle in radians. Fills `self.waits`.
    #[allow(clippy::too_many_arguments)]
    pub fn resolve(&mut self, x: &[f64], y: &[f64], radius: &[f64], wants: &[bool], alpha: &[f64], bay: &[bool], margin: f64, angle: f64) {
        let n = x.len();
        // Slices of exactly `n`: indexing by `i < n` then needs no bounds checks.
        let (y, radius, wants, alpha) = (&y[..n], &radius[..n], &wants[..n], &alpha[..n]);
        // A robot alone is never blocked (the paper's N = 1 runs: 40% of its steps).
        let nobody = n < 2 || !wants.contains(&true);
        let uniform = radius.iter().all(|&r| r == radius[0]);
        let r_max = if uniform { radius.first().copied().unwrap_or(0.0) } else { max_radius(radius) };
        // Lists serve where they can (positions not finite: the index's way).
        let listed = !self.space.tiny && self.listed(r_max, margin) && (nobody || self.lists.as_deref_mut().expect("listed").ready(x, y, 2.0 * r_max + margin));
        if listed {
            self.leave_index(x, y, bay);
        } else if !self.space.tiny {
            self.index_behind = false;
            // The index follows every step, so that the next step sees what moved since; the
            // wishes only where the graph follows them too.
            let wishes = (!nobody).then_some(index::Wishes { wants, alpha });
            self.index.refresh(&self.space.grid, x, y, Some(bay), wishes);
        }
        if nobody {
            self.waits[..n].fill(false);
            return;
        }
        self.margin = margin;
        if self.graph.start.len() != n + 1 {
            self.graph.reset(n);
        }
        let ask = Ask { x, y, radius, wants, alpha, bay, margin, angle, r_max, uniform };
        if listed {
            let lists = self.lists.as_deref().expect("listed");
            self.graph.rows_of_pairs(&lists.pairs, &ask);
            self.graph.release_spans(&mut self.waits[..n]);
            // Back to the index once fewer than one robot in eight moves (robots in bays
            // that want to move count as moving: it only decides which way is cheaper).
            let wanting = wants.iter().filter(|&&w| w).count();
            let waiting = self.graph.blocked.len() - self.graph.released.len();
            self.listing = (wanting - waiting) * SWITCH > n;
            return;
        }
        if self.space.tiny {
            self.tiny_places(x, y, radius, bay, uniform);
            self.tiny_rows(&ask);
        } else if (2.0 * r_max + margin).is_nan() {
            self.graph.every_pair(&ask);
        } else {
            self.graph.update(&mut self.index, &self.space.grid, &ask);
            self.graph.release_kept(&mut self.waits[..n]);
            // To the lists once more than a quarter of the fleet moved since the last step.
            self.listing = self.lists.is_some() && self.index.sweeping;
            return;
        }
        self.graph.release(&mut self.waits[..n]);
    }
}

#[cfg(test)]
mod tests;
