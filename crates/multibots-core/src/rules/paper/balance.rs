//! The energy balance, before a run: whether the chargers can keep the fleet charged at all.
//!
//! A robot working draws `robot.consumption` a step from `energy_full` down to the threshold:
//! `work = (energy_full − threshold) / consumption` steps. It then holds a charger for the
//! drive there and the charge back to full: `charge = (energy_full − threshold) / charge_rate`
//! steps, and `drive` steps of the fleet's mean route to its nearest charger at
//! `robot.speed` (every crossing weighed alike, as spread placement spreads the fleet). So
//! each robot holds a charger `(drive + charge) / (work + drive + charge)` of the time, and a
//! fleet sharing fewer chargers than `robots` times that runs down and strands, however well
//! it is run (an untuned 200-robot warehouse with 12 chargers, which it needs 43 of: every
//! robot out of energy from step 2,005). Robots with their own charger always have one. The
//! scenario is warned, with the numbers and what would make it balance. It is a bound, not
//! a forecast: the drive is to the nearest charger, without queues or detours (in that
//! warehouse with 40 chargers on every wall, above the bound of 13 for 100 robots, the
//! trips to a free charger took 440 steps, not 66, and the fleet still stranded: the run's
//! own report then says so).

use crate::input::layout_params::ChargerWalls;
use crate::input::scenario::{ChargerUse, Scenario};
use crate::world::layout::NodeKind;
use crate::world::World;

/// A shared-charger fleet's charging, by the arithmetic above: steps working on a charge,
/// driving to a charger and charging, and the chargers kept busy on average.
struct Balance {
    work: f64,
    drive: f64,
    charge: f64,
    needed: f64,
}

fn balance(scenario: &Scenario, world: &World) -> Balance {
    let r = &scenario.robot;
    let span = r.energy_full - r.threshold;
    let (work, charge) = (span / r.consumption, span / r.charge_rate);
    let layout = &world.layout;
    let to: Vec<Vec<f64>> = layout.chargers.iter().map(|&c| world.graph.lengths_to(c)).collect();
    let highway: Vec<usize> = (0..layout.nodes.len()).filter(|&u| layout.nodes[u].kind == NodeKind::Highway).collect();
    let mean = highway.iter().map(|&u| to.iter().map(|l| l[u]).fold(f64::INFINITY, f64::min)).sum::<f64>() / highway.len().max(1) as f64;
    let drive = if mean.is_finite() { mean / r.speed } else { 0.0 };
    Balance { work, drive, charge, needed: f64::from(scenario.robots) * (drive + charge) / (work + drive + charge) }
}

/// A figure as a message shows it: three significant digits.
fn figure(v: f64) -> String {
    let digits = (2 - v.abs().max(1e-12).log10().floor() as i32).max(0) as usize;
    let text = format!("{v:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// One line per way the scenario's fleet cannot be kept charged (none when it can), for a
/// scenario whose "auto" choices are made.
#[must_use]
pub(crate) fn warnings(scenario: &Scenario, world: &World) -> Vec<String> {
    let chargers = world.layout.chargers.len();
    if scenario.charging.chargers != ChargerUse::Shared || chargers == 0 {
        return Vec::new();
    }
    let b = balance(scenario, world);
    if (chargers as f64) >= b.needed {
        return Vec::new();
    }
    let r = &scenario.robot;
    let share = b.needed / f64::from(scenario.robots);
    let most_robots = (chargers as f64 / share).floor();
    let more = match &scenario.layout_generate {
        Some(g) if g.charger_walls != ChargerWalls::All => {
            format!("at least {} chargers (layout_generate.chargers, with charger_walls = \"all\" to bring them nearer)", b.needed.ceil())
        }
        Some(_) => format!("at least {} chargers (layout_generate.chargers)", b.needed.ceil()),
        None => format!("a layout with at least {} chargers", b.needed.ceil()),
    };
    vec![format!(
        "charging: {} robots sharing {chargers} chargers keep at least {} of them busy (each holds one {}% of the time: {} \
         steps working on a charge at robot.consumption {}, then about {} steps driving to the nearest charger and {} \
         charging at robot.charge_rate {}; queues and detours add to it): the fleet cannot be kept charged and will strand; \
         give it {more}, or at most {most_robots} robots, or a lower robot.consumption",
        scenario.robots,
        figure(b.needed),
        figure(100.0 * share),
        figure(b.work),
        crate::error::number(r.consumption),
        figure(b.drive),
        figure(b.charge),
        crate::error::number(r.charge_rate),
    )]
}
