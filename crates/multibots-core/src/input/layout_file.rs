//! The layout file (TOML): its one schema, and its text parsed into [`LayoutFile`] with
//! one-line errors. The schema is documented in `docs/layout-format.md`. Turning a file into
//! the layout robots drive on (names into ids, the graph's checks) is the world's:
//! `crate::world::layout_file`.

use crate::error::{Error, Result};
use crate::input::layout_params::LayoutParams;
use crate::input::messages::toml_message;
use serde::{Deserialize, Serialize};

/// The layout file, field for field.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LayoutFile {
    /// The layout's name.
    pub name: String,
    /// `[x0, y0, x1, y1]` of the warehouse rectangle, px; chargers may stand outside it.
    pub bounds: [f64; 4],
    /// Aisle width and cell side, px (for drawing).
    pub aisle_width: f64,
    pub cell_size: f64,
    /// Departure zones (where robots start in the paper model), by node name.
    pub departure: Vec<String>,
    /// Unloading zones, by node name.
    pub unloading: Vec<String>,
    /// The generator's parameters, when the file was generated (for the record only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generated: Option<LayoutParams>,
    /// Highway nodes; `out` lists the directed edges leaving each, in expansion order.
    pub nodes: Vec<NodeEntry>,
    /// Chargers, each joined by a two-way spur to the highway node `node`.
    pub chargers: Vec<ChargerEntry>,
    /// Storage cells; a cell's id is its position in this list.
    pub cells: Vec<CellEntry>,
}

/// A highway node and its out-edges.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NodeEntry {
    pub name: String,
    pub x: f64,
    pub y: f64,
    /// Heads of the directed edges leaving this node, in the order a search expands them.
    pub out: Vec<String>,
}

/// A charger and its spur.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ChargerEntry {
    pub name: String,
    pub x: f64,
    pub y: f64,
    /// The highway node at the other end of the spur.
    pub node: String,
}

/// A storage cell and its service point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CellEntry {
    /// Top-left corner and size of the cell's rectangle, px.
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
    /// Where a robot stands to load: strictly inside the directed edge `edge`.
    pub service: [f64; 2],
    /// `[tail, head]` node names of the edge the service point lies on.
    pub edge: [String; 2],
}

/// Parses a layout file's text; `source_name` (a file name) prefixes syntax errors. Names and
/// numbers are checked when the file becomes a layout (`crate::world::layout_file`).
pub fn parse(text: &str, source_name: &str) -> Result<LayoutFile> {
    crate::input::files::check_toml_shape(text).map_err(|message| Error::LayoutFile { path: source_name.to_string(), message })?;
    let de = toml::Deserializer::new(text);
    serde_path_to_error::deserialize(de).map_err(|e| Error::LayoutFile { path: source_name.to_string(), message: toml_message(text, e) })
}
