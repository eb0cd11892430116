//! The three parts a competitor brings under the 2026 rules, as the Start-Kit's `Entry` and
//! `Executor` see the run (`SharedEnvironment`, tag `v3.1.0`), and the adapter that lets a
//! 2024 scheduler of `schedule/` serve here:
//!
//! | part | called | sees | answers |
//! | --- | --- | --- | --- |
//! | [`Scheduler26`] | at every planner call, first | [`PlanEnv`] | a task id or -1 per robot |
//! | [`Planner26`] | at every planner call, after the scheduler | [`PlanEnv`], with each robot's goal | each robot's next actions |
//! | [`Executor`] | `process_new_plan` when a plan arrives; `next_command` every tick | [`ExecEnv`] | the robots' queues of staged actions and where they will be; GO or STOP per robot |
//!
//! A call's answer is checked by the rules (a schedule robot by robot, staged actions for being
//! a prefix of the old queue followed by the plan); an entry that fails (a Python entry that
//! raises) ends the run with its error.

use super::footprint::{Floor, Pose};
use crate::error::Result;
use crate::input::lorr::GridMap;
use crate::rules::grid::action::Action;
use crate::rules::grid::pool::TaskPool;
use crate::rules::grid::schedule::{ScheduleView, Scheduler};

/// What the scheduler and the planner see at a planner call (the planner's side of the
/// Start-Kit's `SharedEnvironment`).
pub struct PlanEnv<'a> {
    pub map: &'a GridMap,
    /// The floor: obstacles, `agentSize`, `agentCounter`.
    pub floor: &'a Floor,
    /// The tick of the call (`system_timestep`).
    pub tick: u32,
    /// The time limit the Start-Kit hands this call, in ms (the initial call's, then the
    /// communication interval's): a label here, as no call is timed against it.
    pub time_limit_ms: u32,
    /// Where the executor said each robot will be when this call's plan arrives
    /// (`curr_states`).
    pub predicted: &'a [Pose],
    /// Where each robot is now (`system_states`), and whether it is held by a delay.
    pub system: &'a [Pose],
    pub held: &'a [bool],
    /// Each robot's staged actions now.
    pub staged: &'a [Vec<Action>],
    /// The revealed tasks not finished, and the schedule in force.
    pub pool: &'a TaskPool,
    /// The task file's lines (a task's errands are `lines[task.line]`).
    pub lines: &'a [Vec<u32>],
    /// `curr_task_schedule`: the schedule in force for the scheduler, the scheduler's
    /// proposal for the planner.
    pub schedule: &'a [i64],
    /// Each robot's goal, the next errand of its proposed task, or `planner::NO_GOAL` (for the
    /// scheduler, the goals of the schedule in force).
    pub goals: &'a [u32],
    /// Tasks revealed and robots freed since the last call (`new_tasks`, `new_freeagents`).
    pub new_tasks: &'a [u32],
    pub new_free: &'a [u32],
    /// Ticks between planner calls (`ceil(planCommTimeLimit / actionMoveTimeLimit)`).
    pub interval: u32,
}

/// What the executor sees (the executor's own `SharedEnvironment`).
pub struct ExecEnv<'a> {
    pub map: &'a GridMap,
    pub floor: &'a Floor,
    /// The tick.
    pub tick: u32,
    /// Where each robot is (`system_states`), and whether it is held by a delay (drawn at
    /// the last tick).
    pub system: &'a [Pose],
    pub held: &'a [bool],
    /// Ticks between planner calls.
    pub interval: u32,
}

/// A scheduler under the 2026 rules.
pub trait Scheduler26: Send + Sync {
    /// Its name (a built-in's, or the user's file).
    fn name(&self) -> &str;
    /// Proposes a task id or -1 per robot; `proposal` holds the schedule in force when
    /// called.
    fn schedule(&mut self, env: &PlanEnv<'_>, proposal: &mut Vec<i64>) -> Result<()>;
}

/// A planner under the 2026 rules.
pub trait Planner26: Send + Sync {
    /// Its name.
    fn name(&self) -> &str;
    /// Each robot's next actions, in order (`plan[robot]`); `plan` comes with one empty
    /// list per robot.
    fn plan(&mut self, env: &PlanEnv<'_>, plan: &mut [Vec<Action>]) -> Result<()>;
}

/// An executor under the 2026 rules.
pub trait Executor: Send + Sync {
    /// Its name.
    fn name(&self) -> &str;
    /// A plan has arrived: changes `staged` in place (the rules then check that each queue,
    /// waits left out, is a prefix of the old one followed by the plan) and writes where each
    /// robot will be when the next plan arrives into `predicted`.
    fn process_new_plan(&mut self, env: &ExecEnv<'_>, plan: &[Vec<Action>], staged: &mut [Vec<Action>], predicted: &mut Vec<Pose>) -> Result<()>;
    /// GO (`true`) or STOP (`false`) per robot for this tick: GO plays the front of its
    /// staged actions, STOP makes it wait.
    fn next_command(&mut self, env: &ExecEnv<'_>, staged: &[Vec<Action>], go: &mut [bool]) -> Result<()>;
}

/// A 2024 scheduler of `schedule/` under the 2026 rules: it sees the predicted cells.
pub struct Scheduler24(pub Box<dyn Scheduler>);

impl Scheduler26 for Scheduler24 {
    fn name(&self) -> &str {
        self.0.name()
    }

    fn schedule(&mut self, env: &PlanEnv<'_>, proposal: &mut Vec<i64>) -> Result<()> {
        let loc: Vec<u32> = env.predicted.iter().map(|p| p.loc).collect();
        let heading: Vec<u8> = env.predicted.iter().map(|p| p.heading).collect();
        let view = ScheduleView { map: env.map, loc: &loc, heading: &heading, pool: env.pool, lines: env.lines, t: env.tick };
        self.0.schedule(&view, proposal);
        Ok(())
    }
}

/// Whether `new` (waits left out) is a prefix of `old` followed by `plan` (waits left out):
/// what an executor may make of a queue.
#[must_use]
pub fn is_prefix(old: &[Action], plan: &[Action], new: &[Action]) -> bool {
    let moves = |a: &&Action| !matches!(a, Action::W | Action::T);
    let mut expected = old.iter().filter(moves).chain(plan.iter().filter(moves));
    new.iter().filter(moves).all(|a| expected.next() == Some(a))
}
