//! League of Robot Runners problems (the 2023 and 2024 competitions), read and checked: the
//! problem JSON, the MovingAI map (`map.rs`), the agents file and both task formats
//! (`lists.rs`). Formats as in the Start-Kit's `Input_Output_Format.md`; a file that does
//! not fit is one error that names the file and the line ([`crate::Error::InputFile`]).
//!
//! The problem JSON's paths are relative to the folder that holds it. Checks beyond the
//! Start-Kit's: every start and every errand is a free cell of the map, and no two robots
//! start on one cell; an instance that breaks these could not be played by the rules.

mod lists;
mod map;
pub mod y2026;

pub use map::GridMap;
pub use y2026::{DelayConfig, DurationModel, EventModel, Rules2026};

use crate::error::{Error, Result};
use crate::input::files::read_text;
use crate::input::limits::{MAX_INPUT_BYTES, MAX_REVEALED_TASKS, MAX_ROBOTS};
use std::path::{Path, PathBuf};

/// The largest task file read: the 2023 archive's task files hold up to 500,000 lines.
const MAX_TASK_BYTES: u64 = 256 << 20;

/// Which competition's task rules a problem follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    /// 2023: round-robin errands, one cell per task (`taskAssignmentStrategy: roundrobin`).
    Y2023,
    /// 2024: a task pool, a scheduler, tasks of several errands (`version: "2024 LoRR"`).
    Y2024,
    /// 2026: the 2024 tasks, actions of several ticks, robots as squares, delays and an
    /// executor (`version: "2026 LoRR"`, or any problem with a `delayConfig`).
    Y2026,
}

/// A LoRR problem, read whole.
#[derive(Clone, Debug)]
pub struct Problem {
    /// The problem file.
    pub path: PathBuf,
    /// The grid, with its obstacles.
    pub map: GridMap,
    /// Start cell (`row * cols + col`) of each of the `teamSize` robots.
    pub starts: Vec<u32>,
    /// The task file's lines, in order: one errand cell each in 2023, one or more in 2024.
    pub tasks: Vec<Vec<u32>>,
    /// `numTasksReveal`: 2023, errands each robot sees ahead; 2024, the pool is
    /// `int(numTasksReveal * teamSize)` tasks.
    pub num_tasks_reveal: f64,
    /// The task rules.
    pub version: Version,
    /// The 2026 rules' fields (`agentSize`, `agentCounter`, `delayConfig`), under them.
    pub y2026: Option<Rules2026>,
}

#[derive(serde::Deserialize)]
#[serde(rename_all = "camelCase")]
struct ProblemJson {
    map_file: String,
    agent_file: String,
    task_file: String,
    team_size: i64,
    #[serde(default = "one")]
    num_tasks_reveal: f64,
    #[serde(default)]
    task_assignment_strategy: Option<String>,
    #[serde(default)]
    version: Option<String>,
    #[serde(default)]
    delay_config: Option<serde_json::Value>,
}

fn one() -> f64 {
    1.0
}

impl Problem {
    /// Reads a problem JSON and the files it names.
    pub fn load(path: &Path) -> Result<Problem> {
        Problem::load_team(path, None)
    }

