//! Exact distances to goals on the grid (moves between free neighbours, turns not counted):
//! one breadth-first search from each goal, made when a robot first heads for it and kept
//! in a cache of at most `capacity` tables, the least recently used dropped first. A table
//! holds `u16` per free cell (76 KB on the 38,586 free cells of `warehouse_large`), so
//! 10,000 robots with 10,000 different goals need 0.8 GB.
//!
//! A search can be spread over planning rounds: [`Distances::search_within`] expands at
//! most a given number of cells, keeps the rest of its queue (the frontier, a few hundred
//! cells) with the table, and goes on from there when asked again. A table is handed out
//! only once its search is complete, so every distance read is exact, and the budget is a
//! count of cells, not a clock, so that a run is the same on every machine.

use crate::input::lorr::GridMap;
use std::collections::HashMap;

/// "Not reachable" in a table.
pub const FAR: u16 = u16::MAX;

/// A move weight meaning "no move": a weighted search never takes it.
pub const BARRED: u8 = u8::MAX;

/// Distance tables by goal cell.
pub struct Distances {
    index: Vec<u32>,
    neighbours: Vec<[u32; 4]>,
    /// `neighbours` in 4 bytes a cell instead of 16, for the breadth-first search ([`pack`]);
    /// empty on a map too wide for it. A search reads a cell's neighbours once per cell, in
    /// the order of the wave, and on a large map (the 96,603 free cells of `orz900d`) the
    /// 16-byte rows do not stay in cache: the search waited on memory more than it worked.
    packed: Vec<u32>,
    /// A bit per cell of the map, set where a free cell has exactly one free neighbour.
    dead_end: Vec<u64>,
    tables: Vec<Vec<u16>>,
    goal_of: Vec<u32>,
    used: Vec<u64>,
    by_goal: HashMap<u32, u32>,
    /// Per slot, the cells its search has labelled but not expanded yet; empty once the
    /// search is complete.
    frontier: Vec<Vec<u32>>,
    complete: Vec<bool>,
    capacity: usize,
    clock: u64,
    queue: Vec<u32>,
    /// Per free cell, the cost of leaving it in each heading, when moves are weighted
    /// (guidance); `None`: every move costs 1 and searches are breadth-first.
    weight: Option<Vec<[u8; 4]>>,
    /// Dial's queue of the weighted searches, empty between searches.
    buckets: Vec<Vec<u32>>,
    /// Searches made so far.
    pub searches: u64,
}

impl Distances {
    /// Tables for `map`, at most `capacity` kept.
    #[must_use]
    pub fn new(map: &GridMap, capacity: usize) -> Distances {
        let mut index = vec![u32::MAX; map.cells()];
        let mut cells = Vec::new();
        for (c, &free) in map.free.iter().enumerate() {
            if free {
                index[c] = cells.len() as u32;
                cells.push(c as u32);
            }
        }
        let neighbours = cells
            .iter()
            .map(|&c| {
                let mut out = [u32::MAX; 4];
                for h in 0..4 {
                    if let Some(q) = crate::rules::grid::action::ahead(map, c, h) {
                        out[h as usize] = index[q as usize];
                    }
                }
                out
            })
            .collect::<Vec<[u32; 4]>>();
        let packed = pack(&neighbours).unwrap_or_default();
        let mut dead_end = vec![0u64; map.cells().div_ceil(64)];
        for (&c, n) in cells.iter().zip(&neighbours) {
            if n.iter().filter(|&&v| v != u32::MAX).count() == 1 {
                dead_end[c as usize / 64] |= 1 << (c % 64);
            }
        }
        Distances {
            index,
            neighbours,
            packed,
            dead_end,
            tables: Vec::new(),
            goal_of: Vec::new(),
            used: Vec::new(),
            by_goal: HashMap::new(),
            frontier: Vec::new(),
            complete: Vec::new(),
            capacity: capacity.max(1),
            clock: 0,
            queue: Vec::new(),
            weight: None,
            buckets: Vec::new(),
            searches: 0,
        }
    }

