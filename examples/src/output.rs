//! Where the examples write: a folder laid out as `docs/`, pages (`drift.md`) at its top and
//! plots in `figures/`. The user names it as the example's one argument; without one it is
//! `target/docs/` in the workspace, which git ignores, so running an example never rewrites
//! the committed pages and figures. `scripts/figures.sh` regenerates those by passing `docs`.
//!
//! ```sh
//! cargo run --release -p articulated-examples --example hemami_two_link -- /tmp/plots
//! ```

use std::path::{Path, PathBuf};

use articulated::files::write_atomically;

/// The folder an example writes into.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Output {
    root: PathBuf,
}

/// The usage line an example prints for `--help` or a bad command line.
const USAGE: &str = "usage: cargo run --release -p articulated-examples --example NAME [-- OUT]\n\
    writes its pages to OUT/ and its figures to OUT/figures/ (default: target/docs/ in the \
    workspace; `scripts/figures.sh` passes docs/ to regenerate the committed ones)";

impl Output {
    /// The folder from the process' command line (see [`Output::parse`]).
    ///
    /// # Errors
    /// As [`Output::parse`].
    pub fn from_args() -> Result<Self, String> {
        let examples = Path::new(env!("CARGO_MANIFEST_DIR"));
        let workspace = examples.parent().unwrap_or(examples);
        let default = workspace.join("target/docs");
        Self::parse(std::env::args().skip(1), &default)
    }

    /// The folder named by `args` (the arguments after the program's name): none gives
    /// `default`, one names the folder.
    ///
    /// # Errors
    /// More than one argument, an empty one, or `-h`/`--help`: the usage.
    pub fn parse(mut args: impl Iterator<Item = String>, default: &Path) -> Result<Self, String> {
        let root = match (args.next(), args.next()) {
            (None, _) => default.to_path_buf(),
            (Some(a), None) if !a.is_empty() && a != "-h" && a != "--help" => PathBuf::from(a),
            _ => return Err(USAGE.into()),
        };
        Ok(Output { root })
    }

    /// Where the page `name` goes.
    pub fn page(&self, name: &str) -> PathBuf {
        self.root.join(name)
    }

    /// Where the figure `name` goes.
    pub fn figure(&self, name: &str) -> PathBuf {
        self.root.join("figures").join(name)
    }

    /// Writes `contents` to `path` (one of [`page`](Self::page) or
    /// [`figure`](Self::figure)) whole or not at all, creating its folder, and returns the path
    /// as text for the report.
    ///
    /// # Errors
    /// The folder cannot be created or the file written: the path and why.
    pub fn write(&self, path: &Path, contents: &[u8]) -> Result<String, String> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        write_atomically(path, contents).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(path.display().to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_folder_is_the_one_argument_or_the_default() {
        let default = Path::new("/d/target/docs");
        let parse = |args: &[&str]| Output::parse(args.iter().map(|a| a.to_string()), default);
        let out = parse(&[]).unwrap();
        assert_eq!(
            out.figure("a.svg"),
            Path::new("/d/target/docs/figures/a.svg")
        );
        assert_eq!(out.page("a.md"), Path::new("/d/target/docs/a.md"));
        let out = parse(&["docs"]).unwrap();
        assert_eq!(out.figure("a.svg"), Path::new("docs/figures/a.svg"));
        for bad in [&["a", "b"][..], &["--help"], &["-h"], &[""]] {
            assert!(parse(bad).unwrap_err().starts_with("usage:"), "{bad:?}");
        }
    }

    #[test]
    fn writing_creates_the_folder() {
        let dir = std::env::temp_dir().join(format!("articulated-output-{}", std::process::id()));
        let out =
            Output::parse(std::iter::once(dir.display().to_string()), Path::new("x")).unwrap();
        let path = out.figure("f.svg");
        assert_eq!(
            out.write(&path, b"<svg/>").unwrap(),
            path.display().to_string()
        );
        assert_eq!(std::fs::read(&path).unwrap(), b"<svg/>");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
