//! The scenario's tables and value types: fleet, dwell, collision, charging, cost, orders,
//! metrics, placement, unloading and the task list, each with its defaults.

use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::borrow::Cow;
use std::fmt;

/// How a run is measured (docs/metrics.md).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct MetricsParams {
    /// Steps per throughput window: the result's `windows` series counts the deliveries of
    /// each (≥ 1). Default: 1000.
    pub window: u64,
    /// Steps left out of the steady-state figures (throughput, wait share, utilisation), so
    /// that they describe the run after its start-up. Default: 0.
    pub warmup: u64,
    /// A run in which no robot moves, dwells or charges for this many steps while work
    /// remains ends with outcome `gridlock`, and says where; 0 never ends a run so.
    /// Default: 2000.
    pub gridlock: u64,
}

impl Default for MetricsParams {
    fn default() -> Self {
        MetricsParams { window: 1000, warmup: 0, gridlock: 2000 }
    }
}

impl MetricsParams {
    pub(crate) fn is_default(&self) -> bool {
        *self == MetricsParams::default()
    }
}

/// Where goods are delivered.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Unload {
    /// `first` for the paper's fleets (robots on their departure zones), `nearest` for fleets
    /// spread along the aisles ([`crate::input::scenario::Scenario::resolved`]).
    #[default]
    Auto,
    /// The layout's first unloading zone (`M` in the paper layout): works on any layout.
    First,
    /// Each cell's goods go to the unloading zone nearest its service point (extension).
    Nearest,
    /// This unloading zone, by node name.
    Node(String),
}

impl Unload {
    pub(crate) fn is_auto(&self) -> bool {
        *self == Unload::Auto
    }

    /// The text a scenario file uses.
    #[must_use]
    pub fn as_str(&self) -> &str {
        match self {
            Unload::Auto => "auto",
            Unload::First => "first",
            Unload::Nearest => "nearest",
            Unload::Node(name) => name,
        }
    }
}

impl From<&str> for Unload {
    fn from(s: &str) -> Unload {
        match s {
            "auto" => Unload::Auto,
            "first" => Unload::First,
            "nearest" => Unload::Nearest,
            name => Unload::Node(name.to_string()),
        }
    }
}

impl Serialize for Unload {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl JsonSchema for Unload {
    fn schema_name() -> Cow<'static, str> {
        "Unload".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "type": "string",
            "description": "\"auto\" (first for the paper's fleets, nearest for fleets spread along the aisles), \"first\" (the layout's first unloading zone), \"nearest\" (each cell's nearest zone), or an unloading zone's node name.",
            "default": "auto",
        })
    }
}

impl<'de> Deserialize<'de> for Unload {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        String::deserialize(d).map(|s| Unload::from(s.as_str()))
    }
}

/// How robots share the aisles (docs/traffic.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Traffic {
    /// `wait` for the paper's fleets (robots on their departure zones), `reserve` for fleets
    /// spread along the aisles, where collision waiting lets robots drive into each other and
    /// locks up under load ([`crate::input::scenario::Scenario::resolved`]).
    #[default]
    Auto,
    /// The paper's collision waiting: a robot waits while another stands within reach in a
    /// cone ahead of it.
    Wait,
    /// Collision waiting, and crossings taken one robot at a time (a robot refused for long
    /// goes anyway, so the gate never deadlocks).
    Gate,
    /// Lanes and crossings reserved: robots keep their distance along each aisle, take a
    /// crossing only when it is free and their exit has room, in the order they asked, and
    /// detour when an exit stays full; no two robots ever come closer than r_i + r_j.
    Reserve,
}

impl Traffic {
    /// Whether this is `auto` (the default).
    #[must_use]
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    pub fn is_auto(&self) -> bool {
        *self == Traffic::Auto
    }

    /// The name scenario files and the command line use.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Traffic::Auto => "auto",
            Traffic::Wait => "wait",
            Traffic::Gate => "gate",
            Traffic::Reserve => "reserve",
        }
    }
}

