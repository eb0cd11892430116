//! The spatial index of fleets beyond [`super::TINY`] robots: every robot in one array of
//! slots sorted by grid cell, each slot holding what the collision test and the contact
//! count read of that robot (its cell, id, flags, position, heading) together.
//!
//! It is kept from step to step and repaired, not rebuilt. A robot changes cells every
//! dozen steps or so (cells are twice the contact distance wide, robots move a few px a
//! step), so after a refresh the slots are nearly sorted and an insertion sort moves a slot
//! a few places; no pass touches the empty cells. Robots of one cell stand in any order:
//! whatever reads the index finds the same pairs in any order, and counts or decides the
//! same from them. A refresh also notes which robots moved, or stepped into or out of a
//! bay, since the collision test last looked, with where they stood then, and whose wish to
//! move or heading changed: the test re-examines only those robots and their neighbours
//! (`blocking.rs`), and in a jam, where a few robots in a thousand move, that is most of its
//! saving. Robots in bays stay in the index, flagged: they neither block nor wait.
//!
//! Neighbours are found two ways, with the same tests, so the results are the same:
//! - all pairs at once (a pass over the sorted slots: the rest of a robot's cell, the next
//!   cell of its row, and the three cells below, found by two pointers that only move on),
//!   when most robots changed;
//! - the cells of a box around one point, a row at a time (`visit`), for the few that did.

use super::grid::Grid;

/// `a <= b`, or either is NaN: a NaN distance counts as near, so that `blocks` decides it.
#[inline]
pub(super) fn within(a: f64, b: f64) -> bool {
    a.partial_cmp(&b) != Some(std::cmp::Ordering::Greater)
}

/// The robot id in a slot's tag; above it, two flags.
const ROBOT: u32 = (1 << 30) - 1;
const WANTS: u32 = 1 << 31;
const BAY: u32 = 1 << 30;

/// One robot in the index.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Slot {
    /// The key of its grid cell ([`Grid::key`]).
    pub(super) cell: u32,
    /// The robot's id, whether it wants to move (out of a bay), whether it stands in a bay.
    tag: u32,
    pub(super) x: f64,
    pub(super) y: f64,
    /// Its heading, where it wants to move (as the collision test last read it).
    pub(super) alpha: f64,
}

impl Slot {
    #[inline]
    pub(super) fn robot(&self) -> usize {
        (self.tag & ROBOT) as usize
    }

    /// Wants to move, out of a bay, as the collision test last read it.
    #[inline]
    pub(super) fn wants(&self) -> bool {
        self.tag & WANTS != 0
    }

    /// In a bay: it neither blocks nor waits.
    #[inline]
    pub(super) fn in_bay(&self) -> bool {
        self.tag & BAY != 0
    }

    /// Whether the collision test looks at it as a robot that can block (not in a bay).
    #[inline]
    pub(super) fn blocking(&self) -> bool {
        !self.in_bay()
    }

    #[inline]
    fn set(&mut self, flag: u32, on: bool) {
        self.tag = if on { self.tag | flag } else { self.tag & !flag };
    }
}

/// A robot that moved, or stepped into or out of a bay, since the collision test last
/// looked, and where it stood then.
#[derive(Clone, Copy, Debug)]
pub(super) struct Moved {
    pub(super) robot: u32,
    pub(super) x: f64,
    pub(super) y: f64,
    /// Out of a bay then (a robot that could block).
    pub(super) blocking: bool,
}

/// The collision test's view of the robots: whether each wants to move, and its heading.
#[derive(Clone, Copy)]
pub(super) struct Wishes<'a> {
    pub(super) wants: &'a [bool],
    pub(super) alpha: &'a [f64],
}

/// Which lists a robot is noted in: moved since the collision test, or the count, looked.
const FOR_TEST: u8 = 1;
const FOR_COUNT: u8 = 2;
/// The lists of robots moved since the test, or the count, looked hold at most one robot in
/// this many (and one more); past that a list is only an overflow flag, and its reader finds
/// everything again (with the same result). Where the pass over pairs fits the cells, both
/// readers do so from one in eight anyway (`blocking.rs`, `contacts.rs`): in the first steps
/// of a run, where every robot moves, the rest of the fleet is not listed.
const LISTED_UP_TO: usize = 4;

