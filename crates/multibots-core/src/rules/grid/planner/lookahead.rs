//! `rpibt` and `lookahead`: PIBT on the robots' actions (forward, turn, wait) rather than
//! on cells, steered by distances that count the turns; `lookahead` plays several PIBTs a
//! few steps ahead and keeps the first step of the one that gets furthest.
//!
//! ## Why
//! On the archive's 32×32 random maps, `pibt` (cells, then turns) finished about half of the
//! best known (MR24-RANDOM-01: 376 tasks by step 600 against 696). Read from its result
//! file, a robot spends 24 % of its steps turning (37 turns per task for 57 cells of
//! errand-to-errand legs), 17 % waiting and 9 % going away from its errand: its distances
//! ignore the heading, so of two equally short ways it often takes the one with more
//! turns, and a robot that turns holds up the chain of robots planned into its cell.
//!
//! ## What it does
//! Distances are counted in actions over (cell, heading) states: a backward breadth-first
//! search from the errand's four headings, with moves `F`, `R` and `C` (one search per
//! errand cell, cached). Each step robots plan in order of priority (the nearer their errand,
//! the sooner; robots without an errand last; a per-robot random number breaks ties), by PIBT
//! on cells: a neighbouring cell costs the turns to face it, the move, and the distance from
//! there facing that way; the robot's own cell costs its best of `W`, `R` and `C`. Of equal
//! costs the fewer turns go first, so of two equally short ways a robot takes the straighter.
//! A robot planned into another's cell asks it to leave first (priority inheritance); it may
//! not take the asker's cell (a swap). A robot bound for a cell it does not face turns
//! towards it and stays, and whoever planned to enter its cell waits, down the chain.
//!
//! PIBT on actions (a robot asked to leave may only go forward) was tried first and jammed:
//! in a crowd every robot faces another, no chain of forward moves reaches a free cell, and
//! MR24-RANDOM-01 finished 56 tasks by step 600.
//!
//! `lookahead` uses the time the competition allows (the budget: 60 ms a step on
//! average): every step it plays `ROLLOUTS` such PIBTs, each with its own tie-break numbers,
//! [`WINDOW`] steps ahead (robots reaching their errand then stop: the next one is not known
//! yet), scores each by the distance its robots covered (reaching an errand counts for the
//! rest of the window too), and takes the first step of the best. The tie-break numbers of
//! the winner are kept for the next step, so the plan it began is one of the candidates
//! again: the choice changes only when another one gets further.
//!
//! ## Cost
//! One search of 4 × cells states per errand cell (cached, up to [`TABLE_BUDGET`] bytes, then
//! the cache is cleared); per step O(N log N) for `rpibt`, times rollouts × window for
//! `lookahead`, whose rollouts shrink with the fleet to keep to [`ROBOT_STEPS`].
//! Deterministic for a seed.

use super::guidance::{highway_costs, obstacles_in_blocks, WITH};
use super::window::Window;
use super::{PlanView, Planner, NO_GOAL};
use crate::input::lorr::GridMap;
use crate::rules::grid::action::{ahead, Action};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashMap;

const NONE: u32 = u32::MAX;
/// Distance of a state from which the errand cannot be reached.
const FAR: u16 = u16::MAX;

/// Steps each rollout of `lookahead` plays.
pub const WINDOW: usize = 16;
/// Rollouts of `lookahead` per step, at most.
pub const ROLLOUTS: usize = 16;
/// Robot-steps of simulation per planning step (rollouts are cut to fit): about 20 ms on
/// one core.
pub const ROBOT_STEPS: usize = 400_000;
/// The least cost of a move against a lane, in [`WITH`]s, for `rpibt-pp` on a map whose
/// obstacles stand in blocks ([`Lookahead::on_highways_by_density`]).
pub const BLOCK_LANES: f64 = 6.0;
/// Memory the distance tables may take before the cache is cleared.
const TABLE_BUDGET: usize = 1 << 30;
/// Memory up to which every free cell's table is made before the first step
/// ([`Lookahead::prepared`]): 64 MB holds a 32×32 random map's 819 tables (6.7 MB) and
/// `warehouse_small`'s 895 (13.5 MB), not `sortation_medium`'s 9,410 (2.1 GB).
const PREPARED_BUDGET: usize = 64 << 20;

