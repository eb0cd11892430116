//! The 2026 action model's tick (the Start-Kit's `ActionModelWithRotate::step`, tag `v3.1.0`):
//! every robot's request is kept if its footprint can make the tick's slide, and turned into a
//! wait otherwise, so that no two squares ever meet and none touches an obstacle.
//!
//! The rule, in the Start-Kit's order, which decides every tie:
//! 1. Each robot's requested slide and its waiting slide are worked out, and whether each stays
//!    on the map and clear of obstacles (`footprint.rs`). A step sideways off the map is
//!    refused here, where the Start-Kit lets it wrap to the next row (and can then abort on
//!    an overlap it did not foresee; `lorr_check26.py` refuses such a move too).
//! 2. Robots are taken in id order. A robot keeps its request if the slide meets no robot
//!    already decided and, for each neighbour whose *waiting* would be in its way, that
//!    neighbour is decided first (recursively) and then is not in its way. A neighbour already
//!    being decided further up the recursion closes a cycle: the robot that closes it waits,
//!    and the cycle is recorded ("occupancy-chain cycle" when each robot asks for the cell of
//!    the next, else "directed physical-dependency cycle").
//! 3. A robot that cannot keep its request waits, if its waiting slide meets nobody decided;
//!    it waits anyway otherwise. Every robot that waits without having asked to is recorded
//!    ("Agent waits instead of F: ..." with the first reason found).
//!
//! Neighbours are looked up in bins of the cells each robot's square covers at the start of
//! the tick, within `1 + agentSize` cells of the slide, cell by cell in row-major order and by
//! increasing id within a cell: the order the Start-Kit visits them, which decides which
//! robot of a cycle notices it. A decision once taken is final.

use super::footprint::{cells, collide, corner, motion, swept, Floor, Motion, Pose, Rect};
use crate::record::grid26::ModelMessage;
use crate::rules::grid::action::Action;
use std::fmt::Write as _;

/// Why a robot could not keep its request (the first reason found).
#[derive(Clone, Debug)]
enum Reason {
    Invalid,
    Conflicts(u32),
    Cycle(String),
    Unresolved(u32),
    Blocked(u32, bool),
}

/// The model, with the buffers a tick reuses.
#[derive(Default)]
pub struct ActionModel {
    req_pose: Vec<Pose>,
    wait_pose: Vec<Pose>,
    req_motion: Vec<Motion>,
    wait_motion: Vec<Motion>,
    req_ok: Vec<bool>,
    wait_ok: Vec<bool>,
    /// (cell, robot) for each cell a robot's square covers, sorted by cell then robot.
    bins: Vec<(u32, u32)>,
    /// Where each binned cell's entries start in `bins`: an open-addressed table of
    /// (cell, start), [`EMPTY`] where unused, twice the size of `bins` or more, rebuilt each
    /// tick. A table per cell of the map (8 bytes a cell) was out of cache on a map of
    /// millions of cells, and its reads most of the tick; this one is the size of the fleet.
    heads: Vec<(u32, u32)>,
    /// A bit per cell, set where `bins` has entries: a neighbour search reads the bits of its
    /// cells, a 64th of a byte a cell, and `heads` only where one is set.
    occupied: Vec<u64>,
    status: Vec<u8>,
    decided: Vec<bool>,
    chose: Vec<bool>,
    decided_motion: Vec<Motion>,
    reason: Vec<Option<Reason>>,
    stack: Vec<u32>,
    stack_pos: Vec<i32>,
    seen: Vec<u32>,
    seen_stamp: u32,
    neighbours: Vec<u32>,
    /// The messages of the last tick.
    pub errors: Vec<ModelMessage>,
}

/// An unused entry of `ActionModel::heads`.
const EMPTY: u32 = u32::MAX;

/// Where `cell` goes in a table of `len` entries (a power of two), by Fibonacci hashing.
#[inline]
fn slot_of(cell: u32, len: usize) -> usize {
    (u64::from(cell).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> (64 - len.trailing_zeros())) as usize
}

const UNSEEN: u8 = 0;
const VISITING: u8 = 1;
const DONE: u8 = 2;

/// The letter a message names an action by.
fn name(a: Action) -> &'static str {
    match a {
        Action::F => "F",
        Action::R => "R",
        Action::C => "C",
        Action::W => "W",
        Action::T => "NA",
    }
}

