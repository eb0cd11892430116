//! Start-Kit Python entries behind the engine's traits. Conversions only: the engine hands
//! each call's state over as lists of numbers to `multibots.lorr_python.Entries` (which fills
//! the user's `SharedEnvironment` and calls the user's class), and reads the answer back; the
//! rules check it as they check any entry's. The engine runs without the GIL; each call takes
//! it.

use multibots_core::input::lorr::{Problem, Version};
use multibots_core::rules::grid::action::Action;
use multibots_core::rules::grid::planner::{PlanView, Planner, NO_GOAL};
use multibots_core::rules::grid::pool::TaskPool;
use multibots_core::rules::grid::schedule::{ScheduleView, Scheduler};
use multibots_core::rules::grid::y2026::entries::{ExecEnv, Executor, PlanEnv, Planner26, Scheduler26};
use multibots_core::rules::grid::y2026::footprint::Pose;
use multibots_core::rules::grid::y2026::{comm_ms, Entries, Lorr26, TICK_MS};
use multibots_core::rules::grid::{planner, schedule, LorrOptions};
use multibots_core::Error;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::sync::Arc;

/// The entries of a run with Python ones: its options (the Python entries' labels in place of
/// names) and its parts, under the 2026 rules or under the 2023/2024 rules.
pub(crate) enum Made {
    Ticks(LorrOptions, Entries),
    Steps(LorrOptions, Box<dyn Planner>, Box<dyn Scheduler>),
}

/// The error of a bridge call made with the GIL held (`begin`): the user's exception as its
/// cause.
fn entry_error(py: Python<'_>, e: PyErr) -> PyErr {
    if e.get_type(py).name().is_ok_and(|n| n == "EntryError") {
        let msg = e.value(py).str().map(|s| s.to_string()).unwrap_or_default();
        let err = crate::errors::AllocatorError::new_err(msg);
        err.set_cause(py, Some(e));
        return err;
    }
    e
}

/// The built-ins `options` names, with the roles `bridge` plays (`bridge.roles`) in their
/// place; `bridge.begin` (each Python entry's `initialize`) called.
pub(crate) fn made(py: Python<'_>, problem: &Arc<Problem>, mut options: LorrOptions, bridge: PyObject) -> PyResult<Made> {
    let bridge = Arc::new(bridge);
    let roles: Vec<String> = bridge.getattr(py, "roles")?.extract(py)?;
    let has = |r: &str| roles.iter().any(|x| x == r);
    let map = &problem.map;
    let obstacles: Vec<u8> = map.free.iter().map(|&f| u8::from(!f)).collect();
    let n = problem.team_size();
    let scenario = |flag: &str, why: &str| crate::errors::ScenarioError::new_err(format!("{flag}: {why}"));
    match problem.version {
        Version::Y2026 => {
            Lorr26::resolve(problem, &mut options);
            let counter = problem.y2026.as_ref().map_or(1, |r| r.agent_counter);
            bridge
                .call_method1(py, "begin", ("2026", map.rows, map.cols, obstacles, n, counter, comm_ms(&options), TICK_MS))
                .map_err(|e| entry_error(py, e))?;
            let (p, o) = (Arc::clone(problem), options.clone());
            let mut entries = crate::errors::engine(py, move || Entries::built_in(&p, &o))?;
            if has("scheduler") {
                let e = PyEntry::new(py, "scheduler", &bridge)?;
                options.scheduler.clone_from(&e.label);
                entries.scheduler = Box::new(e);
            }
            if has("planner") {
                let e = PyEntry::new(py, "planner", &bridge)?;
                options.planner.clone_from(&e.label);
                entries.planner = Box::new(e);
            }
            if has("executor") {
                entries.executor = Box::new(PyEntry::new(py, "executor", &bridge)?);
            }
            Ok(Made::Ticks(options, entries))
        }
        Version::Y2023 | Version::Y2024 => {
            let year = if problem.version == Version::Y2023 { "2023" } else { "2024" };
            if has("executor") {
                return Err(scenario("--executor-py", &format!("the {year} rules have no executor (executors came with the 2026 rules)")));
            }
            if has("scheduler") && problem.version == Version::Y2023 {
                return Err(scenario("--scheduler-py", "the 2023 rules have no scheduler (errands go round robin)"));
            }
            bridge.call_method1(py, "begin", (year, map.rows, map.cols, obstacles, n, 1u32, 1000u32, 1000u32)).map_err(|e| entry_error(py, e))?;
            let planner: Box<dyn Planner> = if has("planner") {
                let e = PyEntry::new(py, "planner", &bridge)?;
                options.planner.clone_from(&e.label);
                Box::new(e)
            } else {
                if options.planner == "auto" {
                    options.planner = planner::auto_choice(map, n).into();
                }
                planner::built_in(&options.planner, map, n, options.seed).map_err(crate::to_py)?
            };
            let scheduler: Box<dyn Scheduler> = if has("scheduler") {
                let e = PyEntry::new(py, "scheduler", &bridge)?;
                options.scheduler.clone_from(&e.label);
                Box::new(e)
            } else {
                options.scheduler = schedule::resolve(&options.scheduler, false).to_string();
                schedule::built_in(&options.scheduler).map_err(crate::to_py)?
            };
            Ok(Made::Steps(options, planner, scheduler))
        }
    }
}

