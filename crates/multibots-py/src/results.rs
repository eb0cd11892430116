//! A run's result as a Python dictionary (NumPy arrays for per-robot columns).

use multibots_core::record::metrics::RunResult;
use multibots_core::State;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Per-robot counts as uint64, as Python has always had them: the engine keeps them in 32 bits
/// (no run is longer than `limits::MAX_STEPS`).
pub(crate) fn counts<'py>(py: Python<'py>, v: &[u32]) -> Bound<'py, PyArray1<u64>> {
    PyArray1::from_iter(py, v.iter().map(|&c| u64::from(c)))
}

pub(crate) fn result_dict<'py>(py: Python<'py>, r: &RunResult) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("T", r.t)?;
    d.set_item("S", r.s)?;
    d.set_item("C", r.c)?;
    d.set_item("outcome", r.outcome.map_or("running", |o| o.as_str()))?;
    d.set_item("steps", r.steps)?;
    d.set_item("delivered", r.delivered)?;
    d.set_item("goods_total", r.goods_total)?;
    d.set_item("stranded", r.stranded.clone())?;
    d.set_item("cost", r.cost)?;
    d.set_item("window", r.window)?;
    d.set_item("windows", r.windows.clone())?;
    d.set_item("throughput", r.throughput)?;
    d.set_item("sustained_throughput", r.sustained_throughput)?;
    d.set_item("wait_share", r.wait_share)?;
    d.set_item("utilisation", r.utilisation)?;
    d.set_item("contacts", r.contacts)?;
    d.set_item("closest", r.closest)?;
    match &r.gridlock {
        Some(g) => {
            let gd = PyDict::new(py);
            gd.set_item("step", g.step)?;
            gd.set_item("waiting", g.waiting.clone())?;
            gd.set_item("crossings", g.crossings.clone())?;
            d.set_item("gridlock", gd)?;
        }
        None => d.set_item("gridlock", py.None())?,
    }
    match &r.collapse {
        Some(c) => {
            let cd = PyDict::new(py);
            cd.set_item("step", c.step)?;
            cd.set_item("best", c.best)?;
            cd.set_item("last", c.last)?;
            cd.set_item("stranded", c.stranded)?;
            cd.set_item("collapsed", c.collapsed)?;
            cd.set_item("first_stranded", c.first_stranded)?;
            cd.set_item("crossings", c.crossings.clone())?;
            d.set_item("collapse", cd)?;
        }
        None => d.set_item("collapse", py.None())?,
    }
    let resource = |u: &multibots_core::record::resources::ResourceUse| -> PyResult<Bound<'py, PyDict>> {
        let ud = PyDict::new(py);
        ud.set_item("kind", u.kind.as_str())?;
        ud.set_item("node", u.node.clone())?;
        ud.set_item("busy", u.busy)?;
        ud.set_item("mean_queue", u.mean_queue)?;
        ud.set_item("longest_queue", u.longest_queue)?;
        Ok(ud)
    };
    let resources = r.resources.iter().map(resource).collect::<PyResult<Vec<_>>>()?;
    d.set_item("resources", resources)?;
    match &r.bottleneck {
        Some(b) => {
            let bd = resource(&b.resource)?;
            bd.set_item("relieve", b.relieve.clone())?;
            d.set_item("bottleneck", bd)?;
        }
        None => d.set_item("bottleneck", py.None())?,
    }
    let st = &r.robots;
    d.set_item("distance", PyArray1::from_slice(py, &st.distance))?;
    d.set_item("wait_steps", counts(py, &st.wait_steps))?;
    d.set_item("collisions", counts(py, &st.collisions))?;
    d.set_item("energy_used", PyArray1::from_slice(py, &st.energy_used))?;
    d.set_item("robot_delivered", counts(py, &st.delivered))?;
    d.set_item("charges", counts(py, &st.charges))?;
    let flat: Vec<u64> = st.state_steps.iter().flat_map(|row| row.iter().map(|&c| u64::from(c))).collect();
    d.set_item("state_steps", PyArray1::from_vec(py, flat).reshape([st.state_steps.len(), State::COUNT])?)?;
    match &r.lifelong {
        Some(l) => {
            let ll = PyDict::new(py);
            ll.set_item("ordered", l.ordered)?;
            ll.set_item("delivered", r.delivered)?;
            ll.set_item("in_flight", l.in_flight)?;
            ll.set_item("queued", l.queued)?;
            ll.set_item("waiting", l.waiting)?;
            ll.set_item("latency_p50", l.latency_p50)?;
            ll.set_item("latency_p95", l.latency_p95)?;
            ll.set_item("latency_p99", l.latency_p99)?;
            ll.set_item("latency_mean", l.latency_mean)?;
            ll.set_item("energy_per_delivery", l.energy_per_delivery)?;
            d.set_item("lifelong", ll)?;
        }
        None => d.set_item("lifelong", py.None())?,
    }
    match &r.people {
        Some(p) => d.set_item("people", people_dict(py, p)?)?,
        None => d.set_item("people", py.None())?,
    }
    Ok(d)
}

/// A run's people figures; `alone`: the same people's with the fleet removed (or None).
fn people_dict<'py>(py: Python<'py>, p: &multibots_core::people::PeopleFigures) -> PyResult<Bound<'py, PyDict>> {
    let pd = PyDict::new(py);
    pd.set_item("count", p.count)?;
    pd.set_item("min_gap", p.min_gap)?;
    pd.set_item("gap_p1", p.gap_p1)?;
    pd.set_item("contacts", p.contacts)?;
    pd.set_item("protective_stops", p.protective_stops)?;
    pd.set_item("stopped_steps", p.stopped_steps)?;
    pd.set_item("warning_steps", p.warning_steps)?;
    pd.set_item("person_wait_steps", p.person_wait_steps)?;
    pd.set_item("person_steps", p.person_steps)?;
    pd.set_item("tours", p.tours)?;
    pd.set_item("picks", p.picks)?;
    pd.set_item("walk_steps", p.walk_steps)?;
    pd.set_item("blocked_steps", p.blocked_steps)?;
    pd.set_item("protective_radius", p.protective_radius)?;
    pd.set_item("warning_radius", p.warning_radius)?;
    pd.set_item("px_per_m", p.px_per_m)?;
    pd.set_item("step_seconds", p.step_seconds)?;
    match &p.alone {
        Some(a) => pd.set_item("alone", people_dict(py, a)?)?,
        None => pd.set_item("alone", py.None())?,
    }
    Ok(pd)
}
