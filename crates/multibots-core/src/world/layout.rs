//! Warehouse layouts: storage cells, the one-way highway graph, zones and chargers.
//!
//! A layout is data. The paper's warehouse (spec section 1) is what [`LayoutParams::paper`]
//! generates; any other grid of storage groups comes from the same generator, so the paper
//! layout is not a special case anywhere in the engine.

use crate::error::{Error, Result};
use crate::ids::{CellId, NodeId};
use crate::input::layout_params::{Aisles, ChargerWalls, LayoutParams};
use crate::world::buckets::Buckets;
use serde_json::{json, Value};

/// What a node of the graph is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeKind {
    /// An aisle crossing.
    Highway,
    /// A charger: a dead end joined to one highway node by a two-way spur.
    Charger,
}

/// A node of the graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub name: String,
    pub x: f64,
    pub y: f64,
    pub kind: NodeKind,
}

/// A storage cell and where a robot stands to load it.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    pub id: CellId,
    /// Top-left corner and size of the cell's square.
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
    /// The service point: strictly inside the directed edge `edge`.
    pub service: (f64, f64),
    pub edge: (NodeId, NodeId),
}

/// A whole warehouse.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    pub name: String,
    /// `[x0, y0, x1, y1]` of the warehouse rectangle; chargers may stand outside it.
    pub bounds: [f64; 4],
    pub aisle_width: f64,
    pub cell_size: f64,
    pub nodes: Vec<Node>,
    /// Directed highway edges, grouped by their tail in the order a search expands them.
    pub edges: Vec<(NodeId, NodeId)>,
    /// `(charger, node)`: the two-way spur that joins a charger to a highway node.
    pub spurs: Vec<(NodeId, NodeId)>,
    pub cells: Vec<Cell>,
    pub departure: Vec<NodeId>,
    pub unloading: Vec<NodeId>,
    pub chargers: Vec<NodeId>,
}

/// The places for chargers at crossings: `(row, column, dx, dy)` of a crossing and the
/// direction, out of the warehouse, of a spur from it; the top row first (as the paper
/// numbers its chargers), then the bottom row, the left column and the right column.
fn slots(walls: ChargerWalls, rows: usize, cols: usize) -> Vec<(usize, usize, f64, f64)> {
    let mut slots: Vec<_> = (0..=cols).map(|k| (0, k, 0.0, -1.0)).collect();
    if walls != ChargerWalls::Top {
        slots.extend((0..=cols).map(|k| (rows, k, 0.0, 1.0)));
    }
    if walls == ChargerWalls::All {
        slots.extend((0..=rows).map(|m| (m, 0, -1.0, 0.0)));
        slots.extend((0..=rows).map(|m| (m, cols, 1.0, 0.0)));
    }
    slots
}

/// The places for chargers midway between two crossings of a horizontal wall aisle (no
/// storage cell is served from those aisles): `(row, column, dy)`, midway between
/// columns `column` and `column + 1`; the top row first.
fn midway(walls: ChargerWalls, rows: usize, cols: usize) -> Vec<(usize, usize, f64)> {
    let mut places: Vec<_> = (0..cols).map(|k| (0, k, -1.0)).collect();
    if walls != ChargerWalls::Top {
        places.extend((0..cols).map(|k| (rows, k, 1.0)));
    }
    places
}

/// Spreadsheet-style names: A..Z, AA..AZ, BA.. so that the paper's 18 nodes are A..R.
#[must_use]
pub fn node_name(mut i: usize) -> String {
    let mut s = Vec::new();
    loop {
        s.push(b'A' + (i % 26) as u8);
        if i < 26 {
            break;
        }
        i = i / 26 - 1;
    }
    s.reverse();
    String::from_utf8(s).expect("ASCII letters")
}