/// A robot's state as Python gets it: cell, heading, ticks done of the action under way,
/// held by a delay.
type State = (u32, u8, u32, bool);
/// A task as Python gets it: id, tick revealed, robot assigned or -1, errand cells, errands
/// done.
type TaskRow = (u32, u32, i64, Vec<u32>, u32);

/// What a planner call hands Python: the tick, the predicted and the true states, the open
/// tasks, the schedule, the goals (cell, tick revealed), the new tasks and freed robots, the
/// staged actions. Copied as flat vectors (a few memory copies at 10,000 robots); each field
/// becomes Python objects only when the entry reads it (`multibots.mapf.SharedEnvironment`
/// builds it on first access), so that a call costs what the entry reads.
#[pyclass(module = "multibots._core", name = "PlanSnapshot", frozen)]
pub(crate) struct PlanSnapshot {
    #[pyo3(get)]
    tick: u32,
    predicted: Vec<State>,
    system: Vec<State>,
    /// Open tasks: id, tick revealed, robot or -1, errands done, and the span of their
    /// errand cells in `cells`.
    tasks: Vec<(u32, u32, i64, u32, u32, u32)>,
    cells: Vec<u32>,
    schedule: Vec<i64>,
    goals: Vec<Option<(u32, u32)>>,
    new_tasks: Vec<u32>,
    new_free: Vec<u32>,
    staged: Staged,
}

/// Every robot's staged actions, as codes, in one vector (one allocation a call, not one a
/// robot): robot `k`'s are `codes[ends[k - 1]..ends[k]]`.
struct Staged {
    codes: Vec<u8>,
    ends: Vec<u32>,
}

impl Staged {
    fn of<Q: AsRef<[Action]>>(queues: &[Q]) -> Staged {
        let mut codes = Vec::new();
        let ends = queues
            .iter()
            .map(|q| {
                codes.extend(q.as_ref().iter().map(|&a| a as u8));
                codes.len() as u32
            })
            .collect();
        Staged { codes, ends }
    }

    fn rows(&self) -> Vec<&[u8]> {
        let mut from = 0;
        self.ends
            .iter()
            .map(|&end| {
                let row = &self.codes[from..end as usize];
                from = end as usize;
                row
            })
            .collect()
    }
}

#[pymethods]
impl PlanSnapshot {
    /// `curr_states` (cell, heading, count, held).
    fn predicted(&self) -> Vec<State> {
        self.predicted.clone()
    }

    /// `system_states` (cell, heading, count, held).
    fn system(&self) -> Vec<State> {
        self.system.clone()
    }

    /// The open tasks: (id, tick revealed, robot or -1, errand cells, errands done).
    fn tasks(&self) -> Vec<TaskRow> {
        self.tasks
            .iter()
            .map(|&(id, revealed, agent, done, from, len)| (id, revealed, agent, self.cells[from as usize..(from + len) as usize].to_vec(), done))
            .collect()
    }

    /// `curr_task_schedule`.
    fn schedule(&self) -> Vec<i64> {
        self.schedule.clone()
    }

    /// Each robot's goal (cell, tick revealed), or None.
    fn goals(&self) -> Vec<Option<(u32, u32)>> {
        self.goals.clone()
    }

    fn new_tasks(&self) -> Vec<u32> {
        self.new_tasks.clone()
    }

    fn new_free(&self) -> Vec<u32> {
        self.new_free.clone()
    }

    /// Each robot's staged actions, as codes.
    fn staged(&self) -> Vec<Vec<u8>> {
        self.staged.rows().into_iter().map(<[u8]>::to_vec).collect()
    }
}

