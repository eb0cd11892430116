//! `soonest`: `auction` on exact distances, the default under the 2026 rules; and `reassign`,
//! the same auction put up again every step.
//!
//! ## What it does
//! Every free robot bids on the free tasks its estimated completion: the distance to the first
//! errand, then errand to errand, counted in moves along free cells (a breadth-first search
//! from each errand cell, cached), where `auction` counts grid distance; the lowest bid over
//! all pairs wins, round after round. Robots bid first on the tasks nearest by grid distance
//! (a lower bound of the exact one), and the exact distances are only worked out for those.
//! The searches of a call expand at most [`SEARCH_CELLS_PER_CALL`] cells and the cache holds
//! at most [`TABLE_BUDGET`] bytes: past them, grid distance stands in (a count of cells, not a
//! clock, so a run is the same on every machine).
//!
//! ## When to use it
//! Under the 2026 rules, whose runs are short (500 ticks: a robot finishes one to three
//! tasks), so the tasks finished soonest are the ones that count, and on maps whose walls make
//! grid distance a poor guide (mazes, rooms with doors). On the 32 × 32 to 64 × 64 example maps
//! of the 2026 Start-Kit it finishes more than `auction` and far more than `spread`
//! (docs/lorr.md).
//!
//! ## Cost
//! O(free robots × free tasks) grid distances for the lower bounds, then at most
//! [`CANDIDATES`] exact bids per robot; a search of the map per errand cell first met.
//!
//! ## `reassign`
//! Under the 2024 and 2026 rules a task may be taken back from its robot until the robot
//! reaches its first errand. `reassign` uses that: every step it puts up every task not yet
//! opened (held or not) among every robot without an opened task, and runs the auction again,
//! each bid [`APPROACH`] times the distance to the first errand plus the task's own length,
//! plus [`QUEUE`] cells of approach for every robot already given a task there. A robot freed
//! next to a station takes the task a robot far away was heading for, which takes another
//! (the 2024 winner's scheduler, No Man's Sky, scores pairs by approach and length, greedily
//! and then by swaps in the time left; this one is the greedy part, to the end).
//!
//! A robot bound for a first errand counts as [`STAY`] cells nearer to it: without that (approach counted 5 times), about 450 robots a step turned from one
//! station to another on `MR24-SORTATION` (236,939 changes of first errand in its first 500
//! steps, 39,371 with it, about 13,900 of either after a finished task; 13,854 and 13,933
//! tasks finished). The tasks
//! of one first errand's cell are put up as one queue, shortest first ([`by_cells`]), and each
//! leg is read on the table of its earlier errand (distances are symmetric here), so the
//! tables are those of the first errands' cells.
//!
//! ## Options
//! None.
//!
//! ## Example
//! `multibots lorr problem.json --scheduler soonest` (or `--scheduler reassign`)

use super::{ScheduleView, Scheduler};
use crate::rules::grid::planner::{Distances, FAR};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Cells the searches of one call may expand.
pub const SEARCH_CELLS_PER_CALL: u64 = 20_000_000;
/// The memory the tables may take.
pub const TABLE_BUDGET: usize = 512 << 20;
/// Exact bids per robot at a time (its nearest tasks by grid distance).
const CANDIDATES: usize = 8;
/// Cells by which `reassign` counts a robot nearer the first errand it is bound for than it is,
/// so that it leaves it only for a clearly better one.
pub const STAY: u32 = 8;
/// Cells of approach `reassign` counts for every robot bound for the same first errand: a
/// station's tasks go to the robots nearest it up to a point, then to the next station.
/// Without it, `MR24-WAREHOUSE` transposed jammed in front of its stations (per 1,000 steps
/// 24,283, 26,390, 22,516, 18,956, 17,823 tasks; with it, 25,139, 27,868, 27,931 in 3,000
/// steps).
pub const QUEUE: u32 = 30;

/// Sequential single-item auction on exact distances.
pub struct Soonest {
    /// How many times the approach to the first errand counts against the task's own length
    /// (1 for `soonest`).
    approach: u32,
    /// Whether tasks not yet opened are put up again every step (`reassign`).
    reopen: bool,
    dist: Option<Distances>,
    /// Each task's errand-to-errand length once known exactly, by task id.
    legs: Vec<u32>,
    /// The map's free cells.
    free: Option<usize>,
}

