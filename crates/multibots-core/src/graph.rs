//! The highway graph: one-way aisle edges plus two-way charger spurs, and its routing table.
//!
//! Paths follow the paper's Algorithm 1: the first path a breadth-first search finds when it
//! expands out-neighbours in the layout's order. That path is the lexicographically first
//! among the shortest ones, and the lexicographically first shortest path from `u` continues
//! as the lexicographically first shortest path from its second node. So one next-hop table,
//! built once per layout, answers every route without a search per request.

use crate::error::{Error, Result};
use crate::ids::{NodeId, NONE};
use crate::layout::{Layout, NodeKind};
use std::collections::VecDeque;

/// Adjacency in expansion order, the next-hop table and path lengths.
#[derive(Clone, Debug)]
pub struct HighwayGraph {
    n: usize,
    out_start: Vec<u32>,
    out_to: Vec<u32>,
    /// `next[u * n + t]`: the node after `u` on the path to `t` (`NONE` for `u == t`).
    next: Vec<u32>,
    /// `hops[u * n + t]`: edges on that path; `u32::MAX` when `t` cannot be reached.
    hops: Vec<u32>,
    /// `length[u * n + t]`: length of that path in px.
    length: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
}

impl HighwayGraph {
    /// Builds the graph of a layout. Chargers are dead ends: their only edge leads back to
    /// their spur node, so no shortest path passes through one.
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
        for o in &out {
            out_start.push(out_to.len() as u32);
            out_to.extend_from_slice(o);
        }
        out_start.push(out_to.len() as u32);
        let x: Vec<f64> = layout.nodes.iter().map(|p| p.x).collect();
        let y: Vec<f64> = layout.nodes.iter().map(|p| p.y).collect();
        let mut g = HighwayGraph { n, out_start, out_to, next: vec![NONE; n * n], hops: vec![u32::MAX; n * n], length: vec![0.0; n * n], x, y };
        g.build_tables();
        g
    }

    fn build_tables(&mut self) {
        let n = self.n;
        // Reverse adjacency for the distance-to-target searches.
        let mut rev: Vec<Vec<u32>> = vec![Vec::new(); n];
        for u in 0..n {
            for &v in self.out(u) {
                rev[v as usize].push(u as u32);
            }
        }
        let mut dist = vec![u32::MAX; n];
        let mut order = Vec::with_capacity(n);
        let mut queue = VecDeque::with_capacity(n);
        for t in 0..n {
            dist.fill(u32::MAX);
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
            // Nodes in increasing distance, so each next hop's length is already known.
            for &u in &order {
                let u = u as usize;
                self.hops[u * n + t] = dist[u];
                if u == t {
                    continue;
                }
                let want = dist[u] - 1;
                let v = *self.out(u).iter().find(|&&v| dist[v as usize] == want).expect("a node one hop closer exists");
                self.next[u * n + t] = v;
                self.length[u * n + t] = self.segment(u, v as usize) + self.length[v as usize * n + t];
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
        let v = self.next[u.index() * self.n + t.index()];
        (v != NONE).then_some(NodeId(v))
    }

    /// Whether `t` can be reached from `u`.
    #[inline]
    #[must_use]
    pub fn reachable(&self, u: NodeId, t: NodeId) -> bool {
        self.hops[u.index() * self.n + t.index()] != u32::MAX
    }

    /// Length in px of the node path from `u` to `t` (0 when `u == t`).
    #[inline]
    #[must_use]
    pub fn path_length(&self, u: NodeId, t: NodeId) -> f64 {
        self.length[u.index() * self.n + t.index()]
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

/// Checks that robots can use a layout: the highway nodes are strongly connected, every
/// charger hangs on a highway node, and every service point lies strictly inside a highway
/// edge of the graph.
pub fn validate(layout: &Layout, graph: &HighwayGraph) -> Result<()> {
    let highway: Vec<NodeId> = (0..layout.nodes.len() as u32).map(NodeId).filter(|n| layout.nodes[n.index()].kind == NodeKind::Highway).collect();
    if highway.is_empty() {
        return Err(Error::layout("nodes", "no highway node"));
    }
    let first = highway[0];
    for &v in &highway {
        if !graph.reachable(first, v) || !graph.reachable(v, first) {
            let (a, b) = if graph.reachable(first, v) { (v, first) } else { (first, v) };
            return Err(Error::layout(
                "edges",
                format!("the highway graph is not strongly connected: node {} cannot reach node {}", layout.nodes[a.index()].name, layout.nodes[b.index()].name),
            ));
        }
    }
    for &c in &layout.chargers {
        if layout.nodes[c.index()].kind != NodeKind::Charger || layout.spur_node(c).is_none() {
            return Err(Error::layout("chargers", format!("charger {} has no spur to a highway node", layout.nodes[c.index()].name)));
        }
    }
    for cell in &layout.cells {
        let (u, v) = cell.edge;
        if !layout.edges.contains(&(u, v)) {
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
            ("A", "B"), ("B", "C H"), ("C", "D"), ("D", "E J"), ("E", "F"), ("F", "L"),
            ("G", "H A"), ("H", "I N"), ("I", "J C"), ("J", "K P"), ("K", "L E"), ("L", "R"),
            ("M", "G"), ("N", "M"), ("O", "N I"), ("P", "O"), ("Q", "P K"), ("R", "Q"),
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
                let p = crate::layout::LayoutParams { group_rows: rows, group_cols: cols, chargers: cols + 1, ..crate::layout::LayoutParams::paper() };
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
