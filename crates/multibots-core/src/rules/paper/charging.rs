//! Charging (spec section 2 and phase 7, paper III-D): the threshold rule with put-back,
//! opportunistic charging, stranding, the charger pool, and the charging count C.
//!
//! - **Threshold rule.** A robot whose energy falls below the threshold goes to charge: at
//!   once when idle; when heading for goods and not yet inside the service point's edge, it
//!   puts the goods back at the front of the queue first; otherwise it is marked and goes
//!   after unloading.
//! - **Opportunistic charging** (extension): an idle robot below `charging.level` also goes.
//! - **Staggered charging** (extension): an idle robot below its own level, spread between
//!   the threshold and `charging.level` over the fleet, goes when a charger is free for it
//!   (within `charging.reach`); it never queues above the threshold (docs/charging.md says
//!   why).
//! - **Stranding.** A robot whose energy reaches zero stops for good.
//! - **C** counts arrivals at a charger to charge.
//! - **Chargers.** In the paper every robot charges at its own home charger. Shared chargers
//!   (extension) are a pool: a robot claims the nearest free charger by route (ties: the
//!   first in the layout) until it is full; with none free it stops where it is,
//!   WAIT_CHARGER, in a first-come-first-served queue.
//!
//! The arithmetic (ε comparisons, consumption, charging per step) is in [`crate::fleet::energy`].

use crate::alloc::Goods;
use crate::error::{Error, Result};
use crate::fleet::energy;
use crate::fleet::placement::Homes;
use crate::fleet::robot::Robots;
use crate::fleet::robot::{State, Target};
use crate::fleet::route::service_target;
use crate::fleet::route::{self, Place};
use crate::ids::CellId as Cell;
use crate::ids::{CellId, GoodsId, NodeId, NONE};
use crate::input::scenario::{ChargerUse, Scenario};
use crate::record::events::EventKind;
use crate::rules::paper::state::Stations;
use crate::rules::paper::tasks::Cycle;
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
    /// Robots waiting for a charger, in the order they came, with the step each began to wait.
    queue: VecDeque<(u32, u64)>,
    /// Chargers nobody holds.
    free: usize,
    /// Staggered charging: how far a robot above the threshold drives to a free charger, px.
    reach: f64,
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
        let free = layout.chargers.len();
        let reach = scenario.charging.reach.unwrap_or(f64::INFINITY);
        Chargers { shared, slot_of_node, claim: vec![NONE; free], queue: VecDeque::new(), free, reach, to_charger }
    }

    /// Whether a robot sent to charge now would find a charger free: its home charger, or a
    /// shared one nobody holds.
    fn one_free(&self) -> bool {
        !self.shared || self.free > 0
    }

    /// Whether a free charger lies within `reach` px of `from` by route.
    fn nearest_free_within(&self, world: &World, from: Place, reach: f64) -> bool {
        self.nearest_free(world, from).is_some_and(|k| {
            let nodes = world.layout.nodes.len();
            route::length_via_row(&world.graph, from, world.layout.chargers[k], &self.to_charger[k * nodes..(k + 1) * nodes]) <= reach
        })
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

impl Cycle<'_> {
    /// The threshold rule (with put-back), opportunistic charging and stranding, for robot
    /// `i` after its task transition (phase 7).
    pub(crate) fn energy_rules(&mut self, i: usize) {
        let (p, world, t) = (self.p, self.world, self.record.tally.t);
        if energy::below(self.robots.energy[i], p.threshold) {
            match self.robots.state[i] {
                State::Idle => self.stations.send_to_charge(world, self.robots, i, t),
                State::ToPickup if !inside_service_edge(world, self.robots, i) => {
                    let g = Goods { id: GoodsId(self.robots.goods[i]), cell: CellId(self.robots.cell[i]) };
                    self.goods.put_back(g);
                    self.goods.alloc_due = true;
                    self.record.event(EventKind::PutBack, i, g.cell.0);
                    self.robots.goods[i] = NONE;
                    self.robots.cell[i] = NONE;
                    self.stations.send_to_charge(world, self.robots, i, t);
                }
                State::ToPickup | State::Loading | State::ToDrop | State::Unloading => self.robots.marked[i] = true,
                _ => {}
            }
        }
        if let Some(level) = p.opportunistic {
            if self.robots.state[i] == State::Idle && energy::below(self.robots.energy[i], level) {
                self.stations.send_to_charge(world, self.robots, i, t);
            }
        }
        if let Some(level) = p.staggered {
            let chargers = &self.stations.chargers;
            if self.robots.state[i] == State::Idle && energy::below(self.robots.energy[i], own_level(p.threshold, level, i)) && chargers.one_free() {
                let near = !chargers.shared || chargers.reach.is_infinite() || chargers.nearest_free_within(world, Place::of(self.robots, i), chargers.reach);
                if near {
                    self.stations.send_to_charge(world, self.robots, i, t);
                }
            }
        }
        if energy::exhausted(self.robots.energy[i]) && self.robots.state[i] != State::Stranded {
            if self.stations.chargers.shared && self.robots.state[i] == State::ToCharger {
                self.stations.release_charger(world, self.robots, self.robots.charger[i], t);
            }
            self.robots.state[i] = State::Stranded;
            self.robots.energy[i] = 0.0;
            self.robots.routing[i] = false;
            self.record.tally.first_stranded.get_or_insert(t);
            self.record.event(EventKind::Strand, i, NONE);
        }
    }

    /// Robot `i` reached its charger: it charges, and C counts one.
    pub(crate) fn arrive_at_charger(&mut self, i: usize) {
        self.robots.state[i] = State::Charging;
        self.record.tally.c += 1;
        self.record.tally.stats.charges[i] += 1;
        self.record.event(EventKind::Charge, i, NONE);
    }

    /// Robot `i` is full: it is idle again, and frees a shared charger.
    pub(crate) fn leave_charger(&mut self, i: usize) {
        self.robots.state[i] = State::Idle;
        self.goods.alloc_due = true;
        if self.stations.chargers.shared {
            self.stations.release_charger(self.world, self.robots, self.robots.charger[i], self.record.tally.t);
        }
    }
}

