//! Whole runs: `simulate` (one run, optionally recorded) and `simulate_many` (a batch on the
//! engine's thread pool). Both release the GIL and stop on Ctrl-C.

use crate::errors::engine;
use crate::results::result_dict;
use crate::scenario::PyScenario;
use multibots_core::output::replay::ReplayWriter;
use multibots_core::record::frame::FrameSink;
use multibots_core::rules::batch;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::time::Duration;

/// How often a waiting batch looks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs a scenario to its end; records a replay to `record` if given. Ctrl-C stops it.
#[pyfunction]
#[pyo3(signature = (scenario, record=None, allocator=None))]
pub(crate) fn simulate<'py>(py: Python<'py>, scenario: &PyScenario, record: Option<PathBuf>, allocator: Option<PyObject>) -> PyResult<Bound<'py, PyDict>> {
    let s = scenario.inner.clone();
    let mut sim = crate::strategy::new_simulation(py, &s, allocator)?;
    let mut writer = match record {
        Some(path) => {
            let sim = &sim;
            Some(engine(py, move || ReplayWriter::create(&path, sim, serde_json::json!({"scenario": s.to_toml()})))?)
        }
        None => None,
    };
    // An unfinished replay is removed on drop (Ctrl-C, an error).
    crate::slicer::advance(py, &mut sim, u64::MAX, writer.as_mut().map(|w| w as &mut (dyn FrameSink + Send)))?;
    if let Some(w) = writer {
        let sim = &sim;
        engine(py, move || w.finish(sim))?;
    }
    result_dict(py, &sim.result())
}

/// A batch's watch: goes on until Ctrl-C, which it keeps in `interrupted` to raise.
fn until_interrupted(interrupted: &mut Option<PyErr>) -> impl FnMut(usize) -> bool + '_ {
    |_| {
        #[allow(clippy::redundant_closure_for_method_calls)] // the method's lifetime is not general enough
        let signals = Python::with_gil(|py| py.check_signals());
        *interrupted = signals.err();
        interrupted.is_none()
    }
}

/// Runs many scenarios on `workers` threads (0: one per core); results come back in the
/// order given. Ctrl-C stops every worker.
#[pyfunction]
#[pyo3(signature = (scenarios, workers=0))]
pub(crate) fn simulate_many(py: Python<'_>, scenarios: Vec<PyScenario>, workers: usize) -> PyResult<Vec<Bound<'_, PyDict>>> {
    let list: Vec<_> = scenarios.into_iter().map(|s| s.inner).collect();
    let mut interrupted = None;
    let results = engine(py, || Ok(batch::run_many(&list, workers, SIGNAL_POLL, until_interrupted(&mut interrupted))))?;
    if let Some(e) = interrupted {
        return Err(e);
    }
    let results = results.expect("only an interrupt cancels the batch");
    results.into_iter().map(|r| r.map_err(crate::errors::to_py).and_then(|r| result_dict(py, &r))).collect()
}

/// Checks many scenarios as `Scenario.validate` would, on `workers` threads (0: one per core),
/// building each layout once; returns the first failure in the order given (its index and
/// the error `validate` would raise), or `None`. Python strategies are loaded once per name.
/// Ctrl-C stops it, as it stops `simulate_many`.
#[pyfunction]
#[pyo3(signature = (scenarios, workers=0))]
pub(crate) fn check_many(py: Python<'_>, scenarios: Vec<PyScenario>, workers: usize) -> PyResult<Option<(usize, PyObject)>> {
    let mut loaded: Vec<(String, Option<PyErr>)> = Vec::new();
    let mut list = Vec::with_capacity(scenarios.len());
    let mut first_python_error: Option<(usize, PyErr)> = None;
    for (k, s) in scenarios.into_iter().enumerate() {
        let mut s = s.inner;
        if s.allocator.contains(':') {
            // The engine checks everything else with a stand-in; the strategy is loaded here.
            let verdict = if let Some((_, e)) = loaded.iter().find(|(name, _)| *name == s.allocator) {
                e.as_ref().map(|e| e.clone_ref(py))
            } else {
                let e = crate::strategy::for_validation(py, &s).err();
                loaded.push((s.allocator.clone(), e.as_ref().map(|e| e.clone_ref(py))));
                e
            };
            if let (Some(e), None) = (verdict, &first_python_error) {
                first_python_error = Some((k, e));
            }
            s.allocator = "in-turn".into();
        }
        list.push(s);
    }
    let mut interrupted = None;
    let verdicts = engine(py, || Ok(batch::check_many_until(&list, workers, SIGNAL_POLL, until_interrupted(&mut interrupted))));
    let verdicts = match (verdicts, interrupted) {
        (_, Some(e)) | (Err(e), None) => return Err(e),
        (Ok(v), None) => v.expect("only an interrupt cancels the checks"),
    };
    let engine_error = verdicts.into_iter().enumerate().find_map(|(k, v)| v.err().map(|e| (k, e)));
    let first = match (engine_error, first_python_error) {
        (Some((k, e)), Some((j, _))) if k < j => Some((k, crate::errors::to_py(e))),
        (_, Some((j, e))) => Some((j, e)),
        (Some((k, e)), None) => Some((k, crate::errors::to_py(e))),
        (None, None) => None,
    };
    Ok(first.map(|(k, e)| (k, e.into_value(py).into_any())))
}
