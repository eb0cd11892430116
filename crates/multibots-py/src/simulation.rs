//! `Simulation`: a run that Python steps and inspects, its state as NumPy arrays.

use crate::results::result_dict;
use crate::scenario::PyScenario;
use multibots_core::output::codec::Frames;
use multibots_core::record::frame::Frame;
use multibots_core::rules::Run;
use multibots_core::Simulation;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

/// (node, robots) per node with a queue, robots queued for a charger, (from, to, robots) per lane.
type QueuesNow = (Vec<(u32, u32)>, u32, Vec<(u32, u32, u32)>);

/// A run that Python steps and inspects.
#[pyclass(module = "multibots._core", name = "Simulation")]
pub(crate) struct PySimulation {
    sim: Simulation,
}

#[pymethods]
impl PySimulation {
    #[new]
    #[pyo3(signature = (scenario, allocator=None))]
    fn new(py: Python<'_>, scenario: &PyScenario, allocator: Option<PyObject>) -> PyResult<Self> {
        crate::strategy::new_simulation(py, &scenario.inner, allocator).map(|sim| PySimulation { sim })
    }

    /// Runs `n` steps (fewer if the run ends first); returns the steps run.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<u64> {
        crate::slicer::advance(py, &mut self.sim, n, None)
    }

    /// Runs to the end; returns the result dictionary.
    fn run<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::slicer::advance(py, &mut self.sim, u64::MAX, None)?;
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
        PyArray1::from_vec(py, r.positions_flat()).reshape([r.len(), 2])
    }
    #[getter]
    fn human_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (x, y) = self.sim.people().map_or((&[][..], &[][..]), |p| (&p.x[..], &p.y[..]));
        let flat: Vec<f64> = x.iter().zip(y).flat_map(|(&a, &b)| [a, b]).collect();
        PyArray1::from_vec(py, flat).reshape([x.len(), 2])
    }
    #[getter]
    fn human_radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let p = self.sim.people();
        PyArray1::from_vec(py, vec![p.map_or(0.0, |p| p.radius); p.map_or(0, multibots_core::people::People::len)])
    }
    #[getter]
    fn headings<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.sim.robots().heading)
    }
    #[getter]
    fn states<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        PyArray1::from_vec(py, self.sim.robots().state_codes())
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
        PyArray1::from_vec(py, self.sim.robots().home_ids())
    }
    /// Cell each robot carries, or -1.
    #[getter]
    fn carrying<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        PyArray1::from_vec(py, self.sim.robots().carried_cells())
    }
    /// Cell each robot fetches or carries, or -1.
    #[getter]
    fn task_cells<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        PyArray1::from_vec(py, self.sim.robots().task_cells())
    }
    /// 1 where a storage cell holds goods.
    #[getter]
    fn cells<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        PyArray1::from_iter(py, self.sim.cells_full().iter().map(|&f| u8::from(f)))
    }
    /// Collisions S of each robot.
    #[getter]
    fn robot_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        crate::results::counts(py, &self.sim.stats().collisions)
    }
    /// Charges C of each robot.
    #[getter]
    fn robot_c<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        crate::results::counts(py, &self.sim.stats().charges)
    }
    /// Cells of the goods still in the queue, front first.
    #[getter]
    fn queue(&self) -> Vec<u32> {
        self.sim.queue_cells()
    }
    /// Events of the last step: (step, kind, robot, cell) rows; cell is -1 where none.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let ev = self.sim.events();
        let flat: Vec<i64> =
            ev.iter().flat_map(|e| [e.step as i64, e.kind as i64, i64::from(e.robot), if e.cell == u32::MAX { -1 } else { i64::from(e.cell) }]).collect();
        PyArray1::from_vec(py, flat).reshape([ev.len(), 4])
    }
    /// The layout JSON.
    #[getter]
    fn layout_json(&self) -> String {
        self.sim.world().layout.to_json().to_string()
    }
    /// The current state as one frame of the replay codec (a decompressed one-frame chunk
    /// numbered by the step, without events), for live viewers.
    fn frame_chunk<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let mut frame = Frame::default();
        self.sim.emit(&mut frame, false);
        let mut f = Frames::with_capacity(self.sim.robots().len(), 1);
        f.push(&frame, self.sim.t(), false);
        let mut raw = Vec::new();
        f.encode(self.sim.t(), &mut raw);
        PyBytes::new(py, &raw)
    }
    /// What a viewer needs before the first frame (the replay header), as JSON.
    fn viewer_header(&self, scenario_toml: &str) -> String {
        multibots_core::output::replay::header(&self.sim, serde_json::json!({"scenario": scenario_toml})).to_string()
    }
    /// The robots queued in the last step: (node, robots) for each node with a queue, the
    /// robots queued for a shared charger, and (from, to, robots) for each lane with a queue.
    fn queues(&self) -> QueuesNow {
        let q = self.sim.queues();
        (q.nodes.iter().map(|&(n, c)| (n.0, c)).collect(), q.chargers, q.lanes.iter().map(|&(u, v, c)| (u.0, v.0, c)).collect())
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
