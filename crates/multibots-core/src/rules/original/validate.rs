//! What the original can run. Its code has one warehouse, six robots starting at A..F and
//! charging at S..Y, one unloading crossing M, a list of goods handed out in turn, and its
//! numbers written into the code. A scenario asking for anything else is refused with one
//! line that names the field.
//!
//! The scenario's defaults are the paper's numbers; where the original's code differs from
//! them in the letter but not the intent, the default stands for the original's value:
//! `robot.radius = 12.5` (the paper) is the code's `L / 4`, which its integer division makes
//! 12; `collision.margin = 0` (the paper's formula) is the code's `+ 8`. Those fields also
//! accept the code's own values, 12 and 8. No other parameter is honoured: each must keep
//! its default. `step_limit` is honoured as a safety stop, and the `cost` weights do not
//! enter a run.

use super::{MAX_GOODS, RADIUS};
use crate::error::{Error, Result};
use crate::input::scenario::{ChargerUse, ChargingPolicy, Placement, Scenario, Traffic, Unload};
use crate::world::layout::Layout;

/// Most robots: one per start crossing A..F.
const MAX_ROBOTS: u32 = 6;
/// `InitStartGoal`: robot k starts at the k-th of these.
const STARTS: [&str; 6] = ["A", "B", "C", "D", "E", "F"];

/// Checks the scenario; returns its goods, in order.
pub fn check(s: &Scenario) -> Result<Vec<u32>> {
    s.check_values()?;
    // "auto" is the paper's every choice under these rules.
    let resolved = s.resolved(STARTS.len());
    let s = &resolved;
    let refuse = |field: &str, value: String, reason: &str| Err(Error::scenario(field, value, reason));
    if s.layout_generate.is_some() {
        return refuse("layout_generate", "[layout_generate]".into(), "the original rules run only the paper layout");
    }
    if s.layout != "paper" {
        return refuse("layout", format!("\"{}\"", s.layout), "the original rules run only the paper layout");
    }
    if s.allocator != "in-turn" {
        return refuse("allocator", format!("\"{}\"", s.allocator), "the original rules hand out goods in turn only (\"in-turn\")");
    }
    if s.orders.is_some() {
        return refuse("orders", "[orders]".into(), "the original rules fetch a fixed task list (no lifelong orders)");
    }
    if s.placement == Placement::Spread {
        return refuse("placement", "\"spread\"".into(), "the original rules start robot k at the k-th of A..F");
    }
    if s.charging.chargers == ChargerUse::Shared {
        return refuse("charging.chargers", "\"shared\"".into(), "the original rules charge every robot at its own charger");
    }
    if s.charging.policy != ChargingPolicy::Threshold {
        let policy = if s.charging.policy == ChargingPolicy::Staggered { "\"staggered\"" } else { "\"opportunistic\"" };
        return refuse("charging.policy", policy.into(), "the original rules charge by the threshold rule only");
    }
    if s.robots > MAX_ROBOTS {
        return refuse("robots", s.robots.to_string(), "the original rules run at most 6 robots (one per start A..F)");
    }
    if let Some(starts) = &s.starts {
        if starts.iter().map(String::as_str).ne(STARTS[..s.robots as usize].iter().copied()) {
            return refuse("starts", format!("{starts:?}"), "the original rules start robot k at the k-th of A..F");
        }
    }
    if s.traffic != Traffic::Wait {
        return refuse("traffic", format!("\"{}\"", s.traffic.as_str()), "the original rules have their own collision rule");
    }
    if !matches!(&s.unload, Unload::First) && s.unload != Unload::Node("M".into()) {
        return refuse("unload", format!("\"{}\"", s.unload.as_str()), "the original rules unload at M");
    }
    let r = &s.robot;
    if r.radius != 12.5 && r.radius != RADIUS {
        return refuse("robot.radius", r.radius.to_string(), "the original rules use the code's radius L/4 = 12 px (leave the default 12.5, or give 12)");
    }
    let fixed = [
        ("robot.speed", r.speed, 4.0, "the original rules move 4 px a tick"),
        ("robot.energy_full", r.energy_full, 10.0, "the original rules use full energy 10"),
        ("robot.threshold", r.threshold, 3.5, "the original rules use the threshold 3.5"),
        ("robot.consumption", r.consumption, 0.005, "the original rules use 0.005 a tick"),
        ("robot.charge_rate", r.charge_rate, 0.05, "the original rules charge 0.05 a tick"),
        ("collision.angle", s.collision.angle, 30.0, "the original rules use a 30° cone"),
    ];
    for (field, value, original, reason) in fixed {
        if value != original {
            return refuse(field, value.to_string(), reason);
        }
    }
    if s.collision.margin != 0.0 && s.collision.margin != 8.0 {
        return refuse("collision.margin", s.collision.margin.to_string(), "the original rules touch at r_i + r_j + 8 (leave the default 0, or give 8)");
    }
    if s.dwell.loading != 10 {
        return refuse("dwell.loading", s.dwell.loading.to_string(), "the original rules load for 10 ticks");
    }
    if s.dwell.unloading != 20 {
        return refuse("dwell.unloading", s.dwell.unloading.to_string(), "the original rules unload for 20 ticks");
    }
    let cells = s.cells(Layout::paper().cells.len())?;
    if cells.len() < s.robots as usize {
        return refuse("tasks", format!("{} goods", cells.len()), &format!("the original rules need at least one goods per robot ({} robots)", s.robots));
    }
    if cells.len() > MAX_GOODS {
        return refuse("tasks", format!("{} goods", cells.len()), "the original rules deliver at most 50 goods (the code's cart has 50 boxes)");
    }
    Ok(cells)
}
