//! The "blocked by" graph of the collision phase (spec phase 3): each robot's blockers this
//! step, in compressed rows by robot id, kept from step to step; who of the blocked is
//! released is in `cycles.rs`.
//!
//! A robot's blockers depend only on its own position, heading and wish to move, and on the
//! positions of the robots within its contact distance (and whether they stand in bays). So
//! a row is found again only for a robot that changed, or near whose place, before or
//! after, another robot moved or stepped into or out of a bay; every other row is last
//! step's. Where most robots changed (a fleet under way), one pass over the pairs of
//! neighbours finds every row at once instead (`Index::pairs`). Both ways judge a pair with
//! the same filter and the same [`blocks`], so the rows are the same: a kept graph equals a
//! fresh one (tested).

use super::index::{within, Index, Moved};
use super::{blocks, grid::Grid};

/// A pass over every pair beats looking again row by row when more than one robot in this
/// many changed. Measured at the large size (1,000 robots): the pass costs about as much as
/// re-finding a tenth of the rows, with their neighbours.
const FULL_PASS_BELOW: usize = 8;

/// What the rows were found with; any change makes every row be found again.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Inputs {
    margin: u64,
    angle: u64,
    /// The fleet's one radius (bits), or `None` for mixed radii (then compared robot by
    /// robot with `Blocking::radii`).
    radius: Option<u64>,
}

/// "Blocked by" graph in compressed rows by robot id: robot `i`'s blockers are
/// `to[start[i]..start[i + 1]]`.
#[derive(Clone, Debug, Default)]
pub(super) struct Blocking {
    pub(super) start: Vec<u32>,
    pub(super) to: Vec<u32>,
    /// The lists' way's rows, by robot id: `to[span[i].0..span[i].1]` (empty for a robot
    /// not blocked; cleared after the release).
    pub(super) span: Vec<(u32, u32)>,
    /// Last step's rows, read while this step's are written.
    old_start: Vec<u32>,
    old_to: Vec<u32>,
    /// Robots whose row is found again this step (all clear between steps), and the same
    /// robots listed.
    dirty: Vec<bool>,
    marked: Vec<u32>,
    /// Robots with at least one blocker: ascending, or in the order first found on the lists' way.
    pub(super) blocked: Vec<u32>,
    /// Blockers from the pass over pairs, `(from, to)`, before they are sorted into rows.
    edges: Vec<(u32, u32)>,
    moved: Vec<Moved>,
    inputs: Option<Inputs>,
    /// The pairs of robots (ids) within `contact_span` of each other, kept by the pass over
    /// pairs at the index's refresh `near_generation` for the contact count after the moves
    /// (`contacts.rs`), which asks for them that wide.
    pub(super) near: Vec<(u32, u32)>,
    pub(super) near_generation: Option<u64>,
    pub(super) near_span: f64,
    pub(super) contact_span: f64,
    /// Mixed radii: each robot's, as the rows were found with.
    radii: Vec<f64>,
    // Tarjan's algorithm (`cycles.rs`), by robot id.
    pub(super) index: Vec<u32>,
    pub(super) low: Vec<u32>,
    pub(super) stack: Vec<u32>,
    pub(super) call: Vec<(u32, u32)>,
    pub(super) released: Vec<u32>,
    /// Whether [`Blocking::update`] found every row as it was at the last update, and who
    /// waited then: the same graph releases the same robots. In a jam a step often only
    /// moves robots along their queues, without changing who blocks whom.
    same: bool,
    last_waits: Vec<bool>,
}

/// The near filter every way of finding blockers shares: a pair farther apart than this is
/// clearly out of reach (with a relative slack far above rounding), and [`blocks`] decides
/// the rest. The squared distance and the contact distance do not depend on which robot of
/// the pair looks.
#[inline]
fn far(dx: f64, dy: f64, r: f64) -> bool {
    dx * dx + dy * dy > r * r * 1.000_001
}

/// Marks robot `i`'s row to be found again (listed once).
#[inline]
fn mark(dirty: &mut [bool], marked: &mut Vec<u32>, i: usize) {
    if !dirty[i] {
        dirty[i] = true;
        marked.push(i as u32);
    }
}

/// Half the side of a box holding every robot within the near filter of a contact distance
/// of `widest`.
#[inline]
fn reach_box(widest: f64) -> f64 {
    widest * 1.000_001 + 1e-9
}

