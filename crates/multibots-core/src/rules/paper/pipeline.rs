//! The step's pipeline: its buffers, and the phases after phase 1 in their order.

use crate::collision::Collisions;
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
        Pipeline {
            wants: vec![false; n],
            bays: Bays::new(spread, n, r_max, scenario.collision.margin),
            collisions: Collisions::new(world.reach_bounds(), reach, n),
            traffic: (scenario.traffic != Traffic::Wait)
                .then(|| TrafficState::new(scenario.traffic, &world.graph, n, scenario.robot.radius, scenario.collision.margin)),
            contact_reach: (r_max, 2.0 * robots.speed.iter().copied().fold(0.0, f64::max)),
            last_contacts: None,
            progress: false,
        }
    }

    /// A new step up to phase 1: the step count, then phase 0.
    pub fn begin(&mut self, goods: &mut GoodsQueue, record: &mut Record) {
        record.tally.t += 1;
        record.events.clear();
        self.progress = false;
        if goods.lifelong.is_some() {
            goods.arrive(record);
            self.progress = !record.events.is_empty();
        }
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
        intend(robots, &mut self.wants, &mut self.bays);
        if let Some(people) = crowd.people.as_deref_mut() {
            people.guard(robots, &self.wants);
        }
        self.decide(p, &world.graph, robots, record.tally.t, crowd.people.as_deref());
        self.progress |= self.travel(p, &world.graph, robots, crowd.people.as_deref(), record);
        self.count_contacts(p.margin, robots, &mut record.tally);
        if let Some(people) = crowd.people.as_deref_mut() {
            people.step(robots);
        }
        if let Some(alone) = crowd.alone.as_deref_mut() {
            alone.step_alone();
        }
        transitions(p, world, robots, goods, stations, record);
        self.end(p, world, robots, goods, &stations.homes, record);
    }
}
