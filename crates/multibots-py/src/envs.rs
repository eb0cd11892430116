//! The learning environments' engines (`multibots.envs`): the dispatcher, the fleet and the
//! vector of dispatchers. Conversions only: settings from keyword arguments, observations as
//! NumPy arrays (filled without the GIL, then moved into NumPy without a copy), and the engine
//! stepped through [`engine`], which releases the GIL.

use crate::errors::{engine, to_py};
use crate::results::result_dict;
use crate::scenario::PyScenario;
use multibots_core::learning::dispatcher::Progress;
use multibots_core::learning::fleet::{AgentStep, NO_ACTION};
use multibots_core::learning::observation::{Feature, FLEET, GOODS, ROBOT, STATE_GOODS, STATE_ROBOT, STATE_RUN};
use multibots_core::learning::vector::{Batch, Sizes};
use multibots_core::learning::{Dispatcher, Failure, Fleet, InvalidAction, ObsMut, Settings, VectorDispatch};
use multibots_core::{Error, Scenario};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString, PyTuple};

/// Settings from `max_queue`, `reward` (a dict of weights; `failure` a number or `"clock"`)
/// and `invalid` (`"refuse"` or `"wait"`).
fn settings(scenario: &Scenario, max_queue: usize, reward: Option<&Bound<'_, PyDict>>, invalid: &str) -> PyResult<Settings> {
    let mut s = Settings::of(scenario);
    s.max_queue = max_queue;
    s.invalid = match invalid {
        "refuse" => InvalidAction::Refuse,
        "wait" => InvalidAction::Wait,
        other => return Err(to_py(Error::scenario("invalid", format!("{other:?}"), "must be \"refuse\" or \"wait\""))),
    };
    if let Some(d) = reward {
        for (k, v) in d.iter() {
            let key: String = k.extract()?;
            let num = |v: &Bound<'_, PyAny>| -> PyResult<f64> {
                v.extract::<f64>().map_err(|_| to_py(Error::scenario(format!("reward.{key}"), short_repr(v), "must be a number")))
            };
            let w = &mut s.reward;
            match key.as_str() {
                "distance" => w.distance = num(&v)?,
                "time" => w.time = num(&v)?,
                "collision" => w.collision = num(&v)?,
                "charge" => w.charge = num(&v)?,
                "delivery" => w.delivery = num(&v)?,
                "failure" if v.downcast::<PyString>().is_ok_and(|s| s.to_cow().is_ok_and(|c| c == "clock")) => w.failure = Failure::Clock,
                "failure" => w.failure = Failure::Fixed(num(&v)?),
                _ => {
                    return Err(to_py(Error::scenario(
                        format!("reward.{key}"),
                        short_repr(&v),
                        "unknown weight (distance, time, collision, charge, delivery, failure)",
                    )))
                }
            }
        }
    }
    s.check().map_err(to_py)?;
    Ok(s)
}

/// An observation's four arrays, owned until they move into NumPy.
struct Obs {
    robot: Vec<f32>,
    fleet: Vec<f32>,
    queue: Vec<f32>,
    mask: Vec<u8>,
}

impl Obs {
    fn zeros(rows: usize, s: Sizes) -> Obs {
        Obs { robot: vec![0.0; rows * s.robot], fleet: vec![0.0; rows * s.fleet], queue: vec![0.0; rows * s.queue], mask: vec![0; rows * s.mask] }
    }

    fn as_mut(&mut self) -> ObsMut<'_> {
        ObsMut { robot: &mut self.robot, fleet: &mut self.fleet, queue: &mut self.queue, mask: &mut self.mask }
    }

    /// `(robot, fleet, queue, mask)`, each row-major with `rows` leading rows (none if `None`).
    fn into_py(self, py: Python<'_>, rows: Option<usize>, robots: usize, q: usize) -> PyResult<Bound<'_, PyTuple>> {
        let lead: Vec<usize> = rows.into_iter().collect();
        let shape = |rest: &[usize]| -> Vec<usize> { lead.iter().chain(rest).copied().collect() };
        let robot = PyArray1::from_vec(py, self.robot).reshape(shape(&[ROBOT.len()]))?;
        let fleet = PyArray1::from_vec(py, self.fleet).reshape(shape(&[robots, FLEET.len()]))?;
        let queue = PyArray1::from_vec(py, self.queue).reshape(shape(&[q, GOODS.len()]))?;
        // Gymnasium's masks are int8.
        let mask = PyArray1::from_iter(py, self.mask.iter().map(|&m| m as i8)).reshape(shape(&[q + 2]))?;
        PyTuple::new(py, [robot.into_any(), fleet.into_any(), queue.into_any(), mask.into_any()])
    }
}