impl PlanSnapshot {
    #[allow(clippy::too_many_arguments)]
    fn new(
        tick: u32,
        predicted: Vec<State>,
        system: Vec<State>,
        open: Option<(&TaskPool, &[Vec<u32>])>,
        schedule: Vec<i64>,
        goals: Vec<Option<(u32, u32)>>,
        news: (Vec<u32>, Vec<u32>),
        staged: Staged,
    ) -> PlanSnapshot {
        let mut cells = Vec::new();
        let mut tasks = Vec::new();
        if let Some((pool, lines)) = open {
            for &id in pool.open() {
                let t = &pool.tasks[id as usize];
                let line = &lines[t.line as usize];
                tasks.push((id, t.revealed, t.agent, t.done, cells.len() as u32, line.len() as u32));
                cells.extend_from_slice(line);
            }
        }
        let (new_tasks, new_free) = news;
        PlanSnapshot { tick, predicted, system, tasks, cells, schedule, goals, new_tasks, new_free, staged }
    }
}

/// What an executor call hands Python: the tick, the true states and the staged actions, each
/// made Python objects on first access (as `PlanSnapshot`'s).
#[pyclass(module = "multibots._core", name = "ExecSnapshot", frozen)]
pub(crate) struct ExecSnapshot {
    #[pyo3(get)]
    tick: u32,
    system: Vec<State>,
    staged: Staged,
}

#[pymethods]
impl ExecSnapshot {
    /// `system_states` (cell, heading, count, held).
    fn system(&self) -> Vec<State> {
        self.system.clone()
    }

    /// Each robot's staged actions, as codes.
    fn staged(&self) -> Vec<Vec<u8>> {
        self.staged.rows().into_iter().map(<[u8]>::to_vec).collect()
    }
}

impl ExecSnapshot {
    fn new(env: &ExecEnv<'_>, staged: &[Vec<Action>]) -> ExecSnapshot {
        ExecSnapshot { tick: env.tick, system: states(env.system, env.held), staged: Staged::of(staged) }
    }
}

/// One role played by the Python object `bridge` (a `multibots.lorr_python.Entries`).
pub(crate) struct PyEntry {
    label: String,
    bridge: Arc<Py<PyAny>>,
    /// (Planner) the scheduler is Python too: the environment it filled stands.
    synced: bool,
    /// (2024 rules) why the last call failed.
    failure: Option<Error>,
    /// (2024 rules) the tasks the last call saw open, to tell which are new.
    seen: Vec<bool>,
    /// (2024 rules) robots that held a task at the last call.
    busy: Vec<bool>,
}

impl PyEntry {
    pub(crate) fn new(py: Python<'_>, role: &'static str, bridge: &Arc<Py<PyAny>>) -> PyResult<PyEntry> {
        let label: String = bridge.call_method1(py, "label", (role,))?.extract(py)?;
        let roles: Vec<String> = bridge.getattr(py, "roles")?.extract(py)?;
        Ok(PyEntry {
            label,
            bridge: Arc::clone(bridge),
            synced: role == "planner" && roles.iter().any(|r| r == "scheduler"),
            failure: None,
            seen: Vec::new(),
            busy: Vec::new(),
        })
    }

    fn fail(&self, reason: String) -> Error {
        Error::Entry { entry: self.label.clone(), reason }
    }

    /// Calls `method` with `args`, the answer extracted as `T`; an exception becomes the
    /// entry's error (its text: the user's exception, file and line), kept as the cause.
    fn call<T, F>(&self, method: &str, args: F) -> Result<T, Error>
    where
        T: for<'py> FromPyObject<'py>,
        F: for<'py> FnOnce(Python<'py>) -> PyResult<Bound<'py, PyTuple>>,
    {
        Python::with_gil(|py| {
            let answer = args(py).and_then(|a| self.bridge.bind(py).call_method1(method, a)).and_then(|a| a.extract::<T>());
            answer.map_err(|e| {
                let reason = if e.get_type(py).name().is_ok_and(|n| n == "EntryError") {
                    e.value(py).str().map(|s| s.to_string()).unwrap_or_default()
                } else {
                    let ty = e.get_type(py).name().map_or_else(|_| "Exception".into(), |n| n.to_string());
                    let msg = e.value(py).str().map(|s| s.to_string()).unwrap_or_default();
                    format!("{method} failed: {ty}: {}", msg.split_whitespace().collect::<Vec<_>>().join(" "))
                };
                crate::strategy::keep_cause(e);
                self.fail(reason)
            })
        })
    }
}

fn states(poses: &[Pose], held: &[bool]) -> Vec<State> {
    poses.iter().enumerate().map(|(i, p)| (p.loc, p.heading, p.count, held.get(i).copied().unwrap_or(false))).collect()
}