/// What one step's rows are found from: the robots' radii, wishes and headings, and the
/// collision rule's numbers (`r_max`: the largest radius).
pub(super) struct Ask<'a> {
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub radius: &'a [f64],
    pub wants: &'a [bool],
    pub alpha: &'a [f64],
    pub bay: &'a [bool],
    pub margin: f64,
    pub angle: f64,
    pub r_max: f64,
    pub uniform: bool,
}

impl Blocking {
    /// Sizes the rows for `n` robots, none blocked.
    pub(super) fn reset(&mut self, n: usize) {
        self.start.clear();
        self.start.resize(n + 1, 0);
        self.to.clear();
        self.blocked.clear();
        self.dirty.clear();
        self.dirty.resize(n, false);
        self.marked.clear();
        self.index.clear();
        self.index.resize(n, u32::MAX);
        self.low.clear();
        self.low.resize(n, 0);
        self.inputs = None;
        self.same = false;
    }

    /// [`Blocking::release`] after [`Blocking::update`]: last update's answer again where
    /// every row is the same.
    pub(super) fn release_kept(&mut self, waits: &mut [bool]) {
        if self.same && self.last_waits.len() == waits.len() {
            waits.copy_from_slice(&self.last_waits);
            return;
        }
        self.release(waits);
        self.last_waits.clear();
        self.last_waits.extend_from_slice(waits);
    }

    /// This step's rows, from the index (refreshed to `ask`'s positions, bays, wishes and
    /// headings).
    pub(super) fn update(&mut self, index: &mut Index, grid: &Grid, ask: &Ask<'_>) {
        let n = ask.x.len();
        let inputs = Inputs { margin: ask.margin.to_bits(), angle: ask.angle.to_bits(), radius: ask.uniform.then(|| ask.radius[0].to_bits()) };
        let mut all = index.rebuilt || self.start.len() != n + 1 || self.inputs != Some(inputs);
        // Too many moved to be listed: every row is found again (the same rows a long list
        // would give), last step's graph kept for the comparison (nothing of it is stale).
        let unlisted = index.take_moved(&mut self.moved);
        if !ask.uniform {
            let radius = &ask.radius[..n];
            all |= self.radii.len() != n || self.radii.iter().zip(radius).any(|(a, b)| a.to_bits() != b.to_bits());
            self.radii.clear();
            self.radii.extend_from_slice(radius);
        }
        if all {
            self.reset(n);
        }
        let all = all || unlisted;
        self.same = false;
        self.inputs = Some(inputs);
        let changed = self.moved.len() + index.turned.len();
        let widest = 2.0 * ask.r_max + ask.margin;
        // The pass over pairs finds pairs within a cell's width.
        let fits = reach_box(widest.max(self.contact_span)) * 1.001 < grid.size();
        if fits && (all || changed * FULL_PASS_BELOW > n) {
            self.all_rows(index, grid, ask);
        } else {
            index.ready_rows(grid);
            if !all {
                // Robots whose own wish or heading changed.
                for &i in &index.turned {
                    mark(&mut self.dirty, &mut self.marked, i as usize);
                }
                self.spread(index, grid, ask);
            }
            self.same = self.some_rows(index, grid, ask, all) && !all;
        }
    }

    /// Marks the robots whose row may change because another moved: a robot that wants to
    /// move, near where a moved robot stood (as the last rows saw it) or stands now.
    fn spread(&mut self, index: &Index, grid: &Grid, ask: &Ask<'_>) {
        let (radius, margin) = (ask.radius, ask.margin);
        let (dirty, marked) = (&mut self.dirty, &mut self.marked);
        for m in &self.moved {
            let i = m.robot as usize;
            mark(dirty, marked, i);
            let rm = radius[i];
            let h = reach_box(rm + ask.r_max + margin);
            let now = ask.bay.is_empty() || !ask.bay[i];
            for (x, y, was) in [(m.x, m.y, m.blocking), (ask.x[i], ask.y[i], now)] {
                if !was {
                    continue;
                }
                index.visit(grid, x, y, h, |k| {
                    let s = &index.slots[k];
                    let j = s.robot();
                    if s.wants() && !far(s.x - x, s.y - y, radius[j] + rm + margin) {
                        mark(dirty, marked, j);
                    }
                });
            }
        }
    }

