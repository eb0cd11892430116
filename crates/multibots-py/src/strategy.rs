//! Where a run's allocator comes from: a built-in named by the scenario or by Python, a
//! Python object (a `multibots.Allocator` or a plain function), or a `module:Class` or
//! `path/file.py:Class` name (loaded by `multibots.strategies.load_strategy`).
//!
//! A Python allocator becomes an engine [`Allocator`] through [`PyAllocator`]. The engine
//! runs without the GIL; at each allocation event the adapter takes the GIL, hands Python a
//! [`PyAllocView`] and converts the answer. The view answers route queries from its own
//! snapshot of the fleet (the layout's graph is built once per run, the robots' columns are
//! copied per event), so no reference into the engine outlives the call, and it refuses every
//! query once `allocate` has returned.

use multibots_core::alloc::{self, AllocView, EnergyModel, Goods, TaskModel};
use multibots_core::fleet::robot::Robots;
use multibots_core::{Allocator, Assignment, CellId, Decisions, Error, GoodsId, NodeId, RobotId, Scenario, Simulation, World};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString, PyTuple, PyType};
use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

thread_local! {
    /// The Python exception an allocator raised on this thread, kept so that the error the
    /// engine returns can carry it as its `__cause__` (the engine's error is plain text).
    static CAUSE: RefCell<Option<PyErr>> = const { RefCell::new(None) };
}

/// Chains the exception a Python allocator raised (if any) to `err`. Ctrl-C inside a
/// strategy stays a `KeyboardInterrupt`, so that it interrupts as it would anywhere else.
pub(crate) fn with_cause(py: Python<'_>, err: PyErr) -> PyErr {
    if let Some(cause) = CAUSE.with(|c| c.borrow_mut().take()) {
        if cause.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
            return cause;
        }
        err.set_cause(py, Some(cause));
    }
    err
}

/// Keeps `e` as the cause of the engine error about to be returned on this thread (a Python
/// LoRR entry's exception: `lorr_entries.rs`).
pub(crate) fn keep_cause(e: PyErr) {
    CAUSE.with(|c| *c.borrow_mut() = Some(e));
}

/// The goods an answer gives a robot to send it to charge now (`multibots.CHARGE`).
const CHARGE: &str = "charge";

/// An allocator, and the world a Python allocator was built on (the run shares it, so the
/// routing tables are built once).
type Made = (Box<dyn Allocator>, Option<Arc<World>>);

/// A run of `scenario` with `allocator` if Python gave one (an object, a built-in's name or a
/// `module:Class` name), else with the scenario's `allocator` field.
pub(crate) fn new_simulation(py: Python<'_>, scenario: &Scenario, allocator: Option<PyObject>) -> PyResult<Simulation> {
    let (alloc, world) = make_allocator(py, scenario, allocator)?;
    let s = scenario.clone();
    crate::errors::engine(py, move || match world {
        Some(world) => Simulation::with_world(world, &s, alloc),
        None => Simulation::with_allocator(&s, alloc),
    })
}

fn make_allocator(py: Python<'_>, scenario: &Scenario, allocator: Option<PyObject>) -> PyResult<Made> {
    CAUSE.with(|c| c.borrow_mut().take());
    match allocator {
        None => by_name(py, scenario, &scenario.allocator.clone()),
        Some(obj) => {
            let b = obj.bind(py);
            if let Ok(name) = b.downcast::<PyString>() {
                return by_name(py, scenario, &name.to_cow()?);
            }
            PyAllocator::boxed(py, scenario, &obj)
        }
    }
}

