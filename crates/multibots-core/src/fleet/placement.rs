//! Where robots start, where they park when there is no work, and where goods are delivered
//! (spec section 2, and the spread placement of `docs/model.md` section 7).
//!
//! - **Departure placement** (the paper): robot i starts on the charger of the i-th start
//!   node, which is its home; it parks there.
//! - **Spread placement** (big fleets): robots start idle on parking slots strictly inside
//!   the aisle edges, spread evenly over the warehouse; a robot's slot is where it parks and
//!   its home charger is the nearest one by route.
//! - **Unloading**: one zone for every cell (the layout's first, or a named one), or each
//!   cell's nearest zone.

use crate::error::{Error, Result};
use crate::fleet::robot::{Robots, Target};
use crate::fleet::route::{self, Place};
use crate::ids::{NodeId, NONE};
use crate::input::scenario::{Placement, Scenario, Unload};
use crate::world::layout::Layout;
use crate::world::World;

/// Spread placement's parking slots, numbered in edge order: edge `e` holds slots
/// `first[e]..first[e + 1]`. Robot `i` of `n` parks on slot `i · total / n`, so its slot is
/// computed when needed from its edge and the edge's geometry: 4 bytes a robot where the
/// point took 24. (Idle robots are sent home often, to their slots: searching `first` for the
/// edge took 180 instructions a call, the layout's nodes 90; this takes about 40.)
#[derive(Clone, Debug)]
struct Park {
    first: Vec<u64>,
    /// Each edge's tail, head, tail position, head minus tail, and slots plus one.
    geometry: Vec<(NodeId, NodeId, [f64; 5])>,
    robots: usize,
    /// The edge of each robot's slot.
    edge_of: Vec<u32>,
}

impl Park {
    /// The slots `spacing` px or more apart of `layout`, for `n` robots: each robot's edge
    /// found once.
    fn new(layout: &Layout, spacing: f64, n: usize) -> Park {
        let first = parking_slots(layout, spacing);
        let geometry = layout
            .edges
            .iter()
            .zip(first.windows(2))
            .map(|(&(u, v), w)| {
                let ((ux, uy), (vx, vy)) = (layout.pos(u), layout.pos(v));
                (u, v, [ux, uy, vx - ux, vy - uy, (w[1] - w[0] + 1) as f64])
            })
            .collect();
        let mut park = Park { first, geometry, robots: n, edge_of: Vec::new() };
        if park.total() >= n as u64 {
            park.edge_of = (0..n).map(|i| (park.first.partition_point(|&f| f <= park.number(i)) - 1) as u32).collect();
        }
        park
    }

    fn total(&self) -> u64 {
        self.first.last().copied().unwrap_or(0)
    }

    /// The number of robot `i`'s slot.
    fn number(&self, i: usize) -> u64 {
        // `i · total` passes 64 bits only in absurd layouts: 128 bits then.
        let (i, total, n) = (i as u64, self.total(), self.robots as u64);
        i.checked_mul(total).map_or_else(|| (u128::from(i) * u128::from(total) / u128::from(n)) as u64, |p| p / n)
    }

    /// The slot of robot `i`: a point strictly inside a directed edge. Slot `k` of the `m`
    /// evenly spaced on an edge lies `k / (m + 1)` of the way along it.
    fn slot(&self, i: usize) -> (NodeId, NodeId, f64, f64) {
        let e = self.edge_of[i] as usize;
        let k = self.number(i) - self.first[e] + 1;
        let (u, v, [ux, uy, dx, dy, m1]) = self.geometry[e];
        let f = k as f64 / m1;
        (u, v, ux + dx * f, uy + dy * f)
    }
}

/// Where each robot parks and where each cell's goods are delivered.
#[derive(Clone, Debug)]
pub(crate) struct Homes {
    /// Spread placement's parking slots (`None` under departure placement, where robots
    /// park on their home charger).
    park: Option<Park>,
    /// The unloading zone allocators are told about (the first zone under `"nearest"`).
    pub unload: NodeId,
    /// The unloading zone of each cell's goods.
    unload_of_cell: Vec<NodeId>,
}

impl Homes {
    /// Where robot `i` parks: its parking slot (spread placement) or its home charger.
    pub fn target(&self, robots: &Robots, i: usize) -> Target {
        self.park.as_ref().map_or(Target::Node(robots.home[i]), |park| {
            let (u, v, x, y) = park.slot(i);
            Target::Point { u, v, x, y }
        })
    }