/// Which rules run a scenario.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Rules {
    /// The model of docs/model.md: a cleaned-up reading of the paper, without deadlocks.
    #[default]
    Paper,
    /// The authors' original code, reproduced tick for tick, quirks included
    /// ([`crate::rules::original`]).
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
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Placement {
    /// `departure` when the fleet fits the layout's departure zones (or `starts` names them, or
    /// chargers are `home`), `spread` beyond ([`crate::input::scenario::Scenario::resolved`]).
    #[default]
    Auto,
    /// The paper: robot i starts at the charger of the i-th start node.
    Departure,
    /// Robots start idle, strictly inside aisle edges, spread evenly over the layout's
    /// parking slots; each robot's slot is its home (docs/model.md section 7).
    Spread,
}

impl Placement {
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    pub(crate) fn is_auto(&self) -> bool {
        *self == Placement::Auto
    }
}

/// Lifelong orders: a Poisson stream and/or a CSV of `(step, cell)` rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Orders {
    /// Mean orders per step (Poisson), each for a uniformly drawn cell (≥ 0). Default: 0.
    pub rate: f64,
    /// A CSV file of `step,cell` rows (path relative to the working directory).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub csv: Option<String>,
    /// Steps the run lasts (1 to 4294967295). Default: 10000.
    #[schemars(range(min = 1, max = crate::input::limits::MAX_STEPS))]
    pub horizon: u64,
    /// Steps after a pickup until the cell holds goods again (≥ 1). Default: 200.
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
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct RobotParams {
    /// Disc radius, px (> 0). Default: 12.5.
    pub radius: f64,
    /// Distance travelled per step, px (> 0). Default: 4.
    pub speed: f64,
    /// Full battery (> 0). Default: 10.
    pub energy_full: f64,
    /// Below this a robot is sent to charge (0 ≤ threshold < energy_full). Default: 3.5.
    pub threshold: f64,
    /// Energy used per step, except while charging, parked or stranded (> 0). Default: 0.005.
    pub consumption: f64,
    /// Energy gained per step at the charger (> 0). Default: 0.05.
    pub charge_rate: f64,
    /// Energy used per step by a robot standing while it waits for a shared charger (≥ 0):
    /// a robot in a queue draws what its electronics need, not what driving does (the paper
    /// has no such queue). Default: a tenth of `consumption`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub idle_consumption: Option<f64>,
}

/// Steps spent standing to load and to unload.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Dwell {
    /// Steps standing at the service point (≥ 1). Default: 10.
    pub loading: u32,
    /// Steps standing on the unloading node (≥ 1). Default: 20.
    pub unloading: u32,
}

/// Parameters of the collision-waiting rule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct CollisionParams {
    /// Added to r_i + r_j in the contact distance, px (≥ 0); the authors' code used 8.
    /// Default: 0.
    pub margin: f64,
    /// Collision angle, degrees, in (0, 180]. Default: 30.
    pub angle: f64,
}

/// Charging policies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ChargingPolicy {
    /// `threshold` where every robot has its own charger, `staggered` where robots share them
    /// (a fleet that drains together must not go to charge together:
    /// [`crate::input::scenario::Scenario::resolved`]).
    #[default]
    Auto,
    /// The paper's rule: charge only when below the threshold.
    Threshold,
    /// Also: an idle robot below `charging.level` goes to charge.
    Opportunistic,
    /// Also: an idle robot below its own level goes to charge when a charger is free for it
    /// (it never queues for one above the threshold). The levels are spread evenly between
    /// `robot.threshold` and `charging.level` over the fleet, so that a fleet that drains
    /// together does not go to charge together.
    Staggered,
}

impl ChargingPolicy {
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    fn is_auto(&self) -> bool {
        *self == ChargingPolicy::Auto
    }
}

/// Which charger a robot uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ChargerUse {
    /// `home` for the paper's fleets (robots on their departure zones), `shared` for fleets
    /// spread along the aisles ([`crate::input::scenario::Scenario::resolved`]).
    #[default]
    Auto,
    /// The paper: every robot charges at its own home charger.
    Home,
    /// Extension: the nearest free charger; robots queue when none is free.
    Shared,
}

impl ChargerUse {
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    fn is_auto(&self) -> bool {
        *self == ChargerUse::Auto
    }
}

