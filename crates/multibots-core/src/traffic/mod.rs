//! Traffic policies: how robots share the aisles (docs/traffic.md). Chosen per scenario with
//! `traffic = "wait" | "gate" | "reserve"`; each decides, in phase 3, how far every robot
//! that wants to move may travel this step. The step asks [`decide`] and reads the answer
//! with [`moves`]; the lanes (robots in order along each aisle edge) are in `lanes.rs`.
//!
//! - **wait** (the default): the paper's collision waiting ([`crate::collision`]), unchanged.
//! - **gate**: collision waiting, and crossings taken one robot at a time: a robot does not
//!   drive into a crossing's zone while another robot is in it, unless it has waited
//!   [`GATE_PATIENCE`] steps (then collision waiting alone decides, so the gate cannot
//!   deadlock). It removes most side-by-side passes at crossings, at little cost.
//! - **reserve**: no cone. Every crossing has a zone (a disc of the contact distance around
//!   the node) that one robot at a time may occupy; a robot enters a zone only when it is
//!   free and the robot's exit lane has room for it beyond the zone, in the order robots asked
//!   (the longest-waiting first, then the lower id); along a lane a robot keeps the contact
//!   distance to the robot ahead of it *after that robot's own move*, so queues move as one;
//!   a robot refused for a full exit for [`DETOUR_AFTER`] steps takes another exit (a
//!   detour) when one has room. Two robots on one lane keep their distance; two robots on
//!   different lanes meet only near a crossing, where the zone keeps them apart; so no two
//!   robots come closer than r_i + r_j (tested). A robot never stops inside a crossing unless
//!   its route ends there (unloading, charging), so crossings never block each other in a
//!   cycle.
//!
//! Both new policies look ahead only as far as the next crossing and the lane after it, and
//! cost O(N) per step plus sorting each lane (robots keep their order on a lane, so the sort
//! is nearly free).

mod lanes;

use crate::collision::Collisions;
use crate::fleet::bay::Bays;
use crate::fleet::robot::Robots;
use crate::ids::NONE;
use crate::input::scenario::Traffic;
use crate::people::People;
use crate::world::graph::HighwayGraph;
use lanes::{Ahead, Lanes};

/// Steps a robot waits for room on its exit lane before it takes another exit.
pub const DETOUR_AFTER: u32 = 30;

/// `gate`: steps a robot waits for a busy crossing before it goes anyway.
pub const GATE_PATIENCE: u64 = 25;

/// Whether edge `b` continues edge `a` in a straight line (the same direction).
fn straight(g: &HighwayGraph, a: u32, b: u32) -> bool {
    let (a0, a1, la) = g.edge(a);
    let (b0, b1, lb) = g.edge(b);
    let ((ax0, ay0), (ax1, ay1)) = (g.pos(a0), g.pos(a1));
    let ((bx0, by0), (bx1, by1)) = (g.pos(b0), g.pos(b1));
    let (ux, uy, wx, wy) = ((ax1 - ax0) / la, (ay1 - ay0) / la, (bx1 - bx0) / lb, (by1 - by0) / lb);
    ux * wx + uy * wy > 1.0 - 1e-9 && (ux * wy - uy * wx).abs() < 1e-9
}

/// Steps a robot waits for room before a detour may go through a crossing with one way out.
pub const LAST_RESORT_AFTER: u32 = 4 * DETOUR_AFTER;

/// Whether a robot refused `refusals` steps may detour from `v` through `w`. Never into a
/// dead end, where every way on leads back to `v` (a charger at the end of its spur). A
/// crossing with one way out (at the warehouse's walls, on the bottom row) goes on, but a
/// detour through it only comes after [`LAST_RESORT_AFTER`] steps: sooner, robots queued
/// for a busy place leave their queue for long loops; never, and the four full lanes round
/// a block at a wall wait for each other for good.
fn may_detour_to(g: &HighwayGraph, v: u32, w: u32, refusals: u32) -> bool {
    let out = g.out(w as usize);
    out.len() > 1 || refusals >= LAST_RESORT_AFTER && out.iter().any(|&x| x != v)
}

/// What the traffic decision reads of this step: the floor, who wants to move (heading
/// `robots.heading`), the collision rule's numbers, and the people, if any.
pub(crate) struct Scene<'a> {
    pub graph: &'a HighwayGraph,
    /// The step.
    pub t: u64,
    pub wants: &'a [bool],
    pub margin: f64,
    /// The collision angle, radians.
    pub angle: f64,
    pub people: Option<&'a People>,
}

