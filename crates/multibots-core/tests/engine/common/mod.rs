//! Shared by the integration tests.

#![allow(dead_code)]

#[allow(unused_imports)] // not every test binary uses it
pub use multibots_core::input::scenario::PAPER_TASKS;

use multibots_core::input::layout_params::Aisles;
use multibots_core::input::scenario::{ChargerUse, Orders, Placement, Tasks};
use multibots_core::{LayoutParams, Scenario, Traffic, Unload};

/// A lifelong run on a generated warehouse of `rows` × `cols` groups: robots parked along
/// the aisles, shared chargers, the nearest unloading zone and robot, Poisson orders at
/// `rate` for `steps` steps.
#[allow(clippy::too_many_arguments)]
pub fn lifelong(rows: u32, cols: u32, unloading_rows: u32, chargers: u32, aisles: Aisles, robots: u32, rate: f64, steps: u64, traffic: Traffic) -> Scenario {
    let mut s = Scenario::paper(robots, &[]);
    s.layout_generate = Some(LayoutParams { group_rows: rows, group_cols: cols, chargers, unloading_rows, aisles, ..LayoutParams::paper() });
    s.placement = Placement::Spread;
    s.charging.chargers = ChargerUse::Shared;
    s.unload = Unload::Nearest;
    s.allocator = "nearest".into();
    s.traffic = traffic;
    s.robot.consumption = 0.0002;
    s.tasks = Tasks::Cells(vec![]);
    s.orders = Some(Orders { rate, horizon: steps, restock: 50, seed: u64::from(robots), csv: None });
    s
}
