//! Planners: each step a planner reads where every robot is, which way it faces and its next
//! errand, and proposes one action per robot. A planner plugs in as allocators do: the
//! [`Planner`] trait, and [`built_in`] maps the names the command line and Python use.
//! The rules check what it proposes; a planner may be wrong, and its error costs a step of
//! waiting for every robot.
//!
//! | name | what it does |
//! | --- | --- |
//! | `auto` (the default) | on maps of at most [`SMALL_2024`] free cells `rpibt-pp`, or `pibt-no-lanes` from [`JAMMED`] robots per free cell; on larger ones `pibt-one-way`, or `pibt` when robots take more than [`CROWDED`] of the free cells ([`auto_choice`]) |
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
pub use guidance::{highway_costs, lanes_core, obstacles_in_blocks, open_band_costs, AGAINST, WITH};
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
        about: "small maps: rpibt-pp (pibt-no-lanes from 90 % of the free cells taken); else pibt-one-way (pibt above 30 %)",
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
        make: |m, r, s| Box::new(Lookahead::new(m, r, s, 0).guided(m.cells()).on_highways_by_density(m, r, true).prepared(m)),
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

/// The share of free cells above which `auto` takes `pibt` on a map of more than
/// [`SMALL_2024`] free cells: a fleet that fills a third of the floor needs robots to make way
/// against the lanes, which `pibt-one-way` forbids where the lanes go round.
pub const CROWDED: f64 = 0.3;

/// Free cells up to which the 2023 and 2024 rules' `auto` plans on actions (`rpibt-pp`): the
/// archive's small maps have 820 (`random-32-32-20`) to 1,564 (`sortation_small`) free cells,
/// its next map 21,920 (`sortation_medium`). On small maps every errand's table is made before
/// the first step ([`Lookahead::prepared`]) and a step takes at most a few tens of ms with
/// 800 robots; on large ones a step with a few hundred robots took 40 ms on average
/// (`brc202d_500`) for a gain of 1-3 % over `pibt-one-way`.
pub const SMALL_2024: usize = 2_000;

/// Robots per free cell from which `auto` on a small map plays `pibt-no-lanes` rather than
/// `rpibt-pp`: nearly every cell is taken, and PIBT's chains of robots making way beat paths
/// planned ahead, which have nowhere to go (measured on the 32×32 random map: at 0.85 robots
/// per free cell `rpibt-pp` finishes 637 against `pibt`'s 565, at 0.98 734 against
/// `pibt-no-lanes`' 896).
pub const JAMMED: f64 = 0.9;

/// The planner `auto` runs on `map` with `robots` robots under the 2023 and 2024 rules, from
/// the map's free cells and robots per free cell alone (never its name or orientation).
///
/// On a map of at most [`SMALL_2024`] free cells, `rpibt-pp`, or `pibt-no-lanes` from
/// [`JAMMED`] robots per free cell. Measured on the archive's small maps (docs/benchmarks.md):
/// `rpibt-pp` is the best of the planners that keep to 60 ms a step on every 32×32 random
/// instance below 0.9 robots per free cell (MR24-RANDOM-01 632 against `pibt-one-way`'s 397,
/// MR24-RANDOM-03 948 against `pibt`'s 599) and on `warehouse_small` (400 robots: 37,148
/// against `pibt-no-lanes`' 28,737); at 0.98 `pibt-no-lanes` finishes 896 (MR24-RANDOM-05)
/// and 2,908 (MR23-I-08), within 5 % of the best of the others (`lookahead` does better,
/// 966 and 3,317, but takes 90 ms a step).
///
/// On larger maps, `pibt-one-way`, or `pibt` when robots take more than [`CROWDED`] of the
/// free cells. `pibt-one-way` is ahead of `pibt` or level on every warehouse, sortation, city
/// and game instance, a lot on some (MR23-I-10 153,375 against 104,167 at 0.26 robots per
/// free cell), but for MR24-WAREHOUSE (133,138 against 134,150), MR24-CITY-01 (7,227 against
/// 7,255) and TR23-warehouse_large (19,900 against 19,946).
///
/// [`Lookahead::prepared`]: lookahead::Lookahead::prepared
#[must_use]
pub fn auto_choice(map: &GridMap, robots: usize) -> &'static str {
    let free = map.free.iter().filter(|&&f| f).count().max(1);
    let rho = robots as f64 / free as f64;
    if free <= SMALL_2024 {
        if rho >= JAMMED {
            "pibt-no-lanes"
        } else {
            "rpibt-pp"
        }
    } else if rho > CROWDED {
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
/// `rpibt-pp` without the lanes' floor between blocks ([`Lookahead::on_highways_by_density`]),
/// the others as [`built_in`] makes them.
pub fn built_in_lean(name: &str, map: &GridMap, robots: usize, seed: u64) -> Result<Box<dyn Planner>> {
    if name == "rpibt-pp" {
        return Ok(Box::new(Lookahead::new(map, robots, seed, 0).guided(map.cells()).on_highways_by_density(map, robots, false).prepared(map)));
    }
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
