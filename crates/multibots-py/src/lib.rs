//! Python bindings of the MultiBots engine: conversions, error mapping and releasing the GIL.
//! No model logic lives here.

use multibots_core::metrics::RunResult;
use multibots_core::replay::ReplayWriter;
use multibots_core::{Error, Scenario, Simulation, State};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

mod strategy;

create_exception!(_core, MultibotsError, PyException, "Base class of every MultiBots error.");
create_exception!(_core, ScenarioError, MultibotsError, "A scenario field or file the model cannot run with.");
create_exception!(_core, LayoutError, MultibotsError, "A layout robots cannot use.");
create_exception!(_core, AllocatorError, MultibotsError, "A strategy returned assignments the engine cannot carry out.");
create_exception!(_core, EngineError, MultibotsError, "An internal error of the engine (a bug: please report it).");

/// The one place engine errors become Python exceptions.
#[allow(clippy::needless_pass_by_value)] // by value so that it serves as `map_err(to_py)`
fn to_py(e: Error) -> PyErr {
    let msg = e.to_string();
    match e {
        Error::Scenario { .. } | Error::Parse { .. } => ScenarioError::new_err(msg),
        Error::Layout { .. } => LayoutError::new_err(msg),
        Error::Allocator { .. } => Python::with_gil(|py| strategy::with_cause(py, AllocatorError::new_err(msg))),
        Error::Io { .. } => MultibotsError::new_err(msg),
    }
}

/// Runs engine code without the GIL, turning errors and panics into exceptions.
fn engine<T: Send>(py: Python<'_>, f: impl FnOnce() -> Result<T, Error> + Send) -> PyResult<T> {
    let out = py.allow_threads(|| catch_unwind(AssertUnwindSafe(f)));
    match out {
        Ok(r) => r.map_err(to_py),
        Err(panic) => {
            let what = panic.downcast_ref::<&str>().map(|s| (*s).to_string()).or_else(|| panic.downcast_ref::<String>().cloned()).unwrap_or_default();
            Err(EngineError::new_err(format!("internal error in the engine: {what}")))
        }
    }
}

/// Steps between two checks for Ctrl-C in long runs.
const SIGNAL_EVERY: u64 = 1 << 14;

#[pyclass(module = "multibots._core", name = "Scenario", frozen)]
#[derive(Clone)]
struct PyScenario {
    inner: Scenario,
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

    /// Checks every field, against the layout too.
    fn validate(&self, py: Python<'_>) -> PyResult<()> {
        let s = self.inner.clone();
        let alloc = strategy::for_validation(py, &s)?;
        engine(py, move || Simulation::with_allocator(&s, alloc).map(drop))
    }

    /// The scenario's task list as cell ids (random lists drawn).
    fn cells(&self, py: Python<'_>) -> PyResult<Vec<u32>> {
        let s = self.inner.clone();
        engine(py, move || s.cells(&s.resolve_layout()?))
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.inner == other.inner
    }
}

fn result_dict<'py>(py: Python<'py>, r: &RunResult) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("T", r.t)?;
    d.set_item("S", r.s)?;
    d.set_item("C", r.c)?;
    d.set_item("outcome", r.outcome.map_or("running", |o| o.as_str()))?;
    d.set_item("steps", r.steps)?;
    d.set_item("delivered", r.delivered)?;
    d.set_item("goods_total", r.goods_total)?;
    d.set_item("stranded", r.stranded.clone())?;
    let st = &r.robots;
    d.set_item("distance", PyArray1::from_slice(py, &st.distance))?;
    d.set_item("wait_steps", PyArray1::from_slice(py, &st.wait_steps))?;
    d.set_item("collisions", PyArray1::from_slice(py, &st.collisions))?;
    d.set_item("energy_used", PyArray1::from_slice(py, &st.energy_used))?;
    d.set_item("robot_delivered", PyArray1::from_slice(py, &st.delivered))?;
    d.set_item("charges", PyArray1::from_slice(py, &st.charges))?;
    let flat: Vec<u64> = st.state_steps.iter().flat_map(|row| row.iter().copied()).collect();
    d.set_item("state_steps", PyArray1::from_vec(py, flat).reshape([st.state_steps.len(), State::COUNT])?)?;
    match &r.lifelong {
        Some(l) => {
            let ll = PyDict::new(py);
            ll.set_item("ordered", l.ordered)?;
            ll.set_item("delivered", r.delivered)?;
            ll.set_item("in_flight", l.in_flight)?;
            ll.set_item("queued", l.queued)?;
            ll.set_item("waiting", l.waiting)?;
            ll.set_item("throughput", l.throughput)?;
            ll.set_item("latency_p50", l.latency_p50)?;
            ll.set_item("latency_p95", l.latency_p95)?;
            ll.set_item("latency_p99", l.latency_p99)?;
            ll.set_item("latency_mean", l.latency_mean)?;
            ll.set_item("utilisation", l.utilisation)?;
            ll.set_item("energy_per_delivery", l.energy_per_delivery)?;
            d.set_item("lifelong", ll)?;
        }
        None => d.set_item("lifelong", py.None())?,
    }
    Ok(d)
}