/// The slots, kept sorted; each robot's place among them and what the slots last saw of it,
/// by robot id (so that finding what changed reads memory in order); and what changed since
/// the collision test, and since the contact count, last looked.
// Four flags of different readers (rows, both lists, the next refresh), not states of one.
#[allow(clippy::struct_excessive_bools)]
#[derive(Clone, Debug, Default)]
pub(super) struct Index {
    pub(super) slots: Vec<Slot>,
    /// The first slot of each grid row, and one past the last (rows + 1 entries), for
    /// [`Index::visit`]; found again only when a search needs it after the slots moved
    /// (`rows_stale`): where most robots changed, nothing searches.
    row_start: Vec<u32>,
    rows_stale: bool,
    /// By robot id: its slot, its position, whether it stands in a bay, whether it wants to
    /// move (out of a bay) and its heading, as the slots have them.
    place: Vec<u32>,
    pub(super) px: Vec<f64>,
    pub(super) py: Vec<f64>,
    aside: Vec<bool>,
    wants: Vec<bool>,
    alpha: Vec<f64>,
    /// Robots moved since the collision test last looked, and since the contact count did;
    /// per robot id, bits of which of the two lists it is in.
    pub(super) moved: Vec<Moved>,
    shifted: Vec<u32>,
    noted: Vec<u8>,
    /// Bits of the lists that more robots moved for than they hold (`LISTED_UP_TO`), as in
    /// `noted`.
    unlisted: u8,
    /// Robots whose wish to move or heading changed (at the last refresh with wishes).
    pub(super) turned: Vec<u32>,
    /// Set when the slots were built anew (the first refresh, or a fleet of another size):
    /// every robot is new to the collision test, and to the count.
    pub(super) rebuilt: bool,
    recount: bool,
    /// Refreshes so far: what was collected from the slots at one refresh is good until the
    /// next.
    pub(super) generation: u64,
    /// More than one robot in [`LISTED_UP_TO`] moved at the last refresh: the next refresh
    /// with wishes rewrites every slot without noting who changed ([`Index::rewrite`]).
    pub(super) sweeping: bool,
}

impl Index {
    /// Brings the slots to the robots' positions (`bay[i]`: in a bay; empty: nobody; `None`:
    /// as the slots have it) and, with `wishes`, to their wishes and headings; sorts them
    /// again; notes what changed.
    pub(super) fn refresh(&mut self, grid: &Grid, x: &[f64], y: &[f64], bay: Option<&[bool]>, wishes: Option<Wishes<'_>>) {
        let n = x.len();
        self.generation += 1;
        if self.slots.len() != n {
            self.build(grid, x, &y[..n], bay.unwrap_or(&[]));
        }
        self.turned.clear();
        let sorted = match (bay, wishes) {
            (Some(bay), Some(w)) if self.sweeping && !bay.is_empty() => self.rewrite(grid, x, y, |i, _| bay[i], w),
            (Some(_), Some(w)) if self.sweeping => self.rewrite(grid, x, y, |_, _| false, w),
            _ => {
                let sorted = match bay {
                    Some(bay) if !bay.is_empty() => self.follow(grid, x, y, |i, _| bay[i]),
                    Some(_) => self.follow(grid, x, y, |_, _| false),
                    None => self.follow(grid, x, y, |_, aside| aside),
                };
                if let Some(w) = wishes {
                    self.follow_wishes(w);
                }
                sorted
            }
        };
        if !sorted {
            self.repair();
            self.rows_stale = true;
        }
    }

    /// The positions alone, every slot written again and sorted, nothing noted (for the
    /// neighbour lists' builds, `lists.rs`, which read positions and pairs only).
    pub(super) fn place_all(&mut self, grid: &Grid, x: &[f64], y: &[f64]) {
        let n = x.len();
        self.generation += 1;
        if self.slots.len() != n {
            self.build(grid, x, &y[..n], &[]);
            return;
        }
        let (y, place) = (&y[..n], &self.place[..n]);
        let slots = &mut self.slots[..];
        let mut sorted = true;
        for i in 0..n {
            let s = &mut slots[place[i] as usize];
            let cell = grid.key(x[i], y[i]);
            sorted &= cell == s.cell;
            (s.cell, s.x, s.y) = (cell, x[i], y[i]);
        }
        self.px.copy_from_slice(x);
        self.py.copy_from_slice(y);
        if !sorted {
            self.repair();
            self.rows_stale = true;
        }
    }

