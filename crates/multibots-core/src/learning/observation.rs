//! What a decider sees: features of itself, of the fleet and of the queue's first slots, the
//! action mask, and the global state. Every feature is a number in a documented range
//! (`docs/learning.md` names each one), clipped into it, so that an observation always lies
//! in its space.
//!
//! Scales: positions are relative to the rectangle robots can reach (0 to 1 across it);
//! lengths are in units of L = its width + height; energies in units of a full battery;
//! step counts in units of L / speed (the steps to drive L).

use crate::alloc::{AllocView, TaskModel};
use crate::fleet::energy;
use crate::fleet::robot::{Robots, State, Target};
use crate::fleet::route::{self, Place};
use crate::fleet::route::{route_nodes, service_place, service_target};
use crate::ids::{CellId, NodeId, RobotId, NONE};
use crate::input::scenario::Scenario;
use crate::rules::paper::Paper;
use crate::rules::Engine;
use crate::world::World;

/// One feature: its name (as `docs/learning.md` lists it) and its range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feature {
    pub name: &'static str,
    pub low: f32,
    pub high: f32,
}

const fn f(name: &'static str, low: f32, high: f32) -> Feature {
    Feature { name, low, high }
}

/// The deciding robot's features.
pub const ROBOT: [Feature; 8] = [
    f("energy", 0.0, 1.0),
    f("energy_above_threshold", -1.0, 1.0),
    f("x", 0.0, 1.0),
    f("y", 0.0, 1.0),
    f("route_to_charger", 0.0, 4.0),
    f("on_charger", 0.0, 1.0),
    f("open_goods", 0.0, 4.0),
    f("deciding_robots", 0.0, 1.0),
];

/// Each robot's features in the fleet table (rows in robot id order).
pub const FLEET: [Feature; 19] = [
    f("state_idle", 0.0, 1.0),
    f("state_to_pickup", 0.0, 1.0),
    f("state_loading", 0.0, 1.0),
    f("state_to_drop", 0.0, 1.0),
    f("state_unloading", 0.0, 1.0),
    f("state_to_charger", 0.0, 1.0),
    f("state_charging", 0.0, 1.0),
    f("state_to_home", 0.0, 1.0),
    f("state_parked", 0.0, 1.0),
    f("state_stranded", 0.0, 1.0),
    f("state_wait_charger", 0.0, 1.0),
    f("energy", 0.0, 1.0),
    f("x", 0.0, 1.0),
    f("y", 0.0, 1.0),
    f("route_left", 0.0, 4.0),
    f("carrying", 0.0, 1.0),
    f("decides_later", 0.0, 1.0),
    f("decided_earlier", 0.0, 1.0),
    f("is_self", 0.0, 1.0),
];

/// Each queue slot's features, as the deciding robot sees them (slots in queue order).
pub const GOODS: [Feature; 10] = [
    f("open", 0.0, 1.0),
    f("route_to_goods", 0.0, 4.0),
    f("goods_to_unload", 0.0, 4.0),
    f("task_steps", 0.0, 8.0),
    f("energy_after", -1.0, 1.0),
    f("ends_below_threshold", 0.0, 1.0),
    f("traffic", 0.0, 8.0),
    f("x", 0.0, 1.0),
    f("y", 0.0, 1.0),
    f("slot", 0.0, 1.0),
];

/// Global state: each robot's features (the fleet table's first 16).
pub const STATE_ROBOT: [Feature; 16] = {
    let mut out = [f("", 0.0, 0.0); 16];
    let mut k = 0;
    while k < 16 {
        out[k] = FLEET[k];
        k += 1;
    }
    out
};

/// Global state: each queue slot's features.
pub const STATE_GOODS: [Feature; 5] = [f("open", 0.0, 1.0), f("goods_to_unload", 0.0, 4.0), f("x", 0.0, 1.0), f("y", 0.0, 1.0), f("slot", 0.0, 1.0)];

/// Global state: the run's features.
pub const STATE_RUN: [Feature; 4] = [f("time", 0.0, 1.0), f("delivered", 0.0, 1.0), f("open_goods", 0.0, 4.0), f("idle_robots", 0.0, 1.0)];

