//! The highway graph: one-way aisle edges plus two-way charger spurs, and its routing table.
//!
//! Paths follow the paper's Algorithm 1: the first path a breadth-first search finds when it
//! expands out-neighbours in the layout's order. That path is the lexicographically first
//! among the shortest ones, and the lexicographically first shortest path from `u` continues
//! as the lexicographically first shortest path from its second node. So one next-hop table,
//! built once per layout, answers every route without a search per request.

use crate::error::{Error, Result};
use crate::ids::NodeId;
use crate::world::layout::{Layout, NodeKind};
use std::collections::VecDeque;

/// Adjacency in expansion order, the next-hop table and path lengths.
///
/// Memory: the next-hop table stores, for every (node, target) pair, the *position* of the
/// next hop in the node's out-list in one byte (out-degrees are tiny), so it takes n² bytes:
/// 4 MB for a 2,000-node warehouse, where `u32` hops plus `f64` lengths would take 64 MB.
/// Path lengths are tabulated only for small graphs (up to [`LENGTH_TABLE_MAX`] nodes, which
/// covers the paper layout and the allocators' cost queries there); on larger graphs they are
/// summed along the next-hop chain on request. The step loop never needs a length.
#[derive(Clone, Debug)]
pub struct HighwayGraph {
    n: usize,
    out_start: Vec<u32>,
    out_to: Vec<u32>,
    /// `next[t * n + u]`: position in `out(u)` of the node after `u` on the path to `t`
    /// (`NO_HOP` for `u == t` or when `t` cannot be reached). Rows by target, so the rows of
    /// the few targets a fleet uses at a time stay in cache.
    next: Vec<u8>,
    /// `length[t * n + u]`: length of that path in px, when `n <= LENGTH_TABLE_MAX`.
    length: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    /// Tail node and length of each directed edge, by edge id (`out_start[u] + position`).
    edge_from: Vec<u32>,
    edge_len: Vec<f64>,
}

/// Marks "no next hop" in the byte table.
const NO_HOP: u8 = u8::MAX;

/// Largest graph whose path lengths are tabulated (8 MB of `f64` at this size).
pub const LENGTH_TABLE_MAX: usize = 1024;

/// Largest out-degree a node may have: positions are stored in a byte, `u8::MAX` is "none".
pub const MAX_OUT_DEGREE: usize = 254;

impl HighwayGraph {
    /// Builds the graph of a layout. Chargers are dead ends: their only edge leads back to
    /// their spur node, so no shortest path passes through one. Out-degrees above
    /// [`MAX_OUT_DEGREE`] are cut (layout validation rejects such layouts first).
    #[must_use]
    pub fn new(layout: &Layout) -> HighwayGraph {
        let n = layout.nodes.len();
        let mut out: Vec<Vec<u32>> = vec![Vec::new(); n];
        for &(u, v) in &layout.edges {
            out[u.index()].push(v.0);
        }
        for &(c, node) in &layout.spurs {
            out[node.index()].push(c.0);
            out[c.index()].push(node.0);
        }
        let mut out_start = Vec::with_capacity(n + 1);
        let mut out_to = Vec::new();
        for o in &mut out {
            o.truncate(MAX_OUT_DEGREE);
            out_start.push(out_to.len() as u32);
            out_to.extend_from_slice(o);
        }
        out_start.push(out_to.len() as u32);
        let x: Vec<f64> = layout.nodes.iter().map(|p| p.x).collect();
        let y: Vec<f64> = layout.nodes.iter().map(|p| p.y).collect();
        let lengths = if n <= LENGTH_TABLE_MAX { n * n } else { 0 };
        let mut edge_from = Vec::with_capacity(out_to.len());
        let mut edge_len = Vec::with_capacity(out_to.len());
        for u in 0..n {
            for &v in &out_to[out_start[u] as usize..out_start[u + 1] as usize] {
                edge_from.push(u as u32);
                edge_len.push(((x[v as usize] - x[u]).powi(2) + (y[v as usize] - y[u]).powi(2)).sqrt());
            }
        }
        let mut g = HighwayGraph { n, out_start, out_to, next: vec![NO_HOP; n * n], length: vec![0.0; lengths], x, y, edge_from, edge_len };
        g.build_tables(&[]);
        g
    }

