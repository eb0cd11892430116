//! How a PIBT planner is made: its variant (the guidance its distances follow and how its
//! ties go), the cells whose wrong way it keeps to robots it brings nearer, and its
//! distance tables, built once from the final move costs.

use super::{Pibt, NONE};
use crate::input::lorr::GridMap;
use crate::rules::grid::action::ahead;
use crate::rules::grid::planner::dist::{Distances, BARRED};
use crate::rules::grid::planner::guidance::{highway_costs, lanes_core, open_band_costs, AGAINST};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Which PIBT: the built-in planners `pibt`, `pibt-no-lanes`, `pibt-one-way` and
/// `pibt-no-highways` (`crate::rules::grid::planner::BUILT_INS`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// `pibt`: distances on the highways (`guidance.rs`), ties to the emptier lane.
    Highways,
    /// `pibt-no-lanes`: on the highways, ties straight ahead.
    StraightTies,
    /// `pibt-one-way`: on the highways, ties straight ahead, never against a lane between
    /// cells the lanes connect both ways ([`lanes_core`]) but to back out for a swap,
    /// elsewhere only if the step brings the robot nearer its errand; moves along open
    /// bands a tenth dearer ([`open_band_costs`]).
    OneWay,
    /// `pibt-no-highways`: every move costing the same, ties to the emptier lane.
    NoHighways,
    /// `pibt-grid`: `pibt-no-highways` steering by grid distance alone, with no search of the
    /// map (maps of millions of cells, where a search per errand costs more than it gains).
    Grid,
}

/// The memory the distance tables may take, 2 GB: the budget is 4 GB in all.
const TABLE_BUDGET: usize = 2 << 30;

/// How many distance tables fit [`TABLE_BUDGET`] on `map`, and at least one per robot.
fn table_capacity(map: &GridMap, robots: usize) -> usize {
    let free = map.free.iter().filter(|&&f| f).count().max(1);
    (TABLE_BUDGET / (2 * free)).max(robots + 1)
}

/// The memory a lean planner's tables may take (`Pibt::lean`).
const LEAN_BUDGET: usize = 1 << 30;

impl Pibt {
    /// The same planner, lean on a large map (the 2026 rules' built-in on maps of millions of
    /// cells): its tables take at most 1 GB, not one per robot, and the robots nearest their
    /// errands (by grid distance) get them first, the others steering by grid distance.
    #[must_use]
    pub fn lean(mut self, map: &GridMap) -> Pibt {
        let free = map.free.iter().filter(|&&f| f).count().max(1);
        // At least 8 tables, but never more than robots + 1 (a fleet of 3 needs 4, not 8).
        let capacity = (LEAN_BUDGET / (2 * free)).max(8).min(self.urgency.len() + 1);
        self.dist = match &self.costs {
            Some(costs) => Distances::weighted(map, capacity, |c, h| costs[c as usize][h as usize]),
            None => Distances::new(map, capacity),
        };
        self.lean = true;
        self
    }

    /// A planner of `variant` for `robots` robots on `map`, seeded by `seed`.
    #[must_use]
    pub fn new(map: &GridMap, robots: usize, seed: u64, variant: Variant) -> Pibt {
        match variant {
            Variant::Highways => Pibt::build(map, robots, seed, true, true, false),
            Variant::StraightTies => Pibt::build(map, robots, seed, true, false, false),
            Variant::OneWay => Pibt::build(map, robots, seed, true, false, true),
            Variant::NoHighways => Pibt::build(map, robots, seed, false, true, false),
            Variant::Grid => Pibt { search: false, ..Pibt::build(map, robots, seed, false, true, false) },
        }
    }

    /// A planner whose distances follow the highways if `highways`, whose ties go to the
    /// emptier lane if `lanes`, and that keeps off the wrong way of every lane if `one_way`
    /// (which needs the highways).
    pub(super) fn build(map: &GridMap, robots: usize, seed: u64, highways: bool, lanes: bool, one_way: bool) -> Pibt {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let tie = (0..robots).map(|_| rng.random::<f32>()).collect();
        let mut costs = highways.then(|| highway_costs(map));
        let mut wrong_way = vec![0u8; map.cells()];
        if let Some(costs) = &mut costs {
            for p in 0..map.cells() as u32 {
                if !map.free[p as usize] {
                    continue;
                }
                for h in 0..4u8 {
                    let Some(q) = ahead(map, p, h) else { continue };
                    if !map.free[q as usize] || costs[p as usize][h as usize] != AGAINST {
                        continue;
                    }
                    let side = |c: u32, s: u8| ahead(map, c, s).is_some_and(|u| map.free[u as usize]);
                    let (s1, s2) = ((h + 1) % 4, (h + 3) % 4);
                    // A passage: `q` and the cell after it have walls on both sides.
                    let walled = |c: u32| !side(c, s1) && !side(c, s2);
                    let beyond = ahead(map, q, h).filter(|&u| map.free[u as usize]);
                    let open = !walled(q) || !beyond.is_some_and(walled);
                    if !open {
                        wrong_way[p as usize] |= 1 << h;
                    }
                }
            }
            if one_way {
                keep_one_way(map, costs, &mut wrong_way);
            }
        }
        let capacity = table_capacity(map, robots);
        Pibt {
            dist: match &costs {
                Some(costs) => Distances::weighted(map, capacity, |c, h| costs[c as usize][h as usize]),
                None => Distances::new(map, capacity),
            },
            cols: map.cols,
            rng,
            tie,
            urgency: vec![0; robots],
            slot: vec![NONE; robots],
            order: (0..robots as u32).collect(),
            occ_now: vec![NONE; map.cells()],
            occ_bits: vec![0; map.cells().div_ceil(64)],
            occ_next: vec![NONE; map.cells()],
            next: vec![NONE; robots],
            stack: Vec::new(),
            queue: Vec::new(),
            bound: vec![NONE; robots],
            bonus: vec![0; robots],
            lanes,
            wrong_way,
            costs,
            lean: false,
            search: true,
        }
    }
}

/// `pibt-one-way`'s costs and wrong ways: every step against a lane is kept to robots it
/// brings nearer, moves along open bands cost a tenth more, and a step against the lane
/// between cells of the lanes' core is barred.
fn keep_one_way(map: &GridMap, costs: &mut [[u8; 4]], wrong_way: &mut [u8]) {
    for (bits, cost) in wrong_way.iter_mut().zip(costs.iter()) {
        for (h, &c) in cost.iter().enumerate() {
            if c == AGAINST {
                *bits |= 1 << h;
            }
        }
    }
    open_band_costs(map, costs);
    let core = lanes_core(map, costs);
    for p in (0..map.cells() as u32).filter(|&p| core[p as usize]) {
        for h in 0..4u8 {
            if costs[p as usize][h as usize] == AGAINST && ahead(map, p, h).is_some_and(|q| core[q as usize]) {
                costs[p as usize][h as usize] = BARRED;
            }
        }
    }
}
