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

/// The temporary path beside an output file that the atomic writers (replays, layout
/// files) write to before renaming it over `path`: `.NAME.PID.tmp`.
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
    Ok(dir.join(format!(".{name}.{}.tmp", std::process::id())))
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

/// Removes `.NAME.PID.tmp` files in `dir` whose writer process is gone. Only where the
/// process table can be read (`/proc`); elsewhere nothing is removed.
fn remove_stale(dir: &Path, name: &str) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let prefix = format!(".{name}.");
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(pid) = file.to_str().and_then(|f| f.strip_prefix(&prefix)).and_then(|rest| rest.strip_suffix(".tmp")) else { continue };
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
        assert_eq!(tmp, dir.join(format!(".r.mbr.{}.tmp", std::process::id())));
        if Path::new("/proc/self").exists() {
            assert!(!dead.exists());
        }
        assert!(other.exists(), "only the same target's leftovers go");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
