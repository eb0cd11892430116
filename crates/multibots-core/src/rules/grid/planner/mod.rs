//! Planners: each step a planner reads where every robot is, which way it faces and its next
//! errand, and proposes one action per robot. A planner plugs in as allocators do: the
//! [`Planner`] trait, and [`built_in`] maps the names the command line and Python use.
//! The rules check what it proposes; a planner may be wrong, and its error costs a step of
//! waiting for every robot.
//!
//! | name | what it does |
//! | --- | --- |
//! | `auto` (the default) | `pibt-one-way`, or `pibt` when robots take more than [`CROWDED`] of the free cells ([`auto_choice`]) |
//! | `pibt` | PIBT with rotations (Okumura et al. 2022), `pibt.rs`, on highways (`guidance.rs`) |
//! | `pibt-no-lanes` | the same PIBT on highways, ties going straight ahead, not to the emptier lane |
//! | `pibt-one-way` | `pibt-no-lanes`, never against a lane where the lanes go round (`guidance::lanes_core`; a swap may back out), elsewhere only if that brings the robot nearer; open bands crossed, not travelled along (`guidance::open_band_costs`) |
//! | `pibt-no-highways` | the same PIBT, every move costing the same |
//! | `pibt-grid` | `pibt-no-highways` steering by grid distance alone, no search of the map (the 2026 rules' `auto` on maps of over [`HUGE`] free cells) |
//! | `rpibt` | PIBT on actions, distances counting turns (`lookahead.rs`) |
//! | `rpibt-pp` | `rpibt`, each robot first trying the next cell of a path planned a few steps ahead round the robots before it in priority (`window.rs`); on highways whose against-the-lane cost grows with robots per free cell (`Lookahead::on_highways_by_density`) |
//! | `lookahead` | `rpibt` played several times a few steps ahead, the best first step kept (`lookahead.rs`) |

mod dist;
mod guidance;
mod lookahead;
mod pibt;
mod window;

pub use dist::{Distances, BARRED, FAR};
pub use guidance::{highway_costs, lanes_core, open_band_costs, AGAINST, WITH};
pub use lookahead::Lookahead;
pub use pibt::{Pibt, Variant};

use super::action::Action;
use crate::error::{Error, Result};
use crate::input::lorr::GridMap;

/// "No errand" in [`PlanView::goals`].
pub const NO_GOAL: u32 = u32::MAX;

/// What a planner sees at a step.
pub struct PlanView<'a> {
    /// The grid.
    pub map: &'a GridMap,
    /// Each robot's cell.
    pub loc: &'a [u32],
    /// Each robot's heading (0 east, 1 south, 2 west, 3 north).
    pub heading: &'a [u8],
    /// Each robot's next errand, or [`NO_GOAL`].
    pub goals: &'a [u32],
    /// The current step.
    pub t: u32,
    /// The 2024 rules' tasks, where a planner may read them (a Python planner's
    /// `SharedEnvironment` shows them); `None` under the 2023 rules and in rollouts.
    pub tasks: Option<TaskView<'a>>,
}

/// The tasks a planner may see under the 2024 rules.
#[derive(Clone, Copy)]
pub struct TaskView<'a> {
    /// The pool and the schedule in force.
    pub pool: &'a crate::rules::grid::pool::TaskPool,
    /// The schedule proposed this step.
    pub proposal: &'a [i64],
    /// The task file's lines.
    pub lines: &'a [Vec<u32>],
}

/// A planner: one action per robot per step.
pub trait Planner: Send + Sync {
    /// The planner's name, as [`built_in`] knows it.
    fn name(&self) -> &'static str;
    /// Fills `actions` (one per robot) for the step from `view`.
    fn plan(&mut self, view: &PlanView<'_>, actions: &mut [Action]);
    /// Why the last call failed, if it did (a Python planner that raised): the run then stops
    /// with this error. Built-in planners never fail.
    fn failure(&mut self) -> Option<crate::error::Error> {
        None
    }
}

/// A built-in planner: its name (the same on the command line, in Python and in a replay's
/// header), one line on what it does (the command line's help), and how it is made for a
/// map, a fleet and a seed.
pub struct BuiltIn {
    pub name: &'static str,
    pub about: &'static str,
    make: fn(&GridMap, usize, u64) -> Box<dyn Planner>,
}

/// The built-in planners; the first is the default.
pub const BUILT_INS: &[BuiltIn] = &[
    BuiltIn {
        name: "auto",
        about: "pibt-one-way, or pibt when robots fill more than 30 % of the free cells",
        make: |map, robots, seed| make(auto_choice(map, robots), map, robots, seed),
    },
    BuiltIn {
        name: "pibt",
        about: "PIBT with rotations on highways, ties to the emptier lane",
        make: |m, r, s| Box::new(Pibt::new(m, r, s, Variant::Highways)),
    },
    BuiltIn { name: "pibt-no-lanes", about: "pibt, ties going straight ahead", make: |m, r, s| Box::new(Pibt::new(m, r, s, Variant::StraightTies)) },
    BuiltIn {
        name: "pibt-one-way",
        about: "pibt-no-lanes, never against a lane where the lanes go round",
        make: |m, r, s| Box::new(Pibt::new(m, r, s, Variant::OneWay)),
    },
    BuiltIn { name: "pibt-no-highways", about: "pibt, every move costing the same", make: |m, r, s| Box::new(Pibt::new(m, r, s, Variant::NoHighways)) },
    BuiltIn {
        name: "pibt-grid",
        about: "pibt-no-highways by grid distance alone (maps of millions of cells)",
        make: |m, r, s| Box::new(Pibt::new(m, r, s, Variant::Grid)),
    },
    BuiltIn { name: "rpibt", about: "PIBT on actions, distances counting turns", make: |m, r, s| Box::new(Lookahead::new(m, r, s, 0)) },
    BuiltIn {
        name: "rpibt-pp",
        about: "rpibt following paths planned a few steps ahead (small maps)",
        make: |m, r, s| Box::new(Lookahead::new(m, r, s, 0).guided(m.cells()).on_highways_by_density(m, r)),
    },
    BuiltIn {
        name: "lookahead",
        about: "rpibt played a few steps ahead, the best first step kept",
        make: |m, r, s| Box::new(Lookahead::new(m, r, s, lookahead::ROLLOUTS)),
    },
];

/// The built-in planners' names.
pub fn names() -> impl Iterator<Item = &'static str> {
    BUILT_INS.iter().map(|b| b.name)
}

