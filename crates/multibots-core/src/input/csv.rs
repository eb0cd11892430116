//! One reader for the CSV tables a scenario names (`orders.csv`: `step,cell`;
//! `humans.csv`: `person,cell`): two integers a line, a first line that is not two integers
//! being a header, blank lines and lines starting with `#` skipped. Each file is read once
//! per world ([`Tables`]) and shared by every run on it, as the world is (batches, and every
//! `reset()` of a learning environment); each run checks the rows against its own sizes.

use crate::error::{Error, Result};
use crate::input::files::{read_text, MAX_INPUT_BYTES};
use crate::input::limits::shown;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// A table's rows: its line number (from 1), then the two integers.
#[derive(Debug)]
pub(crate) struct Rows {
    /// `field = "path"`, for errors about a row.
    field: String,
    value: String,
    pub(crate) lines: Vec<(usize, u64, i64)>,
}

impl Rows {
    /// The error for row `line` of this table.
    pub(crate) fn error(&self, line: usize, why: impl std::fmt::Display) -> Error {
        Error::scenario(&self.field, &self.value, format!("line {line}: {why}"))
    }
}

/// The tables read for one world, by field and path.
#[derive(Debug, Default)]
pub struct Tables {
    read: Mutex<Vec<(String, PathBuf, Arc<Rows>)>>,
}

impl Tables {
    /// The rows of the table at `path`, the scenario's `field` (`orders.csv`, `humans.csv`),
    /// whose lines hold `columns` (`step,cell`): read on first use, then shared.
    pub(crate) fn rows(&self, field: &str, path: &Path, columns: &str) -> Result<Arc<Rows>> {
        let mut read = self.read.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((_, _, rows)) = read.iter().find(|(f, p, _)| f == field && p == path) {
            return Ok(Arc::clone(rows));
        }
        let rows = Arc::new(parse(field, path, columns)?);
        read.push((field.to_string(), path.to_path_buf(), Arc::clone(&rows)));
        Ok(rows)
    }
}

fn parse(field: &str, path: &Path, columns: &str) -> Result<Rows> {
    let value = format!("\"{}\"", path.display());
    let text = read_text(path, MAX_INPUT_BYTES).map_err(|e| Error::scenario(field, &value, format!("cannot read: {e}")))?;
    let mut out = Rows { field: field.to_string(), value, lines: Vec::new() };
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let parts: Vec<&str> = line.split(',').map(str::trim).collect();
        let parsed = match parts.as_slice() {
            [a, b] => a.parse::<u64>().ok().zip(b.parse::<i64>().ok()),
            _ => None,
        };
        let Some((a, b)) = parsed else {
            if out.lines.is_empty() && k == 0 {
                continue; // header
            }
            return Err(out.error(k + 1, format!("expected `{columns}` with integers, got \"{}\"", shown(line))));
        };
        out.lines.push((k + 1, a, b));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_is_read_once_and_its_errors_name_the_field_the_file_and_the_line() {
        let dir = std::env::temp_dir().join(format!("mb-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("orders.csv");
        std::fs::write(&path, "step,cell\n# a comment\n\n3, 7\n1,-2\n").unwrap();
        let tables = Tables::default();
        let rows = tables.rows("orders.csv", &path, "step,cell").unwrap();
        assert_eq!(rows.lines, vec![(4, 3, 7), (5, 1, -2)]);
        // Changed on disk: the world keeps what it read.
        std::fs::write(&path, "1,1\n").unwrap();
        assert!(Arc::ptr_eq(&rows, &tables.rows("orders.csv", &path, "step,cell").unwrap()));
        let fresh = Tables::default();
        assert_eq!(fresh.rows("orders.csv", &path, "step,cell").unwrap().lines, vec![(1, 1, 1)]);
        std::fs::write(&path, "1,1\nx,2\n").unwrap();
        let e = Tables::default().rows("humans.csv", &path, "person,cell").unwrap_err().to_string();
        assert_eq!(e, format!("humans.csv = \"{}\": line 2: expected `person,cell` with integers, got \"x,2\"", path.display()));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