    /// Reads a problem with a team of `team` robots instead of its `teamSize`: the first
    /// `team` agents of its agents file, and (2024) a task pool of `int(numTasksReveal ·
    /// team)`, as the competition sizes it for a team. Sweeps over the team size use it.
    pub fn load_team(path: &Path, team: Option<usize>) -> Result<Problem> {
        let text = read_text(path, MAX_INPUT_BYTES).map_err(|m| Error::input_file(path, None, m))?;
        // Nesting and key length checked before the parser recurses or allocates (docs/limits.md).
        crate::input::files::check_json_shape(&text).map_err(|m| Error::input_file(path, None, m))?;
        // serde would take a list as the fields in order: only an object is a problem.
        let kind = match text.trim_start().chars().next() {
            Some('{') => None,
            Some('[') => Some("a list"),
            Some('"') => Some("text"),
            Some('n') => Some("null"),
            Some('t' | 'f') => Some("true or false"),
            Some(c) if c == '-' || c.is_ascii_digit() => Some("a number"),
            Some(_) => Some("not JSON"),
            None => Some("an empty file"),
        };
        if let Some(kind) = kind {
            return Err(Error::input_file(path, Some(1), format!("expected a JSON object with mapFile, agentFile, taskFile and teamSize, not {kind}")));
        }
        let mut de = serde_json::Deserializer::from_str(&text);
        let json: ProblemJson = serde_path_to_error::deserialize(&mut de).map_err(|e| field_error(path, &e))?;
        let line_of = |key: &str| text.lines().position(|l| l.contains(&format!("\"{key}\""))).map_or(1, |i| i + 1);
        // The 2026 Start-Kit plays any problem with a delayConfig under its rules (it never
        // reads `version`), and refuses one without.
        let version = match (&json.version, &json.task_assignment_strategy) {
            _ if json.delay_config.is_some() => Version::Y2026,
            (Some(v), _) if v.contains("2026") => Version::Y2026,
            (Some(v), _) if v.contains("2024") => Version::Y2024,
            (Some(v), _) => {
                return Err(Error::input_file(
                    path,
                    Some(line_of("version")),
                    format!("version '{v}' is not one this reader knows (\"2024 LoRR\", \"2026 LoRR\")"),
                ))
            }
            (None, Some(s)) if s == "roundrobin" => Version::Y2023,
            (None, Some(s)) => {
                return Err(Error::input_file(
                    path,
                    Some(line_of("taskAssignmentStrategy")),
                    format!("taskAssignmentStrategy '{s}': only 'roundrobin' is a rule of the 2023 competition"),
                ))
            }
            (None, None) => Version::Y2023,
        };
        if json.team_size < 1 || json.team_size > i64::from(MAX_ROBOTS) {
            return Err(Error::input_file(
                path,
                Some(line_of("teamSize")),
                format!("teamSize = {}: expected a number of robots from 1 to {MAX_ROBOTS} (docs/limits.md)", json.team_size),
            ));
        }
        if !(json.num_tasks_reveal.is_finite() && json.num_tasks_reveal > 0.0) {
            return Err(Error::input_file(
                path,
                Some(line_of("numTasksReveal")),
                format!("numTasksReveal = {}: expected a number above 0", crate::error::number(json.num_tasks_reveal)),
            ));
        }
        match team {
            Some(0) => return Err(crate::error::Error::scenario("robots", 0, "must be at least 1")),
            Some(t) if t > MAX_ROBOTS as usize => return Err(crate::error::Error::scenario("robots", t, format!("at most {MAX_ROBOTS}"))),
            _ => {}
        }
        let n = team.unwrap_or(json.team_size as usize);
        // The tasks revealed at the start are allocated before anything runs: 2024, the pool of
        // int(numTasksReveal · teamSize); 2023, int(numTasksReveal) errands ahead of each robot.
        let revealed = match version {
            Version::Y2024 | Version::Y2026 => json.num_tasks_reveal * n as f64,
            Version::Y2023 => json.num_tasks_reveal.floor().max(1.0) * n as f64,
        };
        if revealed > MAX_REVEALED_TASKS as f64 {
            return Err(Error::input_file(
                path,
                Some(line_of("numTasksReveal")),
                format!(
                    "numTasksReveal = {}: with {n} robots it reveals {} tasks at once; at most {MAX_REVEALED_TASKS} (docs/limits.md)",
                    crate::error::number(json.num_tasks_reveal),
                    crate::error::number(revealed.floor())
                ),
            ));
        }
        let base = path.parent().unwrap_or(Path::new("."));
        let map = GridMap::load(&base.join(&json.map_file))?;
        let agent_path = base.join(&json.agent_file);
        let starts = lists::agents(&agent_path, &read(&agent_path, MAX_INPUT_BYTES)?, n, &map)?;
        let task_path = base.join(&json.task_file);
        let task_text = read(&task_path, MAX_TASK_BYTES)?;
        let tasks = match version {
            Version::Y2023 => lists::tasks_2023(&task_path, &task_text, &map)?,
            Version::Y2024 | Version::Y2026 => lists::tasks_2024(&task_path, &task_text, &map)?,
        };
        let y2026 = match version {
            Version::Y2026 => {
                let whole: serde_json::Value = serde_json::from_str(&text)
                    .map_err(|e| Error::input_file(path, Some(e.line().max(1)), e.to_string().lines().next().unwrap_or_default().to_string()))?;
                Some(y2026::read(path, &whole, &line_of)?)
            }
            _ => None,
        };
        if version != Version::Y2023 && (json.num_tasks_reveal * n as f64) < 1.0 {
            return Err(Error::input_file(path, Some(line_of("numTasksReveal")), "numTasksReveal * teamSize is below 1: the task pool would be empty"));
        }
        Ok(Problem { path: path.to_path_buf(), map, starts, tasks, num_tasks_reveal: json.num_tasks_reveal, version, y2026 })
    }

