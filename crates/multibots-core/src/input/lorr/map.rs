//! MovingAI `.map` files: `type octile`, `height H`, `width W`, `map`, then H rows of W
//! characters. `@` and `T` are obstacles; `.`, `E`, `S` (and the other passable letters of
//! the format, `G`) are free. Rows longer than W are cut to W, as the Start-Kit reads them.

use crate::error::{Error, Result};
use crate::input::files::read_text;
use crate::input::limits::MAX_INPUT_BYTES;
use crate::input::limits::MAX_MAP_CELLS;
use std::path::Path;

/// A grid of cells, `row * cols + col`, each free or an obstacle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GridMap {
    /// Rows (the map's height).
    pub rows: u32,
    /// Columns (the map's width).
    pub cols: u32,
    /// Whether each cell is free, row by row.
    pub free: Vec<bool>,
}

impl GridMap {
    /// Reads a MovingAI map file.
    pub fn load(path: &Path) -> Result<GridMap> {
        let text = read_text(path, MAX_INPUT_BYTES).map_err(|m| Error::input_file(path, None, m))?;
        GridMap::parse(&text).map_err(|(line, m)| Error::input_file(path, Some(line), m))
    }

    /// Parses a map's text; the error is its line (from 1) and what is wrong.
    pub fn parse(text: &str) -> Result<GridMap, (usize, String)> {
        let lines: Vec<&str> = text.lines().map(|l| l.trim_end_matches('\r')).collect();
        let header = |i: usize, key: &str| -> Result<u32, (usize, String)> {
            let line = lines.get(i).ok_or((i + 1, format!("the file ends before the '{key}' line")))?;
            let mut words = line.split_whitespace();
            if words.next() != Some(key) {
                return Err((i + 1, format!("expected '{key} N', found '{}'", crate::error::shown(line))));
            }
            let value = words.next().and_then(|w| w.parse::<u32>().ok()).filter(|v| (1..=100_000).contains(v));
            value.ok_or((i + 1, format!("'{key}' needs a whole number from 1 to 100000")))
        };
        match lines.first() {
            Some(l) if l.starts_with("type") => {}
            _ => return Err((1, "expected 'type octile' (a MovingAI map)".into())),
        }
        let rows = header(1, "height")?;
        let cols = header(2, "width")?;
        if u64::from(rows) * u64::from(cols) > MAX_MAP_CELLS {
            return Err((2, format!("{rows} x {cols} cells is more than the {MAX_MAP_CELLS} this reader takes (docs/limits.md)")));
        }
        if lines.get(3).map(|l| l.trim()) != Some("map") {
            return Err((4, "expected the line 'map'".into()));
        }
        let mut free = Vec::with_capacity((rows * cols) as usize);
        for r in 0..rows as usize {
            let line = lines.get(4 + r).ok_or((4 + r + 1, format!("the map has {r} rows; the header says {rows}")))?;
            let bytes = line.as_bytes();
            if bytes.len() < cols as usize {
                return Err((4 + r + 1, format!("the row has {} cells; the header says {cols}", bytes.len())));
            }
            for (c, &b) in bytes[..cols as usize].iter().enumerate() {
                free.push(match b {
                    b'.' | b'E' | b'S' | b'G' => true,
                    b'@' | b'T' | b'O' | b'W' => false,
                    _ => {
                        return Err((
                            4 + r + 1,
                            format!("column {}: '{}' is not a map cell ('.', 'E', 'S', '@', 'T')", c + 1, crate::error::shown(&(b as char).to_string())),
                        ))
                    }
                });
            }
        }
        Ok(GridMap { rows, cols, free })
    }

    /// The number of cells.
    #[must_use]
    pub fn cells(&self) -> usize {
        self.free.len()
    }

    /// The cell `row * cols + col` as (row, column).
    #[must_use]
    pub fn row_col(&self, cell: u32) -> (u32, u32) {
        (cell / self.cols, cell % self.cols)
    }
}
