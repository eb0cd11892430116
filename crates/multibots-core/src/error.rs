//! The engine's one error type. Every variant renders as a single line that names what was
//! wrong, so that the command line can print it as it is.

use thiserror::Error;

/// Everything the engine can refuse or fail at.
#[derive(Debug, Error)]
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

    /// An allocation strategy returned assignments the engine cannot carry out.
    #[error("allocator '{strategy}': {reason}")]
    Allocator { strategy: String, reason: String },

    /// Reading or writing a file failed.
    #[error("{path}: {message}")]
    Io { path: String, message: String },
}

impl Error {
    pub(crate) fn scenario(field: impl Into<String>, value: impl std::fmt::Display, reason: impl Into<String>) -> Self {
        Error::Scenario { field: field.into(), value: value.to_string(), reason: reason.into() }
    }

    pub(crate) fn layout(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Layout { field: field.into(), reason: reason.into() }
    }

    pub(crate) fn io(path: impl Into<String>, err: &std::io::Error) -> Self {
        Error::Io { path: path.into(), message: err.to_string() }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