/// When robots go to charge. The threshold rule always applies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Charging {
    /// `"threshold"` (the paper's rule), `"opportunistic"` or `"staggered"` (docs/charging.md),
    /// or `"auto"`: threshold with each robot's own charger, staggered with shared ones.
    /// Default: `"auto"`.
    #[serde(skip_serializing_if = "ChargingPolicy::is_auto")]
    pub policy: ChargingPolicy,
    /// With `"opportunistic"`: an idle robot below this energy goes to charge; with
    /// `"staggered"`: the highest of the robots' own levels (threshold < level ≤
    /// energy_full). Default: 7.
    pub level: f64,
    /// `"home"` (the paper) or `"shared"` (nearest free charger, queue when none), or
    /// `"auto"`: home for the paper's fleets (on their departure zones), shared for fleets
    /// spread along the aisles. Default: `"auto"`.
    #[serde(skip_serializing_if = "ChargerUse::is_auto")]
    #[schemars(extend("default" = "auto"))]
    pub chargers: ChargerUse,
    /// With `"staggered"` and shared chargers: a robot above the threshold goes only to a free
    /// charger at most this far by route, px (> 0), so that the chargers' time is spent
    /// charging rather than waiting for robots driving across the warehouse. Default: no
    /// limit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reach: Option<f64>,
}

impl Default for Charging {
    fn default() -> Self {
        Charging { policy: ChargingPolicy::Auto, level: 7.0, chargers: ChargerUse::Auto, reach: None }
    }
}

/// Weights of Cost_total = w_d·distance (px) + w_t·T (steps) + w_c·S (collisions).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
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

impl Default for RobotParams {
    fn default() -> Self {
        RobotParams { radius: 12.5, speed: 4.0, energy_full: 10.0, threshold: 3.5, consumption: 0.005, charge_rate: 0.05, idle_consumption: None }
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

impl JsonSchema for Tasks {
    fn schema_name() -> Cow<'static, str> {
        "Tasks".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "The goods to fetch, in order: a list of distinct cell ids, or { random = COUNT, seed = SEED } for COUNT distinct cells drawn with SEED.",
            "oneOf": [
                { "type": "array", "items": { "type": "integer", "minimum": 0 } },
                {
                    "type": "object",
                    "properties": {
                        "random": { "type": "integer", "minimum": 1, "description": "Number of distinct cells to draw." },
                        "seed": { "type": "integer", "minimum": 0, "default": 0, "description": "Seed of the portable generator (ChaCha8)." },
                    },
                    "required": ["random"],
                    "additionalProperties": false,
                },
            ],
        })
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

/// Workers on the floor (extension, docs/people.md): pickers who walk the aisles in either
/// direction, dwell at storage cells and return to a station, and the safety zones robots
/// keep around them. Lengths are in metres and speeds in metres per second, tied to the
/// layout's pixels by `px_per_m` and to steps by `step_seconds`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Humans {
    /// Number of workers (0 to 100000). Default: 0.
    pub count: u32,
    /// Walking speed, m/s (> 0, at most 10). Default: 1.2.
    pub speed: f64,
    /// Body radius, m (> 0, at most 5). Default: 0.25.
    pub radius: f64,
    /// Pixels per metre of the layout (0.01 to 1000). Default: 25 (the paper's 25 px robot is 1 m wide,
    /// its 50 px aisles 2 m).
    pub px_per_m: f64,
    /// Seconds per step (0.001 to 10). Default: 0.05 (the paper's T fits 0.0508 s per step).
    pub step_seconds: f64,
    /// Storage cells visited per pick tour (1 to 100). Default: 3.
    pub tour: u32,
    /// Steps spent picking at each cell (≥ 0). Default: 40.
    pub pick: u32,
    /// Steps spent at the station between tours (≥ 0). Default: 20.
    pub rest: u32,
    /// Seed of the tours and stations (ChaCha8). Default: 0.
    pub seed: u64,
    /// A CSV file of `person,cell` rows: each worker's tour, in order, repeated (instead of
    /// drawn tours).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub csv: Option<String>,
    /// Robot deceleration, m/s² (0.01 to 100): sizes the stopping distance v²/2a. Default: 5.
    pub decel: f64,
    /// Protective zone: stopping distance, one step of travel and this margin, m (0 to 100), beyond
    /// the robot's and the person's radii. A person ahead or beside inside it stops the robot.
    /// Default: 0.2.
    pub protective: f64,
    /// Warning zone: this much further than the protective zone, m (0 to 100); inside it a robot
    /// slows to `slow` of its speed. Default: 1.
    pub warning: f64,
    /// Speed factor in the warning zone, in (0, 1]. Default: 0.5.
    pub slow: f64,
}

