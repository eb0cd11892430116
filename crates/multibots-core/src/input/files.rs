//! Reading input files safely: only regular files, and never more than a cap, so that a
//! scenario, layout or orders file that is a device (`/dev/zero`), a FIFO or a huge file
//! gets a one-line error instead of a hang or runaway memory.

use std::io::Read;
use std::path::{Path, PathBuf};

pub use crate::input::limits::MAX_INPUT_BYTES;

/// The text of a regular file of at most `limit` bytes; the error is one line.
pub fn read_text(path: &Path, limit: u64) -> Result<String, String> {
    // Checked before opening: opening a FIFO with no writer would block.
    let meta = std::fs::metadata(path).map_err(|e| one_line(&e))?;
    if !meta.is_file() {
        return Err(if meta.is_dir() { "is a directory, not a file".into() } else { "is not a regular file".into() });
    }
    if meta.len() > limit {
        return Err(format!("is {} bytes; the limit is {limit}", meta.len()));
    }
    let file = std::fs::File::open(path).map_err(|e| one_line(&e))?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| one_line(&e))?;
    if bytes.len() as u64 > limit {
        return Err(format!("grew past the limit of {limit} bytes while being read"));
    }
    String::from_utf8(bytes).map_err(|e| format!("is not UTF-8 text (byte {})", e.utf8_error().valid_up_to()))
}

/// Checks the shape of TOML text before a parser sees it: no value nested deeper than
/// [`MAX_NESTING`] levels (tables, lists and the parts of dotted keys, counted together) and
/// no key longer than [`MAX_KEY_BYTES`]. Parsers recurse once per level, and a dotted key of
/// 100,000 parts makes 100,000 nested tables, so this is one pass over the bytes that
/// allocates nothing but its stack of open brackets. The text need not be valid TOML: what
/// is not, the parser reports afterwards. The error is one line: `line N: ...`.
///
/// [`MAX_NESTING`]: crate::input::limits::MAX_NESTING
/// [`MAX_KEY_BYTES`]: crate::input::limits::MAX_KEY_BYTES
pub fn check_toml_shape(text: &str) -> Result<(), String> {
    Shape::new(text.as_bytes(), false).scan()
}

/// [`check_toml_shape`] for JSON text: nesting of arrays and objects, and the length of keys.
pub fn check_json_shape(text: &str) -> Result<(), String> {
    Shape::new(text.as_bytes(), true).scan()
}

/// The scanner of [`check_toml_shape`] and [`check_json_shape`].
struct Shape<'a> {
    b: &'a [u8],
    i: usize,
    line: usize,
    json: bool,
    /// Open brackets (`[` or `{`) and the depth of each.
    open: Vec<(u8, usize)>,
    /// Parts of the current `[table]` header (TOML).
    header: usize,
    /// The depth of the value that comes next.
    pending: usize,
    /// Whether a key comes next (TOML: at a line start, or after `{` or `,` in a table).
    want_key: bool,
}

impl<'a> Shape<'a> {
    fn new(b: &'a [u8], json: bool) -> Self {
        Shape { b, i: 0, line: 1, json, open: Vec::new(), header: 0, pending: 0, want_key: !json }
    }

    fn deep(&self, depth: usize, what: &str) -> Result<(), String> {
        use crate::input::limits::MAX_NESTING;
        if depth > MAX_NESTING {
            return Err(format!("line {}: {what} nested deeper than {MAX_NESTING} levels (docs/limits.md)", self.line));
        }
        Ok(())
    }

    fn long_key(&self, len: usize) -> String {
        format!("line {}: a key of {len} bytes; at most {} (docs/limits.md)", self.line, crate::input::limits::MAX_KEY_BYTES)
    }

    fn blanks(&mut self) {
        while self.i < self.b.len() && matches!(self.b[self.i], b' ' | b'\t') {
            self.i += 1;
        }
    }

