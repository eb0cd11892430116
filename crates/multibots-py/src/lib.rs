//! Python bindings of the MultiBots engine: conversions, error mapping and releasing the GIL.
//! No model logic lives here.
//!
//! | module | what it binds |
//! | --- | --- |
//! | `errors` | the exception tree, and the helper that runs engine code without the GIL |
//! | `scenario` | `Scenario` |
//! | `simulation` | `Simulation`: stepping a run and reading its state |
//! | `run` | `simulate`, `simulate_many`, `check_many` |
//! | `results` | a run's result as a dictionary |
//! | `layouts` | layout files and layout JSON |
//! | `codec` | state and event names, the paper's task lists, replay chunks |
//! | `envs` | the learning environments' engines: `Dispatcher`, `Fleet`, `VectorDispatch` |
//! | `lorr` | `LorrRun`: League of Robot Runners problems under the competition's rules |
//! | `strategy` | allocators: built-ins by name, Python objects, `module:Class` names |

use pyo3::prelude::*;

mod codec;
mod envs;
mod errors;
mod layouts;
mod lorr;
mod lorr_entries;
mod results;
mod run;
mod scenario;
mod simulation;
mod slicer;
mod strategy;

// `strategy` names these by their old paths.
pub(crate) use errors::{to_py, ScenarioError};

/// Panics inside the engine wrapper: lets the tests check that a panic becomes
/// `EngineError` and leaves the interpreter running.
#[pyfunction]
fn _panic_for_tests(py: Python<'_>) -> PyResult<()> {
    errors::engine(py, || -> Result<(), multibots_core::Error> { panic!("deliberate panic for the tests") })
}

/// The engine's limits (docs/limits.md), by the name of what they bound: the one definition
/// that Python's checks read.
fn limits(m: &Bound<'_, PyModule>) -> PyResult<()> {
    use multibots_core::input::limits as l;
    let d = pyo3::types::PyDict::new(m.py());
    d.set_item("robots", l::MAX_ROBOTS)?;
    d.set_item("steps", l::MAX_STEPS)?;
    d.set_item("humans", l::MAX_HUMANS)?;
    d.set_item("nodes", l::MAX_NODES)?;
    d.set_item("cells", l::MAX_CELLS)?;
    d.set_item("input_bytes", l::MAX_INPUT_BYTES)?;
    d.set_item("lorr_steps", l::MAX_LORR_STEPS)?;
    d.set_item("plan_time_limit_ms", l::MAX_PLAN_TIME_LIMIT_MS)?;
    m.add("LIMITS", d)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // Load NumPy's C API now: loaded lazily, a pending Ctrl-C would surface inside it.
    let _ = numpy::PyArray1::<f64>::zeros(py, 0, false);
    errors::register(m)?;
    m.add_class::<scenario::PyScenario>()?;
    m.add_class::<simulation::PySimulation>()?;
    m.add_class::<lorr::PyLorrRun>()?;
    m.add_function(wrap_pyfunction!(run::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(run::simulate_many, m)?)?;
    m.add_function(wrap_pyfunction!(run::check_many, m)?)?;
    m.add_function(wrap_pyfunction!(layouts::layout_json, m)?)?;
    m.add_function(wrap_pyfunction!(layouts::generate_layout_toml, m)?)?;
    m.add_function(wrap_pyfunction!(layouts::layout_file_json, m)?)?;
    m.add_function(wrap_pyfunction!(layouts::routing_table_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::toml_shape_error, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)?;
    codec::register(m)?;
    lorr::register(m)?;
    limits(m)?;
    strategy::register(m)?;
    envs::register(m)?;
    Ok(())
}