    /// The same graph, routed so that among the shortest paths (fewest hops) each route takes
    /// the one through the fewest nodes marked in `avoid` (its target not counted) that is no
    /// longer in px than the spec's, then the first in the search's order. Routes keep their
    /// hops and get no longer; only ties change. Used
    /// under `traffic = "reserve"` to keep through traffic off unloading zones, where robots
    /// stand for the unloading time (docs/traffic.md, rule 7).
    #[must_use]
    pub fn routed_around(mut self, avoid: &[bool]) -> HighwayGraph {
        assert_eq!(avoid.len(), self.n, "one mark per node");
        self.next.fill(NO_HOP);
        self.build_tables(avoid);
        self
    }

    /// The next-hop (and length) tables; `avoid` empty: the spec's BFS choice, else see
    /// [`HighwayGraph::routed_around`].
    fn build_tables(&mut self, avoid: &[bool]) {
        let n = self.n;
        // Reverse adjacency for the distance-to-target searches.
        let mut rev: Vec<Vec<u32>> = vec![Vec::new(); n];
        for u in 0..n {
            for &v in self.out(u) {
                rev[v as usize].push(u as u32);
            }
        }
        let with_length = !self.length.is_empty();
        let mut dist = vec![u32::MAX; n];
        let mut order = Vec::with_capacity(n);
        let mut queue = VecDeque::with_capacity(n);
        // Per node, the avoided nodes its chosen path to the current target passes through,
        // and its length.
        let mut around = vec![(0u32, 0.0f64); if avoid.is_empty() { 0 } else { n }];
        for t in 0..n {
            dist.fill(u32::MAX);
            if !avoid.is_empty() {
                around[t] = (0, 0.0);
            }
            order.clear();
            dist[t] = 0;
            queue.push_back(t as u32);
            while let Some(v) = queue.pop_front() {
                order.push(v);
                for &u in &rev[v as usize] {
                    if dist[u as usize] == u32::MAX {
                        dist[u as usize] = dist[v as usize] + 1;
                        queue.push_back(u);
                    }
                }
            }
            // Nodes in increasing distance, so each next hop's length is already known. The
            // first out-neighbour one hop closer is the spec's BFS choice (see module docs).
            for &u in &order {
                let u = u as usize;
                if u == t {
                    continue;
                }
                let want = dist[u] - 1;
                let k = if avoid.is_empty() {
                    self.out(u).iter().position(|&v| dist[v as usize] == want).expect("a node one hop closer exists")
                } else {
                    // Among the out-neighbours one hop closer (their paths known), the first
                    // whose path passes the fewest avoided nodes, itself included, and is no
                    // longer than the first one's (the spec's choice).
                    let mut best: Option<(u32, f64, usize)> = None;
                    let mut limit = f64::INFINITY;
                    for (k, &v) in self.out(u).iter().enumerate() {
                        let v = v as usize;
                        if dist[v] != want {
                            continue;
                        }
                        let length = self.segment(u, v) + around[v].1;
                        if best.is_none() {
                            limit = length + 1e-9;
                        }
                        let passes = around[v].0 + u32::from(v != t && avoid[v]);
                        if length <= limit && best.map_or(true, |(p, _, _)| passes < p) {
                            best = Some((passes, length, k));
                        }
                    }
                    let (passes, length, k) = best.expect("a node one hop closer exists");
                    around[u] = (passes, length);
                    k
                };
                self.next[t * n + u] = k as u8;
                if with_length {
                    let v = self.out(u)[k] as usize;
                    self.length[t * n + u] = self.segment(u, v) + self.length[t * n + v];
                }
            }
        }
    }