impl ActionModel {
    /// Plays one tick: `act` holds each robot's request and, after the call, what it did
    /// (its request, or `W`); `next` gets the states after the tick; `time` is the model's
    /// step count (the tick played, counted from 1). The tick's messages are in
    /// [`ActionModel::errors`].
    pub fn step(&mut self, floor: &Floor, prev: &[Pose], act: &mut [Action], time: u32, next: &mut Vec<Pose>) {
        let n = prev.len();
        self.errors.clear();
        self.prepare(floor, prev, act);
        self.bin(floor, prev);
        self.status.clear();
        self.status.resize(n, UNSEEN);
        self.decided.clear();
        self.decided.resize(n, false);
        self.chose.clear();
        self.chose.resize(n, false);
        self.decided_motion.clone_from(&self.wait_motion);
        self.reason.clear();
        self.reason.resize(n, None);
        self.stack.clear();
        self.stack_pos.clear();
        self.stack_pos.resize(n, -1);
        if self.seen.len() != n {
            self.seen = vec![0; n];
            self.seen_stamp = 0;
        }
        let mut tick = Tick { model: self, floor, prev, req: act, time };
        for i in 0..n {
            tick.resolve(i);
        }
        for (i, a) in act.iter_mut().enumerate() {
            let asked = *a;
            if !self.chose[i] {
                *a = Action::W;
                if asked != Action::W {
                    let why = self.reason[i].take().map_or_else(|| "requested motion rejected by recursive dependency resolution".to_string(), describe);
                    self.errors.push(ModelMessage { agent: i as i64, other: -1, time, message: format!("Agent waits instead of {}: {why}", name(asked)) });
                }
            }
        }
        next.clear();
        next.extend(prev.iter().zip(act.iter()).map(|(p, &a)| floor.next(p, a)));
    }

    /// Each robot's requested and waiting states, slides, and whether each slide is clear.
    fn prepare(&mut self, floor: &Floor, prev: &[Pose], req: &[Action]) {
        let cells = u64::from(floor.rows) * u64::from(floor.cols);
        self.req_pose.clear();
        self.wait_pose.clear();
        self.req_motion.clear();
        self.wait_motion.clear();
        self.req_ok.clear();
        self.wait_ok.clear();
        for (p, &a) in prev.iter().zip(req) {
            let from = corner(p, floor.cols, floor.m);
            for (want, poses, motions, oks) in
                [(a, &mut self.req_pose, &mut self.req_motion, &mut self.req_ok), (Action::W, &mut self.wait_pose, &mut self.wait_motion, &mut self.wait_ok)]
            {
                let q = floor.next(p, want);
                let on_map = u64::from(q.loc) < cells;
                let m = if on_map { motion(from, corner(&q, floor.cols, floor.m)) } else { motion(from, from) };
                poses.push(q);
                motions.push(m);
                // Staying put is clear: every square starts clear (`Floor::fits`).
                oks.push(on_map && ((m.x0 == m.x1 && m.y0 == m.y1) || floor.clear(&m)));
            }
        }
    }

    /// Bins every robot by the cells its square covers at the start of the tick.
    fn bin(&mut self, floor: &Floor, prev: &[Pose]) {
        let n_cells = (floor.rows * floor.cols) as usize;
        if self.occupied.len() == n_cells.div_ceil(64) {
            for &(cell, _) in &self.bins {
                self.occupied[cell as usize / 64] = 0;
            }
        } else {
            self.occupied = vec![0; n_cells.div_ceil(64)];
        }
        self.bins.clear();
        for (i, p) in prev.iter().enumerate() {
            let (x, y) = corner(p, floor.cols, floor.m);
            let r = Rect { min_x: x, min_y: y, max_x: x + floor.size, max_y: y + floor.size };
            let (r0, r1, c0, c1) = cells(&r, floor.rows, floor.cols);
            for row in r0..=r1 {
                for col in c0..=c1 {
                    self.bins.push(((row * i64::from(floor.cols) + col) as u32, i as u32));
                }
            }
        }
        // Stable: robots stay in id order within a cell.
        self.bins.sort_by_key(|&(cell, _)| cell);
        let len = (2 * self.bins.len()).next_power_of_two().max(2);
        self.heads.clear();
        self.heads.resize(len, (EMPTY, 0));
        let mut last = EMPTY;
        for (k, &(cell, _)) in self.bins.iter().enumerate() {
            if cell == last {
                continue;
            }
            last = cell;
            self.occupied[cell as usize / 64] |= 1 << (cell % 64);
            let mut h = slot_of(cell, len);
            while self.heads[h].0 != EMPTY {
                h = (h + 1) & (len - 1);
            }
            self.heads[h] = (cell, k as u32);
        }
    }

