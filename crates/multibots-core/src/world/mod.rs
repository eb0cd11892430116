//! The world a run happens in: the warehouse layout and its generator (`layout`), the highway
//! graph with its routing table (`graph`), where robots start, park and unload (`placement`),
//! and [`World`], built and checked once and shared by every run on it.

pub(crate) mod graph;
pub mod layout;
pub(crate) mod placement;

use crate::error::Result;
use crate::input::scenario::Scenario;
use crate::world::layout::{Layout, NodeKind};
use graph::HighwayGraph;
use std::sync::Arc;

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

    /// The world a scenario names: `"paper"`, a layout file, or `[layout_generate]`.
    pub fn of(scenario: &Scenario) -> Result<Arc<World>> {
        World::new(scenario.resolve_layout()?)
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