/// Whether robot `i` is strictly inside the edge of the service point it is fetching from
/// (past the point of putting goods back).
fn inside_service_edge(world: &World, r: &Robots, i: usize) -> bool {
    // A robot fetching goods always has their cell (they are set and cleared together).
    debug_assert!(r.cell[i] != NONE, "robot {i} fetches goods without a cell");
    let (u, v) = world.layout.cells[r.cell[i] as usize].edge;
    r.at_node[i] == NONE && r.edge_u[i] == u.0 && r.edge_v[i] == v.0
}

fn head_for_charger(world: &World, r: &mut Robots, i: usize, charger: NodeId) {
    r.state[i] = State::ToCharger;
    r.charger[i] = charger.0;
    route::assign(r, &world.graph, i, Target::Node(charger));
}

impl Stations {
    /// Sends robot `i` to charge at step `t`: to its home charger, or to the pool's nearest
    /// free one.
    pub(crate) fn send_to_charge(&mut self, world: &World, r: &mut Robots, i: usize, t: u64) {
        if !self.chargers.shared {
            let charger = r.home[i];
            head_for_charger(world, r, i, charger);
            return;
        }
        if let Some(k) = self.chargers.nearest_free(world, Place::of(r, i)) {
            self.claim_charger(world, r, i, k);
        } else {
            r.state[i] = State::WaitCharger;
            r.routing[i] = false;
            if self.homes.spread() {
                // It waits in its bay, out of the traffic, not where it stands (often an
                // unloading zone, where the next robot would stand on it).
                route::assign(r, &world.graph, i, self.homes.target(r, i));
            }
            self.chargers.queue.push_back((i as u32, t));
        }
    }

    fn claim_charger(&mut self, world: &World, r: &mut Robots, i: usize, k: usize) {
        debug_assert!(self.chargers.claim[k] == NONE, "charger {k} claimed twice");
        self.chargers.claim[k] = i as u32;
        self.chargers.free -= 1;
        head_for_charger(world, r, i, world.layout.chargers[k]);
    }

    /// A charger became free at step `t`: of the robots still waiting, the one whose drive to
    /// it is shortest, less the steps it has waited, takes it (ties: the first to come).
    /// Serving the longest-waiting robot wherever it stands left chargers idle while robots
    /// drove across the warehouse to them; counting the wait keeps a far robot from waiting
    /// for ever.
    fn release_charger(&mut self, world: &World, r: &mut Robots, charger: u32, t: u64) {
        let chargers = &mut self.chargers;
        let k = chargers.slot_of_node[charger as usize];
        if k == NONE {
            return;
        }
        if chargers.claim[k as usize] != NONE {
            chargers.free += 1;
        }
        chargers.claim[k as usize] = NONE;
        let state = &r.state;
        chargers.queue.retain(|&(j, _)| state[j as usize] == State::WaitCharger);
        let nodes = world.layout.nodes.len();
        let row = &chargers.to_charger[k as usize * nodes..(k as usize + 1) * nodes];
        let mut best: Option<(f64, usize)> = None;
        for (pos, &(j, since)) in chargers.queue.iter().enumerate() {
            let j = j as usize;
            let drive = route::length_via_row(&world.graph, Place::of(r, j), NodeId(charger), row) / r.speed[j];
            let priority = drive - (t - since) as f64;
            if best.map_or(true, |(b, _)| priority < b) {
                best = Some((priority, pos));
            }
        }
        if let Some((_, pos)) = best {
            let (j, _) = chargers.queue.remove(pos).expect("a position of the queue");
            self.claim_charger(world, r, j as usize, k as usize);
        }
    }
}

