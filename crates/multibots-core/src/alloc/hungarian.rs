//! `hungarian`: the optimal batch assignment by route length.
//!
//! # What it does
//! At each allocation event it builds the matrix of route lengths from every idle robot to
//! every open goods' service point and gives out the assignment with the least total length
//! (as many pairs as there are idle robots or open goods, whichever is fewer). Every open
//! goods is a candidate, not only the front of the queue, so the queue order is not kept.
//! Ties between equally short assignments go the same way on every run (the solver scans
//! robots by id and goods in queue order).
//!
//! # When to use it
//! When travel empty to the goods dominates and several robots become idle at once (the
//! start of a run, or a large fleet): it never does worse on total empty travel than a
//! greedy rule, and does better when greedy choices block each other. With one idle robot at
//! a time it picks the goods nearest to it.
//!
//! # Cost
//! O(k² · m) per event for k = min(idle, goods) and m = max(idle, goods), on top of k · m
//! route-length queries (table look-ups on the paper layout).
//!
//! # Options
//! None. [`solve`] is the solver on its own, for other strategies (`min-cost` uses it).
//!
//! # Example
//! ```toml
//! allocator = "hungarian"
//! ```
//!
//! Why our own solver: the `pathfinding` crate's `kuhn_munkres` needs integer weights
//! (and maximises), while route lengths and cost estimates are `f64`; scaling to integers
//! would change ties. The shortest-augmenting-path Hungarian method below is ~50 lines and
//! tested against brute force.

use super::{AllocView, Allocator, Assignment, Decisions};
use crate::error::Result;

/// The optimal batch assignment by route length.
#[derive(Clone, Copy, Debug, Default)]
pub struct Hungarian;

impl Allocator for Hungarian {
    fn name(&self) -> &'static str {
        "hungarian"
    }

    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> Result<()> {
        let (n, m) = (view.idle.len(), view.goods.len());
        let mut cost = Vec::with_capacity(n * m);
        for &r in view.idle {
            cost.extend(view.goods.iter().map(|g| view.route_length(r, g.cell)));
        }
        push_solution(view, &cost, out);
        Ok(())
    }
}

/// Solves the idle × goods matrix `cost` (row-major) and appends the pairs to `out`.
pub(crate) fn push_solution(view: &AllocView<'_>, cost: &[f64], out: &mut Decisions) {
    let m = view.goods.len();
    for (i, col) in solve(cost, view.idle.len(), m).into_iter().enumerate() {
        if let Some(j) = col {
            out.assign.push(Assignment { robot: view.idle[i], goods: view.goods[j].id });
        }
    }
}

/// Minimum-cost assignment on a `rows × cols` matrix (row-major, finite values): each row
/// gets at most one column and each column at most one row, with min(rows, cols) pairs.
/// Returns the column of each row.
#[must_use]
pub fn solve(cost: &[f64], rows: usize, cols: usize) -> Vec<Option<usize>> {
    assert_eq!(cost.len(), rows * cols, "cost matrix is rows × cols");
    if rows == 0 || cols == 0 {
        return vec![None; rows];
    }
    if rows > cols {
        // The method below needs rows ≤ cols: solve the transpose.
        let t: Vec<f64> = (0..cols * rows).map(|k| cost[(k % rows) * cols + k / rows]).collect();
        let by_col = solve(&t, cols, rows);
        let mut out = vec![None; rows];
        for (c, r) in by_col.into_iter().enumerate() {
            if let Some(r) = r {
                out[r] = Some(c);
            }
        }
        return out;
    }
    // Shortest augmenting paths with potentials (u on rows, v on columns), 1-based with a
    // virtual column 0; O(rows² · cols).
    let (n, m) = (rows, cols);
    let mut u = vec![0.0; n + 1];
    let mut v = vec![0.0; m + 1];
    let mut p = vec![0usize; m + 1]; // p[j]: row matched to column j
    let mut way = vec![0usize; m + 1];
    for i in 1..=n {
        p[0] = i;
        let mut j0 = 0;
        let mut minv = vec![f64::INFINITY; m + 1];
        let mut used = vec![false; m + 1];
        loop {
            used[j0] = true;
            let i0 = p[j0];
            let mut delta = f64::INFINITY;
            let mut j1 = 0;
            for j in 1..=m {
                if !used[j] {
                    let cur = cost[(i0 - 1) * m + (j - 1)] - u[i0] - v[j];
                    if cur < minv[j] {
                        minv[j] = cur;
                        way[j] = j0;
                    }
                    // Strictly less: the first column wins a tie, so results are reproducible.
                    if minv[j] < delta {
                        delta = minv[j];
                        j1 = j;
                    }
                }
            }
            for j in 0..=m {
                if used[j] {
                    u[p[j]] += delta;
                    v[j] -= delta;
                } else {
                    minv[j] -= delta;
                }
            }
            j0 = j1;
            if p[j0] == 0 {
                break;
            }
        }
        loop {
            let j1 = way[j0];
            p[j0] = p[j1];
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    let mut out = vec![None; n];
    for j in 1..=m {
        if p[j] != 0 {
            out[p[j] - 1] = Some(j - 1);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::solve;

    fn total(cost: &[f64], cols: usize, sol: &[Option<usize>]) -> f64 {
        sol.iter().enumerate().filter_map(|(i, c)| c.map(|c| cost[i * cols + c])).sum()
    }

    /// The least total over every way of giving min(rows, cols) pairs.
    fn brute(cost: &[f64], rows: usize, cols: usize) -> f64 {
        fn rec(cost: &[f64], rows: usize, cols: usize, i: usize, used: &mut Vec<bool>, left: usize) -> f64 {
            if left == 0 {
                return 0.0;
            }
            if i == rows {
                return f64::INFINITY;
            }
            let mut best = if rows - i > left { rec(cost, rows, cols, i + 1, used, left) } else { f64::INFINITY };
            for c in 0..cols {
                if !used[c] {
                    used[c] = true;
                    best = best.min(cost[i * cols + c] + rec(cost, rows, cols, i + 1, used, left - 1));
                    used[c] = false;
                }
            }
            best
        }
        rec(cost, rows, cols, 0, &mut vec![false; cols], rows.min(cols))
    }

    #[test]
    fn matches_brute_force_on_many_small_matrices() {
        // A fixed linear congruential sequence: the same matrices on every machine.
        let mut x: u64 = 12345;
        let mut next = || {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            ((x >> 33) % 100) as f64 / 4.0
        };
        for rows in 1..=5 {
            for cols in 1..=5 {
                for _ in 0..20 {
                    let cost: Vec<f64> = (0..rows * cols).map(|_| next()).collect();
                    let sol = solve(&cost, rows, cols);
                    let pairs = sol.iter().flatten().count();
                    assert_eq!(pairs, rows.min(cols));
                    let mut cs: Vec<usize> = sol.iter().flatten().copied().collect();
                    cs.sort_unstable();
                    cs.dedup();
                    assert_eq!(cs.len(), pairs, "a column used twice");
                    assert!((total(&cost, cols, &sol) - brute(&cost, rows, cols)).abs() < 1e-9, "{rows}x{cols} {cost:?} {sol:?}");
                }
            }
        }
    }

    #[test]
    fn greedy_trap() {
        // Greedy takes the 1, then pays 100; the optimum is 2 + 2.
        let cost = [1.0, 2.0, 2.0, 100.0];
        assert_eq!(solve(&cost, 2, 2), vec![Some(1), Some(0)]);
    }
}
