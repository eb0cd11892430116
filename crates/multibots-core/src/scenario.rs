//! The scenario schema: the one definition of every field, its default and its checks.
//! TOML files, Python dictionaries and the command line all land here.

use crate::error::{Error, Result};
use crate::layout::{Layout, LayoutParams};
use rand::{Rng, SeedableRng};
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::fmt;

/// A whole run: layout, fleet, tasks and model parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// The warehouse layout. Default: `"paper"`.
    #[serde(default = "defaults::layout")]
    pub layout: String,
    /// Number of robots, N ≥ 1. Default: 3.
    #[serde(default = "defaults::robots")]
    pub robots: u32,
    /// Start node of each robot (departure zones, distinct). Default: the layout's departure
    /// zones in order (A, B, C, … in the paper layout).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub starts: Option<Vec<String>>,
    /// The unloading zone every robot delivers to. Default: `"M"`.
    #[serde(default = "defaults::unload")]
    pub unload: String,
    /// The goods to fetch, in order: a list of cell ids, or `{ random = COUNT, seed = SEED }`.
    pub tasks: Tasks,
    /// Steps after which an unfinished run ends incomplete. Default: 100000.
    #[serde(default = "defaults::step_limit")]
    pub step_limit: u64,
    /// Task-allocation strategy. Default: `"in-turn"`.
    #[serde(default = "defaults::allocator")]
    pub allocator: String,
    /// The rule set: `"paper"` (the model of docs/model.md) or `"original"` (the authors'
    /// code, tick for tick: docs/original-rules.md). Default: `"paper"`.
    #[serde(default, skip_serializing_if = "Rules::is_paper")]
    pub rules: Rules,
    /// When robots go to charge.
    #[serde(default)]
    pub charging: Charging,
    /// Weights of the paper's Cost_total = w_d·distance + w_t·time + w_c·collisions.
    #[serde(default)]
    pub cost: CostWeights,
    /// Robot parameters.
    #[serde(default)]
    pub robot: RobotParams,
    /// Dwell times.
    #[serde(default)]
    pub dwell: Dwell,
    /// The collision-waiting rule.
    #[serde(default)]
    pub collision: CollisionParams,
    /// A generated layout (extension): when given, it is the layout, and `layout` must be
    /// left at its default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layout_generate: Option<LayoutParams>,
    /// Where robots start (extension): `"departure"` (the paper: one per departure zone, at
    /// its charger) or `"spread"` (parked evenly along the aisles, for large fleets).
    #[serde(default, skip_serializing_if = "Placement::is_departure")]
    pub placement: Placement,
    /// Lifelong operation (extension): orders arrive over time and the run lasts a horizon.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orders: Option<Orders>,
}

/// Which rules run a scenario.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Rules {
    /// The model of docs/model.md: a cleaned-up reading of the paper, without deadlocks.
    #[default]
    Paper,
    /// The authors' original code, reproduced tick for tick, quirks included
    /// ([`crate::original`]).
    Original,
}

impl Rules {
    /// Whether these are the paper rules (the default).
    #[must_use]
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    pub fn is_paper(&self) -> bool {
        *self == Rules::Paper
    }
}

/// Where robots start.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Placement {
    /// The paper: robot i starts at the charger of the i-th start node.
    #[default]
    Departure,
    /// Robots start idle, strictly inside aisle edges, spread evenly over the layout's
    /// parking slots; each robot's slot is its home (docs/model.md section 7).
    Spread,
}

impl Placement {
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    fn is_departure(&self) -> bool {
        *self == Placement::Departure
    }
}

/// Lifelong orders: a Poisson stream and/or a CSV of `(step, cell)` rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Orders {
    /// Mean orders per step (Poisson), each for a uniformly drawn cell. Default: 0.
    pub rate: f64,
    /// A CSV file of `step,cell` rows (path relative to the working directory).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub csv: Option<String>,
    /// Steps the run lasts. Default: 10000.
    pub horizon: u64,
    /// Steps after a pickup until the cell holds goods again. Default: 200.
    pub restock: u64,
    /// Seed of the Poisson stream. Default: 0.
    pub seed: u64,
}