    fn scan(mut self) -> Result<(), String> {
        while self.i < self.b.len() {
            let c = self.b[self.i];
            match c {
                b'\n' => {
                    self.line += 1;
                    self.i += 1;
                    if self.open.is_empty() && !self.json {
                        self.want_key = true;
                    }
                    continue;
                }
                b' ' | b'\t' | b'\r' => {
                    self.i += 1;
                    continue;
                }
                b'#' if !self.json => {
                    while self.i < self.b.len() && self.b[self.i] != b'\n' {
                        self.i += 1;
                    }
                    continue;
                }
                _ => {}
            }
            if self.want_key {
                self.want_key = false;
                if self.open.is_empty() && c == b'[' {
                    // A [table] or [[array of tables]] header.
                    self.i += if self.b.get(self.i + 1) == Some(&b'[') { 2 } else { 1 };
                    self.header = self.key(0)?;
                    continue;
                }
                if c != b'}' {
                    let base = self.open.last().map_or(self.header, |o| o.1);
                    self.pending = base + self.key(base)?;
                    continue;
                }
            }
            match c {
                b'"' | b'\'' => {
                    let start = self.i;
                    self.string();
                    if self.json && self.open.last().is_some_and(|o| o.0 == b'{') && self.i - start > crate::input::limits::MAX_KEY_BYTES + 2 {
                        // An object's key: a string followed by ':'.
                        let mut k = self.i;
                        while k < self.b.len() && matches!(self.b[k], b' ' | b'\t' | b'\r' | b'\n') {
                            k += 1;
                        }
                        if self.b.get(k) == Some(&b':') {
                            return Err(self.long_key(self.i - start - 2));
                        }
                    }
                }
                b'[' | b'{' => {
                    // In a list, or anywhere in JSON, one deeper than the container; in a
                    // TOML table, one deeper than the key it is the value of.
                    let depth = match self.open.last() {
                        Some(&(b'[', d)) => d,
                        Some(&(_, d)) if self.json => d,
                        _ => self.pending,
                    } + 1;
                    self.deep(depth, "a value")?;
                    self.open.push((c, depth));
                    self.pending = depth;
                    self.i += 1;
                    self.want_key = c == b'{' && !self.json;
                }
                b']' | b'}' => {
                    self.open.pop();
                    self.i += 1;
                }
                b',' => {
                    self.want_key = !self.json && self.open.last().is_some_and(|o| o.0 == b'{');
                    self.i += 1;
                }
                _ => self.i += 1,
            }
        }
        Ok(())
    }

    /// A TOML key (`a`, `"a b"`, `a.b.c`, with blanks around the dots); returns its number
    /// of parts, having checked each part's length and the depth they reach from `base`.
    fn key(&mut self, base: usize) -> Result<usize, String> {
        let mut parts = 0;
        loop {
            self.blanks();
            let start = self.i;
            if matches!(self.b.get(self.i), Some(b'"' | b'\'')) {
                self.string();
            } else {
                while self.i < self.b.len() && (self.b[self.i].is_ascii_alphanumeric() || matches!(self.b[self.i], b'_' | b'-')) {
                    self.i += 1;
                }
            }
            if self.i == start {
                return Ok(parts); // not a key: the parser says what it is
            }
            if self.i - start > crate::input::limits::MAX_KEY_BYTES {
                return Err(self.long_key(self.i - start));
            }
            parts += 1;
            self.deep(base + parts, "a key")?;
            self.blanks();
            if self.b.get(self.i) != Some(&b'.') {
                return Ok(parts);
            }
            self.i += 1;
        }
    }

    /// Skips the string at `i`: JSON's, or TOML's basic, literal and multi-line strings.
    fn string(&mut self) {
        let q = self.b[self.i];
        let triple = !self.json && self.b[self.i..].starts_with(&[q, q, q]);
        self.i += if triple { 3 } else { 1 };
        while self.i < self.b.len() {
            let c = self.b[self.i];
            if c == b'\\' && q == b'"' {
                self.i += 2;
                continue;
            }
            if c == b'\n' {
                if !triple {
                    return; // an unclosed string: the parser says so
                }
                self.line += 1;
            }
            if c == q && (!triple || self.b[self.i..].starts_with(&[q, q, q])) {
                self.i += if triple { 3 } else { 1 };
                // A multi-line string may end in one or two quotes of its own.
                for _ in 0..2 {
                    if triple && self.b.get(self.i) == Some(&q) {
                        self.i += 1;
                    }
                }
                return;
            }
            self.i += 1;
        }
    }
}

