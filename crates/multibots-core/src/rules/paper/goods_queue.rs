//! The goods queue and phase 1, the hand-out (spec section 4, phase 1).
//!
//! Goods wait in a queue, front first. At an allocation event (robots became idle, or goods
//! joined the queue) the allocator sees the idle robots and the queue and answers with
//! [`Decisions`]: assignments, and robots to send to charge now. The engine checks every
//! decision before it carries any out, so a strategy can never corrupt the run. Idle robots
//! left without goods go home to park when the queue is empty (in lifelong runs, parked robots
//! wake when orders are open).
//!
//! Phase 1 comes in two halves, [`GoodsQueue::begin_hand_out`] (who is idle, and whether
//! decisions are needed) and [`GoodsQueue::finish_hand_out`] (check and carry out); the
//! allocator answers in between ([`GoodsQueue::hand_out`]), or, paused at a decision point, a
//! caller outside the engine does (`decision_point.rs`).
//!
//! Goods put back by the threshold rule return to the front of the queue.

use crate::alloc::{AllocView, Allocator, Assignment, Decisions, Goods};
use crate::error::{Error, Result};
use crate::fleet::placement::Homes;
use crate::fleet::robot::{Robots, State, Target};
use crate::fleet::route::{self, service_target};
use crate::ids::{CellId, GoodsId, NodeId, RobotId};
use crate::input::scenario::Orders;
use crate::people::People;
use crate::record::events::{Event, EventKind};
use crate::rules::paper::lifelong::{Lifelong, OrderWindow, StockEvent};
use crate::rules::paper::state::{Record, Stations};
use crate::rules::paper::Params;
use crate::world::World;
use std::collections::VecDeque;

/// Goods not yet taken, which cells hold goods, the lifelong orders that bring more, and
/// phase 1's state.
#[derive(Clone, Debug)]
pub(crate) struct GoodsQueue {
    /// Goods not yet taken, front first.
    pub queue: VecDeque<Goods>,
    /// Which cells hold goods.
    pub cells_full: Vec<bool>,
    /// By goods id: the cell, whether the goods are in the queue, and whether the allocator
    /// handed them out in the current call (O(1) checks and removals per assignment instead
    /// of a scan of the queue). Lifelong runs drop delivered orders from the front.
    slots: OrderWindow<Slot>,
    /// Reused by every allocation event.
    pub(crate) idle: Vec<RobotId>,
    /// Beside `idle`: whether that robot was parked until this event woke it (it stands on
    /// its home slot, its route fields already those of the way home).
    woken: Vec<bool>,
    pub(crate) decisions: Decisions,
    taken: Vec<bool>,
    /// Paused at a decision point: phase 1 of the current step waits for decisions from
    /// outside the engine.
    pub(crate) pending: bool,
    /// An allocation event is due: robots became idle or goods joined the queue.
    pub(crate) alloc_due: bool,
    /// Lifelong orders and restocks (`None`: the task list is all there is).
    pub(crate) lifelong: Option<Lifelong>,
}

/// What the queue knows of one goods item, in 4 bytes: its cell (below 2^30,
/// `limits::MAX_CELLS`), whether it is in the queue, and whether the allocator handed it out
/// in the current call (the two top bits).
#[derive(Clone, Copy, Debug)]
struct Slot(u32);

const _: () = assert!(crate::input::limits::MAX_CELLS < 1 << 30);

impl Slot {
    const IN_QUEUE: u32 = 1 << 31;
    const HANDED: u32 = 1 << 30;
    const EMPTY: Slot = Slot(0);

    /// Goods of `cell` in the queue.
    fn queued(cell: CellId) -> Slot {
        Slot(cell.0 | Slot::IN_QUEUE)
    }

    fn cell(self) -> CellId {
        CellId(self.0 & !(Slot::IN_QUEUE | Slot::HANDED))
    }

    fn in_queue(self) -> bool {
        self.0 & Slot::IN_QUEUE != 0
    }

    fn handed(self) -> bool {
        self.0 & Slot::HANDED != 0
    }

    fn set(&mut self, flag: u32, on: bool) {
        if on {
            self.0 |= flag;
        } else {
            self.0 &= !flag;
        }
    }
}

