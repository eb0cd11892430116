//! The task cycle (spec phase 7): TO_PICKUP → LOADING → TO_DROP → UNLOADING → IDLE, and the
//! arrivals that end a trip (at a charger, at home).
//!
//! A robot makes at most one transition per step. Loading takes `dwell.loading` steps at the
//! service point and empties the cell; unloading takes `dwell.unloading` steps on the
//! unloading zone and is one delivery. A robot marked by the threshold rule goes to charge
//! after unloading instead of becoming idle.

use crate::fleet::energy;
use crate::fleet::robot::{Robots, State, Target};
use crate::fleet::route;
use crate::ids::NONE;
use crate::record::events::EventKind;
use crate::rules::paper::goods_queue::GoodsQueue;
use crate::rules::paper::state::{Record, Stations};
use crate::rules::paper::Params;
use crate::world::World;

/// Phase 7: at most one state transition per robot, then the threshold and stranding rules.
pub(crate) fn transitions(p: &Params, world: &World, robots: &mut Robots, goods: &mut GoodsQueue, stations: &mut Stations, record: &mut Record) {
    let mut cycle = Cycle { p, world, robots, goods, stations, record };
    for i in 0..cycle.robots.len() {
        let r = &cycle.robots;
        if p.due(r.state[i], r.routing[i], r.dwell[i], r.energy[i]) {
            cycle.task_transition(i);
            cycle.energy_rules(i);
        }
        cycle.record.tally.stats.state_steps[i][cycle.robots.state[i] as usize] += 1;
    }
}

/// What phase 7 touches, for one robot at a time: the task cycle (here) and the charging
/// rules (`charging.rs`).
pub(crate) struct Cycle<'a> {
    pub p: &'a Params,
    pub world: &'a World,
    pub robots: &'a mut Robots,
    pub goods: &'a mut GoodsQueue,
    pub stations: &'a mut Stations,
    pub record: &'a mut Record,
}

impl Cycle<'_> {
    /// The task transition of robot `i` in phase 7, if one is due.
    fn task_transition(&mut self, i: usize) {
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
        let t = self.record.tally.t;
        self.record.tally.last_work = t;
        self.goods.picked(t, cell);
        self.robots.carrying[i] = true;
        self.robots.state[i] = State::ToDrop;
        self.record.event(EventKind::Pickup, i, cell);
        let zone = self.stations.homes.unload_of(cell);
        route::assign(self.robots, &self.world.graph, i, Target::Node(zone));
    }

    /// Unloading is done: one delivery; the robot is idle, or goes to charge if marked.
    fn deliver(&mut self, i: usize) {
        let cell = self.robots.cell[i];
        let tally = &mut self.record.tally;
        tally.last_work = tally.t;
        tally.delivered += 1;
        tally.stats.delivered[i] += 1;
        if let Some(ll) = self.goods.lifelong.as_mut() {
            ll.delivered(tally.t, self.robots.goods[i]);
        }
        self.record.event(EventKind::Deliver, i, cell);
        self.robots.goods[i] = NONE;
        self.robots.cell[i] = NONE;
        self.robots.carrying[i] = false;
        if self.robots.marked[i] {
            self.robots.marked[i] = false;
            self.stations.send_to_charge(self.world, self.robots, i, self.record.tally.t);
        } else {
            self.robots.state[i] = State::Idle;
            self.goods.alloc_due = true;
        }
    }
}