    fn segment(&self, u: usize, v: usize) -> f64 {
        let (dx, dy) = (self.x[v] - self.x[u], self.y[v] - self.y[u]);
        (dx * dx + dy * dy).sqrt()
    }

    /// Position of a node, px.
    #[inline]
    #[must_use]
    pub fn pos(&self, u: u32) -> (f64, f64) {
        (self.x[u as usize], self.y[u as usize])
    }

    /// Number of nodes, chargers included.
    #[must_use]
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether the graph has no node.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Number of directed edges (spurs count once each way).
    #[must_use]
    pub fn edge_count(&self) -> usize {
        self.out_to.len()
    }

    /// The id of the directed edge `u -> v` (`NONE` when there is none).
    #[inline]
    #[must_use]
    pub fn edge_id(&self, u: u32, v: u32) -> u32 {
        let (a, b) = (self.out_start[u as usize] as usize, self.out_start[u as usize + 1] as usize);
        self.out_to[a..b].iter().position(|&w| w == v).map_or(crate::ids::NONE, |k| (a + k) as u32)
    }

    /// Tail, head and length of edge `e`.
    #[inline]
    #[must_use]
    pub fn edge(&self, e: u32) -> (u32, u32, f64) {
        let e = e as usize;
        (self.edge_from[e], self.out_to[e], self.edge_len[e])
    }

    /// The ids of the edges leaving `u`, in expansion order.
    #[must_use]
    pub fn out_edges(&self, u: u32) -> std::ops::Range<u32> {
        self.out_start[u as usize]..self.out_start[u as usize + 1]
    }

    /// Out-neighbours of `u`, in expansion order.
    #[inline]
    #[must_use]
    pub fn out(&self, u: usize) -> &[u32] {
        &self.out_to[self.out_start[u] as usize..self.out_start[u + 1] as usize]
    }

    /// The node after `u` on the path to `t`.
    #[inline]
    #[must_use]
    pub fn next_hop(&self, u: NodeId, t: NodeId) -> Option<NodeId> {
        let k = self.next[t.index() * self.n + u.index()];
        (k != NO_HOP).then(|| NodeId(self.out_to[self.out_start[u.index()] as usize + k as usize]))
    }

    /// Whether `t` can be reached from `u`.
    #[inline]
    #[must_use]
    pub fn reachable(&self, u: NodeId, t: NodeId) -> bool {
        u == t || self.next[t.index() * self.n + u.index()] != NO_HOP
    }

    /// Length in px of the node path from `u` to `t` (0 when `u == t` or unreachable).
    #[inline]
    #[must_use]
    pub fn path_length(&self, u: NodeId, t: NodeId) -> f64 {
        if !self.length.is_empty() {
            return self.length[t.index() * self.n + u.index()];
        }
        self.walk_length(u, t)
    }

    /// Sums a path's segments front to back along the next-hop chain. No allocation: charger
    /// choices call this inside the step loop on large layouts.
    fn walk_length(&self, u: NodeId, t: NodeId) -> f64 {
        let mut total = 0.0;
        let mut at = u;
        while let Some(v) = self.next_hop(at, t) {
            total += self.segment(at.index(), v.index());
            at = v;
        }
        total
    }

    /// Path lengths from every node to `t` (0 at `t` and where `t` cannot be reached), in
    /// O(n): `len(u) = seg(u, next) + len(next)`, the table's own sum.
    #[must_use]
    pub fn lengths_to(&self, t: NodeId) -> Vec<f64> {
        let n = self.n;
        let mut len = vec![f64::NAN; n];
        len[t.index()] = 0.0;
        let mut chain = Vec::new();
        for u in 0..n {
            let mut at = NodeId(u as u32);
            while len[at.index()].is_nan() {
                chain.push(at);
                if let Some(v) = self.next_hop(at, t) {
                    at = v;
                } else {
                    len[at.index()] = 0.0;
                    chain.pop();
                    break;
                }
            }
            while let Some(w) = chain.pop() {
                let v = self.next_hop(w, t).expect("on a chain to t");
                len[w.index()] = self.segment(w.index(), v.index()) + len[v.index()];
            }
        }
        len
    }

