//! The 2026 schedule rules (the Start-Kit's `TaskManager::set_task_assignment`, tag `v3.1.0`),
//! on the 2024 task pool (`pool.rs`, whose reveal, errands and events are the same). Where the
//! 2024 rules refuse a faulty schedule whole, the 2026 ones correct it robot by robot, in id
//! order, and record each correction:
//! 1. a task not in the pool (finished, or never revealed) is dropped ("task already
//!    finished");
//! 2. a task already given to a robot of lower id in the same schedule is dropped ("task is
//!    already assigned by the second agent at the same time");
//! 3. a robot that has opened its task (reached its first errand) keeps it ("schedule agent to
//!    another task who is already opened a task");
//! 4. a task opened by another robot is dropped ("task is already opened by other agent").
//!
//! A schedule of the wrong length is refused whole ("Invalid schedule size"). Each correction
//! is stamped with the tick after the communication point, as the Start-Kit stamps it.

use crate::rules::grid::pool::{ScheduleError, TaskPool};

/// Sets the schedule `s` at the communication point of tick `t`, correcting `s` in place.
#[allow(clippy::needless_range_loop)] // robot i across several arrays
pub fn assign(pool: &mut TaskPool, t: u32, s: &mut [i64]) {
    let n = pool.current.len();
    let err =
        |pool: &mut TaskPool, kind, task, agent: usize, other| pool.errors.push(ScheduleError { kind, task, agent: agent as i64, other, timestep: t + 1 });
    if s.len() != n {
        pool.errors.push(ScheduleError { kind: "Invalid schedule size", task: -1, agent: -1, other: -1, timestep: t + 1 });
        return;
    }
    for (a, &id) in s.iter().enumerate() {
        if pool.planner_schedule[a].last().map_or(true, |&(_, last)| last != id) {
            pool.planner_schedule[a].push((t, id));
        }
    }
    // Who holds each task in this schedule so far (by task id).
    let mut holder: std::collections::HashMap<i64, usize> = std::collections::HashMap::with_capacity(n);
    for i in 0..n {
        if s[i] != -1 && !pool.is_open(s[i]) {
            err(pool, "task already finished", s[i], i, -1);
            s[i] = -1;
        }
        if s[i] != -1 {
            if let Some(&j) = holder.get(&s[i]) {
                err(pool, "task is already assigned by the second agent at the same time", s[i], i, j as i64);
                s[i] = -1;
            }
        }
        let cur = pool.current[i];
        if cur != -1 && pool.tasks[cur as usize].done > 0 && s[i] != cur {
            err(pool, "schedule agent to another task who is already opened a task", s[i], i, -1);
            s[i] = cur;
        }
        if s[i] != -1 {
            let task = &pool.tasks[s[i] as usize];
            if task.done > 0 && task.agent != i as i64 {
                let other = task.agent;
                err(pool, "task is already opened by other agent", s[i], i, other);
                s[i] = -1;
            }
        }
        if s[i] != -1 {
            holder.insert(s[i], i);
        }
    }
    for k in 0..n {
        let id = pool.current[k];
        if id >= 0 {
            pool.tasks[id as usize].agent = -1;
        }
    }
    for (k, &id) in s.iter().enumerate() {
        pool.current[k] = id;
        if id >= 0 {
            pool.tasks[id as usize].agent = k as i64;
        }
    }
    for (k, &id) in pool.current.iter().enumerate() {
        if pool.actual_schedule[k].last().map_or(true, |&(_, last)| last != id) {
            pool.actual_schedule[k].push((t, id));
        }
    }
}
