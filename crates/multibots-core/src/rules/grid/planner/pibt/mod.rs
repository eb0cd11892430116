//! PIBT with rotations: Priority Inheritance with Backtracking (Okumura, Machida, Défago,
//! Tamura, "Priority inheritance with backtracking for iterative multi-agent path finding",
//! AIJ 2022), run on cells, then turned into the rotation action model.
//!
//! ## What it does
//! Each step, robots are taken in order of priority: the nearer its errand, the sooner a
//! robot plans (as the 2024 League of Robot Runners winner's planner orders its robots),
//! robots without an errand last, with a fixed random fraction per robot to break ties
//! (seeded, so a run is the same every time). Plain PIBT's priority, the steps since the
//! errand was set, lets two queues facing each other on a corridor take turns at winning,
//! and a crowded warehouse then jams (measured on `warehouse_large` with 5,000 robots: 20,695
//! tasks against 73,257). A robot takes the free neighbouring cell (or its own) nearest its
//! errand by exact distance on the highways (`guidance.rs`), or by grid distance for
//! `pibt-no-highways`; ties go to the lane with fewer robots on its next 8 cells (not for
//! `pibt-no-lanes`), then to the cell straight ahead (no turn needed), then to a seeded
//! random order. If another robot stands there, that robot is asked to move first and
//! inherits the priority; if it cannot, the next cell is tried (backtracking). The
//! result has no vertex conflict and no swap.
//!
//! The lane count matters on shelf maps. A robot bound for a shelf across the map has many
//! equally short routes (along the open band by the stations, then down; or down first,
//! then along a shelf corridor), and preferring the cell ahead keeps every such robot on
//! the band, which fills: on `MR24-WAREHOUSE` (10,000 robots, scheduler `nearest`) the band
//! in front of the stations jammed and the finished tasks fell from 18,354 in the first
//! 1,000 steps to 11,711 and 8,784 in the next. Taking the emptier lane spreads them over the
//! shelf corridors: 59,326 tasks in 3,000 steps against 38,849 (tie-break seeds 1 and 2:
//! 51,858 and 49,177; seed 1 without it: 35,011); with `spread`, 78,269 against 52,915. It
//! only breaks ties: ranking a crowded lane below a longer route, or below waiting, made
//! robots wait for each other in a circle and the fleet stopped within 1,000 steps
//! (measured, then left out). On the 2023 instances, whose errands come in a fixed order, it
//! costs (MR23-I-10: 83,981 against 95,115), hence `pibt-no-lanes`.
//!
//! On the highways, a robot steps against the lane into a passage one cell wide and at
//! least two long (an aisle between shelves: the entered cell and the next have walls on
//! both sides) only if the step brings it nearer its errand, never to make way, unless it
//! backs out for a swap (below). Robots pushed aside into the wrong way of an aisle met the
//! robots coming along it head-on, neither could give way in a full aisle, and on MR23-I-10
//! (10,000 robots, 2023 rules) the shelf rows near the stations froze solid. Measured over
//! 5,000 steps: MR23-I-10 104,167 tasks against 83,981 (`pibt`), 115,779 against 95,115
//! (`pibt-no-lanes`), the fleet no longer slowing down after step 2,000; TR23-warehouse_large
//! 19,946 against 19,929; in 3,000 steps MR24-WAREHOUSE 78,918 against 78,269, and
//! MR24-SORTATION (72,775) and MR24-CITY-01 (7,255) the same. Counting every passage
//! without a free 2×2 block, one-cell gaps included, cost the small random maps 15-20 %;
//! with passages of two cells or more they lose 0-5 % (MR24-RANDOM-03 to 05, four seeds).
//! Keeping robots off the wrong way of open areas too (`pibt-one-way`, which also breaks
//! ties straight ahead as `pibt-no-lanes` does) gives MR23-I-10 128,162 in 5,000 steps and
//! MR23-I-06 138,726 (`pibt`: 108,795), MR24-SORTATION 76,429 in 3,000 steps (72,775), but
//! MR24-WAREHOUSE 74,308 (78,918), which needs the lane count; and with the lane count kept
//! MR24-RANDOM-05 fell from 699 to 193 and MR24-CITY-01 from 6,991 to 6,806 (3,000 steps;
//! both against the first, wider aisle rule). So the default keeps both ways in open areas.
//! Only in open cells whose eight neighbours are all free: MR23-I-10 +2.6 % (3,000 steps),
//! random maps unchanged, but MR24-SORTATION -0.8 % and MR24-CITY-01 -2.6 %; left out.
//! `pibt-one-way` now bars the wrong way outright between cells the lanes connect both ways
//! (`guidance::lanes_core`; MR23-I-10 134,955), and weights moves along open bands a tenth
//! more (`guidance::open_band_costs`; 153,375, every 1,000 steps 30,306-30,957).
//!
//! Plain PIBT deadlocks where two robots meet head-on in a corridor that ends (a dead end of
//! the random maps): the one of higher priority wants in, the other can only leave through
//! it, and priorities that grow alike never change who wins. The swap operation of
//! Okumura's later PIBT (LaCAM*, "Engineering LaCAM*", 2024) resolves it: when a robot's
//! best cell holds a robot that must pass it (the corridor ahead has no branch before the
//! second robot's way out), and the corridor behind the first robot has a branch, the first
//! robot walks backwards (its candidates reversed) and pulls the second one after it until
//! they can pass at the branch.
//!
//! A robot whose cell is not straight ahead turns towards it instead (`R` or `C`; a cell
//! behind is turned to clockwise), and so stays where it is this step; it stays bound for
//! that cell (reserved before anyone else plans) until it gets there, as the Start-Kit's
//! default planner does, since choosing again would undo the turn. Any robot that planned
//! to enter the cell of a robot that stays must then wait too, and so on down the chain
//! (`settle`), so that the joint action is always valid. A robot in a dead end gets 10
//! more of priority (ten cells without highways, one move along a lane with them; it can
//! only leave the way others come in: scaled to ten lane moves, the measured scores did not
//! change beyond 0.3 %). A robot without an errand
//! keeps its cell unless pushed.
//!
//! ## When to use it
//! Always: fast and never invalid. On small open maps (the archive's 32×32 random maps)
//! `pibt-no-highways` finishes 5-15 % more. It does not look ahead, so in narrow corridors
//! robots can oscillate.
//!
//! ## Cost
//! O(N log N) per step, plus one search of the map per new errand cell (cached; Dijkstra's
//! with a ring of buckets on the highways, breadth-first without them),
//! at most `SEARCH_CELLS_PER_ROUND` cells expanded per step, a search going on over several
//! steps if need be.
//!
//! The recursion of the paper runs on an explicit stack: a chain of pushes can be as long
//! as the fleet (10,000 robots), deeper than a thread's stack allows.