    /// Bytes held by the routing tables (next hops and lengths).
    #[must_use]
    pub fn table_bytes(&self) -> usize {
        self.next.len() + self.length.len() * std::mem::size_of::<f64>()
    }

    /// The node path from `u` to `t`, both included; `None` if `t` cannot be reached.
    #[must_use]
    pub fn node_path(&self, u: NodeId, t: NodeId) -> Option<Vec<NodeId>> {
        if !self.reachable(u, t) {
            return None;
        }
        let mut path = vec![u];
        let mut at = u;
        while at != t {
            at = self.next_hop(at, t)?;
            path.push(at);
        }
        Some(path)
    }

    /// The literal search of the paper's Algorithm 1: breadth-first over simple paths,
    /// expanding out-neighbours in order, stopping at the first path that reaches `t`.
    /// Kept as the reference the next-hop table is tested against.
    #[must_use]
    pub fn bfs_path(&self, u: NodeId, t: NodeId) -> Option<Vec<NodeId>> {
        let mut queue: VecDeque<Vec<u32>> = VecDeque::from([vec![u.0]]);
        while let Some(path) = queue.pop_front() {
            let last = *path.last().expect("paths are never empty");
            if last == t.0 {
                return Some(path.into_iter().map(NodeId).collect());
            }
            if path.len() > self.n {
                continue;
            }
            for &v in self.out(last as usize) {
                if !path.contains(&v) {
                    let mut p = path.clone();
                    p.push(v);
                    queue.push_back(p);
                }
            }
        }
        None
    }
}

