//! The League of Robot Runners' 2026 rules (Start-Kit `v3.1.0`), within the grid rule set: the
//! 2024 map, task pool and schedulers, with actions of `agentCounter` ticks, robots as squares
//! of side `agentSize` (`footprint.rs`), a tick resolved as the Start-Kit's action model
//! resolves it (`model.rs`), seeded delays drawn as its generator draws them (`delays.rs`,
//! `random.rs`), schedules corrected robot by robot (`tasks.rs`) and an executor between the
//! planner and the robots (`entries.rs`; the built-ins `planner.rs`, `executor.rs`).
//!
//! Time is counted in ticks; the planner is called every `interval` ticks
//! (`ceil(planCommTimeLimit / actionMoveTimeLimit)`, 10 at the competition's 1,000 and 100 ms).
//! In the order of the Start-Kit's `BaseSystem::simulate`:
//! 1. before the first tick, the initial call: the scheduler, then the planner, see every
//!    robot free and every task new;
//! 2. at a communication point (tick 0, `interval`, `2 · interval`, ...): the schedule and the
//!    plan of the last call are applied: the schedule is corrected and set (`tasks.rs`), the
//!    executor stages the plan and predicts where the robots will be (its queues are checked:
//!    each may only be a prefix of the old queue followed by the plan, waits left out); then
//!    the next call is made, from the prediction;
//! 3. every tick: the executor says GO or STOP per robot; the delays are drawn; each robot asks
//!    for the front of its staged actions if GO, else a wait, and a held robot for a wait; the
//!    model plays the tick; a staged wait is used up by any wait, a staged move or turn when
//!    the robot's cell or heading changes; then each robot on the next errand of its task
//!    advances it, finished tasks free their robots and are replaced in the pool.
//!
//! What is not the Start-Kit's, and why: the Start-Kit runs the planner on a thread and applies
//! its answer at the first communication point after it returns, so which tick a plan reaches
//! depends on the machine; here a call's answer is always applied `interval` ticks after the
//! call (what the Start-Kit does whenever the planner keeps to its time), and no tick is lost
//! to a slow entry, so a run is the same on every machine. Robots that finish a task between a
//! call and its application are taken off their entry of the called schedule (the Start-Kit
//! does this for its C++ schedulers, and loses it to a race for Python ones). A step sideways
//! off the map is refused (the Start-Kit wraps it to the next row).

pub mod delays;
pub mod entries;
pub mod executor;
pub mod footprint;
pub mod model;
pub mod planner;
pub mod random;
mod run;
mod show;
pub mod tasks;

pub use run::{comm_ms, Entries, Lorr26, COMM_MS, INITIAL_MS, TICK_MS};
