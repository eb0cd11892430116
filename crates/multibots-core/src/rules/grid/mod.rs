//! The League of Robot Runners' rules (2023 and 2024 competitions), as a rule set of the
//! engine: robots on grid cells with a heading, one action each per step, a planner
//! (`planner/`) and, under the 2024 rules, a scheduler (`schedule/`). The action model and
//! its check are in `action.rs`, the 2023 round-robin errands in `errands.rs`, the 2024 task
//! pool and the check of schedules in `pool.rs`. What a run records is in
//! [`crate::record::grid`]; the result file the competition's tools read is written from it
//! by `crate::output::lorr`.
//!
//! A step, in the order of the Start-Kit's `BaseSystem::simulate` (tag `v2.1.2`; the 2023
//! archive's order is the same):
//! 1. (2024) the scheduler proposes a task per robot, starting from the schedule in force;
//!    each robot's goal is the next errand of the task proposed for it (2023: its first
//!    errand);
//! 2. the planner proposes actions, timed. With a plan time limit L ms, a plan that took
//!    e ms costs floor(e / L) steps in which every robot waits first (`T` in the paths; 2023:
//!    `T` in the planner's paths, `W` in the actual ones and an error per step), as the
//!    Start-Kit lets its clock run while it waits for the planner;
//! 3. every robot with a goal adds one to its cost (`sumOfCost`, `makespan`);
//! 4. the actions are checked (`action.rs`); a fault makes every robot wait, and is recorded;
//! 5. the tasks are updated: 2023, errands reached are done and refilled; 2024, the proposed
//!    schedule is checked and set, errands reached advance, the pool is refilled.

pub mod action;
pub mod errands;
mod figures;
pub mod planner;
pub mod pool;
pub mod schedule;
mod show;
pub mod y2026;

pub use figures::Figures;
pub use show::CELL_PX;
pub use y2026::Lorr26;

use crate::error::Result;
use crate::input::limits::MAX_PLAN_TIME_LIMIT_MS;
use crate::input::lorr::{Problem, Version};
use crate::record::grid::{ActionError, Record};
use action::{Action, Validator};
use errands::RoundRobin;
use planner::{PlanView, Planner, NO_GOAL};
use pool::TaskPool;
use schedule::{ScheduleView, Scheduler};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How a LoRR run is played.
#[derive(Clone, Debug)]
pub struct LorrOptions {
    /// The planner's name (`auto`, the default: [`planner::auto_choice`]).
    pub planner: String,
    /// The scheduler's name (`auto`, the default: `reassign` under the 2024 rules, `soonest`
    /// under the 2026 rules).
    pub scheduler: String,
    /// The seed of the planner's tie-breaks (default 0).
    pub seed: u64,
    /// The competition's plan time limit per step, in milliseconds; `None` (the default)
    /// lets the planner take what it needs, and the run is then the same on every machine.
    pub plan_time_limit_ms: Option<u64>,
    /// (2026 rules) whether an executor's staged actions must stay a prefix of those it had
    /// followed by the new plan (the Start-Kit checks it unless `--disableStagedActionValidation`,
    /// which the Combined track allows). Default: checked.
    pub staged_validation: bool,
}

impl Default for LorrOptions {
    fn default() -> Self {
        LorrOptions { planner: "auto".into(), scheduler: "auto".into(), seed: 0, plan_time_limit_ms: None, staged_validation: true }
    }
}

/// The task rules in play.
pub enum Tasks {
    /// 2023.
    RoundRobin(RoundRobin),
    /// 2024.
    Pool(TaskPool),
}

/// A run of a LoRR problem.
pub struct LorrRun {
    problem: Arc<Problem>,
    options: LorrOptions,
    t: u32,
    loc: Vec<u32>,
    heading: Vec<u8>,
    tasks: Tasks,
    planner: Box<dyn Planner>,
    scheduler: Box<dyn Scheduler>,
    proposal: Vec<i64>,
    goals: Vec<u32>,
    actions: Vec<Action>,
    validator: Validator,
    record: Record,
    /// What the frames show (`show.rs`).
    shown: show::Shown,
    /// Why the run stopped, if an entry failed (a Python planner or scheduler that raised).
    failure: Option<crate::error::Error>,
}