/// Generates a grid layout and returns its layout file text (TOML), checked.
#[pyfunction]
#[pyo3(signature = (params_json, name="generated"))]
fn generate_layout_toml(py: Python<'_>, params_json: &str, name: &str) -> PyResult<String> {
    let params: multibots_core::LayoutParams = serde_json::from_str(params_json).map_err(|e| ScenarioError::new_err(format!("layout parameters: {e}")))?;
    let name = name.to_string();
    engine(py, move || {
        let layout = multibots_core::Layout::generate(&params, &name)?;
        multibots_core::layout_file::check_layout(&layout)?;
        Ok(multibots_core::layout_file::to_toml(&layout, Some(params)))
    })
}

/// Reads and checks layout file text; returns the layout JSON.
#[pyfunction]
#[pyo3(signature = (text, source_name="layout"))]
fn layout_file_json(py: Python<'_>, text: &str, source_name: &str) -> PyResult<String> {
    let (text, source) = (text.to_string(), source_name.to_string());
    engine(py, move || {
        let layout = multibots_core::layout_file::from_toml(&text, &source)?;
        multibots_core::layout_file::check_layout(&layout)?;
        Ok(layout.to_json().to_string())
    })
}

/// Bytes of the routing tables of a scenario's layout, and the world's node count.
#[pyfunction]
fn routing_table_bytes(py: Python<'_>, scenario: &PyScenario) -> PyResult<(usize, usize)> {
    let s = scenario.inner.clone();
    engine(py, move || {
        let layout = s.resolve_layout()?;
        let g = multibots_core::HighwayGraph::new(&layout);
        Ok((g.table_bytes(), g.len()))
    })
}

/// Runs a scenario to its end; records a replay to `record` if given. Ctrl-C stops it.
#[pyfunction]
#[pyo3(signature = (scenario, record=None, allocator=None))]
fn simulate<'py>(py: Python<'py>, scenario: &PyScenario, record: Option<PathBuf>, allocator: Option<PyObject>) -> PyResult<Bound<'py, PyDict>> {
    let s = scenario.inner.clone();
    let alloc = strategy::make_allocator(py, &s, allocator)?;
    let mut sim = {
        let s = s.clone();
        engine(py, move || Simulation::with_allocator(&s, alloc))?
    };
    let mut writer = match record {
        Some(path) => {
            let sim = &sim;
            Some(engine(py, move || ReplayWriter::create(&path, sim, &s.to_toml()))?)
        }
        None => None,
    };
    // In slices, so that a pending Ctrl-C is seen; an unfinished replay is removed on drop.
    while !sim.done() {
        let (sim, writer) = (&mut sim, &mut writer);
        engine(py, move || {
            let mut k = 0;
            while k < SIGNAL_EVERY && !sim.done() {
                sim.step()?;
                if let Some(w) = writer.as_mut() {
                    w.frame(sim)?;
                }
                k += 1;
            }
            Ok(())
        })?;
        py.check_signals()?;
    }
    let r = sim.result();
    if let Some(w) = writer {
        let r = r.clone();
        engine(py, move || w.finish(&r))?;
    }
    result_dict(py, &r)
}

