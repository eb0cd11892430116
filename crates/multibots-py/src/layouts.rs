//! Layouts: generating layout files, reading and checking them, and the layout JSON viewers
//! draw from.

use crate::errors::{engine, to_py};
use crate::scenario::PyScenario;
use multibots_core::world::{layout_file, resolve_layout};
use multibots_core::{HighwayGraph, Layout, LayoutParams, Scenario};
use pyo3::prelude::*;

/// Generates a grid layout and returns its layout file text (TOML), checked.
#[pyfunction]
#[pyo3(signature = (params_json, name="generated"))]
pub(crate) fn generate_layout_toml(py: Python<'_>, params_json: &str, name: &str) -> PyResult<String> {
    let params = LayoutParams::from_json(params_json).map_err(to_py)?;
    let name = name.to_string();
    engine(py, move || {
        let layout = Layout::generate(&params, &name)?;
        layout_file::check_layout(&layout)?;
        Ok(layout_file::to_toml(&layout, Some(params)))
    })
}

/// Reads and checks layout file text; returns the layout JSON.
#[pyfunction]
#[pyo3(signature = (text, source_name="layout"))]
pub(crate) fn layout_file_json(py: Python<'_>, text: &str, source_name: &str) -> PyResult<String> {
    let (text, source) = (text.to_string(), source_name.to_string());
    engine(py, move || {
        let layout = layout_file::from_toml(&text, &source)?;
        layout_file::check_layout(&layout)?;
        Ok(layout.to_json().to_string())
    })
}

/// Bytes of the routing tables of a scenario's layout, and the world's node count.
#[pyfunction]
pub(crate) fn routing_table_bytes(py: Python<'_>, scenario: &PyScenario) -> PyResult<(usize, usize)> {
    let s = scenario.inner.clone();
    engine(py, move || {
        let layout = resolve_layout(&s)?;
        layout.check_size()?;
        let g = HighwayGraph::new(&layout);
        Ok((g.table_bytes(), g.len()))
    })
}

/// The layout JSON of a named layout (`"paper"` or a layout file).
#[pyfunction]
pub(crate) fn layout_json(py: Python<'_>, name: &str) -> PyResult<String> {
    let s = Scenario { layout: name.to_string(), ..Scenario::paper(1, &[0]) };
    engine(py, move || Ok(resolve_layout(&s)?.to_json().to_string()))
}
