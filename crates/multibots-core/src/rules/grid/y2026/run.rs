//! A run under the 2026 rules: the tick loop and the planner's calls (the order is in the
//! module docs of `y2026`).

use super::delays::Delays;
use super::entries::{is_prefix, ExecEnv, Executor, PlanEnv, Planner26, Scheduler24, Scheduler26};
use super::executor::Tpg;
use super::footprint::{Floor, Pose};
use super::model::ActionModel;
use super::planner::Rollout;
use super::tasks;
use crate::error::{Error, Result};
use crate::input::lorr::{Problem, Version};
use crate::record::grid26::{Record26, SEGMENT};
use crate::rules::grid::action::Action;
use crate::rules::grid::planner::{self, NO_GOAL};
use crate::rules::grid::pool::TaskPool;
use crate::rules::grid::{schedule, LorrOptions};
use std::sync::Arc;
use std::time::Instant;

/// The Start-Kit's default `actionMoveTimeLimit` (ms per tick) and `initialPlanTimeLimit`.
pub const TICK_MS: u32 = 100;
/// The Start-Kit's default `planCommTimeLimit`, in ms.
pub const COMM_MS: u32 = 1000;
/// The Start-Kit's default `initialPlanTimeLimit`, in ms.
pub const INITIAL_MS: u32 = 1000;

/// The communication interval of a run with `options`, in ms: `--plan-time-limit`, or the
/// Start-Kit's default [`COMM_MS`].
#[must_use]
pub fn comm_ms(options: &LorrOptions) -> u32 {
    options.plan_time_limit_ms.map_or(COMM_MS, |ms| ms.min(u64::from(u32::MAX)) as u32)
}

/// An entry's failure.
fn fail(entry: &str, reason: String) -> Error {
    Error::Entry { entry: entry.to_string(), reason }
}

/// A competitor's three parts.
pub struct Entries {
    pub scheduler: Box<dyn Scheduler26>,
    pub planner: Box<dyn Planner26>,
    pub executor: Box<dyn Executor>,
}

impl Entries {
    /// The built-ins: a scheduler and a planner of the 2024 tables by name (the planner
    /// played ahead, `planner.rs`), and the `tpg` executor.
    pub fn built_in(problem: &Problem, options: &LorrOptions) -> Result<Entries> {
        let planner = planner::built_in_lean(&options.planner, &problem.map, problem.team_size(), options.seed)?;
        Ok(Entries {
            scheduler: Box::new(Scheduler24(schedule::built_in(&options.scheduler)?)),
            planner: Box::new(Rollout::new(planner, &options.planner)),
            executor: Box::new(Tpg::new()),
        })
    }
}

/// A run of a 2026 problem.
pub struct Lorr26 {
    pub(super) problem: Arc<Problem>,
    pub(super) options: LorrOptions,
    pub(super) floor: Floor,
    pub(super) t: u32,
    /// Ticks between planner calls, and the time limit each call is told (ms).
    interval: u32,
    comm_ms: u32,
    pub(super) states: Vec<Pose>,
    next: Vec<Pose>,
    model: ActionModel,
    delays: Delays,
    pub(super) held: Vec<bool>,
    pub(super) pool: TaskPool,
    entries: Entries,
    /// The last call's schedule and plan, applied at the next communication point.
    schedule: Vec<i64>,
    plan: Vec<Vec<Action>>,
    staged: Vec<Vec<Action>>,
    predicted: Vec<Pose>,
    goals: Vec<u32>,
    /// Tasks revealed and robots freed since the last call.
    new_tasks: Vec<u32>,
    new_free: Vec<u32>,
    go: Vec<bool>,
    act: Vec<Action>,
    started: Vec<(u32, u32, u32)>,
    pub(super) record: Record26,
    /// What the frames show (`show.rs`).
    pub(super) shown: super::show::Shown,
}

impl Lorr26 {
    /// A run at tick 0 with the built-in entries named by `options` (`auto` resolved).
    pub fn new(problem: Arc<Problem>, mut options: LorrOptions) -> Result<Lorr26> {
        Lorr26::resolve(&problem, &mut options);
        let entries = Entries::built_in(&problem, &options)?;
        Lorr26::with(problem, options, entries)
    }

    /// Names the built-ins `auto` stands for under the 2026 rules, for `problem`.
    pub fn resolve(problem: &Problem, options: &mut LorrOptions) {
        if options.planner == "auto" {
            options.planner = planner::auto_choice_2026(&problem.map, problem.team_size()).into();
        }
        options.scheduler = schedule::resolve(&options.scheduler, true).to_string();
    }

