//! Reading a model file of either kind, chosen by extension.

use std::path::Path;

use articulated_dynamics::model::Model;

use crate::lower::{self, FileError};
use crate::urdf::{self, UrdfError};

/// Why a model file could not be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// A `.chain` file that does not read, parse or validate (each diagnostic names its line and
    /// column).
    Chain(FileError),
    /// A URDF file that does not read or import.
    Urdf(UrdfError),
    /// An extension that is neither `.chain` nor `.urdf`.
    UnknownExtension(String),
    /// `floating` asked for a `.chain` file, where the free base is written in the file itself.
    FloatingChain(String),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Chain(e) => write!(f, "{e}"),
            LoadError::Urdf(e) => write!(f, "{e}"),
            LoadError::UnknownExtension(p) => write!(
                f,
                "{p}: error: unknown model format: expected a `.chain` or `.urdf` file"
            ),
            LoadError::FloatingChain(p) => write!(
                f,
                "{p}: error: a free base is added only under a URDF root; in a `.chain` file write \
                 it as a joint, e.g. `joint base: free {{ parent: world, child: … }}`"
            ),
        }
    }
}

impl std::error::Error for LoadError {}

/// Loads a `.chain` or `.urdf` file into a [`Model`]. With `floating`, a URDF root gets the
/// default free base (Euler `zyx`, Wieber's form): q and v gain 6 leading entries.
pub fn load_model(path: &Path, floating: bool) -> Result<Model, LoadError> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("chain") if floating => Err(LoadError::FloatingChain(path.display().to_string())),
        Some("chain") => lower::load_chain_file(path).map_err(LoadError::Chain),
        Some("urdf") => urdf::load_urdf_file(path, floating).map_err(LoadError::Urdf),
        _ => Err(LoadError::UnknownExtension(path.display().to_string())),
    }
}
