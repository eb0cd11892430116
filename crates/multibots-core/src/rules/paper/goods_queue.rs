//! The goods queue and phase 1, the hand-out (spec section 4, phase 1).
//!
//! Goods wait in a queue, front first. At an allocation event (robots became idle, or goods
//! joined the queue) the allocator sees the idle robots and the queue and answers with
//! [`Decisions`]: assignments, and robots to send to charge now. The engine checks every
//! decision before it carries any out, so a strategy can never corrupt the run. Idle robots
//! left without goods go home to park when the queue is empty (in lifelong runs, parked robots
//! wake when orders are open).
//!
//! Phase 1 comes in two halves, [`Paper::begin_hand_out`] (who is idle, and whether decisions
//! are needed) and [`Paper::finish_hand_out`] (check and carry out); the allocator answers in
//! between, or, paused at a decision point, a caller outside the engine does
//! (`decision_point.rs`).
//!
//! Goods put back by the threshold rule return to the front of the queue.

use crate::alloc::{AllocView, Assignment, Decisions, Goods};
use crate::error::{Error, Result};
use crate::fleet::robot::{Robots, State, Target};
use crate::fleet::route::service_target;
use crate::ids::{CellId, GoodsId, NodeId, RobotId};
use crate::input::scenario::Orders;
use crate::record::events::{Event, EventKind};
use crate::rules::paper::lifelong::{Lifelong, OrderWindow, StockEvent};
use crate::rules::paper::{Paper, Params};
use crate::world::World;
use std::collections::VecDeque;

