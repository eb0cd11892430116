//! Collision waiting (spec phase 3, paper III-C), and the contact count after the moves.
//! The folder holds the rule (`blocks`, here), the spatial index the robots are sorted into
//! (`grid.rs`), the pairs of neighbours found in it (`pairs.rs`), the "blocked by" graph
//! and who of the blocked is released (`blocking.rs`, `cycles.rs`), and the contacts
//! (`contacts.rs`).
//!
//! Robot `i`, wanting to move with heading α, is blocked by robot `j` when
//! `dist(i, j) <= r_i + r_j + margin` and the angle between α and the bearing to `j`, folded
//! into [0°, 180°], is under the collision angle (30°); `dist = 0` always blocks. In each
//! strongly connected component of two or more robots of the "blocked by" graph, the robot
//! with the smallest id is released. Everyone else who is blocked waits.
//!
//! Candidates come from a uniform grid whose cells are twice the `reach` given to
//! [`Collisions::new`] wide (the largest contact distance; wider where the cell count is
//! capped), so the cost grows with N, not N². Each step the robots are sorted by cell, with
//! their positions copied alongside, so the cells a search box covers in a grid row are one
//! contiguous run. In a dense grid the pairs of neighbouring robots are found once from the
//! sorted order instead of a box per robot (`pairs.rs`), and the contact count after the
//! moves reads the same pairs. The speed-ups are exact: shortcuts (distances along the axes,
//! the cone box, the "clearly far" filter) only skip work whose outcome is certain, and
//! `blocks` decides every case near a boundary, so results are bit-identical to the
//! brute-force definition (tested in `tests/collision_grid.rs`) as long as every contact
//! distance is within `reach`. All buffers live in [`Collisions`] and are reused from step
//! to step.

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
mod pairs;

/// Fleets of at most this many robots use no cells (see [`Collisions`]): with 32 robots a
/// pass over all of them is as cheap as reading a few cells.
const TINY: usize = 32;

use blocking::Blocking;
use grid::{Grid, Space};
use pairs::Near;

/// Reusable state of the collision phase, in three parts: the spatial index that sorts the
/// robots into the grid ([`Space`], `grid.rs`), the pairs of neighbours found in it
/// ([`Near`], `pairs.rs`), and the "blocked by" graph with its release of cycles
/// ([`Blocking`], `blocking.rs`, `cycles.rs`). The contact count (`contacts.rs`) reads the
/// first two.
#[derive(Clone, Debug, Default)]
pub struct Collisions {
    space: Space,
    near: Near,
    graph: Blocking,
    /// The margin of the last [`Collisions::resolve`] (0 before it).
    margin: f64,
    /// Tiny fleets: the widest distance [`Collisions::contacts`] has looked at.
    contact_need: f64,
    /// `closest` counts pairs within `r_i + r_j` plus this (infinite: every pair looked at).
    closest_within: f64,
    /// [`Collisions::contacts_of_every_pair`]'s buffers: who is in the grid, who is in a bay,
    /// and the robots in bays by cell.
    in_grid: Vec<bool>,
    in_bay: Vec<bool>,
    bays_by_cell: Vec<(u64, u32)>,
    /// The last collision angle and its sine (the same every step).
    sin_angle: (f64, f64),
    /// Output: robots that wait this step.
    pub waits: Vec<bool>,
}