    /// The rows of the marked robots (`every`: of every robot) found again, the others
    /// copied from last step; whether every row came out as it was. The rows between two
    /// marked robots are copied as one block: in a jam, where a few robots move, that is
    /// nearly every row.
    fn some_rows(&mut self, index: &Index, grid: &Grid, ask: &Ask<'_>, every: bool) -> bool {
        let n = ask.x.len();
        std::mem::swap(&mut self.start, &mut self.old_start);
        std::mem::swap(&mut self.to, &mut self.old_to);
        let (old_start, old_to) = (&self.old_start[..], &self.old_to[..]);
        let (start, to, blocked) = (&mut self.start, &mut self.to, &mut self.blocked);
        start.clear();
        to.clear();
        blocked.clear();
        let (x, y, radius, wants, alpha, bay) = (&ask.x[..n], &ask.y[..n], &ask.radius[..n], &ask.wants[..n], &ask.alpha[..n], ask.bay);
        let (margin, angle) = (ask.margin, ask.angle);
        let (dirty, marked) = (&mut self.dirty[..n], &mut self.marked);
        if every {
            marked.clear();
            marked.extend(0..n as u32);
        } else {
            marked.sort_unstable();
        }
        let mut same = true;
        let mut next = 0;
        for k in 0..=marked.len() {
            let i = marked.get(k).map_or(n, |&i| i as usize);
            if i > next {
                // Rows `next..i` are last step's: one block of `to`, their starts shifted.
                let (a, b) = (old_start[next] as usize, old_start[i] as usize);
                let shift = to.len().wrapping_sub(a);
                for r in next..i {
                    start.push((old_start[r] as usize).wrapping_add(shift) as u32);
                    if old_start[r] != old_start[r + 1] {
                        blocked.push(r as u32);
                    }
                }
                to.extend_from_slice(&old_to[a..b]);
            }
            if i == n {
                break;
            }
            dirty[i] = false;
            next = i + 1;
            let before = to.len();
            start.push(before as u32);
            let old = &old_to[old_start[i] as usize..old_start[i + 1] as usize];
            if wants[i] && (bay.is_empty() || !bay[i]) {
                let (xi, yi, ri) = (x[i], y[i], radius[i]);
                index.visit(grid, xi, yi, reach_box(ri + ask.r_max + margin), |k| {
                    let s = &index.slots[k];
                    let j = s.robot();
                    if j == i || !s.blocking() {
                        return;
                    }
                    let r = ri + radius[j] + margin;
                    if !far(s.x - xi, s.y - yi, r) && blocks(xi, yi, alpha[i], s.x, s.y, r, angle) {
                        to.push(j as u32);
                    }
                });
            }
            // Blockers in another order count as a change: it only costs a release.
            same &= to[before..] == *old;
            if to.len() > before {
                blocked.push(i as u32);
            }
        }
        marked.clear();
        start.push(to.len() as u32);
        same
    }

    /// Every row at once, from the pairs of neighbouring robots; the pairs within the contact
    /// count's reach are kept for it (`near`).
    fn all_rows(&mut self, index: &Index, grid: &Grid, ask: &Ask<'_>) {
        let n = ask.x.len();
        let (radius, margin, angle) = (&ask.radius[..n], ask.margin, ask.angle);
        let widest = 2.0 * ask.r_max + margin;
        let reach2 = widest * widest * 1.000_001;
        let span2 = self.contact_span * self.contact_span;
        let slots = &index.slots[..];
        let (edges, near) = (&mut self.edges, &mut self.near);
        edges.clear();
        near.clear();
        index.pairs(grid, reach2.max(span2), |k, m| {
            let (a, b) = (&slots[k], &slots[m]);
            let (i, j) = (a.robot(), b.robot());
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            let d2 = dx * dx + dy * dy;
            if within(d2, span2) {
                near.push((i as u32, j as u32));
            }
            if !(a.wants() || b.wants()) || !(a.blocking() && b.blocking()) || d2 > reach2 {
                return;
            }
            let r = radius[i] + radius[j] + margin;
            if far(dx, dy, r) {
                return;
            }
            if a.wants() && blocks(a.x, a.y, a.alpha, b.x, b.y, r, angle) {
                edges.push((i as u32, j as u32));
            }
            if b.wants() && blocks(b.x, b.y, b.alpha, a.x, a.y, r, angle) {
                edges.push((j as u32, i as u32));
            }
        });
        self.near_generation = (span2 > 0.0).then_some(index.generation);
        self.near_span = self.contact_span;
        self.rows_from_edges(n);
    }