/// Features of the deciding robot.
pub const ROBOT_FEATURES: usize = ROBOT.len();
/// Features of each robot in the fleet table.
pub const FLEET_FEATURES: usize = FLEET.len();
/// Features of each queue slot.
pub const GOODS_FEATURES: usize = GOODS.len();
/// Global state: features of each robot, of each queue slot, and of the run.
pub const STATE_ROBOT_FEATURES: usize = STATE_ROBOT.len();
pub const STATE_GOODS_FEATURES: usize = STATE_GOODS.len();
pub const STATE_RUN_FEATURES: usize = STATE_RUN.len();

/// Where one observation goes: row-major arrays of `ROBOT_FEATURES`, `N × FLEET_FEATURES`,
/// `max_queue × GOODS_FEATURES` and `max_queue + 2` (the mask, 1 = allowed).
pub struct ObsMut<'a> {
    pub robot: &'a mut [f32],
    pub fleet: &'a mut [f32],
    pub queue: &'a mut [f32],
    pub mask: &'a mut [u8],
}

/// One observation, owned (for a policy used as an allocator).
#[derive(Clone, Debug, PartialEq)]
pub struct Observation {
    pub robot: Vec<f32>,
    pub fleet: Vec<f32>,
    pub queue: Vec<f32>,
    pub mask: Vec<u8>,
}

impl Observation {
    /// Zeros, for `robots` robots and `max_queue` slots.
    #[must_use]
    pub fn zeros(robots: usize, max_queue: usize) -> Observation {
        Observation {
            robot: vec![0.0; ROBOT_FEATURES],
            fleet: vec![0.0; robots * FLEET_FEATURES],
            queue: vec![0.0; max_queue * GOODS_FEATURES],
            mask: vec![0; max_queue + 2],
        }
    }

    /// Where to write it.
    pub fn as_mut(&mut self) -> ObsMut<'_> {
        ObsMut { robot: &mut self.robot, fleet: &mut self.fleet, queue: &mut self.queue, mask: &mut self.mask }
    }
}

/// Per-decision-point marks the features show: which robots decide at this point, which
/// have decided, and which slots robots before took.
#[derive(Clone, Debug, Default)]
pub(crate) struct Marks {
    /// Per robot: 0 not deciding here, 1 still to decide, 2 decided.
    pub robot: Vec<u8>,
    /// Per visible slot: the robot that took it at this point, or `NONE`.
    pub taken: Vec<u32>,
    /// Robots deciding at this point.
    pub deciding: usize,
    /// Per highway node: how many robots' expected paths cover it (the traffic proxy of
    /// [`AllocView::traffic`], counted once per point).
    pub cover: Vec<u32>,
}

impl Marks {
    /// Marks for a decision point: `deciding` robots to decide, no slot taken, and the cover
    /// of every robot's expected path.
    pub fn start(&mut self, view: &AllocView<'_>, deciding: &[RobotId], max_queue: usize) {
        let n = view.robot_count();
        self.robot.clear();
        self.robot.resize(n, 0);
        for &r in deciding {
            self.robot[r.index()] = 1;
        }
        self.deciding = deciding.len();
        self.taken.clear();
        self.taken.resize(max_queue, NONE);
        self.cover.clear();
        self.cover.resize(view.graph().len(), 0);
        let mut buf = Vec::with_capacity(64);
        for j in 0..n {
            buf.clear();
            view.footprint(j, &mut buf);
            buf.sort_unstable();
            buf.dedup();
            for &u in &buf {
                self.cover[u as usize] += 1;
            }
        }
    }

    /// No decision point (the terminal observation).
    pub fn none(&mut self, robots: usize, max_queue: usize) {
        self.robot.clear();
        self.robot.resize(robots, 0);
        self.taken.clear();
        self.taken.resize(max_queue, NONE);
        self.deciding = 0;
        self.cover.clear();
    }
}

/// Turns a run's state into features: the scales of one world and scenario.
#[derive(Clone, Debug)]
pub struct Encoder {
    x0: f64,
    y0: f64,
    w: f64,
    h: f64,
    /// L = w + h.
    length: f64,
    /// Steps to drive L.
    steps: f64,
    energy_full: f64,
    threshold: f64,
    model: TaskModel,
    max_queue: usize,
}

