//! A generated layout's parameters (`[layout_generate]`, `multibots layout generate`): what
//! the user asks for, parsed and checked. The generator that turns them into a layout is in
//! `crate::world::layout`.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// The generator's parameters: a grid of storage groups between one-way aisles. Omitted
/// fields take the paper's values, but for the aisle directions and the unloading rows,
/// which the generator chooses for the warehouse's size (`"auto"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct LayoutParams {
    /// Rows of storage groups (R).
    pub group_rows: u32,
    /// Columns of storage groups (C).
    pub group_cols: u32,
    /// Cells across a group (1 or 2: every cell must touch a vertical aisle).
    pub group_width: u32,
    /// Cells down a group.
    pub group_height: u32,
    /// Aisle width, px.
    pub aisle: f64,
    /// Side of a storage cell, px.
    pub cell: f64,
    /// Number of chargers, each at the end of a spur pointing out of the warehouse, spread
    /// evenly over the crossings of the walls that `charger_walls` names (C + 1 on the top
    /// wall; a corner crossing of two chosen walls takes one for each), and beyond one at every
    /// such crossing, midway between two crossings of the top (and bottom) row: at most 2C + 1
    /// on the top wall alone.
    pub chargers: u32,
    /// Which walls of the warehouse carry chargers: `"top"` (the paper: above the top row of
    /// crossings), `"top-bottom"` (also below the bottom row), or `"all"` (also beside the
    /// leftmost and rightmost columns), so that a big fleet has chargers near every part of the
    /// warehouse. Default: `"top"`.
    #[serde(skip_serializing_if = "ChargerWalls::is_top")]
    pub charger_walls: ChargerWalls,
    /// Length of a charger's spur, px.
    pub spur: f64,
    /// Rows of crossings whose crossings are unloading zones, spread evenly from the bottom
    /// row up (1: the bottom row, as in the paper; at most `group_rows`), or `"auto"`: one
    /// row per four rows of groups (rounded, at least one), so that unloading capacity grows
    /// with the warehouse. Default: `"auto"`.
    #[serde(skip_serializing_if = "LayoutParams::auto_rows", with = "rows_or_auto")]
    #[schemars(schema_with = "rows_or_auto::schema")]
    pub unloading_rows: u32,
    /// Directions of the horizontal aisles: `"paper"` (every row east but the bottom one,
    /// which runs west), `"alternate"` (rows alternate east and west, the top east and the
    /// bottom west), which gives big warehouses as many westward aisles as eastward ones, or
    /// `"auto"`: the paper's up to two rows of groups, alternate beyond. Vertical aisles
    /// alternate north and south either way, the rightmost south. Default: `"auto"`.
    #[serde(skip_serializing_if = "Aisles::is_auto")]
    pub aisles: Aisles,
}

/// `unloading_rows = "auto"`, as the parameters hold it.
pub const AUTO_ROWS: u32 = 0;

/// `unloading_rows`: a count, or `"auto"` ([`AUTO_ROWS`]).
mod rows_or_auto {
    use serde::{de, Deserializer, Serializer};

    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's `with` passes a reference
    pub fn serialize<S: Serializer>(rows: &u32, s: S) -> Result<S::Ok, S::Error> {
        if *rows == super::AUTO_ROWS {
            s.serialize_str("auto")
        } else {
            s.serialize_u32(*rows)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
        struct Rows;
        impl de::Visitor<'_> for Rows {
            type Value = u32;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"auto\" or a count of rows of at least 1")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<u32, E> {
                if v == "auto" {
                    Ok(super::AUTO_ROWS)
                } else {
                    Err(E::invalid_value(de::Unexpected::Str(v), &self))
                }
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<u32, E> {
                match u32::try_from(v) {
                    Ok(n) if n >= 1 => Ok(n),
                    _ => Err(E::invalid_value(de::Unexpected::Signed(v), &self)),
                }
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<u32, E> {
                match u32::try_from(v) {
                    Ok(n) if n >= 1 => Ok(n),
                    _ => Err(E::invalid_value(de::Unexpected::Unsigned(v), &self)),
                }
            }
        }
        d.deserialize_any(Rows)
    }

    pub fn schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "anyOf": [{ "type": "integer", "format": "uint32", "minimum": 1 }, { "type": "string", "enum": ["auto"] }]
        })
    }
}

