//! One step of the paper model (spec section 4), phase by phase.

use crate::alloc::{self, service_target, AllocView, Allocator, Assignment, Goods};
use crate::collision::Collisions;
use crate::energy;
use crate::error::{Error, Result};
use crate::graph::{self, HighwayGraph};
use crate::ids::{CellId, GoodsId, NodeId, RobotId, NONE};
use crate::layout::{Layout, NodeKind};
use crate::metrics::{Outcome, RobotStats, RunResult};
use crate::robot::{Robots, State, Target};
use crate::route::{self, Place};
use crate::scenario::{ChargingPolicy, Scenario};
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
#[derive(Clone, Debug)]
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
    collisions: Collisions,
    wants: Vec<bool>,
    alpha: Vec<f64>,
    stats: RobotStats,
    events: Vec<Event>,
    idle_buf: Vec<RobotId>,
    assign_buf: Vec<Assignment>,
    taken_buf: Vec<bool>,
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
        let unload = layout
            .node_named(&scenario.unload)
            .ok_or_else(|| Error::scenario("unload", format!("\"{}\"", scenario.unload), "unknown node"))?;
        if !layout.unloading.contains(&unload) {
            return Err(Error::scenario("unload", format!("\"{}\"", scenario.unload), "is not an unloading zone"));
        }
        let n = scenario.robots as usize;
        let starts: Vec<NodeId> = match &scenario.starts {
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
        let mut robots = Robots::default();
        for (i, &start) in starts.iter().enumerate() {
            let home = layout.charger_at(start).ok_or_else(|| {
                Error::scenario(format!("starts[{i}]"), format!("\"{}\"", layout.nodes[start.index()].name), "has no charger to be the robot's home")
            })?;
            robots.push(home, layout.pos(home), home, r.radius, r.speed, r.energy_full);
        }
        let mut cells_full = vec![false; layout.cells.len()];
        let queue: VecDeque<Goods> = cells
            .iter()
            .enumerate()
            .map(|(k, &c)| {
                cells_full[c as usize] = true;
                Goods { id: GoodsId(k as u32), cell: CellId(c) }
            })
            .collect();
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
            collisions: Collisions::new(b, reach, n),
            wants: vec![false; n],
            alpha: vec![0.0; n],
            stats: RobotStats::new(n),
            events: Vec::new(),
            idle_buf: Vec::with_capacity(n),
            assign_buf: Vec::with_capacity(n),
            taken_buf: Vec::new(),
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
        self.t += 1;
        self.events.clear();
        self.allocate()?;
        self.intend();
        self.block();
        self.travel();
        self.dwell_and_consume();
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
        for i in 0..self.robots.len() {
            if self.robots.state[i] == State::Idle {
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
        for k in 0..self.assign_buf.len() {
            let Assignment { robot, goods } = self.assign_buf[k];
            let pos = self.queue.iter().position(|g| g.id == goods).expect("checked");
            let g = self.queue.remove(pos).expect("checked");
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
                    let home = self.robots.home[i];
                    self.route(i, Target::Node(home));
                }
            }
        }
        self.alloc_due = false;
        Ok(())
    }

    fn check_assignments(&mut self) -> Result<()> {
        let name = self.allocator.name().to_string();
        let bad = |reason: String| Err(Error::Allocator { strategy: name.clone(), reason });
        let n = self.robots.len();
        self.taken_buf.clear();
        self.taken_buf.resize(n, false);
        for (k, a) in self.assign_buf.iter().enumerate() {
            let i = a.robot.index();
            if i >= n {
                return bad(format!("assignment {k}: unknown robot id {}", a.robot));
            }
            if self.robots.state[i] != State::Idle {
                return bad(format!("assignment {k}: robot {} is not idle (it is {})", a.robot, self.robots.state[i].name()));
            }
            if self.taken_buf[i] {
                return bad(format!("assignment {k}: robot {} is given goods twice", a.robot));
            }
            self.taken_buf[i] = true;
            if !self.queue.iter().any(|g| g.id == a.goods) {
                return bad(format!("assignment {k}: unknown or taken goods id {}", a.goods));
            }
            if self.assign_buf[..k].iter().any(|b| b.goods == a.goods) {
                return bad(format!("assignment {k}: goods {} handed out twice", a.goods));
            }
        }
        Ok(())
    }

    /// Phase 2: who wants to move, and where each is heading.
    fn intend(&mut self) {
        let r = &mut self.robots;
        for i in 0..r.len() {
            let w = r.routing[i] && r.state[i].travels();
            self.wants[i] = w;
            if w {
                let a = (r.wp_y[i] - r.y[i]).atan2(r.wp_x[i] - r.x[i]);
                self.alpha[i] = a;
                r.heading[i] = a;
            }
        }
    }

    /// Phase 3: collision waiting and the count S.
    fn block(&mut self) {
        let r = &self.robots;
        self.collisions.resolve(&r.x, &r.y, &r.radius, &self.wants, &self.alpha, self.p.margin, self.p.angle);
        for i in 0..self.robots.len() {
            let w = self.collisions.waits[i];
            if w {
                self.stats.wait_steps[i] += 1;
                if !self.robots.waited[i] {
                    self.s += 1;
                    self.stats.collisions[i] += 1;
                    self.event(EventKind::Wait, i, NONE);
                }
            }
            self.robots.waited[i] = w;
        }
    }

    /// Phase 4: robots that may move travel `speed` px along their routes.
    fn travel(&mut self) {
        let g = &self.world.graph;
        for i in 0..self.robots.len() {
            if self.wants[i] && !self.collisions.waits[i] {
                let speed = self.robots.speed[i];
                self.stats.distance[i] += route::advance(&mut self.robots, g, i, speed);
            }
        }
    }

    /// Phases 5 and 6: dwell counters, charging, consumption.
    fn dwell_and_consume(&mut self) {
        let p = &self.p;
        let r = &mut self.robots;
        for i in 0..r.len() {
            match r.state[i] {
                State::Loading | State::Unloading => r.dwell[i] += 1,
                State::Charging => r.energy[i] = energy::charge(r.energy[i], p.charge_rate, p.energy_full),
                _ => {}
            }
            if !matches!(r.state[i], State::Charging | State::Parked | State::Stranded) {
                let e = energy::consume(r.energy[i], p.consumption);
                self.stats.energy_used[i] += r.energy[i] - e;
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
        for i in 0..self.robots.len() {
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
                    self.robots.carrying[i] = true;
                    self.robots.state[i] = State::ToDrop;
                    self.event(EventKind::Pickup, i, cell);
                    self.route(i, Target::Node(self.p.unload));
                }
                State::Unloading if self.robots.dwell[i] >= self.p.unloading => {
                    let cell = self.robots.cell[i];
                    self.delivered += 1;
                    self.stats.delivered[i] += 1;
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
                }
                _ => {}
            }
            if energy::below(self.robots.energy[i], self.p.threshold) {
                match self.robots.state[i] {
                    State::Idle => self.send_to_charge(i),
                    State::ToPickup if !self.inside_service_edge(i) => {
                        let g = Goods { id: GoodsId(self.robots.goods[i]), cell: CellId(self.robots.cell[i]) };
                        self.queue.push_front(g);
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
                self.robots.state[i] = State::Stranded;
                self.robots.energy[i] = 0.0;
                self.robots.routing[i] = false;
                self.event(EventKind::Strand, i, NONE);
            }
            self.stats.state_steps[i][self.robots.state[i] as usize] += 1;
        }
    }

    fn send_to_charge(&mut self, i: usize) {
        self.robots.state[i] = State::ToCharger;
        let charger = self.charger_of(i);
        self.robots.charger[i] = charger.0;
        self.route(i, Target::Node(charger));
    }

    /// Phase 8: completion first, then the step limit.
    fn end(&mut self) {
        if self.delivered == self.goods_total && (0..self.robots.len()).all(|i| self.robots.at_node[i] == self.robots.home[i].0) {
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
