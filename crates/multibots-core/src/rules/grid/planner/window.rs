//! Windowed prioritized planning, as guidance for `rpibt` (planner `rpibt-pp`): robots in
//! order of priority each search a path over (cell, heading, step) for the next
//! [`HORIZON`] steps that avoids the cells and moves of the robots searched before them
//! (a space-time reservation table), by A* on the turn-counting distances (costs on the
//! highways when the tables have them). Only the first
//! step of each path is used: it is the cell PIBT tries first for that robot (and the turn
//! or wait it makes if that cell is its own). PIBT still plans everyone, so the joint action
//! is valid whatever the paths; they only steer robots round the ones ahead of them in
//! priority before they meet, which PIBT, looking one step ahead, cannot.

use super::lookahead::Tables;
use crate::rules::grid::action::Action;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

const NONE: u32 = u32::MAX;

/// Steps each path looks ahead. Measured with spread, seeds 0 and 1, MR24-RANDOM-01 to 04
/// summed: 8 steps 2,851 (seed 0), 12 steps 2,989 and 2,863, 16 steps 3,081 and 3,014, 20
/// steps 3,038 (seed 0) at twice the time of 16.
pub const HORIZON: usize = 16;
/// States one search may expand before it gives up (the robot is then not guided).
const EXPANSIONS: usize = 3_000;

/// The reservation table and the search's buffers.
pub struct Window {
    cells: usize,
    /// Per step 0..=HORIZON and cell, the robot there, or `NONE`.
    at: Vec<u32>,
    touched: Vec<usize>,
    /// Per state (step, cell, heading): the stamp of the search that reached it, and its
    /// parent state.
    seen: Vec<u32>,
    parent: Vec<u32>,
    stamp: u32,
    heap: BinaryHeap<(Reverse<u32>, u32, u32, u32)>,
    path: Vec<u32>,
}

impl Window {
    /// Buffers for a map of `cells` cells.
    pub fn new(cells: usize) -> Window {
        let states = (HORIZON + 1) * cells * 4;
        Window {
            cells,
            at: vec![NONE; (HORIZON + 1) * cells],
            touched: Vec::new(),
            seen: vec![0; states],
            parent: vec![NONE; states],
            stamp: 0,
            heap: BinaryHeap::new(),
            path: Vec::new(),
        }
    }

    fn reserve(&mut self, t: usize, cell: u32, a: u32) {
        let i = t * self.cells + cell as usize;
        self.at[i] = a;
        self.touched.push(i);
    }

    /// Fills `guide` (the cell each robot should be in after the step, or `NONE`) and
    /// `turn` (the action it makes if that cell is its own) for robots in `order`.
    #[allow(clippy::too_many_arguments)]
    pub fn plan(&mut self, tables: &Tables, loc: &[u32], heading: &[u8], goals: &[u32], no_goal: u32, order: &[u32], guide: &mut [u32], turn: &mut [Action]) {
        for &i in &self.touched {
            self.at[i] = NONE;
        }
        self.touched.clear();
        // Every robot holds its cell at step 0; robots without an errand hold it throughout.
        for (a, &p) in loc.iter().enumerate() {
            self.reserve(0, p, a as u32);
            if goals[a] == no_goal {
                for t in 1..=HORIZON {
                    self.reserve(t, p, a as u32);
                }
            }
        }
        for &a in order {
            let a = a as usize;
            guide[a] = NONE;
            if goals[a] == no_goal {
                continue;
            }
            if self.search(tables, loc[a], heading[a], goals[a], a as u32) {
                // `self.path` holds the states from the last to the first after the start.
                let mut prev = loc[a] * 4 + u32::from(heading[a]);
                let mut t = 0;
                let path = std::mem::take(&mut self.path);
                for &s in path.iter().rev() {
                    t += 1;
                    self.reserve(t, s / 4, a as u32);
                    if t == 1 {
                        guide[a] = s / 4;
                        turn[a] = if s == prev {
                            Action::W
                        } else if s / 4 != prev / 4 {
                            Action::F
                        } else if s % 4 == (prev % 4 + 1) % 4 {
                            Action::R
                        } else {
                            Action::C
                        };
                    }
                    prev = s;
                }
                self.path = path;
                // At its errand before the horizon: it stays there.
                for t in t + 1..=HORIZON {
                    self.reserve(t, prev / 4, a as u32);
                }
            }
        }
    }

    /// A* from (p, h) at step 0; `self.path` gets the states after the start, last first.
    fn search(&mut self, tables: &Tables, p: u32, h: u8, goal: u32, a: u32) -> bool {
        let dist = tables.get(goal);
        let cells4 = self.cells * 4;
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.seen.fill(0);
            self.stamp = 1;
        }
        self.heap.clear();
        let start = p * 4 + u32::from(h);
        self.seen[start as usize] = self.stamp;
        self.parent[start as usize] = NONE;
        // Key: f, then the later step first, the cost so far; the state index (step · cells · 4 + cell · 4 + heading).
        self.heap.push((Reverse(u32::from(dist[start as usize])), 0, 0, start));
        let mut expanded = 0;
        while let Some((_, t, g, s)) = self.heap.pop() {
            let (t, local) = (t as usize, s % cells4 as u32);
            let (c, hd) = (local / 4, (local % 4) as u8);
            if c == goal || t == HORIZON {
                if t == 0 {
                    return false;
                }
                self.path.clear();
                let mut x = s;
                while self.parent[x as usize] != NONE {
                    self.path.push(x % cells4 as u32);
                    x = self.parent[x as usize];
                }
                return true;
            }
            expanded += 1;
            if expanded > EXPANSIONS {
                return false;
            }
            let ahead = tables.next[c as usize][hd as usize];
            let moves = [(ahead, hd), (c, (hd + 1) % 4), (c, (hd + 3) % 4), (c, hd)];
            for (v, nh) in moves {
                if v == NONE {
                    continue;
                }
                let t1 = t + 1;
                let other = self.at[t1 * self.cells + v as usize];
                if other != NONE && other != a {
                    continue;
                }
                // A swap: the robot at v now is at c next.
                if v != c {
                    let k = self.at[t * self.cells + v as usize];
                    if k != NONE && k != a && self.at[t1 * self.cells + c as usize] == k {
                        continue;
                    }
                }
                let ns = (t1 * cells4) as u32 + v * 4 + u32::from(nh);
                if self.seen[ns as usize] == self.stamp {
                    continue;
                }
                let hv = dist[(v * 4 + u32::from(nh)) as usize];
                if hv == u16::MAX {
                    continue;
                }
                self.seen[ns as usize] = self.stamp;
                self.parent[ns as usize] = (t * cells4) as u32 + c * 4 + u32::from(hd);
                // Reaching the goal ends the path; at the horizon the rest counts as its distance.
                let g1 = g + if v == c { tables.unit } else { tables.forward(c, hd) };
                self.heap.push((Reverse(g1 + u32::from(hv)), t1 as u32, g1, ns));
            }
        }
        false
    }
}