/// For `Scenario.validate()`: checks the allocator name (a `module:Class` must import and
/// name a class) and returns an allocator to validate the rest of the scenario with.
pub(crate) fn for_validation(py: Python<'_>, scenario: &Scenario) -> PyResult<Box<dyn Allocator>> {
    let name = scenario.allocator.as_str();
    if name.contains(':') {
        resolve(py, name)?;
        if scenario.rules == multibots_core::Rules::Original {
            // The stand-in below is in-turn, which the original rules accept: say it now, not
            // when the run starts.
            return Err(crate::to_py(multibots_core::rules::original::check_allocator(name).expect_err("a module:Class is not in-turn")));
        }
        return Ok(Box::new(alloc::InTurn));
    }
    alloc::built_in(scenario).map_err(crate::to_py)
}

fn by_name(py: Python<'_>, scenario: &Scenario, name: &str) -> PyResult<Made> {
    if name.contains(':') {
        let class = resolve(py, name)?;
        let obj = class
            .call0()
            .map_err(|e| crate::ScenarioError::new_err(format!("allocator = \"{name}\": calling it with no arguments failed: {}", one_line(py, &e))))?;
        // A name from a file or the command line is user input: a wrong one is a scenario error.
        return PyAllocator::boxed(py, scenario, &obj.unbind())
            .map_err(|e| crate::ScenarioError::new_err(format!("allocator = \"{name}\": calling it returned no allocator ({})", one_line(py, &e))));
    }
    let s = Scenario { allocator: name.to_string(), ..scenario.clone() };
    Ok((alloc::built_in(&s).map_err(crate::to_py)?, None))
}

/// The class (or function) a `module:Class` or `path/file.py:Class` name refers to. The
/// loading rules live in one Python function, `multibots.strategies.load_strategy`, whose
/// errors are one-line `ScenarioError`s naming the allocator.
fn resolve<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("multibots.strategies")?.getattr("load_strategy")?.call1((name,))
}

fn one_line(py: Python<'_>, e: &PyErr) -> String {
    let ty = e.get_type(py).name().map_or_else(|_| "Exception".into(), |n| n.to_string());
    let msg = e.value(py).str().map(|s| s.to_string()).unwrap_or_default();
    let msg = msg.split_whitespace().collect::<Vec<_>>().join(" ");
    if msg.is_empty() {
        ty
    } else {
        format!("{ty}: {msg}")
    }
}

/// A Python allocator behind the engine's trait.
struct PyAllocator {
    name: String,
    /// The object's bound `allocate` method, or the function itself.
    call: PyObject,
    world: Arc<World>,
    model: TaskModel,
    /// Energy when full, the charging threshold and the speed: the scales of a policy's
    /// observations ([`PyAllocView::decide`]).
    scales: (f64, f64, f64),
}

