//! The fields of a 2026 problem (the Start-Kit's `driver.cpp` and `parse_delay_config`, tag
//! `v3.1.0`): `agentSize` (the side of a robot's square, in cells; default 1), `agentCounter`
//! (ticks per action; default 10) and `delayConfig`, whose eight fields are all required, as the
//! Start-Kit requires them. Each field is checked as the Start-Kit checks it, in its order, and
//! a field it leaves unchecked is bounded here where a value would break the run: a counter
//! below 1 (the Start-Kit aborts at the first move), a square larger than 8 cells, a delay
//! longer than 1,000,000,000 ticks.

use crate::error::{Error, Result};
use serde_json::Value;
use std::path::Path;

/// How robots are picked for a delay at each tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventModel {
    /// Each free robot with probability `pDelay`.
    Bernoulli,
    /// A Poisson(`teamSize · pDelay`) number of free robots, picked at random.
    Poisson,
}

/// How long a delay lasts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DurationModel {
    /// Uniform over `[minDelay, maxDelay]`.
    Uniform,
    /// A normal draw rounded and clamped to `[minDelay, maxDelay]`.
    Gaussian,
}

/// `delayConfig`.
#[derive(Clone, Debug, PartialEq)]
pub struct DelayConfig {
    /// The seed of `std::mt19937` (a negative JSON number wraps, as `get<unsigned>` does).
    pub seed: u32,
    pub min_delay: i32,
    pub max_delay: i32,
    pub event_model: EventModel,
    pub p_delay: f64,
    pub duration_model: DurationModel,
    pub gauss_mean_ratio: f64,
    pub gauss_std_ratio: f64,
}

/// What a 2026 problem adds to a 2024 one.
#[derive(Clone, Debug, PartialEq)]
pub struct Rules2026 {
    /// `agentSize`, as the Start-Kit's `float`.
    pub agent_size: f32,
    /// `agentCounter`: ticks an action takes.
    pub agent_counter: u32,
    /// `delayConfig`.
    pub delays: DelayConfig,
}

/// The longest delay a problem may ask for.
pub const MAX_DELAY: i64 = 1_000_000_000;
/// The largest robot (its square's side, in cells).
pub const MAX_AGENT_SIZE: f64 = 8.0;

/// Reads the 2026 fields of a problem's JSON object; `line_of(key)` is the line to name.
pub(super) fn read(path: &Path, json: &Value, line_of: &dyn Fn(&str) -> usize) -> Result<Rules2026> {
    let bad = |key: &str, what: String| Error::input_file(path, Some(line_of(key.rsplit('.').next().unwrap_or(key))), format!("{key}: {what}"));
    let agent_size = match json.get("agentSize") {
        None => 1.0,
        Some(v) => {
            let s = v.as_f64().ok_or_else(|| bad("agentSize", format!("expected a number, got {v}")))?;
            if !(s > 0.0 && s <= MAX_AGENT_SIZE) {
                return Err(bad("agentSize", format!("{s} must be above 0 and at most {MAX_AGENT_SIZE} cells")));
            }
            s as f32
        }
    };
    let agent_counter = match json.get("agentCounter") {
        None => 10,
        Some(v) => {
            // nlohmann's get<int> cuts a fraction off, as here.
            let c = v.as_f64().filter(|c| c.is_finite()).ok_or_else(|| bad("agentCounter", format!("expected a whole number, got {v}")))?;
            let c = c.trunc();
            if !(1.0..=1_000_000.0).contains(&c) {
                return Err(bad("agentCounter", format!("{c} must be from 1 to 1000000 (ticks per action)")));
            }
            c as u32
        }
    };
    let cfg = json.get("delayConfig").ok_or_else(|| bad("delayConfig", "the 2026 rules require it (the Start-Kit refuses a problem without it)".into()))?;
    if !cfg.is_object() {
        return Err(bad("delayConfig", format!("expected an object, got {cfg}")));
    }
    let field = |key: &str| cfg.get(key).ok_or_else(|| bad(&format!("delayConfig.{key}"), "missing (every field of delayConfig is required)".into()));
    let whole = |key: &str| -> Result<i64> {
        let v = field(key)?;
        v.as_i64()
            .or_else(|| v.as_u64().map(|u| u as i64))
            .or_else(|| v.as_f64().filter(|f| f.is_finite()).map(|f| f.trunc() as i64))
            .ok_or_else(|| bad(&format!("delayConfig.{key}"), format!("expected a whole number, got {v}")))
    };
    let number = |key: &str| -> Result<f64> {
        let v = field(key)?;
        v.as_f64().filter(|f| f.is_finite()).ok_or_else(|| bad(&format!("delayConfig.{key}"), format!("expected a number, got {v}")))
    };
    let text = |key: &str| -> Result<String> {
        let v = field(key)?;
        v.as_str().map(str::to_string).ok_or_else(|| bad(&format!("delayConfig.{key}"), format!("expected a string, got {v}")))
    };
    let seed = whole("seed")? as u32;
    let min_delay = whole("minDelay")?;
    if !(1..=MAX_DELAY).contains(&min_delay) {
        return Err(bad("delayConfig.minDelay", format!("{min_delay} must be above 0 (and at most {MAX_DELAY})")));
    }
    let max_delay = whole("maxDelay")?;
    if !(min_delay..=MAX_DELAY).contains(&max_delay) {
        return Err(bad("delayConfig.maxDelay", format!("{max_delay} must be at least minDelay ({min_delay}) and at most {MAX_DELAY}")));
    }
    let event_model = match text("eventModel")?.as_str() {
        "bernoulli" => EventModel::Bernoulli,
        "poisson" => EventModel::Poisson,
        other => return Err(bad("delayConfig.eventModel", format!("'{}' is neither \"bernoulli\" nor \"poisson\"", crate::error::shown(other)))),
    };
    let p_delay = number("pDelay")?;
    if !(0.0..=1.0).contains(&p_delay) {
        return Err(bad("delayConfig.pDelay", format!("{p_delay} must be from 0 to 1")));
    }
    let duration_model = match text("durationModel")?.as_str() {
        "uniform" => DurationModel::Uniform,
        "gaussian" => DurationModel::Gaussian,
        other => return Err(bad("delayConfig.durationModel", format!("'{}' is neither \"uniform\" nor \"gaussian\"", crate::error::shown(other)))),
    };
    let gauss_mean_ratio = number("gaussMeanRatio")?;
    let gauss_std_ratio = number("gaussStdRatio")?;
    if duration_model == DurationModel::Gaussian {
        if !(0.0..=1.0).contains(&gauss_mean_ratio) {
            return Err(bad("delayConfig.gaussMeanRatio", format!("{gauss_mean_ratio} must be from 0 to 1")));
        }
        if gauss_std_ratio < 0.0 {
            return Err(bad("delayConfig.gaussStdRatio", format!("{gauss_std_ratio} must be 0 or more")));
        }
    }
    let delays =
        DelayConfig { seed, min_delay: min_delay as i32, max_delay: max_delay as i32, event_model, p_delay, duration_model, gauss_mean_ratio, gauss_std_ratio };
    Ok(Rules2026 { agent_size, agent_counter, delays })
}
