//! `LorrRun`: a League of Robot Runners problem run under the competition's rules
//! (`multibots_core::rules::grid`). Only conversions: the engine owns every rule.

use crate::errors::engine;
use multibots_core::input::lorr::Problem;
use multibots_core::output::{lorr, replay::ReplayWriter};
use multibots_core::record::frame::FrameSink;
use multibots_core::rules::grid::{LorrOptions, LorrRun};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

#[pyclass(module = "multibots._core", name = "LorrRun")]
pub(crate) struct PyLorrRun {
    run: LorrRun,
    /// The replay being written (`record=`), until `finish_record`.
    replay: Option<ReplayWriter>,
}

#[pymethods]
impl PyLorrRun {
    #[new]
    #[pyo3(signature = (problem, planner="auto", scheduler="spread", seed=0, plan_time_limit_ms=None, team_size=None, record=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        problem: PathBuf,
        planner: &str,
        scheduler: &str,
        seed: u64,
        plan_time_limit_ms: Option<u64>,
        team_size: Option<usize>,
        record: Option<PathBuf>,
    ) -> PyResult<Self> {
        let options = LorrOptions { planner: planner.into(), scheduler: scheduler.into(), seed, plan_time_limit_ms };
        let (run, replay) = engine(py, move || {
            let run = LorrRun::new(Arc::new(Problem::load_team(&problem, team_size)?), options)?;
            let replay = record.map(|path| ReplayWriter::create(&path, &run, serde_json::Value::Null)).transpose()?;
            Ok((run, replay))
        })?;
        Ok(PyLorrRun { run, replay })
    }

    /// Runs up to step `until` (recording every step when a replay is open); the step
    /// reached.
    fn run_to(&mut self, py: Python<'_>, until: u32) -> PyResult<u32> {
        let steps = u64::from(until.saturating_sub(self.run.t()));
        crate::slicer::advance(py, &mut self.run, steps, self.replay.as_mut().map(|w| w as &mut (dyn FrameSink + Send)))?;
        Ok(self.run.t())
    }

    /// Finishes the replay opened with `record=` (its footer, then the rename into place).
    fn finish_record(&mut self, py: Python<'_>) -> PyResult<()> {
        let (run, replay) = (&self.run, self.replay.take());
        engine(py, move || replay.map_or(Ok(()), |w| w.finish(run)))
    }

    #[getter]
    fn t(&self) -> u32 {
        self.run.t()
    }

    #[getter]
    fn finished(&self) -> u64 {
        self.run.finished()
    }

    #[getter]
    fn planner(&self) -> String {
        self.run.planner().to_owned()
    }

    #[getter]
    fn team_size(&self) -> usize {
        self.run.problem().team_size()
    }

    #[getter]
    fn version(&self) -> &'static str {
        match self.run.problem().version {
            multibots_core::input::lorr::Version::Y2023 => "2023",
            multibots_core::input::lorr::Version::Y2024 => "2024",
        }
    }

    /// MultiBots' figures as a JSON object's text.
    fn figures_json(&self) -> String {
        serde_json::to_string(&self.run.figures()).expect("figures serialise")
    }

    /// Writes the competition's result file, atomically.
    fn write_result(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let run = &self.run;
        engine(py, move || lorr::write_result(run, &path))
    }

    /// Writes MultiBots' figures as JSON, atomically.
    fn write_figures(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let run = &self.run;
        engine(py, move || lorr::write_figures(run, &path))
    }
}

/// The files a run of the problem at `path` reads: the problem, then the map, agents and
/// tasks files it names (as far as its JSON can be read): what no output may be.
#[pyfunction]
#[allow(clippy::needless_pass_by_value)] // PyO3 converts the argument into an owned path
pub(crate) fn lorr_files(path: PathBuf) -> Vec<PathBuf> {
    multibots_core::input::lorr::problem_files(&path)
}

/// The built-in planners and schedulers, as `(name, what it does)`, the default first: the
/// one list the command line, Python and the docs read.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    use multibots_core::rules::grid::{planner, schedule};
    let py = m.py();
    m.add("LORR_PLANNERS", pyo3::types::PyTuple::new(py, planner::BUILT_INS.iter().map(|b| (b.name, b.about)))?)?;
    m.add("LORR_SCHEDULERS", pyo3::types::PyTuple::new(py, schedule::BUILT_INS.iter().map(|b| (b.name, b.about)))?)?;
    m.add_function(wrap_pyfunction!(lorr_files, m)?)?;
    Ok(())
}
