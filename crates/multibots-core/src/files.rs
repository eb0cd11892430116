//! Reading input files safely: only regular files, and never more than a cap, so that a
//! scenario, layout or orders file that is a device (`/dev/zero`), a FIFO or a huge file
//! gets a one-line error instead of a hang or runaway memory.

use std::io::Read;
use std::path::Path;

pub use crate::limits::MAX_INPUT_BYTES;

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
}