    /// The positions and bays of [`Index::refresh`]; whether the slots are still sorted.
    #[inline]
    fn follow(&mut self, grid: &Grid, x: &[f64], y: &[f64], bay: impl Fn(usize, bool) -> bool) -> bool {
        let n = x.len();
        let (y, px, py, aside, noted, place) = (&y[..n], &mut self.px[..n], &mut self.py[..n], &mut self.aside[..n], &mut self.noted[..n], &self.place[..n]);
        let mut sorted = true;
        let cap = n / LISTED_UP_TO + 1;
        let mut unlisted = self.unlisted;
        let mut changed = 0;
        for i in 0..n {
            let (xi, yi) = (x[i], y[i]);
            let b = bay(i, aside[i]);
            // Bits, not values: a NaN is a change, and so (harmlessly) is 0.0 to -0.0.
            if (xi.to_bits() ^ px[i].to_bits()) | (yi.to_bits() ^ py[i].to_bits()) == 0 && b == aside[i] {
                continue;
            }
            changed += 1;
            // Past `cap` robots a list is only a count: its reader looks at everyone anyway
            // (and once both lists are, nothing more is noted).
            if unlisted != FOR_TEST | FOR_COUNT {
                let mut note = noted[i];
                if note & FOR_TEST == 0 && unlisted & FOR_TEST == 0 {
                    if self.moved.len() < cap {
                        self.moved.push(Moved { robot: i as u32, x: px[i], y: py[i], blocking: !aside[i] });
                        note |= FOR_TEST;
                    } else {
                        unlisted |= FOR_TEST;
                    }
                }
                if note & FOR_COUNT == 0 && unlisted & FOR_COUNT == 0 {
                    if self.shifted.len() < cap {
                        self.shifted.push(i as u32);
                        note |= FOR_COUNT;
                    } else {
                        unlisted |= FOR_COUNT;
                    }
                }
                noted[i] = note;
            }
            (px[i], py[i], aside[i]) = (xi, yi, b);
            let s = &mut self.slots[place[i] as usize];
            (s.x, s.y) = (xi, yi);
            s.set(BAY, b);
            let cell = grid.key(xi, yi);
            sorted &= cell == s.cell;
            s.cell = cell;
        }
        self.unlisted = unlisted;
        self.sweeping = changed >= cap;
        sorted
    }

    /// [`Index::refresh`] where most robots move: every slot written again from the robots'
    /// positions, bays, wishes and headings, without comparing or noting who changed; both
    /// lists then count as overflowed, so their readers look at everyone (which they would
    /// from so many changes anyway, with the same results). Whether the slots are still
    /// sorted. It counts who moved all the same, to go back to following robot by robot
    /// when few do.
    #[inline]
    fn rewrite(&mut self, grid: &Grid, x: &[f64], y: &[f64], bay: impl Fn(usize, bool) -> bool, Wishes { wants, alpha }: Wishes<'_>) -> bool {
        let n = x.len();
        let (y, px, py, aside, place) = (&y[..n], &mut self.px[..n], &mut self.py[..n], &mut self.aside[..n], &self.place[..n]);
        let (wants, alpha, pw, pa) = (&wants[..n], &alpha[..n], &mut self.wants[..n], &mut self.alpha[..n]);
        let slots = &mut self.slots[..];
        let mut sorted = true;
        let mut changed = 0;
        for i in 0..n {
            let (xi, yi) = (x[i], y[i]);
            let b = bay(i, aside[i]);
            changed += usize::from((xi.to_bits() ^ px[i].to_bits()) | (yi.to_bits() ^ py[i].to_bits()) != 0 || b != aside[i]);
            // A robot in a bay neither blocks nor waits: it wants nothing of the test.
            let w = wants[i] && !b;
            let cell = grid.key(xi, yi);
            let s = &mut slots[place[i] as usize];
            sorted &= cell == s.cell;
            let tag = i as u32 | if w { WANTS } else { 0 } | if b { BAY } else { 0 };
            *s = Slot { cell, tag, x: xi, y: yi, alpha: alpha[i] };
            (px[i], py[i], aside[i], pw[i], pa[i]) = (xi, yi, b, w, alpha[i]);
        }
        self.unlisted = FOR_TEST | FOR_COUNT;
        self.sweeping = changed > n / LISTED_UP_TO;
        sorted
    }

