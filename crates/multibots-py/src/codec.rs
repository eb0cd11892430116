//! The engine's names and its replay codec, for the Python reader and the viewer.

use crate::errors::MultibotsError;
use multibots_core::output::codec;
use multibots_core::{EventKind, State};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

/// Inflates and decodes a replay chunk's zlib stream into NumPy arrays, refusing to inflate
/// past `limit` bytes. Errors are one line (`ValueError` subclasses of `MultibotsError` are
/// raised by the reader, which adds the file and the chunk).
#[pyfunction]
pub(crate) fn decode_chunk<'py>(py: Python<'py>, compressed: &Bound<'py, PyBytes>, limit: usize) -> PyResult<Bound<'py, PyDict>> {
    let bytes = compressed.as_bytes().to_vec();
    let c = py.allow_threads(move || codec::inflate(&bytes, limit).and_then(|raw| codec::decode(&raw))).map_err(MultibotsError::new_err)?;
    let (k, n, e) = (c.frames as usize, c.robots as usize, c.events.len() / 4);
    let d = PyDict::new(py);
    d.set_item("first_frame", c.first_frame)?;
    d.set_item("frames", c.frames)?;
    d.set_item("robots", c.robots)?;
    d.set_item("counters", PyArray1::from_vec(py, c.counters).reshape([k, 3])?)?;
    d.set_item("x", PyArray1::from_vec(py, c.x).reshape([k, n])?)?;
    d.set_item("y", PyArray1::from_vec(py, c.y).reshape([k, n])?)?;
    d.set_item("events", PyArray1::from_vec(py, c.events).reshape([e, 4])?)?;
    d.set_item("energy_u16", PyArray1::from_vec(py, c.energy).reshape([k, n])?)?;
    d.set_item("heading_u8", PyArray1::from_vec(py, c.heading).reshape([k, n])?)?;
    d.set_item("state_raw", PyArray1::from_vec(py, c.state).reshape([k, n])?)?;
    let p = c.people as usize;
    d.set_item("people_x", PyArray1::from_vec(py, c.people_x).reshape([k, p])?)?;
    d.set_item("people_y", PyArray1::from_vec(py, c.people_y).reshape([k, p])?)?;
    Ok(d)
}

/// Inflates a replay chunk's zlib stream, refusing to inflate past `limit` bytes, and checks
/// that its sections fit its head; returns the decompressed bytes.
#[pyfunction]
pub(crate) fn inflate_chunk<'py>(py: Python<'py>, compressed: &Bound<'py, PyBytes>, limit: usize) -> PyResult<Bound<'py, PyBytes>> {
    let bytes = compressed.as_bytes().to_vec();
    let raw = py.allow_threads(move || codec::inflate(&bytes, limit).and_then(|raw| codec::decode(&raw).map(|_| raw))).map_err(MultibotsError::new_err)?;
    Ok(PyBytes::new(py, &raw))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("STATE_NAMES", pyo3::types::PyTuple::new(py, State::ALL.iter().map(|s| s.name()))?)?;
    let events = PyDict::new(py);
    for k in EventKind::ALL {
        events.set_item(k.code(), k.name())?;
    }
    m.add("EVENT_NAMES", events)?;
    m.add("PAPER_TASKS", pyo3::types::PyTuple::new(py, multibots_core::input::scenario::PAPER_TASKS.iter().map(|g| g.to_vec()))?)?;
    m.add("BYTES_PER_ROBOT_STEP", codec::BYTES_PER_ROBOT_STEP)?;
    m.add("REPLAY_VERSION", codec::VERSION)?;
    m.add("REPLAY_MAGIC", PyBytes::new(py, codec::MAGIC))?;
    m.add("MARKED", codec::MARKED)?;
    m.add("STATE_MASK", codec::STATE_MASK)?;
    m.add("HEADING_STEPS", codec::HEADING_STEPS)?;
    m.add("ENERGY_SCALE", codec::ENERGY_SCALE)?;
    m.add("MOVING_STATES", pyo3::types::PyTuple::new(py, State::ALL.iter().filter(|s| s.travels()).map(|&s| s as u8).collect::<Vec<_>>())?)?;
    m.add_function(wrap_pyfunction!(decode_chunk, m)?)?;
    m.add_function(wrap_pyfunction!(inflate_chunk, m)?)?;
    Ok(())
}
