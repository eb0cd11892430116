//! Routes (spec section 3) and motion along them (spec phase 4).
//!
//! A route is not stored as a list of waypoints: a robot keeps its current waypoint, the goal
//! node of its node path and an optional final point (a service point) beyond that goal. Each
//! time it reaches a node it looks up the next one in the graph's next-hop table. That gives
//! the same polyline as the spec's, with no allocation and no search per route.

#[cfg(test)]
use crate::fleet::motion::Motion;
use crate::fleet::robot::{Robots, Target};
use crate::ids::{CellId, NodeId, NONE};
use crate::world::graph::HighwayGraph;
use crate::world::layout::Layout;

/// Distance between two points.
#[inline]
#[must_use]
pub fn dist(ax: f64, ay: f64, bx: f64, by: f64) -> f64 {
    let (dx, dy) = (bx - ax, by - ay);
    (dx * dx + dy * dy).sqrt()
}

/// Whether point `p` lies strictly ahead of `(x, y)` along the direction `u -> v`.
fn strictly_ahead(g: &HighwayGraph, u: u32, v: u32, x: f64, y: f64, px: f64, py: f64) -> bool {
    let (ux, uy) = g.pos(u);
    let (vx, vy) = g.pos(v);
    (px - x) * (vx - ux) + (py - y) * (vy - uy) > 0.0
}

/// Where a robot is, for planning: on a node, or strictly inside the directed edge `(u, v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Place {
    pub x: f64,
    pub y: f64,
    pub at_node: u32,
    pub edge_u: u32,
    pub edge_v: u32,
}

impl Place {
    /// The place of robot `i`.
    #[must_use]
    pub fn of(r: &Robots, i: usize) -> Place {
        // A robot in a bay leaves it where it stepped aside: routes start on the lane.
        let (x, y) = r.on_lane(i);
        Place { x, y, at_node: r.at_node[i], edge_u: r.edge_u[i], edge_v: r.edge_v[i] }
    }

    /// Standing on node `n`.
    #[must_use]
    pub fn node(g: &HighwayGraph, n: NodeId) -> Place {
        let (x, y) = g.pos(n.0);
        Place { x, y, at_node: n.0, edge_u: NONE, edge_v: NONE }
    }
}

/// A planned route: the first waypoint, then the node path to `goal`, then the final point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Plan {
    /// `false` for a route of length zero (already at the target).
    pub moving: bool,
    pub wp_x: f64,
    pub wp_y: f64,
    /// The first waypoint's node, or `NONE` when it is the final point.
    pub wp_node: u32,
    /// The edge the robot moves along first.
    pub edge_u: u32,
    pub edge_v: u32,
    pub goal: u32,
    pub has_final: bool,
    pub final_x: f64,
    pub final_y: f64,
    pub final_v: u32,
}

/// Plans the spec's route from a place to a target.
#[must_use]
pub(crate) fn plan(g: &HighwayGraph, from: Place, target: Target) -> Plan {
    let (goal, has_final, fx, fy, fv) = match target {
        Target::Node(t) => (t.0, false, 0.0, 0.0, NONE),
        Target::Point { u, v, x, y } => (u.0, true, x, y, v.0),
    };
    let mut p = Plan { moving: true, wp_x: 0.0, wp_y: 0.0, wp_node: NONE, edge_u: NONE, edge_v: NONE, goal, has_final, final_x: fx, final_y: fy, final_v: fv };
    let direct = |p: &mut Plan, u: u32| {
        p.wp_x = fx;
        p.wp_y = fy;
        p.wp_node = NONE;
        p.edge_u = u;
        p.edge_v = fv;
    };
    let via = |p: &mut Plan, from: u32, next: u32| {
        let (x, y) = g.pos(next);
        p.wp_x = x;
        p.wp_y = y;
        p.wp_node = next;
        p.edge_u = from;
        p.edge_v = next;
    };
    if has_final && from.x == fx && from.y == fy {
        p.moving = false;
        return p;
    }
    if from.at_node == NONE {
        let (u, v) = (from.edge_u, from.edge_v);
        if has_final && goal == u && fv == v && strictly_ahead(g, u, v, from.x, from.y, fx, fy) {
            direct(&mut p, u);
        } else {
            via(&mut p, u, v);
        }
    } else {
        let u = from.at_node;
        if u == goal {
            if has_final {
                direct(&mut p, u);
            } else {
                p.moving = false;
            }
        } else {
            let next = g.next_hop(NodeId(u), NodeId(goal)).map_or(NONE, |n| n.0);
            debug_assert!(next != NONE, "validated layouts are strongly connected");
            via(&mut p, u, next);
        }
    }
    p
}