    /// A run with the caller's entries (the names in `options` are then labels); the initial
    /// planner call is made here.
    pub fn with(problem: Arc<Problem>, options: LorrOptions, entries: Entries) -> Result<Lorr26> {
        let rules = match (&problem.version, &problem.y2026) {
            (Version::Y2026, Some(r)) => r.clone(),
            _ => return Err(Error::scenario("problem", problem.path.display(), "is not a 2026 problem (no delayConfig)")),
        };
        let n = problem.team_size();
        // `--plan-time-limit` is the communication interval under these rules.
        let comm_ms = comm_ms(&options);
        let interval = comm_ms.div_ceil(TICK_MS).max(1);
        let floor = Floor::new(problem.map.rows, problem.map.cols, problem.map.free.iter().map(|&f| !f).collect(), rules.agent_size, rules.agent_counter);
        if let Some((i, why)) = floor.misfit(&problem.starts) {
            return Err(Error::scenario("agentSize", rules.agent_size, format!("robot {i} cannot start: {why}")));
        }
        let pool = TaskPool::new(n, problem.reveal(), problem.tasks.len());
        let states: Vec<Pose> = problem.starts.iter().map(|&c| Pose::at(c)).collect();
        let mut run = Lorr26 {
            interval,
            comm_ms,
            next: Vec::with_capacity(n),
            model: ActionModel::default(),
            delays: Delays::new(&rules.delays, n),
            held: vec![false; n],
            new_tasks: pool.new_tasks.clone(),
            new_free: (0..n as u32).collect(),
            pool,
            entries,
            schedule: vec![-1; n],
            plan: vec![Vec::new(); n],
            staged: vec![Vec::new(); n],
            predicted: states.clone(),
            goals: vec![NO_GOAL; n],
            go: vec![false; n],
            act: vec![Action::W; n],
            started: Vec::new(),
            record: Record26::new(n),
            shown: super::show::Shown::default(),
            states,
            floor,
            problem,
            options,
            t: 0,
        };
        run.call(INITIAL_MS)?;
        run.note_shown();
        Ok(run)
    }

    /// Runs until tick `until`; the ticks run.
    pub fn run_to(&mut self, until: u32) -> Result<u32> {
        let start = self.t;
        while self.t < until {
            self.tick()?;
        }
        Ok(self.t - start)
    }

    /// One planner call: the scheduler, each robot's goal, the planner.
    fn call(&mut self, limit_ms: u32) -> Result<()> {
        let began = Instant::now();
        let n = self.states.len();
        let mut proposal = self.pool.current.clone();
        let Lorr26 { problem, floor, t, predicted, states, held, staged, pool, new_tasks, new_free, interval, entries, goals, .. } = self;
        macro_rules! env {
            ($goals:expr, $schedule:expr) => {
                PlanEnv {
                    map: &problem.map,
                    floor,
                    tick: *t,
                    time_limit_ms: limit_ms,
                    predicted,
                    system: states,
                    held,
                    staged,
                    pool,
                    lines: &problem.tasks,
                    schedule: $schedule,
                    goals: $goals,
                    new_tasks,
                    new_free,
                    interval: *interval,
                }
            };
        }
        entries.scheduler.schedule(&env!(goals, &pool.current), &mut proposal)?;
        let scheduled = began.elapsed();
        let mut next_goals = vec![NO_GOAL; n];
        for (k, g) in next_goals.iter_mut().enumerate() {
            if let Some(&id) = proposal.get(k) {
                if pool.is_open(id) {
                    *g = pool.next_errand(id as u32, &problem.tasks);
                }
            }
        }
        let mut plan = vec![Vec::new(); n];
        entries.planner.plan(&env!(&next_goals, &proposal), &mut plan)?;
        if plan.len() != n {
            return Err(fail(entries.planner.name(), format!("the plan has {} rows for {n} robots", plan.len())));
        }
        self.goals = next_goals;
        self.schedule = proposal;
        self.plan = plan;
        self.new_tasks.clear();
        self.new_free.clear();
        self.record.plan_ms.push((self.t, began.elapsed().as_secs_f64() * 1e3));
        self.record.schedule_ms.push(scheduled.as_secs_f64() * 1e3);
        Ok(())
    }