    /// The wishes and headings of [`Index::refresh`] (a robot in a bay neither blocks nor
    /// waits: it wants nothing of the test).
    fn follow_wishes(&mut self, Wishes { wants, alpha }: Wishes<'_>) {
        let n = self.place.len();
        let (wants, alpha, pw, pa, aside) = (&wants[..n], &alpha[..n], &mut self.wants[..n], &mut self.alpha[..n], &self.aside[..n]);
        for i in 0..n {
            let w = wants[i] && !aside[i];
            if w == pw[i] && (!w || alpha[i].to_bits() == pa[i].to_bits()) {
                continue;
            }
            (pw[i], pa[i]) = (w, alpha[i]);
            let s = &mut self.slots[self.place[i] as usize];
            s.set(WANTS, w);
            s.alpha = alpha[i];
            self.turned.push(i as u32);
        }
    }

    /// New slots for every robot, sorted; every robot counts as new, wanting nothing.
    fn build(&mut self, grid: &Grid, x: &[f64], y: &[f64], bay: &[bool]) {
        let n = x.len();
        self.slots.clear();
        self.slots.extend((0..n).map(|i| {
            let mut s = Slot { cell: grid.key(x[i], y[i]), tag: i as u32, x: x[i], y: y[i], alpha: 0.0 };
            s.set(BAY, !bay.is_empty() && bay[i]);
            s
        }));
        self.slots.sort_unstable_by_key(|s| s.cell);
        self.place.clear();
        self.place.resize(n, 0);
        for (k, s) in self.slots.iter().enumerate() {
            self.place[s.robot()] = k as u32;
        }
        (self.px, self.py) = (x.to_vec(), y.to_vec());
        self.aside.clear();
        self.aside.extend((0..n).map(|i| !bay.is_empty() && bay[i]));
        self.wants.clear();
        self.wants.resize(n, false);
        self.alpha.clear();
        self.alpha.resize(n, 0.0);
        self.moved.clear();
        self.shifted.clear();
        self.unlisted = 0;
        self.noted.clear();
        self.noted.resize(n, 0);
        self.rebuilt = true;
        self.recount = true;
        self.rows(grid);
    }

    /// Insertion sort from nearly sorted slots (places follow); far from sorted (robots
    /// jumped), a sort outright.
    fn repair(&mut self) {
        let n = self.slots.len();
        let (slots, place) = (&mut self.slots[..], &mut self.place[..]);
        let mut moves = 0;
        for k in 1..n {
            // The cells alone first: most slots are in order, and are not copied.
            if slots[k - 1].cell <= slots[k].cell {
                continue;
            }
            let v = slots[k];
            let mut j = k;
            while j > 0 && slots[j - 1].cell > v.cell {
                slots[j] = slots[j - 1];
                place[slots[j].robot()] = j as u32;
                j -= 1;
            }
            slots[j] = v;
            place[v.robot()] = j as u32;
            moves += k - j;
            if moves > 8 * n {
                slots.sort_unstable_by_key(|s| s.cell);
                for (k, s) in slots.iter().enumerate() {
                    place[s.robot()] = k as u32;
                }
                return;
            }
        }
    }

    /// Makes [`Index::visit`] ready: `row_start` up to date with the slots.
    #[inline]
    pub(super) fn ready_rows(&mut self, grid: &Grid) {
        if self.rows_stale {
            self.rows(grid);
        }
    }

    /// `row_start` from the sorted slots.
    fn rows(&mut self, grid: &Grid) {
        self.rows_stale = false;
        let rows = grid.rows();
        self.row_start.clear();
        for (k, s) in self.slots.iter().enumerate() {
            let row = (s.cell >> grid.shift) as usize;
            if row >= self.row_start.len() {
                self.row_start.resize(row + 1, k as u32);
            }
        }
        self.row_start.resize(rows + 1, self.slots.len() as u32);
    }

