//! The scenario schema: the one definition of every field, its default and its checks.
//! TOML files, Python dictionaries and the command line all land here.

use crate::error::{Error, Result};
use crate::input::layout_params::LayoutParams;
use crate::input::messages::{json_message, toml_message};
use rand::{Rng, SeedableRng};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

mod tables;
pub use tables::*;

/// A whole run: layout, fleet, tasks and model parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// The warehouse layout. Default: `"paper"`.
    #[serde(default = "defaults::layout")]
    pub layout: String,
    /// N, the number of robots (≥ 1). Default: 3.
    #[serde(default = "defaults::robots")]
    pub robots: u32,
    /// Robot i starts at the charger of the i-th start node: distinct departure zones, one per
    /// robot. Default: the layout's departure zones in order (A, B, C, … in the paper layout).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub starts: Option<Vec<String>>,
    /// Where goods are delivered: `"first"` (the layout's first unloading zone: `M` in the
    /// paper layout), `"nearest"` (each cell's goods to the zone nearest its service point),
    /// an unloading zone's node name, or `"auto"`: first for the paper's fleets (on their
    /// departure zones), nearest for fleets spread along the aisles. Default: `"auto"`.
    #[serde(default, skip_serializing_if = "Unload::is_auto")]
    pub unload: Unload,
    /// The goods to fetch, in order: a list of distinct cell ids, or `{ random = COUNT, seed =
    /// SEED }` for COUNT distinct cells drawn with a portable generator (ChaCha8), the same on
    /// every machine.
    pub tasks: Tasks,
    /// A run not finished after this many steps ends `incomplete` (1 to 4294967295). Default: 100000.
    #[serde(default = "defaults::step_limit")]
    #[schemars(range(min = 1, max = crate::input::limits::MAX_STEPS))]
    pub step_limit: u64,
    /// Task-allocation strategy: a built-in (`in-turn`, `nearest`, `hungarian`, `auction`,
    /// `energy-aware`, `min-cost`; docs/strategies.md) or a Python `module:Class`. Default:
    /// `"in-turn"`.
    #[serde(default = "defaults::allocator")]
    pub allocator: String,
    /// The rule set: `"paper"` (the model of docs/model.md) or `"original"` (the authors'
    /// code, tick for tick: docs/original-rules.md). Default: `"paper"`.
    #[serde(default, skip_serializing_if = "Rules::is_paper")]
    pub rules: Rules,
    /// How robots share the aisles: `"wait"` (the paper's collision waiting), `"gate"`
    /// (waiting, and crossings taken one robot at a time) or `"reserve"`
    /// (lanes and crossings reserved: no contact, no gridlock; docs/traffic.md), or `"auto"`:
    /// wait for the paper's fleets (on their departure zones), reserve for fleets spread along
    /// the aisles. Default: `"auto"`.
    #[serde(default, skip_serializing_if = "Traffic::is_auto")]
    pub traffic: Traffic,
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
    /// its charger), `"spread"` (parked evenly along the aisles, for large fleets), or
    /// `"auto"`: departure when the fleet fits the layout's departure zones (or `starts` names
    /// them, or `charging.chargers` is `"home"`), spread beyond. Default: `"auto"`.
    #[serde(default, skip_serializing_if = "Placement::is_auto")]
    #[schemars(extend("default" = "auto"))]
    pub placement: Placement,
    /// Lifelong operation (extension): orders arrive over time and the run lasts a horizon.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orders: Option<Orders>,
    /// How the run is measured: throughput windows, warm-up, gridlock detection.
    #[serde(default, skip_serializing_if = "MetricsParams::is_default")]
    pub metrics: MetricsParams,
    /// Workers on the floor and the safety zones robots keep around them (extension,
    /// docs/people.md). Absent: no people, and the run is exactly as without this table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub humans: Option<Humans>,
}

