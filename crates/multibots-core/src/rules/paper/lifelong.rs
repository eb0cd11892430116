//! Lifelong operation (an extension of the paper model, `docs/model.md` section 7): orders
//! arrive over time, at a Poisson rate or from a CSV of `(step, cell)` rows; picked cells
//! restock after a delay; the run lasts a fixed horizon.
//!
//! An order names a cell. It joins the allocation queue when its cell holds goods and no
//! other order has claimed the cell; otherwise it waits, first come first served, in its
//! cell's own backlog until the cell restocks. So the allocators only ever see orders they
//! can fetch, and goods are conserved: ordered = delivered + in flight + queued + waiting.
//!
//! Memory follows the orders in progress, not the horizon: per-order state lives in an
//! [`OrderWindow`] that starts at the oldest order not yet delivered and drops delivered
//! orders from its front, so a run of a million steps holds about as much as one of a
//! thousand. What must outlive an order, its latency, is 8 bytes per delivery. Buffers grow
//! (amortised) with the orders that arrive; nothing is reserved up front for the horizon.

use crate::error::Result;
use crate::ids::{CellId, GoodsId, NONE};
use crate::input::csv::Tables;
use crate::input::scenario::Orders;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::VecDeque;
use std::path::Path;

/// Arrivals and stock of a lifelong run.
#[derive(Clone, Debug)]
pub struct Lifelong {
    pub horizon: u64,
    restock: u64,
    rate: f64,
    rng: ChaCha8Rng,
    /// CSV orders sorted by step (stable), and the next one to release.
    csv: Vec<(u64, u32)>,
    csv_next: usize,
    cells: usize,
    /// Orders so far (the next order's id).
    ordered: u64,
    /// The orders not yet delivered, by order (goods) id.
    open: OrderWindow<OpenOrder>,
    /// A queued or fetched order holds its cell until the pickup.
    reserved: Vec<bool>,
    /// Per-cell backlogs of orders waiting for stock, as linked lists over order ids (the
    /// links are in `open`).
    wait_head: Vec<u32>,
    wait_tail: Vec<u32>,
    /// Orders in all backlogs.
    pub waiting: u64,
    /// Restocks due: `(step, cell)`, in pickup order; the delay is constant, so due steps
    /// never decrease along the list.
    restocks: VecDeque<(u64, u32)>,
    /// Order-to-delivery latency of every delivery, steps.
    pub latencies: Vec<u64>,
}

/// What a lifelong run keeps of an order until its delivery: 12 bytes (a run that cannot keep
/// up holds every order that waits).
#[derive(Clone, Copy, Debug)]
struct OpenOrder {
    /// The step it arrived, low and high halves (a `u64` would pad the entry to 16 bytes).
    arrival: [u32; 2],
    /// The next order in its cell's backlog (`NONE`: none), or [`DELIVERED`].
    wait_next: u32,
}

/// `wait_next` of a delivered order (order ids stay far below it, `limits::MAX_ORDERS`).
const DELIVERED: u32 = NONE - 1;

impl OpenOrder {
    fn new(arrival: u64) -> OpenOrder {
        OpenOrder { arrival: [arrival as u32, (arrival >> 32) as u32], wait_next: NONE }
    }

    fn arrival(self) -> u64 {
        u64::from(self.arrival[0]) | u64::from(self.arrival[1]) << 32
    }
}

/// Per-order values of the orders with ids from `base` on, by order id: ids below `base` are
/// done with and their values dropped. Orders finish roughly in the order they arrive, so the
/// window spans the orders in progress; an order that never finishes only keeps it from
/// shrinking (then it grows like a vector of every order, never more).
#[derive(Clone, Debug)]
pub(crate) struct OrderWindow<T> {
    base: usize,
    values: VecDeque<T>,
}

impl<T: Clone> OrderWindow<T> {
    /// An empty window from id 0.
    pub fn new() -> OrderWindow<T> {
        OrderWindow { base: 0, values: VecDeque::new() }
    }

    /// The value of order `id`, if it is in the window.
    #[inline]
    pub fn get_mut(&mut self, id: usize) -> Option<&mut T> {
        self.values.get_mut(id.checked_sub(self.base)?)
    }

    /// Ids below this one are dropped.
    pub fn base(&self) -> usize {
        self.base
    }

    /// One past the last id in the window.
    pub fn end(&self) -> usize {
        self.base + self.values.len()
    }

    /// Extends the window to hold ids up to `id`, new ones `fill`.
    pub fn reach(&mut self, id: usize, fill: T) {
        if id >= self.end() {
            self.values.resize(id + 1 - self.base, fill);
        }
    }

    /// Drops the values of ids below `base`.
    pub fn drop_below(&mut self, base: usize) {
        while self.base < base && self.values.pop_front().is_some() {
            self.base += 1;
        }
        self.base = self.base.max(base);
    }

    /// The first value, if any.
    fn front(&self) -> Option<&T> {
        self.values.front()
    }
}

