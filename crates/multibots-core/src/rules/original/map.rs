//! The original's warehouse: its 24 named points, its one-way graph and the first path its
//! search finds, and where each goods is fetched.
//!
//! - **Points** (`Graph.generateGraphNodes`): the 18 aisle crossings A..R at
//!   (75 + 150k, 125 + 250m), and the charging positions S, T, U, V, W, Y at (75 + 150k, 85).
//!   The original draws the warehouse 50 px right of and 100 px below [`Layout::paper`]
//!   (`margin_left = 50`, `margin_top = 100`); otherwise the frames agree, and the point
//!   numbering here (A..R = 0..17, S..Y = 18..23) is the paper layout's node numbering (CH0..CH5
//!   after R). The engine keeps positions in the original's frame, so that its float
//!   arithmetic is the original's bit for bit, and shifts them only for viewers.
//! - **Graph** (`Graph.generateGraph`): the rows A→F and G→L run east, M←R west; the columns
//!   run north at A/G/M, C/I/O, E/K/Q and south at B/H/N, D/J/P, F/L/R. A crossing lists its
//!   row neighbour before its column neighbour. The charging positions are not in the graph:
//!   robots jump between them and their start crossing.
//! - **Paths** (`Graph.BFS`): a breadth-first search over simple paths that returns the first
//!   path it dequeues at the goal. That is the path of a plain breadth-first search in which
//!   each crossing keeps the first crossing that reached it; a test checks the two agree on
//!   all 324 pairs. The search always starts on an empty queue (every caller clears the
//!   robot's queue first, or it is empty), so a path depends only on its two ends.
//! - **Shelves** (`WorldController.Controller.__init__`, `param.GOOD_FIND_LETTER_*`): the goods
//!   of cell `8g + 2b + a` (the paper layout's numbering) is fetched on vertical aisle
//!   k = g/2 + a. A robot drives to the aisle's crossing it can enter the shelf's edge from
//!   (the *forward* letter), then to the loading point (75 + 150k, 175 + 250r + 50b), and
//!   leaves by the edge's other end (the *backward* letter).
//!
//! [`Layout::paper`]: crate::world::layout::Layout::paper

use std::sync::OnceLock;

/// Named points: A..R, then the charging positions S, T, U, V, W, Y.
#[cfg(test)]
pub const POINTS: usize = 24;
/// Aisle crossings A..R.
pub const CROSSINGS: usize = 18;
/// The unloading crossing M (`InitStartGoal`: every robot's `goalletter`).
pub const UNLOAD: u8 = 12;
/// The first charging position, S.
pub const CHARGER_0: u8 = 18;
/// "No point": the original's `'x'` (no plan left) and its initial `''`.
pub const NOWHERE: u8 = u8::MAX;
/// The original's frame lies this far right of and below the paper layout's.
pub const FRAME_DX: f64 = 50.0;
pub const FRAME_DY: f64 = 100.0;

/// Letters as the original names the points (`W` is followed by `Y`: it has no `X`).
#[cfg(test)]
pub const LETTERS: &[u8; POINTS] = b"ABCDEFGHIJKLMNOPQRSTUVWY";

/// Where point `p` stands, in the original's frame (all integers, as in the original).
#[must_use]
pub fn point(p: u8) -> (f64, f64) {
    if p < 18 {
        (75.0 + 150.0 * f64::from(p % 6), 125.0 + 250.0 * f64::from(p / 6))
    } else {
        (75.0 + 150.0 * f64::from(p - 18), 85.0)
    }
}

/// The lines `Graph.generateGraph` strings together, in its order: three rows, six columns.
const LINES: [&[u8]; 9] = [b"ABCDEF", b"GHIJKL", b"RQPONM", b"MGA", b"BHN", b"OIC", b"DJP", b"QKE", b"FLR"];

/// Out-neighbours of each crossing in the original's order (at most two).
#[must_use]
pub fn out_neighbours() -> [Vec<u8>; CROSSINGS] {
    let mut out: [Vec<u8>; CROSSINGS] = Default::default();
    for line in LINES {
        for w in line.windows(2) {
            out[usize::from(w[0] - b'A')].push(w[1] - b'A');
        }
    }
    out
}

/// A node path: what `Strategy.currentOverallPlans[agent]` holds, consumed from the front.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plan {
    nodes: [u8; CROSSINGS],
    head: u8,
    len: u8,
}

