//! The step of the paper rules as a pipeline, after rapier's `PhysicsPipeline::step`: one
//! function calls the phases in order ([`Pipeline::step`]), each phase takes the state it
//! touches as arguments (`state.rs` splits it by concern), and the pipeline holds only its
//! own buffers. No phase can reach the run as a whole.
//!
//! | spec | [`Phase`] | what | takes |
//! | --- | --- | --- | --- |
//! | 0 | `Arrive` | the step count; lifelong orders and restocks arrive | goods, record |
//! | 1 | `HandOut` | idle robots get goods or go to charge, or go home | the allocator, robots, goods, stations, record, people |
//! | 2 | `Intend` | who wants to move, where each is heading; who stands in a bay | robots, `wants`, bays |
//! | – | `PeopleGuard` | robots stop, or slow down, for people near them | people, robots, `wants` |
//! | 3 | `Decide` | collision waiting or a traffic policy; robots step into and out of bays | robots, `wants`, bays, collisions, traffic, people |
//! | 4–6 | `Travel` | the count S; travel; dwell counters, charging and consumption | robots, phase 3's answer, bays, people, record |
//! | – | `Contacts` | contacts after the moves | robots, collisions, bays, record |
//! | – | `PeopleWalk` | people walk, pick or rest; the safety figures | people, robots |
//! | – | `PeopleAloneWalk` | the same people on a floor with no robot (output only) | the people alone |
//! | 7 | `Tasks` | the task cycle, then the charging rules | robots, goods, stations, record |
//! | 8 | `End` | completion, stalls, the step limit or horizon; the resources' use | robots, goods, homes, record, phase 3's answer |
//!
//! Every phase also reads the world and the model's numbers ([`Params`]). A step can also be
//! driven in three pieces, with phase 1 decided outside the engine in between
//! (`decision_point.rs`): [`Pipeline::begin`], the two halves of phase 1
//! ([`GoodsQueue::begin_hand_out`], [`GoodsQueue::finish_hand_out`]), and
//! [`Pipeline::finish`]. Runs of quiet steps take a lean pass over phases 2 to 6 instead
//! (`cruise.rs`), then the same phases 7 and 8.

use crate::alloc::Allocator;
use crate::collision::Collisions;
use crate::error::Result;
use crate::fleet::bay::Bays;
use crate::fleet::robot::Robots;
use crate::input::scenario::{Scenario, Traffic};
use crate::rules::paper::goods_queue::GoodsQueue;
use crate::rules::paper::intend::intend;
use crate::rules::paper::state::{Crowd, Record, Stations};
use crate::rules::paper::tasks::transitions;
use crate::rules::paper::Params;
use crate::traffic::TrafficState;
use crate::world::World;

/// The phases of a step, declared in the order the step runs them (the module's table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Phase {
    Arrive,
    HandOut,
    Intend,
    PeopleGuard,
    Decide,
    Travel,
    Contacts,
    PeopleWalk,
    PeopleAloneWalk,
    Tasks,
    End,
}

// Read by the `profiling` feature's totals, and by the test below.
#[cfg_attr(not(feature = "profiling"), allow(dead_code))]
impl Phase {
    pub(crate) const COUNT: usize = 11;
    /// Every phase, in the order of the table.
    pub(crate) const ALL: [Phase; Phase::COUNT] = [
        Phase::Arrive,
        Phase::HandOut,
        Phase::Intend,
        Phase::PeopleGuard,
        Phase::Decide,
        Phase::Travel,
        Phase::Contacts,
        Phase::PeopleWalk,
        Phase::PeopleAloneWalk,
        Phase::Tasks,
        Phase::End,
    ];
}

/// Runs one phase: the one place a per-phase timer goes. It compiles to the call alone,
/// unless the `profiling` feature times each phase (`profile.rs`).
#[allow(clippy::inline_always)] // a hook that must cost nothing
#[inline(always)]
fn run<R>(phase: Phase, f: impl FnOnce() -> R) -> R {
    #[cfg(feature = "profiling")]
    {
        super::profile::run(phase, f)
    }
    #[cfg(not(feature = "profiling"))]
    {
        let _ = phase;
        f()
    }
}

/// The step's own buffers: what one phase leaves for the next (rebuilt every step), and the
/// collision index and traffic policy's state, carried from step to step.
pub(crate) struct Pipeline {
    /// Phase 2's answer: who wants to move (the heading it wants is `robots.heading`).
    pub wants: Vec<bool>,
    /// Who stands in a bay this step (spread placement, `fleet/bay.rs`).
    pub bays: Bays,
    /// Collision waiting (phase 3) and its answer, and the grid the contact count reads.
    pub collisions: Collisions,
    /// The `gate` and `reserve` traffic policies (`None`: the paper's collision waiting).
    pub traffic: Option<TrafficState>,
    /// The fleet's largest radius and twice its top speed, for counting contacts (robots
    /// keep both for the whole run).
    pub contact_reach: (f64, f64),
    /// The last step's contacts and closest approach (`None` before the first count).
    pub last_contacts: Option<(u64, f64)>,
    /// Whether anything happened this step: a robot moved, dwelt or charged, or stock
    /// changed (no progress for long while work remains is a gridlock).
    pub progress: bool,
}