/// The share of free cells above which `auto` takes `pibt`: a fleet that fills a third of
/// the floor needs robots to make way against the lanes, which `pibt-one-way` forbids where
/// the lanes go round.
pub const CROWDED: f64 = 0.3;

/// The planner `auto` runs on `map` with `robots` robots.
///
/// Measured on the League's archive (docs/lorr.md, docs/benchmarks.md): `pibt-one-way` is
/// ahead of `pibt` or level on every warehouse, sortation, city and game instance, a lot on
/// some (MR23-I-10 153,375 against 104,167 at 0.26 robots per free cell), but for MR24-WAREHOUSE
/// (133,138 against 134,150), MR24-CITY-01 (7,227 against 7,255) and TR23-warehouse_large
/// (19,900 against 19,946); on the 32×32 random maps it is behind on four of six below 0.3
/// (RANDOM-02, 0.24: 451 against 476) and far behind as they fill (0.49: 516 against 599;
/// 0.98: 177 against 848). Density alone cannot separate these (MR23-I-10 at 0.26 needs
/// `pibt-one-way`, RANDOM-02 at 0.24 `pibt`); the line is drawn where the losses grow. On
/// `warehouse_small` (2023 example instances, 0.31 and 0.63) `auto` takes `pibt`, level and
/// 3.6 % behind `pibt-one-way`.
#[must_use]
pub fn auto_choice(map: &GridMap, robots: usize) -> &'static str {
    let free = map.free.iter().filter(|&&f| f).count().max(1);
    if robots as f64 > CROWDED * free as f64 {
        "pibt"
    } else {
        "pibt-one-way"
    }
}

/// Free cells above which the 2026 rules' `auto` steers by grid distance (`pibt-grid`).
pub const HUGE: usize = 400_000;
/// Free cells up to which the 2026 rules' `auto` plans on actions (`rpibt-pp`).
pub const SMALL: usize = 20_000;

/// Robots per free cell from which the 2026 rules' `auto` plays `pibt` (highways) rather than
/// `pibt-no-highways` on a mid-sized map, in percent.
pub const LANES_FROM_PERCENT: usize = 5;

/// The planner `auto` plays under the 2026 rules, by the map's free cells and the fleet:
/// `rpibt-pp` up to [`SMALL`] free cells (its tables count turns, which take as long as moves
/// there); up to [`HUGE`], `pibt` where robots take at least [`LANES_FROM_PERCENT`] % of the free
/// cells (lanes pay in a dense warehouse: 1,555 tasks against 891 on `fulfill-example_2500`)
/// and `pibt-no-highways` where they are sparser (the same tasks in a sixth of the time on the
/// city and game maps); `pibt-grid` beyond (a search per errand of a map of millions of cells
/// costs more than it gains in a run of 500 ticks). Measured in `docs/lorr.md`.
#[must_use]
pub fn auto_choice_2026(map: &GridMap, robots: usize) -> &'static str {
    let free = map.free.iter().filter(|&&f| f).count();
    if free <= SMALL {
        "rpibt-pp"
    } else if free > HUGE {
        "pibt-grid"
    } else if robots * 100 >= free * LANES_FROM_PERCENT {
        "pibt"
    } else {
        "pibt-no-highways"
    }
}

/// A built-in planner by name, for `map`, seeded by `seed`.
pub fn built_in(name: &str, map: &GridMap, robots: usize, seed: u64) -> Result<Box<dyn Planner>> {
    match BUILT_INS.iter().find(|b| b.name == name) {
        Some(b) => Ok((b.make)(map, robots, seed)),
        None => Err(Error::scenario("planner", name, format!("is not a planner; the built-in ones are {}", names().collect::<Vec<_>>().join(", ")))),
    }
}

/// A built-in planner by name as the 2026 rules' built-in plays it: the PIBT planners lean
/// ([`Pibt::lean`]: tables within 1 GB, searched for the robots nearest their errands first),
/// the others as [`built_in`] makes them.
pub fn built_in_lean(name: &str, map: &GridMap, robots: usize, seed: u64) -> Result<Box<dyn Planner>> {
    let variant = match name {
        "pibt" => Variant::Highways,
        "pibt-no-lanes" => Variant::StraightTies,
        "pibt-one-way" => Variant::OneWay,
        "pibt-no-highways" => Variant::NoHighways,
        "pibt-grid" => Variant::Grid,
        _ => return built_in(name, map, robots, seed),
    };
    Ok(Box::new(Pibt::new(map, robots, seed, variant).lean(map)))
}

fn make(name: &str, map: &GridMap, robots: usize, seed: u64) -> Box<dyn Planner> {
    built_in(name, map, robots, seed).expect("a built-in name")
}
