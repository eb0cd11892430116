//! The task cycle (spec phase 7): TO_PICKUP → LOADING → TO_DROP → UNLOADING → IDLE, and the
//! arrivals that end a trip (at a charger, at home).
//!
//! A robot makes at most one transition per step. Loading takes `dwell.loading` steps at the
//! service point and empties the cell; unloading takes `dwell.unloading` steps on the
//! unloading zone and is one delivery. A robot marked by the threshold rule goes to charge
//! after unloading instead of becoming idle.

use crate::fleet::energy;
use crate::fleet::robot::{State, Target};
use crate::ids::NONE;
use crate::record::events::EventKind;
use crate::rules::paper::Paper;

impl Paper {
    /// Phase 7: at most one state transition per robot, then the threshold and stranding rules.
    pub(crate) fn transitions(&mut self) {
        let p = self.p;
        for i in 0..self.robots.len() {
            let r = &self.robots;
            if p.due(r.state[i], r.routing[i], r.dwell[i], r.energy[i]) {
                self.task_transition(i);
                self.energy_rules(i);
            }
            self.tally.stats.state_steps[i][self.robots.state[i] as usize] += 1;
        }
    }

    /// The task transition of robot `i` in phase 7, if one is due.
    pub(crate) fn task_transition(&mut self, i: usize) {
        let arrived = !self.robots.routing[i];
        match self.robots.state[i] {
            State::ToPickup if arrived => self.begin_dwell(i, State::Loading),
            State::ToDrop if arrived => self.begin_dwell(i, State::Unloading),
            State::ToCharger if arrived => self.arrive_at_charger(i),
            State::ToHome if arrived => self.robots.state[i] = State::Parked,
            State::Loading if self.robots.dwell[i] >= self.p.loading => self.pick_up(i),
            State::Unloading if self.robots.dwell[i] >= self.p.unloading => self.deliver(i),
            State::Charging if energy::is_full(self.robots.energy[i], self.p.energy_full) => self.leave_charger(i),
            _ => {}
        }
    }

    fn begin_dwell(&mut self, i: usize, state: State) {
        self.robots.state[i] = state;
        self.robots.dwell[i] = 0;
    }

    /// Loading is done: the cell is empty and the robot heads for its unloading zone.
    fn pick_up(&mut self, i: usize) {
        let cell = self.robots.cell[i];
        self.tally.last_work = self.tally.t;
        self.goods.cells_full[cell as usize] = false;
        if let Some(ll) = self.lifelong.as_mut() {
            ll.picked(self.tally.t, cell);
        }
        self.robots.carrying[i] = true;
        self.robots.state[i] = State::ToDrop;
        self.event(EventKind::Pickup, i, cell);
        let zone = self.homes.unload_of(cell);
        self.route(i, Target::Node(zone));
    }

    /// Unloading is done: one delivery; the robot is idle, or goes to charge if marked.
    fn deliver(&mut self, i: usize) {
        let cell = self.robots.cell[i];
        self.tally.last_work = self.tally.t;
        self.tally.delivered += 1;
        self.tally.stats.delivered[i] += 1;
        if let Some(ll) = self.lifelong.as_mut() {
            ll.delivered(self.tally.t, self.robots.goods[i]);
        }
        self.event(EventKind::Deliver, i, cell);
        self.robots.goods[i] = NONE;
        self.robots.cell[i] = NONE;
        self.robots.carrying[i] = false;
        if self.robots.marked[i] {
            self.robots.marked[i] = false;
            self.send_to_charge(i);
        } else {
            self.robots.state[i] = State::Idle;
            self.alloc_due = true;
        }
    }
}
