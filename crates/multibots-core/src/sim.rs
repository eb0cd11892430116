//! One step of the paper model (spec section 4), phase by phase.

use crate::alloc::{self, service_target, AllocView, Allocator, Assignment, Goods};
use crate::collision::{bearing, Collisions};
use crate::energy;
use crate::error::{Error, Result};
use crate::graph::{self, HighwayGraph};
use crate::ids::{CellId, GoodsId, NodeId, RobotId, NONE};
use crate::layout::{Layout, NodeKind};
use crate::lifelong::{self, Lifelong, StockEvent};
use crate::metrics::{LifelongStats, Outcome, RobotStats, RunResult};
use crate::robot::{Robots, State, Target};
use crate::route::{self, Place};
use crate::scenario::{ChargerUse, ChargingPolicy, Placement, Scenario};
use std::collections::VecDeque;
use std::sync::Arc;

/// A layout with its graph and routing table, shared by every run on it.
#[derive(Debug)]
pub struct World {
    pub layout: Layout,
    pub graph: HighwayGraph,
}

impl World {
    /// Builds and validates the graph of a layout.
    pub fn new(layout: Layout) -> Result<Arc<World>> {
        let graph = HighwayGraph::new(&layout);
        graph::validate(&layout, &graph)?;
        Ok(Arc::new(World { layout, graph }))
    }
}

/// What happened during a step, for replays and live viewers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum EventKind {
    Assign = 1,
    PutBack = 2,
    Pickup = 3,
    Deliver = 4,
    Wait = 5,
    Charge = 6,
    Strand = 7,
    Restock = 8,
    Order = 9,
}

/// An event: in step `step`, `robot` did `kind` (with `cell` where it applies, else `NONE`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Event {
    pub step: u64,
    pub kind: EventKind,
    pub robot: u32,
    pub cell: u32,
}

/// The model's numbers, taken from a validated scenario.
#[derive(Clone, Copy, Debug)]
struct Params {
    speed: f64,
    energy_full: f64,
    threshold: f64,
    consumption: f64,
    charge_rate: f64,
    loading: u32,
    unloading: u32,
    margin: f64,
    angle: f64,
    step_limit: u64,
    unload: NodeId,
    /// Opportunistic charging: idle robots below this level go to charge.
    opportunistic: Option<f64>,
}

/// A run in progress.
pub struct Simulation {
    world: Arc<World>,
    p: Params,
    robots: Robots,
    queue: VecDeque<Goods>,
    cells_full: Vec<bool>,
    goods_total: u64,
    delivered: u64,
    t: u64,
    s: u64,
    c: u64,
    outcome: Option<Outcome>,
    allocator: Box<dyn Allocator>,
    /// An allocation event is due: robots became idle or goods joined the queue.
    alloc_due: bool,
    /// Set when a step failed part-way: the run cannot go on.
    failure: Option<String>,
    collisions: Collisions,
    wants: Vec<bool>,
    alpha: Vec<f64>,
    stats: RobotStats,
    events: Vec<Event>,
    idle_buf: Vec<RobotId>,
    assign_buf: Vec<Assignment>,
    taken_buf: Vec<bool>,
    /// Indexed by goods id: whether the goods are in the queue, and whether the allocator
    /// handed them out in the current call. They make checking and removing assignments
    /// O(1) per assignment instead of a scan of the queue.
    in_queue: Vec<bool>,
    handed: Vec<bool>,
    /// The cell of every goods item, by goods id.
    goods_cells: Vec<CellId>,
    /// The unloading zone of each cell's goods (all `p.unload`, except `unload = "nearest"`).
    unload_of_cell: Vec<NodeId>,
    /// Spread placement: each robot's parking slot, its home (empty in the paper model).
    park: Vec<Target>,
    /// Lifelong orders and restocking (`None` in the paper model).
    lifelong: Option<Lifelong>,
    /// Shared chargers (extension): which robot holds each charger, and the robots waiting
    /// for one, first come first served.
    shared: bool,
    charger_slot: Vec<u32>,
    claim: Vec<u32>,
    charge_queue: VecDeque<u32>,
    /// `to_charger[k * nodes + u]`: path length from node `u` to charger `k`, for O(1)
    /// nearest-charger choices inside the step loop (shared chargers only).
    to_charger: Vec<f64>,
}

/// Route length from a place to a node whose distances `row` (from every node) are known:
/// the same route as [`route::length`], without walking the path.
fn length_by_row(g: &HighwayGraph, from: Place, target: NodeId, row: &[f64]) -> f64 {
    let p = route::plan(g, from, Target::Node(target));
    if !p.moving {
        return 0.0;
    }
    route::dist(from.x, from.y, p.wp_x, p.wp_y) + row[p.wp_node as usize]
}