impl PyAllocator {
    fn boxed(py: Python<'_>, scenario: &Scenario, obj: &PyObject) -> PyResult<Made> {
        let b = obj.bind(py);
        if b.is_instance_of::<PyType>() {
            let what = b.getattr("__name__").map(|n| n.to_string()).unwrap_or_default();
            return Err(PyTypeError::new_err(format!("allocator: got the class {what}; pass an instance, such as {what}()")));
        }
        let call = match b.getattr("allocate") {
            Ok(m) if m.is_callable() => m,
            _ if b.is_callable() => b.clone(),
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "allocator: expected a multibots.Allocator, a function f(view) or a strategy name, got {}",
                    b.get_type().name()?
                )))
            }
        };
        let name = match b.getattr("name") {
            Ok(n) if n.is_instance_of::<PyString>() && !n.to_string().is_empty() => n.to_string(),
            _ => match b.getattr("__name__") {
                Ok(n) => n.to_string(),
                Err(_) => b.get_type().name()?.to_string(),
            },
        };
        let s = scenario.clone();
        let world = py.allow_threads(move || s.check_values().and_then(|()| World::of(&s))).map_err(crate::to_py)?;
        let scales = (scenario.robot.energy_full, scenario.robot.threshold, scenario.robot.speed);
        Ok((Box::new(PyAllocator { name, call: call.unbind(), world: world.clone(), model: TaskModel::of(scenario), scales }), Some(world)))
    }

    fn fail(&self, reason: impl Into<String>) -> Error {
        Error::Allocator { strategy: self.name.clone(), reason: reason.into() }
    }

    /// Converts `None`, a dict `{robot: goods}` or an iterable of `(robot, goods)` pairs,
    /// where goods may be the string `"charge"` (send the robot to charge now).
    fn convert(&self, py: Python<'_>, answer: &Bound<'_, PyAny>, out: &mut Decisions) -> Result<(), Error> {
        let shape = || self.fail(format!("allocate() must return a dict {{robot: goods}} or a list of (robot, goods) pairs, got {}", type_name(answer)));
        if answer.is_none() {
            return Ok(());
        }
        let mut pair = |k: usize, r: &Bound<'_, PyAny>, g: &Bound<'_, PyAny>| -> Result<(), Error> {
            let id = |v: &Bound<'_, PyAny>, what: &str| -> Result<u32, Error> {
                if v.is_instance_of::<pyo3::types::PyBool>() {
                    return Err(self.fail(format!("assignment {k}: {what} id must be an integer, got bool")));
                }
                v.extract::<u32>().map_err(|_| self.fail(format!("assignment {k}: {what} id must be an integer 0 or more, got {}", repr(v))))
            };
            let robot = RobotId(id(r, "robot")?);
            if let Ok(s) = g.downcast::<PyString>() {
                if s.to_cow().map_err(|_| shape())? != CHARGE {
                    return Err(self.fail(format!("assignment {k}: goods must be a goods id or \"{CHARGE}\", got {}", repr(g))));
                }
                out.charge.push(robot);
            } else {
                out.assign.push(Assignment { robot, goods: GoodsId(id(g, "goods")?) });
            }
            Ok(())
        };
        if let Ok(d) = answer.downcast::<PyDict>() {
            for (k, (r, g)) in d.iter().enumerate() {
                pair(k, &r, &g)?;
            }
            return Ok(());
        }
        if answer.is_instance_of::<PyString>() {
            return Err(shape());
        }
        let iter = answer.try_iter().map_err(|_| shape())?;
        for (k, item) in iter.enumerate() {
            let item = item.map_err(|e| self.fail(format!("iterating the answer raised {}", one_line(py, &e))))?;
            let t = item
                .extract::<(Bound<'_, PyAny>, Bound<'_, PyAny>)>()
                .map_err(|_| self.fail(format!("assignment {k}: expected a (robot, goods) pair, got {}", repr(&item))))?;
            pair(k, &t.0, &t.1)?;
        }
        Ok(())
    }
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type().name().map_or_else(|_| "object".into(), |n| n.to_string())
}

fn repr(v: &Bound<'_, PyAny>) -> String {
    let s = v.repr().map_or_else(|_| "?".into(), |r| r.to_string());
    if s.chars().count() > 60 {
        format!("{}...", s.chars().take(57).collect::<String>())
    } else {
        s
    }
}

impl Allocator for PyAllocator {
    fn name(&self) -> &str {
        &self.name
    }

    fn allocate(&mut self, view: &AllocView<'_>, out: &mut Decisions) -> Result<(), Error> {
        Python::with_gil(|py| {
            let snap = PyAllocView::snapshot(py, view, &self.world, &self.model, self.scales)
                .map_err(|e| self.fail(format!("building the view failed: {}", one_line(py, &e))))?;
            let pv = Bound::new(py, snap).map_err(|e| self.fail(one_line(py, &e)))?;
            let answer = self.call.bind(py).call1((pv.clone(),));
            // The view is only valid during the call: later queries would answer from a stale
            // fleet.
            pv.get().valid.store(false, Ordering::Relaxed);
            match answer {
                Ok(a) => self.convert(py, &a, out),
                Err(e) => {
                    let reason = format!("raised {}", one_line(py, &e));
                    CAUSE.with(|c| *c.borrow_mut() = Some(e));
                    Err(self.fail(reason))
                }
            }
        })
    }
}