impl GoodsQueue {
    /// The queue at the start of a run: the task list in order, or, with lifelong orders, a
    /// stocked warehouse whose task list arrives as the first orders.
    pub fn new(cell_count: usize, task_cells: &[u32], orders: Option<&Orders>, csv: Vec<(u64, u32)>) -> GoodsQueue {
        let mut cells_full = vec![false; cell_count];
        let mut queue: VecDeque<Goods> = VecDeque::with_capacity(cell_count.max(task_cells.len()));
        let mut lifelong = None;
        if let Some(o) = orders {
            cells_full.fill(true);
            let mut ll = Lifelong::new(o, cell_count, csv);
            ll.initial(task_cells, &cells_full, &mut |id, cell| queue.push_back(Goods { id, cell }));
            lifelong = Some(ll);
        } else {
            queue.extend(task_cells.iter().enumerate().map(|(k, &c)| {
                cells_full[c as usize] = true;
                Goods { id: GoodsId(k as u32), cell: CellId(c) }
            }));
        }
        // Lifelong slots grow with the orders that arrive.
        let mut slots = OrderWindow::new();
        for gd in &queue {
            slots.reach(gd.id.index(), Slot::EMPTY);
            slots[gd.id.index()] = Slot::queued(gd.cell);
        }
        GoodsQueue {
            queue,
            cells_full,
            slots,
            // Like the assignments, the idle list grows to the most robots idle at once.
            idle: Vec::new(),
            woken: Vec::new(),
            // Assignments grow to the largest allocation event's (not the fleet's) count.
            decisions: Decisions { assign: Vec::new(), charge: Vec::new() },
            taken: Vec::new(),
            pending: false,
            alloc_due: true,
            lifelong,
        }
    }

    /// Phase 0 (lifelong): restocks and the orders of this step arrive; the orders whose
    /// cells can serve them join the queue, and make an allocation event due.
    pub(crate) fn arrive(&mut self, record: &mut Record) {
        let (t, events) = (record.tally.t, &mut record.events);
        let GoodsQueue { queue, cells_full, slots, lifelong, alloc_due, .. } = self;
        let Some(ll) = lifelong.as_mut() else { return };
        // Orders delivered before the oldest open one are done with.
        slots.drop_below(ll.first_open());
        ll.begin_step(
            t,
            cells_full,
            &mut |id, cell| {
                queue.push_back(Goods { id, cell });
                let k = id.index();
                slots.reach(k, Slot::EMPTY);
                slots[k] = Slot::queued(cell);
                *alloc_due = true;
            },
            &mut |e| {
                let (kind, cell) = match e {
                    StockEvent::Order(c) => (EventKind::Order, c),
                    StockEvent::Restock(c) => (EventKind::Restock, c),
                };
                events.push(Event::of_cell(t, kind, cell));
            },
        );
        record.tally.goods_total = ll.ordered();
    }

    /// A robot picked up the goods of `cell` at step `t`: the cell is empty (and restocks,
    /// in a lifelong run).
    pub(crate) fn picked(&mut self, t: u64, cell: u32) {
        self.cells_full[cell as usize] = false;
        if let Some(ll) = self.lifelong.as_mut() {
            ll.picked(t, cell);
        }
    }

    /// Goods put back by the threshold rule go to the front of the queue.
    pub fn put_back(&mut self, g: Goods) {
        self.queue.push_front(g);
        self.slots[g.id.index()].set(Slot::IN_QUEUE, true);
    }

    /// The cell of a goods item.
    pub fn cell_of(&self, goods: GoodsId) -> CellId {
        self.slots[goods.index()].cell()
    }

    /// Checks the decisions in order (assignments, then robots sent to charge) and marks the
    /// goods `handed`; the first problem comes back as the reason, with every mark undone.
    fn check(&mut self, robots: &Robots, energy_full: f64) -> std::result::Result<(), String> {
        let r = self.check_each(robots, energy_full);
        if r.is_err() {
            for a in &self.decisions.assign {
                if let Some(slot) = self.slots.get_mut(a.goods.index()) {
                    slot.set(Slot::HANDED, false);
                }
            }
        }
        r
    }