fn goals(pool: &TaskPool, schedule: &[i64], goals: &[u32]) -> Vec<Option<(u32, u32)>> {
    goals
        .iter()
        .enumerate()
        .map(|(k, &g)| {
            let id = schedule.get(k).copied().unwrap_or(-1);
            (g != NO_GOAL && pool.is_open(id)).then(|| (g, pool.tasks[id as usize].revealed))
        })
        .collect()
}

fn codes(q: &[Action]) -> Vec<u8> {
    q.iter().map(|&a| a as u8).collect()
}

impl PyEntry {
    fn action(&self, code: i64, robot: usize) -> Result<Action, Error> {
        Ok(match code {
            0 => Action::F,
            1 => Action::R,
            2 => Action::C,
            3 => Action::W,
            4 => Action::T,
            _ => return Err(self.fail(format!("robot {robot}: action {code} is not one of FW=0, CR=1, CCR=2, W=3, NA=4"))),
        })
    }

    fn actions(&self, rows: Vec<Vec<i64>>, n: usize) -> Result<Vec<Vec<Action>>, Error> {
        if rows.len() != n {
            return Err(self.fail(format!("answered {} rows of actions for {n} robots", rows.len())));
        }
        rows.into_iter().enumerate().map(|(i, row)| row.into_iter().map(|a| self.action(a, i)).collect()).collect()
    }

    /// The 2026 state the planner side sees.
    fn plan_state(env: &PlanEnv<'_>) -> PlanSnapshot {
        PlanSnapshot::new(
            env.tick,
            states(env.predicted, &[]),
            states(env.system, env.held),
            Some((env.pool, env.lines)),
            env.schedule.to_vec(),
            goals(env.pool, env.schedule, env.goals),
            (env.new_tasks.to_vec(), env.new_free.to_vec()),
            Staged::of(env.staged),
        )
    }
}

impl Scheduler26 for PyEntry {
    fn name(&self) -> &str {
        &self.label
    }

    fn schedule(&mut self, env: &PlanEnv<'_>, proposal: &mut Vec<i64>) -> Result<(), Error> {
        let snapshot = PyEntry::plan_state(env);
        let answer: Vec<i64> = self.call("schedule", |py| (env.time_limit_ms, snapshot).into_pyobject(py))?;
        if answer.len() != proposal.len() {
            return Err(self.fail(format!("answered {} task ids for {} robots", answer.len(), proposal.len())));
        }
        *proposal = answer;
        Ok(())
    }
}

impl Planner26 for PyEntry {
    fn name(&self) -> &str {
        &self.label
    }

    fn plan(&mut self, env: &PlanEnv<'_>, plan: &mut [Vec<Action>]) -> Result<(), Error> {
        let snapshot = PyEntry::plan_state(env);
        let rows: Vec<Vec<i64>> = self.call("plan", |py| (env.time_limit_ms, self.synced, snapshot).into_pyobject(py))?;
        for (slot, row) in plan.iter_mut().zip(self.actions(rows, env.system.len())?) {
            *slot = row;
        }
        Ok(())
    }
}

impl Executor for PyEntry {
    fn name(&self) -> &str {
        &self.label
    }

    fn process_new_plan(&mut self, env: &ExecEnv<'_>, plan: &[Vec<Action>], staged: &mut [Vec<Action>], predicted: &mut Vec<Pose>) -> Result<(), Error> {
        let n = env.system.len();
        let args = (TICK_MS, ExecSnapshot::new(env, staged), plan.iter().map(|q| codes(q)).collect::<Vec<_>>());
        let (queues, states_): (Vec<Vec<i64>>, Vec<(i64, i64)>) = self.call("process_new_plan", |py| args.into_pyobject(py))?;
        for (slot, q) in staged.iter_mut().zip(self.actions(queues, n)?) {
            *slot = q;
        }
        if states_.len() != n {
            return Err(self.fail(format!("process_new_plan answered {} states for {n} robots", states_.len())));
        }
        let cells = i64::from(env.floor.rows) * i64::from(env.floor.cols);
        predicted.clear();
        for (i, (loc, ori)) in states_.into_iter().enumerate() {
            // The Start-Kit hands any prediction on to the planner; one off the map (an
            // executor's arithmetic gone wrong) stands here for where the robot is now.
            if (0..cells).contains(&loc) && (0..4).contains(&ori) {
                predicted.push(Pose { loc: loc as u32, heading: ori as u8, count: 0, doing: Action::T });
            } else {
                predicted.push(Pose { count: 0, doing: Action::T, ..env.system[i] });
            }
        }
        Ok(())
    }