impl Layout {
    /// Checks the sizes that the engine allocates for, before it builds anything: nodes
    /// (the routing table grows with their square), cells and coordinates
    /// ([`crate::input::limits`]).
    pub fn check_size(&self) -> Result<()> {
        use crate::input::limits::{MAX_CELLS, MAX_COORD, MAX_NODES};
        if self.nodes.len() > MAX_NODES {
            return Err(Error::layout(
                "nodes",
                format!("{} nodes: at most {MAX_NODES} (the routing table takes one byte per pair of nodes)", self.nodes.len()),
            ));
        }
        if self.cells.len() > MAX_CELLS {
            return Err(Error::layout("cells", format!("{} storage cells: at most {MAX_CELLS}", self.cells.len())));
        }
        let far = |v: f64| !v.is_finite() || v.abs() > MAX_COORD;
        if let Some(n) = self.nodes.iter().find(|n| far(n.x) || far(n.y)) {
            return Err(Error::layout("nodes", format!("\"{}\" at ({}, {}): coordinates must be finite and within ±{MAX_COORD:.0e} px", n.name, n.x, n.y)));
        }
        if self.bounds.iter().any(|&v| far(v)) {
            return Err(Error::layout("bounds", format!("{:?}: coordinates must be finite and within ±{MAX_COORD:.0e} px", self.bounds)));
        }
        Ok(())
    }

    /// Checks that the layout can be real: at least one storage cell, every cell inside the
    /// bounds, no two cells overlapping, no node (crossing or charger) inside a cell.
    pub fn check_geometry(&self) -> Result<()> {
        if self.cells.is_empty() {
            return Err(Error::layout("cells", "no storage cell (at least one is needed)"));
        }
        let [x0, y0, x1, y1] = self.bounds;
        for c in &self.cells {
            if c.x < x0 || c.y < y0 || c.x + c.w > x1 || c.y + c.h > y1 {
                return Err(Error::layout(format!("cells[{}]", c.id), format!("lies outside the bounds {:?}", self.bounds)));
            }
        }
        // The cells' corners in a grid (`buckets.rs`) of cells at least as large as the largest
        // storage cell: a cell can only meet cells, and cover nodes, whose corner lies within
        // that size of its own. At most about twelve grid cells per storage cell (larger ones
        // only add candidates): no hashing, which took a sixth of a paper run's call.
        let widest = self.cells.iter().map(|c| c.w.max(c.h)).fold(0.0, f64::max);
        let (w, h) = (x1 - x0, y1 - y0);
        let n = self.cells.len() as f64;
        let size = widest.max((w * h / (4.0 * n)).sqrt()).max((w + h) / (8.0 * n + 64.0));
        let size = if size.is_finite() && size > 0.0 { size } else { f64::INFINITY };
        let mut grid = Buckets::new(self.bounds, size);
        let (xs, ys): (Vec<f64>, Vec<f64>) = self.cells.iter().map(|c| (c.x, c.y)).unzip();
        grid.build(&xs, &ys, |_| true);
        // The cells near a point, by index (the first overlap found does not depend on the grid).
        let candidates = |x: f64, y: f64, into: &mut Vec<usize>| {
            into.clear();
            grid.near(x, y, size, |k| into.push(k));
            into.sort_unstable();
        };
        let mut near = Vec::new();
        for (k, a) in self.cells.iter().enumerate() {
            candidates(a.x, a.y, &mut near);
            for b in near.iter().filter(|&&j| j > k).map(|&j| &self.cells[j]) {
                if a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h {
                    return Err(Error::layout(format!("cells[{}]", b.id), format!("overlaps cells[{}]", a.id)));
                }
            }
        }
        for n in &self.nodes {
            candidates(n.x, n.y, &mut near);
            for c in near.iter().map(|&j| &self.cells[j]) {
                if n.x > c.x && n.x < c.x + c.w && n.y > c.y && n.y < c.y + c.h {
                    return Err(Error::layout(format!("cells[{}]", c.id), format!("covers the node \"{}\" at ({}, {})", n.name, n.x, n.y)));
                }
            }
        }
        Ok(())
    }

    /// The paper's layout (spec section 1).
    #[must_use]
    pub fn paper() -> Layout {
        Layout::generate(&LayoutParams::paper(), "paper").expect("the paper layout is valid")
    }