    fn check_each(&mut self, robots: &Robots, energy_full: f64) -> std::result::Result<(), String> {
        let n = robots.len();
        self.taken.clear();
        self.taken.resize(n, false);
        let idle_robot = |taken: &mut [bool], what: &str, robot: RobotId| -> std::result::Result<(), String> {
            let i = robot.index();
            if i >= n {
                return Err(format!("{what}: unknown robot id {robot}"));
            }
            if robots.state[i] != State::Idle {
                return Err(format!("{what}: robot {robot} is not idle (it is {})", robots.state[i].name()));
            }
            if taken[i] {
                return Err(format!("{what}: robot {robot} is given two decisions"));
            }
            taken[i] = true;
            Ok(())
        };
        for (k, a) in self.decisions.assign.iter().enumerate() {
            idle_robot(&mut self.taken, &format!("assignment {k}"), a.robot)?;
            let gi = a.goods.index();
            let Some(slot) = self.slots.get_mut(gi).filter(|s| s.in_queue()) else {
                return Err(format!("assignment {k}: unknown or taken goods id {}", a.goods));
            };
            if slot.handed() {
                return Err(format!("assignment {k}: goods {} handed out twice", a.goods));
            }
            slot.set(Slot::HANDED, true);
        }
        for (k, &robot) in self.decisions.charge.iter().enumerate() {
            idle_robot(&mut self.taken, &format!("charge {k}"), robot)?;
            let e = robots.energy[robot.index()];
            if crate::fleet::energy::is_full(e, energy_full) {
                return Err(format!("charge {k}: robot {robot} is full (energy {e})"));
            }
        }
        Ok(())
    }

    /// One pass over the queue removes every goods handed out, keeping the others' order.
    fn remove_handed(&mut self) {
        let slots = &mut self.slots;
        self.queue.retain(|g| {
            let slot = &mut slots[g.id.index()];
            let keep = !slot.handed();
            slot.set(Slot::IN_QUEUE, keep);
            keep
        });
    }
}

impl GoodsQueue {
    /// Phase 1 with the allocator: idle robots get goods or go to charge, or go home when no
    /// goods are open.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn hand_out(
        &mut self,
        allocator: &mut dyn Allocator,
        p: &Params,
        world: &World,
        robots: &mut Robots,
        stations: &mut Stations,
        record: &mut Record,
        people: Option<&People>,
    ) -> Result<()> {
        if self.begin_hand_out(robots) {
            let mut decisions = std::mem::take(&mut self.decisions);
            let view = self.view(robots, world, stations.homes.unload, p, record.tally.t).with_people(people);
            let asked = allocator.allocate(&view, &mut decisions);
            self.decisions = decisions;
            asked?;
        }
        self.finish_hand_out(p, world, robots, stations, record).map_err(|reason| Error::Allocator { strategy: allocator.name().to_string(), reason })
    }

    /// Phase 1, first half: at an allocation event, parked robots wake (lifelong runs, when
    /// orders are open) and the idle robots are listed. Returns whether the event needs
    /// decisions: idle robots and open goods. The decisions start empty.
    pub(crate) fn begin_hand_out(&mut self, robots: &mut Robots) -> bool {
        if !self.alloc_due {
            return false;
        }
        self.idle.clear();
        self.woken.clear();
        self.decisions.clear();
        // Lifelong: robots parked for want of orders go back to work when orders are open.
        let wake = self.lifelong.is_some() && !self.queue.is_empty();
        for (i, s) in robots.state.iter_mut().enumerate() {
            let woken = wake && *s == State::Parked;
            if woken {
                *s = State::Idle;
            }
            if *s == State::Idle {
                self.idle.push(RobotId(i as u32));
                self.woken.push(woken);
            }
        }
        if self.idle.is_empty() {
            self.alloc_due = false;
            return false;
        }
        self.queue.make_contiguous();
        !self.queue.is_empty()
    }

    /// What deciders see between the two halves of phase 1 (the queue is contiguous then),
    /// from the fields it reads (so that the allocator itself can be borrowed beside it).
    pub(crate) fn view<'a>(&'a self, robots: &'a Robots, world: &'a World, unload: NodeId, p: &Params, t: u64) -> AllocView<'a> {
        AllocView {
            step: t,
            idle: &self.idle,
            goods: self.queue.as_slices().0,
            robots,
            layout: &world.layout,
            graph: &world.graph,
            unload,
            energy_full: p.energy_full,
            threshold: p.threshold,
            consumption: p.consumption,
            speed: p.speed,
            people_x: &[],
            people_y: &[],
        }
    }

    /// Phase 1, second half: checks the decisions, then carries them out (assignments, then
    /// robots sent to charge, in the order given); idle robots left go home when no goods
    /// are open. A refused answer changes nothing and comes back as the reason.
    pub(crate) fn finish_hand_out(
        &mut self,
        p: &Params,
        world: &World,
        robots: &mut Robots,
        stations: &mut Stations,
        record: &mut Record,
    ) -> std::result::Result<(), String> {
        if !self.alloc_due {
            return Ok(());
        }
        if !self.decisions.is_empty() {
            self.check(robots, p.energy_full)?;
        }
        if !self.decisions.assign.is_empty() {
            self.remove_handed();
        }
        for k in 0..self.decisions.assign.len() {
            let Assignment { robot, goods } = self.decisions.assign[k];
            self.slots[goods.index()].set(Slot::HANDED, false);
            let cell = self.cell_of(goods);
            let i = robot.index();
            robots.goods[i] = goods.0;
            robots.cell[i] = cell.0;
            robots.state[i] = State::ToPickup;
            route::assign(robots, &world.graph, i, service_target(&world.layout, cell));
            record.event(EventKind::Assign, i, cell.0);
        }
        for k in 0..self.decisions.charge.len() {
            let i = self.decisions.charge[k].index();
            stations.send_to_charge(world, robots, i, record.tally.t);
        }
        if self.queue.is_empty() {
            let homes = &stations.homes;
            for k in 0..self.idle.len() {
                let i = self.idle[k].index();
                if robots.state[i] == State::Idle {
                    robots.state[i] = State::ToHome;
                    if self.woken[k] {
                        // Woken from its slot and left idle: it parked on arrival there, and
                        // nothing has moved it or changed its route since, so routing it home
                        // again would write what its fields hold (a route of length zero). At
                        // the large size that is a quarter of the fleet each step.
                        if cfg!(any(test, debug_assertions)) {
                            assert!(route_home_changes_nothing(world, homes, robots, i), "robot {i} woken away from its route home");
                        }
                        continue;
                    }
                    let home: Target = homes.target(robots, i);
                    route::assign(robots, &world.graph, i, home);
                }
            }
        }
        self.alloc_due = false;
        Ok(())
    }
}

