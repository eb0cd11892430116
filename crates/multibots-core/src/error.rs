//! The engine's one error type. Every variant renders as a single line that names what was
//! wrong, so that the command line can print it as it is.

use thiserror::Error;

/// Everything the engine can refuse or fail at.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum Error {
    /// A scenario field has a value the model cannot run with.
    #[error("{field} = {value}: {reason}")]
    Scenario { field: String, value: String, reason: String },

    /// A scenario or layout file that is not valid TOML, or whose fields have the wrong type.
    #[error("{source_name}: {message}")]
    Parse { source_name: String, message: String },

    /// A layout whose graph or geometry cannot carry robots.
    #[error("layout {field}: {reason}")]
    Layout { field: String, reason: String },

    /// A layout file that cannot be read, is not valid TOML, or whose fields have the wrong
    /// type.
    #[error("{path}: {message}")]
    LayoutFile { path: String, message: String },

    /// An allocation strategy returned assignments the engine cannot carry out.
    #[error("allocator '{strategy}': {reason}")]
    Allocator { strategy: String, reason: String },

    /// A planner, scheduler or executor of a League of Robot Runners run (built in, or a
    /// Start-Kit Python file) failed, or answered what the rules cannot take; `entry` names
    /// it (`planner pyMAPFPlanner.py`).
    #[error("{entry}: {reason}")]
    Entry { entry: String, reason: String },

    /// Decisions from outside the engine (a learning environment, `Simulation::decide`) that
    /// it cannot carry out, or a call out of turn. The run is unchanged and can go on.
    #[error("decision at step {step}: {reason}")]
    Decision { step: u64, reason: String },

    /// Reading or writing a file failed.
    #[error("{path}: {message}")]
    Io { path: String, message: String },

    /// A problem file of another format (a League of Robot Runners problem, map, agents or
    /// tasks file) that cannot be read; `place` names the file and, where there is one, the
    /// line (`maps/a.map, line 7`).
    #[error("{place}: {message}")]
    InputFile { place: String, message: String },
}

impl Error {
    /// A scenario field's value refused for `reason`; the value is shortened and made inert
    /// ([`shown`]).
    #[must_use]
    pub fn scenario(field: impl Into<String>, value: impl std::fmt::Display, reason: impl Into<String>) -> Self {
        Error::Scenario { field: shown(&field.into()), value: shown(&value.to_string()), reason: reason.into() }
    }

    pub(crate) fn layout(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Layout { field: shown(&field.into()), reason: inert(&reason.into()) }
    }

    pub(crate) fn input_file(path: &std::path::Path, line: Option<usize>, message: impl Into<String>) -> Self {
        // The file's name is what the user needs: a long path keeps its end.
        let full = path.display().to_string();
        let count = full.chars().count();
        let tail: String = if count > 160 { format!("…{}", full.chars().skip(count - 160).collect::<String>()) } else { full };
        let shown = inert(&tail);
        let place = match line {
            Some(n) => format!("{shown}, line {n}"),
            None => shown,
        };
        Error::InputFile { place, message: inert(&message.into()) }
    }

    pub(crate) fn io(path: impl Into<String>, err: &std::io::Error) -> Self {
        Error::Io { path: shown(&path.into()), message: inert(&err.to_string()) }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// A value as it may appear in a message: at most 60 characters (with the full length when
/// cut), control characters escaped, so that a huge or hostile value never floods or drives
/// the terminal.
#[must_use]
pub fn shown(value: &str) -> String {
    shown_within(value, 60)
}

/// A number as a message shows it: as written for ordinary sizes (`12.5`, `2000000000`), in
/// exponent form past them (`1e308`, `2.5e-7`), `nan` and `inf` as TOML spells them, never
/// 300 digits.
#[must_use]
pub fn number(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.into()
    } else if v == 0.0 || (1e-4..1e16).contains(&v.abs()) {
        v.to_string()
    } else {
        format!("{v:e}")
    }
}

/// A message from a parser or the system, cut to 240 characters and with its control
/// characters escaped (it may quote the input).
#[must_use]
pub fn inert(message: &str) -> String {
    shown_within(message, 240)
}

fn shown_within(value: &str, max: usize) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    for (k, ch) in value.chars().enumerate() {
        if k == max {
            let _ = write!(out, "… ({} characters)", value.chars().count());
            break;
        }
        if ch.is_control() {
            out.extend(ch.escape_default());
        } else {
            out.push(ch);
        }
    }
    out
}

/// The known name closest to `name`, when it is near enough to be a slip of the keyboard: at
/// most a third of its letters (and at least one) to insert, delete or change. A name that
/// differs only in case is always near. `None` when nothing is, or two are equally near.
#[must_use]
pub fn did_you_mean(name: &str, known: impl IntoIterator<Item = impl AsRef<str>>) -> Option<String> {
    let lower = name.to_lowercase();
    let most = (name.chars().count() / 3).max(1);
    let mut best: Option<(usize, String)> = None;
    let mut tie = false;
    for k in known {
        let k = k.as_ref();
        if k == name {
            return None;
        }
        let d = if k.to_lowercase() == lower { 0 } else { edit_distance(&lower, &k.to_lowercase()) };
        if d > most {
            continue;
        }
        match &best {
            Some((b, _)) if d > *b => {}
            Some((b, _)) if d == *b => tie = true,
            _ => {
                best = Some((d, k.to_string()));
                tie = false;
            }
        }
    }
    best.filter(|_| !tie).map(|(_, k)| k)
}

/// Levenshtein distance, in characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_in_messages_are_short_and_inert() {
        assert_eq!(shown("M"), "M");
        assert_eq!(shown("a\u{1b}[31mb\n"), "a\\u{1b}[31mb\\n");
        let long = "x".repeat(10_000_000);
        let s = shown(&long);
        assert!(s.len() < 100 && s.ends_with("(10000000 characters)"), "{s}");
    }

    #[test]
    fn numbers_in_messages_are_short() {
        assert_eq!(number(12.5), "12.5");
        assert_eq!(number(2e9), "2000000000");
        assert_eq!(number(1e308), "1e308");
        assert_eq!(number(-2.5e-7), "-2.5e-7");
        assert_eq!(number(f64::NAN), "nan");
        assert_eq!(number(f64::NEG_INFINITY), "-inf");
        assert_eq!(number(0.0), "0");
    }
}