mod build;
#[cfg(test)]
mod tests;

pub use build::Variant;

use super::dist::{Distances, BARRED, FAR};
use super::{PlanView, Planner, NO_GOAL};
use crate::rules::grid::action::{ahead, heading_to, Action};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

const NONE: u32 = u32::MAX;

/// The PIBT planner's state between steps.
pub struct Pibt {
    dist: Distances,
    cols: u32,
    rng: ChaCha8Rng,
    tie: Vec<f32>,
    /// Per robot, how soon it plans: [`FAR`] less its distance to its errand.
    urgency: Vec<u32>,
    slot: Vec<u32>,
    order: Vec<u32>,
    occ_now: Vec<u32>,
    /// `occ_now[c] != NONE`, a bit per cell: the lane count reads eight cells a candidate, and
    /// on a map of millions of cells these bits stay in cache where `occ_now` does not.
    occ_bits: Vec<u64>,
    occ_next: Vec<u32>,
    next: Vec<u32>,
    stack: Vec<Frame>,
    queue: Vec<u32>,
    /// The cell each robot is bound for and has not reached (it is still turning towards
    /// it), or `NONE`.
    bound: Vec<u32>,
    bonus: Vec<u32>,
    /// Whether ties go to the emptier lane (`pibt`) or straight to the cell ahead.
    lanes: bool,
    /// Per cell, bit `h` set if leaving it in heading `h` is kept to robots it brings
    /// nearer their errand: against the lane into a passage one cell wide and at least two
    /// long, or against the lane anywhere for `pibt-one-way`.
    wrong_way: Vec<u8>,
    /// The highways' move costs, if any.
    costs: Option<Vec<[u8; 4]>>,
    /// Searches go to the robots nearest their errands first (`Pibt::lean`), not in id order.
    lean: bool,
    /// Whether the map is searched at all (`pibt-grid` steers by grid distance alone).
    search: bool,
}

