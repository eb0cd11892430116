//! The one Ctrl-C slicer: every run the binding drives, under any rules, goes forward
//! through [`advance`], in slices of about [`SLICE`] without the GIL, with a check for
//! Ctrl-C between two slices.

use crate::errors::engine;
use multibots_core::record::frame::FrameSink;
use multibots_core::rules::Run;
use pyo3::prelude::*;
use std::time::{Duration, Instant};

/// The wall time a slice aims at: Ctrl-C is seen within about this, or one step when a
/// single step takes longer.
const SLICE: Duration = Duration::from_millis(50);
/// The most steps in a slice (a slice of quiet steps can be very fast).
const MOST: u64 = 1 << 20;

/// Runs `run` up to `steps` steps (fewer if it ends first), giving every frame to `sink`
/// when there is one; returns the steps run. Slices start at one step and grow or shrink so
/// that each takes about [`SLICE`].
pub(crate) fn advance(py: Python<'_>, run: &mut dyn Run, steps: u64, mut sink: Option<&mut (dyn FrameSink + Send)>) -> PyResult<u64> {
    let mut done = 0;
    let mut slice = 1u64;
    while done < steps && !run.done() {
        let k = (steps - done).min(slice);
        let began = Instant::now();
        let (run_, sink_) = (&mut *run, sink.as_deref_mut());
        done += engine(py, move || run_.advance(k, sink_.map(|s| s as &mut dyn FrameSink)))?;
        py.check_signals()?;
        let took = began.elapsed();
        if took < SLICE / 2 {
            slice = (slice * 2).min(MOST);
        } else if took > SLICE * 2 {
            slice = (slice / 2).max(1);
        }
    }
    Ok(done)
}