/// What a Python allocator sees at an allocation event. Read-only; valid only during the
/// call to `allocate`.
#[pyclass(module = "multibots._core", name = "AllocView", frozen)]
pub(crate) struct PyAllocView {
    valid: AtomicBool,
    world: Arc<World>,
    robots: Robots,
    idle_ids: Vec<RobotId>,
    open: Vec<Goods>,
    unload_node: NodeId,
    energy_model: EnergyModel,
    model: TaskModel,
    scales: (f64, f64, f64),
    #[pyo3(get)]
    step: u64,
    #[pyo3(get)]
    idle: Py<PyArray1<u32>>,
    #[pyo3(get)]
    goods: Py<PyArray1<u32>>,
    #[pyo3(get)]
    goods_cells: Py<PyArray1<u32>>,
    #[pyo3(get)]
    positions: Py<PyArray2<f64>>,
    #[pyo3(get)]
    human_positions: Py<PyArray2<f64>>,
    #[pyo3(get)]
    energy: Py<PyArray1<f64>>,
    #[pyo3(get)]
    states: Py<PyArray1<u8>>,
    #[pyo3(get)]
    homes: Py<PyArray1<u32>>,
    #[pyo3(get)]
    task_cells: Py<PyArray1<i64>>,
}

fn frozen<T: numpy::Element, D: numpy::ndarray::Dimension>(a: Bound<'_, numpy::PyArray<T, D>>) -> Py<numpy::PyArray<T, D>> {
    a.readwrite().make_nonwriteable();
    a.unbind()
}

impl PyAllocView {
    fn snapshot(py: Python<'_>, view: &AllocView<'_>, world: &Arc<World>, model: &TaskModel, scales: (f64, f64, f64)) -> PyResult<PyAllocView> {
        let r = view.robots();
        let n = r.len();
        let flat: Vec<f64> = r.positions_flat();
        Ok(PyAllocView {
            valid: AtomicBool::new(true),
            world: Arc::clone(world),
            robots: r.clone(),
            idle_ids: view.idle.to_vec(),
            open: view.goods.to_vec(),
            unload_node: view.unload(),
            energy_model: view.energy_params(),
            model: model.clone(),
            scales,
            step: view.step,
            idle: frozen(PyArray1::from_iter(py, view.idle.iter().map(|i| i.0))),
            goods: frozen(PyArray1::from_iter(py, view.goods.iter().map(|g| g.id.0))),
            goods_cells: frozen(PyArray1::from_iter(py, view.goods.iter().map(|g| g.cell.0))),
            positions: frozen(PyArray1::from_vec(py, flat).reshape([n, 2])?),
            human_positions: frozen(
                PyArray1::from_vec(py, view.people_x.iter().zip(view.people_y).flat_map(|(&x, &y)| [x, y]).collect()).reshape([view.people_x.len(), 2])?,
            ),
            energy: frozen(PyArray1::from_slice(py, &r.energy)),
            states: frozen(PyArray1::from_vec(py, r.state_codes())),
            homes: frozen(PyArray1::from_vec(py, r.home_ids())),
            task_cells: frozen(PyArray1::from_iter(py, r.task_cells().into_iter().map(i64::from))),
        })
    }