/// Distances in actions to each errand cell, over (cell, heading) states.
pub(super) struct Tables {
    /// Per cell and heading, the cell ahead if free, or `NONE`.
    pub(super) next: Vec<[u32; 4]>,
    cells: usize,
    by_goal: HashMap<u32, Vec<u16>>,
    queue: Vec<u32>,
    /// Per cell and heading, the cost of a move forward (the highways, `guidance.rs`), or
    /// `None`: every action costs one.
    weight: Option<Vec<[u8; 4]>>,
    /// The cost of a turn or a wait: [`WITH`] on the highways, else 1.
    pub(super) unit: u32,
}

impl Tables {
    fn new(map: &GridMap) -> Tables {
        let next = (0..map.cells() as u32)
            .map(|c| std::array::from_fn(|h| ahead(map, c, h as u8).filter(|&q| map.free[q as usize] && map.free[c as usize]).unwrap_or(NONE)))
            .collect();
        Tables { next, cells: map.cells(), by_goal: HashMap::new(), queue: Vec::new(), weight: None, unit: 1 }
    }

    /// The same tables with moves costing as on the highways (`guidance.rs`).
    fn on_highways(mut self, map: &GridMap, against: u8) -> Tables {
        let mut w = highway_costs(map);
        for c in w.iter_mut().flatten() {
            if *c > WITH {
                *c = against;
            }
        }
        self.weight = Some(w);
        self.unit = u32::from(WITH);
        self
    }

    /// The cost of a move forward from `cell` facing `h`.
    pub(super) fn forward(&self, cell: u32, h: u8) -> u32 {
        self.weight.as_ref().map_or(1, |w| u32::from(w[cell as usize][h as usize]))
    }

    /// Clears the cache if `needed` more tables would not fit in [`TABLE_BUDGET`]: called
    /// before a step's tables are made, never between, so that none of them is dropped.
    fn make_room(&mut self, needed: usize) {
        if (self.by_goal.len() + needed) * self.cells * 8 > TABLE_BUDGET {
            self.by_goal.clear();
        }
    }

    /// Makes sure `goal`'s table exists.
    fn ensure(&mut self, goal: u32) {
        if self.by_goal.contains_key(&goal) {
            return;
        }
        if self.weight.is_some() {
            self.ensure_weighted(goal);
            return;
        }
        let mut t = vec![FAR; self.cells * 4];
        self.queue.clear();
        for h in 0..4 {
            t[goal as usize * 4 + h] = 0;
            self.queue.push(goal * 4 + h as u32);
        }
        let mut head = 0;
        while head < self.queue.len() {
            let s = self.queue[head];
            head += 1;
            let (c, h) = (s / 4, s % 4);
            let d = t[s as usize] + 1;
            // Predecessors: the cell behind, facing the same way (F); the same cell turned
            // counter-clockwise (R brings it here) or clockwise (C).
            let back = self.next[c as usize][((h + 2) % 4) as usize];
            let mut preds = [NONE; 3];
            if back != NONE {
                preds[0] = back * 4 + h;
            }
            preds[1] = c * 4 + (h + 3) % 4;
            preds[2] = c * 4 + (h + 1) % 4;
            for p in preds {
                if p != NONE && t[p as usize] == FAR {
                    t[p as usize] = d;
                    self.queue.push(p);
                }
            }
        }
        self.by_goal.insert(goal, t);
    }

    /// `ensure` by Dijkstra's search, moves costing as the highways say.
    fn ensure_weighted(&mut self, goal: u32) {
        let mut t = vec![FAR; self.cells * 4];
        let mut heap = std::collections::BinaryHeap::new();
        for h in 0..4 {
            t[goal as usize * 4 + h] = 0;
            heap.push(std::cmp::Reverse((0u16, goal * 4 + h as u32)));
        }
        while let Some(std::cmp::Reverse((d, s))) = heap.pop() {
            if d != t[s as usize] {
                continue;
            }
            let (c, h) = (s / 4, (s % 4) as u8);
            let back = self.next[c as usize][((h + 2) % 4) as usize];
            let mut preds = [(NONE, 0); 3];
            if back != NONE {
                preds[0] = (back * 4 + u32::from(h), self.forward(back, h));
            }
            preds[1] = (c * 4 + u32::from((h + 3) % 4), self.unit);
            preds[2] = (c * 4 + u32::from((h + 1) % 4), self.unit);
            for (p, w) in preds {
                if p == NONE {
                    continue;
                }
                let nd = (u32::from(d) + w).min(u32::from(FAR) - 1) as u16;
                if nd < t[p as usize] {
                    t[p as usize] = nd;
                    heap.push(std::cmp::Reverse((nd, p)));
                }
            }
        }
        self.by_goal.insert(goal, t);
    }

