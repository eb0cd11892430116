//! One reader for the CSV tables a scenario names (`orders.csv`: `step,cell`;
//! `humans.csv`: `person,cell`): two integers a line, a first line that is not two integers
//! being a header, blank lines and lines starting with `#` skipped. A file is read from disk
//! once per scenario ([`Tables`]: a run, a batch's runs of one scenario, every `reset()` of a
//! learning environment until it is given a new scenario) and parsed by each run, which
//! checks every row against its own sizes, in line order.

use crate::error::shown;
use crate::error::{Error, Result};
use crate::input::files::{read_text, MAX_INPUT_BYTES};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::{Arc, Mutex};

/// A table's text, with the field and path its errors name.
#[derive(Debug)]
pub(crate) struct Table {
    field: String,
    value: String,
    text: Arc<str>,
}

impl Table {
    /// The error for line `line` (from 1) of this table.
    pub(crate) fn error(&self, line: usize, why: impl std::fmt::Display) -> Error {
        Error::scenario(&self.field, &self.value, format!("line {line}: {why}"))
    }

    /// The rows as `(line, a, b)`, in file order; a line that is not two integers of types
    /// `A` and `B` (`columns` names them) is an error, but for a header on the first line.
    pub(crate) fn rows<'a, A: FromStr, B: FromStr>(&'a self, columns: &'a str) -> impl Iterator<Item = Result<(usize, A, B)>> + 'a {
        let mut any = false;
        self.text.lines().enumerate().filter_map(move |(k, line)| {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                return None;
            }
            let parts: Vec<&str> = line.split(',').map(str::trim).collect();
            let parsed = match parts.as_slice() {
                [a, b] => a.parse::<A>().ok().zip(b.parse::<B>().ok()),
                _ => None,
            };
            match parsed {
                Some((a, b)) => {
                    any = true;
                    Some(Ok((k + 1, a, b)))
                }
                None if !any && k == 0 => None, // a header
                None => Some(Err(self.error(k + 1, format!("expected `{columns}` with integers, got \"{}\"", shown(line))))),
            }
        })
    }
}

/// The tables one scenario's runs have read, by field and path.
#[derive(Debug, Default)]
pub struct Tables {
    read: Mutex<Vec<(String, PathBuf, Arc<str>)>>,
}

impl Tables {
    /// The table at `path`, the scenario's `field` (`orders.csv`, `humans.csv`): read on
    /// first use, then shared.
    pub(crate) fn read(&self, field: &str, path: &Path) -> Result<Table> {
        let value = format!("\"{}\"", path.display());
        let mut read = self.read.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let text = if let Some((_, _, text)) = read.iter().find(|(f, p, _)| f == field && p == path) {
            Arc::clone(text)
        } else {
            let text: Arc<str> = read_text(path, MAX_INPUT_BYTES).map_err(|e| Error::scenario(field, &value, format!("cannot read: {e}")))?.into();
            read.push((field.to_string(), path.to_path_buf(), Arc::clone(&text)));
            text
        };
        Ok(Table { field: field.to_string(), value, text })
    }
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
        let rows = |t: &Tables| t.read("orders.csv", &path).unwrap().rows::<u64, i64>("step,cell").collect::<Result<Vec<_>>>().unwrap();
        assert_eq!(rows(&tables), vec![(4, 3, 7), (5, 1, -2)]);
        // Changed on disk: the scenario's runs keep what they read; a new scenario reads anew.
        std::fs::write(&path, "1,1\n").unwrap();
        assert_eq!(rows(&tables), vec![(4, 3, 7), (5, 1, -2)]);
        assert_eq!(rows(&Tables::default()), vec![(1, 1, 1)]);
        // A negative number where the column holds none is a line that is not two integers.
        std::fs::write(&path, "1,1\n0,-1\n").unwrap();
        let table = Tables::default().read("humans.csv", &path).unwrap();
        let e = table.rows::<u64, u64>("person,cell").collect::<Result<Vec<_>>>().unwrap_err().to_string();
        assert_eq!(e, format!("humans.csv = \"{}\": line 2: expected `person,cell` with integers, got \"0,-1\"", path.display()));
        // ... and on the first line, a header.
        std::fs::write(&path, "0,-1\n2,3\n").unwrap();
        let table = Tables::default().read("humans.csv", &path).unwrap();
        assert_eq!(table.rows::<u64, u64>("person,cell").collect::<Result<Vec<_>>>().unwrap(), vec![(2, 2, 3)]);
        let e = Tables::default().read("orders.csv", &dir.join("none.csv")).unwrap_err().to_string();
        assert!(e.starts_with("orders.csv = \"") && e.contains("cannot read"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