impl Scene<'_> {
    /// Whether a robot of `radius` may stand at `(x, y)` as far as people go.
    fn clear(&self, x: f64, y: f64, radius: f64) -> bool {
        self.people.map_or(true, |p| p.clear_of(x, y, radius))
    }
}

/// Phase 3 for the fleet: who waits, and how far each robot that wants to move may travel.
/// Without a policy (`wait`), the paper's collision waiting decides; `gate` keeps its
/// decisions and adds crossings taken one at a time; `reserve` decides alone, then sorts the
/// robots into the collision grid, which the contact count reads after the moves. Robots
/// step into and out of their bays first (`bays`, settled here because under `reserve` a
/// robot leaves its bay only where its lane has room); robots in a bay are out of the
/// traffic. [`moves`] reads the answer.
pub(crate) fn decide(traffic: Option<&mut TrafficState>, collisions: &mut Collisions, bays: &mut Bays, r: &mut Robots, scene: &Scene<'_>) {
    let reserve = traffic.as_ref().is_some_and(|ts| ts.policy == Traffic::Reserve);
    if !reserve {
        // Under collision waiting a robot leaves its bay when it wants to: it steps back onto
        // its lane whoever is passing (the cone then decides, and a contact is counted).
        bays.settle(r, scene.graph, |x, y, radius| scene.clear(x, y, radius));
    }
    let (wants, margin, angle) = (scene.wants, scene.margin, scene.angle);
    let Some(ts) = traffic else {
        collisions.resolve(&r.x, &r.y, &r.radius, wants, &r.heading, bays.flags(), margin, angle);
        return;
    };
    let cone = if ts.policy == Traffic::Gate {
        collisions.resolve(&r.x, &r.y, &r.radius, wants, &r.heading, bays.flags(), margin, angle);
        Some(&collisions.waits[..])
    } else {
        None
    };
    ts.decide(r, bays, cone, scene);
    if reserve {
        // Robots waiting to leave a bay are still in it; the grid serves to count contacts
        // after the moves.
        collisions.build_grid(&r.x, &r.y, &r.radius, bays.flags());
    }
}

/// The answer of [`decide`] for the first `n` robots: who waits, and how far each may travel
/// (`None`: its full speed, under collision waiting alone).
pub(crate) fn moves<'a>(traffic: Option<&'a TrafficState>, collisions: &'a Collisions, n: usize) -> (&'a [bool], Option<&'a [f64]>) {
    match traffic {
        None => (&collisions.waits[..n], None),
        Some(ts) => (&ts.waits[..n], Some(&ts.budget[..n])),
    }
}

/// The state of the `gate` and `reserve` policies.
#[derive(Clone, Debug)]
pub(crate) struct TrafficState {
    pub policy: Traffic,
    /// Zone radius: the largest contact distance, 2 r_max + margin.
    zone: f64,
    margin: f64,
    lanes: Lanes,
    /// Per node: how many robots were admitted into the zone this step, the lane they came
    /// from and the lane they leave on (a platoon shares both).
    admitted_count: Vec<u32>,
    admitted_from: Vec<u32>,
    admitted_exit: Vec<u32>,
    admitted_nodes: Vec<u32>,
    /// Robots asking to enter a zone this step, and the step each began to wait for one.
    requests: Vec<u32>,
    waiting_since: Vec<u64>,
    /// Consecutive steps a robot was refused for a full exit.
    exit_refusals: Vec<u32>,
    ahead: Vec<Option<Ahead>>,
    /// Output: how far each robot may travel, and who waits.
    pub budget: Vec<f64>,
    pub waits: Vec<bool>,
}

impl TrafficState {
    pub fn new(policy: Traffic, g: &HighwayGraph, robots: usize, radius_max: f64, margin: f64) -> TrafficState {
        TrafficState {
            policy,
            zone: 2.0 * radius_max + margin,
            margin,
            lanes: Lanes::new(robots, g.edge_count(), g.len()),
            admitted_count: vec![0; g.len()],
            admitted_from: vec![NONE; g.len()],
            admitted_exit: vec![NONE; g.len()],
            admitted_nodes: Vec::with_capacity(robots),
            requests: Vec::with_capacity(robots),
            waiting_since: vec![u64::MAX; robots],
            exit_refusals: vec![0; robots],
            ahead: vec![None; robots],
            budget: vec![0.0; robots],
            waits: vec![false; robots],
        }
    }

