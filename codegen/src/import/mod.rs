//! What the file importers (URDF, MJCF) share: their error, which reports every problem of a
//! file at once, each at its file and line, and the frames and mass properties they compose
//! ([`frames`]).

pub(crate) mod frames;

use std::fmt;
use std::path::{Path, PathBuf};

/// An error found while importing a robot file: every problem found, each at its line.
///
/// Displays one problem per line, as `file:line: message` (or `file: message` when no line is
/// known); a description given as a string is called `<urdf>` or `<mjcf>`. A problem inside a
/// file that an MJCF `<include>`s names that file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ImportError {
    /// What a description given as text is called in messages.
    unnamed: &'static str,
    /// The first problem, then the others, in the order of their lines.
    problems: Vec<Located>,
}

/// One problem: its file (`None`: the file the description was read from), line and message.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Located {
    file: Option<PathBuf>,
    line: Option<usize>,
    message: String,
}

impl ImportError {
    /// A problem of a URDF description, at no line yet.
    pub(crate) fn new(message: impl Into<String>) -> Self {
        ImportError {
            unnamed: "<urdf>",
            problems: vec![Located {
                file: None,
                line: None,
                message: message.into(),
            }],
        }
    }
    /// The same problems, in a description called `unnamed` when it is given as text.
    pub(crate) fn called(mut self, unnamed: &'static str) -> Self {
        self.unnamed = unnamed;
        self
    }
    /// The first of `errors` carrying the others (`None` for none).
    pub(crate) fn all(errors: Vec<ImportError>) -> Option<ImportError> {
        let unnamed = errors.first()?.unnamed;
        Some(ImportError {
            unnamed,
            problems: errors.into_iter().flat_map(|e| e.problems).collect(),
        })
    }
    /// The same problem at `line`.
    pub(crate) fn at(mut self, line: Option<usize>) -> Self {
        if let Some(p) = self.problems.first_mut() {
            p.line = line;
        }
        self
    }
    /// The same problem, at a line of another file than the description's (an MJCF include).
    pub(crate) fn at_file(mut self, file: Option<PathBuf>, line: Option<usize>) -> Self {
        if let Some(p) = self.problems.first_mut() {
            p.file = file;
            p.line = line;
        }
        self
    }
    /// The line of the first problem (`usize::MAX` where unknown), to sort by.
    pub(crate) fn sort_key(&self) -> usize {
        self.line().unwrap_or(usize::MAX)
    }
    /// How many problems this error reports (the first and the others).
    pub fn count(&self) -> usize {
        self.problems.len()
    }
    /// The same error, in the file `path` (for messages).
    pub fn in_file(mut self, path: &Path) -> Self {
        for p in &mut self.problems {
            p.file.get_or_insert_with(|| path.to_path_buf());
        }
        self
    }
    /// The file of the first problem (`None` for a description given as text).
    pub fn file(&self) -> Option<&Path> {
        self.problems.first().and_then(|p| p.file.as_deref())
    }
    /// The 1-based line of the first problem's element, when it could be found.
    pub fn line(&self) -> Option<usize> {
        self.problems.first().and_then(|p| p.line)
    }
    /// What is wrong (the first problem), without the file and line.
    pub fn message(&self) -> &str {
        self.problems.first().map_or("", |p| p.message.as_str())
    }
}

impl fmt::Display for ImportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, p) in self.problems.iter().enumerate() {
            if k > 0 {
                writeln!(f)?;
            }
            match &p.file {
                Some(path) => write!(f, "{}", path.display())?,
                None => write!(f, "{}", self.unnamed)?,
            }
            if let Some(l) = p.line {
                write!(f, ":{l}")?;
            }
            write!(f, ": {}", p.message)?;
        }
        Ok(())
    }
}

impl std::error::Error for ImportError {}
