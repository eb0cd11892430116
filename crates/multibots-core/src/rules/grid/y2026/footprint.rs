//! A robot's footprint under the 2026 rules, in the Start-Kit's single-precision arithmetic
//! (`src/ActionModel.cpp` at tag `v3.1.0`): a square of side `agentSize` whose top-left corner
//! is its cell's top-left corner, shifted by `count / M` of a cell along its heading while a
//! forward move is under way (a turn does not shift it). Over one tick the square slides in a
//! straight line from where it was to where it is; two such squares collide if their open
//! interiors meet at some instant of the tick, with the Start-Kit's tolerance of 1e-6.
//!
//! Every figure is an `f32`, every operation a single `f32` operation, in the order the
//! Start-Kit writes it: its build (x86-64, SSE, no fused multiply-add) rounds each step to
//! single precision, so the same sequence here gives the same bits and the same verdicts
//! (checked tick by tick against the Start-Kit's own model in `tests/engine/lorr26_model.rs`).

use crate::rules::grid::action::Action;

/// The Start-Kit's tolerance.
const EPS: f32 = 1e-6;

/// A robot's state under the 2026 rules: its cell, heading (0 east, 1 south, 2 west, 3 north),
/// how many ticks of the action under way are done, and that action ([`Action::T`], the
/// Start-Kit's `NA`, when none).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pose {
    /// The cell, `row * cols + col`.
    pub loc: u32,
    /// The heading.
    pub heading: u8,
    /// Ticks done of the action under way (0 when none).
    pub count: u32,
    /// The action under way, or [`Action::T`].
    pub doing: Action,
}

impl Pose {
    /// A robot standing on `loc` facing east, doing nothing: how every robot starts.
    #[must_use]
    pub fn at(loc: u32) -> Pose {
        Pose { loc, heading: 0, count: 0, doing: Action::T }
    }

    /// Whether an action is under way (a wait pauses it; any other request goes on with it).
    #[must_use]
    pub fn busy(&self) -> bool {
        self.count > 0 && self.doing != Action::T
    }
}

/// A square's slide over one tick: from `(x0, y0)` to `(x1, y1)` (top-left corners).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    pub x0: f32,
    pub y0: f32,
    pub x1: f32,
    pub y1: f32,
}

/// An axis-aligned rectangle: `[min_x, max_x] × [min_y, max_y]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    pub min_x: f32,
    pub min_y: f32,
    pub max_x: f32,
    pub max_y: f32,
}

/// Where a robot's square is: its top-left corner, in cells (x the column, y the row).
#[must_use]
pub fn corner(p: &Pose, cols: u32, m: u32) -> (f32, f32) {
    let mut x = (p.loc % cols) as f32;
    let mut y = (p.loc / cols) as f32;
    if p.doing == Action::F && p.count > 0 {
        let frac = p.count as f32 / m as f32;
        match p.heading {
            0 => x += frac,
            1 => y += frac,
            2 => x -= frac,
            _ => y -= frac,
        }
    }
    (x, y)
}

/// The slide from `a` to `b`.
#[must_use]
pub fn motion(a: (f32, f32), b: (f32, f32)) -> Motion {
    Motion { x0: a.0, y0: a.1, x1: b.0, y1: b.1 }
}

/// The rectangle a square of side `size` sweeps over a slide.
#[must_use]
pub fn swept(m: &Motion, size: f32) -> Rect {
    Rect { min_x: m.x0.min(m.x1), min_y: m.y0.min(m.y1), max_x: m.x0.max(m.x1) + size, max_y: m.y0.max(m.y1) + size }
}

/// Whether two rectangles' interiors meet.
#[must_use]
pub fn overlap(a: &Rect, b: &Rect) -> bool {
    a.min_x < b.max_x && a.max_x > b.min_x && a.min_y < b.max_y && a.max_y > b.min_y
}