fn clip(v: f64, (lo, hi): (f32, f32)) -> f32 {
    (v as f32).clamp(lo, hi)
}

fn within(v: f64, f: Feature) -> f32 {
    clip(v, (f.low, f.high))
}

impl Encoder {
    /// The scales of a scenario on its world.
    #[must_use]
    pub fn new(world: &World, scenario: &Scenario, max_queue: usize) -> Encoder {
        Encoder::with_model(world, scenario.robot.energy_full, scenario.robot.threshold, scenario.robot.speed, TaskModel::of(scenario), max_queue)
    }

    /// The same from the energy model and task model (what an allocator's view carries).
    #[must_use]
    pub fn with_model(world: &World, energy_full: f64, threshold: f64, speed: f64, model: TaskModel, max_queue: usize) -> Encoder {
        let [x0, y0, x1, y1] = world.reach_bounds();
        let (w, h) = ((x1 - x0).max(1.0), (y1 - y0).max(1.0));
        Encoder { x0, y0, w, h, length: w + h, steps: (w + h) / speed, energy_full, threshold, model, max_queue }
    }

    /// Queue slots shown.
    #[must_use]
    pub fn max_queue(&self) -> usize {
        self.max_queue
    }

    fn x(&self, x: f64) -> f32 {
        clip((x - self.x0) / self.w, (0.0, 1.0))
    }

    fn y(&self, y: f64) -> f32 {
        clip((y - self.y0) / self.h, (0.0, 1.0))
    }

    /// Whether robot `r` may take slot `k`: it holds open goods no robot before took.
    pub(crate) fn slot_open(view: &AllocView<'_>, marks: &Marks, k: usize) -> bool {
        k < view.goods.len() && marks.taken[k] == NONE
    }

    /// Whether robot `r` may go to charge now: it is not full.
    pub(crate) fn can_charge(&self, view: &AllocView<'_>, r: RobotId) -> bool {
        !energy::is_full(view.energy(r), self.energy_full)
    }

    /// The action mask of robot `r` when it decides: open slots, charge unless full, wait.
    pub(crate) fn mask(&self, view: &AllocView<'_>, r: RobotId, marks: &Marks, deciding: bool, out: &mut [u8]) {
        let q = self.max_queue;
        for (k, m) in out[..q].iter_mut().enumerate() {
            *m = u8::from(deciding && Encoder::slot_open(view, marks, k));
        }
        out[q] = u8::from(deciding && self.can_charge(view, r));
        out[q + 1] = 1;
    }

    /// The observation of robot `r`; `deciding` says whether it decides at this point (else
    /// its mask allows only "wait").
    pub(crate) fn observe(&self, view: &AllocView<'_>, r: RobotId, marks: &Marks, deciding: bool, out: ObsMut<'_>) {
        let ObsMut { robot: robot_out, fleet, queue, mask } = out;
        let rb = view.robots();
        let i = r.index();
        let n = rb.len();
        let e = rb.energy[i];
        let home = Target::Node(rb.home[i]);
        let on_charger = rb.at_node[i] != NONE && view.layout().nodes[rb.at_node[i] as usize].kind == crate::world::layout::NodeKind::Charger;
        let robot = [
            e / self.energy_full,
            (e - self.threshold) / self.energy_full,
            0.0,
            0.0,
            route::length(view.graph(), Place::of(rb, i), home) / self.length,
            f64::from(u8::from(on_charger)),
            view.goods.len() as f64 / self.max_queue as f64,
            marks.deciding as f64 / n as f64,
        ];
        for (k, (v, o)) in robot.iter().zip(robot_out.iter_mut()).enumerate() {
            *o = within(*v, ROBOT[k]);
        }
        robot_out[2] = self.x(rb.x[i]);
        robot_out[3] = self.y(rb.y[i]);
        self.fleet(view.graph(), rb, Some((i, marks)), fleet, FLEET_FEATURES);
        self.queue(view, r, marks, queue);
        self.mask(view, r, marks, deciding, mask);
    }