    pub(super) fn get(&self, goal: u32) -> &[u16] {
        &self.by_goal[&goal]
    }
}

/// The buffers of one PIBT step.
struct Work {
    occ_now: Vec<u32>,
    res: Vec<u32>,
    next: Vec<u32>,
    order: Vec<u32>,
    key: Vec<u64>,
    stay: Vec<u32>,
}

impl Work {
    fn new(cells: usize, robots: usize) -> Work {
        Work {
            occ_now: vec![NONE; cells],
            res: vec![NONE; cells],
            next: vec![NONE; robots],
            order: (0..robots as u32).collect(),
            key: vec![0; robots],
            stay: Vec::new(),
        }
    }
}

/// What one PIBT step reads.
struct Step<'a> {
    tables: &'a Tables,
    loc: &'a [u32],
    heading: &'a [u8],
    goals: &'a [u32],
    /// Per robot, the cell the windowed paths (`window.rs`) lead it to, or `NONE`, and the
    /// action it makes if that is its own cell.
    guide: Option<(&'a [u32], &'a [Action])>,
}

impl Step<'_> {
    fn cost(&self, a: usize, cell: u32, h: u8) -> u32 {
        let g = self.goals[a];
        if g == NO_GOAL {
            0
        } else {
            u32::from(self.tables.get(g)[cell as usize * 4 + h as usize])
        }
    }

    /// The best of `W`, `R` and `C` for robot `a`, and what it costs.
    fn best_stay(&self, a: usize) -> (u32, Action) {
        let (p, h) = (self.loc[a], self.heading[a]);
        let unit = self.tables.unit;
        let mut best = (self.cost(a, p, h).saturating_add(unit), Action::W);
        for (act, nh) in [(Action::R, (h + 1) % 4), (Action::C, (h + 3) % 4)] {
            let c = self.cost(a, p, nh).saturating_add(unit);
            if c < best.0 {
                best = (c, act);
            }
        }
        best
    }

    /// Candidate cells of robot `a`, best first: each neighbour at the cost of the turns to
    /// face it, the move and the distance from there; its own cell at the cost of its best
    /// stay. Ties go to the fewer turns, then to the cell ahead.
    fn candidates(&self, a: usize) -> ([u32; 5], usize) {
        let (p, h) = (self.loc[a], self.heading[a]);
        let mut keyed = [(0u32, 0u8, NONE); 5];
        let mut n = 0;
        let no_goal = self.goals[a] == NO_GOAL;
        keyed[n] = (if no_goal { 0 } else { self.best_stay(a).0 }, 1, p);
        n += 1;
        for d in 0..4u8 {
            let u = self.tables.next[p as usize][d as usize];
            if u == NONE {
                continue;
            }
            let turns = [0u8, 1, 2, 1][((d + 4 - h) % 4) as usize];
            let step = self.tables.forward(p, d) + self.tables.unit * u32::from(turns);
            let c = if no_goal { step } else { self.cost(a, u, d).saturating_add(step) };
            if c >= u32::from(FAR) {
                continue;
            }
            keyed[n] = (c, if turns == 0 { 0 } else { turns + 1 }, u);
            n += 1;
        }
        if let Some((guide, _)) = self.guide {
            for k in &mut keyed[..n] {
                if k.2 == guide[a] {
                    k.0 = 0;
                    k.1 = 0;
                }
            }
        }
        keyed[..n].sort_unstable();
        let mut out = [NONE; 5];
        for (o, k) in out.iter_mut().zip(&keyed[..n]) {
            *o = k.2;
        }
        (out, n)
    }

    /// Plans robot `a`'s next cell (PIBT on cells); `from` is the cell of the robot that
    /// asked it to leave (`NONE` at the top), which it may not take (a swap). Whether it
    /// found a cell.
    fn pibt(&self, w: &mut Work, a: usize, from: u32) -> bool {
        let p = self.loc[a];
        let (cands, n) = self.candidates(a);
        for &c in &cands[..n] {
            if c == from || w.res[c as usize] != NONE {
                continue;
            }
            let b = w.occ_now[c as usize];
            // A swap with a robot already planned into this one's cell.
            if b != NONE && b as usize != a && w.next[b as usize] == p {
                continue;
            }
            w.res[c as usize] = a as u32;
            w.next[a] = c;
            if b != NONE && b as usize != a && w.next[b as usize] == NONE && !self.pibt(w, b as usize, p) {
                // `b` stays, and now holds its cell.
                w.next[a] = NONE;
                continue;
            }
            return true;
        }
        // Every cell refused: it stays, and takes its cell back from the asker.
        w.res[p as usize] = a as u32;
        w.next[a] = p;
        false
    }

    #[allow(clippy::needless_range_loop)] // robot `a` indexes several columns at once
    /// One joint action for every robot, in the order of `tie` (lower first among equals);
    /// `w.next` then holds each robot's cell after it.
    fn run(&self, w: &mut Work, tie: &[u32], acts: &mut [Action]) {
        let n = self.loc.len();
        for a in 0..n {
            w.occ_now[self.loc[a] as usize] = a as u32;
            w.next[a] = NONE;
            let d = if self.goals[a] == NO_GOAL { u64::from(u32::MAX) } else { u64::from(self.cost(a, self.loc[a], self.heading[a])) };
            w.key[a] = (d << 32) | u64::from(tie[a]);
        }
        let key = &w.key;
        w.order.sort_unstable_by_key(|&a| (key[a as usize], a));
        for i in 0..n {
            let a = w.order[i] as usize;
            if w.next[a] == NONE {
                self.pibt(w, a, NONE);
            }
        }
        // Cells to actions: a robot bound for a cell it does not face turns towards it and
        // stays; whoever planned to enter the cell of a robot that stays waits, down the chain.
        w.stay.clear();
        for a in 0..n {
            let (p, h, q) = (self.loc[a], self.heading[a], w.next[a]);
            acts[a] = if q == p {
                match self.guide {
                    Some((guide, turn)) if guide[a] == p => turn[a],
                    _ => self.best_stay(a).1,
                }
            } else if self.tables.next[p as usize][h as usize] == q {
                Action::F
            } else if self.tables.next[p as usize][((h + 3) % 4) as usize] == q {
                Action::C
            } else {
                Action::R
            };
            if acts[a] != Action::F {
                w.stay.push(a as u32);
            }
        }
        while let Some(s) = w.stay.pop() {
            let p = self.loc[s as usize];
            let r = w.res[p as usize];
            if r != NONE && r != s && acts[r as usize] == Action::F {
                acts[r as usize] = Action::W;
                w.stay.push(r);
            }
        }
        for a in 0..n {
            w.occ_now[self.loc[a] as usize] = NONE;
            w.res[w.next[a] as usize] = NONE;
            if acts[a] != Action::F {
                w.next[a] = self.loc[a];
            }
        }
    }
}

