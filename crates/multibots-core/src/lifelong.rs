//! Lifelong operation (an extension of the paper model, `docs/model.md` section 7): orders
//! arrive over time, at a Poisson rate or from a CSV of `(step, cell)` rows; picked cells
//! restock after a delay; the run lasts a fixed horizon.
//!
//! An order names a cell. It joins the allocation queue when its cell holds goods and no
//! other order has claimed the cell; otherwise it waits, first come first served, in its
//! cell's own backlog until the cell restocks. So the allocators only ever see orders they
//! can fetch, and goods are conserved: ordered = delivered + in flight + queued + waiting.
//!
//! Every buffer is sized at the start for the orders the run can expect (up to a million),
//! so the step loop seldom allocates; past that they grow with the orders that arrive.

use crate::error::{Error, Result};
use crate::ids::{CellId, GoodsId, NONE};
use crate::scenario::Orders;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
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
    /// Arrival step of every order, indexed by order (goods) id.
    pub arrival: Vec<u64>,
    /// A queued or fetched order holds its cell until the pickup.
    reserved: Vec<bool>,
    /// Per-cell backlogs of orders waiting for stock, as linked lists over order ids.
    wait_head: Vec<u32>,
    wait_tail: Vec<u32>,
    wait_next: Vec<u32>,
    /// Orders in all backlogs.
    pub waiting: u64,
    /// Restocks due: `(step, cell)`, in pickup order; the delay is constant, so due steps
    /// never decrease along the list.
    restocks: std::collections::VecDeque<(u64, u32)>,
    /// Order-to-delivery latency of every delivery, steps.
    pub latencies: Vec<u64>,
}

/// What `begin_step` did, for events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StockEvent {
    /// An order arrived for this cell.
    Order(u32),
    /// This cell restocked.
    Restock(u32),
}

/// Reads `(step, cell)` rows. A first line that is not two integers is a header; blank lines
/// and lines starting with `#` are skipped.
pub fn read_csv(path: &Path, cells: usize) -> Result<Vec<(u64, u32)>> {
    let shown = path.display().to_string();
    let text = crate::files::read_text(path, crate::files::MAX_INPUT_BYTES)
        .map_err(|e| Error::scenario("orders.csv", format!("\"{shown}\""), format!("cannot read: {e}")))?;
    let mut rows = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let parts: Vec<&str> = line.split(',').map(str::trim).collect();
        let parsed = match parts.as_slice() {
            [a, b] => a.parse::<u64>().ok().zip(b.parse::<i64>().ok()),
            _ => None,
        };
        let Some((step, cell)) = parsed else {
            if rows.is_empty() && k == 0 {
                continue; // header
            }
            return Err(Error::scenario("orders.csv", format!("\"{shown}\""), format!("line {}: expected `step,cell` with integers, got \"{line}\"", k + 1)));
        };
        if step == 0 {
            return Err(Error::scenario("orders.csv", format!("\"{shown}\""), format!("line {}: step 0: steps start at 1", k + 1)));
        }
        if cell < 0 || cell as usize >= cells {
            return Err(Error::scenario(
                "orders.csv",
                format!("\"{shown}\""),
                format!("line {}: cell {cell} out of range 0..{}", k + 1, cells.saturating_sub(1)),
            ));
        }
        rows.push((step, cell as u32));
    }
    rows.sort_by_key(|r| r.0); // stable: rows of one step keep their file order
    Ok(rows)
}

impl Lifelong {
    /// Prepares a run over `cells` cells; `initial` orders (the task list) arrive at step 0.
    #[must_use]
    pub fn new(o: &Orders, cells: usize, csv: Vec<(u64, u32)>, initial: usize) -> Lifelong {
        // Room for the orders a run expects, up to a million: beyond that the buffers grow with
        // the orders that arrive, so memory follows the run, not its horizon.
        let expected = (initial + csv.len() + (o.rate * o.horizon as f64 * 1.1) as usize + 64).min(1 << 20);
        Lifelong {
            horizon: o.horizon,
            restock: o.restock,
            rate: o.rate,
            rng: ChaCha8Rng::seed_from_u64(o.seed),
            csv,
            csv_next: 0,
            cells,
            arrival: Vec::with_capacity(expected),
            reserved: vec![false; cells],
            wait_head: vec![NONE; cells],
            wait_tail: vec![NONE; cells],
            wait_next: Vec::with_capacity(expected),
            waiting: 0,
            restocks: std::collections::VecDeque::with_capacity(cells),
            latencies: Vec::with_capacity(expected),
        }
    }

    /// Orders so far.
    #[must_use]
    pub fn ordered(&self) -> u64 {
        self.arrival.len() as u64
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
        let id = self.arrival.len() as u32;
        self.arrival.push(t);
        self.wait_next.push(NONE);
        let c = cell as usize;
        if cells_full[c] && !self.reserved[c] {
            self.reserved[c] = true;
            queue(GoodsId(id), CellId(cell));
        } else {
            if self.wait_tail[c] == NONE {
                self.wait_head[c] = id;
            } else {
                self.wait_next[self.wait_tail[c] as usize] = id;
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
                self.wait_head[c] = self.wait_next[head as usize];
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

    /// Order `goods` was delivered at step `t`.
    pub fn delivered(&mut self, t: u64, goods: u32) {
        self.latencies.push(t - self.arrival[goods as usize]);
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
    fn poisson_mean_is_close_to_the_rate() {
        let o = Orders { rate: 3.5, ..Orders::default() };
        let mut l = Lifelong::new(&o, 10, Vec::new(), 0);
        let n = 20_000;
        let total: u64 = (0..n).map(|_| l.poisson()).sum();
        let mean = total as f64 / f64::from(n);
        assert!((mean - 3.5).abs() < 0.1, "{mean}");
        let o = Orders { rate: 40.0, ..Orders::default() };
        let mut l = Lifelong::new(&o, 10, Vec::new(), 0);
        let total: u64 = (0..2000).map(|_| l.poisson()).sum();
        assert!((total as f64 / 2000.0 - 40.0).abs() < 1.0);
    }
}