    /// The fleet table, `stride` features a row: the one-hot state, energy, x, y, route left,
    /// carrying, and with `decider` the marks of the decision point and which row is the
    /// decider.
    fn fleet(&self, g: &crate::world::graph::HighwayGraph, rb: &Robots, decider: Option<(usize, &Marks)>, out: &mut [f32], stride: usize) {
        out.fill(0.0);
        for j in 0..rb.len() {
            let row = &mut out[j * stride..(j + 1) * stride];
            row[rb.state[j] as usize] = 1.0;
            row[11] = clip(rb.energy[j] / self.energy_full, (0.0, 1.0));
            row[12] = self.x(rb.x[j]);
            row[13] = self.y(rb.y[j]);
            row[14] = clip(remaining_length(rb, g, j) / self.length, (0.0, 4.0));
            row[15] = f32::from(u8::from(rb.carrying[j]));
            if let Some((i, marks)) = decider {
                row[16] = f32::from(u8::from(marks.robot[j] == 1 && j != i));
                row[17] = f32::from(u8::from(marks.robot[j] == 2));
                row[18] = f32::from(u8::from(j == i));
            }
        }
    }

    /// The queue slots as seen by robot `r`.
    fn queue(&self, view: &AllocView<'_>, r: RobotId, marks: &Marks, out: &mut [f32]) {
        out.fill(0.0);
        let rb = view.robots();
        let n = rb.len();
        let from = Place::of(rb, r.index());
        // The decider's own expected path does not count as traffic.
        let mut own = Vec::new();
        view.footprint(r.index(), &mut own);
        let mut mine = Vec::with_capacity(64);
        for (k, g) in view.goods.iter().take(self.max_queue).enumerate() {
            if marks.taken[k] != NONE {
                continue;
            }
            let row = &mut out[k * GOODS_FEATURES..(k + 1) * GOODS_FEATURES];
            let to_goods = route::length(view.graph(), from, service_target(view.layout(), g.cell));
            let to_unload = view.cell_to_unload(g.cell);
            let speed = rb.speed[r.index()];
            let steps = (to_goods / speed).ceil() + f64::from(self.model.loading) + (to_unload / speed).ceil() + f64::from(self.model.unloading);
            let after = rb.energy[r.index()] - steps * view.energy_params().consumption;
            let traffic = if marks.cover.is_empty() { 0 } else { Encoder::traffic(view, r, g.cell, marks, &own, &mut mine) };
            let (sx, sy) = view.layout().cells[g.cell.index()].service;
            let v = [
                1.0,
                to_goods / self.length,
                to_unload / self.length,
                steps / self.steps,
                after / self.energy_full,
                f64::from(u8::from(energy::below(after, self.threshold))),
                f64::from(traffic) / (n.max(2) - 1) as f64,
                0.0,
                0.0,
                k as f64 / self.max_queue as f64,
            ];
            for (f, (x, o)) in v.iter().zip(row.iter_mut()).enumerate() {
                *o = within(*x, GOODS[f]);
            }
            row[7] = self.x(sx);
            row[8] = self.y(sy);
        }
    }

    /// [`AllocView::traffic`] from the point's cover: the (other robot, node) pairs where the
    /// route of robot `r` to fetch `cell` and unload it meets another robot's expected path.
    fn traffic(view: &AllocView<'_>, r: RobotId, cell: CellId, marks: &Marks, own: &[u32], mine: &mut Vec<u32>) -> u32 {
        mine.clear();
        route_nodes(view.graph(), Place::of(view.robots(), r.index()), service_target(view.layout(), cell), mine);
        route_nodes(view.graph(), service_place(view.layout(), cell), Target::Node(view.unload()), mine);
        mine.retain(|&u| view.layout().nodes[u as usize].kind == crate::world::layout::NodeKind::Highway);
        mine.sort_unstable();
        mine.dedup();
        mine.iter().map(|&u| marks.cover[u as usize] - u32::from(own.contains(&u))).sum()
    }

