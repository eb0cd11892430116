//! The 2024 task rules (the Start-Kit's `TaskManager.cpp`, tag `v2.1.2`). A pool of
//! `int(numTasksReveal · N)` tasks is revealed in file order (task id i holds line i mod M)
//! and refilled after every step. After each step, in this order:
//! 1. the scheduler's proposal is recorded where it changed (`plannerSchedule`) and checked
//!    robot by robot in id order; the first fault refuses it whole and the last valid
//!    schedule stays: a task not in the pool ("task already finished"), one task for two
//!    robots, or a robot taken off a task it has opened (its first errand reached);
//! 2. each robot on the next errand of its task advances it by one; the last errand finishes
//!    the task and frees the robot;
//! 3. the pool is refilled.

/// One revealed task.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Task {
    /// Its line in the task file.
    pub line: u32,
    /// The step it was revealed.
    pub revealed: u32,
    /// How many of its errands are done.
    pub done: u32,
    /// The robot it is assigned to, or -1.
    pub agent: i64,
    /// Its position in the pool's list of open ids, or `u32::MAX` once finished.
    slot: u32,
}

/// A refused schedule, as the result file records it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScheduleError {
    /// What was wrong, in the Start-Kit's words.
    pub kind: &'static str,
    /// The task named.
    pub task: i64,
    /// The robot it was given to.
    pub agent: i64,
    /// The other robot involved, or -1.
    pub other: i64,
    /// The step after the one the schedule took effect (the Start-Kit's count).
    pub timestep: u32,
}

/// The task pool and the schedule in force.
pub struct TaskPool {
    size: usize,
    /// Every task revealed, by id.
    pub tasks: Vec<Task>,
    open: Vec<u32>,
    /// The task each robot holds, or -1.
    pub current: Vec<i64>,
    /// Per robot, (step, task) each time its proposal changed.
    pub planner_schedule: Vec<Vec<(u32, i64)>>,
    /// Per robot, (step, task) each time its task in force changed.
    pub actual_schedule: Vec<Vec<(u32, i64)>>,
    /// Refused schedules.
    pub errors: Vec<ScheduleError>,
    /// (step, robot, task, errands done) each time a robot reached an errand.
    pub events: Vec<(u32, u32, u32, u32)>,
    /// Tasks finished so far.
    pub finished: u64,
    /// Robots freed by the last update, and tasks revealed by it.
    pub new_free: Vec<u32>,
    /// Tasks revealed by the last update.
    pub new_tasks: Vec<u32>,
    lines: usize,
}

impl TaskPool {
    /// The pool at step 0.
    #[must_use]
    pub fn new(n: usize, size: usize, lines: usize) -> TaskPool {
        let mut pool = TaskPool {
            size,
            tasks: Vec::new(),
            open: Vec::new(),
            current: vec![-1; n],
            planner_schedule: vec![Vec::new(); n],
            actual_schedule: vec![Vec::new(); n],
            errors: Vec::new(),
            events: Vec::new(),
            finished: 0,
            new_free: (0..n as u32).collect(),
            new_tasks: Vec::new(),
            lines,
        };
        pool.reveal(0);
        pool
    }

    /// The ids of the tasks in the pool (revealed, not finished), in no set order.
    #[must_use]
    pub fn open(&self) -> &[u32] {
        &self.open
    }

    /// Whether `id` is in the pool.
    #[must_use]
    pub fn is_open(&self, id: i64) -> bool {
        id >= 0 && (id as usize) < self.tasks.len() && self.tasks[id as usize].slot != u32::MAX
    }

    /// The errand task `id` waits for next.
    #[must_use]
    pub fn next_errand(&self, id: u32, lines: &[Vec<u32>]) -> u32 {
        let task = &self.tasks[id as usize];
        lines[task.line as usize][task.done as usize]
    }