    /// Tables whose moves cost `weight(cell, heading)` (at least 1, at most 254) instead of
    /// 1; a move whose weight is [`BARRED`] (255) is never taken.
    #[must_use]
    pub fn weighted(map: &GridMap, capacity: usize, weight: impl Fn(u32, u8) -> u8) -> Distances {
        let mut d = Distances::new(map, capacity);
        let mut w = Vec::with_capacity(d.neighbours.len());
        for (c, &free) in map.free.iter().enumerate() {
            if free {
                w.push(std::array::from_fn(|h| weight(c as u32, h as u8).max(1)));
            }
        }
        let largest = w.iter().flatten().copied().filter(|&x| x != BARRED).max().unwrap_or(1);
        d.buckets = vec![Vec::new(); usize::from(largest) + 1];
        d.weight = Some(w);
        d
    }

    /// The number of free neighbours of `cell`.
    #[must_use]
    pub fn degree(&self, cell: u32) -> u32 {
        let i = self.index[cell as usize];
        if i == u32::MAX {
            return 0;
        }
        self.neighbours[i as usize].iter().filter(|&&v| v != u32::MAX).count() as u32
    }

    /// Whether `cell` is free with exactly one free neighbour (`degree(cell) == 1`), from a
    /// bit per cell: asked for every robot every round, where `degree` reads two tables of
    /// 4 and 16 bytes a cell, out of cache on a map of millions of cells.
    #[must_use]
    pub fn dead_end(&self, cell: u32) -> bool {
        (self.dead_end[cell as usize / 64] >> (cell % 64)) & 1 == 1
    }

    /// Marks a new round of use: tables used in this round are not dropped before the next.
    pub fn tick(&mut self) {
        self.clock += 1;
    }

    /// The table slot for `goal` if its search is complete (marked as used this round).
    pub fn cached(&mut self, goal: u32) -> Option<u32> {
        let s = *self.by_goal.get(&goal)?;
        self.used[s as usize] = self.clock;
        self.complete[s as usize].then_some(s)
    }

    /// The table slot for `goal`, searched to the end if it is not cached.
    pub fn slot(&mut self, goal: u32) -> u32 {
        let mut unbounded = u64::MAX;
        self.search_within(goal, &mut unbounded).expect("an unbounded search completes")
    }

    /// The table slot for `goal` once its search is complete: the search is started or
    /// resumed and expands at most `budget` cells (each one taken off `budget`); `None` if
    /// it is not complete yet (it goes on at the next call).
    pub fn search_within(&mut self, goal: u32, budget: &mut u64) -> Option<u32> {
        let s = if let Some(&s) = self.by_goal.get(&goal) {
            s
        } else if *budget == 0 {
            return None;
        } else {
            // A full cache whose every table served this round keeps them: evicting one would
            // only make its robot search again (never so under the 2023 and 2024 rules, whose
            // planners keep a table per robot and one more).
            if self.tables.len() >= self.capacity && self.used.iter().all(|&u| u == self.clock) {
                return None;
            }
            self.start(goal)
        };
        self.used[s as usize] = self.clock;
        // Without budget an unfinished search waits: resuming would only reshuffle its frontier.
        if !self.complete[s as usize] && *budget > 0 {
            self.expand(s as usize, budget);
        }
        self.complete[s as usize].then_some(s)
    }

    /// A slot for `goal`'s new search: a new table, or the least recently used one.
    fn start(&mut self, goal: u32) -> u32 {
        let s = if self.tables.len() < self.capacity {
            self.tables.push(vec![FAR; self.neighbours.len()]);
            self.goal_of.push(goal);
            self.used.push(0);
            self.frontier.push(Vec::new());
            self.complete.push(false);
            (self.tables.len() - 1) as u32
        } else {
            let s = (0..self.used.len()).min_by_key(|&i| self.used[i]).expect("capacity >= 1") as u32;
            self.by_goal.remove(&self.goal_of[s as usize]);
            self.goal_of[s as usize] = goal;
            self.tables[s as usize].fill(FAR);
            s
        };
        self.by_goal.insert(goal, s);
        self.searches += 1;
        let g = self.index[goal as usize];
        let frontier = &mut self.frontier[s as usize];
        frontier.clear();
        if g != u32::MAX {
            self.tables[s as usize][g as usize] = 0;
            frontier.push(g);
        }
        self.complete[s as usize] = frontier.is_empty();
        s
    }