impl<T: Clone> std::ops::Index<usize> for OrderWindow<T> {
    type Output = T;
    fn index(&self, id: usize) -> &T {
        &self.values[id - self.base]
    }
}

impl<T: Clone> std::ops::IndexMut<usize> for OrderWindow<T> {
    fn index_mut(&mut self, id: usize) -> &mut T {
        &mut self.values[id - self.base]
    }
}

/// What `begin_step` did, for events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StockEvent {
    /// An order arrived for this cell.
    Order(u32),
    /// This cell restocked.
    Restock(u32),
}

/// The `(step, cell)` rows of the orders table at `path` (read once per scenario, `tables`),
/// checked against the layout's `cells` line by line, and sorted by step (rows of one step
/// keep their file order).
pub(crate) fn orders_csv(tables: &Tables, path: &Path, cells: usize) -> Result<Vec<(u64, u32)>> {
    let table = tables.read("orders.csv", path)?;
    let mut rows = Vec::new();
    for row in table.rows::<u64, i64>("step,cell") {
        let (line, step, cell) = row?;
        if step == 0 {
            return Err(table.error(line, "step 0: steps start at 1"));
        }
        if cell < 0 || cell as usize >= cells {
            return Err(table.error(line, format!("cell {cell} out of range 0..{}", cells.saturating_sub(1))));
        }
        #[allow(clippy::cast_possible_truncation)]
        rows.push((step, cell as u32));
    }
    rows.sort_by_key(|r| r.0); // stable: rows of one step keep their file order
    Ok(rows)
}

impl Lifelong {
    /// Prepares a run over `cells` cells. Order buffers start empty and grow with the orders
    /// that arrive.
    #[must_use]
    pub fn new(o: &Orders, cells: usize, csv: Vec<(u64, u32)>) -> Lifelong {
        Lifelong {
            horizon: o.horizon,
            restock: o.restock,
            rate: o.rate,
            rng: ChaCha8Rng::seed_from_u64(o.seed),
            csv,
            csv_next: 0,
            cells,
            ordered: 0,
            open: OrderWindow::new(),
            reserved: vec![false; cells],
            wait_head: vec![NONE; cells],
            wait_tail: vec![NONE; cells],
            waiting: 0,
            restocks: VecDeque::new(),
            latencies: Vec::new(),
        }
    }

    /// Orders so far.
    #[must_use]
    pub fn ordered(&self) -> u64 {
        self.ordered
    }

    /// The oldest order not yet delivered (or the next order's id): the state of every order
    /// below it is dropped.
    #[must_use]
    pub fn first_open(&self) -> usize {
        self.open.base()
    }