    /// Where `cell`'s entries start in `bins`; `cell` must be binned (its bit set).
    #[inline]
    fn head(&self, cell: u32) -> usize {
        let len = self.heads.len();
        let mut h = slot_of(cell, len);
        while self.heads[h].0 != cell {
            debug_assert_ne!(self.heads[h].0, EMPTY, "cell {cell} is binned");
            h = (h + 1) & (len - 1);
        }
        self.heads[h].1 as usize
    }
}

/// The words of a reason.
fn describe(r: Reason) -> String {
    match r {
        Reason::Invalid => "requested motion is invalid (boundary or hard obstacle)".into(),
        Reason::Conflicts(j) => format!("requested motion conflicts with resolved agent {j}"),
        Reason::Cycle(d) => d,
        Reason::Unresolved(j) => format!("dependency on agent {j} could not be resolved"),
        Reason::Blocked(j, moved) => format!("requested motion blocked by agent {j}{}", if moved { "" } else { " (agent waited)" }),
    }
}

/// One tick's resolution: the model's buffers and the tick's inputs.
struct Tick<'a> {
    model: &'a mut ActionModel,
    floor: &'a Floor,
    prev: &'a [Pose],
    req: &'a [Action],
    time: u32,
}

impl Tick<'_> {
    fn set_reason(&mut self, i: usize, r: impl FnOnce() -> Reason) {
        if self.model.reason[i].is_none() {
            self.model.reason[i] = Some(r());
        }
    }

    /// Decides robot `i` (and, first, the neighbours it depends on); whether it keeps its
    /// request.
    fn resolve(&mut self, i: usize) -> bool {
        let m = &mut *self.model;
        if m.decided[i] {
            return m.chose[i];
        }
        if m.status[i] == VISITING {
            return false;
        }
        m.status[i] = VISITING;
        m.stack_pos[i] = m.stack.len() as i32;
        m.stack.push(i as u32);
        if !self.commit(i, true) {
            self.commit(i, false);
        }
        let m = &mut *self.model;
        if !m.decided[i] {
            m.decided[i] = true;
            m.chose[i] = false;
            m.decided_motion[i] = m.wait_motion[i];
        }
        m.stack.pop();
        m.stack_pos[i] = -1;
        m.status[i] = DONE;
        m.chose[i]
    }

    /// Tries to decide robot `i` on its request (`asked`) or on waiting.
    fn commit(&mut self, i: usize, asked: bool) -> bool {
        let size = self.floor.size;
        let ok = if asked { self.model.req_ok[i] } else { self.model.wait_ok[i] };
        if !ok {
            if asked {
                self.set_reason(i, || Reason::Invalid);
            }
            return false;
        }
        let mv = if asked { self.model.req_motion[i] } else { self.model.wait_motion[i] };
        if mv.x0 == mv.x1 && mv.y0 == mv.y1 {
            // A square that stays put (a wait, a turn, a pause) always can: a robot decided
            // before it whose slide would meet it depended on it, and was decided after it or
            // refused (a cycle). Nor does it depend on anyone. So no neighbour need be looked at,
            // and the outcome is the Start-Kit's.
            let m = &mut *self.model;
            m.decided[i] = true;
            m.chose[i] = asked;
            m.decided_motion[i] = mv;
            return true;
        }
        let (from, to) = self.collect_neighbours(i, &mv);
        for k in from..to {
            let j = self.model.neighbours[k] as usize;
            if self.model.decided[j] {
                if collide(&mv, size, &self.model.decided_motion[j], size) {
                    if asked {
                        self.set_reason(i, || Reason::Conflicts(j as u32));
                    }
                    self.model.neighbours.truncate(from);
                    return false;
                }
                continue;
            }
            if !(asked && self.model.wait_ok[j] && collide(&mv, size, &self.model.wait_motion[j], size)) {
                continue;
            }
            if self.model.status[j] == VISITING {
                let d = self.cycle(i, j);
                self.set_reason(i, || Reason::Cycle(d.clone()));
                self.model.errors.push(ModelMessage { agent: i as i64, other: j as i64, time: self.time, message: d });
                self.model.neighbours.truncate(from);
                return false;
            }
            let moved = self.resolve(j);
            if !self.model.decided[j] {
                self.set_reason(i, || Reason::Unresolved(j as u32));
                self.model.neighbours.truncate(from);
                return false;
            }
            if collide(&mv, size, &self.model.decided_motion[j], size) {
                self.set_reason(i, || Reason::Blocked(j as u32, moved));
                self.model.neighbours.truncate(from);
                return false;
            }
        }
        self.model.neighbours.truncate(from);
        let m = &mut *self.model;
        m.decided[i] = true;
        m.chose[i] = asked;
        m.decided_motion[i] = mv;
        true
    }

    /// Appends to the shared list the robots binned within `1 + size` of `i`'s slide, in the
    /// Start-Kit's order, each once, `i` left out; their range in the list.
    fn collect_neighbours(&mut self, i: usize, mv: &Motion) -> (usize, usize) {
        let (rows, cols, size) = (self.floor.rows, self.floor.cols, self.floor.size);
        let margin = 1.0 + size;
        let s = swept(mv, size);
        let q = Rect { min_x: s.min_x - margin, min_y: s.min_y - margin, max_x: s.max_x + margin, max_y: s.max_y + margin };
        let (r0, r1, c0, c1) = cells(&q, rows, cols);
        let m = &mut *self.model;
        m.seen_stamp = m.seen_stamp.wrapping_add(1);
        if m.seen_stamp == 0 {
            m.seen.fill(0);
            m.seen_stamp = 1;
        }
        let from = m.neighbours.len();
        if c0 > c1 {
            return (from, from);
        }
        for r in r0..=r1 {
            // The row's cells c0..=c1 whose bit is set, in increasing order: the cells of the
            // Start-Kit's walk that hold a robot, in its order.
            let (lo, hi) = ((r * i64::from(cols) + c0) as usize, (r * i64::from(cols) + c1) as usize);
            for w in lo / 64..=hi / 64 {
                let mut bits = m.occupied[w];
                if w == lo / 64 {
                    bits &= u64::MAX << (lo % 64);
                }
                if w == hi / 64 {
                    bits &= u64::MAX >> (63 - hi % 64);
                }
                while bits != 0 {
                    let cell = w * 64 + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    m.gather(cell, i);
                }
            }
        }
        (from, m.neighbours.len())
    }
}