/// Whether routing robot `i` home would leave its fields as they are (checked in debug
/// builds and in the crate's own tests, which run optimised).
fn route_home_changes_nothing(world: &World, homes: &Homes, r: &Robots, i: usize) -> bool {
    let p = route::plan(&world.graph, route::Place::of(r, i), homes.target(r, i));
    !p.moving
        && !r.routing[i]
        && (p.goal, p.has_final, p.final_x.to_bits(), p.final_y.to_bits(), p.final_v)
            == (r.goal[i], r.has_final[i], r.final_x[i].to_bits(), r.final_y[i].to_bits(), r.final_v[i])
}

#[cfg(test)]
mod tests {
    use crate::fleet::robot::State;
    use crate::input::scenario::Scenario;
    use crate::rules::paper::Paper;

    #[test]
    fn parked_robots_woken_and_left_idle_stay_on_their_route_home() {
        // The small size: orders trickle in, so parked robots are woken and most are left
        // idle again. Each time, the crate's own tests check that routing it home would
        // change nothing (`route_home_changes_nothing`); here, that it happened often. A
        // woken robot parks again within the step, having spent one step's energy.
        let s = Scenario::from_toml(include_str!("../../../../../benchmarks/sizes/small.toml"), "small.toml").unwrap();
        let mut sim = Paper::new(&s).unwrap();
        let mut woken = 0;
        for _ in 0..3000 {
            let before: Vec<(State, f64)> = sim.robots.state.iter().copied().zip(sim.robots.energy.iter().copied()).collect();
            sim.step().unwrap();
            let r = &sim.robots;
            woken += before.iter().enumerate().filter(|&(i, &(st, e))| st == State::Parked && r.state[i] == State::Parked && r.energy[i] < e).count();
        }
        assert!(woken > 1000, "{woken} woken and parked again");
        assert!(sim.record.tally.delivered > 0);
    }
}