/// PIBT on actions with turn-counting distances; with rollouts, `lookahead`.
pub struct Lookahead {
    tables: Tables,
    work: Work,
    rng: ChaCha8Rng,
    /// The tie-break numbers in force (the last winner's).
    tie: Vec<u32>,
    rollouts: usize,
    name: &'static str,
    // Rollout buffers.
    loc: Vec<u32>,
    heading: Vec<u8>,
    goals: Vec<u32>,
    acts: Vec<Action>,
    first: Vec<Action>,
    cand: Vec<u32>,
    /// Windowed paths guiding `rpibt` (`rpibt-pp`), and what they give.
    window: Option<Window>,
    guide: Vec<u32>,
    turn: Vec<Action>,
}

impl Lookahead {
    /// A planner for `robots` robots on `map`, seeded by `seed`; `rollouts` 0 plans one step
    /// (`rpibt`), more plays that many rollouts at most (`lookahead`).
    #[must_use]
    pub fn new(map: &GridMap, robots: usize, seed: u64, rollouts: usize) -> Lookahead {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let tie = (0..robots).map(|_| rng.random::<u32>()).collect();
        Lookahead {
            tables: Tables::new(map),
            work: Work::new(map.cells(), robots),
            rng,
            tie,
            rollouts,
            name: if rollouts == 0 { "rpibt" } else { "lookahead" },
            loc: vec![0; robots],
            heading: vec![0; robots],
            goals: vec![NO_GOAL; robots],
            acts: vec![Action::W; robots],
            first: vec![Action::W; robots],
            cand: vec![0; robots],
            window: None,
            guide: vec![NONE; robots],
            turn: vec![Action::W; robots],
        }
    }

    /// The same planner guided by windowed paths (`rpibt-pp`, `window.rs`).
    #[must_use]
    pub fn guided(mut self, cells: usize) -> Lookahead {
        self.window = Some(Window::new(cells));
        self.name = "rpibt-pp";
        self
    }