impl ActionModel {
    /// Appends to `neighbours` the robots binned at `cell` not yet seen this search, `i` left
    /// out, by increasing id.
    fn gather(&mut self, cell: usize, i: usize) {
        for &(at, j) in &self.bins[self.head(cell as u32)..] {
            if at as usize != cell {
                break;
            }
            if j as usize != i && self.seen[j as usize] != self.seen_stamp {
                self.seen[j as usize] = self.seen_stamp;
                self.neighbours.push(j);
            }
        }
    }
}

impl Tick<'_> {
    /// The words for the cycle `i` closes on `k`, which is further up the recursion.
    fn cycle(&self, i: usize, k: usize) -> String {
        let m = &*self.model;
        let start = usize::try_from(m.stack_pos[k]).unwrap_or(0);
        let chain = &m.stack[start..];
        let cell_of_next = |u: usize, v: usize| m.req_pose[u].loc == self.prev[v].loc;
        let occupancy = chain.windows(2).all(|w| cell_of_next(w[0] as usize, w[1] as usize)) && cell_of_next(i, k);
        let mut s = String::from(if occupancy { "occupancy-chain cycle: " } else { "directed physical-dependency cycle: " });
        let link = |a: usize, s: &mut String| {
            let next = m.req_pose[a].loc;
            let next = if next == u32::MAX { -1 } else { i64::from(next) };
            let _ = write!(s, "a{a}(loc={}, act={}, next={next})", self.prev[a].loc, name(self.req[a]));
        };
        for &a in chain {
            link(a as usize, &mut s);
            s.push_str(" -> ");
        }
        link(k, &mut s);
        s
    }
}
