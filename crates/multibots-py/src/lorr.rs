//! `LorrRun`: a League of Robot Runners problem run under the competition's rules
//! (`multibots_core::rules::grid`). Only conversions: the engine owns every rule.

use crate::errors::engine;
use multibots_core::input::lorr::Problem;
use multibots_core::output::grid_replay::GridReplay;
use multibots_core::rules::grid::{LorrOptions, LorrRun};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// Steps run between two checks for Ctrl-C: at 10,000 robots, about a second.
const SLICE: u32 = 20;

#[pyclass(module = "multibots._core", name = "LorrRun")]
pub(crate) struct PyLorrRun {
    run: LorrRun,
    /// The replay being written (`record=`), until `finish_record`.
    replay: Option<GridReplay>,
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
            let replay = record.map(|path| GridReplay::create(&path, &run)).transpose()?;
            Ok((run, replay))
        })?;
        Ok(PyLorrRun { run, replay })
    }

    /// Runs up to step `until` in slices, checking for Ctrl-C between them (and recording
    /// every step when a replay is open); the step reached.
    fn run_to(&mut self, py: Python<'_>, until: u32) -> PyResult<u32> {
        while self.run.t() < until {
            let stop = until.min(self.run.t().saturating_add(SLICE));
            let (run, replay) = (&mut self.run, &mut self.replay);
            engine(py, move || match replay {
                Some(w) => w.run_to(run, stop),
                None => Ok(run.run_to(stop)),
            })?;
            py.check_signals()?;
        }
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
        engine(py, move || run.write_result(&path))
    }

    /// Writes MultiBots' figures as JSON, atomically.
    fn write_figures(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let run = &self.run;
        engine(py, move || run.write_figures(&path))
    }
}