    /// The global state: every robot's features, the queue's first slots, and the run's
    /// progress (see the bounds constants for the order).
    pub(crate) fn state(&self, paper: &Paper, out: &mut [f32]) {
        let rb = paper.robots();
        let n = rb.len();
        let fleet_len = n * STATE_ROBOT_FEATURES;
        self.fleet(&paper.world().graph, rb, None, &mut out[..fleet_len], STATE_ROBOT_FEATURES);
        let q = self.max_queue;
        let slots = &mut out[fleet_len..fleet_len + q * STATE_GOODS_FEATURES];
        slots.fill(0.0);
        let layout = &paper.world().layout;
        for (k, g) in paper.queue().iter().take(q).enumerate() {
            let row = &mut slots[k * STATE_GOODS_FEATURES..(k + 1) * STATE_GOODS_FEATURES];
            let zone = paper.unload_of(g.cell.0);
            let to_unload = route::length(&paper.world().graph, service_place(layout, g.cell), Target::Node(zone));
            let (sx, sy) = layout.cells[g.cell.index()].service;
            row[0] = 1.0;
            row[1] = clip(to_unload / self.length, (0.0, 4.0));
            row[2] = self.x(sx);
            row[3] = self.y(sy);
            row[4] = clip(k as f64 / q as f64, (0.0, 1.0));
        }
        let run = &mut out[fleet_len + q * STATE_GOODS_FEATURES..];
        let idle = rb.state.iter().filter(|&&s| s == State::Idle).count();
        let v = [
            paper.t() as f64 / paper.limit().max(1) as f64,
            paper.delivered() as f64 / paper.goods_total().max(1) as f64,
            paper.queue().len() as f64 / q as f64,
            idle as f64 / n as f64,
        ];
        for (k, (x, o)) in v.iter().zip(run.iter_mut()).enumerate() {
            *o = within(*x, STATE_RUN[k]);
        }
    }

    /// Length of the global state for `robots` robots.
    #[must_use]
    pub fn state_len(&self, robots: usize) -> usize {
        robots * STATE_ROBOT_FEATURES + self.max_queue * STATE_GOODS_FEATURES + STATE_RUN_FEATURES
    }
}

/// Length in px of what is left of robot `i`'s route, without allocating: to its waypoint,
/// along the node path to its goal, then to its final point.
fn remaining_length(r: &Robots, g: &crate::world::graph::HighwayGraph, i: usize) -> f64 {
    if !r.routing[i] {
        return 0.0;
    }
    let mut total = route::dist(r.x[i], r.y[i], r.wp_x[i], r.wp_y[i]);
    if r.wp_node[i] != NONE {
        total += g.path_length(NodeId(r.wp_node[i]), NodeId(r.goal[i]));
        if r.has_final[i] {
            let (gx, gy) = g.pos(r.goal[i]);
            total += route::dist(gx, gy, r.final_x[i], r.final_y[i]);
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scenario::PAPER_TASKS;
    use crate::Simulation;

    #[test]
    fn traffic_from_the_cover_equals_the_views_traffic_and_routes_left_match() {
        let s = Scenario::paper(6, &PAPER_TASKS[2]);
        let mut sim = Simulation::new(&s).unwrap();
        let mut checked = 0;
        while sim.advance_to_decision().unwrap() {
            let v = sim.pending_view().unwrap();
            let mut marks = Marks::default();
            marks.start(&v, v.idle, 10);
            for &r in v.idle {
                let mut own = Vec::new();
                v.footprint(r.index(), &mut own);
                for g in v.goods {
                    assert_eq!(Encoder::traffic(&v, r, g.cell, &marks, &own, &mut Vec::new()), v.traffic(r, g.cell));
                    checked += 1;
                }
            }
            for j in 0..v.robot_count() {
                let exact = v.remaining_length(RobotId(j as u32));
                assert!((remaining_length(v.robots(), v.graph(), j) - exact).abs() < 1e-9);
            }
            let mut d = crate::alloc::Decisions::new();
            crate::Allocator::allocate(&mut crate::alloc::InTurn, &v, &mut d).unwrap();
            sim.decide(&d).unwrap();
        }
        assert!(checked > 20, "{checked}");
    }
}
