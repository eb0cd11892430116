//! `LorrRun`: a League of Robot Runners problem run under the competition's rules
//! (`multibots_core::rules::grid`: `LorrRun` for 2023 and 2024, `Lorr26` for 2026). Only
//! conversions: the engine owns every rule.

use crate::errors::engine;
use multibots_core::input::lorr::{Problem, Version};
use multibots_core::output::{lorr, lorr26, replay::ReplayWriter};
use multibots_core::record::frame::FrameSink;
use multibots_core::rules::grid::{Figures, Lorr26, LorrOptions, LorrRun};
use multibots_core::rules::Run;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// A run under the 2023/2024 rules or under the 2026 rules, by the problem's version.
pub(crate) enum Rules {
    Steps(Box<LorrRun>),
    Ticks(Box<Lorr26>),
}

impl Rules {
    fn as_run(&mut self) -> &mut (dyn Run + Send) {
        match self {
            Rules::Steps(r) => &mut **r,
            Rules::Ticks(r) => &mut **r,
        }
    }

    fn t(&self) -> u32 {
        match self {
            Rules::Steps(r) => r.t(),
            Rules::Ticks(r) => r.t(),
        }
    }

    fn problem(&self) -> &Problem {
        match self {
            Rules::Steps(r) => r.problem(),
            Rules::Ticks(r) => r.problem(),
        }
    }

    fn figures(&self) -> Figures {
        match self {
            Rules::Steps(r) => r.figures(),
            Rules::Ticks(r) => r.figures(),
        }
    }
}

#[pyclass(module = "multibots._core", name = "LorrRun")]
pub(crate) struct PyLorrRun {
    run: Rules,
    /// The replay being written (`record=`), until `finish_record`.
    replay: Option<ReplayWriter>,
}

#[pymethods]
impl PyLorrRun {
    #[new]
    #[pyo3(signature = (problem, planner="auto", scheduler="auto", seed=0, plan_time_limit_ms=None, team_size=None, record=None, entries=None, delay_seed=None, staged_validation=true))]
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
        entries: Option<PyObject>,
        delay_seed: Option<u32>,
        staged_validation: bool,
    ) -> PyResult<Self> {
        let options = LorrOptions { planner: planner.into(), scheduler: scheduler.into(), seed, plan_time_limit_ms, staged_validation };
        let mut problem = engine(py, move || Problem::load_team(&problem, team_size))?;
        if let Some(s) = delay_seed {
            // Another draw of the same delay model: what the problem file with this
            // `delayConfig.seed` gives, in the Start-Kit as here.
            let Some(rules) = problem.y2026.as_mut() else {
                return Err(crate::errors::ScenarioError::new_err(format!(
                    "delay_seed = {s}: a {} problem has no delays (only the 2026 rules draw them)",
                    if problem.version == Version::Y2023 { "2023" } else { "2024" }
                )));
            };
            rules.delays.seed = s;
        }
        if !staged_validation && problem.version != Version::Y2026 {
            return Err(crate::errors::ScenarioError::new_err(
                "staged_validation = False: only the 2026 rules stage actions (the 2023 and 2024 rules have no executor)",
            ));
        }
        let problem = Arc::new(problem);
        let made = match entries {
            None => None,
            Some(bridge) => Some(crate::lorr_entries::made(py, &problem, options.clone(), bridge)?),
        };
        let (run, replay) = engine(py, move || {
            let mut run = match made {
                Some(crate::lorr_entries::Made::Ticks(options, entries)) => Rules::Ticks(Box::new(Lorr26::with(problem, options, entries)?)),
                Some(crate::lorr_entries::Made::Steps(options, planner, scheduler)) => {
                    Rules::Steps(Box::new(LorrRun::with(problem, options, planner, scheduler)?))
                }
                None if problem.version == Version::Y2026 => Rules::Ticks(Box::new(Lorr26::new(problem, options)?)),
                None => Rules::Steps(Box::new(LorrRun::new(problem, options)?)),
            };
            let replay = record.map(|path| ReplayWriter::create(&path, run.as_run(), serde_json::Value::Null)).transpose()?;
            Ok((run, replay))
        })?;
        Ok(PyLorrRun { run, replay })
    }

    /// Runs up to step `until` (recording every step when a replay is open); the step
    /// reached.
    fn run_to(&mut self, py: Python<'_>, until: u32) -> PyResult<u32> {
        let steps = u64::from(until.saturating_sub(self.run.t()));
        crate::slicer::advance(py, self.run.as_run(), steps, self.replay.as_mut().map(|w| w as &mut (dyn FrameSink + Send)))?;
        Ok(self.run.t())
    }

    /// Finishes the replay opened with `record=` (its footer, then the rename into place).
    fn finish_record(&mut self, py: Python<'_>) -> PyResult<()> {
        let (run, replay) = (self.run.as_run(), self.replay.take());
        engine(py, move || replay.map_or(Ok(()), |w| w.finish(&*run)))
    }

    #[getter]
    fn t(&self) -> u32 {
        self.run.t()
    }

    #[getter]
    fn finished(&self) -> u64 {
        match &self.run {
            Rules::Steps(r) => r.finished(),
            Rules::Ticks(r) => r.finished(),
        }
    }

    #[getter]
    fn planner(&self) -> String {
        match &self.run {
            Rules::Steps(r) => r.planner().to_owned(),
            Rules::Ticks(r) => r.names().0.to_owned(),
        }
    }

    /// The scheduler that plays (`auto` resolved).
    #[getter]
    fn scheduler(&self) -> String {
        match &self.run {
            Rules::Steps(r) => r.options().scheduler.clone(),
            Rules::Ticks(r) => r.names().1.to_owned(),
        }
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
            multibots_core::input::lorr::Version::Y2026 => "2026",
        }
    }

    /// MultiBots' figures as a JSON object's text.
    fn figures_json(&self) -> String {
        serde_json::to_string(&self.run.figures()).expect("figures serialise")
    }

    /// Writes the competition's result file, atomically.
    fn write_result(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let run = &self.run;
        engine(py, move || match run {
            Rules::Steps(r) => lorr::write_result(r, &path),
            Rules::Ticks(r) => lorr26::write_result(r, &path),
        })
    }

    /// Writes MultiBots' figures as JSON, atomically.
    fn write_figures(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let run = &self.run;
        engine(py, move || match run {
            Rules::Steps(r) => lorr::write_figures(r, &path),
            Rules::Ticks(r) => lorr26::write_figures(r, &path),
        })
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