    /// Runs `f` on an engine view over the snapshot, after checking the view is still valid.
    fn with_view<T>(&self, f: impl FnOnce(&AllocView<'_>) -> T) -> PyResult<T> {
        if !self.valid.load(Ordering::Relaxed) {
            return Err(PyRuntimeError::new_err("this AllocView has expired: use it only during the allocate() call that received it"));
        }
        let v = AllocView::new(self.step, &self.idle_ids, &self.open, &self.robots, &self.world.layout, &self.world.graph, self.unload_node, self.energy_model);
        Ok(f(&v))
    }

    fn robot(&self, robot: i64) -> PyResult<RobotId> {
        let n = self.robots.len();
        if robot < 0 || robot as usize >= n {
            return Err(PyValueError::new_err(format!("robot = {robot}: out of range 0..{}", n.saturating_sub(1))));
        }
        Ok(RobotId(robot as u32))
    }

    fn cell(&self, cell: i64) -> PyResult<CellId> {
        let n = self.world.layout.cells.len();
        if cell < 0 || cell as usize >= n {
            return Err(PyValueError::new_err(format!("cell = {cell}: out of range 0..{}", n - 1)));
        }
        Ok(CellId(cell as u32))
    }
}

#[pymethods]
impl PyAllocView {
    /// Number of robots in the fleet.
    #[getter]
    fn robot_count(&self) -> usize {
        self.robots.len()
    }
    /// Full energy.
    #[getter]
    fn energy_full(&self) -> f64 {
        self.energy_model.energy_full
    }
    /// Below this energy the threshold rule sends a robot to charge.
    #[getter]
    fn threshold(&self) -> f64 {
        self.energy_model.threshold
    }
    /// Energy used per step while not charging or parked.
    #[getter]
    fn consumption(&self) -> f64 {
        self.energy_model.consumption
    }
    /// Energy gained per step of charging.
    #[getter]
    fn charge_rate(&self) -> f64 {
        self.model.charge_rate
    }
    /// Distance per step, px.
    #[getter]
    fn speed(&self) -> f64 {
        self.energy_model.speed
    }
    /// Steps spent loading.
    #[getter]
    fn loading(&self) -> u32 {
        self.model.loading
    }
    /// Steps spent unloading.
    #[getter]
    fn unloading(&self) -> u32 {
        self.model.unloading
    }
    /// Node id of the unloading zone.
    #[getter]
    fn unload(&self) -> u32 {
        self.unload_node.0
    }
    /// The scenario's cost weights (w_d, w_t, w_c).
    #[getter]
    fn cost_weights(&self) -> (f64, f64, f64) {
        let w = &self.model.weights;
        (w.distance, w.time, w.collision)
    }

    /// Route length in px from a robot's position to a cell's service point.
    fn route_length(&self, robot: i64, cell: i64) -> PyResult<f64> {
        let (r, c) = (self.robot(robot)?, self.cell(cell)?);
        self.with_view(|v| v.route_length(r, c))
    }

    /// Route lengths from every idle robot to every open goods: an (idle, goods) array.
    fn route_lengths<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let m = self.open.len();
        let flat = self.with_view(|v| v.idle.iter().flat_map(|&r| v.goods.iter().map(move |g| v.route_length(r, g.cell))).collect::<Vec<f64>>())?;
        PyArray1::from_vec(py, flat).reshape([self.idle_ids.len(), m])
    }

    /// Route length in px from a cell's service point to the unloading zone.
    fn cell_to_unload(&self, cell: i64) -> PyResult<f64> {
        let c = self.cell(cell)?;
        self.with_view(|v| v.cell_to_unload(c))
    }

    /// Route length in px from the unloading zone to a robot's home charger.
    fn unload_to_home(&self, robot: i64) -> PyResult<f64> {
        let r = self.robot(robot)?;
        self.with_view(|v| v.unload_to_home(r))
    }

    /// Length in px of the rest of a robot's current route (0 when it is not travelling).
    fn remaining_length(&self, robot: i64) -> PyResult<f64> {
        let r = self.robot(robot)?;
        self.with_view(|v| v.remaining_length(r))
    }

    /// How often other robots' expected paths meet the route of robot fetching cell.
    fn traffic(&self, robot: i64, cell: i64) -> PyResult<u32> {
        let (r, c) = (self.robot(robot)?, self.cell(cell)?);
        self.with_view(|v| v.traffic(r, c))
    }

    /// Steps for a robot to fetch a cell and unload it, if nothing is in its way.
    fn task_steps(&self, robot: i64, cell: i64) -> PyResult<f64> {
        let (r, c) = (self.robot(robot)?, self.cell(cell)?);
        self.with_view(|v| self.model.task_steps(v, r, c))
    }