    /// Decides how far each robot that wants to move may travel this step (`budget`), and
    /// who waits. Robots in a bay (`bays`) are out of the traffic. For `gate`, `cone_waits`
    /// are the collision-waiting rule's decisions, which it keeps.
    fn decide(&mut self, r: &mut Robots, bays: &mut Bays, cone_waits: Option<&[bool]>, scene: &Scene<'_>) {
        let (g, t, wants, people) = (scene.graph, scene.t, scene.wants, scene.people);
        let n = r.len();
        if self.policy == Traffic::Reserve {
            self.rejoin(r, g, bays);
            // Robots step aside, or back onto a lane with room, before the lanes are read.
            bays.settle(r, g, |x, y, radius| scene.clear(x, y, radius));
        }
        self.lanes.build(r, g, self.zone, bays.flags());
        for &k in &self.admitted_nodes {
            self.admitted_count[k as usize] = 0;
        }
        self.admitted_nodes.clear();
        self.requests.clear();
        // Desired moves, and who asks to enter a zone.
        for i in 0..n {
            self.waits[i] = false;
            self.ahead[i] = None;
            // A robot stopped for a person stands, and one slowed near a person moves less:
            // the robots behind it must know before they move (under `reserve`).
            let halted = people.is_some_and(|p| p.stop[i]);
            let moving = wants[i] && !halted && cone_waits.map_or(true, |w| !w[i]) && self.lanes.edge_of[i] != NONE;
            if !moving {
                self.budget[i] = 0.0;
                continue;
            }
            let mut a = self.lanes.ahead_of(r, g, i);
            let mut give_way = false;
            if self.policy == Traffic::Reserve {
                if r.at_node[i] != NONE {
                    give_way = !self.spur_clear(g, self.lanes.edge_of[i]);
                } else if a.v != NONE && a.e2 != NONE && a.stop < self.zone && !self.spur_clear(g, a.e2) {
                    // Inside the crossing's zone already (sent to a charger on its way
                    // through), with the charger's spur in use: it goes round instead.
                    give_way = !self.detour(r, g, i, &a);
                    a = self.lanes.ahead_of(r, g, i);
                }
            }
            let mut d = match people {
                Some(p) if p.slow[i] => r.speed[i] * p.slow_factor,
                _ => r.speed[i],
            };
            if a.v == NONE || a.e2 == NONE {
                d = d.min(a.stop);
            } else {
                // Never into the zone beyond the next crossing in the same step.
                d = d.min(a.stop + (a.len2 - self.zone).max(0.0)).min(a.stop + a.stop2);
            }
            if give_way {
                // Bound for a charger whose spur another robot is leaving by: it waits, or
                // (on the crossing) goes round from the next step.
                d = 0.0;
                if r.at_node[i] != NONE {
                    self.exit_refusals[i] = DETOUR_AFTER;
                }
            }
            self.budget[i] = d;
            self.ahead[i] = Some(a);
            if a.v != NONE && a.stop >= self.zone && a.stop - d < self.zone {
                self.requests.push(i as u32);
            }
        }
        self.admit(r, g, t);
        if self.policy == Traffic::Reserve {
            self.follow(r);
        }
        if self.policy == Traffic::Reserve {
            self.leave_stuck_nodes(r, g, wants);
        }
        for ((b, w), &want) in self.budget.iter_mut().zip(self.waits.iter_mut()).zip(&wants[..n]) {
            if want && *b <= 0.0 {
                *b = 0.0;
                *w = true;
            }
        }
    }