    /// A communication point: the last call's schedule and plan applied, the next call made.
    fn communicate(&mut self) -> Result<()> {
        let t = self.t;
        tasks::assign(&mut self.pool, t, &mut self.schedule);
        let before = self.staged.clone();
        let plan = std::mem::take(&mut self.plan);
        let env = ExecEnv { map: &self.problem.map, floor: &self.floor, tick: t, system: &self.states, held: &self.held, interval: self.interval };
        let mut predicted = Vec::with_capacity(self.states.len());
        self.entries.executor.process_new_plan(&env, &plan, &mut self.staged, &mut predicted)?;
        let name = self.entries.executor.name().to_string();
        if self.staged.len() != before.len() || predicted.len() != before.len() {
            return Err(fail(&name, format!("process_new_plan gave {} queues and {} states for {} robots", self.staged.len(), predicted.len(), before.len())));
        }
        for (i, q) in self.staged.iter().enumerate() {
            if self.options.staged_validation && !is_prefix(&before[i], &plan[i], q) {
                let show = |v: &[Action]| v.iter().map(|a| a.letter()).collect::<String>();
                return Err(fail(
                    &name,
                    format!("robot {i}'s staged actions {} are not a prefix of {} then {} (waits left out)", show(q), show(&before[i]), show(&plan[i])),
                ));
            }
        }
        self.predicted = predicted;
        self.call(self.comm_ms)
    }

    /// One tick.
    pub fn tick(&mut self) -> Result<()> {
        if self.t % self.interval == 0 {
            self.communicate()?;
        }
        let n = self.states.len();
        if self.t % SEGMENT == 0 {
            self.record.snapshots.extend(self.states.iter().map(|p| (p.loc, p.heading, p.count)));
        }
        let env = ExecEnv { map: &self.problem.map, floor: &self.floor, tick: self.t, system: &self.states, held: &self.held, interval: self.interval };
        self.entries.executor.next_command(&env, &self.staged, &mut self.go)?;
        self.started.clear();
        self.delays.tick(&mut self.started);
        for &(a, from, to) in &self.started {
            self.record.delays[a as usize].push((from, to));
        }
        for i in 0..n {
            self.held[i] = self.delays.held(i);
            let front = self.staged[i].first().copied();
            self.act[i] = match front {
                Some(a) if self.go[i] && !self.held[i] => a,
                _ => Action::W,
            };
            if self.held[i] {
                self.record.held_ticks += 1;
            }
        }
        self.record.planned.extend(self.act.iter().map(|&a| a as u8));
        self.model.step(&self.floor, &self.states, &mut self.act, self.t + 1, &mut self.next);
        self.record.actual.extend(self.act.iter().map(|&a| a as u8));
        for i in 0..n {
            let (pre, now) = (self.states[i], self.next[i]);
            let q = &mut self.staged[i];
            if q.is_empty() {
                continue;
            }
            if (q[0] == Action::W && self.act[i] == Action::W) || pre.loc != now.loc || pre.heading != now.heading {
                q.remove(0);
            }
        }
        std::mem::swap(&mut self.states, &mut self.next);
        self.t += 1;
        let loc: Vec<u32> = self.states.iter().map(|p| p.loc).collect();
        let done = self.pool.advance(self.t, &loc, &self.problem.tasks);
        for &k in &self.pool.new_free {
            self.schedule[k as usize] = -1;
        }
        self.new_free.extend_from_slice(&self.pool.new_free);
        self.new_tasks.extend_from_slice(&self.pool.new_tasks);
        self.record.finished_at.push((self.t, done as u32));
        self.record.messages += self.model.errors.len() as u64;
        self.record.last_messages = std::mem::take(&mut self.model.errors);
        self.note_shown();
        Ok(())
    }

    /// The current tick.
    #[must_use]
    pub fn t(&self) -> u32 {
        self.t
    }

    /// Tasks finished so far: the competition's score.
    #[must_use]
    pub fn finished(&self) -> u64 {
        self.pool.finished
    }

    /// The planner that plays (`auto` resolved), and the scheduler and executor.
    #[must_use]
    pub fn names(&self) -> (&str, &str, &str) {
        (self.entries.planner.name(), self.entries.scheduler.name(), self.entries.executor.name())
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

    /// Each robot's state now.
    #[must_use]
    pub fn states(&self) -> &[Pose] {
        &self.states
    }

    /// The floor: the map as the model sees it, `agentSize`, `agentCounter`.
    #[must_use]
    pub fn floor(&self) -> &Floor {
        &self.floor
    }

    /// The task pool and the schedule in force.
    #[must_use]
    pub fn pool(&self) -> &TaskPool {
        &self.pool
    }

    /// What the run recorded.
    #[must_use]
    pub fn record(&self) -> &Record26 {
        &self.record
    }
}
