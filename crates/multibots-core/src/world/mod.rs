//! The world a run happens in: the warehouse layout and its generator (`layout`), layout
//! files turned into layouts (`layout_file`), the highway graph with its routing table
//! (`graph`), and [`World`], built from the layout a scenario names ([`resolve_layout`]),
//! checked once and shared by every run on it.

pub(crate) mod buckets;
pub(crate) mod graph;
pub mod layout;
pub mod layout_file;

use crate::error::{Error, Result};
use crate::input::scenario::{Scenario, Traffic};
use crate::world::layout::{Layout, NodeKind};
use graph::HighwayGraph;
use std::sync::Arc;

/// The layout a scenario names.
///
/// `"paper"`, a layout file (a path ending in `.toml`, relative to the working
/// directory), or, with `[layout_generate]`, the generated grid.
pub fn resolve_layout(scenario: &Scenario) -> Result<Layout> {
    if let Some(p) = &scenario.layout_generate {
        if scenario.layout != crate::input::scenario::defaults::layout() {
            return Err(Error::scenario("layout", format!("\"{}\"", scenario.layout), "give either layout or [layout_generate], not both"));
        }
        return Layout::generate(p, "generated").map_err(|e| match e {
            Error::Scenario { field, value, reason } => Error::Scenario { field: field.replacen("layout.", "layout_generate.", 1), value, reason },
            other => other,
        });
    }
    match scenario.layout.as_str() {
        "paper" => Ok(Layout::paper()),
        path if std::path::Path::new(path).extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) => layout_file::read(std::path::Path::new(path)),
        other => Err(Error::scenario("layout", format!("\"{other}\""), "unknown layout (known: paper, or a layout file ending in .toml)")),
    }
}

/// A layout with its graph and routing table.
#[derive(Debug)]
pub struct World {
    pub layout: Layout,
    pub graph: HighwayGraph,
}

impl World {
    /// Builds and validates the graph of a layout.
    pub fn new(layout: Layout) -> Result<Arc<World>> {
        layout.check_size()?;
        let graph = HighwayGraph::new(&layout);
        graph::validate(&layout, &graph)?;
        Ok(Arc::new(World { layout, graph }))
    }

    /// The world a scenario names: `"paper"`, a layout file, or `[layout_generate]`. Under
    /// `traffic = "reserve"` routes keep through traffic off the unloading zones where a route
    /// as short does ([`HighwayGraph::routed_around`]); under the other policies they are the
    /// paper's.
    pub fn of(scenario: &Scenario) -> Result<Arc<World>> {
        let layout = resolve_layout(scenario)?;
        let reserve = scenario.resolved(layout.departure.len()).traffic == Traffic::Reserve;
        World::routed(layout, reserve)
    }

    /// The world of a resolved layout, its routes kept off the unloading zones where a route
    /// as short does when `reserve` ([`HighwayGraph::routed_around`]).
    pub fn routed(layout: Layout, reserve: bool) -> Result<Arc<World>> {
        layout.check_size()?;
        let mut graph = HighwayGraph::new(&layout);
        graph::validate(&layout, &graph)?;
        if reserve {
            let mut unloading = vec![false; graph.len()];
            for &u in &layout.unloading {
                unloading[u.index()] = true;
            }
            graph = graph.routed_around(&unloading);
        }
        Ok(Arc::new(World { layout, graph }))
    }

    /// Whether a node is a charger.
    #[must_use]
    pub fn is_charger(&self, n: crate::ids::NodeId) -> bool {
        self.layout.nodes[n.index()].kind == NodeKind::Charger
    }

    /// The rectangle robots can reach: the warehouse and every node outside it (chargers
    /// stand outside), `[x0, y0, x1, y1]`.
    #[must_use]
    pub fn reach_bounds(&self) -> [f64; 4] {
        let mut b = self.layout.bounds;
        for node in &self.layout.nodes {
            b[0] = b[0].min(node.x);
            b[1] = b[1].min(node.y);
            b[2] = b[2].max(node.x);
            b[3] = b[3].max(node.y);
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ids::NodeId;

    #[test]
    fn reserve_routes_round_unloading_zones_and_the_other_policies_keep_the_spec_routes() {
        let mut s = Scenario::from_toml(include_str!("../../../../scenarios/warehouse-1000.toml"), "w.toml").unwrap();
        let spec = |w: &World| {
            let fresh = HighwayGraph::new(&w.layout);
            (0..w.graph.len() as u32)
                .step_by(7)
                .all(|u| (0..w.graph.len() as u32).all(|t| w.graph.node_path(NodeId(u), NodeId(t)) == fresh.node_path(NodeId(u), NodeId(t))))
        };
        for traffic in [Traffic::Wait, Traffic::Gate] {
            s.traffic = traffic;
            assert!(spec(&World::of(&s).unwrap()), "{traffic:?}");
        }
        s.traffic = Traffic::Reserve;
        assert!(!spec(&World::of(&s).unwrap()));
    }
}
