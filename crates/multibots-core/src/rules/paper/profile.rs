//! A per-phase profile of the step (the `profiling` feature; `examples/phases.rs` prints it).
//! Each phase of [`Pipeline`](super::pipeline::Pipeline) runs through [`run`]: its wall time
//! is added to the thread's totals, and it runs inside a function of its own, never inlined,
//! so that callgrind's inclusive count of that function is the phase's instructions
//! (`valgrind --tool=callgrind --toggle-collect='*phases::measured*'`, then
//! `callgrind_annotate --inclusive=yes`; `benchmarks/phases.py` does both).
//!
//! Without the feature the hook is the bare call: no build but this one pays anything.

use super::pipeline::Phase;
use std::cell::RefCell;
use std::time::{Duration, Instant};

thread_local! {
    /// Per phase: the wall time and the calls so far on this thread.
    static TOTALS: RefCell<[(Duration, u64); Phase::COUNT]> = const { RefCell::new([(Duration::ZERO, 0); Phase::COUNT]) };
}

/// One phase's share of the steps run on this thread since the last [`take`].
#[derive(Clone, Debug)]
pub struct PhaseTime {
    /// The phase's name in the pipeline's table (`Intend`, `Decide`, ...).
    pub phase: &'static str,
    pub wall: Duration,
    pub calls: u64,
}

/// The totals of every phase since the last call (or the thread's start), in the order of the
/// pipeline's table; the totals start again from zero.
#[must_use]
pub fn take() -> Vec<PhaseTime> {
    TOTALS.with(|t| {
        let totals = std::mem::take(&mut *t.borrow_mut());
        Phase::ALL.iter().zip(totals).map(|(&p, (wall, calls))| PhaseTime { phase: name(p), wall, calls }).collect()
    })
}

fn name(p: Phase) -> &'static str {
    match p {
        Phase::Arrive => "Arrive",
        Phase::HandOut => "HandOut",
        Phase::Intend => "Intend",
        Phase::PeopleGuard => "PeopleGuard",
        Phase::Decide => "Decide",
        Phase::Travel => "Travel",
        Phase::Contacts => "Contacts",
        Phase::PeopleWalk => "PeopleWalk",
        Phase::PeopleAloneWalk => "PeopleAloneWalk",
        Phase::Tasks => "Tasks",
        Phase::End => "End",
    }
}

/// Runs `f` as `phase`: timed, inside that phase's own function.
pub(super) fn run<R>(phase: Phase, f: impl FnOnce() -> R) -> R {
    let t0 = Instant::now();
    let r = match phase {
        Phase::Arrive => phase_arrive(f),
        Phase::HandOut => phase_hand_out(f),
        Phase::Intend => phase_intend(f),
        Phase::PeopleGuard => phase_people_guard(f),
        Phase::Decide => phase_decide(f),
        Phase::Travel => phase_travel(f),
        Phase::Contacts => phase_contacts(f),
        Phase::PeopleWalk => phase_people_walk(f),
        Phase::PeopleAloneWalk => phase_people_alone_walk(f),
        Phase::Tasks => phase_tasks(f),
        Phase::End => phase_end(f),
    };
    let wall = t0.elapsed();
    TOTALS.with(|t| {
        let slot = &mut t.borrow_mut()[phase as usize];
        slot.0 += wall;
        slot.1 += 1;
    });
    r
}

/// One function per phase, each named for callgrind (`phase_<name>`).
macro_rules! markers {
    ($($name:ident),*) => {$(
        #[inline(never)]
        fn $name<R>(f: impl FnOnce() -> R) -> R {
            f()
        }
    )*};
}

markers!(
    phase_arrive,
    phase_hand_out,
    phase_intend,
    phase_people_guard,
    phase_decide,
    phase_travel,
    phase_contacts,
    phase_people_walk,
    phase_people_alone_walk,
    phase_tasks,
    phase_end
);