    /// Robots leaving a bay join their lane only where it has room: a contact distance to the
    /// robots ahead and behind; until then they stay in the bay.
    fn rejoin(&mut self, r: &Robots, g: &HighwayGraph, bays: &mut Bays) {
        if !bays.exist() {
            return;
        }
        let n = r.len();
        // Joining: standing in a bay (where it is, not what it did last step: a step back a
        // person refused leaves it there) and no longer to be in one.
        let joining: Vec<usize> = (0..n).filter(|&i| r.in_bay(i) && !bays.holds(i)).collect();
        if !joining.is_empty() {
            for &i in &joining {
                bays.keep(i, true);
            }
            self.lanes.build(r, g, self.zone, bays.flags());
            for &i in &joining {
                if r.at_node[i] != NONE {
                    bays.keep(i, false);
                    continue;
                }
                let e = g.edge_id(r.edge_u[i], r.edge_v[i]);
                let (ux, uy) = g.pos(g.edge(e).0);
                let (x, y) = r.on_lane(i);
                let s = crate::fleet::motion::axis_dist(x - ux, y - uy);
                let clear = self.lanes.lane(e).iter().all(|&j| (self.lanes.s[j as usize] - s).abs() >= r.radius[i] + r.radius[j as usize] + self.margin);
                let (_, v, len) = g.edge(e);
                let zones_free =
                    (s >= self.zone || self.lanes.holder[g.edge(e).0 as usize] == NONE) && (len - s >= self.zone || self.lanes.holder[v as usize] == NONE);
                bays.keep(i, !(clear && zones_free));
            }
        }
    }

    /// Zone admissions, longest-waiting first: a robot enters a free zone when its exit lane
    /// has room for it beyond the zone; refused, it stops at the zone's edge.
    fn admit(&mut self, r: &mut Robots, g: &HighwayGraph, t: u64) {
        let ws = &self.waiting_since;
        self.requests.sort_unstable_by_key(|&i| (ws[i as usize], i));
        for k in 0..self.requests.len() {
            let i = self.requests[k] as usize;
            let a = self.ahead[i].expect("requests have a look-ahead");
            let v = a.v as usize;
            let (mut free, mut exit_ok) = self.may_enter(r, g, i, &a);
            if self.policy == Traffic::Gate {
                // The cheap rule: one robot in a crossing at a time, no exit check, and a
                // robot refused for long goes anyway (the collision waiting then applies), so
                // the gate never deadlocks.
                exit_ok = true;
                let since = self.waiting_since[i];
                if !free && since != u64::MAX && t - since >= GATE_PATIENCE {
                    free = true;
                }
            }
            if free && exit_ok {
                if self.admitted_count[v] == 0 {
                    self.admitted_nodes.push(v as u32);
                    self.admitted_from[v] = self.lanes.edge_of[i];
                    self.admitted_exit[v] = a.e2;
                }
                self.admitted_count[v] += 1;
                self.waiting_since[i] = u64::MAX;
                self.exit_refusals[i] = 0;
                continue;
            }
            self.budget[i] = (a.stop - self.zone).max(0.0);
            if self.waiting_since[i] == u64::MAX {
                self.waiting_since[i] = t;
            }
            if free && !exit_ok {
                self.exit_refusals[i] += 1;
                if self.exit_refusals[i] >= DETOUR_AFTER && self.detour(r, g, i, &a) {
                    self.exit_refusals[i] = 0;
                }
            }
        }
    }

    /// Whether robot `i` may enter the zone of `a.v`, and whether its exit lane has room for
    /// it beyond the zone: (may, room). The zone must be free, or hold only robots going
    /// straight through the way `i` goes (a platoon on one line): robots already leaving it
    /// on `i`'s exit lane, and robots admitted this step from `i`'s own lane onto the same
    /// exit. The room counts them all. A route that ends in the zone needs no exit, and so
    /// joins no platoon.
    fn may_enter(&self, r: &Robots, g: &HighwayGraph, i: usize, a: &Ahead) -> (bool, bool) {
        let v = a.v as usize;
        let ends_here = a.e2 == NONE || a.stop2 < self.zone;
        let (in_zone, admitted) = (self.lanes.count[v], self.admitted_count[v]);
        if in_zone == 0 && admitted == 0 {
            return (true, ends_here || self.room_on(r, g, i, a.e2));
        }
        let e = self.lanes.edge_of[i];
        let platoon = !ends_here
            && straight(g, e, a.e2)
            && (in_zone == 0 || self.lanes.leaving[v] == a.e2)
            && (admitted == 0 || (self.admitted_from[v] == e && self.admitted_exit[v] == a.e2));
        if !platoon {
            return (false, false);
        }
        let gap = 2.0 * r.radius[i] + self.margin;
        let need = self.zone + gap * f64::from(in_zone + admitted + 1);
        let p = self.lanes.last_beyond(a.e2, self.zone);
        let room = if p == NONE { a.len2 - self.zone >= need } else { self.lanes.s[p as usize] >= need };
        (true, room && self.spur_clear(g, a.e2))
    }