impl Plan {
    /// No plan left (the original's `[]`).
    pub const EMPTY: Plan = Plan { nodes: [0; CROSSINGS], head: 0, len: 0 };

    /// The next point to go to, or [`NOWHERE`] (`Strategy.getNextPlannedNode`).
    #[inline]
    #[must_use]
    pub fn front(&self) -> u8 {
        if self.head < self.len {
            self.nodes[usize::from(self.head)]
        } else {
            NOWHERE
        }
    }

    /// Drops the point just reached (`currentOverallPlans[agent].pop(0)`).
    #[inline]
    pub fn pop_front(&mut self) {
        debug_assert!(self.head < self.len, "the original pops a point it is heading to");
        self.head = (self.head + 1).min(self.len);
    }

    /// The last point, or [`NOWHERE`].
    #[must_use]
    pub fn last(&self) -> u8 {
        if self.head < self.len {
            self.nodes[usize::from(self.len - 1)]
        } else {
            NOWHERE
        }
    }

    /// The points still to visit, next first.
    #[must_use]
    pub fn remaining(&self) -> &[u8] {
        &self.nodes[usize::from(self.head)..usize::from(self.len)]
    }
}

/// The first path `Graph.BFS` finds between every two crossings.
pub struct Routes {
    plans: Vec<Plan>,
}

impl Routes {
    /// The table, built once per process.
    pub fn get() -> &'static Routes {
        static ROUTES: OnceLock<Routes> = OnceLock::new();
        ROUTES.get_or_init(Routes::build)
    }

    fn build() -> Routes {
        let out = out_neighbours();
        let mut plans = Vec::with_capacity(CROSSINGS * CROSSINGS);
        for s in 0..CROSSINGS {
            // Plain BFS; each crossing keeps the first crossing that reached it.
            let mut parent = [NOWHERE; CROSSINGS];
            let mut seen = [false; CROSSINGS];
            let mut queue = Vec::with_capacity(CROSSINGS);
            seen[s] = true;
            queue.push(s as u8);
            let mut k = 0;
            while k < queue.len() {
                let u = queue[k];
                k += 1;
                for &v in &out[usize::from(u)] {
                    if !seen[usize::from(v)] {
                        seen[usize::from(v)] = true;
                        parent[usize::from(v)] = u;
                        queue.push(v);
                    }
                }
            }
            for (t, &reached) in seen.iter().enumerate() {
                assert!(reached, "the original's graph is strongly connected");
                let mut rev = Vec::with_capacity(CROSSINGS);
                let mut v = t as u8;
                rev.push(v);
                while usize::from(v) != s {
                    v = parent[usize::from(v)];
                    rev.push(v);
                }
                let mut plan = Plan::EMPTY;
                for (i, &p) in rev.iter().rev().enumerate() {
                    plan.nodes[i] = p;
                }
                plan.len = rev.len() as u8;
                plans.push(plan);
            }
        }
        Routes { plans }
    }

    /// `Strategy.setNewPlan(agent, from, to)`: the path from `from` to `to`, both included.
    #[inline]
    #[must_use]
    pub fn plan(&self, from: u8, to: u8) -> Plan {
        self.plans[usize::from(from) * CROSSINGS + usize::from(to)]
    }
}

/// Where the goods of one cell is fetched.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shelf {
    /// The crossing a robot drives to first (`goodfindletter[0]`).
    pub forward: u8,
    /// The crossing it leaves by, loaded (`goodfindletter[1]`).
    pub backward: u8,
    /// Where it stands to load (`good.agentx`, `good.agenty`), in the original's frame.
    pub x: f64,
    pub y: f64,
}