impl Soonest {
    /// A `soonest` scheduler.
    #[must_use]
    pub fn new() -> Soonest {
        Soonest { approach: 1, reopen: false, dist: None, legs: Vec::new(), free: None }
    }

    /// `reassign`: every step, every task not yet opened is put up again among the robots
    /// without an opened task, each bid [`APPROACH`] times the approach plus the task's length.
    #[must_use]
    pub fn reassign() -> Soonest {
        Soonest { approach: APPROACH, reopen: true, ..Soonest::new() }
    }
}

impl Default for Soonest {
    fn default() -> Self {
        Soonest::new()
    }
}

/// How many times `reassign` counts the approach to a task's first errand against the task's
/// length. The 2024 winner counted it 5 times; with our planners 20 finishes as many on the
/// random maps and more where tasks are long (`TR-24-warehouse_large_5000`: 92,160 against
/// 90,015), since a lighter approach takes the short tasks first and leaves the pool the long
/// ones (the tasks finished there were 183 cells long on average in the first 1,000 steps,
/// then 225).
pub const APPROACH: u32 = 20;

/// The distance between two cells: exact if `to`'s table is cached or fits the budget, else
/// the grid distance.
fn between(dist: &mut Distances, view: &ScheduleView<'_>, from: u32, to: u32, budget: &mut u64) -> u32 {
    match dist.search_within(to, budget) {
        Some(slot) => match dist.get(slot, from) {
            FAR => u32::from(FAR),
            d => u32::from(d),
        },
        None => view.manhattan(from, to),
    }
}