impl Default for Orders {
    fn default() -> Self {
        Orders { rate: 0.0, csv: None, horizon: 10_000, restock: 200, seed: 0 }
    }
}

/// Robot body, motion and battery.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RobotParams {
    /// Disc radius, px. Default: 12.5.
    pub radius: f64,
    /// Distance per step, px. Default: 4.
    pub speed: f64,
    /// Full energy. Default: 10.
    pub energy_full: f64,
    /// Below this a robot is sent to charge. Default: 3.5.
    pub threshold: f64,
    /// Energy used per step while not charging or parked. Default: 0.005.
    pub consumption: f64,
    /// Energy gained per step while charging. Default: 0.05.
    pub charge_rate: f64,
}

/// Steps spent standing to load and to unload.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Dwell {
    /// Steps at the service point. Default: 10.
    pub loading: u32,
    /// Steps on the unloading node. Default: 20.
    pub unloading: u32,
}

/// Parameters of the collision-waiting rule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CollisionParams {
    /// Added to r_i + r_j, px. Default: 0 (the authors' code used 8).
    pub margin: f64,
    /// Collision angle, degrees. Default: 30.
    pub angle: f64,
}

/// Charging policies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ChargingPolicy {
    /// The paper's rule: charge only when below the threshold.
    Threshold,
    /// Also: an idle robot below `charging.level` goes to charge.
    Opportunistic,
}

/// Which charger a robot uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ChargerUse {
    /// The paper: every robot charges at its own home charger.
    #[default]
    Home,
    /// Extension: the nearest free charger; robots queue when none is free.
    Shared,
}

impl ChargerUse {
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    fn is_home(&self) -> bool {
        *self == ChargerUse::Home
    }
}

/// When robots go to charge. The threshold rule always applies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Charging {
    /// `"threshold"` (the paper's rule) or `"opportunistic"`. Default: `"threshold"`.
    pub policy: ChargingPolicy,
    /// With `"opportunistic"`: an idle robot below this energy goes to charge. Default: 7.
    pub level: f64,
    /// `"home"` (the paper) or `"shared"` (nearest free charger, queue when none). Default:
    /// `"home"`.
    #[serde(skip_serializing_if = "ChargerUse::is_home")]
    pub chargers: ChargerUse,
}

impl Default for Charging {
    fn default() -> Self {
        Charging { policy: ChargingPolicy::Threshold, level: 7.0, chargers: ChargerUse::Home }
    }
}

/// Weights of Cost_total = w_d·distance (px) + w_t·T (steps) + w_c·S (collisions).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CostWeights {
    /// w_d, per px travelled by the fleet. Default: 0.25 (one step of travel at 4 px/step).
    pub distance: f64,
    /// w_t, per step of task time. Default: 1.
    pub time: f64,
    /// w_c, per collision. Default: 50.
    pub collision: f64,
}

impl Default for CostWeights {
    fn default() -> Self {
        CostWeights { distance: 0.25, time: 1.0, collision: 50.0 }
    }
}

/// The task list.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Tasks {
    /// Cell ids, fetched in this order.
    Cells(Vec<i64>),
    /// `count` distinct cells drawn with `seed`; the same on every machine.
    Random { random: u32, seed: u64 },
}

mod defaults {
    pub fn layout() -> String {
        "paper".into()
    }
    pub fn robots() -> u32 {
        3
    }
    pub fn unload() -> String {
        "M".into()
    }
    pub fn step_limit() -> u64 {
        100_000
    }
    pub fn allocator() -> String {
        "in-turn".into()
    }
}

impl Default for RobotParams {
    fn default() -> Self {
        RobotParams { radius: 12.5, speed: 4.0, energy_full: 10.0, threshold: 3.5, consumption: 0.005, charge_rate: 0.05 }
    }
}

impl Default for Dwell {
    fn default() -> Self {
        Dwell { loading: 10, unloading: 20 }
    }
}

impl Default for CollisionParams {
    fn default() -> Self {
        CollisionParams { margin: 0.0, angle: 30.0 }
    }
}