    /// The same planner with moves costing as on the highways (`guidance.rs`), a move
    /// against a lane costing more the more crowded the map: [`WITH`] times 12ρ − 2 (at
    /// least 1, at most 20) for ρ robots per free cell, and at least [`BLOCK_LANES`] where the
    /// obstacles stand in blocks ([`obstacles_in_blocks`]) if `blocks`. Measured on the 32×32 random map
    /// (seed 0, spread): 100 robots (ρ 0.12) finished 596 tasks without highways, 616 with
    /// 15, 540 with 60; 400 robots (ρ 0.49) 724 without, 892 with 60, 799 with 100; 700
    /// robots (ρ 0.85) 397 without, 617 with 60, 636 with 100, 578 with 200 (`pibt`'s).
    /// Between shelves the lanes pay sooner: on `warehouse_small` (2023 example instances,
    /// 5,000 steps) 400 robots (ρ 0.31) finished 22,176 with 18, 37,148 with 60 and 37,392
    /// with 200; 100 robots (ρ 0.08) 13,222 without, 12,948 with 60. `blocks` false leaves
    /// that floor out: the 2026 rules' rooms and mazes have walls, not shelves, and
    /// `room-example_150` finished 79 tasks with it against 90 without.
    #[must_use]
    pub fn on_highways_by_density(mut self, map: &GridMap, robots: usize, blocks: bool) -> Lookahead {
        let free = map.free.iter().filter(|&&f| f).count().max(1);
        let rho = robots as f64 / free as f64;
        let least = if blocks && obstacles_in_blocks(map) { BLOCK_LANES } else { 1.0 };
        let against = (f64::from(WITH) * (12.0 * rho - 2.0).clamp(least, 20.0)).round() as u8;
        if against > WITH {
            self.tables = std::mem::replace(&mut self.tables, Tables::new(&GridMap { rows: 0, cols: 0, free: Vec::new() })).on_highways(map, against);
        }
        self
    }

    /// The same planner with the table of every free cell made now, if they all fit in
    /// [`PREPARED_BUDGET`]: made as errands appear instead, a dense fleet's first step
    /// searches one table per robot (800 robots on a 32×32 map: 100-200 ms, beyond the
    /// 60 ms a step), where the competition gives preprocessing its own time. The plans are
    /// the same either way.
    #[must_use]
    pub fn prepared(mut self, map: &GridMap) -> Lookahead {
        let free: Vec<u32> = (0..map.cells() as u32).filter(|&c| map.free[c as usize]).collect();
        if free.len() * map.cells() * 8 <= PREPARED_BUDGET {
            for c in free {
                self.tables.ensure(c);
            }
        }
        self
    }

    /// Plays `WINDOW` steps from the view with tie-break numbers `tie`; the first step's
    /// actions go to `first`; the score (the higher, the further the robots got).
    fn rollout(&mut self, view: &PlanView<'_>, tie: &[u32], first: &mut [Action]) -> i64 {
        let n = view.loc.len();
        self.loc.copy_from_slice(view.loc);
        self.heading.copy_from_slice(view.heading);
        self.goals.copy_from_slice(view.goals);
        let mut score = 0i64;
        for t in 0..WINDOW {
            let step = Step { tables: &self.tables, loc: &self.loc, heading: &self.heading, goals: &self.goals, guide: None };
            step.run(&mut self.work, tie, &mut self.acts);
            if t == 0 {
                first.copy_from_slice(&self.acts);
            }
            for a in 0..n {
                match self.acts[a] {
                    Action::F => self.loc[a] = self.work.next[a],
                    act => self.heading[a] = act.turned(self.heading[a]),
                }
                if self.goals[a] != NO_GOAL && self.loc[a] == self.goals[a] {
                    // Reached: it counts for every step left, and waits for its next errand.
                    score += (WINDOW - t) as i64;
                    self.goals[a] = NO_GOAL;
                }
            }
        }
        for a in 0..n {
            let g = view.goals[a];
            if g == NO_GOAL {
                continue;
            }
            let t = self.tables.get(g);
            let before = i64::from(t[view.loc[a] as usize * 4 + view.heading[a] as usize]);
            let after = if self.goals[a] == NO_GOAL { 0 } else { i64::from(t[self.loc[a] as usize * 4 + self.heading[a] as usize]) };
            score += before - after;
        }
        score
    }
}

