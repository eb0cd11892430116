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
    /// ([`crate::input::limits::shown`]).
    #[must_use]
    pub fn scenario(field: impl Into<String>, value: impl std::fmt::Display, reason: impl Into<String>) -> Self {
        Error::Scenario { field: crate::input::limits::shown(&field.into()), value: crate::input::limits::shown(&value.to_string()), reason: reason.into() }
    }

    pub(crate) fn layout(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Layout { field: crate::input::limits::shown(&field.into()), reason: crate::input::limits::inert(&reason.into()) }
    }

    pub(crate) fn input_file(path: &std::path::Path, line: Option<usize>, message: impl Into<String>) -> Self {
        // The file's name is what the user needs: a long path keeps its end.
        let full = path.display().to_string();
        let count = full.chars().count();
        let tail: String = if count > 160 { format!("…{}", full.chars().skip(count - 160).collect::<String>()) } else { full };
        let shown = crate::input::limits::inert(&tail);
        let place = match line {
            Some(n) => format!("{shown}, line {n}"),
            None => shown,
        };
        Error::InputFile { place, message: crate::input::limits::inert(&message.into()) }
    }

    pub(crate) fn io(path: impl Into<String>, err: &std::io::Error) -> Self {
        Error::Io { path: crate::input::limits::shown(&path.into()), message: crate::input::limits::inert(&err.to_string()) }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// One line for a TOML file that does not fit its schema: the field's path, or the line for
/// a syntax error, then the first line of the parser's message.
pub(crate) fn toml_message(text: &str, e: serde_path_to_error::Error<toml::de::Error>) -> String {
    // The path holds the user's keys, which may be anything (a control character, 10 MB).
    let path = crate::input::limits::shown(&e.path().to_string());
    let inner = e.into_inner();
    let msg = crate::input::limits::inert(inner.message().lines().next().unwrap_or_default().trim());
    if !path.is_empty() && path != "." {
        return format!("{path}: {msg}");
    }
    match inner.span() {
        Some(span) => format!("line {}: {msg}", text[..span.start.min(text.len())].matches('\n').count() + 1),
        None => msg,
    }
}