/// Directions of a generated layout's horizontal aisles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Aisles {
    /// Every row east but the bottom one, which runs west (the paper's).
    Paper,
    /// Rows alternate east and west, the top east and the bottom west.
    Alternate,
    /// The paper's up to two rows of groups, alternate beyond (with the paper's directions
    /// all westward traffic of a big warehouse shares its one bottom aisle).
    #[default]
    Auto,
}

impl Aisles {
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    fn is_auto(&self) -> bool {
        *self == Aisles::Auto
    }
}

/// Walls of a generated layout that carry chargers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ChargerWalls {
    /// Above the top row of crossings (the paper's).
    #[default]
    Top,
    /// Above the top row and below the bottom row.
    TopBottom,
    /// Above the top row, below the bottom row, left of the leftmost column and right of the
    /// rightmost one.
    All,
}

impl ChargerWalls {
    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    fn is_top(&self) -> bool {
        *self == ChargerWalls::Top
    }

    /// The most chargers there can be: one per place.
    fn most(self, rows: u64, cols: u64) -> u64 {
        match self {
            ChargerWalls::Top => 2 * cols + 1,
            ChargerWalls::TopBottom => 2 * (2 * cols + 1),
            ChargerWalls::All => 2 * (2 * cols + 1) + 2 * (rows + 1),
        }
    }

    /// What each place is, for an error naming the most chargers there can be.
    fn describe(self) -> &'static str {
        match self {
            ChargerWalls::Top => "one per top-aisle crossing and one midway between two; charger_walls = \"top-bottom\" or \"all\" places more",
            ChargerWalls::TopBottom => "one per crossing of the top and bottom rows and one midway between two; charger_walls = \"all\" places more",
            ChargerWalls::All => "one per crossing along each wall, two at the corners, and one midway between two crossings of the top and bottom rows",
        }
    }
}

/// What a scenario's `[layout_generate]` table starts from: the paper's warehouse, with the
/// choices that must suit the warehouse's size (aisle directions, unloading rows) made by
/// the generator (`"auto"`). The paper's own layout is [`LayoutParams::paper`], explicit.
impl Default for LayoutParams {
    fn default() -> Self {
        LayoutParams { unloading_rows: AUTO_ROWS, aisles: Aisles::Auto, ..LayoutParams::paper() }
    }
}

impl LayoutParams {
    /// The paper's warehouse: 2 × 5 groups of 2 × 4 cells, 50 px aisles, six chargers.
    #[must_use]
    pub fn paper() -> Self {
        LayoutParams {
            group_rows: 2,
            group_cols: 5,
            group_width: 2,
            group_height: 4,
            aisle: 50.0,
            cell: 50.0,
            chargers: 6,
            spur: 40.0,
            charger_walls: ChargerWalls::Top,
            unloading_rows: 1,
            aisles: Aisles::Paper,
        }
    }

    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    fn auto_rows(n: &u32) -> bool {
        *n == AUTO_ROWS
    }

    /// The parameters with every `"auto"` choice made for this warehouse's size.
    #[must_use]
    pub fn resolved(&self) -> LayoutParams {
        let mut p = self.clone();
        if p.aisles == Aisles::Auto {
            p.aisles = if p.group_rows <= 2 { Aisles::Paper } else { Aisles::Alternate };
        }
        if p.unloading_rows == AUTO_ROWS {
            p.unloading_rows = ((p.group_rows + 2) / 4).clamp(1, p.group_rows.max(1));
        }
        p
    }