    /// After the step that led to `t`: schedule, errands, refill. How many tasks finished.
    pub fn update(&mut self, t: u32, proposal: &[i64], loc: &[u32], lines: &[Vec<u32>]) -> u64 {
        self.set_schedule(t, proposal);
        self.advance(t, loc, lines)
    }

    /// After the step that led to `t`, the schedule in force left as it is: each robot on the
    /// next errand of its task advances it (an event each), a task whose last errand is reached
    /// finishes and frees its robot, and the pool is refilled. How many tasks finished.
    pub fn advance(&mut self, t: u32, loc: &[u32], lines: &[Vec<u32>]) -> u64 {
        let before = self.finished;
        self.new_free.clear();
        for (k, &p) in loc.iter().enumerate() {
            let id = self.current[k];
            if id < 0 {
                continue;
            }
            let task = &mut self.tasks[id as usize];
            let errands = &lines[task.line as usize];
            if errands[task.done as usize] != p {
                continue;
            }
            task.done += 1;
            if task.done as usize == errands.len() {
                self.current[k] = -1;
                self.close(id as u32);
                self.finished += 1;
                self.new_free.push(k as u32);
            }
            self.events.push((t, k as u32, id as u32, self.tasks[id as usize].done));
        }
        self.reveal(t);
        self.finished - before
    }

    fn set_schedule(&mut self, t: u32, proposal: &[i64]) {
        for (k, &id) in proposal.iter().enumerate() {
            if self.planner_schedule[k].last().map_or(true, |&(_, last)| last != id) {
                self.planner_schedule[k].push((t, id));
            }
        }
        if let Some(e) = self.refusal(t, proposal) {
            self.errors.push(e);
            return;
        }
        for &id in &self.current {
            if id >= 0 {
                self.tasks[id as usize].agent = -1;
            }
        }
        for (k, &id) in proposal.iter().enumerate() {
            self.current[k] = id;
            if id >= 0 {
                self.tasks[id as usize].agent = k as i64;
            }
        }
        for (k, &id) in self.current.iter().enumerate() {
            if self.actual_schedule[k].last().map_or(true, |&(_, last)| last != id) {
                self.actual_schedule[k].push((t, id));
            }
        }
    }

    /// The first fault of a proposal, robots in id order, as `validate_task_assignment`.
    fn refusal(&self, t: u32, proposal: &[i64]) -> Option<ScheduleError> {
        let err = |kind, task, agent: usize, other| Some(ScheduleError { kind, task, agent: agent as i64, other, timestep: t + 1 });
        let mut holder: std::collections::HashMap<i64, usize> = std::collections::HashMap::new();
        for (k, &id) in proposal.iter().enumerate() {
            if id != -1 && !self.is_open(id) {
                return err("task already finished", id, k, -1);
            }
            if id != -1 {
                if let Some(&j) = holder.get(&id) {
                    return err("task is already assigned by the second agent at the same time", id, k, j as i64);
                }
            }
            let cur = self.current[k];
            if cur != -1 && self.tasks[cur as usize].done > 0 && id != cur {
                return err("task is already opened by the second agent", id, k, self.tasks[cur as usize].agent);
            }
            if id != -1 {
                holder.insert(id, k);
            }
        }
        None
    }

    fn close(&mut self, id: u32) {
        let slot = self.tasks[id as usize].slot as usize;
        self.open.swap_remove(slot);
        if let Some(&moved) = self.open.get(slot) {
            self.tasks[moved as usize].slot = slot as u32;
        }
        self.tasks[id as usize].slot = u32::MAX;
    }

    fn reveal(&mut self, t: u32) {
        self.new_tasks.clear();
        while self.open.len() < self.size {
            let id = self.tasks.len() as u32;
            self.tasks.push(Task { line: (id as usize % self.lines) as u32, revealed: t, done: 0, agent: -1, slot: self.open.len() as u32 });
            self.open.push(id);
            self.new_tasks.push(id);
        }
    }
}