/// The shelf of cell `cell` (0..80).
#[must_use]
pub fn shelf(cell: u8) -> Shelf {
    let (g, i) = (cell / 8, cell % 8);
    let (a, b) = (i % 2, i / 2);
    let (c, r) = (g / 2, g % 2);
    let k = c + a;
    let (upper, lower) = (6 * r + k, 6 * r + 6 + k);
    // Columns A, C, E (even k) run north.
    let (forward, backward) = if k % 2 == 0 { (lower, upper) } else { (upper, lower) };
    Shelf { forward, backward, x: 75.0 + 150.0 * f64::from(k), y: 175.0 + 250.0 * f64::from(r) + 50.0 * f64::from(b) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Graph.BFS` as written: a queue of simple paths, the first dequeued at the goal wins.
    fn bfs_over_paths(out: &[Vec<u8>; CROSSINGS], start: u8, end: u8) -> Vec<u8> {
        let mut queue = std::collections::VecDeque::from([vec![start]]);
        while let Some(path) = queue.pop_front() {
            let last = *path.last().unwrap();
            if last == end {
                return path;
            }
            for &v in &out[usize::from(last)] {
                if !path.contains(&v) {
                    let mut p = path.clone();
                    p.push(v);
                    queue.push_back(p);
                }
            }
        }
        unreachable!("strongly connected")
    }

    #[test]
    fn plain_bfs_finds_the_originals_first_path() {
        let out = out_neighbours();
        let routes = Routes::get();
        for s in 0..CROSSINGS as u8 {
            for t in 0..CROSSINGS as u8 {
                assert_eq!(routes.plan(s, t).remaining(), bfs_over_paths(&out, s, t).as_slice(), "{s} -> {t}");
            }
        }
        let name = |p: &[u8]| p.iter().map(|&c| char::from(LETTERS[usize::from(c)])).collect::<String>();
        assert_eq!(name(routes.plan(0, 14).remaining()), "ABCDJPO");
        assert_eq!(name(routes.plan(12, 0).remaining()), "MGA");
    }

    #[test]
    fn graph_matches_the_spec_table() {
        let out = out_neighbours();
        let name = |v: &Vec<u8>| v.iter().map(|&c| char::from(LETTERS[usize::from(c)])).collect::<String>();
        let table = ["B", "CH", "D", "EJ", "F", "L", "HA", "IN", "JC", "KP", "LE", "R", "G", "M", "NI", "O", "PK", "Q"];
        for (i, want) in table.iter().enumerate() {
            assert_eq!(name(&out[i]), *want, "out-neighbours of {}", char::from(LETTERS[i]));
        }
    }

    #[test]
    fn points_are_the_paper_layout_shifted() {
        let l = crate::world::layout::Layout::paper();
        for p in 0..POINTS as u8 {
            let (x, y) = point(p);
            let n = &l.nodes[usize::from(p)];
            assert_eq!((x - FRAME_DX, y - FRAME_DY), (n.x, n.y), "point {}", char::from(LETTERS[usize::from(p)]));
        }
    }

    #[test]
    fn shelves_match_param_py_and_the_layout() {
        // param.GOOD_FIND_LETTER_{UP,DOWN}_{LEFT,RIGHT}, indexed by the group's column.
        let up_left = ["GA", "BH", "IC", "DJ", "KE"];
        let up_right = ["BH", "IC", "DJ", "KE", "FL"];
        let down_left = ["MG", "HN", "OI", "JP", "QK"];
        let down_right = ["HN", "OI", "JP", "QK", "LR"];
        let l = crate::world::layout::Layout::paper();
        for cell in 0..80u8 {
            let s = shelf(cell);
            let (g, i) = (usize::from(cell / 8), cell % 8);
            let table = match (g % 2, i % 2) {
                (0, 0) => up_left,
                (0, _) => up_right,
                (_, 0) => down_left,
                _ => down_right,
            };
            let want = table[g / 2].as_bytes();
            assert_eq!((LETTERS[usize::from(s.forward)], LETTERS[usize::from(s.backward)]), (want[0], want[1]), "cell {cell}");
            // WorldController: agentx = x - 25 (left) or x + 75 (right), agenty = y + 25.
            let col = (g / 2) as f64;
            let x = (3.0 * col + 1.0) * 50.0 + 50.0 + if i % 2 == 1 { 50.0 + 75.0 } else { -25.0 };
            let y = if g % 2 == 0 { 150.0 } else { 400.0 } + f64::from(i / 2) * 50.0 + 25.0;
            assert_eq!((s.x, s.y), (x, y), "cell {cell}");
            let c = &l.cells[usize::from(cell)];
            assert_eq!((s.x - FRAME_DX, s.y - FRAME_DY), c.service, "cell {cell}");
            assert_eq!((u32::from(s.forward), u32::from(s.backward)), (c.edge.0 .0, c.edge.1 .0), "cell {cell}");
        }
    }
}