/// Checks that robots can use a layout: the highway nodes are strongly connected (so every
/// zone and service point can be reached and left), every zone is a highway node, every
/// charger hangs on a highway node by its spur (so it can be reached and left), every
/// service point lies strictly inside a highway edge of the graph, and no node has more
/// out-edges than the routing table can name.
pub fn validate(layout: &Layout, graph: &HighwayGraph) -> Result<()> {
    layout.check_geometry()?;
    let highway: Vec<NodeId> = (0..layout.nodes.len() as u32).map(NodeId).filter(|n| layout.nodes[n.index()].kind == NodeKind::Highway).collect();
    if highway.is_empty() {
        return Err(Error::layout("nodes", "no highway node"));
    }
    let mut degrees = vec![0usize; layout.nodes.len()];
    for &(u, _) in &layout.edges {
        degrees[u.index()] += 1;
    }
    for &(_, n) in &layout.spurs {
        degrees[n.index()] += 1;
    }
    for (u, &degree) in degrees.iter().enumerate() {
        if degree > MAX_OUT_DEGREE {
            return Err(Error::layout(format!("nodes[{u}]"), format!("node {} has {degree} out-edges (at most {MAX_OUT_DEGREE})", layout.nodes[u].name)));
        }
    }
    let first = highway[0];
    for &v in &highway {
        if !graph.reachable(first, v) || !graph.reachable(v, first) {
            let (a, b) = if graph.reachable(first, v) { (v, first) } else { (first, v) };
            return Err(Error::layout(
                "edges",
                format!(
                    "the highway graph is not strongly connected: node {} cannot reach node {}",
                    layout.nodes[a.index()].name,
                    layout.nodes[b.index()].name
                ),
            ));
        }
    }
    for (field, zones) in [("departure", &layout.departure), ("unloading", &layout.unloading)] {
        if zones.is_empty() {
            return Err(Error::layout(field, "no zone given (at least one is needed)"));
        }
        for (i, z) in zones.iter().enumerate() {
            if layout.nodes[z.index()].kind != NodeKind::Highway {
                return Err(Error::layout(format!("{field}[{i}]"), format!("{} is not a highway node", layout.nodes[z.index()].name)));
            }
        }
    }
    if layout.chargers.is_empty() {
        return Err(Error::layout("chargers", "no charger (at least one is needed)"));
    }
    for &c in &layout.chargers {
        let ok = layout.nodes[c.index()].kind == NodeKind::Charger && layout.spur_node(c).is_some_and(|n| layout.nodes[n.index()].kind == NodeKind::Highway);
        if !ok {
            return Err(Error::layout("chargers", format!("charger {} has no spur to a highway node", layout.nodes[c.index()].name)));
        }
    }
    for cell in &layout.cells {
        let (u, v) = cell.edge;
        let highway_edge = layout.nodes[v.index()].kind == NodeKind::Highway && graph.out(u.index()).contains(&v.0);
        if !highway_edge {
            return Err(Error::layout(format!("cells[{}].edge", cell.id), "is not a highway edge"));
        }
        let (ux, uy) = layout.pos(u);
        let (vx, vy) = layout.pos(v);
        let (sx, sy) = cell.service;
        let cross = (vx - ux) * (sy - uy) - (vy - uy) * (sx - ux);
        let along = (sx - ux) * (vx - ux) + (sy - uy) * (vy - uy);
        let len2 = (vx - ux) * (vx - ux) + (vy - uy) * (vy - uy);
        if cross.abs() > 1e-9 * len2.max(1.0) || along <= 0.0 || along >= len2 {
            return Err(Error::layout(format!("cells[{}].service", cell.id), "does not lie strictly inside its edge"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(l: &Layout, p: &[NodeId]) -> String {
        p.iter().map(|n| l.nodes[n.index()].name.as_str()).collect::<Vec<_>>().join(" ")
    }

    #[test]
    fn paper_graph_has_the_spec_table_in_order() {
        let l = Layout::paper();
        let g = HighwayGraph::new(&l);
        let table = [
            ("A", "B"),
            ("B", "C H"),
            ("C", "D"),
            ("D", "E J"),
            ("E", "F"),
            ("F", "L"),
            ("G", "H A"),
            ("H", "I N"),
            ("I", "J C"),
            ("J", "K P"),
            ("K", "L E"),
            ("L", "R"),
            ("M", "G"),
            ("N", "M"),
            ("O", "N I"),
            ("P", "O"),
            ("Q", "P K"),
            ("R", "Q"),
        ];
        for (node, outs) in table {
            let u = l.node_named(node).unwrap();
            let highway: Vec<NodeId> = g.out(u.index()).iter().map(|&v| NodeId(v)).filter(|v| l.nodes[v.index()].kind == NodeKind::Highway).collect();
            assert_eq!(names(&l, &highway), outs, "out-neighbours of {node}");
        }
        assert_eq!(l.edges.len(), 27);
        validate(&l, &g).unwrap();
    }

    #[test]
    fn next_hop_paths_equal_the_literal_bfs() {
        let l = Layout::paper();
        let g = HighwayGraph::new(&l);
        for u in 0..l.nodes.len() as u32 {
            for t in 0..l.nodes.len() as u32 {
                assert_eq!(g.node_path(NodeId(u), NodeId(t)), g.bfs_path(NodeId(u), NodeId(t)), "{u} -> {t}");
            }
        }
    }

    #[test]
    fn worked_example_node_paths() {
        let l = Layout::paper();
        let g = HighwayGraph::new(&l);
        let n = |s| l.node_named(s).unwrap();
        assert_eq!(names(&l, &g.node_path(n("A"), n("O")).unwrap()), "A B C D J P O");
        assert_eq!(names(&l, &g.node_path(n("I"), n("M")).unwrap()), "I J P O N M");
        assert_eq!(names(&l, &g.node_path(n("M"), n("CH0")).unwrap()), "M G A CH0");
        assert_eq!(g.path_length(n("A"), n("O")), 1100.0);
        assert_eq!(g.path_length(n("I"), n("M")), 850.0);
        assert_eq!(g.path_length(n("M"), n("CH0")), 540.0);
    }

    #[test]
    fn lengths_to_a_target_equal_the_table() {
        let l = Layout::paper();
        let g = HighwayGraph::new(&l);
        for t in 0..l.nodes.len() as u32 {
            let row = g.lengths_to(NodeId(t));
            for u in 0..l.nodes.len() as u32 {
                assert_eq!(row[u as usize], g.path_length(NodeId(u), NodeId(t)));
                assert_eq!(g.walk_length(NodeId(u), NodeId(t)), g.path_length(NodeId(u), NodeId(t)));
            }
        }
    }

    #[test]
    fn routes_round_unloading_zones_are_as_short_and_pass_fewer() {
        // A warehouse with unloading zones on three rows of crossings: every route keeps its
        // hops, is no longer, passes no more unloading zones than the spec's route (its target
        // not counted), and many pass fewer.
        let p = crate::input::layout_params::LayoutParams {
            group_rows: 9,
            group_cols: 8,
            chargers: 9,
            unloading_rows: 3,
            aisles: crate::input::layout_params::Aisles::Alternate,
            ..crate::input::layout_params::LayoutParams::paper()
        };
        let l = Layout::generate(&p, "g").unwrap();
        let plain = HighwayGraph::new(&l);
        let mut unloading = vec![false; l.nodes.len()];
        for &u in &l.unloading {
            unloading[u.index()] = true;
        }
        let around = plain.clone().routed_around(&unloading);
        validate(&l, &around).unwrap();
        let passes = |path: &[NodeId]| path.iter().skip(1).take(path.len().saturating_sub(2)).filter(|v| unloading[v.index()]).count();
        let (mut fewer, mut before, mut after) = (0, 0, 0);
        for u in 0..l.nodes.len() as u32 {
            for t in 0..l.nodes.len() as u32 {
                let (a, b) = (plain.node_path(NodeId(u), NodeId(t)).unwrap(), around.node_path(NodeId(u), NodeId(t)).unwrap());
                assert_eq!(a.len(), b.len(), "{u} -> {t}: as many hops");
                assert_eq!(a.first(), b.first());
                assert_eq!(a.last(), b.last());
                assert!(around.path_length(NodeId(u), NodeId(t)) <= plain.path_length(NodeId(u), NodeId(t)) + 1e-6, "{u} -> {t}: no longer");
                assert!(passes(&b) <= passes(&a), "{u} -> {t}: {} through {}", names(&l, &b), names(&l, &a));
                fewer += usize::from(passes(&b) < passes(&a));
                (before, after) = (before + passes(&a), after + passes(&b));
            }
        }
        assert!(fewer > 1000 && after * 4 < before * 3, "{fewer} routes pass fewer; {before} passes before, {after} after");
    }

    #[test]
    fn chargers_are_dead_ends() {
        let l = Layout::paper();
        let g = HighwayGraph::new(&l);
        for u in 0..l.nodes.len() as u32 {
            for t in 0..l.nodes.len() as u32 {
                let p = g.node_path(NodeId(u), NodeId(t)).unwrap();
                for inner in p.iter().skip(1).take(p.len().saturating_sub(2)) {
                    assert_eq!(l.nodes[inner.index()].kind, NodeKind::Highway);
                }
            }
        }
    }

    #[test]
    fn generated_layouts_are_strongly_connected() {
        for rows in 1..4 {
            for cols in 1..7 {
                let p = crate::input::layout_params::LayoutParams {
                    group_rows: rows,
                    group_cols: cols,
                    chargers: cols + 1,
                    ..crate::input::layout_params::LayoutParams::paper()
                };
                let l = Layout::generate(&p, "g").unwrap();
                validate(&l, &HighwayGraph::new(&l)).unwrap_or_else(|e| panic!("{rows}x{cols}: {e}"));
            }
        }
    }

    #[test]
    fn a_broken_graph_is_named() {
        let mut l = Layout::paper();
        l.edges.retain(|&(u, v)| !(l.nodes[u.index()].name == "F" && l.nodes[v.index()].name == "L"));
        let err = validate(&l, &HighwayGraph::new(&l)).unwrap_err().to_string();
        assert!(err.contains("not strongly connected"), "{err}");
    }
}