impl Scheduler for Soonest {
    fn name(&self) -> &'static str {
        if self.reopen {
            "reassign"
        } else {
            "soonest"
        }
    }

    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        if self.reopen {
            for (k, p) in proposal.iter_mut().enumerate() {
                let id = view.pool.current[k];
                if id >= 0 && view.pool.tasks[id as usize].done == 0 {
                    *p = -1;
                }
            }
        }
        // Free robots: those without a task in force (`reassign`: or with one not opened yet),
        // and none proposed yet.
        let robots: Vec<usize> = (0..proposal.len()).filter(|&k| proposal[k] == -1 && (self.reopen || view.pool.current[k] == -1)).collect();
        let proposed: std::collections::HashSet<i64> = proposal.iter().copied().filter(|&id| id >= 0).collect();
        let mut tasks: Vec<u32> = view
            .pool
            .open()
            .iter()
            .copied()
            .filter(|&id| !proposed.contains(&i64::from(id)) && (self.reopen || view.pool.tasks[id as usize].agent == -1))
            .collect();
        tasks.sort_unstable();
        if robots.is_empty() || tasks.is_empty() {
            return;
        }
        let free = *self.free.get_or_insert_with(|| view.map.free.iter().filter(|&&f| f).count().max(1));
        // On a map of millions of cells a search costs more than it gains: grid distance.
        let mut budget = if free > crate::rules::grid::planner::HUGE { 0 } else { SEARCH_CELLS_PER_CALL };
        let dist = self.dist.get_or_insert_with(|| Distances::new(view.map, (TABLE_BUDGET / (2 * free)).max(8)));
        dist.tick();
        if self.legs.len() < view.pool.tasks.len() {
            self.legs.resize(view.pool.tasks.len(), u32::MAX);
        }
        let mut shape: Vec<(u32, u32)> = Vec::with_capacity(tasks.len());
        for &id in &tasks {
            let errands = &view.lines[view.pool.tasks[id as usize].line as usize];
            if self.legs[id as usize] == u32::MAX {
                let mut exact = true;
                let mut sum = 0u32;
                for w in errands.windows(2) {
                    // Distances are symmetric: `reassign` reads a leg on the table of its
                    // earlier errand, so that its tables are those of the first errands (352
                    // cells for `MR24-WAREHOUSE`'s 100,000 tasks), which its bids need anyway.
                    let (from, to) = if self.reopen { (w[1], w[0]) } else { (w[0], w[1]) };
                    sum = sum.saturating_add(between(dist, view, from, to, &mut budget));
                    exact &= dist.cached(to).is_some();
                }
                if exact {
                    self.legs[id as usize] = sum;
                }
                shape.push((errands[0], sum));
            } else {
                shape.push((errands[0], self.legs[id as usize]));
            }
        }
        let approach = self.approach;
        let sale = Sale { approach, robots: &robots, tasks: &tasks, shape: &shape };
        if self.reopen {
            by_cells(view, dist, &mut budget, &sale, proposal);
            return;
        }
        if robots.len() * tasks.len() > RINGS_FROM {
            by_tasks(view, dist, &mut budget, &sale, proposal);
            return;
        }
        let mut taken = vec![false; tasks.len()];
        let mut heap: BinaryHeap<Reverse<(u32, u32, u32)>> = BinaryHeap::new();
        let mut pending = vec![0usize; robots.len()];
        let mut bids_of = |r: usize, taken: &[bool], heap: &mut BinaryHeap<Reverse<(u32, u32, u32)>>, budget: &mut u64| -> usize {
            let at = view.loc[robots[r]];
            let mut near: Vec<(u32, u32)> = (0..tasks.len())
                .filter(|&i| !taken[i])
                .map(|i| (approach.saturating_mul(view.manhattan(at, shape[i].0)).saturating_add(shape[i].1), i as u32))
                .collect();
            let keep = CANDIDATES.min(near.len());
            if keep == 0 {
                return 0;
            }
            near.select_nth_unstable(keep - 1);
            near.truncate(keep);
            near.sort_unstable();
            for &(_, i) in &near {
                let bid = approach.saturating_mul(between(dist, view, at, shape[i as usize].0, budget)).saturating_add(shape[i as usize].1);
                heap.push(Reverse((bid, i, r as u32)));
            }
            keep
        };
        for (r, p) in pending.iter_mut().enumerate() {
            *p = bids_of(r, &taken, &mut heap, &mut budget);
        }
        let mut sold = vec![false; robots.len()];
        while let Some(Reverse((_, i, r))) = heap.pop() {
            let (i, r) = (i as usize, r as usize);
            if sold[r] {
                continue;
            }
            pending[r] -= 1;
            if taken[i] {
                if pending[r] == 0 {
                    pending[r] = bids_of(r, &taken, &mut heap, &mut budget);
                }
                continue;
            }
            taken[i] = true;
            sold[r] = true;
            proposal[robots[r]] = i64::from(tasks[i]);
        }
    }
}

/// Robot-task pairs above which the auction is run from the tasks' side: each task takes bids
/// from its [`CANDIDATES`] nearest free robots, found in rings of buckets of [`BUCKET`] cells
/// (a fleet fills the map, so a few rings hold them), rather than every robot scanning every
/// task (at step 0 of 10,000 robots and 10,000 tasks: 0.1 s rather than 8 s).
const RINGS_FROM: usize = 1_000_000;
/// A bucket's side, in cells.
const BUCKET: u32 = 16;

/// Points of the map (robots, or cells holding tasks) in buckets of [`BUCKET`] × [`BUCKET`]
/// cells, to find those nearest a cell. A point taken (a robot sold, a cell emptied) leaves its
/// bucket, so that searches late in an auction, when most points near a cell are taken, do
/// not go over them again.
struct Near {
    rows: u32,
    cols: u32,
    /// Per bucket, its points' (row, column, index): rows and columns at hand, not divided out
    /// of a cell per point and search.
    buckets: Vec<Vec<(u32, u32, u32)>>,
    /// Per point, its bucket and its place there; `u32::MAX` once taken.
    at: Vec<(u32, u32)>,
    left: usize,
}

impl Near {
    /// `cells[i]` is point `i`.
    fn new(view: &ScheduleView<'_>, cells: impl Iterator<Item = u32>) -> Near {
        let (rows, cols) = (view.map.rows.div_ceil(BUCKET), view.map.cols.div_ceil(BUCKET));
        let mut buckets: Vec<Vec<(u32, u32, u32)>> = vec![Vec::new(); (rows * cols) as usize];
        let mut at = Vec::new();
        for (i, cell) in cells.enumerate() {
            let (y, x) = view.map.row_col(cell);
            let b = (y / BUCKET) * cols + x / BUCKET;
            at.push((b, buckets[b as usize].len() as u32));
            buckets[b as usize].push((y, x, i as u32));
        }
        let left = at.len();
        Near { rows, cols, buckets, at, left }
    }

