//! `Scenario`: the engine's scenario schema, parsed and printed by the engine.

use crate::errors::{engine, to_py};
use multibots_core::{Scenario, Simulation};
use pyo3::prelude::*;

#[pyclass(module = "multibots._core", name = "Scenario", frozen)]
#[derive(Clone)]
pub(crate) struct PyScenario {
    pub inner: Scenario,
}

#[pymethods]
impl PyScenario {
    /// Parses TOML text; `source_name` prefixes error messages.
    #[staticmethod]
    fn from_toml(text: &str, source_name: &str) -> PyResult<Self> {
        Scenario::from_toml(text, source_name).map(|inner| PyScenario { inner }).map_err(to_py)
    }

    /// Parses JSON text.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        Scenario::from_json(text).map(|inner| PyScenario { inner }).map_err(to_py)
    }

    fn to_toml(&self) -> String {
        self.inner.to_toml()
    }

    fn to_json(&self) -> String {
        self.inner.to_json()
    }

    /// The allocator's name, without a round trip through JSON (checked for every run of a
    /// batch).
    #[getter]
    fn allocator(&self) -> &str {
        &self.inner.allocator
    }

    /// Checks every field, against the layout too.
    fn validate(&self, py: Python<'_>) -> PyResult<()> {
        let s = self.inner.clone();
        let alloc = crate::strategy::for_validation(py, &s)?;
        engine(py, move || Simulation::with_allocator(&s, alloc).map(drop))
    }

    /// What the scenario should be told before it runs (a fleet its chargers cannot keep
    /// charged), one line each.
    fn warnings(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        let s = self.inner.clone();
        engine(py, move || multibots_core::rules::warnings(&s))
    }

    /// The scenario with every "auto" choice made for its layout.
    fn resolved(&self, py: Python<'_>) -> PyResult<PyScenario> {
        let s = self.inner.clone();
        engine(py, move || multibots_core::rules::resolved(&s)).map(|inner| PyScenario { inner })
    }

    /// The files a run of the scenario reads, as (field, path): what no output may be.
    fn files(&self) -> Vec<(&'static str, std::path::PathBuf)> {
        self.inner.files()
    }

    /// The scenario's task list as cell ids (random lists drawn).
    fn cells(&self, py: Python<'_>) -> PyResult<Vec<u32>> {
        let s = self.inner.clone();
        engine(py, move || s.cells(multibots_core::world::resolve_layout(&s)?.cells.len()))
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.inner == other.inner
    }
}

/// What is wrong with the shape of TOML text (nesting too deep, a key too long), as one line
/// (`line N: ...`), or None: checked before Python's own TOML parser reads a file.
#[pyfunction]
pub(crate) fn toml_shape_error(text: &str) -> Option<String> {
    multibots_core::input::files::check_toml_shape(text).err()
}