    /// Generates a grid warehouse. Rows of aisles run east except the bottom one, which runs
    /// west; vertical aisles alternate north (even) and south (odd), and the rightmost one
    /// always runs south, so every crossing can reach every other one.
    pub fn generate(p: &LayoutParams, name: &str) -> Result<Layout> {
        p.check()?;
        let p = &p.resolved();
        let (rows, cols) = (p.group_rows as usize, p.group_cols as usize);
        let (w, h) = (f64::from(p.group_width), f64::from(p.group_height));
        let pitch_x = w * p.cell + p.aisle;
        let pitch_y = h * p.cell + p.aisle;
        let half = p.aisle / 2.0;
        let kn = cols + 1; // crossings per aisle row
        let node_of = |m: usize, k: usize| NodeId((m * kn + k) as u32);
        let north = |k: usize| k % 2 == 0 && !(k == cols && cols % 2 == 0);
        let east = |m: usize| match p.aisles {
            Aisles::Paper | Aisles::Auto => m < rows,
            Aisles::Alternate => m % 2 == 0 && m < rows,
        };

        let mut nodes = Vec::with_capacity((rows + 1) * kn + p.chargers as usize);
        for m in 0..=rows {
            for k in 0..kn {
                nodes.push(Node { name: node_name(m * kn + k), x: half + k as f64 * pitch_x, y: half + m as f64 * pitch_y, kind: NodeKind::Highway });
            }
        }
        // Out-edges in expansion order: the horizontal edge first, then the vertical one.
        let mut edges = Vec::new();
        for m in 0..=rows {
            for k in 0..kn {
                let u = node_of(m, k);
                if east(m) {
                    if k + 1 < kn {
                        edges.push((u, node_of(m, k + 1)));
                    }
                } else if k > 0 {
                    edges.push((u, node_of(m, k - 1)));
                }
                if north(k) {
                    if m > 0 {
                        edges.push((u, node_of(m - 1, k)));
                    }
                } else if m < rows {
                    edges.push((u, node_of(m + 1, k)));
                }
            }
        }
        // Chargers at crossings first, spread evenly over their places in order (with the top
        // wall alone and at most C + 1 chargers, i · (C + 1) / K of the top row: the paper's);
        // beyond one at every crossing, the rest spread evenly midway between crossings of the
        // top and bottom rows, each on a node of its own that splits the aisle in two.
        let slots = slots(p.charger_walls, rows, cols);
        let k_all = p.chargers as usize;
        let at_crossings = k_all.min(slots.len());
        let midway = midway(p.charger_walls, rows, cols);
        let extra = k_all - at_crossings;
        let mids: Vec<(usize, usize, f64)> = (0..extra).map(|j| midway[j * midway.len() / extra]).collect();
        let mut mid_nodes = Vec::with_capacity(mids.len());
        for &(m, k, _) in &mids {
            let (a, b) = (node_of(m, k), node_of(m, k + 1));
            let id = NodeId(nodes.len() as u32);
            let (x, y) = ((nodes[a.index()].x + nodes[b.index()].x) / 2.0, nodes[a.index()].y);
            nodes.push(Node { name: node_name(id.index()), x, y, kind: NodeKind::Highway });
            mid_nodes.push(id);
            // The aisle's edge between the two crossings now runs through the new node.
            let (from, to) = if east(m) { (a, b) } else { (b, a) };
            let e = edges.iter().position(|&uv| uv == (from, to)).expect("a wall aisle's edge");
            edges[e] = (from, id);
        }
        for (&(m, k, _), &id) in mids.iter().zip(&mid_nodes) {
            let (a, b) = (node_of(m, k), node_of(m, k + 1));
            edges.push((id, if east(m) { b } else { a }));
        }
        let mut chargers = Vec::new();
        let mut spurs = Vec::new();
        let places = (0..at_crossings)
            .map(|i| {
                let (m, k, dx, dy) = slots[i * slots.len() / at_crossings];
                (node_of(m, k), dx, dy)
            })
            .chain(mids.iter().zip(&mid_nodes).map(|(&(_, _, dy), &id)| (id, 0.0, dy)))
            .collect::<Vec<_>>();
        for (i, (at, dx, dy)) in places.into_iter().enumerate() {
            let id = NodeId(nodes.len() as u32);
            let (x, y) = (nodes[at.index()].x + dx * p.spur, nodes[at.index()].y + dy * p.spur);
            nodes.push(Node { name: format!("CH{i}"), x, y, kind: NodeKind::Charger });
            chargers.push(id);
            spurs.push((id, at));
        }
        let cells_per_group = p.group_width * p.group_height;
        let mut cells = Vec::with_capacity(rows * cols * cells_per_group as usize);
        for c in 0..cols {
            for r in 0..rows {
                for b in 0..p.group_height as usize {
                    for a in 0..p.group_width as usize {
                        let id = CellId(cells.len() as u32);
                        let x = p.aisle + c as f64 * pitch_x + a as f64 * p.cell;
                        let y = p.aisle + r as f64 * pitch_y + b as f64 * p.cell;
                        let k = c + a;
                        let sy = y + p.cell / 2.0;
                        let edge = if north(k) { (node_of(r + 1, k), node_of(r, k)) } else { (node_of(r, k), node_of(r + 1, k)) };
                        cells.push(Cell { id, x, y, w: p.cell, h: p.cell, service: (half + k as f64 * pitch_x, sy), edge });
                    }
                }
            }
        }
        let layout = Layout {
            name: name.to_string(),
            bounds: [0.0, 0.0, p.aisle + cols as f64 * pitch_x, p.aisle + rows as f64 * pitch_y],
            aisle_width: p.aisle,
            cell_size: p.cell,
            nodes,
            edges,
            spurs,
            cells,
            departure: (0..kn).map(|k| node_of(0, k)).collect(),
            // The bottom row first (its first crossing is the default zone), then rows evenly
            // spaced above it.
            unloading: (0..p.unloading_rows as usize)
                .map(|j| rows - (j * rows).div_ceil(p.unloading_rows as usize))
                .flat_map(|m| (0..kn).map(move |k| node_of(m, k)))
                .collect(),
            chargers,
        };
        Ok(layout)
    }

