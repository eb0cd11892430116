//! Planners: each step a planner reads where every robot is, which way it faces and its next
//! errand, and proposes one action per robot. A planner plugs in as allocators do: the
//! [`Planner`] trait, and [`built_in`] maps the names the command line and Python use.
//! The rules check what it proposes; a planner may be wrong, and its error costs a step of
//! waiting for every robot.
//!
//! | name | what it does |
//! | --- | --- |
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
pub const BUILT_INS: &[&str] = &["pibt", "pibt-no-lanes", "pibt-one-way", "pibt-no-highways", "rpibt", "rpibt-pp", "lookahead"];

/// A built-in planner by name, for `map`, seeded by `seed`.
pub fn built_in(name: &str, map: &GridMap, robots: usize, seed: u64) -> Result<Box<dyn Planner>> {
    match name {
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