    /// Whether `slot` still holds `goal`'s table.
    #[must_use]
    pub fn holds(&self, slot: u32, goal: u32) -> bool {
        self.goal_of.get(slot as usize) == Some(&goal)
    }

    /// The distance from `cell` in table `slot`, `FAR` if unreachable.
    #[must_use]
    pub fn get(&self, slot: u32, cell: u32) -> u16 {
        let i = self.index[cell as usize];
        if i == u32::MAX {
            FAR
        } else {
            self.tables[slot as usize][i as usize]
        }
    }

    /// Breadth-first search in slot `s` from its frontier, at most `budget` cells expanded.
    fn expand(&mut self, s: usize, budget: &mut u64) {
        if self.weight.is_some() {
            self.expand_weighted(s, budget);
            return;
        }
        let table = &mut self.tables[s];
        // The shared queue keeps its capacity from search to search; the slot keeps only
        // what is left when the budget runs out.
        self.queue.clear();
        self.queue.append(&mut self.frontier[s]);
        // Every free cell enters the queue at most once in a search, so the queue never
        // outgrows the free cells, and each neighbour is written at the tail whether it is
        // new or not, the tail moving on only if it is: no branch on whether a cell is new,
        // which a processor guesses wrong about as often as right. A missing neighbour is the
        // cell itself, which is labelled and so never new. The queue and the table are those
        // of the plain loop (push the neighbours that are new, east, south, west, north).
        let mut tail = self.queue.len();
        self.queue.resize(self.neighbours.len().max(tail) + 1, 0);
        let queue = &mut self.queue;
        let mut head = 0;
        if self.packed.is_empty() {
            while head < tail && *budget > 0 {
                *budget -= 1;
                let u = queue[head];
                head += 1;
                let around = self.neighbours[u as usize].map(|v| if v == u32::MAX { u } else { v });
                visit(table, queue, u, around, &mut tail);
            }
        } else {
            while head < tail && *budget > 0 {
                *budget -= 1;
                let u = queue[head];
                head += 1;
                visit(table, queue, u, unpack(u, self.packed[u as usize]), &mut tail);
            }
        }
        self.queue.truncate(tail);
        if head < self.queue.len() {
            self.frontier[s].extend_from_slice(&self.queue[head..]);
        } else {
            self.frontier[s] = Vec::new();
            self.complete[s] = true;
        }
    }
}

/// One cell `u` of a breadth-first search expanded: each of `around` not labelled yet gets
/// `u`'s distance and one more, and joins the queue at `tail`.
#[inline]
fn visit(table: &mut [u16], queue: &mut [u32], u: u32, around: [u32; 4], tail: &mut usize) {
    let d = table[u as usize].saturating_add(1).min(FAR - 1);
    for v in around {
        let fresh = table[v as usize] == FAR;
        table[v as usize] = if fresh { d } else { table[v as usize] };
        queue[*tail] = v;
        *tail += usize::from(fresh);
    }
}

/// Packing of a free cell's neighbours: bit 0 east free, bit 1 west free, bits 2-16 how many
/// free cells on from it the cell south is (0: none), bits 17-31 the same back to the cell
/// north. Free cells are numbered in row-major order, so east and west are the next and the
/// previous number, and north and south lie less than a row away.
const EAST: u32 = 1;
const WEST: u32 = 2;
const SPAN: u32 = (1 << 15) - 1;

/// `neighbours` packed, or `None` if some north or south neighbour is too far off in the
/// numbering (a map more than 32,767 cells wide).
fn pack(neighbours: &[[u32; 4]]) -> Option<Vec<u32>> {
    neighbours
        .iter()
        .enumerate()
        .map(|(u, n)| {
            let u = u as u32;
            let east = n[0] != u32::MAX;
            let west = n[2] != u32::MAX;
            debug_assert!(!east || n[0] == u + 1);
            debug_assert!(!west || n[2] == u - 1);
            let south = if n[1] == u32::MAX { 0 } else { n[1] - u };
            let north = if n[3] == u32::MAX { 0 } else { u - n[3] };
            (south <= SPAN && north <= SPAN).then_some((u32::from(east) * EAST) | (u32::from(west) * WEST) | (south << 2) | (north << 17))
        })
        .collect()
}

