//! The League of Robot Runners' action record: what each robot was told and did, step by
//! step, the refused joint actions and the planning time, as the rules of `crate::rules::grid`
//! write them and the competition's result file (`crate::output::lorr`) reads them.

/// A refused joint action, as the result file records it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ActionError {
    /// "unallowed move", "vertex conflict" or "edge conflict".
    pub kind: &'static str,
    /// The robot whose action was found at fault.
    pub agent: i64,
    /// The other robot of a conflict, or -1.
    pub other: i64,
    /// The step the joint action would have led to.
    pub timestep: u32,
}

/// A run's record, step by step.
#[derive(Default)]
pub struct Record {
    n: usize,
    /// The planner's actions, step-major (`step * N + robot`), as `Action as u8`.
    pub planned: Vec<u8>,
    /// The actions carried out, step-major.
    pub actual: Vec<u8>,
    /// Seconds each planning round took.
    pub planner_times: Vec<f64>,
    /// Refused joint actions.
    pub errors: Vec<ActionError>,
    /// Steps lost to the plan time limit.
    pub timeouts: u32,
    /// Steps each robot had a goal.
    pub costs: Vec<u32>,
    /// (step, tasks finished in it), one per planned step.
    pub finished_at: Vec<(u32, u32)>,
    /// (step, milliseconds its plan took), one per planned step.
    pub plan_ms: Vec<(u32, f64)>,
}

impl Record {
    pub(crate) fn new(n: usize) -> Record {
        Record { n, costs: vec![0; n], ..Record::default() }
    }

    /// Steps recorded.
    #[must_use]
    pub fn steps(&self) -> usize {
        self.actual.len().checked_div(self.n).unwrap_or(0)
    }
}