impl Planner for Lookahead {
    fn name(&self) -> &'static str {
        self.name
    }

    fn plan(&mut self, view: &PlanView<'_>, actions: &mut [Action]) {
        let n = view.loc.len();
        let new = view.goals.iter().filter(|&&g| g != NO_GOAL && !self.tables.by_goal.contains_key(&g)).count();
        self.tables.make_room(new);
        for &g in view.goals {
            if g != NO_GOAL {
                self.tables.ensure(g);
            }
        }
        if self.rollouts == 0 {
            let mut guide = None;
            if let Some(window) = &mut self.window {
                let mut order: Vec<u32> = (0..n as u32).collect();
                let key = |a: u32| {
                    let a = a as usize;
                    let g = view.goals[a];
                    let d = if g == NO_GOAL { u64::from(u32::MAX) } else { u64::from(self.tables.get(g)[view.loc[a] as usize * 4 + view.heading[a] as usize]) };
                    ((d << 32) | u64::from(self.tie[a]), a)
                };
                order.sort_unstable_by_key(|&a| key(a));
                window.plan(&self.tables, view.loc, view.heading, view.goals, NO_GOAL, &order, &mut self.guide, &mut self.turn);
                guide = Some((&self.guide[..], &self.turn[..]));
            }
            let step = Step { tables: &self.tables, loc: view.loc, heading: view.heading, goals: view.goals, guide };
            step.run(&mut self.work, &self.tie, actions);
            return;
        }
        let rollouts = self.rollouts.min(ROBOT_STEPS / (WINDOW * n.max(1))).max(1);
        let tie = std::mem::take(&mut self.tie);
        let mut first = std::mem::take(&mut self.first);
        let mut best = self.rollout(view, &tie, actions);
        self.tie = tie;
        for r in 1..rollouts {
            // Half the candidates change a few robots' numbers, half draw them all anew.
            let mut cand = std::mem::take(&mut self.cand);
            if r % 2 == 1 {
                cand.copy_from_slice(&self.tie);
                for _ in 0..(n / 8).max(1) {
                    let a = self.rng.random_range(0..n);
                    cand[a] = self.rng.random::<u32>();
                }
            } else {
                for c in &mut cand {
                    *c = self.rng.random::<u32>();
                }
            }
            let score = self.rollout(view, &cand, &mut first);
            if score > best {
                best = score;
                actions.copy_from_slice(&first);
                std::mem::swap(&mut self.tie, &mut cand);
            }
            self.cand = cand;
        }
        self.first = first;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(map: &str, loc: &[u32], heading: &[u8], goals: &[u32], rollouts: usize) -> Vec<Action> {
        let map = GridMap::parse(map).unwrap();
        let mut p = Lookahead::new(&map, loc.len(), 3, rollouts);
        let mut actions = vec![Action::W; loc.len()];
        p.plan(&PlanView { map: &map, loc, heading, goals, t: 0, tasks: None }, &mut actions);
        actions
    }

    #[test]
    fn distances_count_the_turns() {
        let map = GridMap::parse("type octile\nheight 2\nwidth 3\nmap\n...\n...\n").unwrap();
        let mut t = Tables::new(&map);
        t.ensure(2);
        let d = t.get(2);
        // From cell 0: facing east two moves; facing south a turn first; facing west two turns.
        assert_eq!((d[0], d[1], d[2], d[3]), (2, 3, 4, 3));
    }

    #[test]
    fn a_pushed_robot_leaves_forward_and_the_pusher_follows() {
        let map = "type octile\nheight 1\nwidth 4\nmap\n....\n";
        assert_eq!(plan(map, &[0, 1], &[0, 0], &[3, NO_GOAL], 0), vec![Action::F, Action::F]);
        // Facing the pusher, the robot ahead cannot leave: the pusher waits.
        let a = plan(map, &[0, 1], &[0, 2], &[3, NO_GOAL], 0);
        assert_eq!(a[0], Action::W);
        assert_ne!(a[1], Action::F);
    }

    #[test]
    fn lookahead_gives_a_valid_joint_action() {
        let map = "type octile\nheight 3\nwidth 3\nmap\n...\n.@.\n...\n";
        let a = plan(map, &[0, 1, 2], &[0, 0, 1], &[2, 0, 8], 8);
        let map = GridMap::parse(map).unwrap();
        let mut v = crate::rules::grid::action::Validator::default();
        assert!(v.check(&map, &[0, 1, 2], &[0, 0, 1], &a, 1).is_none());
    }
}