    /// The robots noted as moved since the last call (the contact count's list), into
    /// `into`; whether every robot is to be counted again: the slots were built anew since,
    /// or too many moved to be listed.
    pub(super) fn take_shifted(&mut self, into: &mut Vec<u32>) -> bool {
        into.clear();
        for &i in &self.shifted {
            self.noted[i as usize] &= !FOR_COUNT;
        }
        std::mem::swap(into, &mut self.shifted);
        let unlisted = self.unlisted & FOR_COUNT != 0;
        self.unlisted &= !FOR_COUNT;
        std::mem::take(&mut self.recount) | unlisted
    }

    /// The robots noted as moved since the last call, with their places then, into `into`;
    /// the marks are cleared. Whether too many moved to be listed (every row is to be found
    /// again).
    pub(super) fn take_moved(&mut self, into: &mut Vec<Moved>) -> bool {
        into.clear();
        for m in &self.moved {
            self.noted[m.robot as usize] &= !FOR_TEST;
        }
        std::mem::swap(into, &mut self.moved);
        self.rebuilt = false;
        let unlisted = self.unlisted & FOR_TEST != 0;
        self.unlisted &= !FOR_TEST;
        unlisted
    }

    /// The slots of the cells within `h` of `(x, y)` along both axes, a row at a time: `f(k)`
    /// for each slot `k` (the point's own robot included), after [`Index::ready_rows`]. Every
    /// robot whose position lies within `h` of the point along each axis is among them: cells
    /// are monotonic in the position, so the box's corner cells bound every cell inside it.
    #[inline]
    pub(super) fn visit(&self, grid: &Grid, x: f64, y: f64, h: f64, mut f: impl FnMut(usize)) {
        debug_assert!(!self.rows_stale, "ready_rows before visit");
        let (c0, r0) = grid.cell_of(x - h, y - h);
        let (c1, r1) = grid.cell_of(x + h, y + h);
        for row in r0..=r1 {
            let (lo, hi) = (grid.key_at(c0, row), grid.key_at(c1, row));
            let (a, b) = (self.row_start[row as usize] as usize, self.row_start[row as usize + 1] as usize);
            let in_row = &self.slots[a..b];
            let k0 = a + in_row.partition_point(|s| s.cell < lo);
            let k1 = a + in_row.partition_point(|s| s.cell <= hi);
            for k in k0..k1 {
                f(k);
            }
        }
    }

    /// Every pair of slots `k != m` in neighbouring cells (the same cell, the next one in
    /// its row, or the three below) whose positions are not farther apart than `sqrt(r2)`
    /// (a NaN distance counts as near): `f(k, m)`, each pair once. Every pair within a
    /// cell's width is among them. The grid keeps a free column on each side, so the next
    /// key is in the same row and the three below in the next.
    #[inline]
    pub(super) fn pairs(&self, grid: &Grid, r2: f64, mut f: impl FnMut(usize, usize)) {
        let slots = &self.slots[..];
        let n = slots.len();
        let down = 1u32 << grid.shift;
        // The first slot at or past the cell below-left, and past the cell below-right: both
        // only move on as the cell grows.
        let (mut b0, mut b1) = (0, 0);
        for k in 0..n {
            let s = slots[k];
            let c = s.cell;
            let mut m = k + 1;
            while m < n && slots[m].cell <= c + 1 {
                let (dx, dy) = (slots[m].x - s.x, slots[m].y - s.y);
                if within(dx * dx + dy * dy, r2) {
                    f(k, m);
                }
                m += 1;
            }
            let (lo, hi) = (c + down - 1, c + down + 1);
            while b0 < n && slots[b0].cell < lo {
                b0 += 1;
            }
            b1 = b1.max(b0);
            while b1 < n && slots[b1].cell <= hi {
                b1 += 1;
            }
            for (m, t) in slots.iter().enumerate().take(b1).skip(b0) {
                let (dx, dy) = (t.x - s.x, t.y - s.y);
                if within(dx * dx + dy * dy, r2) {
                    f(k, m);
                }
            }
        }
    }
}