pub(crate) mod defaults {
    pub fn layout() -> String {
        "paper".into()
    }
    pub fn robots() -> u32 {
        3
    }
    pub fn step_limit() -> u64 {
        100_000
    }
    pub fn allocator() -> String {
        "in-turn".into()
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

impl Scenario {
    /// Parses TOML text; `source_name` (a file name) prefixes error messages.
    pub fn from_toml(text: &str, source_name: &str) -> Result<Scenario> {
        crate::input::files::check_toml_shape(text).map_err(|message| Error::Parse { source_name: source_name.to_string(), message })?;
        let de = toml::Deserializer::new(text);
        serde_path_to_error::deserialize(de).map_err(|e| Error::Parse { source_name: source_name.to_string(), message: toml_message(text, e) })
    }

    /// Parses JSON text (what the Python API sends).
    pub fn from_json(text: &str) -> Result<Scenario> {
        let fail = |message: String| Error::Parse { source_name: "scenario".to_string(), message };
        // The position in the JSON text is left out of messages: the user never wrote it.
        crate::input::files::check_json_shape(text).map_err(|m| fail(m.split_once(": ").map_or(m.clone(), |(_, rest)| rest.to_string())))?;
        let mut de = serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(&mut de).map_err(|e| fail(json_message(&e)))
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
            unload: Unload::Auto,
            tasks: Tasks::Cells(cells.iter().map(|&c| i64::from(c)).collect()),
            step_limit: defaults::step_limit(),
            allocator: defaults::allocator(),
            rules: Rules::Paper,
            traffic: Traffic::Auto,
            charging: Charging::default(),
            cost: CostWeights::default(),
            robot: RobotParams::default(),
            dwell: Dwell::default(),
            collision: CollisionParams::default(),
            layout_generate: None,
            placement: Placement::Auto,
            orders: None,
            metrics: MetricsParams::default(),
            humans: None,
        }
    }

    /// The scenario with every `"auto"` choice made for a layout of `departures` departure
    /// zones: the paper's choices (departure placement, home chargers, the threshold rule,
    /// the first unloading zone, collision waiting) for a fleet that fits its departure zones
    /// or whose `starts` are named, and under the original rules; for a larger fleet, the
    /// choices that keep it running (spread placement, shared chargers, staggered charging, the
    /// nearest unloading zone, reserved lanes). A choice the scenario makes itself stays.
    #[must_use]
    pub fn resolved(&self, departures: usize) -> Scenario {
        let mut s = self.clone();
        if s.placement == Placement::Auto {
            // Home chargers are the paper's too: a fleet on the aisles cannot have them.
            let paper = s.rules == Rules::Original || s.starts.is_some() || s.charging.chargers == ChargerUse::Home || s.robots as usize <= departures;
            s.placement = if paper { Placement::Departure } else { Placement::Spread };
        }
        let spread = s.placement == Placement::Spread;
        if s.charging.chargers == ChargerUse::Auto {
            s.charging.chargers = if spread { ChargerUse::Shared } else { ChargerUse::Home };
        }
        if s.charging.policy == ChargingPolicy::Auto {
            // Staggering needs levels to spread between the threshold and `charging.level`.
            let room = s.charging.level > s.robot.threshold && s.charging.level <= s.robot.energy_full;
            s.charging.policy = if s.charging.chargers == ChargerUse::Shared && room { ChargingPolicy::Staggered } else { ChargingPolicy::Threshold };
        }
        if s.unload == Unload::Auto {
            s.unload = if spread { Unload::Nearest } else { Unload::First };
        }
        if s.traffic == Traffic::Auto {
            s.traffic = if spread { Traffic::Reserve } else { Traffic::Wait };
        }
        s
    }

    /// The files a run of this scenario reads, by the field that names them: a layout file,
    /// the orders' and the people's CSV tables (paths as written, relative to the working
    /// directory). What a command must never write over.
    #[must_use]
    pub fn files(&self) -> Vec<(&'static str, std::path::PathBuf)> {
        let mut out = Vec::new();
        if self.layout_generate.is_none() && std::path::Path::new(&self.layout).extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
            out.push(("layout", self.layout.clone().into()));
        }
        if let Some(csv) = self.orders.as_ref().and_then(|o| o.csv.as_ref()) {
            out.push(("orders.csv", csv.into()));
        }
        if let Some(csv) = self.humans.as_ref().and_then(|h| h.csv.as_ref()) {
            out.push(("humans.csv", csv.into()));
        }
        out
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
        if self.robots > crate::input::limits::MAX_ROBOTS {
            return Err(Error::scenario("robots", self.robots, format!("at most {}", crate::input::limits::MAX_ROBOTS)));
        }
        if self.step_limit == 0 {
            return Err(Error::scenario("step_limit", 0, "must be greater than 0"));
        }
        if self.step_limit > crate::input::limits::MAX_STEPS {
            return Err(Error::scenario("step_limit", self.step_limit, format!("at most {}", crate::input::limits::MAX_STEPS)));
        }
        let r = &self.robot;
        positive("robot.radius", r.radius)?;
        positive("robot.speed", r.speed)?;
        positive("robot.energy_full", r.energy_full)?;
        positive("robot.consumption", r.consumption)?;
        positive("robot.charge_rate", r.charge_rate)?;
        if let Some(idle) = r.idle_consumption {
            if !(idle.is_finite() && idle >= 0.0) {
                return Err(Error::scenario("robot.idle_consumption", idle, "must be 0 or more"));
            }
        }
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
        if !ch.level.is_finite() {
            return Err(Error::scenario("charging.level", ch.level, "must be a finite number"));
        }
        if matches!(ch.policy, ChargingPolicy::Opportunistic | ChargingPolicy::Staggered) && !(ch.level > r.threshold && ch.level <= r.energy_full) {
            return Err(Error::scenario(
                "charging.level",
                ch.level,
                format!("must be above robot.threshold ({}) and at most robot.energy_full ({})", r.threshold, r.energy_full),
            ));
        }
        if let Some(reach) = ch.reach {
            if !(reach.is_finite() && reach > 0.0) {
                return Err(Error::scenario("charging.reach", reach, "must be greater than 0 px"));
            }
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
        if let Some(h) = &self.humans {
            h.check(&self.robot)?;
            if h.count > 0 && self.rules == Rules::Original {
                return Err(Error::scenario("humans.count", h.count, "people need the paper rules (rules = \"paper\"): the authors' code has none"));
            }
        }
        if let Some(o) = &self.orders {
            if !(o.rate.is_finite() && o.rate >= 0.0) {
                return Err(Error::scenario("orders.rate", o.rate, "must be 0 or more"));
            }
            if o.rate > crate::input::limits::MAX_ORDER_RATE {
                return Err(Error::scenario("orders.rate", o.rate, format!("at most {} orders per step", crate::input::limits::MAX_ORDER_RATE)));
            }
            let expected = o.rate * o.horizon as f64;
            if expected > crate::input::limits::MAX_ORDERS {
                let most = crate::input::limits::MAX_ORDERS;
                // The factor nearer its own limit is the one to name.
                let err = if o.horizon as f64 / crate::input::limits::MAX_STEPS as f64 > o.rate / crate::input::limits::MAX_ORDER_RATE {
                    let why = format!("expects {expected:.3e} orders at orders.rate = {} per step; at most {most:.0e}: lower the horizon or the rate", o.rate);
                    Error::scenario("orders.horizon", o.horizon, why)
                } else {
                    let why =
                        format!("expects {expected:.3e} orders over orders.horizon = {} steps; at most {most:.0e}: lower the rate or the horizon", o.horizon);
                    Error::scenario("orders.rate", o.rate, why)
                };
                return Err(err);
            }
            if o.horizon == 0 {
                return Err(Error::scenario("orders.horizon", 0, "must be at least 1 step"));
            }
            if o.horizon > crate::input::limits::MAX_STEPS {
                return Err(Error::scenario("orders.horizon", o.horizon, format!("at most {} steps", crate::input::limits::MAX_STEPS)));
            }
            if o.restock == 0 {
                return Err(Error::scenario("orders.restock", 0, "must be at least 1 step"));
            }
            if o.rate == 0.0 && o.csv.is_none() && matches!(&self.tasks, Tasks::Cells(c) if c.is_empty()) {
                return Err(Error::scenario("orders.rate", 0, "no orders: give a rate above 0, a csv file or tasks"));
            }
        }
        if self.metrics.window == 0 {
            return Err(Error::scenario("metrics.window", 0, "must be at least 1 step"));
        }
        // The run's windows are kept, one count each: bounded before the run starts.
        let (run, by) = self.orders.as_ref().map_or((self.step_limit, "step_limit"), |o| (o.horizon, "orders.horizon"));
        if run / self.metrics.window > crate::input::limits::MAX_WINDOWS {
            return Err(Error::scenario(
                "metrics.window",
                self.metrics.window,
                format!("{by} = {run} makes {} throughput windows; at most {} (docs/limits.md)", run / self.metrics.window, crate::input::limits::MAX_WINDOWS),
            ));
        }
        if self.placement == Placement::Spread && self.starts.is_some() {
            return Err(Error::scenario(
                "starts",
                format!("{:?}", self.starts.as_deref().unwrap_or_default()),
                "not used with placement = \"spread\" (robots start on parking slots)",
            ));
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

    /// The task list's cells, checked against a layout of `n` storage cells.
    pub fn cells(&self, n: usize) -> Result<Vec<u32>> {
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
        assert_eq!(e, "s.toml: robot.speed = \"fast\": expected a number");
        let e = Scenario::from_toml("tasks = [1]\nrobts = 3", "s.toml").unwrap_err().to_string();
        assert!(e.starts_with("s.toml: unknown field `robts` (did you mean `robots`? known: layout, robots, "), "{e}");
        let e = Scenario::from_toml("tasks = [1]\n[robot]\nsped = 3", "s.toml").unwrap_err().to_string();
        assert!(e.starts_with("s.toml: robot: unknown field `sped` (did you mean `speed`? known: radius, speed, "), "{e}");
        // Nothing near: no guess.
        let e = Scenario::from_toml("tasks = [1]\nvelocity = 3", "s.toml").unwrap_err().to_string();
        assert!(e.starts_with("s.toml: unknown field `velocity` (known: layout, "), "{e}");
        let e = Scenario::from_toml("tasks = [1]\ntraffic = \"reserv\"", "s.toml").unwrap_err().to_string();
        assert_eq!(e, "s.toml: traffic = \"reserv\": expected one of auto, wait, gate, reserve (did you mean \"reserve\"?)");
        let e = Scenario::from_toml("tasks = [1, \"x\"]", "s.toml").unwrap_err().to_string();
        assert!(e.contains("tasks[1]") || e.contains("tasks"), "{e}");
        let e = Scenario::from_toml("tasks = [1", "s.toml").unwrap_err().to_string();
        assert!(e.starts_with("s.toml: "), "{e}");
        assert!(!e.contains('\n'));
    }

    #[test]
    fn type_errors_speak_the_users_words() {
        let err = |text: &str| Scenario::from_toml(text, "s.toml").unwrap_err().to_string();
        let cases = [
            ("robots = 4294967296", "s.toml: robots = 4294967296: expected a whole number from 0 to 4294967295"),
            ("[layout_generate]\ngroup_height = 2e9", "s.toml: layout_generate.group_height = 2000000000.0: expected a whole number from 0 to 4294967295, written without a decimal point or exponent"),
            ("robots = [1]", "s.toml: robots: expected a whole number from 0 to 4294967295, not a list"),
            ("traffic = \"x\"", "s.toml: traffic = \"x\": expected one of auto, wait, gate, reserve"),
            ("rules = 5", "s.toml: rules: expected text in quotes"),
            ("starts = [1]", "s.toml: starts[0] = 1: expected text in quotes"),
            ("orders = 5", "s.toml: orders = 5: expected a table"),
            ("[humans]\nseed = 18446744073709551615 # big", "s.toml: line 3: seed = 18446744073709551615: too large (TOML whole numbers are at most 9223372036854775807)"),
        ];
        for (body, want) in cases {
            // Tables after the task list.
            assert_eq!(err(&format!("tasks = [1]\n{body}")), want);
        }
        let json = |text: &str| Scenario::from_json(text).unwrap_err().to_string();
        assert_eq!(
            json(r#"{"tasks":[1],"robots":1e20}"#),
            "scenario: robots = 1e20: expected a whole number from 0 to 4294967295, written without a decimal point or exponent"
        );
        assert_eq!(json(r#"{"tasks":[1],"collision":{"margin":1e400}}"#), "scenario: collision.margin: a number out of range (at most ±1.8e308)");
        let deep = format!("{{\"tasks\":[1],\"x\":{}{}}}", "[".repeat(40), "]".repeat(40));
        assert_eq!(json(&deep), "scenario: a value nested deeper than 32 levels (docs/limits.md)");
        for e in [err("tasks = [1]\nrobots = 2.5"), json(r#"{"tasks":[1],"robots":"x"}"#)] {
            for word in ["u32", "invalid type", "floating point", "line 1 column", "sequence"] {
                assert!(!e.contains(word), "{e}");
            }
        }
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
        assert_eq!(s.cells(80).unwrap_err().to_string(), "tasks[1] = 80: cell id out of range 0..79");
        let s = Scenario::paper(3, &[5, 5]);
        assert_eq!(s.cells(80).unwrap_err().to_string(), "tasks[1] = 5: cell named twice in the task list");
        // A product too large names the factor nearer its own limit.
        let mut s = Scenario::paper(3, &[1]);
        s.orders = Some(Orders { rate: 100_000.0, horizon: 30_000_000, ..Orders::default() });
        assert!(s.check_values().unwrap_err().to_string().starts_with("orders.rate = 100000: expects 3.000e12 orders"));
        s.orders = Some(Orders { rate: 1.0, horizon: 4_000_000_000, ..Orders::default() });
        assert!(s.check_values().unwrap_err().to_string().starts_with("orders.horizon = 4000000000: expects 4.000e9 orders at orders.rate = 1"));
        let mut s = Scenario::paper(3, &[1]);
        s.metrics.window = 1;
        s.step_limit = crate::input::limits::MAX_STEPS;
        assert_eq!(
            s.check_values().unwrap_err().to_string(),
            "metrics.window = 1: step_limit = 4294967295 makes 4294967295 throughput windows; at most 10000000 (docs/limits.md)"
        );
    }

    #[test]
    fn auto_is_the_paper_for_the_paper_fleets_and_what_keeps_a_spread_fleet_running() {
        // The paper's scenario: every choice the paper's, so its results never move.
        let paper = Scenario::paper(6, &[11, 8, 39]).resolved(6);
        assert_eq!(
            (paper.placement, paper.charging.chargers, paper.charging.policy, paper.unload.clone(), paper.traffic),
            (Placement::Departure, ChargerUse::Home, ChargingPolicy::Threshold, Unload::First, Traffic::Wait)
        );
        // More robots than departure zones: spread along the aisles, and what that needs.
        let big = Scenario { robots: 200, ..Scenario::paper(1, &[11]) }.resolved(6);
        assert_eq!(
            (big.placement, big.charging.chargers, big.charging.policy, big.unload.clone(), big.traffic),
            (Placement::Spread, ChargerUse::Shared, ChargingPolicy::Staggered, Unload::Nearest, Traffic::Reserve)
        );
        // Named starts, or the original rules: the paper's placement whatever the size.
        let named = Scenario { robots: 200, starts: Some(vec!["A".into()]), ..Scenario::paper(1, &[11]) }.resolved(6);
        assert_eq!(named.placement, Placement::Departure);
        let mut home = Scenario { robots: 200, ..Scenario::paper(1, &[11]) };
        home.charging.chargers = ChargerUse::Home;
        assert_eq!(home.resolved(6).placement, Placement::Departure, "home chargers are the paper's placement");
        let original = Scenario { robots: 200, rules: Rules::Original, ..Scenario::paper(1, &[11]) }.resolved(6);
        assert_eq!((original.placement, original.traffic), (Placement::Departure, Traffic::Wait));
        // A choice the scenario makes stays; staggering needs room between threshold and level.
        let mut own = Scenario { robots: 200, traffic: Traffic::Gate, ..Scenario::paper(1, &[11]) };
        own.charging.level = own.robot.threshold;
        let own = own.resolved(6);
        assert_eq!((own.traffic, own.charging.policy), (Traffic::Gate, ChargingPolicy::Threshold));
        // "auto" is what a file says by saying nothing, and it reads back the same.
        let file = Scenario::from_toml("robots = 2\ntasks = [11]\ntraffic = \"auto\"", "a.toml").unwrap();
        assert_eq!(file, Scenario::from_toml(&file.to_toml(), "b.toml").unwrap());
        assert!(!file.to_toml().contains("traffic"));
    }
}