/// Route length from a place to `target`, whose distances from every node (`row`, from
/// [`HighwayGraph::lengths_to`]) are known: the same figure as [`length`], without walking the
/// node path. For choices made inside the step loop (the nearest charger, unloading zone).
#[must_use]
pub(crate) fn length_via_row(g: &HighwayGraph, from: Place, target: NodeId, row: &[f64]) -> f64 {
    let p = plan(g, from, Target::Node(target));
    if !p.moving {
        return 0.0;
    }
    dist(from.x, from.y, p.wp_x, p.wp_y) + row[p.wp_node as usize]
}

/// Gives robot `i` the route to `target`; returns whether it has anywhere to go.
pub fn assign(r: &mut Robots, g: &HighwayGraph, i: usize, target: Target) -> bool {
    let p = plan(g, Place::of(r, i), target);
    r.routing[i] = p.moving;
    r.goal[i] = p.goal;
    r.has_final[i] = p.has_final;
    r.final_x[i] = p.final_x;
    r.final_y[i] = p.final_y;
    r.final_v[i] = p.final_v;
    if p.moving {
        r.wp_x[i] = p.wp_x;
        r.wp_y[i] = p.wp_y;
        r.wp_node[i] = p.wp_node;
        if r.at_node[i] != NONE {
            // Leaving a node: the robot is now on the first edge of the route.
            r.edge_u[i] = p.edge_u;
            r.edge_v[i] = p.edge_v;
        }
    }
    p.moving
}

/// Sends robot `i`, standing on a node with a route under way, along the edge to `w`
/// instead of the route's first edge (a detour, for traffic policies); the route continues
/// from `w` to its goal.
pub(crate) fn detour_at_node(r: &mut Robots, g: &HighwayGraph, i: usize, w: u32) {
    debug_assert!(r.at_node[i] != NONE && r.routing[i]);
    let (x, y) = g.pos(w);
    r.wp_x[i] = x;
    r.wp_y[i] = y;
    r.wp_node[i] = w;
    r.edge_u[i] = r.at_node[i];
    r.edge_v[i] = w;
}

/// Length in px of the planned route.
#[must_use]
pub fn length(g: &HighwayGraph, from: Place, target: Target) -> f64 {
    let p = plan(g, from, target);
    if !p.moving {
        return 0.0;
    }
    let first = dist(from.x, from.y, p.wp_x, p.wp_y);
    if p.wp_node == NONE {
        return first;
    }
    let mut total = first + g.path_length(NodeId(p.wp_node), NodeId(p.goal));
    if p.has_final {
        let (gx, gy) = g.pos(p.goal);
        total += dist(gx, gy, p.final_x, p.final_y);
    }
    total
}

/// The waypoints of the planned route, starting with the place itself.
#[must_use]
pub fn waypoints(g: &HighwayGraph, from: Place, target: Target) -> Vec<(f64, f64)> {
    let p = plan(g, from, target);
    let fin = p.has_final.then_some((p.final_x, p.final_y));
    polyline(g, (from.x, from.y), p.moving.then_some((p.wp_x, p.wp_y, p.wp_node)), p.goal, fin)
}

