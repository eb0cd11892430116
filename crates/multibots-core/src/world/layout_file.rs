//! Layouts as files: a layout file ([`LayoutFile`], read by `crate::input::layout_file`)
//! turned into the layout robots drive on and back. Nodes, chargers and cells are referred to
//! by name in the file, so that people can edit it; names become ids in file order (highway
//! nodes first, then chargers), which is the order a generated layout has, so `generate →
//! write → read` gives back the very same [`Layout`].

use crate::error::{Error, Result};
use crate::ids::{CellId, NodeId};
use crate::input::layout_file::{CellEntry, ChargerEntry, LayoutFile, NodeEntry};
use crate::input::layout_params::LayoutParams;
use crate::world::graph::{self, HighwayGraph, MAX_OUT_DEGREE};
use crate::world::layout::{Cell, Layout, Node, NodeKind};
use std::collections::HashMap;
use std::path::Path;

fn finite(field: String, values: &[f64]) -> Result<()> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::layout(field, "coordinates must be finite numbers"))
    }
}

/// The file form of a layout. Highway nodes are written in id order, then chargers.
#[must_use]
pub fn to_file(l: &Layout, generated: Option<LayoutParams>) -> LayoutFile {
    let name = |n: NodeId| l.nodes[n.index()].name.clone();
    let mut out: Vec<Vec<String>> = vec![Vec::new(); l.nodes.len()];
    for &(u, v) in &l.edges {
        out[u.index()].push(name(v));
    }
    let nodes = l
        .nodes
        .iter()
        .enumerate()
        .filter(|(_, n)| n.kind == NodeKind::Highway)
        .map(|(i, n)| NodeEntry { name: n.name.clone(), x: n.x, y: n.y, out: std::mem::take(&mut out[i]) })
        .collect();
    let chargers = l
        .chargers
        .iter()
        .map(|&c| {
            let n = &l.nodes[c.index()];
            ChargerEntry { name: n.name.clone(), x: n.x, y: n.y, node: l.spur_node(c).map(name).unwrap_or_default() }
        })
        .collect();
    let cells = l
        .cells
        .iter()
        .map(|c| CellEntry { x: c.x, y: c.y, w: c.w, h: c.h, service: [c.service.0, c.service.1], edge: [name(c.edge.0), name(c.edge.1)] })
        .collect();
    LayoutFile {
        name: l.name.clone(),
        bounds: l.bounds,
        aisle_width: l.aisle_width,
        cell_size: l.cell_size,
        departure: l.departure.iter().map(|&n| name(n)).collect(),
        unloading: l.unloading.iter().map(|&n| name(n)).collect(),
        generated,
        nodes,
        chargers,
        cells,
    }
}