    /// Parses the parameters from JSON (what the Python API sends); errors name the field as
    /// `layout.FIELD` with the value.
    pub fn from_json(text: &str) -> Result<LayoutParams> {
        crate::input::files::check_json_shape(text).map_err(|m| Error::Parse {
            source_name: "layout parameters".into(),
            message: m.split_once(": ").map_or(m.clone(), |(_, rest)| rest.to_string()),
        })?;
        let mut de = serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = crate::error::shown(&e.path().to_string());
            let field = if path.is_empty() || path == "." { "layout".to_string() } else { format!("layout.{path}") };
            // The JSON position is left out: the user set a flag or a dictionary, not this text.
            let text = e.inner().to_string();
            let text = text.lines().next().unwrap_or_default();
            let text = text.rfind(" at line ").map_or(text, |k| &text[..k]).trim();
            match crate::input::messages::plain_parts(text, None) {
                (Some(value), reason) => Error::Scenario { field, value, reason },
                (None, message) => Error::Parse { source_name: field, message },
            }
        })
    }

    /// Checks every parameter; errors name the field as `layout.FIELD`. A size that is too
    /// large names the field that makes it so: the largest factor of a product, the field
    /// whose default would shrink an extent the most.
    pub fn check(&self) -> Result<()> {
        use crate::error::number;
        use crate::input::limits::{MAX_CELLS, MAX_COORD};
        let bad = |field: &str, value: String, reason: &str| Err(Error::scenario(format!("layout.{field}"), value, reason));
        if self.group_rows == 0 {
            return bad("group_rows", self.group_rows.to_string(), "must be at least 1");
        }
        if self.group_cols == 0 {
            return bad("group_cols", self.group_cols.to_string(), "must be at least 1");
        }
        if !(1..=2).contains(&self.group_width) {
            return bad("group_width", self.group_width.to_string(), "must be 1 or 2 (every cell needs an aisle beside it)");
        }
        if self.group_height == 0 {
            return bad("group_height", self.group_height.to_string(), "must be at least 1");
        }
        for (field, v) in [("aisle", self.aisle), ("cell", self.cell), ("spur", self.spur)] {
            if !(v.is_finite() && v > 0.0) {
                return bad(field, number(v), "must be greater than 0");
            }
        }
        if self.unloading_rows != AUTO_ROWS && self.unloading_rows > self.group_rows {
            return bad("unloading_rows", self.unloading_rows.to_string(), &format!("must be between 1 and group_rows ({})", self.group_rows));
        }
        let (rows, cols) = (u64::from(self.group_rows), u64::from(self.group_cols));
        let places = self.charger_walls.most(rows, cols);
        if self.chargers == 0 || u64::from(self.chargers) > places {
            return bad("chargers", self.chargers.to_string(), &format!("must be between 1 and {places} ({})", self.charger_walls.describe()));
        }
        let factors =
            [("group_rows", self.group_rows), ("group_cols", self.group_cols), ("group_width", self.group_width), ("group_height", self.group_height)];
        let cells: u64 = factors.iter().map(|f| u64::from(f.1)).product();
        if cells > MAX_CELLS as u64 {
            let (field, value) = factors.iter().max_by_key(|f| f.1).expect("four factors");
            return bad(field, value.to_string(), &format!("layout too large: {cells} storage cells (at most {MAX_CELLS})"));
        }
        let extent = |p: &LayoutParams| {
            let width = f64::from(p.group_cols) * (f64::from(p.group_width) * p.cell + p.aisle) + p.aisle;
            let height = f64::from(p.group_rows) * (f64::from(p.group_height) * p.cell + p.aisle) + p.aisle + p.spur;
            width.max(height)
        };
        let across = extent(self);
        if across > MAX_COORD {
            // The field whose paper value would shrink the layout the most.
            let paper = LayoutParams::paper();
            let with = |f: &str| {
                let mut p = self.clone();
                match f {
                    "group_rows" => p.group_rows = paper.group_rows,
                    "group_cols" => p.group_cols = paper.group_cols,
                    "group_height" => p.group_height = paper.group_height,
                    "aisle" => p.aisle = paper.aisle,
                    "cell" => p.cell = paper.cell,
                    _ => p.spur = paper.spur,
                }
                extent(&p)
            };
            let fields = ["aisle", "cell", "spur", "group_rows", "group_cols", "group_height"];
            let field = fields.into_iter().min_by(|a, b| with(a).total_cmp(&with(b))).expect("six fields");
            let value = match field {
                "aisle" => number(self.aisle),
                "cell" => number(self.cell),
                "spur" => number(self.spur),
                "group_rows" => self.group_rows.to_string(),
                "group_cols" => self.group_cols.to_string(),
                _ => self.group_height.to_string(),
            };
            let size = if across.is_finite() { format!("{across:.3e} px across") } else { "more than 1e308 px across".into() };
            return bad(field, value, &format!("layout too large: {size} (at most {MAX_COORD:.0e})"));
        }
        let nodes = (u64::from(self.group_rows) + 1) * (u64::from(self.group_cols) + 1);
        // The next-hop table takes one byte per (node, target) pair: 10,000 crossings are 100 MB.
        if nodes > 10_000 {
            let (field, value) = if self.group_rows >= self.group_cols { ("group_rows", self.group_rows) } else { ("group_cols", self.group_cols) };
            return bad(field, value.to_string(), &format!("layout too large: {nodes} aisle crossings (at most 10,000)"));
        }
        Ok(())
    }
}