/// Runs many scenarios on `workers` threads; results come back in the order given. Ctrl-C
/// stops every worker.
#[pyfunction]
#[pyo3(signature = (scenarios, workers=0))]
fn simulate_many(py: Python<'_>, scenarios: Vec<PyScenario>, workers: usize) -> PyResult<Vec<Bound<'_, PyDict>>> {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    let list: Vec<Scenario> = scenarios.into_iter().map(|s| s.inner).collect();
    let interrupted: std::sync::Mutex<Option<PyErr>> = std::sync::Mutex::new(None);
    let results = engine(py, || {
        let workers = if workers == 0 { std::thread::available_parallelism().map_or(1, usize::from) } else { workers }.min(list.len().max(1));
        let next = AtomicUsize::new(0);
        let finished = AtomicUsize::new(0);
        let cancel = AtomicBool::new(false);
        let mut slots: Vec<Option<Result<RunResult, Error>>> = (0..list.len()).map(|_| None).collect();
        let done = std::sync::Mutex::new(&mut slots);
        std::thread::scope(|scope| {
            for _ in 0..workers {
                scope.spawn(|| loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    if k >= list.len() {
                        break;
                    }
                    let r = Simulation::new(&list[k]).and_then(|mut sim| {
                        while !sim.done() && !cancel.load(Ordering::Relaxed) {
                            sim.step()?;
                        }
                        Ok(sim.result())
                    });
                    done.lock().expect("no worker panics while holding the lock")[k] = Some(r);
                    finished.fetch_add(1, Ordering::Release);
                });
            }
            // This thread watches for Ctrl-C while the workers run.
            while finished.load(Ordering::Acquire) < list.len() && !cancel.load(Ordering::Relaxed) {
                std::thread::sleep(std::time::Duration::from_millis(20));
                #[allow(clippy::redundant_closure_for_method_calls)] // the method's lifetime is not general enough
                let signals = Python::with_gil(|py| py.check_signals());
                if let Err(e) = signals {
                    *interrupted.lock().expect("not poisoned") = Some(e);
                    cancel.store(true, Ordering::Relaxed);
                }
            }
        });
        if cancel.load(Ordering::Relaxed) {
            return Ok(Vec::new());
        }
        slots.into_iter().map(|r| r.expect("every slot is filled")).collect::<Result<Vec<_>, Error>>()
    })?;
    if let Some(e) = interrupted.into_inner().expect("not poisoned") {
        return Err(e);
    }
    results.iter().map(|r| result_dict(py, r)).collect()
}

/// Panics inside the engine wrapper: lets the tests check that a panic becomes
/// `EngineError` and leaves the interpreter running.
#[pyfunction]
fn _panic_for_tests(py: Python<'_>) -> PyResult<()> {
    engine(py, || -> Result<(), Error> { panic!("deliberate panic for the tests") })
}

/// The layout JSON of a named layout.
#[pyfunction]
fn layout_json(name: &str) -> PyResult<String> {
    let s = Scenario { layout: name.to_string(), ..Scenario::paper(1, &[0]) };
    let layout = s.resolve_layout().map_err(to_py)?;
    Ok(layout.to_json().to_string())
}

/// A run that Python steps and inspects.
#[pyclass(module = "multibots._core", name = "Simulation")]
struct PySimulation {
    sim: Simulation,
}

#[pymethods]
impl PySimulation {
    #[new]
    #[pyo3(signature = (scenario, allocator=None))]
    fn new(py: Python<'_>, scenario: &PyScenario, allocator: Option<PyObject>) -> PyResult<Self> {
        let s = scenario.inner.clone();
        let alloc = strategy::make_allocator(py, &s, allocator)?;
        engine(py, move || Simulation::with_allocator(&s, alloc)).map(|sim| PySimulation { sim })
    }