/// The temporary path beside an output file that the atomic writers (replays, layout
/// files) write to before renaming it over `path`: `.NAME.PID.K.tmp`, K the first free.
///
/// Refuses a target that exists and is not a regular file: renaming over `/dev/full` or a
/// folder would replace a device or a directory with a file. Removes temporary files of the
/// same target left by writers that were killed (their process no longer exists), so a
/// `kill -9` costs disk space only until the next write.
pub fn output_temp(path: &Path) -> Result<PathBuf, String> {
    replaceable(path)?;
    let name = path.file_name().ok_or("is not a file name")?.to_string_lossy().into_owned();
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    remove_stale(dir, &name);
    // The first K free, as well as the process: two writers of one process with one target
    // (a result and a replay named alike) never share a temporary file.
    let pid = std::process::id();
    let free = (0..=u32::MAX).map(|k| dir.join(format!(".{name}.{pid}.{k}.tmp"))).find(|p| !p.exists()).expect("some K is free");
    Ok(free)
}

/// Checks that `path` is a new path or a regular file, which a rename may replace (called
/// again just before the rename: the path may have changed while the file was written).
pub fn replaceable(path: &Path) -> Result<(), String> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err("is a directory; refusing to replace it with a file".into()),
        Ok(m) if !m.is_file() => Err("is not a regular file (a device, FIFO or socket); refusing to replace it".into()),
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(one_line(&e)),
        _ => Ok(()),
    }
}

/// Removes `.NAME.PID.K.tmp` files in `dir` whose writer process is gone. Only where the
/// process table can be read (`/proc`); elsewhere nothing is removed.
fn remove_stale(dir: &Path, name: &str) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let prefix = format!(".{name}.");
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let file = entry.file_name();
        // `.NAME.PID.K.tmp`
        let Some(pid) =
            file.to_str().and_then(|f| f.strip_prefix(&prefix)).and_then(|rest| rest.strip_suffix(".tmp")).map(|rest| rest.split('.').next().unwrap_or(rest))
        else {
            continue;
        };
        if pid.parse::<u32>().is_ok_and(|p| p != std::process::id() && !Path::new(&format!("/proc/{p}")).exists()) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

fn one_line(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => e.to_string(),
    }
}