    fn room_on(&self, r: &Robots, g: &HighwayGraph, i: usize, e: u32) -> bool {
        let tail = self.lanes.tail(e);
        (tail == NONE || tail as usize == i || self.lanes.s[tail as usize] >= self.zone + r.radius[i] + r.radius[tail as usize] + self.margin)
            && self.spur_clear(g, e)
    }

    /// Whether edge `e`, when it leads into a charger's spur (the only two-way edges, and a
    /// dead end: the robot leaving the charger and the one coming to it would meet head-on
    /// and stand there for good), has nobody coming back along it and nobody at the charger.
    /// Aisles are one way, and a spur out of a charger leads to a crossing: always clear.
    fn spur_clear(&self, g: &HighwayGraph, e: u32) -> bool {
        let (u, w, _) = g.edge(e);
        let back = g.edge_id(w, u);
        back == NONE || g.out(w as usize).len() > 1 || (self.lanes.lane(back).is_empty() && self.lanes.holder[w as usize] == NONE)
    }

    /// Another exit from `a.v` with room, not a charger's dead end: robot `i` will take it.
    fn detour(&self, r: &mut Robots, g: &HighwayGraph, i: usize, a: &Ahead) -> bool {
        if a.v == r.goal[i] {
            return false;
        }
        for e in g.out_edges(a.v) {
            let (_, w, _) = g.edge(e);
            if e == a.e2 || !may_detour_to(g, a.v, w, self.exit_refusals[i]) && w != r.goal[i] {
                continue;
            }
            if self.room_on(r, g, i, e) {
                if r.via.len() <= i {
                    r.via.resize(r.len(), NONE);
                }
                r.via[i] = w;
                return true;
            }
        }
        false
    }

    /// A robot standing on a node (after unloading, or leaving a charger) whose exit lane has
    /// stayed full for [`DETOUR_AFTER`] steps takes another exit with room: it must not hold
    /// the crossing while the lanes around wait for it.
    #[allow(clippy::needless_range_loop)] // robot ids index several columns
    fn leave_stuck_nodes(&mut self, r: &mut Robots, g: &HighwayGraph, wants: &[bool]) {
        for i in 0..r.len() {
            if !(wants[i] && r.at_node[i] != NONE && self.lanes.edge_of[i] != NONE) {
                continue;
            }
            if self.budget[i] > 0.0 && !self.waits[i] {
                self.exit_refusals[i] = 0;
                continue;
            }
            self.exit_refusals[i] += 1;
            if self.exit_refusals[i] < DETOUR_AFTER {
                continue;
            }
            let v = r.at_node[i];
            let current = self.lanes.edge_of[i];
            for e in g.out_edges(v) {
                let (_, w, _) = g.edge(e);
                if e == current || !may_detour_to(g, v, w, self.exit_refusals[i]) && w != r.goal[i] {
                    continue;
                }
                if self.room_on(r, g, i, e) {
                    crate::fleet::route::detour_at_node(r, g, i, w);
                    self.exit_refusals[i] = 0;
                    break;
                }
            }
        }
    }

    /// Along each lane, front first: a robot keeps the contact distance to the robot ahead
    /// after that robot's move, and to the last robot of its exit lane, measured through the
    /// node (as that robot stood at the start of the step, since it only moves away).
    fn follow(&mut self, r: &Robots) {
        for e in 0..self.lanes.edges() as u32 {
            let lane = self.lanes.lane(e);
            for (k, &i) in lane.iter().enumerate() {
                let i = i as usize;
                let Some(a) = self.ahead[i] else { continue };
                let mut d = self.budget[i];
                if k > 0 {
                    let j = lane[k - 1] as usize;
                    let gap = r.radius[i] + r.radius[j] + self.margin;
                    // The robot ahead is still on this lane after its move unless it crossed
                    // the node, in which case the zone keeps `i` back.
                    let sj = self.lanes.s[j] + self.budget[j];
                    if sj <= a.len {
                        d = d.min(sj - gap - a.s);
                    }
                }
                // Across the node too, even short of it: the robot ahead may have stopped
                // just past the node (for a person) while this one is in the zone behind it.
                if a.v != NONE && a.e2 != NONE {
                    let tail = self.lanes.tail(a.e2);
                    if tail != NONE && tail as usize != i {
                        let gap = r.radius[i] + r.radius[tail as usize] + self.margin;
                        d = d.min(a.stop + self.lanes.s[tail as usize] - gap);
                    }
                }
                self.budget[i] = d.max(0.0);
            }
        }
    }
}