/// A packed cell's neighbours in the order of `neighbours` (east, south, west, north), `u`
/// itself where there is none.
#[inline]
fn unpack(u: u32, p: u32) -> [u32; 4] {
    let (south, north) = ((p >> 2) & SPAN, (p >> 17) & SPAN);
    [u + (p & EAST), u + south, u - ((p & WEST) >> 1), u - north]
}

impl Distances {
    /// Dijkstra's search in slot `s` from its frontier (towards the goal: a cell's
    /// distance is the cost of its move onto a neighbour plus the neighbour's), at most
    /// `budget` cells expanded. Costs are small integers, so the queue is Dial's: a ring of
    /// buckets, one per distance, as many as the largest cost plus one.
    fn expand_weighted(&mut self, s: usize, budget: &mut u64) {
        let weight = self.weight.as_ref().expect("weighted tables");
        let table = &mut self.tables[s];
        let ring = self.buckets.len();
        let mut cur = u16::MAX;
        for u in self.frontier[s].drain(..) {
            let d = table[u as usize];
            cur = cur.min(d);
            self.buckets[d as usize % ring].push(u);
        }
        let mut waiting = self.buckets.iter().map(Vec::len).sum::<usize>();
        while *budget > 0 && waiting > 0 {
            let b = cur as usize % ring;
            let Some(u) = self.buckets[b].pop() else {
                cur += 1;
                continue;
            };
            waiting -= 1;
            if table[u as usize] != cur {
                continue;
            }
            *budget -= 1;
            for (h, &v) in self.neighbours[u as usize].iter().enumerate() {
                if v == u32::MAX {
                    continue;
                }
                // v moves onto u heading the opposite way of h.
                let w = weight[v as usize][(h + 2) % 4];
                if w == BARRED {
                    continue;
                }
                let dv = cur.saturating_add(u16::from(w)).min(FAR - 1);
                if dv < table[v as usize] {
                    table[v as usize] = dv;
                    self.buckets[dv as usize % ring].push(v);
                    waiting += 1;
                }
            }
        }
        if waiting == 0 {
            self.frontier[s] = Vec::new();
            self.complete[s] = true;
        } else {
            // Stale entries go: a cell is kept once, at its current label.
            let frontier = &mut self.frontier[s];
            for (b, bucket) in self.buckets.iter_mut().enumerate() {
                frontier.extend(bucket.drain(..).filter(|&u| table[u as usize] as usize % ring == b && table[u as usize] >= cur));
            }
            frontier.sort_unstable();
            frontier.dedup();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn search_matches_a_walk_around_the_wall() {
        let map = GridMap::parse("type octile\nheight 3\nwidth 3\nmap\n...\n@@.\n...\n").unwrap();
        let mut d = Distances::new(&map, 1);
        let s = d.slot(6);
        let got: Vec<u16> = (0..9).map(|c| d.get(s, c)).collect();
        assert_eq!(got, vec![6, 5, 4, FAR, FAR, 3, 0, 1, 2]);
        d.tick();
        let s2 = d.slot(0);
        assert!(!d.holds(s, 6) && d.holds(s2, 0));
        assert_eq!(d.get(s2, 8), 4);
    }

    #[test]
    fn packed_neighbours_unpack_to_the_table() {
        let map = GridMap::parse("type octile\nheight 4\nwidth 5\nmap\n.....\n.@@@.\n...@.\n.@...\n").unwrap();
        let d = Distances::new(&map, 1);
        assert_eq!(d.packed.len(), d.neighbours.len());
        for (u, n) in d.neighbours.iter().enumerate() {
            assert_eq!(unpack(u as u32, d.packed[u]), n.map(|v| if v == u32::MAX { u as u32 } else { v }), "free cell {u}");
        }
        for c in 0..map.cells() as u32 {
            assert_eq!(d.dead_end(c), d.degree(c) == 1, "cell {c}");
        }
    }

    #[test]
    fn a_search_spread_over_calls_gives_the_table_of_one_search() {
        let map = GridMap::parse("type octile\nheight 4\nwidth 5\nmap\n.....\n.@@@.\n...@.\n.@...\n").unwrap();
        let mut whole = Distances::new(&map, 4);
        let w = whole.slot(19);
        let mut parts = Distances::new(&map, 4);
        let mut calls = 0;
        let p = loop {
            calls += 1;
            let mut budget = 2;
            if let Some(p) = parts.search_within(19, &mut budget) {
                break p;
            }
            assert_eq!(budget, 0, "an unfinished search spends its whole budget");
            assert_eq!(parts.cached(19), None, "an unfinished table is not handed out");
        };
        assert!(calls > 2);
        let cells = map.cells() as u32;
        assert_eq!((0..cells).map(|c| parts.get(p, c)).collect::<Vec<_>>(), (0..cells).map(|c| whole.get(w, c)).collect::<Vec<_>>());
        assert_eq!(parts.searches, 1);
        let mut none = 0;
        assert_eq!(parts.search_within(0, &mut none), None, "no budget, no new search");
    }

    /// Distances to `goal` by Bellman-Ford over every move, sharing nothing with the search.
    fn relaxed(map: &GridMap, goal: u32, weight: impl Fn(u32, u8) -> u8) -> Vec<u16> {
        let mut d = vec![FAR; map.cells()];
        d[goal as usize] = 0;
        loop {
            let mut changed = false;
            for c in 0..map.cells() as u32 {
                if !map.free[c as usize] {
                    continue;
                }
                for h in 0..4 {
                    let Some(q) = crate::rules::grid::action::ahead(map, c, h) else { continue };
                    if weight(c, h) == BARRED {
                        continue;
                    }
                    if map.free[q as usize] && d[q as usize] != FAR && d[q as usize] + u16::from(weight(c, h)) < d[c as usize] {
                        d[c as usize] = d[q as usize] + u16::from(weight(c, h));
                        changed = true;
                    }
                }
            }
            if !changed {
                return d;
            }
        }
    }

    #[test]
    fn weighted_tables_match_a_relaxation_however_the_search_is_spread() {
        let map = GridMap::parse("type octile\nheight 5\nwidth 7\nmap\n.......\n.@@.@@.\n...@...\n.@.@.@.\n.......\n").unwrap();
        let plain: fn(u32, u8) -> u8 = |c, h| [3u8, 7, 1, 12][h as usize] + (c % 3) as u8;
        // The move from the corner east barred: cell 0 still reaches cell 1, the long way round.
        let barred: fn(u32, u8) -> u8 = |c, h| if c == 0 && h == 0 { BARRED } else { [3u8, 7, 1, 12][h as usize] };
        let mut round = Distances::weighted(&map, 2, barred);
        let mut short = Distances::weighted(&map, 2, plain);
        let (r, s) = (round.slot(1), short.slot(1));
        assert!((0..map.cells() as u32).filter(|&c| map.free[c as usize]).all(|c| round.get(r, c) != FAR));
        assert!(round.get(r, 0) > short.get(s, 0) + 20, "{} against {}", round.get(r, 0), short.get(s, 0));
        for (weight, goal) in [plain, barred].into_iter().flat_map(|w| [(w, 0), (w, 1), (w, 16), (w, 34)]) {
            let want = relaxed(&map, goal, weight);
            for step in [1, 3, u64::MAX] {
                let mut d = Distances::weighted(&map, 2, weight);
                let slot = loop {
                    let mut budget = step;
                    if let Some(s) = d.search_within(goal, &mut budget) {
                        break s;
                    }
                };
                let got: Vec<u16> = (0..map.cells() as u32).map(|c| d.get(slot, c)).collect();
                assert_eq!(got, want, "goal {goal}, {step} cells a call");
            }
        }
    }
}