    fn taken(&self, i: usize) -> bool {
        self.at[i].0 == u32::MAX
    }

    fn take(&mut self, i: usize) {
        let (b, place) = self.at[i];
        let bucket = &mut self.buckets[b as usize];
        bucket.swap_remove(place as usize);
        if let Some(&(_, _, moved)) = bucket.get(place as usize) {
            self.at[moved as usize].1 = place;
        }
        self.at[i] = (u32::MAX, u32::MAX);
        self.left -= 1;
    }

    /// The `want` points left nearest `cell` by grid distance (all of them once fewer are
    /// left), as (distance, point), nearest first.
    fn nearest(&self, view: &ScheduleView<'_>, cell: u32, want: usize) -> Vec<(u32, u32)> {
        self.best_by(view, cell, want, |floor| floor, |d, _| d)
    }

    /// The `want` points left of least `key(grid distance, point)`, as (key, point), least
    /// first (then lowest point), where `bound(d)` is at most the key of any point `d` or more
    /// away: the rings stop as soon as nothing further can do better, rather than sweep the map.
    fn best_by(&self, view: &ScheduleView<'_>, cell: u32, want: usize, bound: impl Fn(u32) -> u32, key: impl Fn(u32, u32) -> u32) -> Vec<(u32, u32)> {
        let want = want.min(self.left);
        if want == 0 {
            return Vec::new();
        }
        let (y, x) = view.map.row_col(cell);
        let (by, bx) = (i64::from(y / BUCKET), i64::from(x / BUCKET));
        let mut best: Vec<(u32, u32)> = Vec::with_capacity(want + 1);
        for k in 0..=i64::from(self.rows.max(self.cols)) {
            let floor = ((k - 1).max(0) as u32) * BUCKET;
            if best.len() == want && bound(floor) > best[want - 1].0 {
                break;
            }
            for dy in -k..=k {
                for dx in -k..=k {
                    if dy.abs() != k && dx.abs() != k {
                        continue;
                    }
                    let (qy, qx) = (by + dy, bx + dx);
                    if qy < 0 || qx < 0 || qy >= i64::from(self.rows) || qx >= i64::from(self.cols) {
                        continue;
                    }
                    for &(py, px, i) in &self.buckets[(qy * i64::from(self.cols) + qx) as usize] {
                        let found = (key(py.abs_diff(y) + px.abs_diff(x), i), i);
                        if best.len() < want || found < best[best.len() - 1] {
                            let at = best.partition_point(|&b| b < found);
                            best.insert(at, found);
                            best.truncate(want);
                        }
                    }
                }
            }
        }
        best
    }
}

/// What an auction sells and to whom: the robots (fleet indices), the tasks (ids), each
/// task's first errand and length (`shape`), and the weight of a robot's approach.
#[derive(Clone, Copy)]
struct Sale<'a> {
    approach: u32,
    robots: &'a [usize],
    tasks: &'a [u32],
    shape: &'a [(u32, u32)],
}