struct Frame {
    agent: u32,
    cands: [u32; 5],
    n: u8,
    i: u8,
    /// The robot pulled into this one's cell if its first candidate is taken (a swap).
    swap: u32,
}

/// Cells the distance searches of a planning round may expand: about 0.1 s on one quiet
/// core (a search of `warehouse_large` expands its 38,586 free cells in 0.3-0.7 ms, the
/// latter on a loaded machine), so that no round, the first included, comes near a second
/// at 10,000 robots. Robots whose table is not complete steer by grid distance until a
/// later round completes it. A count of cells, not a clock: a run is the same on every
/// machine.
const SEARCH_CELLS_PER_ROUND: u64 = 12_000_000;

/// How far ahead a robot counts the robots on a lane it could take. Measured on
/// `MR24-WAREHOUSE` over 2,000 steps: 4 cells gave 35,547 tasks, 8 gave 46,458, 16 gave
/// 35,931 (a far count sees robots that will have moved on).
const LANE_CELLS: u32 = 8;

impl Pibt {
    /// Distance searches made so far.
    #[must_use]
    pub fn searches(&self) -> u64 {
        self.dist.searches
    }

    fn cost(&self, a: usize, cell: u32, goal: u32) -> u16 {
        if goal == NO_GOAL {
            0
        } else if self.slot[a] == NONE {
            // No table yet (its search is not complete): the grid distance for now. It counts
            // cells, not the highways' tenths of a cell, so these robots (their errand is
            // new) plan before the others; scaled to the tables' unit, MR24-WAREHOUSE
            // finished 15,987 by step 1,000 against 18,354.
            let (r0, c0) = (cell / self.cols, cell % self.cols);
            let (r1, c1) = (goal / self.cols, goal % self.cols);
            (r0.abs_diff(r1) + c0.abs_diff(c1)).min(u32::from(FAR - 1)) as u16
        } else {
            self.dist.get(self.slot[a], cell)
        }
    }

    /// Candidate cells of robot `a`, best first, and which of them (a bit per rank) are a
    /// step against the lane through a one-cell passage that does not bring it nearer.
    fn candidates(&mut self, view: &PlanView<'_>, a: usize) -> ([u32; 5], u8, u8) {
        let p = view.loc[a];
        let goal = view.goals[a];
        let mut keyed: [(u16, u8, u8, u32, u32, bool); 5] = [(0, 0, 0, 0, NONE, false); 5];
        let mut n = 0;
        // The key: distance to the goal, then the emptier lane, then the cell straight ahead
        // first, then a seeded random draw. A robot without a goal stays first.
        let dp = self.cost(a, p, goal);
        keyed[n] = (dp, 0, u8::from(goal != NO_GOAL), self.rng.random::<u32>(), p, false);
        n += 1;
        for h in 0..4u8 {
            if let Some(q) = ahead(view.map, p, h) {
                if !view.map.free[q as usize] {
                    continue;
                }
                let d = self.cost(a, q, goal);
                if d == FAR {
                    continue;
                }
                let barred = self.costs.as_ref().is_some_and(|c| c[p as usize][h as usize] == BARRED);
                let wrong = barred || ((self.wrong_way[p as usize] >> h) & 1 == 1 && d >= dp);
                let crowd = if self.lanes { self.crowd_ahead(view, q, h) } else { 0 };
                keyed[n] = (d, crowd, u8::from(h != view.heading[a]), self.rng.random::<u32>(), q, wrong);
                n += 1;
            }
        }
        keyed[..n].sort_unstable();
        let mut out = [NONE; 5];
        let mut wrong = 0u8;
        for (i, (o, k)) in out.iter_mut().zip(&keyed[..n]).enumerate() {
            *o = k.4;
            wrong |= u8::from(k.5) << i;
        }
        (out, n as u8, wrong)
    }

    /// Robots on the [`LANE_CELLS`] cells from `q` on in direction `h`, up to a wall.
    fn crowd_ahead(&self, view: &PlanView<'_>, q: u32, h: u8) -> u8 {
        let mut cell = Some(q);
        let mut robots = 0;
        let bit = |bits: &[u64], c: u32| (bits[(c >> 6) as usize] >> (c & 63)) & 1 == 1;
        for _ in 0..LANE_CELLS {
            let Some(c) = cell.filter(|&c| view.map.free[c as usize]) else { break };
            robots += u8::from(bit(&self.occ_bits, c));
            cell = ahead(view.map, c, h);
        }
        robots
    }

