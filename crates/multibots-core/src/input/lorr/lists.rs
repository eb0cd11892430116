//! The agents file (a count, then one start cell per line) and the task files: 2023, a
//! count then one cell per line; 2024, a `#` line, a count, then one task per line as
//! comma-separated errand cells. Lines that start with `#` are comments in every file, as
//! the 2024 files open with one. Blank lines are skipped.

use super::GridMap;
use crate::error::{Error, Result};
use std::path::Path;

/// The data lines of a file: (line number from 1, text).
fn data_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())).filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
}

fn cell(path: &Path, line: usize, word: &str, map: &GridMap, what: &str) -> Result<u32> {
    let v: i64 =
        word.trim().parse().map_err(|_| Error::input_file(path, Some(line), format!("'{}' is not a cell number", crate::error::shown(word.trim()))))?;
    if v < 0 || v >= map.cells() as i64 {
        return Err(Error::input_file(path, Some(line), format!("cell {v} is off the {} x {} map", map.rows, map.cols)));
    }
    if !map.free[v as usize] {
        let (r, c) = map.row_col(v as u32);
        return Err(Error::input_file(path, Some(line), format!("{what} cell {v} (row {r}, column {c}) is an obstacle")));
    }
    Ok(v as u32)
}

/// The count line, then the rest; the count must be at least `min` and the file must hold it.
fn counted<'a>(path: &Path, text: &'a str, what: &str) -> Result<(usize, Vec<(usize, &'a str)>)> {
    let mut lines = data_lines(text);
    let (line, first) = lines.next().ok_or_else(|| Error::input_file(path, None, format!("the file is empty; it must start with the number of {what}")))?;
    let count: usize =
        first.parse().map_err(|_| Error::input_file(path, Some(line), format!("'{}' is not the number of {what}", crate::error::shown(first))))?;
    let rest: Vec<(usize, &str)> = lines.take(count).collect();
    if rest.len() < count {
        let last = rest.last().map_or(line, |(l, _)| *l);
        return Err(Error::input_file(path, Some(last), format!("the file says {count} {what} but holds {}", rest.len())));
    }
    Ok((line, rest))
}

/// The first `n` start cells of an agents file.
pub(super) fn agents(path: &Path, text: &str, n: usize, map: &GridMap) -> Result<Vec<u32>> {
    let (count_line, rows) = counted(path, text, "agents")?;
    if rows.len() < n {
        return Err(Error::input_file(path, Some(count_line), format!("teamSize is {n} but the file has {} agents", rows.len())));
    }
    let mut taken = vec![false; map.cells()];
    let mut starts = Vec::with_capacity(n);
    for &(line, word) in &rows[..n] {
        let c = cell(path, line, word, map, "start")?;
        if std::mem::replace(&mut taken[c as usize], true) {
            return Err(Error::input_file(path, Some(line), format!("two agents start on cell {c}")));
        }
        starts.push(c);
    }
    Ok(starts)
}

/// A 2023 task file: one errand cell per task.
pub(super) fn tasks_2023(path: &Path, text: &str, map: &GridMap) -> Result<Vec<Vec<u32>>> {
    let (line, rows) = counted(path, text, "tasks")?;
    if rows.is_empty() {
        return Err(Error::input_file(path, Some(line), "the file holds no task"));
    }
    rows.iter()
        .map(|&(line, word)| {
            if word.contains(',') {
                return Err(Error::input_file(path, Some(line), "a 2023 task is one cell; this line has several (a 2024 task file?)"));
            }
            Ok(vec![cell(path, line, word, map, "errand")?])
        })
        .collect()
}

/// A 2024 task file: comma-separated errand cells per task.
pub(super) fn tasks_2024(path: &Path, text: &str, map: &GridMap) -> Result<Vec<Vec<u32>>> {
    let (line, rows) = counted(path, text, "tasks")?;
    if rows.is_empty() {
        return Err(Error::input_file(path, Some(line), "the file holds no task"));
    }
    rows.iter().map(|&(line, text)| text.split(',').map(|w| cell(path, line, w, map, "errand")).collect()).collect()
}