    /// Number of highway nodes (chargers excluded).
    #[must_use]
    pub fn highway_nodes(&self) -> usize {
        self.nodes.iter().filter(|n| n.kind == NodeKind::Highway).count()
    }

    /// The node with this name.
    #[must_use]
    pub fn node_named(&self, name: &str) -> Option<NodeId> {
        self.nodes.iter().position(|n| n.name == name).map(|i| NodeId(i as u32))
    }

    /// The charger joined to this highway node, if any.
    #[must_use]
    pub fn charger_at(&self, node: NodeId) -> Option<NodeId> {
        self.spurs.iter().find(|&&(_, n)| n == node).map(|&(c, _)| c)
    }

    /// The highway node a charger's spur leads to.
    #[must_use]
    pub fn spur_node(&self, charger: NodeId) -> Option<NodeId> {
        self.spurs.iter().find(|&&(c, _)| c == charger).map(|&(_, n)| n)
    }

    /// Position of a node.
    #[must_use]
    pub fn pos(&self, n: NodeId) -> (f64, f64) {
        let node = &self.nodes[n.index()];
        (node.x, node.y)
    }

    /// The layout JSON of `docs/replay-format.md`, shared by replays, the viewer and figures.
    #[must_use]
    pub fn to_json(&self) -> Value {
        let ids = |v: &[NodeId]| v.iter().map(|n| n.0).collect::<Vec<_>>();
        json!({
            "name": self.name,
            "bounds": self.bounds,
            "aisle_width": self.aisle_width,
            "cell_size": self.cell_size,
            "nodes": self.nodes.iter().map(|n| json!({
                "name": n.name, "x": n.x, "y": n.y,
                "kind": match n.kind { NodeKind::Highway => "highway", NodeKind::Charger => "charger" },
            })).collect::<Vec<_>>(),
            "edges": self.edges.iter().map(|(u, v)| [u.0, v.0]).collect::<Vec<_>>(),
            "spurs": self.spurs.iter().map(|(c, n)| [c.0, n.0]).collect::<Vec<_>>(),
            "cells": self.cells.iter().map(|c| json!({
                "id": c.id.0, "x": c.x, "y": c.y, "w": c.w, "h": c.h,
                "service": [c.service.0, c.service.1], "edge": [c.edge.0 .0, c.edge.1 .0],
            })).collect::<Vec<_>>(),
            "departure": ids(&self.departure),
            "unloading": ids(&self.unloading),
            "chargers": ids(&self.chargers),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_run_like_spreadsheet_columns() {
        assert_eq!(node_name(0), "A");
        assert_eq!(node_name(17), "R");
        assert_eq!(node_name(25), "Z");
        assert_eq!(node_name(26), "AA");
        assert_eq!(node_name(27), "AB");
        assert_eq!(node_name(26 + 26 * 26), "AAA");
    }

    #[test]
    fn paper_geometry_matches_the_spec_formulas() {
        let l = Layout::paper();
        assert_eq!(l.bounds, [0.0, 0.0, 800.0, 550.0]);
        assert_eq!(l.cells.len(), 80);
        assert_eq!(l.highway_nodes(), 18);
        assert_eq!(l.edges.len(), 27);
        for r in 0..2usize {
            for c in 0..5usize {
                for b in 0..4usize {
                    for a in 0..2usize {
                        let g = 2 * c + r;
                        let id = 8 * g + 2 * b + a;
                        let cell = &l.cells[id];
                        assert_eq!(cell.id.index(), id);
                        let centre = (cell.x + cell.w / 2.0, cell.y + cell.h / 2.0);
                        let expect = ((75 + 150 * c + 50 * a) as f64, (75 + 250 * r + 50 * b) as f64);
                        assert_eq!(centre, expect, "centre of cell {id}");
                        let service = ((25 + 150 * (c + a)) as f64, (75 + 250 * r + 50 * b) as f64);
                        assert_eq!(cell.service, service, "service point of cell {id}");
                    }
                }
            }
        }
        for (i, ch) in l.chargers.iter().enumerate() {
            assert_eq!(l.pos(*ch), ((25 + 150 * i) as f64, -15.0));
            assert_eq!(l.nodes[ch.index()].name, format!("CH{i}"));
        }
        assert_eq!(l.node_named("A"), Some(NodeId(0)));
        assert_eq!(l.node_named("R"), Some(NodeId(17)));
        assert_eq!(l.node_named("CH0"), Some(NodeId(18)));
    }

    #[test]
    fn service_point_of_cell_42_lies_on_edge_o_to_i() {
        let l = Layout::paper();
        let c = &l.cells[42];
        assert_eq!(c.service, (325.0, 375.0));
        assert_eq!(l.nodes[c.edge.0.index()].name, "O");
        assert_eq!(l.nodes[c.edge.1.index()].name, "I");
    }

    #[test]
    fn generator_rejects_cells_without_an_aisle() {
        let p = LayoutParams { group_width: 3, ..LayoutParams::paper() };
        assert!(Layout::generate(&p, "x").unwrap_err().to_string().contains("group_width"));
    }

    #[test]
    fn the_geometry_check_finds_what_a_pass_over_every_pair_finds() {
        // Random cells of mixed sizes (a few large ones make the buckets coarse) and nodes,
        // some on and outside the bounds: the bucketed check refuses exactly the layouts
        // that the definition, pair by pair, refuses.
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move |k: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * k
        };
        let mut refused = 0;
        for trial in 0..400 {
            let mut l = Layout::paper();
            let (w, h) = (50.0 + next(2000.0), 50.0 + next(300.0));
            l.bounds = [-10.0, 5.0, w - 10.0, h + 5.0];
            let many = 1 + (next(40.0) as usize);
            l.cells.truncate(many.min(l.cells.len()));
            for c in &mut l.cells {
                let side = if next(1.0) < 0.1 { next(h / 2.0) } else { next(12.0) };
                (c.w, c.h) = (side.max(0.5).min(w / 2.0), next(12.0).max(0.5).min(h / 2.0));
                (c.x, c.y) = (-10.0 + next(w - c.w - 1e-6), 5.0 + next(h - c.h - 1e-6));
            }
            for n in &mut l.nodes {
                (n.x, n.y) = (-40.0 + next(w + 60.0), next(h + 20.0));
            }
            let cells = &l.cells;
            let overlap = (0..cells.len()).any(|a| {
                (a + 1..cells.len()).any(|b| {
                    let (a, b) = (&cells[a], &cells[b]);
                    a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h
                })
            });
            let covered = l.nodes.iter().any(|n| cells.iter().any(|c| n.x > c.x && n.x < c.x + c.w && n.y > c.y && n.y < c.y + c.h));
            let found = l.check_geometry();
            assert_eq!(found.is_err(), overlap || covered, "trial {trial}: {found:?}");
            if overlap {
                let e = found.unwrap_err().to_string();
                assert!(e.contains("overlaps"), "trial {trial}: {e}");
            }
            refused += usize::from(overlap || covered);
        }
        // Both answers are exercised.
        assert!((50..350).contains(&refused), "{refused} of 400 refused");
    }
}