    /// A robot's frame: its candidates, reversed when a swap is needed.
    fn frame(&mut self, view: &PlanView<'_>, a: u32) -> Frame {
        let (mut cands, mut n, wrong) = self.candidates(view, a as usize);
        let swap = self.swap_partner(view, a, cands[0]);
        if swap == NONE {
            // Against the lane through a one-cell passage only on the robot's own route:
            // pushed robots stepping aside into the wrong way of an aisle met the robots
            // coming along it head-on, and on MR23-I-10 those meetings froze the aisles
            // between the stations and the shelves.
            let mut kept = 0;
            for i in 0..n as usize {
                if (wrong >> i) & 1 == 0 {
                    cands[kept] = cands[i];
                    kept += 1;
                }
            }
            cands[kept..].fill(NONE);
            n = kept as u8;
        } else {
            // Backing out of a corridor to let a robot pass may go against the lane.
            cands[..n as usize].reverse();
        }
        Frame { agent: a, cands, n, i: 0, swap }
    }

    fn d(&self, view: &PlanView<'_>, a: u32, cell: u32) -> u32 {
        let g = view.goals[a as usize];
        u32::from(self.cost(a as usize, cell, g))
    }

    /// The free neighbours of `cell` that count as ways on in a corridor walk: not `from`,
    /// and not a dead end where a robot stands on its own goal.
    fn ways(&self, view: &PlanView<'_>, cell: u32, from: u32) -> (u32, u32) {
        let (mut n, mut last) = (0, NONE);
        for h in 0..4 {
            let Some(u) = ahead(view.map, cell, h) else { continue };
            if !view.map.free[u as usize] || u == from {
                continue;
            }
            let k = self.occ_now[u as usize];
            if k != NONE && view.goals[k as usize] == u && Self::degree(view, u) == 1 {
                continue;
            }
            n += 1;
            last = u;
        }
        (n, last)
    }

    fn degree(view: &PlanView<'_>, cell: u32) -> u32 {
        (0..4).filter(|&h| ahead(view.map, cell, h).is_some_and(|u| view.map.free[u as usize])).count() as u32
    }

    /// The robot `a` must swap with to reach `best`, if a swap is both needed and possible.
    fn swap_partner(&self, view: &PlanView<'_>, a: u32, best: u32) -> u32 {
        let here = view.loc[a as usize];
        if best == here || best == NONE {
            return NONE;
        }
        let j = self.occ_now[best as usize];
        if j != NONE && self.next[j as usize] == NONE && self.swap_required(view, a, j, here, best) && self.swap_possible(view, best, here) {
            return j;
        }
        // Clearing the way for a robot behind (push and swap).
        for h in 0..4 {
            let Some(u) = ahead(view.map, here, h) else { continue };
            let k = self.occ_now[u as usize];
            if k != NONE && k != a && view.loc[k as usize] != best && self.swap_required(view, k, a, here, best) && self.swap_possible(view, best, here) {
                return k;
            }
        }
        NONE
    }

    /// Whether `pusher` (at `pusher_at`) can only get past `puller` (at `puller_at`) by a
    /// swap: walking the corridor ahead finds no branch before the pusher's way is clear.
    fn swap_required(&self, view: &PlanView<'_>, pusher: u32, puller: u32, pusher_at: u32, puller_at: u32) -> bool {
        let (mut back, mut front) = (pusher_at, puller_at);
        let mut guard = view.map.cells();
        while self.d(view, pusher, front) < self.d(view, pusher, back) && guard > 0 {
            guard -= 1;
            let (n, next) = self.ways(view, front, back);
            if n >= 2 {
                return false;
            }
            if n == 0 {
                break;
            }
            back = front;
            front = next;
        }
        self.d(view, puller, back) < self.d(view, puller, front)
            && (self.d(view, pusher, back) == 0 || self.d(view, pusher, front) < self.d(view, pusher, back))
    }