/// The part of the tick `[0, 1]` in which the gap `d0 + dv·t` lies strictly inside `(lo, up)`,
/// with the tolerance; `None` if there is none.
fn window(d0: f32, dv: f32, lo: f32, up: f32) -> Option<(f32, f32)> {
    if dv > -EPS && dv < EPS {
        return (d0 > lo + EPS && d0 < up - EPS).then_some((0.0, 1.0));
    }
    let (mut t0, mut t1) = ((lo - d0) / dv, (up - d0) / dv);
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let te = EPS / dv.abs();
    t0 = (t0 + te).max(0.0);
    t1 = (t1 - te).min(1.0);
    (t0 <= t1).then_some((t0, t1))
}

/// Whether a square of side `sa` sliding along `a` and one of side `sb` sliding along `b`
/// collide during the tick.
#[must_use]
pub fn collide(a: &Motion, sa: f32, b: &Motion, sb: f32) -> bool {
    if !overlap(&swept(a, sa), &swept(b, sb)) {
        return false;
    }
    let d0x = a.x0 - b.x0;
    let d0y = a.y0 - b.y0;
    let dvx = (a.x1 - a.x0) - (b.x1 - b.x0);
    let dvy = (a.y1 - a.y0) - (b.y1 - b.y0);
    let Some((tx0, tx1)) = window(d0x, dvx, -sa, sb) else { return false };
    let Some((ty0, ty1)) = window(d0y, dvy, -sa, sb) else { return false };
    tx0.max(ty0) <= tx1.min(ty1)
}

/// The cells a rectangle covers, clipped to the map: `(r0, r1, c0, c1)`, inclusive (empty
/// when `r0 > r1` or `c0 > c1`).
#[must_use]
pub fn cells(r: &Rect, rows: u32, cols: u32) -> (i64, i64, i64, i64) {
    let c0 = (r.min_x.floor() as i64).max(0);
    let r0 = (r.min_y.floor() as i64).max(0);
    let c1 = (r.max_x.ceil() as i64 - 1).min(i64::from(cols) - 1);
    let r1 = (r.max_y.ceil() as i64 - 1).min(i64::from(rows) - 1);
    (r0, r1, c0, c1)
}

/// The map as the model sees it: obstacles, the square's side and the ticks per action.
#[derive(Clone, Debug)]
pub struct Floor {
    pub rows: u32,
    pub cols: u32,
    /// Whether each cell is an obstacle.
    pub obstacle: Vec<bool>,
    /// `agentSize`, as the Start-Kit's `float`.
    pub size: f32,
    /// `agentCounter`: ticks per action.
    pub m: u32,
    /// `obstacle` as bits, a bit per cell in row-major order: the model looks up an obstacle
    /// for every slide of every tick, and on a map of millions of cells a bit per cell stays
    /// in cache where a byte per cell does not (the 1,800 × 1,912 map of `iron_harvest`:
    /// 0.4 MB against 3.4 MB). Private, so that it is made from `obstacle` only
    /// ([`Floor::new`]).
    blocked: Vec<u64>,
}

impl Floor {
    /// A floor of `rows × cols` cells with `obstacle` (a flag per cell, row-major), squares
    /// of side `size` and `m` ticks per action.
    #[must_use]
    pub fn new(rows: u32, cols: u32, obstacle: Vec<bool>, size: f32, m: u32) -> Floor {
        let mut blocked = vec![0u64; obstacle.len().div_ceil(64)];
        for (c, _) in obstacle.iter().enumerate().filter(|(_, &o)| o) {
            blocked[c / 64] |= 1 << (c % 64);
        }
        Floor { rows, cols, obstacle, size, m, blocked }
    }

    /// Whether `cell` is an obstacle.
    #[inline]
    fn is_obstacle(&self, cell: usize) -> bool {
        (self.blocked[cell / 64] >> (cell % 64)) & 1 == 1
    }