    /// A uniform number in [0, 1) from 53 random bits (portable across machines).
    fn uniform(&mut self) -> f64 {
        (self.rng.random::<u64>() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A Poisson draw with mean `rate` (Knuth's product of uniforms, in slices of mean at
    /// most 16 so that `exp(-mean)` never underflows; a sum of Poisson draws is Poisson).
    fn poisson(&mut self) -> u64 {
        let mut left = self.rate;
        let mut count = 0;
        while left > 0.0 {
            let mean = left.min(16.0);
            left -= mean;
            let limit = (-mean).exp();
            let mut p = self.uniform();
            while p > limit {
                count += 1;
                p *= self.uniform();
            }
        }
        count
    }

    /// A new order for `cell` at step `t`: queued through `queue` if the cell can serve it,
    /// else into the cell's backlog. Returns the order id.
    fn order(&mut self, t: u64, cell: u32, cells_full: &[bool], queue: &mut impl FnMut(GoodsId, CellId)) -> u32 {
        let id = self.ordered as u32;
        self.ordered += 1;
        self.open.reach(id as usize, OpenOrder::new(t));
        let c = cell as usize;
        if cells_full[c] && !self.reserved[c] {
            self.reserved[c] = true;
            queue(GoodsId(id), CellId(cell));
        } else {
            if self.wait_tail[c] == NONE {
                self.wait_head[c] = id;
            } else {
                self.open[self.wait_tail[c] as usize].wait_next = id;
            }
            self.wait_tail[c] = id;
            self.waiting += 1;
        }
        id
    }

    /// The task list's orders, arriving at step 0.
    pub fn initial(&mut self, cells: &[u32], cells_full: &[bool], queue: &mut impl FnMut(GoodsId, CellId)) {
        for &c in cells {
            self.order(0, c, cells_full, queue);
        }
    }

    /// Start of step `t`: restocks that are due, then the step's arrivals (CSV rows first,
    /// then Poisson orders, each for a uniformly drawn cell). `queue` receives orders that
    /// become fetchable; `event` hears of every order and restock.
    pub fn begin_step(&mut self, t: u64, cells_full: &mut [bool], queue: &mut impl FnMut(GoodsId, CellId), event: &mut impl FnMut(StockEvent)) {
        while let Some(&(due, cell)) = self.restocks.front() {
            if due > t {
                break;
            }
            self.restocks.pop_front();
            let c = cell as usize;
            cells_full[c] = true;
            event(StockEvent::Restock(cell));
            let head = self.wait_head[c];
            if head != NONE {
                self.wait_head[c] = self.open[head as usize].wait_next;
                if self.wait_head[c] == NONE {
                    self.wait_tail[c] = NONE;
                }
                self.waiting -= 1;
                self.reserved[c] = true;
                queue(GoodsId(head), CellId(cell));
            }
        }
        while self.csv_next < self.csv.len() && self.csv[self.csv_next].0 <= t {
            let cell = self.csv[self.csv_next].1;
            self.csv_next += 1;
            self.order(t, cell, cells_full, queue);
            event(StockEvent::Order(cell));
        }
        if self.rate > 0.0 && self.cells > 0 {
            for _ in 0..self.poisson() {
                let cell = (self.rng.random::<u64>() % self.cells as u64) as u32;
                self.order(t, cell, cells_full, queue);
                event(StockEvent::Order(cell));
            }
        }
    }

    /// A robot picked the goods of `cell` at step `t`: the cell is free of its order and
    /// restocks `restock` steps later.
    pub fn picked(&mut self, t: u64, cell: u32) {
        self.reserved[cell as usize] = false;
        self.restocks.push_back((t + self.restock, cell));
    }

    /// Order `goods` was delivered at step `t`: its latency is kept, and the delivered
    /// orders at the front of the window are dropped.
    pub fn delivered(&mut self, t: u64, goods: u32) {
        let order = &mut self.open[goods as usize];
        order.wait_next = DELIVERED;
        self.latencies.push(t - order.arrival());
        while self.open.front().is_some_and(|o| o.wait_next == DELIVERED) {
            self.open.drop_below(self.open.base() + 1);
        }
    }
}

/// Nearest-rank percentile of sorted values (`p` in percent).
#[must_use]
pub fn percentile(sorted: &[u64], p: f64) -> Option<u64> {
    if sorted.is_empty() {
        return None;
    }
    let rank = ((p / 100.0) * sorted.len() as f64).ceil() as usize;
    Some(sorted[rank.clamp(1, sorted.len()) - 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_use_nearest_rank() {
        let v: Vec<u64> = (1..=100).collect();
        assert_eq!(percentile(&v, 50.0), Some(50));
        assert_eq!(percentile(&v, 95.0), Some(95));
        assert_eq!(percentile(&v, 99.0), Some(99));
        assert_eq!(percentile(&[7], 99.0), Some(7));
        assert_eq!(percentile(&[], 50.0), None);
    }

    #[test]
    fn delivered_orders_leave_the_window_in_id_order() {
        let o = Orders { rate: 0.0, ..Orders::default() };
        let mut l = Lifelong::new(&o, 4, Vec::new());
        let mut queued = Vec::new();
        // Cell 0 is empty: orders 1 and 3 wait in its backlog, linked through the window.
        l.initial(&[1, 0, 2, 0], &[false, true, true, true], &mut |id, _| queued.push(id.0));
        assert_eq!((queued, l.waiting, l.ordered()), (vec![0, 2], 2, 4));
        l.delivered(10, 2);
        assert_eq!(l.first_open(), 0, "order 0 is still open");
        l.delivered(12, 0);
        assert_eq!(l.first_open(), 1);
        assert_eq!(l.open.values.len(), 3);
        // The backlog's links survive the front being dropped.
        l.picked(12, 0);
        let mut cells = [true; 4];
        let mut fetched = Vec::new();
        l.begin_step(l.restock + 12, &mut cells, &mut |id, _| fetched.push(id.0), &mut |_| {});
        assert_eq!(fetched, vec![1]);
        l.picked(l.restock + 20, 0);
        l.begin_step(2 * l.restock + 20, &mut cells, &mut |id, _| fetched.push(id.0), &mut |_| {});
        assert_eq!(fetched, vec![1, 3]);
        l.delivered(300, 3);
        l.delivered(301, 1);
        assert_eq!((l.first_open(), l.open.values.len()), (4, 0));
        assert_eq!(l.latencies, vec![10, 12, 300, 301]);
    }

    #[test]
    fn poisson_mean_is_close_to_the_rate() {
        let o = Orders { rate: 3.5, ..Orders::default() };
        let mut l = Lifelong::new(&o, 10, Vec::new());
        let n = 20_000;
        let total: u64 = (0..n).map(|_| l.poisson()).sum();
        let mean = total as f64 / f64::from(n);
        assert!((mean - 3.5).abs() < 0.1, "{mean}");
        let o = Orders { rate: 40.0, ..Orders::default() };
        let mut l = Lifelong::new(&o, 10, Vec::new());
        let total: u64 = (0..2000).map(|_| l.poisson()).sum();
        assert!((total as f64 / 2000.0 - 40.0).abs() < 1.0);
    }
}