    /// Every row from the neighbour lists' pairs (`lists.rs`), judged at the robots'
    /// positions now. Nothing of the rows is kept for the index's way: it finds every row
    /// again when next it runs.
    pub(super) fn rows_of_pairs(&mut self, pairs: &[(u32, u32)], ask: &Ask<'_>) {
        let n = ask.x.len();
        let (x, y, radius, wants, alpha) = (&ask.x[..n], &ask.y[..n], &ask.radius[..n], &ask.wants[..n], &ask.alpha[..n]);
        let bay: &[bool] = if ask.bay.is_empty() { &[] } else { &ask.bay[..n] };
        let (margin, angle) = (ask.margin, ask.angle);
        let edges = &mut self.edges;
        edges.clear();
        for &(i, j) in pairs {
            let (i, j) = (i as usize, j as usize);
            let (wi, wj) = (wants[i], wants[j]);
            // Robots in bays neither block nor wait.
            if !(wi || wj) || (!bay.is_empty() && (bay[i] || bay[j])) {
                continue;
            }
            let r = radius[i] + radius[j] + margin;
            let (dx, dy) = (x[j] - x[i], y[j] - y[i]);
            if far(dx, dy, r) {
                continue;
            }
            if wi && blocks(x[i], y[i], alpha[i], x[j], y[j], r, angle) {
                edges.push((i as u32, j as u32));
            }
            if wj && blocks(x[j], y[j], alpha[j], x[i], y[i], r, angle) {
                edges.push((j as u32, i as u32));
            }
        }
        // Few robots are blocked: their rows as spans of `to`, counted over the edges alone,
        // not over the fleet (the release takes the blocked in any order). The rows kept for
        // the index's way are left as they were: it finds every row again when next it runs.
        if self.span.len() != n {
            self.span.clear();
            self.span.resize(n, (0, 0));
        }
        let (span, blocked, to) = (&mut self.span[..], &mut self.blocked, &mut self.to);
        blocked.clear();
        for &(i, _) in edges.iter() {
            let s = &mut span[i as usize];
            if s.1 == 0 {
                blocked.push(i);
            }
            s.1 += 1;
        }
        let mut total = 0;
        for &i in blocked.iter() {
            let s = &mut span[i as usize];
            let count = s.1;
            // The start twice: the second walks to the row's end as the row is written.
            *s = (total, total);
            total += count;
        }
        to.clear();
        to.resize(total as usize, 0);
        for &(i, j) in edges.iter() {
            let s = &mut span[i as usize];
            to[s.1 as usize] = j;
            s.1 += 1;
        }
        self.inputs = None;
        self.same = false;
        self.near_generation = None;
    }

    /// The rows from `edges`, counted into rows by robot id; `blocked` with them.
    fn rows_from_edges(&mut self, n: usize) {
        let edges = &self.edges;
        let start = &mut self.start;
        start.clear();
        start.resize(n + 1, 0);
        for &(i, _) in edges {
            start[i as usize + 1] += 1;
        }
        self.blocked.clear();
        let mut total = 0;
        for i in 0..n {
            let c = start[i + 1];
            if c > 0 {
                self.blocked.push(i as u32);
            }
            start[i + 1] = total;
            total += c;
        }
        self.to.clear();
        self.to.resize(total as usize, 0);
        // `start[i + 1]` is now the start of row `i`: it walks to the row's end as the row is
        // written, and so becomes the start of row `i + 1`.
        for &(i, j) in edges {
            let c = &mut start[i as usize + 1];
            self.to[*c as usize] = j;
            *c += 1;
        }
    }

    /// The rows by the definition, pair by pair: a NaN radius or margin, which scenarios
    /// refuse but the public API takes, lets robots any distance apart block (`blocks`).
    pub(super) fn every_pair(&mut self, ask: &Ask<'_>) {
        let n = ask.x.len();
        self.reset(n);
        let (x, y, radius, wants, alpha, bay) = (ask.x, ask.y, ask.radius, ask.wants, ask.alpha, ask.bay);
        let out = |i: usize| !bay.is_empty() && bay[i];
        self.start.clear();
        for i in 0..n {
            self.start.push(self.to.len() as u32);
            if !wants[i] || out(i) {
                continue;
            }
            for j in (0..n).filter(|&j| j != i && !out(j)) {
                if blocks(x[i], y[i], alpha[i], x[j], y[j], radius[i] + radius[j] + ask.margin, ask.angle) {
                    self.to.push(j as u32);
                }
            }
            if self.to.len() > self.start[i] as usize {
                self.blocked.push(i as u32);
            }
        }
        self.start.push(self.to.len() as u32);
        // Nothing of this graph may be kept.
        self.inputs = None;
    }
}
