//! Where every robot is on the highway, as traffic policies see it: the directed edge it
//! drives along and how far along it is (lanes, ordered front first), the crossing zones it
//! occupies, and what lies ahead on its route (the next node and the edge after it).

use crate::fleet::robot::Robots;
use crate::ids::NONE;
use crate::world::graph::HighwayGraph;

/// Robots by lane, and the crossing zones they hold, for one step.
#[derive(Clone, Debug, Default)]
pub(crate) struct Lanes {
    /// Per robot: the edge id it drives along (or stands on), or `NONE` (at a node and not
    /// leaving it, or in a bay), and its distance from the edge's tail.
    pub edge_of: Vec<u32>,
    pub s: Vec<f64>,
    /// Per edge: where its robots start in `order` (edges + 1 entries).
    start: Vec<u32>,
    /// Robots by edge, front (largest `s`) first.
    order: Vec<u32>,
    /// Per robot: its index in `order`, or `NONE`.
    rank: Vec<u32>,
    /// Per node: the robot whose centre lies in the node's zone, `NONE`, or `CROWDED`.
    pub holder: Vec<u32>,
    /// Per node with robots in its zone: how many, and the edge they are all leaving the
    /// node on (`NONE` when any of them is arriving, standing on the node, or on another
    /// edge). Straight-through platoons follow such robots into the zone.
    pub count: Vec<u32>,
    pub leaving: Vec<u32>,
    held: Vec<u32>,
    fill: Vec<u32>,
}

/// More than one robot in a zone (never under `reserve`, but possible at the start).
pub(crate) const CROWDED: u32 = NONE - 1;

/// What lies ahead of a robot on its route.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ahead {
    /// The length of the edge it is on, and how far along it the robot is.
    pub len: f64,
    pub s: f64,
    /// The node at the end of the edge, or `NONE` when the route ends on this edge (at its
    /// final point, `stop` px ahead).
    pub v: u32,
    pub stop: f64,
    /// The edge after `v`, or `NONE` when the route ends at `v`; its length, and how far
    /// along it the route ends (`f64::INFINITY`: beyond it).
    pub e2: u32,
    pub len2: f64,
    pub stop2: f64,
}

impl Lanes {
    pub fn new(robots: usize, edges: usize, nodes: usize) -> Lanes {
        Lanes {
            edge_of: vec![NONE; robots],
            s: vec![0.0; robots],
            start: vec![0; edges + 1],
            order: Vec::with_capacity(robots),
            rank: vec![NONE; robots],
            holder: vec![NONE; nodes],
            count: vec![0; nodes],
            leaving: vec![NONE; nodes],
            held: Vec::with_capacity(robots),
            fill: vec![0; edges + 1],
        }
    }

