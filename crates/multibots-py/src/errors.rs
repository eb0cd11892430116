//! The one place engine errors become Python exceptions, and the one helper that runs engine
//! code without the GIL.

use multibots_core::Error;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};

create_exception!(multibots._core, MultibotsError, PyException, "Base class of every MultiBots error.");
create_exception!(multibots._core, ScenarioError, MultibotsError, "A scenario field or file the model cannot run with.");
create_exception!(multibots._core, LayoutError, MultibotsError, "A layout robots cannot use, or a layout file that cannot be read.");
create_exception!(multibots._core, AllocatorError, MultibotsError, "A strategy returned assignments the engine cannot carry out.");
create_exception!(multibots._core, EngineError, MultibotsError, "An internal error of the engine (a bug: please report it).");
create_exception!(
    multibots._core,
    DecisionError,
    MultibotsError,
    "Decisions taken from outside the engine (a learning environment's action) that it cannot carry out."
);

/// Maps an engine error to its exception.
#[allow(clippy::needless_pass_by_value)] // by value so that it serves as `map_err(to_py)`
pub(crate) fn to_py(e: Error) -> PyErr {
    let msg = e.to_string();
    match e {
        Error::Scenario { .. } | Error::Parse { .. } | Error::InputFile { .. } => ScenarioError::new_err(msg),
        Error::Layout { .. } | Error::LayoutFile { .. } => LayoutError::new_err(msg),
        Error::Allocator { .. } | Error::Entry { .. } => Python::with_gil(|py| crate::strategy::with_cause(py, AllocatorError::new_err(msg))),
        Error::Decision { .. } => DecisionError::new_err(msg),
        Error::Io { .. } => MultibotsError::new_err(msg),
    }
}

/// The message of a panic payload.
pub(crate) fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic.downcast_ref::<&str>().map(|s| (*s).to_string()).or_else(|| panic.downcast_ref::<String>().cloned()).unwrap_or_default()
}

/// Runs engine code without the GIL, turning errors and panics into exceptions.
pub(crate) fn engine<T: Send>(py: Python<'_>, f: impl FnOnce() -> Result<T, Error> + Send) -> PyResult<T> {
    match py.allow_threads(|| catch_unwind(AssertUnwindSafe(f))) {
        Ok(r) => r.map_err(to_py),
        Err(panic) => Err(EngineError::new_err(format!("internal error in the engine: {}", panic_message(&*panic)))),
    }
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("MultibotsError", py.get_type::<MultibotsError>())?;
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("LayoutError", py.get_type::<LayoutError>())?;
    m.add("AllocatorError", py.get_type::<AllocatorError>())?;
    m.add("EngineError", py.get_type::<EngineError>())?;
    m.add("DecisionError", py.get_type::<DecisionError>())?;
    Ok(())
}