impl Pipeline {
    /// The buffers for `robots` on `world` (spread placement: `spread`).
    pub fn new(world: &World, scenario: &Scenario, robots: &Robots, spread: bool) -> Pipeline {
        let n = robots.len();
        let r_max = robots.radius.iter().copied().fold(0.0, f64::max);
        let reach = 2.0 * scenario.robot.radius + scenario.collision.margin;
        let mut collisions = Collisions::new(world.reach_bounds(), reach, n);
        collisions.keep_lists(world.reach_bounds());
        Pipeline {
            wants: vec![false; n],
            bays: Bays::new(spread, n, r_max, scenario.collision.margin),
            collisions,
            traffic: (scenario.traffic != Traffic::Wait)
                .then(|| TrafficState::new(scenario.traffic, &world.graph, n, scenario.robot.radius, scenario.collision.margin)),
            contact_reach: (r_max, 2.0 * robots.speed.iter().copied().fold(0.0, f64::max)),
            last_contacts: None,
            progress: false,
        }
    }

    /// A new step up to phase 1: the step count, then phase 0.
    pub fn begin(&mut self, goods: &mut GoodsQueue, record: &mut Record) {
        run(Phase::Arrive, || {
            record.tally.t += 1;
            record.events.clear();
            self.progress = false;
            if goods.lifelong.is_some() {
                goods.arrive(record);
                self.progress = !record.events.is_empty();
            }
        });
    }

    /// One step, every phase in the order of the table. An error of the allocator (phase
    /// 1) ends the step there.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        allocator: &mut dyn Allocator,
        p: &Params,
        world: &World,
        robots: &mut Robots,
        goods: &mut GoodsQueue,
        stations: &mut Stations,
        record: &mut Record,
        crowd: &mut Crowd,
    ) -> Result<()> {
        self.begin(goods, record);
        run(Phase::HandOut, || goods.hand_out(allocator, p, world, robots, stations, record, crowd.people.as_deref()))?;
        self.finish(p, world, robots, goods, stations, record, crowd);
        Ok(())
    }

    /// Phases 2 to 8, after phase 1.
    #[allow(clippy::too_many_arguments)]
    pub fn finish(
        &mut self,
        p: &Params,
        world: &World,
        robots: &mut Robots,
        goods: &mut GoodsQueue,
        stations: &mut Stations,
        record: &mut Record,
        crowd: &mut Crowd,
    ) {
        let g = &world.graph;
        run(Phase::Intend, || intend(robots, &mut self.wants, &mut self.bays));
        run(Phase::PeopleGuard, || crowd.guard(robots, &self.wants));
        run(Phase::Decide, || self.decide(p, g, robots, record.tally.t, crowd.people.as_deref()));
        run(Phase::Travel, || self.progress |= self.travel(p, g, robots, crowd.people.as_deref(), record));
        run(Phase::Contacts, || self.count_contacts(p.margin, robots, &mut record.tally));
        run(Phase::PeopleWalk, || crowd.walk(robots));
        run(Phase::PeopleAloneWalk, || crowd.walk_alone());
        run(Phase::Tasks, || transitions(p, world, robots, goods, stations, record));
        run(Phase::End, || self.end(p, world, robots, goods, &stations.homes, record));
    }
}

#[cfg(test)]
mod tests {
    /// The `Phase` column of the table in a module doc, in order.
    fn table(doc: &str) -> Vec<&str> {
        let rows = doc.lines().skip_while(|l| !(l.starts_with("//! |") && l.contains("Phase"))).skip(2);
        rows.map_while(|l| l.strip_prefix("//! |")).map(|row| row.split('|').nth(1).unwrap().trim().trim_matches('`')).collect()
    }

    #[test]
    fn the_tables_name_the_phases_in_the_order_the_step_runs_them() {
        // The functions above read in the step's order: `begin` (phase 0), `step` (phase 1),
        // `finish` (the rest).
        let code = include_str!("pipeline.rs");
        let code = &code[..code.find("#[cfg(test)]").unwrap()];
        let ran: Vec<&str> = code.split("run(Phase::").skip(1).map(|s| &s[..s.find(',').unwrap()]).collect();
        assert_eq!(ran.len(), super::Phase::COUNT, "{ran:?}");
        let names: Vec<String> = super::Phase::ALL.iter().map(|p| format!("{p:?}")).collect();
        assert_eq!(names, ran, "Phase::ALL");
        assert_eq!(table(code), ran, "pipeline.rs");
        assert_eq!(table(include_str!("mod.rs")), ran, "mod.rs");
    }
}