    /// Whether robot `i` stands where it parks (phase 8).
    pub fn at_home(&self, robots: &Robots, i: usize) -> bool {
        match &self.park {
            Some(park) => {
                robots.at_node[i] == NONE && {
                    let (_, _, x, y) = park.slot(i);
                    robots.on_lane(i) == (x, y)
                }
            }
            None => robots.at_node[i] == robots.home[i].0,
        }
    }

    /// Whether robots park on aisle slots (spread placement).
    pub fn spread(&self) -> bool {
        self.park.is_some()
    }

    /// The unloading zone of a cell's goods.
    pub fn unload_of(&self, cell: u32) -> NodeId {
        self.unload_of_cell[cell as usize]
    }
}

/// The unloading zone a scenario names, checked against the layout.
pub(crate) fn unload_zone(layout: &Layout, unload: &Unload) -> Result<NodeId> {
    let first = *layout.unloading.first().ok_or_else(|| Error::layout("unloading", "the layout has no unloading zone"))?;
    match unload {
        // `auto` is resolved before a run is built; alone, it means the first zone too.
        Unload::Auto | Unload::First | Unload::Nearest => Ok(first),
        Unload::Node(name) => {
            let zones = || layout.unloading.iter().map(|&n| layout.nodes[n.index()].name.as_str()).collect::<Vec<_>>();
            let hint = || format!("the unloading zones are {}; or \"nearest\"", listed(&zones()));
            let node = layout.node_named(name).ok_or_else(|| Error::scenario("unload", format!("\"{name}\""), format!("unknown node: {}", hint())))?;
            if !layout.unloading.contains(&node) {
                return Err(Error::scenario("unload", format!("\"{name}\""), format!("is not an unloading zone: {}", hint())));
            }
            Ok(node)
        }
    }
}

/// The start nodes of departure placement: the scenario's `starts`, or the layout's
/// departure zones in order.
pub(crate) fn start_nodes(layout: &Layout, scenario: &Scenario) -> Result<Vec<NodeId>> {
    let n = scenario.robots as usize;
    if scenario.placement == Placement::Spread {
        return Ok(Vec::new());
    }
    let Some(names) = &scenario.starts else {
        if n > layout.departure.len() {
            return Err(Error::scenario(
                "robots",
                n,
                format!("more robots than start nodes ({}); placement = \"spread\" parks any number of robots along the aisles", layout.departure.len()),
            ));
        }
        return Ok(layout.departure[..n].to_vec());
    };
    if names.len() != n {
        return Err(Error::scenario("starts", format!("{names:?}"), format!("names {} start nodes for {} robots", names.len(), n)));
    }
    let mut v = Vec::with_capacity(n);
    for (i, name) in names.iter().enumerate() {
        let node = layout.node_named(name).ok_or_else(|| {
            let near = crate::error::did_you_mean(name, layout.nodes.iter().map(|n| n.name.as_str()));
            let hint = near.map_or_else(
                || format!("the departure nodes are {}", listed(&layout.departure.iter().map(|&n| layout.nodes[n.index()].name.as_str()).collect::<Vec<_>>())),
                |n| format!("did you mean \"{n}\"?"),
            );
            Error::scenario(format!("starts[{i}]"), format!("\"{name}\""), format!("unknown node ({hint})"))
        })?;
        if !layout.departure.contains(&node) {
            return Err(Error::scenario(format!("starts[{i}]"), format!("\"{name}\""), "is not a departure zone"));
        }
        if v.contains(&node) {
            return Err(Error::scenario(format!("starts[{i}]"), format!("\"{name}\""), "start nodes must be distinct"));
        }
        v.push(node);
    }
    Ok(v)
}

/// Parking slots of spread placement: points strictly inside the highway edges, in edge
/// order, `spacing` px or more apart and from either end node, so that robots standing on
/// them neither block each other nor stand on a crossing.
fn parking_slots(layout: &Layout, spacing: f64) -> Vec<u64> {
    let mut first = Vec::with_capacity(layout.edges.len() + 1);
    let mut total = 0u64;
    first.push(0);
    for &(u, v) in &layout.edges {
        let (ux, uy) = layout.pos(u);
        let (vx, vy) = layout.pos(v);
        let len = route::dist(ux, uy, vx, vy);
        let m = (len / spacing).floor() as u64;
        total = total.saturating_add(m.saturating_sub(1));
        first.push(total);
    }
    first
}

/// The nearest of `zones` from `at` by route (ties: the first listed), given each zone's
/// distance row.
fn nearest(world: &World, at: Place, zones: &[NodeId], rows: &[Vec<f64>]) -> NodeId {
    let mut best = (f64::INFINITY, zones[0]);
    for (k, &z) in zones.iter().enumerate() {
        let d = route::length_via_row(&world.graph, at, z, &rows[k]);
        if d < best.0 {
            best = (d, z);
        }
    }
    best.1
}