impl Default for Humans {
    fn default() -> Self {
        Humans {
            count: 0,
            speed: 1.2,
            radius: 0.25,
            px_per_m: 25.0,
            step_seconds: 0.05,
            tour: 3,
            pick: 40,
            rest: 20,
            seed: 0,
            csv: None,
            decel: 5.0,
            protective: 0.2,
            warning: 1.0,
            slow: 0.5,
        }
    }
}

impl Humans {
    /// Checks every value against its range in [`crate::input::limits`] before anything is built
    /// from it; the error names the field as `humans.NAME`. `robot`: the zones grow with the
    /// robots' speed (their stopping distance).
    pub(crate) fn check(&self, robot: &RobotParams) -> crate::error::Result<()> {
        use crate::error::number;
        use crate::error::Error;
        use crate::input::limits::{MAX_COORD, MAX_HUMANS, MAX_TOUR};
        if self.count > MAX_HUMANS {
            return Err(Error::scenario("humans.count", self.count, format!("at most {MAX_HUMANS} (docs/limits.md)")));
        }
        for (field, v, (low, high), unit) in [
            ("humans.speed", self.speed, crate::input::limits::HUMAN_SPEED, "m/s"),
            ("humans.radius", self.radius, crate::input::limits::HUMAN_RADIUS, "m"),
            ("humans.px_per_m", self.px_per_m, crate::input::limits::HUMAN_PX_PER_M, "px per m"),
            ("humans.step_seconds", self.step_seconds, crate::input::limits::HUMAN_STEP_SECONDS, "s"),
            ("humans.decel", self.decel, crate::input::limits::HUMAN_DECEL, "m/s²"),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::scenario(field, number(v), "must be greater than 0"));
            }
            if !(low..=high).contains(&v) {
                let from = if low > 0.0 { format!("from {low}") } else { "above 0".into() };
                return Err(Error::scenario(field, number(v), format!("must be {from} and at most {high} {unit} (docs/limits.md)")));
            }
        }
        for (field, v) in [("humans.protective", self.protective), ("humans.warning", self.warning)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::scenario(field, number(v), "must be 0 or more"));
            }
            if v > crate::input::limits::HUMAN_ZONE_M {
                return Err(Error::scenario(field, number(v), format!("at most {} m (docs/limits.md)", crate::input::limits::HUMAN_ZONE_M)));
            }
        }
        if !(self.slow.is_finite() && self.slow > 0.0 && self.slow <= 1.0) {
            return Err(Error::scenario("humans.slow", number(self.slow), "must be in (0, 1]"));
        }
        if self.tour == 0 {
            return Err(Error::scenario("humans.tour", 0, "must be at least 1 cell"));
        }
        if self.tour > MAX_TOUR {
            return Err(Error::scenario("humans.tour", self.tour, format!("at most {MAX_TOUR} cells per tour (docs/limits.md)")));
        }
        // The zones around a robot (people/zones.rs) must stay within the layout's
        // coordinates; within the ranges above only a robot's stopping distance can leave
        // them, so its largest factor against the defaults is named.
        let m = self.px_per_m;
        let v = robot.speed / m / self.step_seconds;
        let stopping = v * v / (2.0 * self.decel) * m;
        let zones = robot.radius + self.radius * m + stopping + self.protective * m + robot.speed + self.warning * m;
        if !(zones.is_finite() && zones <= MAX_COORD) {
            if robot.radius >= stopping {
                return Err(Error::scenario(
                    "robot.radius",
                    number(robot.radius),
                    format!("makes the zones around robots larger than any layout (at most {MAX_COORD:.0e} px)"),
                ));
            }
            let d = Humans::default();
            let factors = [
                ("robot.speed", robot.speed, (robot.speed / RobotParams::default().speed).powi(2)),
                ("humans.px_per_m", m, d.px_per_m / m),
                ("humans.step_seconds", self.step_seconds, (d.step_seconds / self.step_seconds).powi(2)),
                ("humans.decel", self.decel, d.decel / self.decel),
            ];
            let (field, value, _) = factors.into_iter().max_by(|a, b| a.2.total_cmp(&b.2)).expect("four factors");
            return Err(Error::scenario(
                field,
                number(value),
                format!("a robot would need {} px to stop before a person; the zones must stay within {MAX_COORD:.0e} px (docs/people.md)", number(stopping)),
            ));
        }
        Ok(())
    }
}
