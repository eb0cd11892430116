//! The goods queue and phase 1, the hand-out (spec section 4, phase 1).
//!
//! Goods wait in a queue, front first. At an allocation event (robots became idle, or goods
//! joined the queue) the allocator sees the idle robots and the queue and answers with
//! assignments; the engine checks every assignment before it carries any out, so a strategy
//! can never corrupt the run. Idle robots left without goods go home to park when the queue
//! is empty (in lifelong runs, parked robots wake when orders are open).
//!
//! Goods put back by the threshold rule return to the front of the queue.

use crate::alloc::{service_target, AllocView, Assignment, Goods};
use crate::error::{Error, Result};
use crate::events::{Event, EventKind};
use crate::ids::{CellId, GoodsId, RobotId, NONE};
use crate::lifelong::{Lifelong, StockEvent};
use crate::robot::{Robots, State, Target};
use crate::scenario::Orders;
use crate::sim::Paper;
use std::collections::VecDeque;

/// Goods not yet taken, and which cells hold goods.
#[derive(Clone, Debug)]
pub(crate) struct GoodsQueue {
    /// Goods not yet taken, front first.
    pub queue: VecDeque<Goods>,
    /// Which cells hold goods.
    pub cells_full: Vec<bool>,
    /// Indexed by goods id: whether the goods are in the queue, and whether the allocator
    /// handed them out in the current call. They make checking and removing assignments
    /// O(1) per assignment instead of a scan of the queue.
    in_queue: Vec<bool>,
    handed: Vec<bool>,
    /// The cell of every goods item, by goods id.
    cells: Vec<CellId>,
    /// Reused by every allocation event.
    pub(crate) idle: Vec<RobotId>,
    pub(crate) assignments: Vec<Assignment>,
    taken: Vec<bool>,
}

impl GoodsQueue {
    /// The queue at the start of a run: the task list in order, or, with lifelong orders, a
    /// stocked warehouse whose task list arrives as the first orders.
    pub fn new(cell_count: usize, task_cells: &[u32], orders: Option<&Orders>, csv: Vec<(u64, u32)>, robots: usize) -> (GoodsQueue, Option<Lifelong>) {
        let mut cells_full = vec![false; cell_count];
        let mut queue: VecDeque<Goods> = VecDeque::with_capacity(cell_count.max(task_cells.len()));
        let mut lifelong = None;
        if let Some(o) = orders {
            cells_full.fill(true);
            let mut ll = Lifelong::new(o, cell_count, csv, task_cells.len());
            ll.initial(task_cells, &cells_full, &mut |id, cell| queue.push_back(Goods { id, cell }));
            lifelong = Some(ll);
        } else {
            queue.extend(task_cells.iter().enumerate().map(|(k, &c)| {
                cells_full[c as usize] = true;
                Goods { id: GoodsId(k as u32), cell: CellId(c) }
            }));
        }
        // Room for every order the run expects, so that the step loop does not allocate.
        let cap = lifelong.as_ref().map_or(queue.len(), |l: &Lifelong| l.arrival.capacity());
        let len = lifelong.as_ref().map_or(queue.len(), |l: &Lifelong| l.arrival.len());
        let mut in_queue = Vec::with_capacity(cap);
        in_queue.resize(len, false);
        let mut handed = Vec::with_capacity(cap);
        handed.resize(len, false);
        let mut cells = Vec::with_capacity(cap);
        cells.resize(len, CellId(NONE));
        for gd in &queue {
            in_queue[gd.id.index()] = true;
            cells[gd.id.index()] = gd.cell;
        }
        let gq = GoodsQueue {
            queue,
            cells_full,
            in_queue,
            handed,
            cells,
            idle: Vec::with_capacity(robots),
            assignments: Vec::with_capacity(robots),
            taken: Vec::new(),
        };
        (gq, lifelong)
    }