    /// Places every robot not in a bay (`out[i]`; empty: nobody is) on its lane and in its
    /// zones.
    #[allow(clippy::needless_range_loop)] // robot ids index several columns
    pub fn build(&mut self, r: &Robots, g: &HighwayGraph, zone: f64, out: &[bool]) {
        let n = r.len();
        for &k in &self.held {
            self.holder[k as usize] = NONE;
            self.count[k as usize] = 0;
            self.leaving[k as usize] = NONE;
        }
        self.held.clear();
        let (holder, count, leaving, held) = (&mut self.holder, &mut self.count, &mut self.leaving, &mut self.held);
        // `on`: the edge the robot is leaving the node on, or NONE.
        let mut hold = |k: u32, i: usize, on: u32| {
            let k = k as usize;
            if holder[k] == NONE {
                held.push(k as u32);
                holder[k] = i as u32;
                leaving[k] = on;
            } else {
                holder[k] = CROWDED;
                if leaving[k] != on {
                    leaving[k] = NONE;
                }
            }
            count[k] += 1;
        };
        for i in 0..n {
            self.edge_of[i] = NONE;
            self.rank[i] = NONE;
            if !out.is_empty() && out[i] {
                continue;
            }
            if r.at_node[i] != NONE {
                hold(r.at_node[i], i, NONE);
                if r.routing[i] && r.edge_u[i] == r.at_node[i] {
                    self.edge_of[i] = g.edge_id(r.edge_u[i], r.edge_v[i]);
                    self.s[i] = 0.0;
                }
                continue;
            }
            let e = g.edge_id(r.edge_u[i], r.edge_v[i]);
            let (u, v, len) = g.edge(e);
            let (ux, uy) = g.pos(u);
            let s = crate::fleet::motion::axis_dist(r.x[i] - ux, r.y[i] - uy);
            self.edge_of[i] = e;
            self.s[i] = s;
            if s < zone {
                hold(u, i, e);
            }
            if len - s < zone {
                hold(v, i, NONE);
            }
        }
        // Robots by edge (a counting sort), then front first within each edge.
        self.start.fill(0);
        for i in 0..n {
            if self.edge_of[i] != NONE {
                self.start[self.edge_of[i] as usize + 1] += 1;
            }
        }
        for k in 1..self.start.len() {
            self.start[k] += self.start[k - 1];
        }
        self.order.clear();
        self.order.resize(self.start[self.start.len() - 1] as usize, NONE);
        self.fill.copy_from_slice(&self.start);
        for i in 0..n {
            let e = self.edge_of[i];
            if e != NONE {
                self.order[self.fill[e as usize] as usize] = i as u32;
                self.fill[e as usize] += 1;
            }
        }
        let s = &self.s;
        for e in 0..self.start.len() - 1 {
            let lane = &mut self.order[self.start[e] as usize..self.start[e + 1] as usize];
            if lane.len() > 1 {
                // Ties (never under `reserve`) by id, so the order is deterministic.
                lane.sort_unstable_by(|&a, &b| s[b as usize].total_cmp(&s[a as usize]).then(a.cmp(&b)));
            }
        }
        for (k, &i) in self.order.iter().enumerate() {
            self.rank[i as usize] = k as u32;
        }
    }

    /// The robots of edge `e`, front first.
    pub fn lane(&self, e: u32) -> &[u32] {
        &self.order[self.start[e as usize] as usize..self.start[e as usize + 1] as usize]
    }

    /// The rearmost robot of edge `e` at least `from` px along it, or `NONE`.
    pub fn last_beyond(&self, e: u32, from: f64) -> u32 {
        self.lane(e).iter().rev().copied().find(|&j| self.s[j as usize] >= from).unwrap_or(NONE)
    }

    /// The robot nearest the tail of edge `e` (the last in its lane), or `NONE`.
    pub fn tail(&self, e: u32) -> u32 {
        self.lane(e).last().copied().unwrap_or(NONE)
    }

    /// The number of edges.
    pub fn edges(&self) -> usize {
        self.start.len() - 1
    }

    /// What lies ahead of robot `i` (on a lane, routing).
    pub fn ahead_of(&self, r: &Robots, g: &HighwayGraph, i: usize) -> Ahead {
        let e = self.edge_of[i];
        let (_, v, len) = g.edge(e);
        let s = self.s[i];
        if r.wp_node[i] == NONE {
            // The final point lies on this edge.
            let stop = crate::fleet::motion::axis_dist(r.final_x[i] - r.x[i], r.final_y[i] - r.y[i]);
            return Ahead { len, s, v: NONE, stop, e2: NONE, len2: 0.0, stop2: 0.0 };
        }
        let goal = r.goal[i];
        let (e2, stop2) = if v == goal {
            if r.has_final[i] {
                let (vx, vy) = g.pos(v);
                (g.edge_id(v, r.final_v[i]), crate::fleet::motion::axis_dist(r.final_x[i] - vx, r.final_y[i] - vy))
            } else {
                (NONE, 0.0)
            }
        } else {
            let via = r.via.get(i).copied().unwrap_or(NONE);
            let w = if via == NONE { g.next_hop(crate::ids::NodeId(v), crate::ids::NodeId(goal)).map_or(NONE, |w| w.0) } else { via };
            (g.edge_id(v, w), f64::INFINITY)
        };
        let len2 = if e2 == NONE { 0.0 } else { g.edge(e2).2 };
        Ahead { len, s, v, stop: len - s, e2, len2, stop2 }
    }
}
