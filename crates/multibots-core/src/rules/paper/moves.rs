//! Phases 3 to 6 (spec section 4): collision waiting and the count S (or a traffic policy,
//! [`crate::traffic`]), travel along the routes, dwell counters, charging and consumption,
//! then the contacts after the moves.

use crate::fleet::robot::{Robots, State};
use crate::ids::NONE;
use crate::people::People;
use crate::record::events::{Event, EventKind};
use crate::record::metrics::Tally;
use crate::rules::paper::pipeline::Pipeline;
use crate::rules::paper::state::Record;
use crate::rules::paper::Params;
use crate::traffic;
use crate::world::graph::HighwayGraph;

impl Pipeline {
    /// Phase 3: who waits and how far each robot may travel: the paper's collision waiting,
    /// or a traffic policy, which may also stop a robot short. Robots step into and out of
    /// their bays first.
    pub(crate) fn decide(&mut self, p: &Params, g: &HighwayGraph, robots: &mut Robots, t: u64, people: Option<&People>) {
        let scene = traffic::Scene { graph: g, t, wants: &self.wants, margin: p.margin, angle: p.angle, people };
        traffic::decide(self.traffic.as_mut(), &mut self.collisions, &mut self.bays, robots, &scene);
    }

    /// Phases 3 (the count S) to 6: travel, dwell counters, charging and consumption, after
    /// the collision decision. From there on every robot's phases touch only that robot, so
    /// one pass does them all, robot by robot. Returns whether anybody moved, dwelt or
    /// charged.
    pub(crate) fn travel(&self, p: &Params, g: &HighwayGraph, robots: &mut Robots, people: Option<&People>, record: &mut Record) -> bool {
        let n = robots.len();
        let (waits, budget) = traffic::moves(self.traffic.as_ref(), &self.collisions, n);
        let bays = &self.bays;
        // People: robots that stop for a person (not a collision) or slow down near one.
        let (halt, slow, slow_factor) = match people {
            Some(pp) => (Some(&pp.stop[..n]), Some(&pp.slow[..n]), pp.slow_factor),
            None => (None, None, 1.0),
        };
        let mut progress = false;
        let wants = &self.wants[..n];
        let st = &mut record.tally.stats;
        let (wait_steps, collisions, distance, energy_used, order_waits) =
            (&mut st.wait_steps[..n], &mut st.collisions[..n], &mut st.distance[..n], &mut st.energy_used[..n], &mut st.order_waits[..n]);
        let (mut motion, r) = robots.split();
        let events = &mut record.events;
        let (t, s) = (record.tally.t, &mut record.tally.s);
        for i in 0..n {
            let state = r.state[i];
            // Phase 3: a wait that begins is a collision.
            let w = waits[i];
            if w {
                wait_steps[i] += 1;
                if matches!(state, State::ToPickup | State::ToDrop) {
                    order_waits[i] += 1;
                }
                if !r.waited[i] {
                    *s += 1;
                    collisions[i] += 1;
                    events.push(Event { step: t, kind: EventKind::Wait, robot: i as u32, cell: NONE });
                }
            }
            r.waited[i] = w;
            // Phase 4: robots that may move travel `speed` px along their routes (or what the
            // traffic policy allows).
            let moves = wants[i] && !w && !halt.is_some_and(|h| h[i]) && !bays.holds(i);
            if moves {
                let mut step = budget.map_or(r.speed[i], |b| b[i]);
                if slow.is_some_and(|s| s[i]) {
                    step = step.min(r.speed[i] * slow_factor);
                }
                distance[i] += motion.advance(g, i, step);
            }
            p.dwell_and_energy(state, !wants[i], &mut r.dwell[i], &mut r.energy[i], &mut energy_used[i]);
            progress |= moves | state.busy_in_place();
        }
        progress
    }

    /// Contacts after the moves of this step, from positions (see
    /// [`crate::collision::Collisions::contacts_of_every_pair`]): every step, every pair.
    /// Positions change only by moves, so a step in which nobody moved has the last step's
    /// pairs again.
    pub(crate) fn count_contacts(&mut self, margin: f64, robots: &Robots, tally: &mut Tally) {
        let n = robots.len();
        // Robots that may have moved: wanted to and did not wait.
        let (waits, _) = traffic::moves(self.traffic.as_ref(), &self.collisions, n);
        let moved = self.wants[..n].iter().zip(waits).any(|(&w, &waited)| w && !waited);
        let (count, closest) = match self.last_contacts {
            Some(last) if !moved => last,
            _ => {
                let r = robots;
                let (r_max, slack) = self.contact_reach;
                if !moved {
                    // No grid was built this step (nobody wanted to move).
                    self.collisions.build_grid(&r.x, &r.y, &r.radius, self.bays.flags());
                }
                let found = self.collisions.contacts_of_every_pair(&r.x, &r.y, &r.radius, r_max, slack, margin);
                self.last_contacts = Some(found);
                found
            }
        };
        tally.contacts += count;
        tally.closest = tally.closest.min(closest);
    }
}
