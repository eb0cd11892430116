//! Charging (spec section 2 and phase 7, paper III-D): the threshold rule with put-back,
//! opportunistic charging, stranding, the charger pool, and the charging count C.
//!
//! - **Threshold rule.** A robot whose energy falls below the threshold goes to charge: at
//!   once when idle; when heading for goods and not yet inside the service point's edge, it
//!   puts the goods back at the front of the queue first; otherwise it is marked and goes
//!   after unloading.
//! - **Opportunistic charging** (extension): an idle robot below `charging.level` also goes.
//! - **Stranding.** A robot whose energy reaches zero stops for good.
//! - **C** counts arrivals at a charger to charge.
//! - **Chargers.** In the paper every robot charges at its own home charger. Shared chargers
//!   (extension) are a pool: a robot claims the nearest free charger by route (ties: the
//!   first in the layout) until it is full; with none free it stops where it is,
//!   WAIT_CHARGER, in a first-come-first-served queue.
//!
//! The arithmetic (ε comparisons, consumption, charging per step) is in [`crate::energy`].

use crate::alloc::Goods;
use crate::energy;
use crate::events::EventKind;
use crate::ids::{CellId, GoodsId, NodeId, NONE};
use crate::robot::{State, Target};
use crate::route::{self, Place};
use crate::scenario::{ChargerUse, Scenario};
use crate::sim::Paper;
use crate::world::World;
use std::collections::VecDeque;

/// Who holds which charger, and who waits for one (shared chargers only).
#[derive(Clone, Debug)]
pub(crate) struct Chargers {
    shared: bool,
    /// Charger node → its index in `layout.chargers` (`NONE` for other nodes).
    slot_of_node: Vec<u32>,
    /// The robot holding each charger, or `NONE`.
    claim: Vec<u32>,
    /// Robots waiting for a charger, first come first served.
    queue: VecDeque<u32>,
    /// `to_charger[k * nodes + u]`: path length from node `u` to charger `k`, for O(1)
    /// nearest-charger choices inside the step loop.
    to_charger: Vec<f64>,
}

impl Chargers {
    pub fn new(world: &World, scenario: &Scenario) -> Chargers {
        let layout = &world.layout;
        let mut slot_of_node = vec![NONE; layout.nodes.len()];
        for (k, &c) in layout.chargers.iter().enumerate() {
            slot_of_node[c.index()] = k as u32;
        }
        let shared = scenario.charging.chargers == ChargerUse::Shared;
        let to_charger = if shared { layout.chargers.iter().flat_map(|&c| world.graph.lengths_to(c)).collect() } else { Vec::new() };
        Chargers { shared, slot_of_node, claim: vec![NONE; layout.chargers.len()], queue: VecDeque::with_capacity(scenario.robots as usize), to_charger }
    }

    /// The nearest free charger from `from` by route (ties: the first in the layout).
    fn nearest_free(&self, world: &World, from: Place) -> Option<usize> {
        let nodes = world.layout.nodes.len();
        let mut best: Option<(f64, usize)> = None;
        for (k, &c) in world.layout.chargers.iter().enumerate() {
            if self.claim[k] != NONE {
                continue;
            }
            let d = route::length_via_row(&world.graph, from, c, &self.to_charger[k * nodes..(k + 1) * nodes]);
            if best.map_or(true, |(b, _)| d < b) {
                best = Some((d, k));
            }
        }
        best.map(|(_, k)| k)
    }
}

impl Paper {
    /// The threshold rule (with put-back), opportunistic charging and stranding, for robot
    /// `i` after its task transition (phase 7).
    pub(crate) fn energy_rules(&mut self, i: usize) {
        if energy::below(self.robots.energy[i], self.p.threshold) {
            match self.robots.state[i] {
                State::Idle => self.send_to_charge(i),
                State::ToPickup if !self.inside_service_edge(i) => {
                    let g = Goods { id: GoodsId(self.robots.goods[i]), cell: CellId(self.robots.cell[i]) };
                    self.goods.put_back(g);
                    self.alloc_due = true;
                    self.event(EventKind::PutBack, i, g.cell.0);
                    self.robots.goods[i] = NONE;
                    self.robots.cell[i] = NONE;
                    self.send_to_charge(i);
                }
                State::ToPickup | State::Loading | State::ToDrop | State::Unloading => self.robots.marked[i] = true,
                _ => {}
            }
        }
        if let Some(level) = self.p.opportunistic {
            if self.robots.state[i] == State::Idle && energy::below(self.robots.energy[i], level) {
                self.send_to_charge(i);
            }
        }
        if energy::exhausted(self.robots.energy[i]) && self.robots.state[i] != State::Stranded {
            if self.chargers.shared && self.robots.state[i] == State::ToCharger {
                self.release_charger(self.robots.charger[i]);
            }
            self.robots.state[i] = State::Stranded;
            self.robots.energy[i] = 0.0;
            self.robots.routing[i] = false;
            self.event(EventKind::Strand, i, NONE);
        }
    }

    /// Whether robot `i` is strictly inside the edge of the service point it is fetching from
    /// (past the point of putting goods back).
    fn inside_service_edge(&self, i: usize) -> bool {
        let r = &self.robots;
        r.at_node[i] == NONE && r.edge_u[i] == r.task_u[i] && r.edge_v[i] == r.task_v[i]
    }

    /// Sends robot `i` to charge: to its home charger, or to the pool's nearest free one.
    pub(crate) fn send_to_charge(&mut self, i: usize) {
        if !self.chargers.shared {
            let charger = self.robots.home[i];
            self.head_for_charger(i, charger);
            return;
        }
        if let Some(k) = self.chargers.nearest_free(&self.world, Place::of(&self.robots, i)) {
            self.claim_charger(i, k);
        } else {
            self.robots.state[i] = State::WaitCharger;
            self.robots.routing[i] = false;
            self.chargers.queue.push_back(i as u32);
        }
    }

    fn head_for_charger(&mut self, i: usize, charger: NodeId) {
        self.robots.state[i] = State::ToCharger;
        self.robots.charger[i] = charger.0;
        self.route(i, Target::Node(charger));
    }

    fn claim_charger(&mut self, i: usize, k: usize) {
        self.chargers.claim[k] = i as u32;
        let charger = self.world.layout.chargers[k];
        self.head_for_charger(i, charger);
    }

    /// A charger became free: the longest-waiting robot (still waiting) takes it.
    fn release_charger(&mut self, charger: u32) {
        let k = self.chargers.slot_of_node[charger as usize];
        if k == NONE {
            return;
        }
        self.chargers.claim[k as usize] = NONE;
        while let Some(j) = self.chargers.queue.pop_front() {
            if self.robots.state[j as usize] == State::WaitCharger {
                self.claim_charger(j as usize, k as usize);
                break;
            }
        }
    }

    /// Robot `i` reached its charger: it charges, and C counts one.
    pub(crate) fn arrive_at_charger(&mut self, i: usize) {
        self.robots.state[i] = State::Charging;
        self.tally.c += 1;
        self.tally.stats.charges[i] += 1;
        self.event(EventKind::Charge, i, NONE);
    }

    /// Robot `i` is full: it is idle again, and frees a shared charger.
    pub(crate) fn leave_charger(&mut self, i: usize) {
        self.robots.state[i] = State::Idle;
        self.alloc_due = true;
        if self.chargers.shared {
            self.release_charger(self.robots.charger[i]);
        }
    }
}