impl<'de> Deserialize<'de> for Tasks {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct TasksVisitor;
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Random {
            random: u32,
            #[serde(default)]
            seed: u64,
        }
        impl<'de> Visitor<'de> for TasksVisitor {
            type Value = Tasks;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a list of cell ids or { random = COUNT, seed = SEED }")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> std::result::Result<Tasks, A::Error> {
                Vec::<i64>::deserialize(de::value::SeqAccessDeserializer::new(seq)).map(Tasks::Cells)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> std::result::Result<Tasks, A::Error> {
                let r = Random::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(Tasks::Random { random: r.random, seed: r.seed })
            }
        }
        d.deserialize_any(TasksVisitor)
    }
}

/// The paper's TABLE III: the goods of task groups 1 to 5, fetched in this order (spec
/// section 5). The experiment runs each with N = 1..6 robots.
pub const PAPER_TASKS: [[u32; 10]; 5] = [
    [11, 8, 39, 28, 53, 1, 69, 42, 79, 6],
    [74, 50, 62, 15, 49, 34, 14, 72, 31, 37],
    [68, 79, 56, 47, 48, 75, 23, 50, 76, 16],
    [59, 6, 74, 2, 67, 49, 53, 28, 25, 79],
    [14, 65, 41, 75, 22, 36, 54, 74, 9, 48],
];

/// Draws `count` distinct cells out of `cells` with a portable generator (`ChaCha8`).
#[must_use]
pub fn random_cells(count: u32, seed: u64, cells: usize) -> Vec<u32> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut pool: Vec<u32> = (0..cells as u32).collect();
    let k = (count as usize).min(cells);
    // Partial Fisher–Yates: the first k entries become the draw, in draw order.
    for i in 0..k {
        let j = i + (rng.random::<u64>() % (cells - i) as u64) as usize;
        pool.swap(i, j);
    }
    pool.truncate(k);
    pool
}

fn parse_error(source_name: &str, path: &str, message: &str) -> Error {
    let message = message.lines().next().unwrap_or(message).trim();
    let at = if path.is_empty() || path == "." { String::new() } else { format!("{path}: ") };
    Error::Parse { source_name: source_name.to_string(), message: format!("{at}{message}") }
}