impl LorrRun {
    /// A run at step 0: robots on their start cells facing east, the first tasks revealed.
    /// `auto` is resolved here: the run's options, its replay header and [`LorrRun::planner`]
    /// name the planner that plays.
    pub fn new(problem: Arc<Problem>, mut options: LorrOptions) -> Result<LorrRun> {
        if options.planner == "auto" {
            options.planner = planner::auto_choice(&problem.map, problem.team_size()).into();
        }
        let planner = planner::built_in(&options.planner, &problem.map, problem.team_size(), options.seed)?;
        options.scheduler = schedule::resolve(&options.scheduler, false).to_string();
        let scheduler = schedule::built_in(&options.scheduler)?;
        LorrRun::with(problem, options, planner, scheduler)
    }

    /// A run with a planner and a scheduler of the caller's (the names in `options` are
    /// then only labels).
    pub fn with(problem: Arc<Problem>, mut options: LorrOptions, planner: Box<dyn Planner>, scheduler: Box<dyn Scheduler>) -> Result<LorrRun> {
        options.scheduler = schedule::resolve(&options.scheduler, false).to_string();
        let n = problem.team_size();
        if let Some(ms) = options.plan_time_limit_ms.filter(|&ms| ms == 0 || ms > MAX_PLAN_TIME_LIMIT_MS) {
            return Err(crate::error::Error::scenario("plan_time_limit", ms, format!("must be from 1 to {MAX_PLAN_TIME_LIMIT_MS} ms")));
        }
        let tasks = match problem.version {
            Version::Y2023 => Tasks::RoundRobin(RoundRobin::new(n, problem.reveal(), &problem.tasks)),
            Version::Y2024 => Tasks::Pool(TaskPool::new(n, problem.reveal(), problem.tasks.len())),
            Version::Y2026 => return Err(crate::error::Error::scenario("problem", problem.path.display(), "is a 2026 problem, played by `Lorr26`")),
        };
        let mut run = LorrRun {
            loc: problem.starts.clone(),
            heading: vec![0; n],
            tasks,
            planner,
            scheduler,
            proposal: vec![-1; n],
            goals: vec![NO_GOAL; n],
            actions: vec![Action::W; n],
            validator: Validator::default(),
            record: Record::new(n),
            shown: show::Shown::default(),
            failure: None,
            problem,
            options,
            t: 0,
        };
        run.note_shown();
        Ok(run)
    }

    /// The planner that plays, as the options name it (`auto` resolved by [`LorrRun::new`];
    /// for [`LorrRun::with`], the caller's label).
    #[must_use]
    pub fn planner(&self) -> &str {
        &self.options.planner
    }

    /// Runs until step `until` (at most); the steps run.
    pub fn run_to(&mut self, until: u32) -> u32 {
        let start = self.t;
        while self.t < until && self.failure.is_none() {
            self.step(until);
        }
        self.t - start
    }

    /// Why the run stopped early, if a planner or scheduler failed.
    #[must_use]
    pub fn failure(&self) -> Option<&crate::error::Error> {
        self.failure.as_ref()
    }