/// A short `repr` of a value for an error message.
fn short_repr(v: &Bound<'_, PyAny>) -> String {
    let s = v.repr().map_or_else(|_| "?".into(), |r| r.to_string());
    s.chars().take(40).collect()
}

fn sizes(robots: usize, max_queue: usize) -> Sizes {
    Sizes { robot: ROBOT.len(), fleet: robots * FLEET.len(), queue: max_queue * GOODS.len(), mask: max_queue + 2 }
}

fn progress_dict<'py>(py: Python<'py>, p: &Progress) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("t", p.t)?;
    d.set_item("S", p.s)?;
    d.set_item("C", p.c)?;
    d.set_item("delivered", p.delivered)?;
    d.set_item("goods_total", p.goods_total)?;
    d.set_item("distance", p.distance)?;
    d.set_item("decisions", p.decisions)?;
    Ok(d)
}

/// The features of each observation part, as `(name, low, high)`: keys `robot`, `fleet`,
/// `queue`, `state_robot`, `state_goods`, `state_run`.
#[pyfunction]
pub(crate) fn observation_features(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    let rows = |t: &[Feature]| -> Vec<(&'static str, f32, f32)> { t.iter().map(|f| (f.name, f.low, f.high)).collect() };
    d.set_item("robot", rows(&ROBOT))?;
    d.set_item("fleet", rows(&FLEET))?;
    d.set_item("queue", rows(&GOODS))?;
    d.set_item("state_robot", rows(&STATE_ROBOT))?;
    d.set_item("state_goods", rows(&STATE_GOODS))?;
    d.set_item("state_run", rows(&STATE_RUN))?;
    Ok(d)
}

/// The single-agent environment's engine: one robot's action per `step`.
#[pyclass(module = "multibots._core", name = "Dispatcher")]
pub(crate) struct PyDispatcher {
    env: Dispatcher,
}

#[pymethods]
impl PyDispatcher {
    #[new]
    #[pyo3(signature = (scenario, max_queue=10, reward=None, invalid="refuse"))]
    fn new(py: Python<'_>, scenario: &PyScenario, max_queue: usize, reward: Option<&Bound<'_, PyDict>>, invalid: &str) -> PyResult<Self> {
        let st = settings(&scenario.inner, max_queue, reward, invalid)?;
        let s = scenario.inner.clone();
        engine(py, move || Dispatcher::new(&s, st)).map(|env| PyDispatcher { env })
    }

    /// A new episode, on `scenario` if given (as many robots).
    #[pyo3(signature = (scenario=None))]
    fn reset(&mut self, py: Python<'_>, scenario: Option<&PyScenario>) -> PyResult<()> {
        let s = scenario.map(|s| s.inner.clone());
        let env = &mut self.env;
        engine(py, move || env.reset(s.as_ref()))
    }

    /// Takes the deciding robot's action: `(reward, terminated, truncated, invalid)`.
    fn step(&mut self, py: Python<'_>, action: i64) -> PyResult<(f64, bool, bool, bool)> {
        let env = &mut self.env;
        let t = engine(py, move || env.step(action))?;
        Ok((t.reward, t.terminated, t.truncated, t.invalid))
    }

    /// `(robot, fleet, queue, mask)` of the deciding robot (at the end: the last one's, only
    /// "wait" allowed).
    fn observe<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let (n, q) = (self.env.robots(), self.env.settings().max_queue);
        let mut o = Obs::zeros(1, sizes(n, q));
        self.env.observe(o.as_mut());
        o.into_py(py, None, n, q)
    }

    /// The robot deciding now, or None at the end.
    #[getter]
    fn robot(&self) -> Option<u32> {
        self.env.robot().map(|r| r.0)
    }
    #[getter]
    fn ended(&self) -> bool {
        self.env.ended()
    }
    #[getter]
    fn robots(&self) -> usize {
        self.env.robots()
    }
    #[getter]
    fn max_queue(&self) -> usize {
        self.env.settings().max_queue
    }
    fn progress<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        progress_dict(py, &self.env.progress())
    }
    fn result<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        result_dict(py, &self.env.result())
    }
}

/// The multi-agent environment's engine: every robot's action per `step`.
#[pyclass(module = "multibots._core", name = "Fleet")]
pub(crate) struct PyFleet {
    env: Fleet,
}

