//! Files written whole or not at all: the contents go to a temporary file beside the target,
//! which is then renamed over it (a rename within one directory is atomic), so a reader never
//! sees half a trajectory and a failed run leaves the old file, or none, in place.
//!
//! The file gets the permissions a file created by `std::fs::write` would have (on Unix,
//! `0o666` less the process' umask: usually `0o644`), or those of the file it replaces: not the
//! owner-only `0o600` of a temporary file.

use std::io::{self, Write};
use std::path::Path;

/// Writes `contents` to `path` through a temporary file in the same directory, with the
/// permissions of a newly created file, or of the file it replaces ([module docs](self)).
///
/// # Errors
/// The directory cannot take a temporary file, the write fails, or the rename does; the
/// temporary file is removed in every case.
pub fn write_atomically(path: &Path, contents: &[u8]) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".articulated-");
    // The mode `open(2)` gives a new file (`std::fs::File::create`'s), which the umask then
    // narrows, in place of tempfile's owner-only 0o600.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let mut file = builder.tempfile_in(dir)?;
    // A file being replaced keeps its mode.
    #[cfg(unix)]
    if let Ok(old) = std::fs::metadata(path) {
        if old.is_file() {
            file.as_file().set_permissions(old.permissions())?;
        }
    }
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

    /// Issue 31: the files came out `0o600` (tempfile's mode), where a file created by
    /// `std::fs::write` in the same place has `0o666` less the umask; one being replaced keeps
    /// its own mode.
    #[cfg(unix)]
    #[test]
    fn files_have_the_mode_of_a_normally_created_file() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let mode = |p: &std::path::Path| {
            format!(
                "{:o}",
                std::fs::metadata(p).unwrap().permissions().mode() & 0o777
            )
        };
        let normal = dir.path().join("normal.csv");
        std::fs::write(&normal, b"x").unwrap();
        let written = dir.path().join("out.csv");
        write_atomically(&written, b"x").unwrap();
        // (Under the usual umask 0o022: 0o644; only a umask of 0o077 would hide the fault.)
        assert_eq!(mode(&written), mode(&normal));
        // An existing file keeps its mode, narrower or wider than the default.
        for kept in [0o640, 0o664] {
            std::fs::set_permissions(&written, std::fs::Permissions::from_mode(kept)).unwrap();
            write_atomically(&written, b"y").unwrap();
            assert_eq!(mode(&written), format!("{kept:o}"));
            assert_eq!(std::fs::read(&written).unwrap(), b"y");
        }
    }
}