    /// A robot's energy when it has unloaded a cell's goods, if nothing is in its way.
    fn energy_after(&self, robot: i64, cell: i64) -> PyResult<f64> {
        let (r, c) = (self.robot(robot)?, self.cell(cell)?);
        self.with_view(|v| self.model.energy_after(v, r, c))
    }

    /// A learning environment's policy as this event's answer: asks `policy(robot, (robot,
    /// fleet, queue, mask))` for each idle robot's action code, in the order and with the
    /// observations the dispatcher environment (`multibots/Dispatch-v0`) shows, and returns
    /// the `(robot, goods or "charge")` pairs. A masked-out action is refused, or taken as
    /// "wait" with `invalid="wait"`.
    #[pyo3(signature = (policy, max_queue=10, invalid="refuse"))]
    fn decide(&self, py: Python<'_>, policy: &Bound<'_, PyAny>, max_queue: usize, invalid: &str) -> PyResult<Vec<(u32, PyObject)>> {
        use multibots_core::learning::{decide_each, Encoder, InvalidAction};
        let invalid = match invalid {
            "refuse" => InvalidAction::Refuse,
            "wait" => InvalidAction::Wait,
            other => return Err(PyValueError::new_err(format!("invalid = {other:?}: must be \"refuse\" or \"wait\""))),
        };
        if max_queue == 0 || max_queue > multibots_core::learning::MAX_QUEUE_LIMIT {
            return Err(PyValueError::new_err(format!("max_queue = {max_queue}: must be 1 to {}", multibots_core::learning::MAX_QUEUE_LIMIT)));
        }
        let (full, threshold, speed) = self.scales;
        let enc = Encoder::with_model(&self.world, full, threshold, speed, self.model.clone(), max_queue);
        let n = self.robots.len();
        let mut raised: Option<PyErr> = None;
        let out = self.with_view(|v| {
            decide_each(v, &enc, invalid, |r, obs| {
                let arrays = (|| -> PyResult<i64> {
                    let robot = PyArray1::from_slice(py, &obs.robot);
                    let fleet = PyArray1::from_slice(py, &obs.fleet).reshape([n, obs.fleet.len() / n.max(1)])?;
                    let queue = PyArray1::from_slice(py, &obs.queue).reshape([max_queue, obs.queue.len() / max_queue])?;
                    let mask = PyArray1::from_iter(py, obs.mask.iter().map(|&m| m as i8));
                    policy.call1((r.0, (robot, fleet, queue, mask)))?.extract::<i64>()
                })();
                arrays.map_err(|e| {
                    let reason = format!("policy raised {}", one_line(py, &e));
                    raised = Some(e);
                    Error::Decision { step: v.step, reason }
                })
            })
        })?;
        let d = match out {
            Ok(d) => d,
            Err(e) => return Err(raised.take().unwrap_or_else(|| crate::to_py(e))),
        };
        let mut pairs: Vec<(u32, PyObject)> = d
            .assign
            .iter()
            .map(|a| (a.robot.0, a.goods.0.into_pyobject(py).map(|g| g.into_any().unbind())))
            .map(|(r, g)| (r, g.expect("an int converts")))
            .collect();
        for r in &d.charge {
            pairs.push((r.0, PyString::new(py, CHARGE).into_any().unbind()));
        }
        Ok(pairs)
    }

    fn __repr__(&self) -> String {
        format!("AllocView(step={}, idle={:?}, goods={})", self.step, self.idle_ids.iter().map(|r| r.0).collect::<Vec<_>>(), self.open.len())
    }
}

/// Adds the view class and the built-ins' names to `_core`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyAllocView>()?;
    m.add("BUILT_INS", PyTuple::new(m.py(), alloc::BUILT_INS)?)?;
    m.add("CHARGE", CHARGE)?;
    Ok(())
}