/// The auction from the tasks' side; the same rule (the least bid over all pairs wins, round
/// after round), each task's bids coming from the robots nearest its first errand.
fn by_tasks(view: &ScheduleView<'_>, dist: &mut Distances, budget: &mut u64, sale: &Sale<'_>, proposal: &mut [i64]) {
    let Sale { approach, robots, tasks, shape } = *sale;
    let mut near = Near::new(view, robots.iter().map(|&k| view.loc[k]));
    let mut heap: BinaryHeap<Reverse<(u32, u32, u32)>> = BinaryHeap::new();
    let mut pending = vec![0usize; tasks.len()];
    let mut bids_for = |i: usize, near: &Near, heap: &mut BinaryHeap<Reverse<(u32, u32, u32)>>, budget: &mut u64| -> usize {
        let found = near.nearest(view, shape[i].0, CANDIDATES);
        for &(_, r) in &found {
            let bid = approach.saturating_mul(between(dist, view, view.loc[robots[r as usize]], shape[i].0, budget)).saturating_add(shape[i].1);
            heap.push(Reverse((bid, i as u32, r)));
        }
        found.len()
    };
    for (i, p) in pending.iter_mut().enumerate() {
        *p = bids_for(i, &near, &mut heap, budget);
    }
    let mut taken = vec![false; tasks.len()];
    while let Some(Reverse((_, i, r))) = heap.pop() {
        let (i, r) = (i as usize, r as usize);
        if taken[i] {
            continue;
        }
        pending[i] -= 1;
        if near.taken(r) {
            if pending[i] == 0 {
                pending[i] = bids_for(i, &near, &mut heap, budget);
            }
            continue;
        }
        taken[i] = true;
        near.take(r);
        proposal[robots[r]] = i64::from(tasks[i]);
        if near.left == 0 {
            break;
        }
    }
}