    /// One planning round: one step, or more if the planner overran the time limit; never
    /// past step `until`.
    pub fn step(&mut self, until: u32) {
        let n = self.loc.len();
        let began = Instant::now();
        match &self.tasks {
            Tasks::RoundRobin(rr) => {
                for k in 0..n {
                    self.goals[k] = rr.goal(k);
                }
            }
            Tasks::Pool(pool) => {
                self.proposal.copy_from_slice(&pool.current);
                let view = ScheduleView { map: &self.problem.map, loc: &self.loc, heading: &self.heading, pool, lines: &self.problem.tasks, t: self.t };
                self.scheduler.schedule(&view, &mut self.proposal);
                if let Some(e) = self.scheduler.failure() {
                    self.failure = Some(e);
                    return;
                }
                for k in 0..n {
                    let id = self.proposal[k];
                    self.goals[k] = if pool.is_open(id) { pool.next_errand(id as u32, &self.problem.tasks) } else { NO_GOAL };
                }
            }
        }
        let tasks = match &self.tasks {
            Tasks::Pool(pool) => Some(planner::TaskView { pool, proposal: &self.proposal, lines: &self.problem.tasks }),
            Tasks::RoundRobin(_) => None,
        };
        let view = PlanView { map: &self.problem.map, loc: &self.loc, heading: &self.heading, goals: &self.goals, t: self.t, tasks };
        self.planner.plan(&view, &mut self.actions);
        if let Some(e) = self.planner.failure() {
            self.failure = Some(e);
            return;
        }
        let spent = began.elapsed();
        self.record.planner_times.push(spent.as_secs_f64());
        let timeouts = match self.options.plan_time_limit_ms {
            Some(limit) => (spent.as_nanos() / Duration::from_millis(limit).as_nanos()) as u32,
            None => 0,
        };
        let y2023 = matches!(self.tasks, Tasks::RoundRobin(_));
        for _ in 0..timeouts.min(until - self.t) {
            self.record.timeouts += 1;
            self.count_costs();
            self.t += 1;
            self.record_timeout(y2023);
        }
        if self.t >= until {
            // The round's plan was never carried out: nothing changed but the clock.
            self.shown.events.clear();
            return;
        }
        self.count_costs();
        let fault = self.validator.check(&self.problem.map, &self.loc, &self.heading, &self.actions, self.t + 1);
        self.record.planned.extend(self.actions.iter().map(|&a| a as u8));
        match fault {
            None => {
                self.loc.copy_from_slice(self.validator.next());
                for (h, a) in self.heading.iter_mut().zip(&self.actions) {
                    *h = a.turned(*h);
                }
                self.record.actual.extend(self.actions.iter().map(|&a| a as u8));
            }
            Some(e) => {
                self.record.errors.push(e);
                self.record.actual.extend(std::iter::repeat(Action::W as u8).take(n));
            }
        }
        self.t += 1;
        let done = match &mut self.tasks {
            Tasks::RoundRobin(rr) => rr.update(self.t, &self.loc, &self.problem.tasks),
            Tasks::Pool(pool) => pool.update(self.t, &self.proposal, &self.loc, &self.problem.tasks),
        };
        self.record.finished_at.push((self.t, done as u32));
        self.record.plan_ms.push((self.t, spent.as_secs_f64() * 1e3));
        self.note_shown();
    }

    /// A step lost to the plan time limit: every robot's plan and action is `T` (2023: the
    /// action carried out is `W`, and the empty action vector is an error).
    fn record_timeout(&mut self, y2023: bool) {
        let n = self.loc.len();
        self.record.planned.extend(std::iter::repeat(Action::T as u8).take(n));
        let carried = if y2023 { Action::W } else { Action::T };
        self.record.actual.extend(std::iter::repeat(carried as u8).take(n));
        if y2023 {
            // The 2023 system checks an empty action vector and records its size as wrong.
            self.record.errors.push(ActionError { kind: "incorrect vector size", agent: -1, other: -1, timestep: self.t });
        }
    }

    fn count_costs(&mut self) {
        for (c, &g) in self.record.costs.iter_mut().zip(&self.goals) {
            if g != NO_GOAL {
                *c += 1;
            }
        }
    }

    /// The current step.
    #[must_use]
    pub fn t(&self) -> u32 {
        self.t
    }

    /// Tasks (2024) or errands (2023) finished so far: the competition's score.
    #[must_use]
    pub fn finished(&self) -> u64 {
        match &self.tasks {
            Tasks::RoundRobin(rr) => rr.finished,
            Tasks::Pool(pool) => pool.finished,
        }
    }

    /// Each robot's cell.
    #[must_use]
    pub fn locations(&self) -> &[u32] {
        &self.loc
    }

    /// Each robot's heading (0 east, 1 south, 2 west, 3 north).
    #[must_use]
    pub fn headings(&self) -> &[u8] {
        &self.heading
    }

    /// The problem played.
    #[must_use]
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The options played with.
    #[must_use]
    pub fn options(&self) -> &LorrOptions {
        &self.options
    }

    /// The task rules' state.
    #[must_use]
    pub fn tasks(&self) -> &Tasks {
        &self.tasks
    }

    /// What the run recorded.
    #[must_use]
    pub fn record(&self) -> &Record {
        &self.record
    }
}

#[cfg(test)]
mod tests;