    /// Whether a slide stays on the map and clear of every obstacle cell.
    #[must_use]
    pub fn clear(&self, m: &Motion) -> bool {
        let s = swept(m, self.size);
        if !(s.min_x >= 0.0 && s.min_y >= 0.0 && s.max_x <= self.cols as f32 && s.max_y <= self.rows as f32) {
            return false;
        }
        let (r0, r1, c0, c1) = cells(&s, self.rows, self.cols);
        for r in r0..=r1 {
            for c in c0..=c1 {
                let cell = (r * i64::from(self.cols) + c) as usize;
                if self.is_obstacle(cell) {
                    let (x, y) = (c as f32, r as f32);
                    if collide(m, self.size, &Motion { x0: x, y0: y, x1: x, y1: y }, 1.0) {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// The first robot standing on `starts` (facing east, nothing under way) whose square does
    /// not fit: off the map, over an obstacle, or over a robot of lower id (with `agentSize`
    /// above 1 a square reaches into the cells right and below); `None` if all fit. The
    /// Start-Kit aborts on such a start at the first tick.
    #[must_use]
    pub fn misfit(&self, starts: &[u32]) -> Option<(usize, String)> {
        if self.size <= 1.0 {
            // Distinct free cells: each square stays in its own cell.
            return None;
        }
        let reach = self.size.ceil() as i64;
        let mut at: std::collections::HashMap<u32, usize> = std::collections::HashMap::new();
        for (i, &c) in starts.iter().enumerate() {
            let (x, y) = ((c % self.cols) as f32, (c / self.cols) as f32);
            if !self.clear(&Motion { x0: x, y0: y, x1: x, y1: y }) {
                return Some((i, format!("its square of side {} at cell {c} leaves the map or covers an obstacle", self.size)));
            }
            let (r, col) = (i64::from(c / self.cols), i64::from(c % self.cols));
            for dr in -reach..=reach {
                for dc in -reach..=reach {
                    let (rr, cc) = (r + dr, col + dc);
                    if rr < 0 || cc < 0 || rr >= i64::from(self.rows) || cc >= i64::from(self.cols) {
                        continue;
                    }
                    if let Some(&j) = at.get(&((rr * i64::from(self.cols) + cc) as u32)) {
                        if (dr.abs() as f32) < self.size && (dc.abs() as f32) < self.size {
                            return Some((i, format!("its square of side {} at cell {c} overlaps robot {j}'s", self.size)));
                        }
                    }
                }
            }
            at.insert(c, i);
        }
        None
    }

    /// The state after one tick of `a` from `p` (the Start-Kit's `result_state`): an action
    /// under way goes on whatever is asked but a wait, which pauses it; a new `F`, `R` or `C`
    /// starts; each takes `m` ticks and has its effect on the last.
    #[must_use]
    pub fn next(&self, p: &Pose, a: Action) -> Pose {
        let mut n = *p;
        let mut ex = a;
        if p.busy() {
            if a == Action::W {
                return n;
            }
            ex = p.doing;
        }
        if matches!(ex, Action::F | Action::R | Action::C) {
            n.count += 1;
            if n.count >= self.m {
                n.count = 0;
                n.doing = Action::T;
                match ex {
                    Action::F => n.loc = self.ahead(p.loc, p.heading),
                    Action::R => n.heading = (p.heading + 1) % 4,
                    _ => n.heading = (p.heading + 3) % 4,
                }
            } else {
                n.doing = ex;
            }
        } else if p.count == 0 {
            n.doing = Action::T;
        }
        n
    }

    /// The cell ahead, as the Start-Kit computes it (`loc + moves[heading]`); off the map it
    /// is `u32::MAX` (the Start-Kit's out-of-range location), and a step sideways off the map,
    /// which the Start-Kit lets wrap to the next row, is `u32::MAX` too.
    #[must_use]
    pub fn ahead(&self, loc: u32, heading: u8) -> u32 {
        crate::rules::grid::action::ahead_on(self.rows, self.cols, loc, heading).unwrap_or(u32::MAX)
    }
}
