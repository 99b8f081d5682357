//! Files written whole or not at all: the contents go to a temporary file beside the target,
//! which is then renamed over it (a rename within one directory is atomic), so a reader never
//! sees half a trajectory and a failed run leaves the old file, or none, in place.

use std::io::{self, Write};
use std::path::Path;

/// Writes `contents` to `path` through a temporary file in the same directory.
///
/// # Errors
/// The directory cannot take a temporary file, the write fails, or the rename does; the
/// temporary file is removed in every case.
pub fn write_atomically(path: &Path, contents: &[u8]) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut file = tempfile::Builder::new()
        .prefix(".articulated-")
        .tempfile_in(dir)?;
    file.write_all(contents)?;
    file.as_file().sync_all()?;
    file.persist(path).map_err(|e| e.error)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::write_atomically;

    #[test]
    fn writes_whole_files_and_leaves_nothing_behind_on_failure() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        write_atomically(&path, b"t,q0\n0,1\n").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"t,q0\n0,1\n");
        write_atomically(&path, b"t,q0\n").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"t,q0\n");
        // A directory that does not exist: an error, and no file anywhere.
        let missing = dir.path().join("no/such/dir/out.csv");
        assert!(write_atomically(&missing, b"x").is_err());
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(left.len(), 1, "only out.csv remains");
    }
}
