//! Collision waiting (spec phase 3, paper III-C).
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

use std::f64::consts::{FRAC_PI_2, PI, TAU};

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

/// `atan2(dy, dx)`, with the axis-parallel directions of aisles answered without the library
/// call. The shortcuts return exactly what IEEE 754 specifies for `atan2` there (±0, ±π,
/// ±π/2, signs included), so headings are bit-identical either way.
#[inline]
#[must_use]
pub fn bearing(dx: f64, dy: f64) -> f64 {
    if dy == 0.0 && dx > 0.0 {
        dy
    } else if dy == 0.0 && dx < 0.0 {
        PI.copysign(dy)
    } else if dx == 0.0 && dy != 0.0 {
        FRAC_PI_2.copysign(dy)
    } else {
        dy.atan2(dx)
    }
}

/// The angle between two directions, folded into [0, π].
#[inline]
#[must_use]
pub fn folded_angle(a: f64, b: f64) -> f64 {
    // `x % TAU` is `x` below TAU: the common case skips the slow `fmod`.
    let d = (a - b).abs();
    let d = if d < TAU { d } else { d % TAU };
    if d > PI {
        TAU - d
    } else {
        d
    }
}

mod contacts;
mod cycles;
mod grid;
mod pairs;

/// Robot `i`'s place among the robots marked in `bits`, with `rank` counting the marks of
/// the bytes before each; `u32::MAX` if `i` is not marked. Bytes and a table rather than
/// words and `count_ones`: without a CPU feature the build does not assume, that is a
/// dozen instructions, and the release asks once for every edge.
#[inline]
fn place(bits: &[u8], rank: &[u32], i: usize) -> u32 {
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

/// Fleets of at most this many robots use no cells (see [`Collisions`]): with 32 robots a
/// pass over all of them is as cheap as reading a few cells.
const TINY: usize = 32;

use grid::{span, Grid};

/// Reusable state of the collision phase.
#[derive(Clone, Debug, Default)]
pub struct Collisions {
    grid: Grid,
    /// Half-width of the box searched around a robot: the contact distance, a hair wider.
    reach: f64,
    /// Each robot's cell (`u32::MAX`: in a bay, out of the grid). Its column and row are
    /// computed again where needed: two conversions are cheaper than 8 bytes a robot read
    /// from memory.
    cell_of: Vec<u32>,
    // Robots sorted by cell, with their positions and radii copied alongside: the cells of a
    // grid row that a search box covers are one contiguous run, read without chasing links.
    // Two ways to sort, chosen by the grid's size per robot:
    // - dense (a big fleet): a counting sort each step; the robots of cell `c` are
    //   `first[c]..first[c + 1]`. It costs O(cells) per step, cheap when cells are few per
    //   robot.
    // - sparse (a small fleet in a big grid): last step's `order` repaired by insertion sort
    //   (robots seldom change cells), O(N) per step. A cell's run is `start[c]..end[c]`,
    //   valid only when `stamp[c]` is this step's `epoch`; other cells are empty.
    dense: bool,
    // - tiny (a handful of robots, such as the paper's six): no cells at all. Each step one
    //   pass over the pairs of robots in the grid flags, for each, the others within
    //   `cover` of it (`bits`); the collision test and the contact count look only at those.
    //   Robots far apart, as they mostly are, then cost one distance per pair and step. The
    //   tests decide, not the flags, so the results are the same.
    tiny: bool,
    /// Tiny fleets: for the robot in place `k` of `by_cell`, the places of the others that
    /// stood within `cover` of it (a relative slack far above rounding included), as bits.
    bits: Vec<u32>,
    cover: f64,
    /// Tiny fleets: whether the pass over pairs can be skipped (see [`grid::Apart`]).
    apart: grid::Apart,
    /// Tiny fleets: no two robots in the grid stand within `cover` (every flag is clear), so
    /// none blocks another this step.
    clear: bool,
    /// The margin of the last [`Collisions::resolve`] (0 before it).
    margin: f64,
    /// The farthest a coordinate can be from 0 (robots never leave the bounds): rounding
    /// in a move is at most a few units in the last place of it.
    far_coordinate: f64,
    /// Tiny fleets: the widest distance [`Collisions::contacts`] has looked at.
    contact_need: f64,
    /// Robots in the grid (bays aside): `by_cell[..placed]`.
    placed: usize,
    /// The last collision angle and its sine (the same every step).
    sin_angle: (f64, f64),
    first: Vec<u32>,
    order: Vec<u32>,
    epoch: u64,
    stamp: Vec<u64>,
    start: Vec<u32>,
    end: Vec<u32>,
    by_cell: Vec<u32>,
    sx: Vec<f64>,
    sy: Vec<f64>,
    /// Radii, copied only for a fleet of mixed sizes (empty for one radius: then every
    /// contact distance is the same, and no robot reads it).
    sr: Vec<f64>,
    // "Blocked by" graph in compressed rows, over the blocked robots only: row `s` is robot
    // `blocked[s]`'s blockers, `edge_to[edge_start[s]..edge_start[s + 1]]` (robot ids).
    edge_start: Vec<u32>,
    edge_to: Vec<u32>,
    /// The blocked robots as bits of their ids (all clear between steps), and for each byte
    /// of bits how many are blocked in the bytes before it: a robot's place in `blocked`
    /// is a count of bits (`place`), with no per-robot column.
    blocked_bits: Vec<u8>,
    rank: Vec<u32>,
    /// Dense grids: this step's pairs of places within `sqrt(pairs_r2)` (see `pairs.rs`),
    /// `pairs[..pairs_len]` (the buffer only grows), collected by [`Collisions::resolve`] or
    /// by the contact count, and kept until the next grid is built. `pairs_r2` is 0 when
    /// there are none to read (every distance asked for is wider).
    pairs: Vec<(u32, u32)>,
    pairs_len: usize,
    pairs_r2: f64,
    /// Dense grids: the widest squared distance the contact count has ever looked at, so
    /// that the collision test collects its pairs wide enough for the count to reuse them
    /// (`contact_need` is the same for tiny fleets, as a distance).
    contact_span2: f64,
    /// "Blocked by" edges from the pairs, `(from, to)`, before they are sorted into rows.
    pair_edges: Vec<(u32, u32)>,
    /// Where the next edge of each row goes, while they are sorted into rows.
    cursor: Vec<u32>,
    /// Output: robots that wait this step.
    pub waits: Vec<bool>,
    /// Robots standing in a bay beside the aisle (an extension for large fleets, see
    /// docs/model.md section 7): they neither block nor wait. Empty: nobody (the paper).
    pub bay: Vec<bool>,
    // Tarjan's algorithm, iterative, by place in `blocked`.
    index: Vec<u32>,
    low: Vec<u32>,
    on_stack: Vec<bool>,
    stack: Vec<u32>,
    call: Vec<(u32, u32)>,
    released: Vec<bool>,
    /// Robots with at least one blocker this step, ascending.
    blocked: Vec<u32>,
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
            margin: 0.0,
            contact_need: 0.0,
            placed: 0,
            sin_angle: (0.0, 0.0),
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
            edge_start: Vec::new(),
            edge_to: Vec::new(),
            blocked_bits: vec![0; robots.div_ceil(8)],
            rank: vec![0; robots.div_ceil(8)],
            waits: vec![false; robots],
            index: Vec::new(),
            low: Vec::new(),
            on_stack: Vec::new(),
            stack: Vec::new(),
            call: Vec::new(),
            released: Vec::new(),
            blocked: Vec::new(),
            bay: Vec::new(),
            pairs: Vec::new(),
            pairs_len: 0,
            pairs_r2: 0.0,
            contact_span2: 0.0,
            pair_edges: Vec::new(),
            cursor: Vec::new(),
        }
    }

    /// Sorts the robots (bays aside) into the grid by their positions; returns whether the
    /// fleet shares one radius. [`Collisions::resolve`] and [`Collisions::contacts`] read it.
    pub fn build_grid(&mut self, x: &[f64], y: &[f64], radius: &[f64]) -> bool {
        self.sort_into_grid(x, y, radius).0
    }

    /// [`Collisions::build_grid`]; also returns whether a robot in the grid stands at a NaN
    /// coordinate.
    fn sort_into_grid(&mut self, x: &[f64], y: &[f64], radius: &[f64]) -> (bool, bool) {
        let n = x.len();
        let (y, radius) = (&y[..n], &radius[..n]);
        self.pairs_r2 = 0.0;
        let grid = self.grid;
        let bay: &[bool] = if self.bay.is_empty() { &[] } else { &self.bay[..n] };
        let cell_of = &mut self.cell_of[..n];
        // Every robot can block, so every robot goes into the grid (bays aside).
        let mut placed = 0;
        let mut nan = false;
        for i in 0..n {
            if !bay.is_empty() && bay[i] {
                cell_of[i] = u32::MAX;
                continue;
            }
            placed += 1;
            if self.tiny {
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
        if !uniform && self.sr.len() < n {
            self.sr.resize(n, 0.0);
        }
        self.placed = placed;
        if self.tiny {
            self.copy_placed(x, y, radius, uniform);
        } else if self.dense {
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
    /// fleets without bays: by a pass over the pairs. 0 for any other fleet.
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
        if !self.tiny || n > TINY || !self.bay.is_empty() || !wide_enough {
            return 0;
        }
        let (y, speed, moving) = (&y[..n], &speed[..n], &moving[..n]);
        // A move of `speed` lands on the nearest float: it can go a little farther, by up to
        // half a unit in the last place of each coordinate, the same way every step (far
        // from the origin with a tiny speed, that adds up over a long run of steps).
        let rounding = 4.0 * f64::EPSILON * self.far_coordinate;
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

    /// Decides who waits. `alpha[i]` is used only where `wants[i]`; `margin` widens every
    /// contact distance and `angle` is the collision angle in radians. Fills `self.waits`.
    #[allow(clippy::too_many_arguments)]
    pub fn resolve(&mut self, x: &[f64], y: &[f64], radius: &[f64], wants: &[bool], alpha: &[f64], margin: f64, angle: f64) {
        let n = x.len();
        // Slices of exactly `n`: indexing by `i < n` then needs no bounds checks.
        let (y, radius, wants, alpha) = (&y[..n], &radius[..n], &wants[..n], &alpha[..n]);
        self.waits[..n].fill(false);
        self.pairs_r2 = 0.0;
        // A robot alone is never blocked (the paper's N = 1 runs: 40% of its steps).
        if n < 2 || !wants.contains(&true) {
            return;
        }
        self.margin = margin;
        let (uniform, nan) = self.sort_into_grid(x, y, radius);
        // A robot at a NaN coordinate lands in a cell of its own choosing: the boxes decide
        // what it finds, as they always did.
        let pairs = if nan { None } else { self.pair_reach2(radius, uniform, margin) };
        if pairs.is_some_and(|r2| self.collect_pairs(r2)) {
            self.edges_from_pairs(wants, alpha, radius, margin, angle);
            self.release_blocked();
            return;
        }
        let (grid, tiny) = (self.grid, self.tiny);
        // Borrowed field by field: the edges below are written while the runs are read.
        let runs = grid::Runs { first: &self.first, stamp: &self.stamp, start: &self.start, end: &self.end, epoch: self.epoch };
        let cell_of = &self.cell_of[..n];
        let (by_cell, sx, sy, sr) = (&self.by_cell[..n], &self.sx[..n], &self.sy[..n], &self.sr[..if uniform { 0 } else { n }]);

        // Half-width of the cone's box across the heading, with slack above rounding; both
        // in grid units, about half a cell (a hair more, so a box can touch three cells of a
        // row: `run` takes any number).
        let narrow = angle <= FRAC_PI_2;
        let h = self.reach * grid.inv_size;
        if self.sin_angle.0.to_bits() != angle.to_bits() {
            self.sin_angle = (angle, angle.sin());
        }
        let w = (self.reach * self.sin_angle.1 * 1.000_001 + 1e-9) * grid.inv_size;
        // Build the "blocked by" edges (in no particular order: the components, and so who
        // is released, do not depend on it).
        let (edge_to, edge_start, blocked, bits_of_blocked) = (&mut self.edge_to, &mut self.edge_start, &mut self.blocked, &mut self.blocked_bits[..]);
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
        if tiny && !self.clear {
            let bits = &self.bits[..];
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
        if !self.edge_to.is_empty() {
            self.rank_blocked();
        }
        self.release_blocked();
    }

    /// Who of the blocked robots waits: all but the released, from this step's edges (and
    /// the places that [`Collisions::rank_blocked`] counted for them).
    fn release_blocked(&mut self) {
        if self.edge_to.is_empty() {
            return;
        }
        // Only robots that are blocked can wait, or lie on a cycle: the rest of the step's
        // work is in proportion to them, not to the fleet.
        self.release_cycles();
        for (&i, &released) in self.blocked.iter().zip(&self.released) {
            let i = i as usize;
            self.waits[i] = !released;
            // Back to the resting state for the next step.
            self.blocked_bits[i >> 3] = 0;
        }
    }

    /// Counts the blocked robots byte by byte of `blocked_bits`, for [`Collisions::place`].
    fn rank_blocked(&mut self) {
        let mut total = 0;
        for (r, &b) in self.rank.iter_mut().zip(&self.blocked_bits) {
            *r = total;
            total += u32::from(ONES[usize::from(b)]);
        }
    }

    /// Robot `i`'s place in `blocked` (ascending ids), `u32::MAX` if it is not blocked.
    /// Needs [`Collisions::rank_blocked`] after the last robot was marked.
    #[inline]
    fn place(&self, i: usize) -> u32 {
        place(&self.blocked_bits, &self.rank, i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ANGLE: f64 = PI / 6.0;

    fn deg(d: f64) -> f64 {
        d.to_radians()
    }

    #[test]
    fn angle_boundary_just_under_and_just_over_30_degrees() {
        // j at distance 20, bearing 0; i heading 29.9° or 30.1° away from it.
        assert!(blocks(0.0, 0.0, deg(29.9), 20.0, 0.0, 25.0, ANGLE));
        assert!(!blocks(0.0, 0.0, deg(30.1), 20.0, 0.0, 25.0, ANGLE));
        assert!(blocks(0.0, 0.0, deg(-29.9), 20.0, 0.0, 25.0, ANGLE));
        assert!(!blocks(0.0, 0.0, deg(-30.1), 20.0, 0.0, 25.0, ANGLE));
        // Exactly 30° is not "< 30°". A bearing of 30° exactly: j at (cos 30, sin 30)*20.
        assert!(!blocks(0.0, 0.0, 0.0, 20.0 * deg(30.0).cos(), 20.0 * deg(30.0).sin(), 25.0, deg(30.0) - 1e-15));
    }

    #[test]
    fn distance_exactly_the_sum_of_radii_blocks_and_a_hair_more_does_not() {
        assert!(blocks(0.0, 0.0, 0.0, 25.0, 0.0, 12.5 + 12.5, ANGLE));
        assert!(!blocks(0.0, 0.0, 0.0, 25.0 + 1e-9, 0.0, 12.5 + 12.5, ANGLE));
        // 3-4-5: distance exactly 25 off the axis, bearing 36.87°: outside 30°, inside 40°.
        assert!(!blocks(0.0, 0.0, 0.0, 20.0, 15.0, 25.0, ANGLE));
        assert!(blocks(0.0, 0.0, 0.0, 20.0, 15.0, 25.0, deg(40.0)));
        // The margin widens the contact distance.
        assert!(blocks(0.0, 0.0, 0.0, 33.0, 0.0, 25.0 + 8.0, ANGLE));
        assert!(!blocks(0.0, 0.0, 0.0, 33.5, 0.0, 25.0 + 8.0, ANGLE));
    }

    #[test]
    fn shortcuts_agree_with_the_library_bit_for_bit() {
        // Magnitudes from 1e-160 to 1e160 (past the range where the shortcuts apply), both
        // signs, with zeros of both signs in the other coordinate.
        let mut v = 1e-160_f64;
        while v < 1e160 {
            for a in [v, -v, v * 1.000_000_1, -v * 0.999_999_9] {
                for z in [0.0, -0.0] {
                    for (dx, dy) in [(a, z), (z, a)] {
                        assert_eq!(crate::fleet::motion::axis_dist(dx, dy).to_bits(), (dx * dx + dy * dy).sqrt().to_bits(), "dist {dx} {dy}");
                        assert_eq!(bearing(dx, dy).to_bits(), dy.atan2(dx).to_bits(), "bearing {dx} {dy}");
                    }
                }
            }
            v *= 7.3;
        }
        // The folded angle skips `fmod` only below a full turn, where `fmod` is the identity.
        for (a, b) in [(0.0, PI), (-PI, PI), (PI, -PI), (3.0, -3.2), (TAU, 0.0), (7.0, -0.5), (-20.0, 1.0)] {
            let d: f64 = (a - b).abs() % TAU;
            let expect = if d > PI { TAU - d } else { d };
            assert_eq!(folded_angle(a, b).to_bits(), expect.to_bits(), "{a} {b}");
        }
    }

    #[test]
    fn a_nan_margin_or_radius_blocks_as_the_definition_says_in_a_tiny_fleet() {
        // Scenarios refuse them, but the public API takes them: the pass over pairs must
        // not drop a pair that the test itself would accept.
        for (radius, margin) in [([12.5, 12.5], f64::NAN), ([12.5, f64::NAN], 0.0)] {
            let mut c = Collisions::new([-100.0, -100.0, 900.0, 700.0], 25.0, 2);
            c.resolve(&[0.0, 100.0], &[0.0, 0.0], &radius, &[true, false], &[0.0, 0.0], margin, ANGLE);
            let expect = blocks(0.0, 0.0, 0.0, 100.0, 0.0, radius[0] + radius[1] + margin, ANGLE);
            assert!(expect, "the definition lets a NaN contact distance block");
            assert_eq!(c.waits, vec![expect, false], "radius {radius:?}, margin {margin}");
        }
    }

    #[test]
    fn distance_zero_always_blocks() {
        assert!(blocks(5.0, 5.0, deg(135.0), 5.0, 5.0, 25.0, ANGLE));
    }

    #[test]
    fn angles_fold_across_the_seam() {
        // 359° and 1° are 2° apart, not 358°.
        assert!((folded_angle(deg(359.0), deg(1.0)) - deg(2.0)).abs() < 1e-12);
        assert!((folded_angle(deg(-179.0), deg(179.0)) - deg(2.0)).abs() < 1e-12);
        assert!((folded_angle(deg(10.0), deg(190.0)) - PI).abs() < 1e-12);
        // Heading just below +180°, j just past -180° (the same direction, west).
        assert!(blocks(0.0, 0.0, deg(179.0), -20.0, -0.5, 25.0, ANGLE));
    }

    fn run(x: &[f64], y: &[f64], wants: &[bool], alpha: &[f64]) -> Vec<bool> {
        let mut c = Collisions::new([-100.0, -100.0, 900.0, 700.0], 25.0, x.len());
        c.resolve(x, y, &vec![12.5; x.len()], wants, alpha, 0.0, ANGLE);
        c.waits.clone()
    }

    #[test]
    fn head_on_pair_releases_the_smaller_id() {
        // 0 heads east towards 1, 1 heads west towards 0.
        assert_eq!(run(&[100.0, 120.0], &[50.0, 50.0], &[true, true], &[0.0, PI]), vec![false, true]);
        assert_eq!(run(&[120.0, 100.0], &[50.0, 50.0], &[true, true], &[PI, 0.0]), vec![false, true]);
    }

    #[test]
    fn release_is_a_single_pass() {
        // 0 and 1 block each other and 0 is released; 2 is blocked only by 0 (the released
        // one) and still waits; 3 is blocked by 2, which waits, so 3 waits too.
        let x = [120.0, 100.0, 140.0, 160.0];
        let y = [50.0; 4];
        let alpha = [PI, 0.0, PI, PI];
        assert_eq!(run(&x, &y, &[true; 4], &alpha), vec![false, true, true, true]);
    }

    #[test]
    fn three_cycle_releases_its_smallest_id_only() {
        // Three robots around a point, each heading at the next: 2 -> 0 -> 1 -> 2.
        let x: [f64; 3] = [100.0, 120.0, 110.0];
        let y: [f64; 3] = [100.0, 100.0, 100.0 + 17.32];
        let to = |i: usize, j: usize| f64::atan2(y[j] - y[i], x[j] - x[i]);
        let alpha = [to(0, 1), to(1, 2), to(2, 0)];
        assert_eq!(run(&x, &y, &[true; 3], &alpha), vec![false, true, true]);
    }

    #[test]
    fn a_robot_that_does_not_want_to_move_blocks_but_never_waits() {
        let w = run(&[100.0, 120.0], &[50.0, 50.0], &[true, false], &[0.0, PI]);
        assert_eq!(w, vec![true, false]);
    }

    /// Deterministic numbers in [0, 1) (xorshift; no dependency for a test).
    fn uniform(mut s: u64) -> impl FnMut() -> f64 {
        move || (crate::xorshift(&mut s) % 10_000) as f64 / 10_000.0
    }

    #[test]
    fn one_collisions_kept_from_step_to_step_decides_as_a_fresh_one() {
        // The release keeps its marks (`blocked_bits`) only for the step: a kept `Collisions`
        // must decide each step as a new one would, whichever robots were blocked before.
        // Dense clouds with random headings give cycles of every size.
        let mut rnd = uniform(99);
        // Tiny, dense and sparse grids (a few robots in a big box), one radius and mixed.
        for (n, side, mixed) in [(5, 200.0, false), (40, 200.0, false), (300, 200.0, true), (40, 2000.0, false), (60, 2000.0, true)] {
            let bounds = [0.0, 0.0, side, side];
            let mut kept = Collisions::new(bounds, 28.0, n);
            let mut released = 0;
            for step in 0..30 {
                // Every other step crowded into a corner: cycles; else spread out.
                let span = if step % 2 == 0 { 60.0 } else { side };
                let x: Vec<f64> = (0..n).map(|_| rnd() * span).collect();
                let y: Vec<f64> = (0..n).map(|_| rnd() * span).collect();
                let alpha: Vec<f64> = (0..n).map(|_| rnd() * TAU - PI).collect();
                let wants: Vec<bool> = (0..n).map(|_| rnd() < 0.8).collect();
                let radius: Vec<f64> = (0..n).map(|_| if mixed { 8.0 + 6.0 * rnd() } else { 12.5 }).collect();
                kept.resolve(&x, &y, &radius, &wants, &alpha, 0.0, ANGLE);
                let mut fresh = Collisions::new(bounds, 28.0, n);
                fresh.resolve(&x, &y, &radius, &wants, &alpha, 0.0, ANGLE);
                assert_eq!(kept.waits, fresh.waits, "{n} robots in {side} px, step {step}");
                released += kept.blocked.iter().filter(|&&i| !kept.waits[i as usize]).count();
            }
            assert!(n < 40 || released > 0, "{n} robots in {side} px: some cycle was released");
        }
    }

    #[test]
    fn a_tiny_fleet_that_skips_the_pass_over_pairs_decides_and_counts_as_a_fresh_one() {
        // Robots walk a few px a step towards random points on a small floor: mostly far
        // apart (a kept `Collisions` then skips the pass over pairs, see `grid::Apart`), now
        // and then near (blocked, touching), some stepping in and out of bays. The kept one
        // must decide and count contacts every step as a fresh one, which never skips.
        let mut rnd = uniform(2024);
        let speed = 4.0;
        let (mut skipped, mut waited, mut touched, mut steps) = (0, 0, 0, 0);
        for (n, side) in [(2, 150.0), (3, 250.0), (6, 400.0), (12, 600.0), (32, 1000.0)] {
            let bounds = [0.0, 0.0, side, side];
            let mut kept = Collisions::new(bounds, 28.0, n);
            let mut x: Vec<f64> = (0..n).map(|_| (rnd() * side).round()).collect();
            let mut y: Vec<f64> = (0..n).map(|_| (rnd() * side).round()).collect();
            let mut goal: Vec<(f64, f64)> = (0..n).map(|_| (rnd() * side, rnd() * side)).collect();
            let radius = vec![12.5; n];
            for step in 0..2000 {
                // Along one axis at a time, as on aisles (exact positions), else straight
                // (diagonals too: a proof that measured moves by their longer axis would fail).
                let axis = step % 400 < 200;
                let mut alpha = vec![0.0; n];
                for i in 0..n {
                    let (dx, dy) = (goal[i].0 - x[i], goal[i].1 - y[i]);
                    if dx.abs() + dy.abs() < speed {
                        goal[i] = ((rnd() * side).round(), (rnd() * side).round());
                    }
                    alpha[i] = if !axis {
                        dy.atan2(dx)
                    } else if dx.abs() >= speed {
                        if dx > 0.0 {
                            0.0
                        } else {
                            PI
                        }
                    } else if dy > 0.0 {
                        FRAC_PI_2
                    } else {
                        -FRAC_PI_2
                    };
                }
                let wants: Vec<bool> = (0..n).map(|_| rnd() < 0.9).collect();
                if step % 150 == 0 {
                    // Robot 0 steps into a bay or out of it: a new set of robots in the grid.
                    let bay: Vec<bool> = (0..n).map(|i| i == 0 && step % 300 == 0).collect();
                    kept.bay.clone_from(&bay);
                }
                let anchor = kept.apart.x.clone();
                // A twin of the kept state without its proof makes the pass: everything the
                // pass leaves must come out the same, not only the decisions.
                let mut twin = kept.clone();
                twin.apart = grid::Apart::default();
                kept.resolve(&x, &y, &radius, &wants, &alpha, 0.0, ANGLE);
                twin.resolve(&x, &y, &radius, &wants, &alpha, 0.0, ANGLE);
                assert_eq!((&kept.bits, kept.cover.to_bits(), kept.clear), (&twin.bits, twin.cover.to_bits(), twin.clear), "{n} robots, step {step}");
                let mut fresh = Collisions::new(bounds, 28.0, n);
                fresh.bay.clone_from(&kept.bay);
                fresh.resolve(&x, &y, &radius, &wants, &alpha, 0.0, ANGLE);
                assert_eq!(kept.waits, fresh.waits, "{n} robots, step {step}");
                assert_eq!(kept.waits, twin.waits, "{n} robots, step {step}");
                skipped += usize::from(kept.apart.x == anchor && step > 0);
                waited += kept.waits.iter().filter(|&&w| w).count();
                steps += 1;
                // Those that may move do, by `speed` along their heading.
                let moved: Vec<bool> = (0..n).map(|i| wants[i] && !kept.waits[i]).collect();
                for i in (0..n).filter(|&i| moved[i]) {
                    x[i] += speed * alpha[i].cos();
                    y[i] += speed * alpha[i].sin();
                    if axis {
                        (x[i], y[i]) = (x[i].round(), y[i].round());
                    }
                }
                let got = kept.contacts(&x, &y, &radius, &moved, 2.0 * speed);
                let want = fresh.contacts(&x, &y, &radius, &moved, 2.0 * speed);
                assert_eq!((got.0, got.1.to_bits()), (want.0, want.1.to_bits()), "{n} robots, step {step}");
                assert_eq!(twin.contacts(&x, &y, &radius, &moved, 2.0 * speed), got, "{n} robots, step {step}");
                touched += usize::from(got.0 > 0);
            }
        }
        // The test means something: the pass was skipped in many steps, and robots met.
        assert!(skipped * 3 > steps && waited > 100 && touched > 10, "skipped {skipped} of {steps}, waited {waited}, touched {touched}");
    }

    #[test]
    fn the_pairs_stand_in_for_the_boxes_only_where_they_find_the_same() {
        // A dense grid of robots on aisles: the pairs are collected (and the contact count
        // can read them). A robot at a NaN coordinate, a contact distance wider than the
        // boxes reach, or a pile with more pairs than the list keeps: the boxes decide.
        let n = 300;
        let mut rnd = uniform(7);
        let x: Vec<f64> = (0..n).map(|_| (rnd() * 400.0).round()).collect();
        let y: Vec<f64> = (0..n).map(|_| (rnd() * 8.0).floor() * 50.0).collect();
        let (wants, alpha, radius) = (vec![true; n], vec![0.0; n], vec![12.5; n]);
        let kept_pairs = |x: &[f64], y: &[f64], margin: f64| {
            let mut c = Collisions::new([-50.0, -50.0, 450.0, 450.0], 25.0, n);
            assert!(c.dense);
            c.resolve(x, y, &radius, &wants, &alpha, margin, ANGLE);
            c.pairs_r2 > 0.0
        };
        assert!(kept_pairs(&x, &y, 0.0), "the usual case uses the pairs");
        let mut nan_y = y.clone();
        nan_y[17] = f64::NAN;
        assert!(!kept_pairs(&x, &nan_y, 0.0), "a NaN coordinate");
        assert!(!kept_pairs(&x, &y, 1.0), "contacts wider than the boxes reach");
        let (mut px, mut py) = (x.clone(), y.clone());
        for i in 0..200 {
            (px[i], py[i]) = (200.0, 200.0);
        }
        assert!(!kept_pairs(&px, &py, 0.0), "a pile past the list's limit");
    }

    #[test]
    fn grid_finds_neighbours_across_cell_borders_and_agrees_with_brute_force() {
        // Pseudo-random cloud, compared with the O(N²) definition.
        let mut rnd = uniform(12345);
        let n = 400;
        let x: Vec<f64> = (0..n).map(|_| rnd() * 300.0).collect();
        let y: Vec<f64> = (0..n).map(|_| rnd() * 300.0).collect();
        let alpha: Vec<f64> = (0..n).map(|_| rnd() * TAU - PI).collect();
        let wants: Vec<bool> = (0..n).map(|i| i % 3 != 0).collect();
        let mut c = Collisions::new([0.0, 0.0, 300.0, 300.0], 25.0, n);
        c.resolve(&x, &y, &vec![12.5; n], &wants, &alpha, 0.0, ANGLE);
        for i in 0..n {
            let brute: Vec<u32> = (0..n).filter(|&j| j != i && wants[i] && blocks(x[i], y[i], alpha[i], x[j], y[j], 25.0, ANGLE)).map(|j| j as u32).collect();
            let s = c.blocked.binary_search(&(i as u32)).ok();
            let mut got = s.map_or(Vec::new(), |s| c.edge_to[c.edge_start[s] as usize..c.edge_start[s + 1] as usize].to_vec());
            got.sort_unstable();
            assert_eq!(got, brute, "robot {i}");
        }
    }
}
