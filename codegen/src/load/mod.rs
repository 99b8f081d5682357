//! Loading a description: the one place that reads files, for every front end (the macros, the
//! [`Builder`](crate::Builder), the CLI). The file's extension picks the front end:
//! - `.chain`: [`chain_file`] tokenizes the text with line and column spans, then the grammar
//!   ([`crate::parse`]) and the checks ([`crate::lower`]) run on it;
//! - `.urdf`: [`crate::urdf`] imports it;
//! - `.xml`: the root element picks: `<mujoco>` is MJCF ([`crate::mjcf`]), `<robot>` URDF.

pub mod chain_file;

use std::path::{Path, PathBuf};

use articulated_dynamics::model::Model;

pub use chain_file::{parse_chain_str, Diagnostic, FileError};

use crate::options::{Description, Warning};
pub use crate::urdf::FloatingBase;
use crate::urdf::{self, UrdfError, UrdfOptions};

/// How a file is read: the base under a URDF root, what to do with the inertias of bodies that
/// no rigid body has, and whether a warning refuses the file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// The base under a URDF root (ignored for a `.chain` file, which must not ask for one).
    pub floating: FloatingBase,
    /// Replace the inertia of each body that breaks the triangle inequality or is not positive
    /// semi-definite by the mean of its principal moments times the identity, as MuJoCo's
    /// `balanceinertia` does (where that mean is positive), instead of warning.
    pub balance_inertia: bool,
    /// Refuse a file that loads with warnings ([`LoadError::Strict`]).
    pub strict: bool,
    /// In an MJCF model, make each `<joint>` equality with a linear `polycoef` a mimic joint
    /// (or lock its joint where it names no second joint) instead of keeping every coordinate
    /// with a warning ([`crate::mjcf::MjcfOptions::mimic_equalities`]).
    pub mimic_equalities: bool,
}

impl From<FloatingBase> for LoadOptions {
    fn from(floating: FloatingBase) -> Self {
        LoadOptions {
            floating,
            ..LoadOptions::default()
        }
    }
}

/// Why a model file could not be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// The file cannot be read.
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// A `.chain` file that does not parse or validate (each diagnostic names its line and
    /// column).
    Chain(FileError),
    /// A URDF file that does not import.
    Urdf(UrdfError),
    /// An MJCF file that does not import.
    Mjcf(crate::mjcf::MjcfError),
    /// An extension that is not `.chain`, `.urdf` or `.xml`.
    UnknownExtension(PathBuf),
    /// `floating` asked for a `.chain` or MJCF file, where the free base is written in the file
    /// itself.
    FloatingChain(PathBuf),
    /// A strict load ([`LoadOptions::strict`]) of a file that loads with warnings.
    Strict {
        /// The file.
        path: PathBuf,
        /// Every warning, each an error now.
        warnings: Vec<Warning>,
    },
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Read { path, error } => {
                write!(f, "{}: error: cannot read: {error}", path.display())
            }
            LoadError::Chain(e) => write!(f, "{e}"),
            LoadError::Urdf(e) | LoadError::Mjcf(e) => write!(f, "{e}"),
            LoadError::UnknownExtension(p) => write!(
                f,
                "{}: error: unknown model format: expected a `.chain`, `.urdf` or `.xml` (URDF or MJCF) file",
                p.display()
            ),
            LoadError::Strict { path, warnings } => {
                for w in warnings {
                    let line = w.display_in(path).replacen(": warning: ", ": error: ", 1);
                    writeln!(f, "{line}")?;
                }
                write!(f, "(refused: a strict load takes no warnings)")
            }
            LoadError::FloatingChain(p) => write!(
                f,
                "{}: error: a free base is added only under a URDF root; in a `.chain` file write \
                 it as a joint, e.g. `joint base: free {{ parent: world, child: … }}`, and in \
                 MJCF as `<freejoint/>` in the body",
                p.display()
            ),
        }
    }
}

impl std::error::Error for LoadError {}

/// Loads a `.chain`, `.urdf` or `.xml` (URDF or MJCF, by its root element) file into a
/// [`Description`]. With `floating` a URDF root gets a
/// free base: `true` or [`FloatingBase::Euler`] the default (Euler `zyx`, Wieber's form: q and v
/// gain 6 leading entries), [`FloatingBase::Quaternion`] a quaternion (q gains 7, v 6).
///
/// # Errors
/// A [`LoadError`] naming the file (and, for a problem inside it, the line).
pub fn load(path: &Path, floating: impl Into<FloatingBase>) -> Result<Description, LoadError> {
    load_with(path, LoadOptions::from(floating.into()))
}

/// [`load`] as `options` say.
///
/// # Errors
/// As [`load`], and [`LoadError::Strict`] for a strict load of a file with warnings.
pub fn load_with(path: &Path, options: LoadOptions) -> Result<Description, LoadError> {
    let floating = options.floating;
    let ext = path.extension().and_then(|e| e.to_str());
    match ext {
        Some("chain") if floating.is_floating() => {
            return Err(LoadError::FloatingChain(path.to_path_buf()))
        }
        Some("chain" | "urdf" | "xml") => {}
        _ => return Err(LoadError::UnknownExtension(path.to_path_buf())),
    }
    let text = std::fs::read_to_string(path).map_err(|error| LoadError::Read {
        path: path.to_path_buf(),
        error,
    })?;
    let chain = if ext == Some("chain") {
        parse_chain_str(&text, path).map_err(LoadError::Chain)?
    } else if ext == Some("xml") && crate::mjcf::is_mjcf(&text) {
        if floating.is_floating() {
            return Err(LoadError::FloatingChain(path.to_path_buf()));
        }
        let mjcf = crate::mjcf::MjcfOptions {
            balance_inertia: options.balance_inertia,
            mimic_equalities: options.mimic_equalities,
        };
        crate::mjcf::from_mjcf_file_with(path, &text, mjcf).map_err(LoadError::Mjcf)?
    } else {
        let urdf_options = UrdfOptions {
            floating,
            balance_inertia: options.balance_inertia,
        };
        urdf::from_urdf_str_with(&text, urdf_options)
            .map_err(|e| LoadError::Urdf(e.in_file(path)))?
    };
    if options.strict && !chain.warnings.is_empty() {
        return Err(LoadError::Strict {
            path: path.to_path_buf(),
            warnings: chain.warnings,
        });
    }
    Ok(chain)
}

/// [`load`], keeping only the physics (what the reference dynamics needs).
///
/// # Errors
/// As [`load`].
pub fn load_model(path: &Path, floating: impl Into<FloatingBase>) -> Result<Model, LoadError> {
    load(path, floating).map(|d| d.model)
}
