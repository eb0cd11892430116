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
//! | `rpibt` | PIBT on actions, distances counting turns (`lookahead.rs`) |
//! | `rpibt-pp` | `rpibt`, each robot first trying the next cell of a path planned a few steps ahead round the robots before it in priority (`window.rs`); on highways whose against-the-lane cost grows with robots per free cell (`Lookahead::on_highways_by_density`) |
//! | `lookahead` | `rpibt` played several times a few steps ahead, the best first step kept (`lookahead.rs`) |

mod dist;
mod guidance;
mod lookahead;
mod pibt;
mod window;

pub use dist::{Distances, BARRED};
pub use guidance::{highway_costs, lanes_core, open_band_costs, AGAINST, WITH};
pub use lookahead::Lookahead;
pub use pibt::Pibt;

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
}

/// A planner: one action per robot per step.
pub trait Planner: Send + Sync {
    /// The planner's name, as [`built_in`] knows it.
    fn name(&self) -> &'static str;
    /// Fills `actions` (one per robot) for the step from `view`.
    fn plan(&mut self, view: &PlanView<'_>, actions: &mut [Action]);
}

/// The built-in planners, by name.
pub const BUILT_INS: &[&str] = &["auto", "pibt", "pibt-no-lanes", "pibt-one-way", "pibt-no-highways", "rpibt", "rpibt-pp", "lookahead"];

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

/// A built-in planner by name, for `map`, seeded by `seed`.
pub fn built_in(name: &str, map: &GridMap, robots: usize, seed: u64) -> Result<Box<dyn Planner>> {
    match name {
        "auto" => built_in(auto_choice(map, robots), map, robots, seed),
        "pibt" => Ok(Box::new(Pibt::new(map, robots, seed, true, true))),
        "pibt-no-lanes" => Ok(Box::new(Pibt::new(map, robots, seed, true, false))),
        "pibt-one-way" => Ok(Box::new(Pibt::new(map, robots, seed, true, false).one_way(map))),
        "pibt-no-highways" => Ok(Box::new(Pibt::new(map, robots, seed, false, true))),
        "rpibt" => Ok(Box::new(Lookahead::new(map, robots, seed, 0))),
        "rpibt-pp" => Ok(Box::new(Lookahead::new(map, robots, seed, 0).guided(map.cells()).on_highways_by_density(map, robots))),
        "lookahead" => Ok(Box::new(Lookahead::new(map, robots, seed, lookahead::ROLLOUTS))),
        _ => Err(Error::scenario("planner", name, format!("is not a planner; the built-in ones are {}", BUILT_INS.join(", ")))),
    }
}