/// Robot `i`'s own level under staggered charging: between `threshold` (excluded) and
/// `level`, spread over the fleet by the golden-ratio sequence, so that any run of robot
/// numbers (robots placed side by side) holds levels from the whole range, and a fleet of any
/// size covers it evenly.
#[must_use]
pub(crate) fn own_level(threshold: f64, level: f64, i: usize) -> f64 {
    // 1/φ; frac(0.5 + i/φ) for i = 0, 1, 2, …: 0.5, 0.118, 0.736, 0.354, …
    const INV_PHI: f64 = 0.618_033_988_749_894_9;
    let u = (0.5 + i as f64 * INV_PHI).fract();
    threshold + (level - threshold) * (1.0 - u)
}

/// A cell a scenario can ask for, and how to name it in an error.
pub(crate) struct Asked {
    pub field: String,
    pub value: String,
    pub note: String,
    pub cell: u32,
}

/// Refuses a scenario whose battery cannot carry a robot through even the easiest of its
/// tasks: from the best charger to the goods and on to the unloading zone and back to that
/// charger, or even to the goods with energy above the threshold (a robot would turn back to
/// charge before every pickup, for ever). Then nothing can ever be delivered; the error names
/// that task and the energy it needs. `cells` are the cells the scenario can ask for, with
/// the field and value to name and a note before the reason. A single impossible task among
/// feasible ones is left to the run, which ends `livelock` on it (docs/metrics.md).
pub(crate) fn check_reach(world: &World, scenario: &Scenario, homes: &Homes, cells: &[Asked]) -> Result<()> {
    let (g, layout, r) = (&world.graph, &world.layout, &scenario.robot);
    let steps = |d: f64| (d / r.speed).ceil();
    let dwell = f64::from(scenario.dwell.loading + scenario.dwell.unloading);
    let mut memo: Vec<Option<(f64, f64, String)>> = vec![None; layout.cells.len()];
    let mut easiest: Option<(f64, Error)> = None;
    for Asked { field, value, note, cell } in cells {
        let c = *cell as usize;
        if memo[c].is_none() {
            let service = service_target(layout, Cell(*cell));
            let Target::Point { u, v, x, y } = service else { unreachable!("service points are points") };
            let at = Place { x, y, at_node: NONE, edge_u: u.0, edge_v: v.0 };
            let zone = homes.unload_of(*cell);
            let d2 = route::length(g, at, Target::Node(zone));
            let mut best = (f64::INFINITY, f64::INFINITY, String::new());
            for &ch in &layout.chargers {
                let d1 = route::length(g, Place::node(g, ch), service);
                let d3 = route::length(g, Place::node(g, zone), Target::Node(ch));
                let out = steps(d1) * r.consumption;
                let total = (steps(d1) + dwell + steps(d2) + steps(d3)) * r.consumption;
                if (total, out) < (best.0, best.1) {
                    let name = |n: NodeId| layout.nodes[n.index()].name.clone();
                    best = (total, out, format!("{} → cell {cell} → {} → {}", name(ch), name(zone), name(ch)));
                }
            }
            memo[c] = Some(best);
        }
        let (total, out, way) = memo[c].clone().expect("filled above");
        let fault = if out > r.energy_full - r.threshold + energy::EPS {
            format!(
                "{note}reaching it takes {out:.4} energy from the nearest charger, more than robot.energy_full − robot.threshold = {:.4}: a robot would turn back to charge before every pickup",
                r.energy_full - r.threshold
            )
        } else if total > r.energy_full + energy::EPS {
            format!("{note}a round trip ({way}) takes {total:.4} energy; a full battery (robot.energy_full) holds {}", r.energy_full)
        } else {
            return Ok(());
        };
        if easiest.as_ref().map_or(true, |(t, _)| total < *t) {
            easiest = Some((total, Error::scenario(field.clone(), value, fault)));
        }
    }
    easiest.map_or(Ok(()), |(_, e)| Err(e))
}