    /// The number of robots (`teamSize`).
    #[must_use]
    pub fn team_size(&self) -> usize {
        self.starts.len()
    }

    /// 2024: the size of the task pool, `int(numTasksReveal * teamSize)`; 2023: the errands
    /// each robot sees ahead, `int(numTasksReveal)` and at least 1.
    #[must_use]
    pub fn reveal(&self) -> usize {
        match self.version {
            Version::Y2024 => (self.num_tasks_reveal * self.team_size() as f64) as usize,
            // The 2026 Start-Kit multiplies two floats.
            Version::Y2026 => (self.num_tasks_reveal as f32 * self.team_size() as f32) as usize,
            Version::Y2023 => (self.num_tasks_reveal as usize).max(1),
        }
    }
}

/// The files a problem names beside itself (map, agents, tasks), as far as its JSON can be
/// read, after the problem file itself: what a run of it reads, and so what a command must
/// never write over. A problem that cannot be read names only itself (its run then says why).
#[must_use]
pub fn problem_files(path: &Path) -> Vec<PathBuf> {
    let mut out = vec![path.to_path_buf()];
    let Ok(text) = read_text(path, MAX_INPUT_BYTES) else { return out };
    let Ok(value) = serde_json::from_str::<serde_json::Value>(&text) else { return out };
    let base = path.parent().unwrap_or(Path::new("."));
    for key in ["mapFile", "agentFile", "taskFile"] {
        if let Some(name) = value.get(key).and_then(serde_json::Value::as_str) {
            out.push(base.join(name));
        }
    }
    out
}

fn read(path: &Path, limit: u64) -> Result<String> {
    read_text(path, limit).map_err(|m| Error::input_file(path, None, m))
}

/// A problem JSON that does not fit its fields, in the words of the scenario errors: the
/// field, the value as written and what was expected (`teamSize = "4": expected a whole
/// number`), with the line; never serde's or Rust's words.
fn field_error(path: &Path, e: &serde_path_to_error::Error<serde_json::Error>) -> Error {
    let line = Some(e.inner().line().max(1));
    let field = e.path().to_string();
    let text = e.inner().to_string();
    let text = text.lines().next().unwrap_or_default();
    let text = text.rfind(" at line ").map_or(text, |k| &text[..k]).trim();
    let syntax = matches!(e.inner().classify(), serde_json::error::Category::Syntax | serde_json::error::Category::Eof);
    let message = if syntax {
        format!("not JSON: {}", crate::error::inert(text))
    } else if let Some(name) = text.strip_prefix("missing field `").and_then(|m| m.strip_suffix('`')) {
        format!("{name}: missing (a problem names its mapFile, agentFile, taskFile and teamSize)")
    } else {
        crate::input::messages::plain(&field, text, None)
    };
    Error::input_file(path, line, message)
}

#[cfg(test)]
mod tests;