    /// Whether walking back from `puller_at` away from `pusher_at` finds a branch where
    /// the two can pass.
    fn swap_possible(&self, view: &PlanView<'_>, pusher_at: u32, puller_at: u32) -> bool {
        let (mut back, mut front) = (pusher_at, puller_at);
        let mut guard = view.map.cells();
        while front != pusher_at && guard > 0 {
            guard -= 1;
            let (n, next) = self.ways(view, front, back);
            if n >= 2 {
                return true;
            }
            if n == 0 {
                return false;
            }
            back = front;
            front = next;
        }
        false
    }

    /// Plans robot `root` and those it pushes (the paper's PIBT(a, ⊥)).
    fn push_chain(&mut self, view: &PlanView<'_>, root: u32) {
        let frame = self.frame(view, root);
        self.stack.push(frame);
        // The answer of the frame just popped, for the frame below it.
        let mut answer: Option<bool> = None;
        while let Some(top) = self.stack.len().checked_sub(1) {
            if answer.take() == Some(true) {
                self.pull(view, top);
                self.stack.pop();
                answer = Some(true);
                continue;
            }
            let a = self.stack[top].agent;
            let here = view.loc[a as usize];
            let mut pushed = false;
            while self.stack[top].i < self.stack[top].n {
                let f = &mut self.stack[top];
                let c = f.cands[f.i as usize];
                f.i += 1;
                if self.occ_next[c as usize] != NONE {
                    continue;
                }
                let b = self.occ_now[c as usize];
                // A swap with a robot already planned into this one's cell.
                if b != NONE && b != a && self.next[b as usize] == here {
                    continue;
                }
                self.next[a as usize] = c;
                self.occ_next[c as usize] = a;
                if b != NONE && b != a && self.next[b as usize] == NONE {
                    let frame = self.frame(view, b);
                    self.stack.push(frame);
                    pushed = true;
                    break;
                }
                answer = Some(true);
                break;
            }
            if answer == Some(true) {
                self.pull(view, top);
            }
            if pushed {
                continue;
            }
            if answer.is_none() {
                // Every cell refused: stay, and tell the parent to look elsewhere.
                let p = view.loc[a as usize];
                self.next[a as usize] = p;
                self.occ_next[p as usize] = a;
                answer = Some(false);
            }
            self.stack.pop();
        }
    }
}

impl Pibt {
    /// Makes the joint action valid whatever the plan's cells: a robot going forward into a
    /// cell another one also enters, into the cell of one that stays, or along the edge of
    /// one coming the other way, waits instead; then whoever goes into its cell waits too,
    /// down the chain. Cycles of three or more robots all going forward stay: the rules allow
    /// them. `self.queue` holds the robots that stay.
    #[allow(clippy::needless_range_loop)] // robot `a` indexes several columns at once
    fn settle(&mut self, view: &PlanView<'_>, actions: &mut [Action]) {
        let n = view.loc.len();
        // `occ_next` now marks, per cell, the robot going forward into it.
        for a in 0..n {
            self.occ_next[self.next[a] as usize] = NONE;
        }
        for a in 0..n {
            if actions[a] != Action::F {
                continue;
            }
            let q = ahead(view.map, view.loc[a], view.heading[a]).expect("a planned cell is on the map");
            self.next[a] = q;
            let other = self.occ_next[q as usize];
            if other == NONE {
                self.occ_next[q as usize] = a as u32;
            } else {
                actions[a] = Action::W;
                self.queue.push(a as u32);
            }
        }
        for a in 0..n {
            if actions[a] == Action::F {
                let j = self.occ_now[self.next[a] as usize];
                if j != NONE && actions[j as usize] == Action::F && self.next[j as usize] == view.loc[a] {
                    actions[a] = Action::W;
                    self.queue.push(a as u32);
                }
            } else {
                self.next[a] = view.loc[a];
            }
        }
        while let Some(j) = self.queue.pop() {
            let cell = view.loc[j as usize];
            self.next[j as usize] = cell;
            let i = self.occ_next[cell as usize];
            if i != NONE && i != j && actions[i as usize] == Action::F {
                actions[i as usize] = Action::W;
                self.occ_next[cell as usize] = NONE;
                self.queue.push(i);
            }
        }
    }

    /// After robot `stack[top]` secured its first candidate: the swap partner, if any and
    /// still unplanned, follows into its cell.
    fn pull(&mut self, view: &PlanView<'_>, top: usize) {
        let f = &self.stack[top];
        let (a, swap) = (f.agent, f.swap);
        let here = view.loc[a as usize];
        if f.i == 1 && swap != NONE && self.next[swap as usize] == NONE && self.occ_next[here as usize] == NONE {
            self.next[swap as usize] = here;
            self.occ_next[here as usize] = swap;
        }
    }
}