/// Parking slots of spread placement: points strictly inside the highway edges, in edge
/// order, `spacing` px or more apart and from either end node, so that robots standing on
/// them neither block each other nor stand on a crossing.
fn parking_slots(layout: &Layout, spacing: f64) -> Vec<Target> {
    let mut slots = Vec::new();
    for &(u, v) in &layout.edges {
        let (ux, uy) = layout.pos(u);
        let (vx, vy) = layout.pos(v);
        let len = route::dist(ux, uy, vx, vy);
        let m = (len / spacing).floor() as usize;
        let m = m.saturating_sub(1);
        for k in 1..=m {
            let f = k as f64 / (m + 1) as f64;
            slots.push(Target::Point { u, v, x: ux + (vx - ux) * f, y: uy + (vy - uy) * f });
        }
    }
    slots
}

impl Simulation {
    /// A run of `scenario` with its named built-in allocator.
    pub fn new(scenario: &Scenario) -> Result<Simulation> {
        scenario.check_values()?;
        let world = World::new(scenario.resolve_layout()?)?;
        let allocator = alloc::built_in(scenario)?;
        Simulation::with_world(world, scenario, allocator)
    }

    /// A run of `scenario` with a given allocator (such as one written in Python).
    pub fn with_allocator(scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Simulation> {
        scenario.check_values()?;
        let world = World::new(scenario.resolve_layout()?)?;
        Simulation::with_world(world, scenario, allocator)
    }

    /// A run on an already built world, with any allocator.
    pub fn with_world(world: Arc<World>, scenario: &Scenario, allocator: Box<dyn Allocator>) -> Result<Simulation> {
        scenario.check_values()?;
        let layout = &world.layout;
        // `unload = "nearest"` (extension): each cell's goods go to the unloading zone nearest
        // its service point; allocators are told the first zone.
        let unload = if scenario.unload == "nearest" {
            layout.unloading[0]
        } else {
            layout.node_named(&scenario.unload).ok_or_else(|| Error::scenario("unload", format!("\"{}\"", scenario.unload), "unknown node"))?
        };
        if !layout.unloading.contains(&unload) {
            return Err(Error::scenario("unload", format!("\"{}\"", scenario.unload), "is not an unloading zone"));
        }
        let n = scenario.robots as usize;
        let spread = scenario.placement == Placement::Spread;
        let starts: Vec<NodeId> = match &scenario.starts {
            _ if spread => Vec::new(),
            Some(names) => {
                if names.len() != n {
                    return Err(Error::scenario("starts", format!("{names:?}"), format!("names {} start nodes for {} robots", names.len(), n)));
                }
                let mut v = Vec::with_capacity(n);
                for (i, name) in names.iter().enumerate() {
                    let node = layout.node_named(name).ok_or_else(|| Error::scenario(format!("starts[{i}]"), format!("\"{name}\""), "unknown node"))?;
                    if !layout.departure.contains(&node) {
                        return Err(Error::scenario(format!("starts[{i}]"), format!("\"{name}\""), "is not a departure zone"));
                    }
                    if v.contains(&node) {
                        return Err(Error::scenario(format!("starts[{i}]"), format!("\"{name}\""), "start nodes must be distinct"));
                    }
                    v.push(node);
                }
                v
            }
            None => {
                if n > layout.departure.len() {
                    return Err(Error::scenario("robots", n, format!("more robots than start nodes ({})", layout.departure.len())));
                }
                layout.departure[..n].to_vec()
            }
        };
        let cells = scenario.cells(layout)?;
        let r = &scenario.robot;
        let g = &world.graph;
        let mut robots = Robots::default();
        for (i, &start) in starts.iter().enumerate() {
            let home = layout.charger_at(start).ok_or_else(|| {
                Error::scenario(format!("starts[{i}]"), format!("\"{}\"", layout.nodes[start.index()].name), "has no charger to be the robot's home")
            })?;
            robots.push(home, layout.pos(home), home, r.radius, r.speed, r.energy_full);
        }
        let mut park = Vec::new();
        if spread {
            // Slots far enough apart that no two parked robots touch, even with the margin.
            let spacing = layout.cell_size.max(2.0 * (2.0 * r.radius + scenario.collision.margin));
            let slots = parking_slots(layout, spacing);
            let rows: Vec<Vec<f64>> = layout.chargers.iter().map(|&c| g.lengths_to(c)).collect();
            if n > slots.len() {
                return Err(Error::scenario("robots", n, format!("more robots than parking slots ({}) in this layout: generate a larger one", slots.len())));
            }
            for i in 0..n {
                // Evenly over the slot list, so every part of the warehouse gets robots.
                let slot = slots[i * slots.len() / n];
                let Target::Point { u, v, x, y } = slot else { unreachable!("slots are points") };
                let at = Place { x, y, at_node: NONE, edge_u: u.0, edge_v: v.0 };
                // Home charger: the nearest by route (ties: the first charger).
                let mut home = layout.chargers[0];
                let mut best = f64::INFINITY;
                for (k, &c) in layout.chargers.iter().enumerate() {
                    let d = length_by_row(g, at, c, &rows[k]);
                    if d < best {
                        best = d;
                        home = c;
                    }
                }
                robots.push(home, (x, y), home, r.radius, r.speed, r.energy_full);
                robots.at_node[i] = NONE;
                robots.edge_u[i] = u.0;
                robots.edge_v[i] = v.0;
                park.push(slot);
            }
        }
        let mut cells_full = vec![false; layout.cells.len()];
        let mut queue: VecDeque<Goods> = VecDeque::with_capacity(layout.cells.len().max(cells.len()));
        let mut lifelong = None;
        if let Some(o) = &scenario.orders {
            // A stocked warehouse: every cell holds goods at the start.
            cells_full.fill(true);
            let csv = match &o.csv {
                Some(path) => lifelong::read_csv(std::path::Path::new(path), layout.cells.len())?,
                None => Vec::new(),
            };
            let mut ll = Lifelong::new(o, layout.cells.len(), csv, cells.len());
            ll.initial(&cells, &cells_full, &mut |id, cell| queue.push_back(Goods { id, cell }));
            lifelong = Some(ll);
        } else {
            queue.extend(cells.iter().enumerate().map(|(k, &c)| {
                cells_full[c as usize] = true;
                Goods { id: GoodsId(k as u32), cell: CellId(c) }
            }));
        }
        let goods_cap = lifelong.as_ref().map_or(queue.len(), |l: &Lifelong| l.arrival.capacity());
        let mut in_queue = Vec::with_capacity(goods_cap);
        in_queue.resize(lifelong.as_ref().map_or(queue.len(), |l: &Lifelong| l.arrival.len()), false);
        for gd in &queue {
            in_queue[gd.id.index()] = true;
        }
        let mut handed = Vec::with_capacity(goods_cap);
        handed.resize(in_queue.len(), false);
        let mut goods_cells = Vec::with_capacity(goods_cap);
        goods_cells.resize(in_queue.len(), CellId(NONE));
        for gd in &queue {
            goods_cells[gd.id.index()] = gd.cell;
        }
        let unload_of_cell: Vec<NodeId> = if scenario.unload == "nearest" {
            let rows: Vec<Vec<f64>> = layout.unloading.iter().map(|&z| g.lengths_to(z)).collect();
            layout
                .cells
                .iter()
                .map(|c| {
                    let at = Place { x: c.service.0, y: c.service.1, at_node: NONE, edge_u: c.edge.0 .0, edge_v: c.edge.1 .0 };
                    let mut best = (f64::INFINITY, layout.unloading[0]);
                    for (k, &z) in layout.unloading.iter().enumerate() {
                        let d = length_by_row(g, at, z, &rows[k]);
                        if d < best.0 {
                            best = (d, z);
                        }
                    }
                    best.1
                })
                .collect()
        } else {
            vec![unload; layout.cells.len()]
        };
        let mut charger_slot = vec![NONE; layout.nodes.len()];
        for (k, &c) in layout.chargers.iter().enumerate() {
            charger_slot[c.index()] = k as u32;
        }
        let shared = scenario.charging.chargers == ChargerUse::Shared;
        let to_charger = if shared { layout.chargers.iter().flat_map(|&c| g.lengths_to(c)).collect() } else { Vec::new() };
        // Chargers stand outside the warehouse: the grid must cover every node.
        let mut b = layout.bounds;
        for node in &layout.nodes {
            b[0] = b[0].min(node.x);
            b[1] = b[1].min(node.y);
            b[2] = b[2].max(node.x);
            b[3] = b[3].max(node.y);
        }
        let reach = 2.0 * r.radius + scenario.collision.margin;
        let p = Params {
            speed: r.speed,
            energy_full: r.energy_full,
            threshold: r.threshold,
            consumption: r.consumption,
            charge_rate: r.charge_rate,
            loading: scenario.dwell.loading,
            unloading: scenario.dwell.unloading,
            margin: scenario.collision.margin,
            angle: scenario.collision.angle.to_radians(),
            step_limit: scenario.step_limit,
            unload,
            opportunistic: (scenario.charging.policy == ChargingPolicy::Opportunistic).then_some(scenario.charging.level),
        };
        Ok(Simulation {
            p,
            goods_total: queue.len() as u64,
            queue,
            cells_full,
            delivered: 0,
            t: 0,
            s: 0,
            c: 0,
            outcome: None,
            allocator,
            alloc_due: true,
            failure: None,
            collisions: Collisions::new(b, reach, n),
            wants: vec![false; n],
            alpha: vec![0.0; n],
            stats: RobotStats::new(n),
            events: Vec::new(),
            idle_buf: Vec::with_capacity(n),
            assign_buf: Vec::with_capacity(n),
            taken_buf: Vec::new(),
            in_queue,
            handed,
            goods_cells,
            unload_of_cell,
            park,
            lifelong,
            shared,
            charger_slot,
            claim: vec![NONE; layout.chargers.len()],
            charge_queue: VecDeque::with_capacity(n),
            to_charger,
            robots,
            world,
        })
    }

    /// Runs until the run completes or reaches the step limit.
    pub fn run(&mut self) -> Result<RunResult> {
        while self.outcome.is_none() {
            self.step()?;
        }
        Ok(self.result())
    }

    /// Runs one step (all eight phases). Does nothing once the run has ended.
    pub fn step(&mut self) -> Result<()> {
        if self.outcome.is_some() {
            return Ok(());
        }
        if let Some(failure) = &self.failure {
            // Phases after the allocator's error never ran: carrying on would skip them.
            return Err(Error::Allocator { strategy: self.allocator.name().to_string(), reason: format!("the run stopped at step {}: {failure}", self.t) });
        }
        self.t += 1;
        self.events.clear();
        if self.lifelong.is_some() {
            self.orders();
        }
        if let Err(e) = self.allocate() {
            self.failure = Some(e.to_string());
            return Err(e);
        }
        self.intend();
        self.block_and_move();
        self.transitions();
        self.end();
        Ok(())
    }

    fn event(&mut self, kind: EventKind, robot: usize, cell: u32) {
        self.events.push(Event { step: self.t, kind, robot: robot as u32, cell });
    }

    fn route(&mut self, i: usize, target: Target) {
        route::assign(&mut self.robots, &self.world.graph, i, target);
    }

    fn charger_of(&self, i: usize) -> NodeId {
        self.robots.home[i]
    }

    /// Phase 1: idle robots get goods from the allocator, or go home when none are open.
    fn allocate(&mut self) -> Result<()> {
        if !self.alloc_due {
            return Ok(());
        }
        self.idle_buf.clear();
        // Lifelong: robots parked for want of orders go back to work when orders are open.
        let wake = self.lifelong.is_some() && !self.queue.is_empty();
        for (i, s) in self.robots.state.iter_mut().enumerate() {
            if wake && *s == State::Parked {
                *s = State::Idle;
            }
            if *s == State::Idle {
                self.idle_buf.push(RobotId(i as u32));
            }
        }
        if self.idle_buf.is_empty() {
            self.alloc_due = false;
            return Ok(());
        }
        self.assign_buf.clear();
        if !self.queue.is_empty() {
            let view = AllocView {
                step: self.t,
                idle: &self.idle_buf,
                goods: self.queue.make_contiguous(),
                robots: &self.robots,
                layout: &self.world.layout,
                graph: &self.world.graph,
                unload: self.p.unload,
                energy_full: self.p.energy_full,
                threshold: self.p.threshold,
                consumption: self.p.consumption,
                speed: self.p.speed,
            };
            self.allocator.allocate(&view, &mut self.assign_buf)?;
            self.check_assignments()?;
        }
        if !self.assign_buf.is_empty() {
            // One pass over the queue removes every assigned goods, keeping the others' order.
            let in_queue = &mut self.in_queue;
            let handed = &self.handed;
            self.queue.retain(|g| {
                let keep = !handed[g.id.index()];
                in_queue[g.id.index()] = keep;
                keep
            });
        }
        for k in 0..self.assign_buf.len() {
            let Assignment { robot, goods } = self.assign_buf[k];
            self.handed[goods.index()] = false;
            let g = Goods { id: goods, cell: self.goods_cell(goods) };
            let i = robot.index();
            let cell = &self.world.layout.cells[g.cell.index()];
            self.robots.goods[i] = g.id.0;
            self.robots.cell[i] = g.cell.0;
            self.robots.task_u[i] = cell.edge.0 .0;
            self.robots.task_v[i] = cell.edge.1 .0;
            self.robots.state[i] = State::ToPickup;
            let target = service_target(&self.world.layout, g.cell);
            self.route(i, target);
            self.event(EventKind::Assign, i, g.cell.0);
        }
        if self.queue.is_empty() {
            for k in 0..self.idle_buf.len() {
                let i = self.idle_buf[k].index();
                if self.robots.state[i] == State::Idle {
                    self.robots.state[i] = State::ToHome;
                    let home = self.home_target(i);
                    self.route(i, home);
                }
            }
        }
        self.alloc_due = false;
        Ok(())
    }

    fn check_assignments(&mut self) -> Result<()> {
        if let Err(reason) = self.check_each() {
            self.clear_handed(self.assign_buf.len());
            return Err(Error::Allocator { strategy: self.allocator.name().to_string(), reason });
        }
        Ok(())
    }

    /// Checks the assignments in order and marks their goods `handed`; the first problem
    /// comes back as the error's reason.
    fn check_each(&mut self) -> std::result::Result<(), String> {
        let n = self.robots.len();
        self.taken_buf.clear();
        self.taken_buf.resize(n, false);
        for (k, a) in self.assign_buf.iter().enumerate() {
            let i = a.robot.index();
            if i >= n {
                return Err(format!("assignment {k}: unknown robot id {}", a.robot));
            }
            if self.robots.state[i] != State::Idle {
                return Err(format!("assignment {k}: robot {} is not idle (it is {})", a.robot, self.robots.state[i].name()));
            }
            if self.taken_buf[i] {
                return Err(format!("assignment {k}: robot {} is given goods twice", a.robot));
            }
            self.taken_buf[i] = true;
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

    /// Undoes the `handed` marks of the first `k` assignments (after a refused allocation).
    fn clear_handed(&mut self, k: usize) {
        for a in &self.assign_buf[..k] {
            if let Some(h) = self.handed.get_mut(a.goods.index()) {
                *h = false;
            }
        }
    }

    /// The cell of a goods item.
    fn goods_cell(&self, goods: GoodsId) -> CellId {
        self.goods_cells[goods.index()]
    }

    /// Where robot `i` parks: its parking slot (spread placement) or its home charger.
    fn home_target(&self, i: usize) -> Target {
        self.park.get(i).copied().unwrap_or(Target::Node(self.robots.home[i]))
    }

    /// Whether robot `i` stands at its home (phase 8).
    fn at_home(&self, i: usize) -> bool {
        match self.park.get(i) {
            Some(&Target::Point { x, y, .. }) => self.robots.at_node[i] == NONE && self.robots.x[i] == x && self.robots.y[i] == y,
            _ => self.robots.at_node[i] == self.robots.home[i].0,
        }
    }

    /// Lifelong phase 0: restocks and arrivals of this step join the queue.
    fn orders(&mut self) {
        let t = self.t;
        let Some(ll) = self.lifelong.as_mut() else { return };
        let queue = &mut self.queue;
        let in_queue = &mut self.in_queue;
        let handed = &mut self.handed;
        let goods_cells = &mut self.goods_cells;
        let events = &mut self.events;
        let mut grew = false;
        ll.begin_step(
            t,
            &mut self.cells_full,
            &mut |id, cell| {
                queue.push_back(Goods { id, cell });
                let k = id.index();
                if in_queue.len() <= k {
                    // Within the capacity reserved for the expected orders: no allocation.
                    in_queue.resize(k + 1, false);
                    handed.resize(k + 1, false);
                    goods_cells.resize(k + 1, CellId(NONE));
                }
                in_queue[k] = true;
                goods_cells[k] = cell;
                grew = true;
            },
            &mut |e| {
                let (kind, cell) = match e {
                    StockEvent::Order(c) => (EventKind::Order, c),
                    StockEvent::Restock(c) => (EventKind::Restock, c),
                };
                events.push(Event { step: t, kind, robot: NONE, cell });
            },
        );
        self.goods_total = ll.ordered();
        if grew {
            self.alloc_due = true;
        }
    }

    /// Phase 2: who wants to move, and where each is heading.
    fn intend(&mut self) {
        let n = self.robots.len();
        let r = &mut self.robots;
        // Slices of exactly `n` (here and in the phases below): indexing by `i < n` needs
        // no bounds checks.
        let (routing, state, x, y, wp_x, wp_y) = (&r.routing[..n], &r.state[..n], &r.x[..n], &r.y[..n], &r.wp_x[..n], &r.wp_y[..n]);
        let (wants, alpha, head) = (&mut self.wants[..n], &mut self.alpha[..n], &mut r.heading[..n]);
        for i in 0..n {
            let w = routing[i] && state[i].travels();
            wants[i] = w;
            if w {
                let a = bearing(wp_x[i] - x[i], wp_y[i] - y[i]);
                alpha[i] = a;
                head[i] = a;
            }
        }
        if !self.park.is_empty() {
            // Spread placement: parked robots and robots waiting for a charger stand in a
            // bay beside the aisle, out of the traffic (docs/model.md section 7).
            self.collisions.bay.resize(n, false);
            for (b, s) in self.collisions.bay.iter_mut().zip(state) {
                *b = matches!(s, State::Parked | State::WaitCharger);
            }
        }
    }

    /// Phases 3 to 6: collision waiting and the count S, then travel, dwell counters,
    /// charging and consumption. After the collision decision every robot's phases 3 to 6
    /// touch only that robot, so one pass does them all, robot by robot.
    fn block_and_move(&mut self) {
        let n = self.robots.len();
        let p = &self.p;
        let r = &self.robots;
        self.collisions.resolve(&r.x, &r.y, &r.radius, &self.wants, &self.alpha, p.margin, p.angle);
        let g = &self.world.graph;
        let (wants, waits) = (&self.wants[..n], &self.collisions.waits[..n]);
        let st = &mut self.stats;
        let (wait_steps, collisions, distance, energy_used) = (&mut st.wait_steps[..n], &mut st.collisions[..n], &mut st.distance[..n], &mut st.energy_used[..n]);
        for i in 0..n {
            // Phase 3: a wait that begins is a collision.
            let w = waits[i];
            if w {
                wait_steps[i] += 1;
                if !self.robots.waited[i] {
                    self.s += 1;
                    collisions[i] += 1;
                    self.events.push(Event { step: self.t, kind: EventKind::Wait, robot: i as u32, cell: NONE });
                }
            }
            let r = &mut self.robots;
            r.waited[i] = w;
            // Phase 4: robots that may move travel `speed` px along their routes.
            if wants[i] && !w {
                let speed = r.speed[i];
                distance[i] += route::advance(r, g, i, speed);
            }
            // Phases 5 and 6.
            let state = r.state[i];
            match state {
                State::Loading | State::Unloading => r.dwell[i] += 1,
                State::Charging => r.energy[i] = energy::charge(r.energy[i], p.charge_rate, p.energy_full),
                _ => {}
            }
            if !matches!(state, State::Charging | State::Parked | State::Stranded) {
                let e = energy::consume(r.energy[i], p.consumption);
                energy_used[i] += r.energy[i] - e;
                r.energy[i] = e;
            }
        }
    }

    /// Whether robot `i` is strictly inside the edge of the service point it is fetching from.
    fn inside_service_edge(&self, i: usize) -> bool {
        let r = &self.robots;
        r.at_node[i] == NONE && r.edge_u[i] == r.task_u[i] && r.edge_v[i] == r.task_v[i]
    }

    /// Phase 7: at most one state transition per robot, then the threshold and stranding rules.
    fn transitions(&mut self) {
        let p = self.p;
        for i in 0..self.robots.len() {
            let r = &self.robots;
            let (state, e) = (r.state[i], r.energy[i]);
            // Most robots have nothing due: under way, dwelling or charging, with energy to
            // spare. Only the others take the full rules below.
            let due = match state {
                State::ToPickup | State::ToDrop | State::ToCharger | State::ToHome => !r.routing[i],
                State::Loading => r.dwell[i] >= p.loading,
                State::Unloading => r.dwell[i] >= p.unloading,
                State::Charging => energy::is_full(e, p.energy_full),
                _ => false,
            } || energy::below(e, p.threshold)
                || energy::exhausted(e)
                || p.opportunistic.is_some_and(|level| state == State::Idle && energy::below(e, level));
            if due {
                self.transition(i);
            }
            self.stats.state_steps[i][self.robots.state[i] as usize] += 1;
        }
    }

    /// Phase 7 for robot `i`.
    fn transition(&mut self, i: usize) {
        {
            let state = self.robots.state[i];
            let arrived = !self.robots.routing[i];
            match state {
                State::ToPickup if arrived => {
                    self.robots.state[i] = State::Loading;
                    self.robots.dwell[i] = 0;
                }
                State::ToDrop if arrived => {
                    self.robots.state[i] = State::Unloading;
                    self.robots.dwell[i] = 0;
                }
                State::ToCharger if arrived => {
                    self.robots.state[i] = State::Charging;
                    self.c += 1;
                    self.stats.charges[i] += 1;
                    self.event(EventKind::Charge, i, NONE);
                }
                State::ToHome if arrived => self.robots.state[i] = State::Parked,
                State::Loading if self.robots.dwell[i] >= self.p.loading => {
                    let cell = self.robots.cell[i];
                    self.cells_full[cell as usize] = false;
                    if let Some(ll) = self.lifelong.as_mut() {
                        ll.picked(self.t, cell);
                    }
                    self.robots.carrying[i] = true;
                    self.robots.state[i] = State::ToDrop;
                    self.event(EventKind::Pickup, i, cell);
                    self.route(i, Target::Node(self.unload_of_cell[cell as usize]));
                }
                State::Unloading if self.robots.dwell[i] >= self.p.unloading => {
                    let cell = self.robots.cell[i];
                    self.delivered += 1;
                    self.stats.delivered[i] += 1;
                    if let Some(ll) = self.lifelong.as_mut() {
                        ll.delivered(self.t, self.robots.goods[i]);
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
                State::Charging if energy::is_full(self.robots.energy[i], self.p.energy_full) => {
                    self.robots.state[i] = State::Idle;
                    self.alloc_due = true;
                    if self.shared {
                        self.release_charger(self.robots.charger[i]);
                    }
                }
                _ => {}
            }
            if energy::below(self.robots.energy[i], self.p.threshold) {
                match self.robots.state[i] {
                    State::Idle => self.send_to_charge(i),
                    State::ToPickup if !self.inside_service_edge(i) => {
                        let g = Goods { id: GoodsId(self.robots.goods[i]), cell: CellId(self.robots.cell[i]) };
                        self.queue.push_front(g);
                        self.in_queue[g.id.index()] = true;
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
                if self.shared && self.robots.state[i] == State::ToCharger {
                    self.release_charger(self.robots.charger[i]);
                }
                self.robots.state[i] = State::Stranded;
                self.robots.energy[i] = 0.0;
                self.robots.routing[i] = false;
                self.event(EventKind::Strand, i, NONE);
            }
        }
    }

    fn send_to_charge(&mut self, i: usize) {
        if self.shared {
            self.send_to_shared_charger(i);
            return;
        }
        self.robots.state[i] = State::ToCharger;
        let charger = self.charger_of(i);
        self.robots.charger[i] = charger.0;
        self.route(i, Target::Node(charger));
    }

    /// Shared chargers: the nearest free charger by route length (ties: the first in the
    /// layout), claimed until the robot is full; with none free, the robot stops where it is,
    /// WAIT_CHARGER, in a first-come-first-served queue.
    fn send_to_shared_charger(&mut self, i: usize) {
        let layout = &self.world.layout;
        let nodes = layout.nodes.len();
        let from = Place::of(&self.robots, i);
        let mut best: Option<(f64, usize)> = None;
        for (k, &c) in layout.chargers.iter().enumerate() {
            if self.claim[k] != NONE {
                continue;
            }
            let d = length_by_row(&self.world.graph, from, c, &self.to_charger[k * nodes..(k + 1) * nodes]);
            if best.map_or(true, |(b, _)| d < b) {
                best = Some((d, k));
            }
        }
        if let Some((_, k)) = best {
            self.claim_charger(i, k);
        } else {
            self.robots.state[i] = State::WaitCharger;
            self.robots.routing[i] = false;
            self.charge_queue.push_back(i as u32);
        }
    }

    fn claim_charger(&mut self, i: usize, k: usize) {
        let charger = self.world.layout.chargers[k];
        self.claim[k] = i as u32;
        self.robots.state[i] = State::ToCharger;
        self.robots.charger[i] = charger.0;
        self.route(i, Target::Node(charger));
    }

    /// A charger became free: the longest-waiting robot (still waiting) takes it.
    fn release_charger(&mut self, charger: u32) {
        let k = self.charger_slot[charger as usize];
        if k == NONE {
            return;
        }
        self.claim[k as usize] = NONE;
        while let Some(j) = self.charge_queue.pop_front() {
            if self.robots.state[j as usize] == State::WaitCharger {
                self.claim_charger(j as usize, k as usize);
                break;
            }
        }
    }

    /// Phase 8: completion first, then the step limit.
    fn end(&mut self) {
        if let Some(ll) = &self.lifelong {
            if self.t >= ll.horizon {
                self.outcome = Some(Outcome::Horizon);
            }
            return;
        }
        if self.delivered == self.goods_total && (0..self.robots.len()).all(|i| self.at_home(i)) {
            self.outcome = Some(Outcome::Complete);
        } else if self.t >= self.p.step_limit {
            self.outcome = Some(Outcome::Incomplete);
        }
    }

    /// The indicators and per-robot statistics so far.
    #[must_use]
    pub fn result(&self) -> RunResult {
        let stranded = (0..self.robots.len()).filter(|&i| self.robots.state[i] == State::Stranded).map(|i| i as u32).collect();
        RunResult {
            t: (self.outcome == Some(Outcome::Complete)).then_some(self.t),
            s: self.s,
            c: self.c,
            outcome: self.outcome,
            steps: self.t,
            delivered: self.delivered,
            goods_total: self.goods_total,
            stranded,
            robots: self.stats.clone(),
            lifelong: self.lifelong.as_ref().map(|ll| self.lifelong_stats(ll)),
        }
    }

    fn lifelong_stats(&self, ll: &Lifelong) -> LifelongStats {
        let mut lat = ll.latencies.clone();
        lat.sort_unstable();
        let steps = self.t.max(1);
        let busy: u64 = self.stats.state_steps.iter().map(|s| s[State::ToPickup as usize] + s[State::Loading as usize] + s[State::ToDrop as usize] + s[State::Unloading as usize]).sum();
        let energy: f64 = self.stats.energy_used.iter().sum();
        LifelongStats {
            ordered: ll.ordered(),
            in_flight: (0..self.robots.len()).filter(|&i| self.robots.goods[i] != NONE).count() as u64,
            queued: self.queue.len() as u64,
            waiting: ll.waiting,
            throughput: self.delivered as f64 * 1000.0 / steps as f64,
            latency_p50: lifelong::percentile(&lat, 50.0),
            latency_p95: lifelong::percentile(&lat, 95.0),
            latency_p99: lifelong::percentile(&lat, 99.0),
            latency_mean: (!lat.is_empty()).then(|| lat.iter().sum::<u64>() as f64 / lat.len() as f64),
            utilisation: busy as f64 / (steps * self.robots.len() as u64) as f64,
            energy_per_delivery: (self.delivered > 0).then(|| energy / self.delivered as f64),
        }
    }

    // Read-only state, for the bindings, viewers and replays.

    /// The current step (0 before the first).
    #[must_use]
    pub fn t(&self) -> u64 {
        self.t
    }
    /// Whether the run has ended.
    #[must_use]
    pub fn done(&self) -> bool {
        self.outcome.is_some()
    }
    /// The run's outcome, once it has ended.
    #[must_use]
    pub fn outcome(&self) -> Option<Outcome> {
        self.outcome
    }
    /// Collisions S so far.
    #[must_use]
    pub fn s(&self) -> u64 {
        self.s
    }
    /// Charging count C so far.
    #[must_use]
    pub fn c(&self) -> u64 {
        self.c
    }
    /// Goods delivered so far.
    #[must_use]
    pub fn delivered(&self) -> u64 {
        self.delivered
    }
    /// Goods in the task list.
    #[must_use]
    pub fn goods_total(&self) -> u64 {
        self.goods_total
    }
    /// The fleet's columns.
    #[must_use]
    pub fn robots(&self) -> &Robots {
        &self.robots
    }
    /// Per-robot statistics so far.
    #[must_use]
    pub fn stats(&self) -> &RobotStats {
        &self.stats
    }
    /// Which cells hold goods.
    #[must_use]
    pub fn cells_full(&self) -> &[bool] {
        &self.cells_full
    }
    /// Goods not yet taken, front first.
    #[must_use]
    pub fn queue(&self) -> &VecDeque<Goods> {
        &self.queue
    }
    /// Events of the last step.
    #[must_use]
    pub fn events(&self) -> &[Event] {
        &self.events
    }
    /// The layout and graph.
    #[must_use]
    pub fn world(&self) -> &Arc<World> {
        &self.world
    }
    /// Full energy and the threshold.
    #[must_use]
    pub fn energy_levels(&self) -> (f64, f64) {
        (self.p.energy_full, self.p.threshold)
    }
    /// The allocator's name.
    #[must_use]
    pub fn allocator_name(&self) -> &str {
        self.allocator.name()
    }
    /// Robot `i`'s remaining route as waypoints, starting at its position.
    #[must_use]
    pub fn route_of(&self, i: usize) -> Vec<(f64, f64)> {
        route::remaining(&self.robots, &self.world.graph, i)
    }
    /// Route length from a node to a target, for callers outside the step loop.
    #[must_use]
    pub fn route_length_from_node(&self, from: NodeId, target: Target) -> f64 {
        route::length(&self.world.graph, Place::node(&self.world.graph, from), target)
    }
    /// Whether a node is a charger.
    #[must_use]
    pub fn is_charger(&self, n: NodeId) -> bool {
        self.world.layout.nodes[n.index()].kind == NodeKind::Charger
    }
}
