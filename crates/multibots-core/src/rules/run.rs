//! The run contract: what every rule set's run answers, so that whatever drives a run (the
//! binding's Ctrl-C slicer, the replay recorder, batches, viewers) is written once, for any
//! rules. Gymnasium's `Env` (`reset`/`step`) is the model: a small surface every run keeps.
//!
//! [`crate::Simulation`] keeps it for the paper and the original rules, and
//! [`crate::rules::grid::LorrRun`] for the League of Robot Runners' grid.

use crate::error::Result;
use crate::record::frame::{Frame, FrameSink, Summary};
use crate::record::resources::QueueLog;
use serde_json::Value;

/// A run under any rules.
pub trait Run: Send {
    /// Runs up to `max` steps, fewer if the run ends first, and gives `sink` the frame of
    /// every step run when there is one; returns the steps run. A sink sees one frame per
    /// step, in order, whatever the rules do in a step (under the League of Robot Runners'
    /// rules a planning round that overran its time limit takes several: its lost steps
    /// repeat the last frame).
    fn advance(&mut self, max: u64, sink: Option<&mut dyn FrameSink>) -> Result<u64>;
    /// The current step (0 before the first).
    fn time(&self) -> u64;
    /// Whether the run has ended (a run without an end of its own never has).
    fn done(&self) -> bool;
    /// The current state as a frame, with the events of the step that led to it when
    /// `events` (frame 0's are the run's first assignments, where the rules have any).
    fn emit(&self, frame: &mut Frame, events: bool);
    /// What a viewer needs before the first frame: the fleet, the floor, the run's inputs
    /// (the header fields of `docs/replay-format.md` that belong to the run).
    fn describe(&self) -> Value;
    /// The figures so far, as a recording's footer states them.
    fn summary(&self) -> Summary;
    /// A log for the queues of the resources the run reports, frame by frame (`None` where
    /// it reports none).
    fn queue_log(&self) -> Option<QueueLog> {
        None
    }
}