/// The fleet at the start of a run, and where it parks and delivers.
pub(crate) fn place(world: &World, scenario: &Scenario, starts: &[NodeId], unload: NodeId) -> Result<(Robots, Homes)> {
    let layout = &world.layout;
    let g = &world.graph;
    let r = &scenario.robot;
    let n = scenario.robots as usize;
    let mut robots = Robots::default();
    for (i, &start) in starts.iter().enumerate() {
        let home = layout.charger_at(start).ok_or_else(|| {
            Error::scenario(format!("starts[{i}]"), format!("\"{}\"", layout.nodes[start.index()].name), "has no charger to be the robot's home")
        })?;
        robots.push(home, layout.pos(home), home, r.radius, r.speed, r.energy_full);
    }
    let mut park = None;
    if scenario.placement == Placement::Spread {
        // Slots far enough apart that no two parked robots touch, even with the margin.
        let spacing = layout.cell_size.max(2.0 * (2.0 * r.radius + scenario.collision.margin));
        let slots = Park::new(layout, spacing, n);
        if n as u64 > slots.total() {
            return Err(Error::scenario("robots", n, format!("more robots than parking slots ({}) in this layout: generate a larger one", slots.total())));
        }
        let rows: Vec<Vec<f64>> = layout.chargers.iter().map(|&c| g.lengths_to(c)).collect();
        for i in 0..n {
            // Evenly over the slots, so every part of the warehouse gets robots.
            let (u, v, x, y) = slots.slot(i);
            let at = Place { x, y, at_node: NONE, edge_u: u.0, edge_v: v.0 };
            let home = nearest(world, at, &layout.chargers, &rows);
            robots.push(home, (x, y), home, r.radius, r.speed, r.energy_full);
            robots.at_node[i] = NONE;
            robots.edge_u[i] = u.0;
            robots.edge_v[i] = v.0;
        }
        park = Some(slots);
    }
    let unload_of_cell = if scenario.unload == Unload::Nearest {
        let rows: Vec<Vec<f64>> = layout.unloading.iter().map(|&z| g.lengths_to(z)).collect();
        layout
            .cells
            .iter()
            .map(|c| {
                nearest(world, Place { x: c.service.0, y: c.service.1, at_node: NONE, edge_u: c.edge.0 .0, edge_v: c.edge.1 .0 }, &layout.unloading, &rows)
            })
            .collect()
    } else {
        vec![unload; layout.cells.len()]
    };
    // The pushes leave each column with room for up to twice the fleet; a clone holds exactly
    // the fleet (about 140 bytes a robot instead of up to 280).
    Ok((robots.clone(), Homes { park, unload, unload_of_cell }))
}

/// Names for a message: all of them up to 8, else the first 6 and how many more.
fn listed(names: &[&str]) -> String {
    if names.len() <= 8 {
        return names.join(", ");
    }
    format!("{}, ... ({} in all)", names[..6].join(", "), names.len())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::layout_params::LayoutParams;

    #[test]
    fn a_robots_slot_is_the_one_the_full_list_would_give() {
        // The slots as a list, built as spread placement first did, against the numbered
        // slots computed robot by robot: the same points, to the bit.
        let layout = Layout::generate(&LayoutParams { group_rows: 3, group_cols: 4, chargers: 4, ..LayoutParams::paper() }, "t").unwrap();
        for spacing in [25.0, 50.0, 61.3] {
            let mut list = Vec::new();
            for &(u, v) in &layout.edges {
                let ((ux, uy), (vx, vy)) = (layout.pos(u), layout.pos(v));
                let m = ((route::dist(ux, uy, vx, vy) / spacing).floor() as usize).saturating_sub(1);
                for k in 1..=m {
                    let f = k as f64 / (m + 1) as f64;
                    list.push((u, v, ux + (vx - ux) * f, uy + (vy - uy) * f));
                }
            }
            for n in [1, 2, 7, list.len() / 3, list.len()] {
                let park = Park::new(&layout, spacing, n);
                assert_eq!(park.total(), list.len() as u64);
                for i in 0..n {
                    let (u, v, x, y) = park.slot(i);
                    let (eu, ev, ex, ey) = list[i * list.len() / n];
                    assert_eq!((u, v, x.to_bits(), y.to_bits()), (eu, ev, ex.to_bits(), ey.to_bits()), "spacing {spacing}, robot {i} of {n}");
                }
            }
        }
    }
}