/// Builds the layout, checking every name and number; the graph checks come after, in
/// [`check_layout`].
pub fn from_file(file: &LayoutFile) -> Result<Layout> {
    if file.name.trim().is_empty() {
        return Err(Error::layout("name", "must not be empty"));
    }
    finite("bounds".into(), &file.bounds)?;
    if !(file.bounds[2] > file.bounds[0] && file.bounds[3] > file.bounds[1]) {
        return Err(Error::layout("bounds", format!("{:?} is not a rectangle [x0, y0, x1, y1] with x1 > x0 and y1 > y0", file.bounds)));
    }
    for (field, v) in [("aisle_width", file.aisle_width), ("cell_size", file.cell_size)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::layout(field, format!("{v} must be greater than 0")));
        }
    }
    if file.nodes.is_empty() {
        return Err(Error::layout("nodes", "no highway node"));
    }
    let mut ids: HashMap<&str, NodeId> = HashMap::with_capacity(file.nodes.len() + file.chargers.len());
    let mut nodes = Vec::with_capacity(file.nodes.len() + file.chargers.len());
    let entries = file.nodes.iter().map(|n| (n.name.as_str(), n.x, n.y, NodeKind::Highway, "nodes"));
    let chargers = file.chargers.iter().map(|c| (c.name.as_str(), c.x, c.y, NodeKind::Charger, "chargers"));
    for (i, (name, x, y, kind, list)) in entries.chain(chargers).enumerate() {
        let k = if kind == NodeKind::Highway { i } else { i - file.nodes.len() };
        if name.trim().is_empty() {
            return Err(Error::layout(format!("{list}[{k}].name"), "must not be empty"));
        }
        finite(format!("{list}[{k}]"), &[x, y])?;
        if ids.insert(name, NodeId(i as u32)).is_some() {
            return Err(Error::layout(format!("{list}[{k}].name"), format!("\"{name}\" names two nodes")));
        }
        nodes.push(Node { name: name.to_string(), x, y, kind });
    }
    let highway = |field: String, name: &str| -> Result<NodeId> {
        match ids.get(name) {
            Some(&id) if nodes[id.index()].kind == NodeKind::Highway => Ok(id),
            Some(_) => Err(Error::layout(field, format!("\"{name}\" is a charger, not a highway node"))),
            None => Err(Error::layout(field, format!("unknown node \"{name}\""))),
        }
    };
    let mut edges = Vec::new();
    for (i, n) in file.nodes.iter().enumerate() {
        if n.out.len() > MAX_OUT_DEGREE {
            return Err(Error::layout(format!("nodes[{i}].out"), format!("{} out-edges (at most {MAX_OUT_DEGREE})", n.out.len())));
        }
        let u = NodeId(i as u32);
        for (k, head) in n.out.iter().enumerate() {
            let v = highway(format!("nodes[{i}].out[{k}]"), head)?;
            if v == u {
                return Err(Error::layout(format!("nodes[{i}].out[{k}]"), format!("\"{head}\" is an edge from the node to itself")));
            }
            if n.out[..k].contains(head) {
                return Err(Error::layout(format!("nodes[{i}].out[{k}]"), format!("\"{head}\" is listed twice")));
            }
            let (vx, vy) = (nodes[v.index()].x, nodes[v.index()].y);
            if n.x == vx && n.y == vy {
                return Err(Error::layout(format!("nodes[{i}].out[{k}]"), format!("\"{head}\" stands where \"{}\" stands: an edge needs a length", n.name)));
            }
            edges.push((u, v));
        }
    }
    let mut spurs = Vec::with_capacity(file.chargers.len());
    let mut charger_ids = Vec::with_capacity(file.chargers.len());
    for (i, c) in file.chargers.iter().enumerate() {
        let id = NodeId((file.nodes.len() + i) as u32);
        let at = highway(format!("chargers[{i}].node"), &c.node)?;
        let (nx, ny) = (nodes[at.index()].x, nodes[at.index()].y);
        if nx == c.x && ny == c.y {
            return Err(Error::layout(format!("chargers[{i}]"), "stands on its spur node: a spur needs a length"));
        }
        spurs.push((id, at));
        charger_ids.push(id);
    }
    let mut cells = Vec::with_capacity(file.cells.len());
    for (i, c) in file.cells.iter().enumerate() {
        finite(format!("cells[{i}]"), &[c.x, c.y, c.w, c.h, c.service[0], c.service[1]])?;
        if !(c.w > 0.0 && c.h > 0.0) {
            return Err(Error::layout(format!("cells[{i}]"), format!("size {} x {} must be positive", c.w, c.h)));
        }
        let u = highway(format!("cells[{i}].edge[0]"), &c.edge[0])?;
        let v = highway(format!("cells[{i}].edge[1]"), &c.edge[1])?;
        cells.push(Cell { id: CellId(i as u32), x: c.x, y: c.y, w: c.w, h: c.h, service: (c.service[0], c.service[1]), edge: (u, v) });
    }
    let zones = |field: &str, names: &[String]| -> Result<Vec<NodeId>> {
        let mut out = Vec::with_capacity(names.len());
        for (i, n) in names.iter().enumerate() {
            let id = highway(format!("{field}[{i}]"), n)?;
            if out.contains(&id) {
                return Err(Error::layout(format!("{field}[{i}]"), format!("\"{n}\" is listed twice")));
            }
            out.push(id);
        }
        Ok(out)
    };
    let departure = zones("departure", &file.departure)?;
    let unloading = zones("unloading", &file.unloading)?;
    Ok(Layout {
        name: file.name.clone(),
        bounds: file.bounds,
        aisle_width: file.aisle_width,
        cell_size: file.cell_size,
        nodes,
        edges,
        spurs,
        cells,
        departure,
        unloading,
        chargers: charger_ids,
    })
}

/// Checks a layout as robots will use it: builds its graph and validates it (strongly
/// connected; every service point, zone and charger can be reached and left).
pub fn check_layout(layout: &Layout) -> Result<HighwayGraph> {
    layout.check_size()?;
    let g = HighwayGraph::new(layout);
    graph::validate(layout, &g)?;
    Ok(g)
}

/// Parses a layout file's text; `source_name` (a file name) prefixes syntax errors. The
/// layout's names and numbers are checked, not yet its graph (see [`check_layout`]).
pub fn from_toml(text: &str, source_name: &str) -> Result<Layout> {
    from_file(&crate::input::layout_file::parse(text, source_name)?)
}

/// Reads and checks a layout file (its graph too).
pub fn read(path: &Path) -> Result<Layout> {
    let shown = path.display().to_string();
    let text =
        crate::input::files::read_text(path, crate::input::files::MAX_INPUT_BYTES).map_err(|message| Error::LayoutFile { path: shown.clone(), message })?;
    let layout = from_toml(&text, &shown)?;
    check_layout(&layout)?;
    Ok(layout)
}

/// The layout file's text for a layout.
#[must_use]
pub fn to_toml(layout: &Layout, generated: Option<LayoutParams>) -> String {
    let file = to_file(layout, generated);
    let body = toml::to_string(&file).expect("every layout serialises");
    format!("# MultiBots layout file (docs/layout-format.md)\n{body}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_layout_round_trips() {
        let l = Layout::paper();
        let text = to_toml(&l, Some(LayoutParams::paper()));
        let back = from_toml(&text, "paper.toml").unwrap();
        assert_eq!(back, l);
    }
}