/// The remaining waypoints of robot `i`'s route, starting at its position.
#[must_use]
pub fn remaining(r: &Robots, g: &HighwayGraph, i: usize) -> Vec<(f64, f64)> {
    let fin = r.has_final[i].then_some((r.final_x[i], r.final_y[i]));
    polyline(g, (r.x[i], r.y[i]), r.routing[i].then_some((r.wp_x[i], r.wp_y[i], r.wp_node[i])), r.goal[i], fin)
}

/// A route as points: the start, the current waypoint, the node path on to `goal` when the
/// waypoint is a node, then the final point.
fn polyline(g: &HighwayGraph, start: (f64, f64), waypoint: Option<(f64, f64, u32)>, goal: u32, fin: Option<(f64, f64)>) -> Vec<(f64, f64)> {
    let mut pts = vec![start];
    let Some((wx, wy, node)) = waypoint else {
        return pts;
    };
    pts.push((wx, wy));
    if node != NONE {
        let mut at = node;
        while at != goal {
            at = g.next_hop(NodeId(at), NodeId(goal)).map_or(goal, |n| n.0);
            pts.push(g.pos(at));
        }
        pts.extend(fin);
    }
    pts
}

/// Moves robot `i` up to `budget` px along its route, through waypoints without losing
/// distance, stopping exactly at the route's end. Returns the distance travelled. (The
/// step moves robots through [`Motion`] directly; this serves the tests.)
#[cfg(test)]
pub(crate) fn advance(r: &mut Robots, g: &HighwayGraph, i: usize, budget: f64) -> f64 {
    Motion::of(r).advance(g, i, budget)
}

/// The highway-graph nodes a planned route passes, in order (its start node too, if it
/// starts on one).
pub(crate) fn route_nodes(g: &HighwayGraph, from: Place, target: Target, out: &mut Vec<u32>) {
    let p = plan(g, from, target);
    if from.at_node != NONE {
        out.push(from.at_node);
    }
    if !p.moving || p.wp_node == NONE {
        return;
    }
    let goal = NodeId(p.goal);
    let mut at = NodeId(p.wp_node);
    out.push(at.0);
    while at != goal {
        match g.next_hop(at, goal) {
            Some(v) => at = v,
            None => break,
        }
        out.push(at.0);
    }
}

/// The service point of a cell as a route target.
#[must_use]
pub fn service_target(layout: &Layout, cell: CellId) -> Target {
    let c = &layout.cells[cell.index()];
    Target::Point { u: c.edge.0, v: c.edge.1, x: c.service.0, y: c.service.1 }
}