/// Writes a file atomically: a temporary file in the same folder, then a rename, so a
/// reader never sees half a file.
pub fn write_atomic(path: &Path, text: &str) -> crate::error::Result<()> {
    let shown = path.display().to_string();
    let tmp = output_temp(path).map_err(|message| crate::error::Error::Io { path: shown.clone(), message })?;
    std::fs::write(&tmp, text).map_err(|e| crate::error::Error::io(&shown, &e))?;
    let renamed = replaceable(path)
        .map_err(|message| crate::error::Error::Io { path: crate::error::shown(&shown), message })
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| crate::error::Error::io(&shown, &e)));
    if renamed.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    renamed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_what_is_not_a_small_regular_file() {
        assert_eq!(read_text(Path::new("/dev/zero"), 100).unwrap_err(), "is not a regular file");
        assert_eq!(read_text(Path::new("/"), 100).unwrap_err(), "is a directory, not a file");
        assert_eq!(read_text(Path::new("/no/such/file"), 100).unwrap_err(), "no such file");
        let dir = std::env::temp_dir().join(format!("mb-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("a.toml");
        std::fs::write(&f, "x = 1\n").unwrap();
        assert_eq!(read_text(&f, 100).unwrap(), "x = 1\n");
        assert_eq!(read_text(&f, 3).unwrap_err(), "is 6 bytes; the limit is 3");
        std::fs::write(&f, [0xff, 0xfe]).unwrap();
        assert!(read_text(&f, 100).unwrap_err().starts_with("is not UTF-8"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn shape_refuses_deep_nesting_and_long_keys_before_parsing() {
        let deep = |open: &str, close: &str, n: usize| format!("x = {}1{}\n", open.repeat(n), close.repeat(n));
        // Depth counts the key: `x` is level 1, each bracket one more.
        assert_eq!(check_toml_shape(&deep("[", "]", 31)), Ok(()));
        assert_eq!(check_toml_shape(&deep("[", "]", 32)).unwrap_err(), "line 1: a value nested deeper than 32 levels (docs/limits.md)");
        assert!(check_toml_shape(&format!("a = 1\n{}", deep("{a = ", "}", 10_000))).unwrap_err().starts_with("line 2: a key nested"));
        assert!(check_toml_shape(&deep("{a = ", "}", 16)).unwrap_err().contains("a key nested"));
        let dotted = vec!["a"; 100_000].join(".");
        assert_eq!(check_toml_shape(&format!("\n\n{dotted} = 1\n")).unwrap_err(), "line 3: a key nested deeper than 32 levels (docs/limits.md)");
        assert!(check_toml_shape(&format!("[{}]\n", vec!["a"; 40].join(" . "))).unwrap_err().contains("a key nested"));
        assert!(check_toml_shape(&format!("[[{}]]\n", vec!["'a'"; 40].join("."))).unwrap_err().contains("a key nested"));
        // A table header's parts count under its keys.
        let header = format!("[{}]\n", vec!["a"; 31].join("."));
        assert_eq!(check_toml_shape(&format!("{header}b = 1\n")), Ok(()));
        assert_eq!(check_toml_shape(&format!("{header}b.c = 1\n")).unwrap_err(), "line 2: a key nested deeper than 32 levels (docs/limits.md)");
        assert_eq!(check_toml_shape(&format!("{header}\n[b]\nc = [[1]]\n")), Ok(()));
        assert_eq!(check_toml_shape(&format!("{} = 1\n", "k".repeat(2000))).unwrap_err(), "line 1: a key of 2000 bytes; at most 1024 (docs/limits.md)");
        assert!(check_toml_shape(&format!("\"{}\" = 1\n", "k".repeat(2000))).unwrap_err().contains("a key of 2002 bytes"));
        // Brackets in strings and comments are text, and long values are not keys.
        let text = format!(
            "a = \"{0}\\\"{0}\" # {1}\nb = '''\n{0}'''\nc = \"\"\"x\\\"\"\"\"\"\nd = \"{2}\"\ne = '{0}'\n",
            "[".repeat(100),
            "{".repeat(100),
            "k".repeat(5000)
        );
        assert_eq!(check_toml_shape(&text), Ok(()));
        // Siblings are as deep as each other, however many.
        let wide = format!("{{{}}}", (0..100).map(|k| format!("\"k{k}\": {{\"a\": [1]}}")).collect::<Vec<_>>().join(", "));
        assert_eq!(check_json_shape(&wide), Ok(()));
        let wide = format!(
            "x = [{}]\ny = {{ {} }}\n",
            vec!["{ a = [1] }"; 100].join(", "),
            (0..100).map(|k| format!("k{k} = {{ a = 1 }}")).collect::<Vec<_>>().join(", ")
        );
        assert_eq!(check_toml_shape(&wide), Ok(()));
        // Shapes in use pass.
        let real = "tasks = { random = 5, seed = 1 }\n[axes]\n\"robot.threshold\" = [2.5, 3.5]\ntasks = [{ random = 5 }]\n[[nodes]]\nout = [\"B\", \"C\"]\n";
        assert_eq!(check_toml_shape(real), Ok(()));
        assert!(check_json_shape(&format!("{}{}", "[".repeat(33), "]".repeat(33))).unwrap_err().contains("a value nested deeper than 32"));
        assert_eq!(check_json_shape(&format!("{{\"a\": {}1{}}}", "[".repeat(31), "]".repeat(31))), Ok(()));
        assert!(check_json_shape(&format!("{{\"{}\": 1}}", "k".repeat(2000))).unwrap_err().contains("a key of 2000 bytes"));
        assert_eq!(check_json_shape(&format!("{{\"a\": \"{}\", \"b\": [\"{0}\"]}}", "k".repeat(2000))), Ok(()));
    }

    #[test]
    fn output_temp_refuses_devices_and_cleans_up_after_dead_writers() {
        assert!(output_temp(Path::new("/dev/full")).unwrap_err().starts_with("is not a regular file"));
        assert!(output_temp(Path::new("/")).is_err());
        let dir = std::env::temp_dir().join(format!("mb-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("r.mbr");
        // A pid above the kernel's maximum (4194304) never runs: a writer killed long ago.
        let dead = dir.join(".r.mbr.4194399.tmp");
        let other = dir.join(".other.mbr.4194399.tmp");
        std::fs::write(&dead, "half").unwrap();
        std::fs::write(&other, "half").unwrap();
        let tmp = output_temp(&target).unwrap();
        let name = tmp.file_name().unwrap().to_string_lossy().into_owned();
        assert_eq!(tmp.parent(), Some(dir.as_path()));
        assert!(name.starts_with(&format!(".r.mbr.{}.", std::process::id())) && name.rsplit('.').next() == Some("tmp"), "{name}");
        // Two writers of one process never share a temporary file.
        std::fs::write(&tmp, "writing").unwrap();
        assert_ne!(output_temp(&target).unwrap(), tmp);
        if Path::new("/proc/self").exists() {
            assert!(!dead.exists());
        }
        assert!(other.exists(), "only the same target's leftovers go");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
