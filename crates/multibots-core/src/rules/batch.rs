//! Many runs at once, on a pool of threads: the engine of `simulate_many`, `compare` and
//! sweeps.
//!
//! Workers take the next scenario from a shared counter, so long and short runs balance
//! themselves. Runs on the same layout share one [`World`] (its routing table is built once,
//! by whichever worker needs it first). The calling thread sleeps on a condition variable
//! and wakes when a run finishes (or after `poll`, so that it can look for Ctrl-C); a batch
//! of tiny runs costs what its runs cost, with no polling floor. Setting `cancel` stops every
//! worker at its next step.

use crate::error::Result;
use crate::input::csv::Tables;
use crate::input::scenario::{Scenario, Traffic};
use crate::record::metrics::RunResult;
use crate::rules::Simulation;
use crate::world::layout::Layout;
use crate::world::{resolve_layout, World};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, OnceLock};
use std::time::Duration;

/// The worker threads to use: `workers`, or one per core when 0, never more than runs.
#[must_use]
pub fn worker_count(workers: usize, runs: usize) -> usize {
    let w = if workers == 0 { std::thread::available_parallelism().map_or(1, usize::from) } else { workers };
    w.min(runs.max(1))
}

/// What a layout is built from: scenarios with equal keys share it (and a world for each
/// routing: `reserve` routes round the unloading zones, `World::of`).
fn layout_key(s: &Scenario) -> String {
    match &s.layout_generate {
        Some(p) => format!("generate:{}", serde_json::to_string(p).expect("parameters serialise")),
        None => format!("layout:{}", s.layout),
    }
}

struct Progress<T> {
    finished: usize,
    slots: Vec<Option<Result<T>>>,
}

/// Robot-steps between two looks at the cancel flag: about 50 ms at 20 M robot-steps a
/// second, whatever the fleet's size (a big fleet looks after every step).
const CANCEL_EVERY: u64 = 1 << 20;

/// Runs every scenario with its built-in allocator on `workers` threads (0: one per core).
///
/// `watch` runs on the calling thread at least every `poll`, and when the last run finishes;
/// it gets the number of finished runs and returns `false` to cancel the batch. Returns the
/// results in the order given, or `None` when cancelled.
pub fn run_many(scenarios: &[Scenario], workers: usize, poll: Duration, watch: impl FnMut(usize) -> bool) -> Option<Vec<Result<RunResult>>> {
    each(scenarios, workers, poll, watch, |s, world, tables, cancel| {
        let mut sim = Simulation::build(world, tables, s, crate::alloc::built_in(s)?)?;
        let chunk = (CANCEL_EVERY / u64::from(s.robots.max(1))).max(1);
        while !sim.done() && !cancel.load(Ordering::Relaxed) {
            sim.steps(chunk)?;
        }
        Ok(sim.result())
    })
}

/// Checks every scenario as [`Simulation::new`] would (its built-in allocator, its values, its
/// layout, its task list), on `workers` threads, building each layout once: how a sweep
/// checks thousands of planned runs before it starts any. Returns each scenario's verdict,
/// in the order given: where a scenario has several faults, the one `new` names first.
#[must_use]
pub fn check_many(scenarios: &[Scenario], workers: usize) -> Vec<Result<()>> {
    check_many_until(scenarios, workers, Duration::from_secs(3600), |_| true).expect("never cancelled")
}

/// [`check_many`] that can be cancelled as [`run_many`] can: `watch` is called with the number
/// of scenarios checked at least every `poll`; returning false cancels the rest (`None`).
pub fn check_many_until(scenarios: &[Scenario], workers: usize, poll: Duration, watch: impl FnMut(usize) -> bool) -> Option<Vec<Result<()>>> {
    let mut verdicts = each(scenarios, workers, poll, watch, |s, world, tables, _| Simulation::build(world, tables, s, crate::alloc::built_in(s)?).map(drop))?;
    // The pool checks values and the layout before the job names the allocator; `new` names
    // the allocator first.
    for (v, s) in verdicts.iter_mut().zip(scenarios) {
        if v.is_err() {
            if let Err(e) = crate::alloc::built_in(s) {
                *v = Err(e);
            }
        }
    }
    Some(verdicts)
}