/// Standing at a cell's service point, as a place to plan from.
#[must_use]
pub(crate) fn service_place(layout: &Layout, cell: CellId) -> Place {
    let c = &layout.cells[cell.index()];
    Place { x: c.service.0, y: c.service.1, at_node: NONE, edge_u: c.edge.0 .0, edge_v: c.edge.1 .0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::world::layout::Layout;

    fn setup() -> (Layout, HighwayGraph) {
        let l = Layout::paper();
        let g = HighwayGraph::new(&l);
        (l, g)
    }

    fn service(l: &Layout, cell: usize) -> Target {
        let c = &l.cells[cell];
        Target::Point { u: c.edge.0, v: c.edge.1, x: c.service.0, y: c.service.1 }
    }

    #[test]
    fn worked_example_route_lengths() {
        let (l, g) = setup();
        let ch0 = l.node_named("CH0").unwrap();
        let d1 = length(&g, Place::node(&g, ch0), service(&l, 42));
        assert_eq!(d1, 1290.0);
        let at_point = Place { x: 325.0, y: 375.0, at_node: NONE, edge_u: l.node_named("O").unwrap().0, edge_v: l.node_named("I").unwrap().0 };
        let m = l.node_named("M").unwrap();
        assert_eq!(length(&g, at_point, Target::Node(m)), 950.0);
        assert_eq!(length(&g, Place::node(&g, m), Target::Node(ch0)), 540.0);
        let pts = waypoints(&g, at_point, Target::Node(m));
        assert_eq!(pts, vec![(325.0, 375.0), (325.0, 275.0), (475.0, 275.0), (475.0, 525.0), (325.0, 525.0), (175.0, 525.0), (25.0, 525.0)]);
    }

    #[test]
    fn inside_an_edge_goes_straight_to_a_target_ahead_and_round_otherwise() {
        let (l, g) = setup();
        let o = l.node_named("O").unwrap();
        let i_ = l.node_named("I").unwrap();
        // Standing at cell 42's point (325, 375) on O -> I; cell 40's point (325, 325) is ahead.
        let here = Place { x: 325.0, y: 375.0, at_node: NONE, edge_u: o.0, edge_v: i_.0 };
        assert_eq!(length(&g, here, service(&l, 40)), 50.0);
        // Cell 44 (row b = 2, point (325, 425)) is behind: to I, round the block, up from O.
        let behind = service(&l, 44);
        let pts = waypoints(&g, here, behind);
        assert_eq!(pts[1], (325.0, 275.0));
        assert_eq!(*pts.last().unwrap(), (325.0, 425.0));
        assert_eq!(pts[pts.len() - 2], g.pos(o.0));
        // Already there: length zero.
        assert_eq!(length(&g, here, service(&l, 42)), 0.0);
    }

    #[test]
    fn charger_routes_use_the_spur_both_ways() {
        let (l, g) = setup();
        let ch1 = l.node_named("CH1").unwrap();
        let ch0 = l.node_named("CH0").unwrap();
        let pts = waypoints(&g, Place::node(&g, ch1), Target::Node(ch0));
        // Down CH1's spur to B, round through the warehouse to A, up CH0's spur.
        assert_eq!(pts[1], (175.0, 25.0));
        assert_eq!(*pts.last().unwrap(), (25.0, -15.0));
        assert_eq!(pts[pts.len() - 2], (25.0, 25.0));
        assert_eq!(length(&g, Place::node(&g, ch0), Target::Node(ch0)), 0.0);
    }

    #[test]
    fn motion_carries_distance_through_waypoints() {
        let (l, g) = setup();
        let mut r = Robots::default();
        let ch0 = l.node_named("CH0").unwrap();
        r.push(ch0, g.pos(ch0.0), ch0, 12.5, 4.0, 10.0);
        assert!(assign(&mut r, &g, 0, service(&l, 42)));
        let mut travelled = 0.0;
        let mut steps = 0;
        while r.routing[0] {
            travelled += advance(&mut r, &g, 0, 4.0);
            steps += 1;
        }
        assert_eq!(travelled, 1290.0);
        assert_eq!(steps, 323); // ceil(1290 / 4): no distance lost at the seven corners
        assert_eq!((r.x[0], r.y[0]), (325.0, 375.0));
        // 40 px down the spur is 10 steps; the 11th step turns the corner at A with 0 left.
        let mut r2 = Robots::default();
        r2.push(ch0, g.pos(ch0.0), ch0, 12.5, 4.0, 10.0);
        assign(&mut r2, &g, 0, service(&l, 42));
        for _ in 0..10 {
            advance(&mut r2, &g, 0, 4.0);
        }
        assert_eq!((r2.x[0], r2.y[0]), (25.0, 25.0));
        assert_eq!(r2.at_node[0], l.node_named("A").unwrap().0);
        advance(&mut r2, &g, 0, 4.0);
        assert_eq!((r2.x[0], r2.y[0]), (29.0, 25.0));
        // A budget that crosses a corner keeps its remainder: 3 px to B's corner, 3 px on.
        let mut r3 = Robots::default();
        r3.push(ch0, g.pos(ch0.0), ch0, 12.5, 7.0, 10.0);
        assign(&mut r3, &g, 0, service(&l, 42));
        for _ in 0..6 {
            advance(&mut r3, &g, 0, 7.0);
        }
        assert_eq!((r3.x[0], r3.y[0]), (27.0, 25.0));
    }
}
