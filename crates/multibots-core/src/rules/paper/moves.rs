//! Phases 3 to 6 (spec section 4): collision waiting and the count S (or a traffic policy,
//! [`crate::traffic`]), travel along the routes, dwell counters, charging and consumption,
//! then the contacts after the moves.

use crate::fleet::robot::State;
use crate::ids::NONE;
use crate::output::events::{Event, EventKind};
use crate::rules::paper::Paper;
use crate::traffic;

impl Paper {
    /// Phases 3 to 6: collision waiting and the count S, then travel, dwell counters,
    /// charging and consumption. After the collision decision every robot's phases 3 to 6
    /// touch only that robot, so one pass does them all, robot by robot.
    pub(super) fn block_and_move(&mut self) {
        let n = self.robots.len();
        let p = &self.p;
        // Who waits and how far each robot may travel: the paper's collision waiting, or a
        // traffic policy, which may also stop a robot short.
        let scene =
            traffic::Scene { graph: &self.world.graph, t: self.tally.t, wants: &self.wants, margin: p.margin, angle: p.angle, people: self.people.as_deref() };
        traffic::decide(self.traffic.as_mut(), &mut self.collisions, &mut self.bays, &mut self.robots, &scene);
        let (waits, budget) = traffic::moves(self.traffic.as_ref(), &self.collisions, n);
        let bays = &self.bays;
        // People: robots that stop for a person (not a collision) or slow down near one.
        let (halt, slow, slow_factor) = match self.people.as_deref() {
            Some(pp) => (Some(&pp.stop[..n]), Some(&pp.slow[..n]), pp.slow_factor),
            None => (None, None, 1.0),
        };
        let mut progress = false;
        let g = &self.world.graph;
        let wants = &self.wants[..n];
        let st = &mut self.tally.stats;
        let (wait_steps, collisions, distance, energy_used, order_waits) =
            (&mut st.wait_steps[..n], &mut st.collisions[..n], &mut st.distance[..n], &mut st.energy_used[..n], &mut st.order_waits[..n]);
        let (mut motion, r) = self.robots.split();
        let events = &mut self.events;
        let (t, s) = (self.tally.t, &mut self.tally.s);
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
        self.progress |= progress;
        self.count_contacts();
    }

    /// Contacts after the moves of this step, from positions (see
    /// [`Collisions::contacts_of_every_pair`]): every step, every pair. Positions change only
    /// by moves, so a step in which nobody moved has the last step's pairs again.
    fn count_contacts(&mut self) {
        let n = self.robots.len();
        // Robots that may have moved: wanted to and did not wait.
        let (waits, _) = traffic::moves(self.traffic.as_ref(), &self.collisions, n);
        let moved = self.wants[..n].iter().zip(waits).any(|(&w, &waited)| w && !waited);
        let (count, closest) = match self.last_contacts {
            Some(last) if !moved => last,
            _ => {
                let r = &self.robots;
                let (r_max, slack) = self.contact_reach;
                if !moved {
                    // No grid was built this step (nobody wanted to move).
                    self.collisions.build_grid(&r.x, &r.y, &r.radius, self.bays.flags());
                }
                let found = self.collisions.contacts_of_every_pair(&r.x, &r.y, &r.radius, r_max, slack, self.p.margin);
                self.last_contacts = Some(found);
                found
            }
        };
        self.tally.contacts += count;
        self.tally.closest = self.tally.closest.min(closest);
    }
}