/// `reassign`'s auction: the least bid over all pairs wins, round after round, with the
/// tasks of a first errand's cell put up as one queue, least length first (then lowest id):
/// every robot bids less for the shorter of two tasks there, so the cell sells them in that
/// order anyway. A cell's bids rise as it sells (its next task is longer, and [`QUEUE`] more
/// for the robot just sent there): a bid made before is raised when it comes up. Tasks
/// outnumber robots, so each robot bids on the [`CANDIDATES`] cells it could take cheapest by
/// grid distance when it looks (a lower bound of its bid), and on the cell it is bound for; it
/// looks again only once those are all empty, so the queue moves a robot among those cells,
/// not beyond. (From the cells' side, 620 cells competing for the same robots on
/// `MR24-SORTATION`, the searches took as long as the planner.)
fn by_cells(view: &ScheduleView<'_>, dist: &mut Distances, budget: &mut u64, sale: &Sale<'_>, proposal: &mut [i64]) {
    let Sale { approach, robots, tasks, shape } = *sale;
    let stay = approach.saturating_mul(STAY);
    let mut order: Vec<u32> = (0..tasks.len() as u32).collect();
    order.sort_unstable_by_key(|&i| (shape[i as usize].0, shape[i as usize].1, tasks[i as usize]));
    // Per cell: its first errand and its tasks' range in `order`; `next` is the first unsold.
    let mut cells: Vec<(u32, usize, usize)> = Vec::new();
    for (at, &i) in order.iter().enumerate() {
        match cells.last_mut() {
            Some(c) if c.0 == shape[i as usize].0 => c.2 = at + 1,
            _ => cells.push((shape[i as usize].0, at, at + 1)),
        }
    }
    // Per robot, the cell of the task it holds (not opened yet): keeping it is worth `stay`.
    // `cells` is in cell order, so a search finds it.
    let held: Vec<u32> = robots
        .iter()
        .map(|&k| match view.pool.current[k] {
            id if id >= 0 => {
                let first = view.lines[view.pool.tasks[id as usize].line as usize][0];
                cells.binary_search_by_key(&first, |c| c.0).map_or(u32::MAX, |g| g as u32)
            }
            _ => u32::MAX,
        })
        .collect();
    let mut next: Vec<usize> = cells.iter().map(|c| c.1).collect();
    let mut open = Near::new(view, cells.iter().map(|c| c.0));
    // No bid is below the least length: the bound of the rings' search.
    let least = shape.iter().map(|s| s.1).min().unwrap_or(0);
    let queue = approach.saturating_mul(QUEUE);
    // A cell's next task: its length, and `queue` for every robot the cell has sold one to.
    let legs = |g: usize, next: &[usize]| shape[order[next[g]] as usize].1.saturating_add(queue.saturating_mul((next[g] - cells[g].1) as u32));
    // (bid, cell, robot, the bid less the task's length)
    let mut heap: BinaryHeap<Reverse<(u32, u32, u32, u32)>> = BinaryHeap::new();
    let mut bids_of = |r: usize, open: &Near, next: &[usize], heap: &mut BinaryHeap<Reverse<(u32, u32, u32, u32)>>, budget: &mut u64| -> usize {
        let at = view.loc[robots[r]];
        let mut found = open.best_by(
            view,
            at,
            CANDIDATES,
            |floor| approach.saturating_mul(floor).saturating_add(least),
            |d, g| approach.saturating_mul(d).saturating_add(legs(g as usize, next)),
        );
        let h = held[r];
        if h != u32::MAX && !open.taken(h as usize) && !found.iter().any(|f| f.1 == h) {
            found.push((0, h));
        }
        for &(_, g) in &found {
            let d = approach.saturating_mul(between(dist, view, at, cells[g as usize].0, budget));
            let d = if g == h { d.saturating_sub(stay) } else { d };
            heap.push(Reverse((d.saturating_add(legs(g as usize, next)), g, r as u32, d)));
        }
        found.len()
    };
    let mut pending: Vec<usize> = (0..robots.len()).map(|r| bids_of(r, &open, &next, &mut heap, budget)).collect();
    let mut sold = vec![false; robots.len()];
    let mut left = robots.len();
    while let Some(Reverse((bid, g, r, d))) = heap.pop() {
        let (g, r) = (g as usize, r as usize);
        if sold[r] {
            continue;
        }
        if open.taken(g) {
            pending[r] -= 1;
            if pending[r] == 0 {
                pending[r] = bids_of(r, &open, &next, &mut heap, budget);
            }
            continue;
        }
        let now = d.saturating_add(legs(g, &next));
        if now > bid {
            heap.push(Reverse((now, g as u32, r as u32, d)));
            continue;
        }
        proposal[robots[r]] = i64::from(tasks[order[next[g]] as usize]);
        next[g] += 1;
        if next[g] == cells[g].2 {
            open.take(g);
        }
        sold[r] = true;
        left -= 1;
        if left == 0 {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::lorr::GridMap;
    use crate::rules::grid::pool::TaskPool;

    #[test]
    fn reassign_hands_an_unopened_task_to_a_nearer_robot_and_leaves_opened_ones() {
        let map = GridMap::parse("type octile\nheight 1\nwidth 20\nmap\n....................\n").unwrap();
        // Task 0 = [10, 15], task 1 = [2, 3], task 2 = [12, 19]. Robot 0 (at 0) holds task 0,
        // not opened; robot 1 (at 12, task 2's first errand) is free; robot 2 (at 18) holds
        // task 2 and has opened it.
        let lines = vec![vec![10, 15], vec![2, 3], vec![12, 19]];
        let mut pool = TaskPool::new(3, 3, lines.len());
        for (k, id) in [(0usize, 0usize), (2, 2)] {
            pool.current[k] = id as i64;
            pool.tasks[id].agent = k as i64;
        }
        pool.tasks[2].done = 1;
        let loc = [0, 12, 18];
        let view = ScheduleView { map: &map, loc: &loc, heading: &[0; 3], pool: &pool, lines: &lines, t: 1 };
        // Bids, 20 × approach + length: robot 0 for task 1 40 + 1, for task 0 200 - 160 (it is
        // bound there: `STAY`) + 5; robot 1 for task 0 40 + 5, for task 1 200 + 1. Task 2 is
        // not put up, though robot 1 stands on its first errand.
        let mut proposal = vec![0, -1, 2];
        Soonest::reassign().schedule(&view, &mut proposal);
        assert_eq!(proposal, vec![1, 0, 2]);
        // `soonest` never takes a task back: the free robot gets what is left.
        let mut kept = vec![0, -1, 2];
        Soonest::new().schedule(&view, &mut kept);
        assert_eq!(kept, vec![0, 1, 2]);
        // The pool takes the reassignment as valid.
        pool.update(1, &proposal, &loc, &lines);
        assert!(pool.errors.is_empty(), "{:?}", pool.errors);
        assert_eq!(pool.current, vec![1, 0, 2]);
    }

    /// `reassign`'s proposal on a row of `width` free cells, the robots at `loc`, robot `k`
    /// holding task `id` (not opened) for each (k, id) of `holds`, the pool every task of `lines`.
    fn reassigned(width: usize, lines: &[Vec<u32>], holds: &[(usize, usize)], loc: &[u32]) -> Vec<i64> {
        let map = GridMap::parse(&format!("type octile\nheight 1\nwidth {width}\nmap\n{}\n", ".".repeat(width))).unwrap();
        let mut pool = TaskPool::new(loc.len(), lines.len(), lines.len());
        for &(k, id) in holds {
            pool.current[k] = id as i64;
            pool.tasks[id].agent = k as i64;
        }
        let heading = vec![0; loc.len()];
        let view = ScheduleView { map: &map, loc, heading: &heading, pool: &pool, lines, t: 1 };
        let mut proposal = pool.current.clone();
        Soonest::reassign().schedule(&view, &mut proposal);
        proposal
    }

    #[test]
    fn a_cell_sells_its_shortest_task_first_and_a_later_bid_pays_for_the_next() {
        // Tasks 0-2 start at cell 10 (lengths 15, 2, 8); task 3 starts at 20 (length 0).
        let lines = vec![vec![10, 25], vec![10, 12], vec![10, 18], vec![20]];
        // Robot 2 takes task 3 (20 + 0); robots 0 and 1 (both 1 from cell 10) bid 20 + 2 for
        // task 1: the lower id wins it, and the other takes task 2, not task 0.
        assert_eq!(reassigned(30, &lines, &[], &[9, 11, 21]), vec![1, 2, 3]);
    }

    #[test]
    fn a_robot_bound_for_a_cell_counts_stay_cells_nearer_to_it() {
        // Task 0 = [20, 21]. Robot 0 holds it, `gap` cells from cell 20; robot 1 is free, 1 cell
        // from it; task 1 = [39] is far from both. At `STAY` + 1 the two bid the same, and the
        // lower id (robot 0) keeps it.
        for (gap, keeps) in [(STAY, true), (STAY + 1, true), (STAY + 2, false)] {
            let proposal = reassigned(40, &[vec![20, 21], vec![39]], &[(0, 0)], &[20 - gap, 19]);
            assert_eq!(proposal, if keeps { vec![0, 1] } else { vec![1, 0] }, "{gap} cells away");
        }
    }

    #[test]
    fn a_station_s_tasks_go_to_the_robots_nearest_it_up_to_a_point_then_to_the_next() {
        // Three tasks at station 20, three at station 55; robots at 19, 18 and 17.
        let lines = vec![vec![20, 21], vec![20, 21], vec![20, 21], vec![55, 56], vec![55, 56], vec![55, 56]];
        // Robot 0 takes station 20 (1 cell); robot 1 too (2 cells and `QUEUE` for robot 0: 32,
        // against 37 to station 55); robot 2 goes on to station 55 (38 against 3 + 60).
        assert_eq!(reassigned(60, &lines, &[], &[19, 18, 17]), vec![0, 1, 3]);
    }

    #[test]
    fn near_finds_what_a_pass_over_the_points_left_finds() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for round in 0..30 {
            let (rows, cols) = (rng.random_range(1..80u32), rng.random_range(1..80u32));
            let text = format!("type octile\nheight {rows}\nwidth {cols}\nmap\n{}", format!("{}\n", ".".repeat(cols as usize)).repeat(rows as usize));
            let map = GridMap::parse(&text).unwrap();
            let lines: Vec<Vec<u32>> = Vec::new();
            let pool = TaskPool::new(0, 0, 1);
            let view = ScheduleView { map: &map, loc: &[], heading: &[], pool: &pool, lines: &lines, t: 0 };
            let points: Vec<u32> = (0..rng.random_range(1..300)).map(|_| rng.random_range(0..rows * cols)).collect();
            let mut near = Near::new(&view, points.iter().copied());
            for _ in 0..points.len() {
                let at = rng.random_range(0..rows * cols);
                let want = rng.random_range(1..12);
                let mut all: Vec<(u32, u32)> = (0..points.len()).filter(|&i| !near.taken(i)).map(|i| (view.manhattan(points[i], at), i as u32)).collect();
                all.sort_unstable();
                all.truncate(want);
                assert_eq!(near.nearest(&view, at, want), all, "round {round}");
                let i = rng.random_range(0..points.len());
                if !near.taken(i) {
                    near.take(i);
                }
            }
        }
    }
}