    /// Runs `n` steps (fewer if the run ends first); returns the steps run.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<u64> {
        let mut done = 0;
        while done < n && !self.sim.done() {
            let chunk = (n - done).min(SIGNAL_EVERY);
            let sim = &mut self.sim;
            done += engine(py, move || {
                let mut k = 0;
                while k < chunk && !sim.done() {
                    sim.step()?;
                    k += 1;
                }
                Ok(k)
            })?;
            py.check_signals()?;
        }
        Ok(done)
    }

    /// Runs to the end; returns the result dictionary.
    fn run<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        while !self.sim.done() {
            self.step(py, SIGNAL_EVERY)?;
        }
        result_dict(py, &self.sim.result())
    }

    /// The result so far.
    fn result<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        result_dict(py, &self.sim.result())
    }

    #[getter]
    fn t(&self) -> u64 {
        self.sim.t()
    }
    #[getter]
    fn done(&self) -> bool {
        self.sim.done()
    }
    #[getter(S)]
    fn s(&self) -> u64 {
        self.sim.s()
    }
    #[getter(C)]
    fn c(&self) -> u64 {
        self.sim.c()
    }
    #[getter]
    fn delivered(&self) -> u64 {
        self.sim.delivered()
    }
    #[getter]
    fn goods_total(&self) -> u64 {
        self.sim.goods_total()
    }
    #[getter]
    fn outcome(&self) -> Option<&'static str> {
        self.sim.outcome().map(multibots_core::Outcome::as_str)
    }
    #[getter]
    fn energy_full(&self) -> f64 {
        self.sim.energy_levels().0
    }
    #[getter]
    fn threshold(&self) -> f64 {
        self.sim.energy_levels().1
    }
    #[getter]
    fn robot_count(&self) -> usize {
        self.sim.robots().len()
    }
    #[getter]
    fn allocator(&self) -> String {
        self.sim.allocator_name().to_string()
    }

    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let r = self.sim.robots();
        let flat: Vec<f64> = r.x.iter().zip(&r.y).flat_map(|(&x, &y)| [x, y]).collect();
        PyArray1::from_vec(py, flat).reshape([r.len(), 2])
    }
    #[getter]
    fn headings<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.sim.robots().heading)
    }
    #[getter]
    fn states<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        PyArray1::from_iter(py, self.sim.robots().state.iter().map(|&s| s as u8))
    }
    #[getter]
    fn marked<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_slice(py, &self.sim.robots().marked)
    }
    #[getter]
    fn energy<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.sim.robots().energy)
    }
    #[getter]
    fn radius<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.sim.robots().radius)
    }
    #[getter]
    fn home<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        PyArray1::from_iter(py, self.sim.robots().home.iter().map(|h| h.0))
    }
    /// Cell each robot carries, or -1.
    #[getter]
    fn carrying<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let r = self.sim.robots();
        PyArray1::from_iter(py, (0..r.len()).map(|i| if r.carrying[i] { r.cell[i] as i32 } else { -1 }))
    }
    /// Cell each robot fetches or carries, or -1.
    #[getter]
    fn task_cells<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let r = self.sim.robots();
        PyArray1::from_iter(py, (0..r.len()).map(|i| r.goods_of(i).map_or(-1, |(_, c)| c.0 as i32)))
    }
    /// 1 where a storage cell holds goods.
    #[getter]
    fn cells<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        PyArray1::from_iter(py, self.sim.cells_full().iter().map(|&f| u8::from(f)))
    }
    /// Collisions S of each robot.
    #[getter]
    fn robot_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        PyArray1::from_slice(py, &self.sim.stats().collisions)
    }
    /// Charges C of each robot.
    #[getter]
    fn robot_c<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        PyArray1::from_slice(py, &self.sim.stats().charges)
    }
    /// Cells of the goods still in the queue, front first.
    #[getter]
    fn queue(&self) -> Vec<u32> {
        self.sim.queue().iter().map(|g| g.cell.0).collect()
    }
    /// Events of the last step: (step, kind, robot, cell) rows; cell is -1 where none.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let ev = self.sim.events();
        let flat: Vec<i64> = ev.iter().flat_map(|e| [e.step as i64, e.kind as i64, i64::from(e.robot), if e.cell == u32::MAX { -1 } else { i64::from(e.cell) }]).collect();
        PyArray1::from_vec(py, flat).reshape([ev.len(), 4])
    }
    /// The layout JSON.
    #[getter]
    fn layout_json(&self) -> String {
        self.sim.world().layout.to_json().to_string()
    }
    /// Robot `i`'s remaining route as (K, 2) waypoints, starting at its position.
    fn route<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if i >= self.sim.robots().len() {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!("robot {i} out of range 0..{}", self.sim.robots().len())));
        }
        let pts = self.sim.route_of(i);
        let flat: Vec<f64> = pts.iter().flat_map(|&(x, y)| [x, y]).collect();
        PyArray1::from_vec(py, flat).reshape([pts.len(), 2])
    }
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // Load NumPy's C API now: loaded lazily, a pending Ctrl-C would surface inside it.
    let _ = PyArray1::<f64>::zeros(py, 0, false);
    m.add("MultibotsError", py.get_type::<MultibotsError>())?;
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("LayoutError", py.get_type::<LayoutError>())?;
    m.add("AllocatorError", py.get_type::<AllocatorError>())?;
    m.add("EngineError", py.get_type::<EngineError>())?;
    m.add_class::<PyScenario>()?;
    m.add_class::<PySimulation>()?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_many, m)?)?;
    m.add_function(wrap_pyfunction!(layout_json, m)?)?;
    m.add_function(wrap_pyfunction!(generate_layout_toml, m)?)?;
    m.add_function(wrap_pyfunction!(layout_file_json, m)?)?;
    m.add_function(wrap_pyfunction!(routing_table_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)?;
    strategy::register(m)?;
    m.add("BYTES_PER_ROBOT_STEP", multibots_core::replay::BYTES_PER_ROBOT_STEP)?;
    Ok(())
}