#[pymethods]
impl PyFleet {
    #[new]
    #[pyo3(signature = (scenario, max_queue=10, reward=None, invalid="refuse"))]
    fn new(py: Python<'_>, scenario: &PyScenario, max_queue: usize, reward: Option<&Bound<'_, PyDict>>, invalid: &str) -> PyResult<Self> {
        let st = settings(&scenario.inner, max_queue, reward, invalid)?;
        let s = scenario.inner.clone();
        engine(py, move || Fleet::new(&s, st)).map(|env| PyFleet { env })
    }

    #[pyo3(signature = (scenario=None))]
    fn reset(&mut self, py: Python<'_>, scenario: Option<&PyScenario>) -> PyResult<()> {
        let s = scenario.map(|s| s.inner.clone());
        let env = &mut self.env;
        engine(py, move || env.reset(s.as_ref()))
    }

    #[allow(clippy::needless_pass_by_value)] // pyo3 extracts arguments by value
    /// Takes one action per robot (-1: none): `(rewards, invalid, conflict, terminated,
    /// truncated)`.
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray1<'py, i64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<bool>>, Bound<'py, PyArray1<bool>>, bool, bool)> {
        let codes = actions.as_slice()?.to_vec();
        let n = self.env.robots();
        let env = &mut self.env;
        let (out, e) = engine(py, move || {
            let mut out = vec![AgentStep::default(); n];
            let e = env.step(&codes, &mut out)?;
            Ok((out, e))
        })?;
        let rewards = PyArray1::from_iter(py, out.iter().map(|o| o.reward));
        let invalid = PyArray1::from_iter(py, out.iter().map(|o| o.invalid));
        let conflict = PyArray1::from_iter(py, out.iter().map(|o| o.conflict));
        Ok((rewards, invalid, conflict, e.terminated, e.truncated))
    }

    /// Every robot's `(robot, fleet, queue, mask)`, robot `i` in row `i`.
    fn observe<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let (n, q) = (self.env.robots(), self.env.settings().max_queue);
        let mut o = Obs::zeros(n, sizes(n, q));
        self.env.observe_all(o.as_mut());
        o.into_py(py, Some(n), n, q)
    }

    /// Which robots decide at the current point.
    fn deciders<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        let mut out = vec![false; self.env.robots()];
        self.env.deciders(&mut out);
        PyArray1::from_vec(py, out)
    }

    /// The global state.
    fn state<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        let mut out = vec![0.0; self.env.state_len()];
        self.env.state(&mut out);
        PyArray1::from_vec(py, out)
    }

    #[getter]
    fn state_len(&self) -> usize {
        self.env.state_len()
    }
    #[getter]
    fn ended(&self) -> bool {
        self.env.ended()
    }
    #[getter]
    fn robots(&self) -> usize {
        self.env.robots()
    }
    #[getter]
    fn max_queue(&self) -> usize {
        self.env.settings().max_queue
    }
    fn progress<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        progress_dict(py, &self.env.progress())
    }
    fn result<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        result_dict(py, &self.env.result())
    }
}

/// The code of "no action" in the fleet's `step`.
#[pyfunction]
pub(crate) fn no_action() -> i64 {
    NO_ACTION
}

/// Many dispatchers, stepped in one call without the GIL (next-step autoreset).
#[pyclass(module = "multibots._core", name = "VectorDispatch")]
pub(crate) struct PyVectorDispatch {
    env: VectorDispatch,
    robots: usize,
    max_queue: usize,
}

/// One call's arrays, owned until they move into NumPy.
struct Rows {
    obs: Obs,
    reward: Vec<f64>,
    terminated: Vec<bool>,
    truncated: Vec<bool>,
    invalid: Vec<bool>,
    robot_id: Vec<i64>,
    t: Vec<u64>,
}

impl Rows {
    fn new(m: usize, s: Sizes) -> Rows {
        Rows {
            obs: Obs::zeros(m, s),
            reward: vec![0.0; m],
            terminated: vec![false; m],
            truncated: vec![false; m],
            invalid: vec![false; m],
            robot_id: vec![0; m],
            t: vec![0; m],
        }
    }

