//! Where a run's allocator comes from: a built-in named by the scenario, or a Python object.

use multibots_core::{alloc, Allocator, Scenario};
use pyo3::prelude::*;

/// The allocator for a run: `allocator` if Python gave one, else the scenario's built-in.
pub(crate) fn make_allocator(py: Python<'_>, scenario: &Scenario, allocator: Option<PyObject>) -> PyResult<Box<dyn Allocator>> {
    let _ = py;
    if allocator.is_some() {
        return Err(crate::ScenarioError::new_err("allocator: Python allocators are not supported yet"));
    }
    alloc::built_in(scenario).map_err(crate::to_py)
}