impl Planner for Pibt {
    fn name(&self) -> &'static str {
        "pibt"
    }

    #[allow(clippy::needless_range_loop)] // robot `a` indexes several columns at once
    fn plan(&mut self, view: &PlanView<'_>, actions: &mut [Action]) {
        let n = view.loc.len();
        self.dist.tick();
        let mut budget = if self.search { SEARCH_CELLS_PER_ROUND } else { 0 };
        if self.lean {
            let grid = |a: usize| {
                let (p, g) = (view.loc[a], view.goals[a]);
                (p / self.cols).abs_diff(g / self.cols) + (p % self.cols).abs_diff(g % self.cols)
            };
            let mut nearest: Vec<usize> = (0..n).filter(|&a| view.goals[a] != NO_GOAL).collect();
            nearest.sort_unstable_by_key(|&a| (grid(a), a));
            for a in nearest {
                self.slot[a] = self.dist.search_within(view.goals[a], &mut budget).unwrap_or(NONE);
            }
        }
        for a in 0..n {
            let g = view.goals[a];
            // A robot in a dead end goes first: it can only leave the way others come in.
            self.bonus[a] = if g != NO_GOAL && self.dist.dead_end(view.loc[a]) { 10 } else { 0 };
            if g == NO_GOAL {
                self.slot[a] = NONE;
            } else if !self.lean {
                self.slot[a] = self.dist.search_within(g, &mut budget).unwrap_or(NONE);
            }
            // The nearer its errand, the sooner a robot goes; one without an errand goes last.
            self.urgency[a] = if g == NO_GOAL { 0 } else { u32::from(FAR) - u32::from(self.cost(a, view.loc[a], g)) };
            self.occ_now[view.loc[a] as usize] = a as u32;
            self.occ_bits[(view.loc[a] >> 6) as usize] |= 1 << (view.loc[a] & 63);
            self.next[a] = NONE;
        }
        // A robot still turning towards the cell it chose keeps it (the Start-Kit's default
        // planner does the same): choosing again would undo the turn.
        for a in 0..n {
            let b = self.bound[a];
            // Under the 2026 rules a plan is played ahead from where robots are predicted to
            // be, which need not be where the last step left them: only a free neighbour binds.
            let near = b != NONE && (0..4).any(|h| ahead(view.map, view.loc[a], h) == Some(b)) && view.map.free[b as usize];
            if near && b != view.loc[a] {
                self.next[a] = b;
                self.occ_next[b as usize] = a as u32;
            }
        }
        let (urgency, tie, bonus) = (&self.urgency, &self.tie, &self.bonus);
        self.order.sort_unstable_by(|&x, &y| {
            let kx = (urgency[x as usize] + bonus[x as usize]) as f32 + tie[x as usize];
            let ky = (urgency[y as usize] + bonus[y as usize]) as f32 + tie[y as usize];
            ky.total_cmp(&kx).then(x.cmp(&y))
        });
        for i in 0..n {
            let a = self.order[i];
            if self.next[a as usize] == NONE {
                self.push_chain(view, a);
            }
        }
        // Cells to actions: a turn keeps the robot in its cell, and so does a wait; then
        // whoever meant to enter the cell of a robot that stays waits too.
        self.queue.clear();
        for a in 0..n {
            let (p, q) = (view.loc[a], self.next[a]);
            actions[a] = if q == p {
                Action::W
            } else {
                let want = heading_to(view.map, p, q);
                let h = view.heading[a];
                if want == h {
                    Action::F
                } else if want == (h + 3) % 4 {
                    Action::C
                } else {
                    Action::R
                }
            };
            self.bound[a] = if q == p { NONE } else { q };
            if actions[a] != Action::F {
                self.queue.push(a as u32);
            }
        }
        self.settle(view, actions);
        for a in 0..n {
            self.occ_now[view.loc[a] as usize] = NONE;
            self.occ_bits[(view.loc[a] >> 6) as usize] &= !(1 << (view.loc[a] & 63));
            self.occ_next[self.next[a] as usize] = NONE;
        }
    }
}