/// Goods not yet taken, and which cells hold goods.
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
    pub fn new(cell_count: usize, task_cells: &[u32], orders: Option<&Orders>, csv: Vec<(u64, u32)>) -> (GoodsQueue, Option<Lifelong>) {
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
        let gq = GoodsQueue {
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
        };
        (gq, lifelong)
    }

    /// Phase 0 of a lifelong run: restocks and the orders of step `t` arrive; the orders
    /// whose cells can serve them join the queue. Returns whether any did.
    pub fn take_orders(&mut self, ll: &mut Lifelong, t: u64, events: &mut Vec<Event>) -> bool {
        let GoodsQueue { queue, cells_full, slots, .. } = self;
        // Orders delivered before the oldest open one are done with.
        slots.drop_below(ll.first_open());
        let mut grew = false;
        ll.begin_step(
            t,
            cells_full,
            &mut |id, cell| {
                queue.push_back(Goods { id, cell });
                let k = id.index();
                slots.reach(k, Slot::EMPTY);
                slots[k] = Slot::queued(cell);
                grew = true;
            },
            &mut |e| {
                let (kind, cell) = match e {
                    StockEvent::Order(c) => (EventKind::Order, c),
                    StockEvent::Restock(c) => (EventKind::Restock, c),
                };
                events.push(Event::of_cell(t, kind, cell));
            },
        );
        grew
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

impl Paper {
    /// Phase 0 (lifelong): restocks and arrivals of this step join the queue.
    pub(super) fn orders(&mut self) {
        let Some(ll) = self.lifelong.as_mut() else { return };
        if self.goods.take_orders(ll, self.tally.t, &mut self.events) {
            self.alloc_due = true;
        }
        self.tally.goods_total = ll.ordered();
    }

    /// Phase 1 with the allocator: idle robots get goods or go to charge, or go home when no
    /// goods are open.
    pub(crate) fn hand_out(&mut self) -> Result<()> {
        if self.begin_hand_out() {
            let mut decisions = std::mem::take(&mut self.goods.decisions);
            let view = view_of(&self.goods, &self.robots, &self.world, self.homes.unload, &self.p, self.tally.t).with_people(self.people.as_deref());
            let asked = self.allocator.allocate(&view, &mut decisions);
            self.goods.decisions = decisions;
            asked?;
        }
        self.finish_hand_out().map_err(|reason| Error::Allocator { strategy: self.allocator.name().to_string(), reason })
    }

    /// Phase 1, first half: at an allocation event, parked robots wake (lifelong runs, when
    /// orders are open) and the idle robots are listed. Returns whether the event needs
    /// decisions: idle robots and open goods. The decisions start empty.
    pub(crate) fn begin_hand_out(&mut self) -> bool {
        if !self.alloc_due {
            return false;
        }
        let gq = &mut self.goods;
        gq.idle.clear();
        gq.woken.clear();
        gq.decisions.clear();
        // Lifelong: robots parked for want of orders go back to work when orders are open.
        let wake = self.lifelong.is_some() && !gq.queue.is_empty();
        for (i, s) in self.robots.state.iter_mut().enumerate() {
            let woken = wake && *s == State::Parked;
            if woken {
                *s = State::Idle;
            }
            if *s == State::Idle {
                gq.idle.push(RobotId(i as u32));
                gq.woken.push(woken);
            }
        }
        if gq.idle.is_empty() {
            self.alloc_due = false;
            return false;
        }
        gq.queue.make_contiguous();
        !gq.queue.is_empty()
    }

    /// What deciders see between the two halves of phase 1 (the queue is contiguous then).
    pub(crate) fn pending_view_unchecked(&self) -> AllocView<'_> {
        view_of(&self.goods, &self.robots, &self.world, self.homes.unload, &self.p, self.tally.t).with_people(self.people.as_deref())
    }

    /// Phase 1, second half: checks the decisions, then carries them out (assignments, then
    /// robots sent to charge, in the order given); idle robots left go home when no goods
    /// are open. A refused answer changes nothing and comes back as the reason.
    pub(crate) fn finish_hand_out(&mut self) -> std::result::Result<(), String> {
        if !self.alloc_due {
            return Ok(());
        }
        let gq = &mut self.goods;
        if !gq.decisions.is_empty() {
            gq.check(&self.robots, self.p.energy_full)?;
        }
        if !gq.decisions.assign.is_empty() {
            gq.remove_handed();
        }
        for k in 0..self.goods.decisions.assign.len() {
            let Assignment { robot, goods } = self.goods.decisions.assign[k];
            self.goods.slots[goods.index()].set(Slot::HANDED, false);
            let cell = self.goods.cell_of(goods);
            let i = robot.index();
            let r = &mut self.robots;
            r.goods[i] = goods.0;
            r.cell[i] = cell.0;
            r.state[i] = State::ToPickup;
            let target = service_target(&self.world.layout, cell);
            self.route(i, target);
            self.event(EventKind::Assign, i, cell.0);
        }
        for k in 0..self.goods.decisions.charge.len() {
            let i = self.goods.decisions.charge[k].index();
            self.send_to_charge(i);
        }
        if self.goods.queue.is_empty() {
            for k in 0..self.goods.idle.len() {
                let i = self.goods.idle[k].index();
                if self.robots.state[i] == State::Idle {
                    self.robots.state[i] = State::ToHome;
                    if self.goods.woken[k] {
                        // Woken from its slot and left idle: it parked on arrival there, and
                        // nothing has moved it or changed its route since, so routing it home
                        // again would write what its fields hold (a route of length zero). At
                        // the large size that is a quarter of the fleet each step.
                        if cfg!(any(test, debug_assertions)) {
                            assert!(self.route_home_changes_nothing(i), "robot {i} woken away from its route home");
                        }
                        continue;
                    }
                    let home: Target = self.homes.target(&self.robots, i);
                    self.route(i, home);
                }
            }
        }
        self.alloc_due = false;
        Ok(())
    }
}

impl Paper {
    /// Whether routing robot `i` home would leave its fields as they are (checked in debug
    /// builds and in the crate's own tests, which run optimised).
    fn route_home_changes_nothing(&self, i: usize) -> bool {
        let r = &self.robots;
        let p = crate::fleet::route::plan(&self.world.graph, crate::fleet::route::Place::of(r, i), self.homes.target(r, i));
        !p.moving
            && !r.routing[i]
            && (p.goal, p.has_final, p.final_x.to_bits(), p.final_y.to_bits(), p.final_v)
                == (r.goal[i], r.has_final[i], r.final_x[i].to_bits(), r.final_y[i].to_bits(), r.final_v[i])
    }
}

/// The allocator's view of phase 1, from the fields it reads (so that the allocator itself
/// can be borrowed beside it).
fn view_of<'a>(gq: &'a GoodsQueue, robots: &'a Robots, world: &'a World, unload: NodeId, p: &Params, t: u64) -> AllocView<'a> {
    AllocView {
        step: t,
        idle: &gq.idle,
        goods: gq.queue.as_slices().0,
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
        assert!(sim.tally.delivered > 0);
    }
}