/// The pool both share: `job` gets a scenario whose values are checked, its shared world, the
/// CSV tables the batch has read (each file once) and the cancel flag.
fn each<T: Send>(
    scenarios: &[Scenario],
    workers: usize,
    poll: Duration,
    mut watch: impl FnMut(usize) -> bool,
    job: impl Fn(&Scenario, Arc<World>, &Tables, &AtomicBool) -> Result<T> + Sync,
) -> Option<Vec<Result<T>>> {
    let n = scenarios.len();
    let keys: Vec<String> = scenarios.iter().map(layout_key).collect();
    let mut distinct: Vec<&String> = keys.iter().collect();
    distinct.sort();
    distinct.dedup();
    let layouts: Vec<OnceLock<Result<Layout>>> = distinct.iter().map(|_| OnceLock::new()).collect();
    // Per layout, its world with the paper's routes and with reserve's.
    let worlds: Vec<[OnceLock<Result<Arc<World>>>; 2]> = distinct.iter().map(|_| [OnceLock::new(), OnceLock::new()]).collect();
    let world_of = |k: usize| -> Result<Arc<World>> {
        let slot = distinct.binary_search(&&keys[k]).expect("every key is listed");
        let layout = layouts[slot].get_or_init(|| resolve_layout(&scenarios[k])).as_ref().map_err(Clone::clone)?;
        let reserve = scenarios[k].resolved(layout.departure.len()).traffic == Traffic::Reserve;
        worlds[slot][usize::from(reserve)].get_or_init(|| World::routed(layout.clone(), reserve)).clone()
    };
    let tables = Tables::default();
    let next = AtomicUsize::new(0);
    let cancel = AtomicBool::new(false);
    let progress = Mutex::new(Progress { finished: 0, slots: (0..n).map(|_| None).collect() });
    let changed = Condvar::new();
    std::thread::scope(|scope| {
        for _ in 0..worker_count(workers, n) {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= n || cancel.load(Ordering::Relaxed) {
                    break;
                }
                let s = &scenarios[k];
                let r = s.check_values().and_then(|()| job(s, world_of(k)?, &tables, &cancel));
                let mut p = progress.lock().expect("no worker panics while holding the lock");
                p.slots[k] = Some(r);
                p.finished += 1;
                // Only the last run wakes the calling thread early: a wake per run cost a
                // tenth of the paper's 30 runs (a context switch each, and with Python's
                // watch, the interpreter's lock).
                if p.finished == n {
                    changed.notify_one();
                }
            });
        }
        let mut p = progress.lock().expect("not poisoned");
        while p.finished < n {
            p = changed.wait_timeout(p, poll).expect("not poisoned").0;
            let finished = p.finished;
            drop(p);
            if !watch(finished) {
                cancel.store(true, Ordering::Relaxed);
                return;
            }
            p = progress.lock().expect("not poisoned");
        }
    });
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    let p = progress.into_inner().expect("not poisoned");
    Some(p.slots.into_iter().map(|r| r.expect("every slot is filled")).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scenario::PAPER_TASKS;

    #[test]
    fn results_come_back_in_order_and_equal_single_runs() {
        let list: Vec<Scenario> = (1..=6).flat_map(|n| PAPER_TASKS.iter().map(move |g| Scenario::paper(n, g))).collect();
        let mut calls = 0;
        let many = run_many(&list, 2, Duration::from_millis(50), |_| {
            calls += 1;
            true
        })
        .unwrap();
        assert!(calls >= 1);
        for (s, r) in list.iter().zip(many) {
            assert_eq!(r.unwrap(), Simulation::new(s).unwrap().run().unwrap());
        }
    }

    #[test]
    fn errors_stay_with_their_run_and_cancel_stops() {
        let mut bad = Scenario::paper(3, &[1, 2]);
        bad.robot.speed = -1.0;
        let list = vec![Scenario::paper(1, &[5]), bad];
        let r = run_many(&list, 1, Duration::from_millis(10), |_| true).unwrap();
        assert!(r[0].is_ok());
        assert_eq!(r[1].as_ref().unwrap_err().to_string(), "robot.speed = -1: must be greater than 0");
        let long: Vec<Scenario> = (0..50).map(|_| Scenario::paper(1, &PAPER_TASKS[0])).collect();
        assert!(run_many(&long, 1, Duration::from_millis(1), |_| false).is_none());
    }

    #[test]
    fn check_many_gives_the_verdicts_of_single_constructions() {
        let mut bad_speed = Scenario::paper(3, &[1, 2]);
        bad_speed.robot.speed = -1.0;
        let mut bad_unload = Scenario::paper(2, &[5]);
        bad_unload.unload = crate::input::scenario::Unload::Node("nowhere".into());
        let mut bad_allocator = Scenario::paper(2, &[5]);
        bad_allocator.allocator = "fastest".into();
        // Several faults at once: each check names the same one first.
        let mut allocator_and_speed = bad_allocator.clone();
        allocator_and_speed.robot.speed = -1.0;
        let mut allocator_and_unload = bad_unload.clone();
        allocator_and_unload.allocator = "fastest".into();
        let mut speed_and_unload = bad_unload.clone();
        speed_and_unload.robot.speed = -1.0;
        let list = vec![
            Scenario::paper(1, &[5]),
            bad_speed,
            Scenario::paper(6, &PAPER_TASKS[2]),
            bad_unload,
            bad_allocator,
            Scenario::paper(2, &[80]),
            Scenario::paper(2, &[79]),
            allocator_and_speed,
            allocator_and_unload,
            speed_and_unload,
        ];
        for workers in [1, 2] {
            let verdicts = check_many(&list, workers);
            assert_eq!(verdicts.len(), list.len());
            for (s, v) in list.iter().zip(&verdicts) {
                let alone = Simulation::new(s).map(drop);
                assert_eq!(v.as_ref().map_err(ToString::to_string), alone.as_ref().map_err(ToString::to_string));
            }
            assert_eq!(verdicts.iter().filter(|v| v.is_err()).count(), 7, "bad speed, unload, allocator, cell 80 and the three pairs");
        }
    }
}