    fn batch(&mut self) -> Batch<'_> {
        Batch {
            robot: &mut self.obs.robot,
            fleet: &mut self.obs.fleet,
            queue: &mut self.obs.queue,
            mask: &mut self.obs.mask,
            reward: &mut self.reward,
            terminated: &mut self.terminated,
            truncated: &mut self.truncated,
            invalid: &mut self.invalid,
            robot_id: &mut self.robot_id,
            t: &mut self.t,
        }
    }

    fn into_py(self, py: Python<'_>, robots: usize, q: usize) -> PyResult<Bound<'_, PyDict>> {
        let m = self.reward.len();
        let d = PyDict::new(py);
        let obs = self.obs.into_py(py, Some(m), robots, q)?;
        for (k, name) in ["robot", "fleet", "queue", "action_mask"].iter().enumerate() {
            d.set_item(*name, obs.get_item(k)?)?;
        }
        d.set_item("reward", PyArray1::from_vec(py, self.reward))?;
        d.set_item("terminated", PyArray1::from_vec(py, self.terminated))?;
        d.set_item("truncated", PyArray1::from_vec(py, self.truncated))?;
        d.set_item("invalid", PyArray1::from_vec(py, self.invalid))?;
        d.set_item("robot_id", PyArray1::from_vec(py, self.robot_id))?;
        d.set_item("t", PyArray1::from_vec(py, self.t))?;
        Ok(d)
    }
}

#[pymethods]
impl PyVectorDispatch {
    #[allow(clippy::needless_pass_by_value)] // pyo3 extracts arguments by value
    #[new]
    #[pyo3(signature = (scenarios, max_queue=10, reward=None, invalid="refuse", workers=1))]
    fn new(
        py: Python<'_>,
        scenarios: Vec<PyRef<'_, PyScenario>>,
        max_queue: usize,
        reward: Option<&Bound<'_, PyDict>>,
        invalid: &str,
        workers: usize,
    ) -> PyResult<Self> {
        let list: Vec<Scenario> = scenarios.iter().map(|s| s.inner.clone()).collect();
        let Some(first) = list.first() else { return Err(to_py(Error::scenario("num_envs", 0, "must be 1 or more"))) };
        let st = settings(first, max_queue, reward, invalid)?;
        let robots = first.robots as usize;
        engine(py, move || VectorDispatch::new(&list, &st, workers)).map(|env| PyVectorDispatch { env, robots, max_queue })
    }

    /// Starts every environment's next episode: a dict of arrays, one row per environment.
    fn reset<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let mut rows = Rows::new(self.env.len(), self.env.sizes());
        let env = &mut self.env;
        let r = &mut rows;
        engine(py, move || env.reset(r.batch()))?;
        rows.into_py(py, self.robots, self.max_queue)
    }

    #[allow(clippy::needless_pass_by_value)] // pyo3 extracts arguments by value
    /// One action per environment: a dict of arrays (observation parts, `reward`,
    /// `terminated`, `truncated`, `invalid`, `robot_id`, `t`).
    fn step<'py>(&mut self, py: Python<'py>, actions: PyReadonlyArray1<'py, i64>) -> PyResult<Bound<'py, PyDict>> {
        let codes = actions.as_slice()?;
        let mut rows = Rows::new(self.env.len(), self.env.sizes());
        let env = &mut self.env;
        let r = &mut rows;
        engine(py, move || env.step(codes, r.batch()))?;
        rows.into_py(py, self.robots, self.max_queue)
    }

    /// The scenario environment `k`'s next episode runs.
    fn set_next(&mut self, k: usize, scenario: &PyScenario) -> PyResult<()> {
        if k >= self.env.len() {
            return Err(to_py(Error::scenario("env", k, format!("out of range 0..{}", self.env.len() - 1))));
        }
        self.env.set_next(k, scenario.inner.clone());
        Ok(())
    }

    fn __len__(&self) -> usize {
        self.env.len()
    }
    #[getter]
    fn robots(&self) -> usize {
        self.robots
    }
    #[getter]
    fn max_queue(&self) -> usize {
        self.max_queue
    }
    /// Environment `k`'s result so far.
    fn result<'py>(&self, py: Python<'py>, k: usize) -> PyResult<Bound<'py, PyDict>> {
        if k >= self.env.len() {
            return Err(to_py(Error::scenario("env", k, format!("out of range 0..{}", self.env.len() - 1))));
        }
        result_dict(py, &self.env.env(k).result())
    }
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyDispatcher>()?;
    m.add_class::<PyFleet>()?;
    m.add_class::<PyVectorDispatch>()?;
    m.add_function(wrap_pyfunction!(observation_features, m)?)?;
    m.add_function(wrap_pyfunction!(no_action, m)?)?;
    Ok(())
}