    /// Phase 0 of a lifelong run: restocks and the orders of step `t` arrive; the orders
    /// whose cells can serve them join the queue. Returns whether any did.
    pub fn take_orders(&mut self, ll: &mut Lifelong, t: u64, events: &mut Vec<Event>) -> bool {
        let GoodsQueue { queue, cells_full, in_queue, handed, cells, .. } = self;
        let mut grew = false;
        ll.begin_step(
            t,
            cells_full,
            &mut |id, cell| {
                queue.push_back(Goods { id, cell });
                let k = id.index();
                if in_queue.len() <= k {
                    // Within the capacity reserved for the expected orders: no allocation.
                    in_queue.resize(k + 1, false);
                    handed.resize(k + 1, false);
                    cells.resize(k + 1, CellId(NONE));
                }
                in_queue[k] = true;
                cells[k] = cell;
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
        self.in_queue[g.id.index()] = true;
    }

    /// The cell of a goods item.
    pub fn cell_of(&self, goods: GoodsId) -> CellId {
        self.cells[goods.index()]
    }

    /// Checks the assignments in order and marks their goods `handed`; the first problem
    /// comes back as the reason, with every mark undone.
    fn check(&mut self, robots: &Robots) -> std::result::Result<(), String> {
        let r = self.check_each(robots);
        if r.is_err() {
            for a in &self.assignments {
                if let Some(h) = self.handed.get_mut(a.goods.index()) {
                    *h = false;
                }
            }
        }
        r
    }

    fn check_each(&mut self, robots: &Robots) -> std::result::Result<(), String> {
        let n = robots.len();
        self.taken.clear();
        self.taken.resize(n, false);
        for (k, a) in self.assignments.iter().enumerate() {
            let i = a.robot.index();
            if i >= n {
                return Err(format!("assignment {k}: unknown robot id {}", a.robot));
            }
            if robots.state[i] != State::Idle {
                return Err(format!("assignment {k}: robot {} is not idle (it is {})", a.robot, robots.state[i].name()));
            }
            if self.taken[i] {
                return Err(format!("assignment {k}: robot {} is given goods twice", a.robot));
            }
            self.taken[i] = true;
            let gi = a.goods.index();
            if !self.in_queue.get(gi).copied().unwrap_or(false) {
                return Err(format!("assignment {k}: unknown or taken goods id {}", a.goods));
            }
            if self.handed[gi] {
                return Err(format!("assignment {k}: goods {} handed out twice", a.goods));
            }
            self.handed[gi] = true;
        }
        Ok(())
    }

    /// One pass over the queue removes every goods handed out, keeping the others' order.
    fn remove_handed(&mut self) {
        let in_queue = &mut self.in_queue;
        let handed = &self.handed;
        self.queue.retain(|g| {
            let keep = !handed[g.id.index()];
            in_queue[g.id.index()] = keep;
            keep
        });
    }
}

impl Paper {
    /// Phase 1: idle robots get goods from the allocator, or go home when none are open.
    pub(crate) fn hand_out(&mut self) -> Result<()> {
        if !self.alloc_due {
            return Ok(());
        }
        let gq = &mut self.goods;
        gq.idle.clear();
        // Lifelong: robots parked for want of orders go back to work when orders are open.
        let wake = self.lifelong.is_some() && !gq.queue.is_empty();
        for (i, s) in self.robots.state.iter_mut().enumerate() {
            if wake && *s == State::Parked {
                *s = State::Idle;
            }
            if *s == State::Idle {
                gq.idle.push(RobotId(i as u32));
            }
        }
        if gq.idle.is_empty() {
            self.alloc_due = false;
            return Ok(());
        }
        gq.assignments.clear();
        if !gq.queue.is_empty() {
            let view = AllocView {
                step: self.tally.t,
                idle: &gq.idle,
                goods: gq.queue.make_contiguous(),
                robots: &self.robots,
                layout: &self.world.layout,
                graph: &self.world.graph,
                unload: self.homes.unload,
                energy_full: self.p.energy_full,
                threshold: self.p.threshold,
                consumption: self.p.consumption,
                speed: self.p.speed,
            };
            self.allocator.allocate(&view, &mut gq.assignments)?;
            gq.check(&self.robots).map_err(|reason| Error::Allocator { strategy: self.allocator.name().to_string(), reason })?;
        }
        if !gq.assignments.is_empty() {
            gq.remove_handed();
        }
        for k in 0..self.goods.assignments.len() {
            let Assignment { robot, goods } = self.goods.assignments[k];
            self.goods.handed[goods.index()] = false;
            let cell = self.goods.cell_of(goods);
            let i = robot.index();
            let edge = self.world.layout.cells[cell.index()].edge;
            let r = &mut self.robots;
            r.goods[i] = goods.0;
            r.cell[i] = cell.0;
            r.task_u[i] = edge.0 .0;
            r.task_v[i] = edge.1 .0;
            r.state[i] = State::ToPickup;
            let target = service_target(&self.world.layout, cell);
            self.route(i, target);
            self.event(EventKind::Assign, i, cell.0);
        }
        if self.goods.queue.is_empty() {
            for k in 0..self.goods.idle.len() {
                let i = self.goods.idle[k].index();
                if self.robots.state[i] == State::Idle {
                    self.robots.state[i] = State::ToHome;
                    let home: Target = self.homes.target(&self.robots, i);
                    self.route(i, home);
                }
            }
        }
        self.alloc_due = false;
        Ok(())
    }
}