impl Collisions {
    /// A grid over the rectangle `[x0, x1] × [y0, y1]` that robots never leave, with cells
    /// of side `reach` (the largest contact distance).
    #[must_use]
    pub fn new(bounds: [f64; 4], reach: f64, robots: usize) -> Collisions {
        // Cells twice the contact distance wide: the box of half-width `reach` around a robot
        // then overlaps at most 2 × 2 cells (4 list heads to read instead of 9), and the grid
        // is 4 times smaller, so it stays in cache.
        let (w, h) = ((bounds[2] - bounds[0]).max(0.0), (bounds[3] - bounds[1]).max(0.0));
        // Tiny robots in a big warehouse would want billions of cells: past the limit the
        // cells grow, which only adds candidates (every test is still `blocks`).
        let size = (2.0 * reach.max(1e-6)).max((w * h / crate::input::limits::MAX_GRID_CELLS as f64).sqrt() * 1.01);
        // One free cell on every side: a search box never reaches past the grid.
        let cols = (((bounds[2] - bounds[0]) / size).ceil() as usize).max(1) + 3;
        let rows = (((bounds[3] - bounds[1]) / size).ceil() as usize).max(1) + 3;
        let last = |k: usize| i32::try_from(k - 2).unwrap_or(i32::MAX);
        let cells = cols * rows;
        // Measured at two points: at 6.4 cells per robot (1,000 robots) the counting sort is
        // about 10% faster; at 44 (the paper's 6 robots in 266 cells) keeping the order is
        // about 45% faster. The switch lies between.
        let tiny = robots <= TINY;
        let dense = !tiny && cells <= 16 * robots;
        let sparse = !tiny && !dense;
        Collisions {
            space: Space {
                grid: Grid { x0: bounds[0] - size, y0: bounds[1] - size, inv_size: 1.0 / size, cols, last_col: last(cols), last_row: last(rows) },
                reach: reach.max(1e-6) * (1.0 + 1e-9) + 1e-9,
                far_coordinate: bounds.iter().fold(0.0, |m: f64, b| m.max(b.abs())),
                cell_of: vec![0; robots],
                dense,
                tiny,
                bits: if tiny { vec![0; robots] } else { Vec::new() },
                cover: 0.0,
                apart: grid::Apart::default(),
                clear: false,
                placed: 0,
                first: if dense { vec![0; cells + 1] } else { Vec::new() },
                order: if sparse { (0..robots as u32).collect() } else { Vec::new() },
                epoch: 0,
                stamp: if sparse { vec![0; cells] } else { Vec::new() },
                start: if sparse { vec![0; cells] } else { Vec::new() },
                end: if sparse { vec![0; cells] } else { Vec::new() },
                by_cell: vec![0; robots],
                sx: vec![0.0; robots],
                sy: vec![0.0; robots],
                sr: Vec::new(),
            },
            near: Near::default(),
            graph: Blocking { blocked_bits: vec![0; robots.div_ceil(8)], rank: vec![0; robots.div_ceil(8)], ..Blocking::default() },
            margin: 0.0,
            contact_need: 0.0,
            closest_within: f64::INFINITY,
            in_grid: Vec::new(),
            in_bay: Vec::new(),
            bays_by_cell: Vec::new(),
            sin_angle: (0.0, 0.0),
            waits: vec![false; robots],
        }
    }

    /// Sorts the robots into the grid by their positions, robots in a bay (`bay[i]`; empty:
    /// nobody) aside; returns whether the fleet shares one radius. [`Collisions::resolve`] and
    /// [`Collisions::contacts`] read it.
    pub fn build_grid(&mut self, x: &[f64], y: &[f64], radius: &[f64], bay: &[bool]) -> bool {
        self.sort_into_grid(x, y, radius, bay).0
    }

    /// [`Collisions::build_grid`]; also returns whether a robot in the grid stands at a NaN
    /// coordinate.
    fn sort_into_grid(&mut self, x: &[f64], y: &[f64], radius: &[f64], bay: &[bool]) -> (bool, bool) {
        let n = x.len();
        let (y, radius) = (&y[..n], &radius[..n]);
        self.near.pairs_r2 = 0.0;
        let grid = self.space.grid;
        let bay: &[bool] = if bay.is_empty() { &[] } else { &bay[..n] };
        let cell_of = &mut self.space.cell_of[..n];
        // Every robot can block, so every robot goes into the grid (bays aside).
        let mut placed = 0;
        let mut nan = false;
        for i in 0..n {
            if !bay.is_empty() && bay[i] {
                cell_of[i] = u32::MAX;
                continue;
            }
            placed += 1;
            if self.space.tiny {
                // No cells: any mark but "in a bay" will do.
                cell_of[i] = 0;
                continue;
            }
            nan |= x[i].is_nan() | y[i].is_nan();
            let (tx, ty) = grid.scaled(x[i], y[i]);
            let (cx, cy) = grid.cell(tx, ty);
            cell_of[i] = (cy as usize * grid.cols + cx as usize) as u32;
        }
        // One radius for the whole fleet (the usual case): one contact distance, and no
        // radii to copy or read per candidate.
        let uniform = radius.iter().all(|&r| r == radius[0]);
        if !uniform && self.space.sr.len() < n {
            self.space.sr.resize(n, 0.0);
        }
        self.space.placed = placed;
        if self.space.tiny {
            self.copy_placed(x, y, radius, uniform);
        } else if self.space.dense {
            self.counting_sort(x, y, radius, uniform);
        } else {
            self.repair_order(x, y, radius, uniform, placed);
        }
        (uniform, nan)
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
        self.waits[..n].fill(false);
        self.near.pairs_r2 = 0.0;
        // A robot alone is never blocked (the paper's N = 1 runs: 40% of its steps).
        if n < 2 || !wants.contains(&true) {
            return;
        }
        self.margin = margin;
        let (uniform, nan) = self.sort_into_grid(x, y, radius, bay);
        // A robot at a NaN coordinate lands in a cell of its own choosing: the boxes decide
        // what it finds, as they always did.
        let pairs = if nan { None } else { self.pair_reach2(radius, uniform, margin) };
        if pairs.is_some_and(|r2| self.collect_pairs(r2)) {
            self.edges_from_pairs(wants, alpha, radius, margin, angle);
            self.release_blocked();
            return;
        }
        self.edges_from_boxes(x, y, radius, wants, alpha, uniform, margin, angle);
        self.release_blocked();
    }
}

#[cfg(test)]
mod tests;