    fn next_command(&mut self, env: &ExecEnv<'_>, staged: &[Vec<Action>], go: &mut [bool]) -> Result<(), Error> {
        let args = (TICK_MS, ExecSnapshot::new(env, staged));
        let answer: Vec<i64> = self.call("next_command", |py| args.into_pyobject(py))?;
        if answer.len() != go.len() {
            return Err(self.fail(format!("next_command answered {} commands for {} robots", answer.len(), go.len())));
        }
        for (g, c) in go.iter_mut().zip(answer) {
            *g = c == 0;
        }
        Ok(())
    }
}

/// Under the 2024 rules the scheduler sees the robots where they are (the states' counters
/// 0), the tasks revealed since its last call and the robots freed since then (all free robots
/// at the first call).
impl PyEntry {
    fn news24(&mut self, pool: &TaskPool) -> (Vec<u32>, Vec<u32>) {
        if self.seen.len() < pool.tasks.len() {
            self.seen.resize(pool.tasks.len(), false);
        }
        let new_tasks: Vec<u32> = pool.open().iter().copied().filter(|&id| !std::mem::replace(&mut self.seen[id as usize], true)).collect();
        let first = self.busy.is_empty();
        self.busy.resize(pool.current.len(), true);
        let mut new_free = Vec::new();
        for (k, b) in self.busy.iter_mut().enumerate() {
            let now = pool.current[k] >= 0;
            if !now && (*b || first) {
                new_free.push(k as u32);
            }
            *b = now;
        }
        (new_tasks, new_free)
    }
}

impl Scheduler for PyEntry {
    fn name(&self) -> &'static str {
        "python"
    }

    fn schedule(&mut self, view: &ScheduleView<'_>, proposal: &mut [i64]) {
        let st: Vec<State> = view.loc.iter().zip(view.heading).map(|(&l, &h)| (l, h, 0, false)).collect();
        let (new_tasks, new_free) = self.news24(view.pool);
        let goals: Vec<Option<(u32, u32)>> = view
            .pool
            .current
            .iter()
            .map(|&id| view.pool.is_open(id).then(|| (view.pool.next_errand(id as u32, view.lines), view.pool.tasks[id as usize].revealed)))
            .collect();
        let staged = Staged::of(&vec![[]; view.loc.len()]);
        let snapshot =
            PlanSnapshot::new(view.t, st.clone(), st, Some((view.pool, view.lines)), view.pool.current.clone(), goals, (new_tasks, new_free), staged);
        let answer: Result<Vec<i64>, Error> = self.call("schedule", |py| (1000u32, snapshot).into_pyobject(py));
        match answer {
            Ok(a) if a.len() == proposal.len() => proposal.copy_from_slice(&a),
            Ok(a) => self.failure = Some(self.fail(format!("answered {} task ids for {} robots", a.len(), proposal.len()))),
            Err(e) => self.failure = Some(e),
        }
    }

    fn failure(&mut self) -> Option<Error> {
        self.failure.take()
    }
}

impl Planner for PyEntry {
    fn name(&self) -> &'static str {
        "python"
    }

    fn plan(&mut self, view: &PlanView<'_>, actions: &mut [Action]) {
        let n = view.loc.len();
        let st: Vec<State> = view.loc.iter().zip(view.heading).map(|(&l, &h)| (l, h, 0, false)).collect();
        let (open, schedule, goal_rows) = match &view.tasks {
            Some(tv) => (Some((tv.pool, tv.lines)), tv.proposal.to_vec(), goals(tv.pool, tv.proposal, view.goals)),
            None => (None, vec![-1; n], view.goals.iter().map(|&g| (g != NO_GOAL).then_some((g, 0))).collect()),
        };
        let staged = Staged::of(&vec![[]; n]);
        let snapshot = PlanSnapshot::new(view.t, st.clone(), st, open, schedule, goal_rows, (Vec::new(), Vec::new()), staged);
        let answer: Result<Vec<Vec<i64>>, Error> = self.call("plan", |py| (1000u32, self.synced, snapshot).into_pyobject(py));
        let rows = match answer.and_then(|rows| self.actions(rows, n)) {
            Ok(rows) => rows,
            Err(e) => {
                self.failure = Some(e);
                return;
            }
        };
        for (a, row) in actions.iter_mut().zip(rows) {
            *a = row.first().copied().unwrap_or(Action::W);
        }
    }

    fn failure(&mut self) -> Option<Error> {
        self.failure.take()
    }
}