impl Scenario {
    /// Parses TOML text; `source_name` (a file name) prefixes error messages.
    pub fn from_toml(text: &str, source_name: &str) -> Result<Scenario> {
        let de = toml::Deserializer::new(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let mut msg = inner.message().to_string();
            if path.is_empty() || path == "." {
                if let Some(span) = inner.span() {
                    let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
                    msg = format!("line {line}: {msg}");
                }
            }
            parse_error(source_name, &path, &msg)
        })
    }

    /// Parses JSON text (what the Python API sends).
    pub fn from_json(text: &str) -> Result<Scenario> {
        let mut de = serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(&mut de).map_err(|e| parse_error("scenario", &e.path().to_string(), &e.inner().to_string()))
    }

    /// The scenario as TOML.
    #[must_use]
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("every scenario serialises")
    }

    /// The scenario as JSON.
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("every scenario serialises")
    }

    /// The paper's experiment setting with these goods.
    #[must_use]
    pub fn paper(robots: u32, cells: &[u32]) -> Scenario {
        Scenario {
            layout: defaults::layout(),
            robots,
            starts: None,
            unload: defaults::unload(),
            tasks: Tasks::Cells(cells.iter().map(|&c| i64::from(c)).collect()),
            step_limit: defaults::step_limit(),
            allocator: defaults::allocator(),
            rules: Rules::Paper,
            charging: Charging::default(),
            cost: CostWeights::default(),
            robot: RobotParams::default(),
            dwell: Dwell::default(),
            collision: CollisionParams::default(),
            layout_generate: None,
            placement: Placement::Departure,
            orders: None,
        }
    }

    /// The layout this scenario names.
    ///
    /// `"paper"`, a layout file (a path ending in `.toml`, relative to the working
    /// directory), or, with `[layout_generate]`, the generated grid.
    pub fn resolve_layout(&self) -> Result<Layout> {
        if let Some(p) = &self.layout_generate {
            if self.layout != defaults::layout() {
                return Err(Error::scenario("layout", format!("\"{}\"", self.layout), "give either layout or [layout_generate], not both"));
            }
            return Layout::generate(p, "generated").map_err(|e| match e {
                Error::Scenario { field, value, reason } => Error::Scenario { field: field.replacen("layout.", "layout_generate.", 1), value, reason },
                other => other,
            });
        }
        match self.layout.as_str() {
            "paper" => Ok(Layout::paper()),
            path if std::path::Path::new(path).extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) => crate::layout_file::read(std::path::Path::new(path)),
            other => Err(Error::scenario("layout", format!("\"{other}\""), "unknown layout (known: paper, or a layout file ending in .toml)")),
        }
    }

    /// Checks every field that does not depend on the layout.
    pub fn check_values(&self) -> Result<()> {
        let positive = |field: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::scenario(field, v, "must be greater than 0"))
            }
        };
        if self.robots == 0 {
            return Err(Error::scenario("robots", 0, "must be at least 1"));
        }
        if self.step_limit == 0 {
            return Err(Error::scenario("step_limit", 0, "must be greater than 0"));
        }
        let r = &self.robot;
        positive("robot.radius", r.radius)?;
        positive("robot.speed", r.speed)?;
        positive("robot.energy_full", r.energy_full)?;
        positive("robot.consumption", r.consumption)?;
        positive("robot.charge_rate", r.charge_rate)?;
        if !(r.threshold.is_finite() && r.threshold >= 0.0) {
            return Err(Error::scenario("robot.threshold", r.threshold, "must be 0 or more"));
        }
        if r.threshold >= r.energy_full {
            return Err(Error::scenario("robot.threshold", r.threshold, format!("must be below robot.energy_full ({})", r.energy_full)));
        }
        if self.dwell.loading == 0 {
            return Err(Error::scenario("dwell.loading", 0, "must be at least 1 step"));
        }
        if self.dwell.unloading == 0 {
            return Err(Error::scenario("dwell.unloading", 0, "must be at least 1 step"));
        }
        let ch = &self.charging;
        if ch.policy == ChargingPolicy::Opportunistic && !(ch.level.is_finite() && ch.level > r.threshold && ch.level <= r.energy_full) {
            return Err(Error::scenario("charging.level", ch.level, format!("must be above robot.threshold ({}) and at most robot.energy_full ({})", r.threshold, r.energy_full)));
        }
        for (field, w) in [("cost.distance", self.cost.distance), ("cost.time", self.cost.time), ("cost.collision", self.cost.collision)] {
            if !(w.is_finite() && w >= 0.0) {
                return Err(Error::scenario(field, w, "must be 0 or more"));
            }
        }
        let c = &self.collision;
        if !(c.margin.is_finite() && c.margin >= 0.0) {
            return Err(Error::scenario("collision.margin", c.margin, "must be 0 or more"));
        }
        if !(c.angle.is_finite() && c.angle > 0.0 && c.angle <= 180.0) {
            return Err(Error::scenario("collision.angle", c.angle, "must be in (0, 180] degrees"));
        }
        if let Tasks::Random { random, .. } = self.tasks {
            if random == 0 {
                return Err(Error::scenario("tasks.random", 0, "must be at least 1"));
            }
        }
        if let Some(o) = &self.orders {
            if !(o.rate.is_finite() && o.rate >= 0.0) {
                return Err(Error::scenario("orders.rate", o.rate, "must be 0 or more"));
            }
            if o.horizon == 0 {
                return Err(Error::scenario("orders.horizon", 0, "must be at least 1 step"));
            }
            if o.restock == 0 {
                return Err(Error::scenario("orders.restock", 0, "must be at least 1 step"));
            }
            if o.rate == 0.0 && o.csv.is_none() && matches!(&self.tasks, Tasks::Cells(c) if c.is_empty()) {
                return Err(Error::scenario("orders.rate", 0, "no orders: give a rate above 0, a csv file or tasks"));
            }
        }
        if self.placement == Placement::Spread && self.starts.is_some() {
            return Err(Error::scenario("starts", format!("{:?}", self.starts.as_deref().unwrap_or_default()), "not used with placement = \"spread\" (robots start on parking slots)"));
        }
        if self.placement == Placement::Spread && self.charging.chargers == ChargerUse::Home {
            return Err(Error::scenario("placement", "\"spread\"", "robots placed on aisles share chargers: set charging.chargers = \"shared\""));
        }
        if let Tasks::Cells(cells) = &self.tasks {
            if cells.is_empty() && self.orders.is_none() {
                return Err(Error::scenario("tasks", "[]", "the task list is empty"));
            }
        }
        Ok(())
    }

    /// The task list's cells, checked against the layout.
    pub fn cells(&self, layout: &Layout) -> Result<Vec<u32>> {
        let n = layout.cells.len();
        match &self.tasks {
            Tasks::Cells(list) => {
                let mut seen = vec![false; n];
                let mut out = Vec::with_capacity(list.len());
                for (i, &c) in list.iter().enumerate() {
                    if c < 0 || c as usize >= n {
                        return Err(Error::scenario(format!("tasks[{i}]"), c, format!("cell id out of range 0..{}", n - 1)));
                    }
                    if seen[c as usize] {
                        return Err(Error::scenario(format!("tasks[{i}]"), c, "cell named twice in the task list"));
                    }
                    seen[c as usize] = true;
                    out.push(c as u32);
                }
                Ok(out)
            }
            Tasks::Random { random, seed } => {
                if *random as usize > n {
                    return Err(Error::scenario("tasks.random", random, format!("more goods than cells ({n})")));
                }
                Ok(random_cells(*random, *seed, n))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_fill_a_minimal_file() {
        let s = Scenario::from_toml("tasks = [11, 8, 39]", "x.toml").unwrap();
        assert_eq!(s, Scenario::paper(3, &[11, 8, 39]));
        let round = Scenario::from_toml(&s.to_toml(), "y.toml").unwrap();
        assert_eq!(round, s);
    }

    #[test]
    fn errors_name_the_field() {
        let e = Scenario::from_toml("tasks = [1]\nrobot = { speed = \"fast\" }", "s.toml").unwrap_err().to_string();
        assert!(e.starts_with("s.toml: robot.speed: invalid type: string \"fast\""), "{e}");
        let e = Scenario::from_toml("tasks = [1]\nrobts = 3", "s.toml").unwrap_err().to_string();
        assert!(e.contains("unknown field `robts`"), "{e}");
        let e = Scenario::from_toml("tasks = [1, \"x\"]", "s.toml").unwrap_err().to_string();
        assert!(e.contains("tasks[1]") || e.contains("tasks"), "{e}");
        let e = Scenario::from_toml("tasks = [1", "s.toml").unwrap_err().to_string();
        assert!(e.starts_with("s.toml: "), "{e}");
        assert!(!e.contains('\n'));
    }

    #[test]
    fn random_tasks_are_portable_and_distinct() {
        let a = random_cells(10, 7, 80);
        assert_eq!(a, random_cells(10, 7, 80));
        assert_ne!(a, random_cells(10, 8, 80));
        let mut s = a.clone();
        s.sort_unstable();
        s.dedup();
        assert_eq!(s.len(), 10);
        assert!(a.iter().all(|&c| c < 80));
        // Pinned: the same list on every machine.
        assert_eq!(a, random_cells(10, 7, 80));
    }

    #[test]
    fn value_checks() {
        let mut s = Scenario::paper(3, &[1]);
        s.robot.threshold = 10.0;
        assert_eq!(s.check_values().unwrap_err().to_string(), "robot.threshold = 10: must be below robot.energy_full (10)");
        let mut s = Scenario::paper(3, &[1]);
        s.robot.speed = -1.0;
        assert_eq!(s.check_values().unwrap_err().to_string(), "robot.speed = -1: must be greater than 0");
        let s = Scenario::paper(3, &[1, 80]);
        assert_eq!(s.cells(&Layout::paper()).unwrap_err().to_string(), "tasks[1] = 80: cell id out of range 0..79");
        let s = Scenario::paper(3, &[5, 5]);
        assert_eq!(s.cells(&Layout::paper()).unwrap_err().to_string(), "tasks[1] = 5: cell named twice in the task list");
    }
}
