//! A `build.rs` API: the code `chain!` and `#[derive(Chain)]` would emit, written to a file in
//! `OUT_DIR` for users who want to read it (and for descriptions built by a program).
//!
//! In `build.rs`:
//!
//! ```no_run
//! use articulated_codegen::options::{Output, ScalarKind};
//!
//! fn main() -> Result<(), articulated_codegen::build::BuildError> {
//!     articulated_codegen::Builder::new()
//!         .file("models/arm.chain")
//!         .urdf("models/robot.urdf", false)
//!         .scalar(ScalarKind::F32)
//!         .outputs([Output::MassMatrix, Output::InverseDynamics])
//!         .write("chains.rs")?;
//!     Ok(())
//! }
//! ```
//!
//! and in the crate: `include!(concat!(env!("OUT_DIR"), "/chains.rs"));`. `name`, `scalar` and
//! `outputs` apply to the source added last, as `#[chain(…)]` applies to its file.

use std::fmt;
use std::path::{Path, PathBuf};

use articulated_dynamics::model::Model;

use crate::emit;
use crate::generate::generate;
use crate::load::{load_with, FloatingBase, LoadError, LoadOptions};
use crate::options::{Accuracy, Contact, ContactKind, Description, Loop, Output, ScalarKind};

/// Collects descriptions and writes their generated code to one file.
#[derive(Debug, Default)]
pub struct Builder {
    sources: Vec<Entry>,
}

/// One source and what the builder's methods changed about it.
#[derive(Debug)]
struct Entry {
    source: Source,
    name: Option<String>,
    scalar: Option<ScalarKind>,
    outputs: Option<Vec<Output>>,
    accuracy: Option<Accuracy>,
    locks: Vec<(String, Vec<f64>)>,
    keep: Option<Vec<String>>,
    frames: Option<Vec<String>>,
    contacts: Option<Vec<Contact>>,
    loops: Option<Vec<Loop>>,
    quasi_static: bool,
    lanes: Option<usize>,
    strict: bool,
    balance_inertia: bool,
    mimic_equalities: bool,
}

#[derive(Debug)]
enum Source {
    File(PathBuf, FloatingBase),
    Model(Box<Description>),
}

/// Why [`Builder::to_source`] or [`Builder::write`] failed.
#[derive(Debug)]
pub enum BuildError {
    /// A description file does not load (its message names the file and line).
    Load(LoadError),
    /// The generator refused a description: the check stage's problems with the options the
    /// builder gave it (each one, at once), or a limit of the generator.
    Generate {
        /// The file, or the model's name.
        source: String,
        /// Why.
        error: syn::Error,
    },
    /// `OUT_DIR` is not set: [`Builder::write`] is for `build.rs`.
    NoOutDir,
    /// The file cannot be written.
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        error: std::io::Error,
    },
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BuildError::Load(e) => write!(f, "{e}"),
            BuildError::Generate { source, error } => {
                // Every problem the check stage found, one per line.
                for (k, e) in error.clone().into_iter().enumerate() {
                    if k > 0 {
                        writeln!(f)?;
                    }
                    write!(f, "{source}: {e}")?;
                }
                Ok(())
            }
            BuildError::NoOutDir => write!(f, "OUT_DIR is not set: call this from build.rs"),
            BuildError::Write { path, error } => write!(f, "{}: {error}", path.display()),
        }
    }
}

impl std::error::Error for BuildError {}

impl Builder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    fn push(mut self, source: Source) -> Self {
        self.sources.push(Entry {
            source,
            name: None,
            scalar: None,
            outputs: None,
            accuracy: None,
            locks: Vec::new(),
            keep: None,
            frames: None,
            contacts: None,
            loops: None,
            quasi_static: false,
            lanes: None,
            strict: false,
            balance_inertia: false,
            mimic_equalities: false,
        });
        self
    }

    /// Adds a `.chain` file (relative paths are relative to `CARGO_MANIFEST_DIR`).
    pub fn file(self, path: impl AsRef<Path>) -> Self {
        self.push(Source::File(
            path.as_ref().to_path_buf(),
            FloatingBase::Fixed,
        ))
    }

    /// Adds a URDF file; `floating` puts a free base under its root (`true`: Euler `zyx`;
    /// [`FloatingBase::Quaternion`]: a quaternion).
    pub fn urdf(self, path: impl AsRef<Path>, floating: impl Into<FloatingBase>) -> Self {
        self.push(Source::File(path.as_ref().to_path_buf(), floating.into()))
    }

    /// Adds a MuJoCo MJCF file (`.xml`; its free joints are its own).
    pub fn mjcf(self, path: impl AsRef<Path>) -> Self {
        self.push(Source::File(
            path.as_ref().to_path_buf(),
            FloatingBase::Fixed,
        ))
    }

    /// Adds a model built by a program (for example a seeded random tree), with the default
    /// options.
    pub fn model(self, model: Model) -> Self {
        self.push(Source::Model(Box::new(Description::new(model))))
    }

    /// Adds a description built by a program, with its own options.
    pub fn description(self, description: Description) -> Self {
        self.push(Source::Model(Box::new(description)))
    }

    /// Names the type generated for the source added last (instead of the description's name).
    pub fn name(mut self, name: &str) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.name = Some(name.to_string());
        }
        self
    }

    /// The scalar of the source added last (as `scalar = …` in `#[chain(…)]`).
    pub fn scalar(mut self, scalar: ScalarKind) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.scalar = Some(scalar);
        }
        self
    }

    /// The outputs of the source added last (as `outputs = […]` in `#[chain(…)]`).
    pub fn outputs(mut self, outputs: impl IntoIterator<Item = Output>) -> Self {
        if let Some(last) = self.sources.last_mut() {
            let mut outputs: Vec<Output> = outputs.into_iter().collect();
            outputs.sort();
            outputs.dedup();
            last.outputs = Some(outputs);
        }
        self
    }

    /// The accuracy choice of the source added last (as `accuracy = …` in `#[chain(…)]`).
    pub fn accuracy(mut self, accuracy: Accuracy) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.accuracy = Some(accuracy);
        }
        self
    }

    /// Locks `joint` of the source added last at the position coordinates `q` (as `lock = […]` in
    /// `#[chain(…)]`): it becomes fixed and its child merges into its parent.
    pub fn lock(mut self, joint: &str, q: &[f64]) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.locks.push((joint.to_string(), q.to_vec()));
        }
        self
    }

    /// Keeps only `bodies` of the source added last (as `keep = […]`): the other joints are
    /// locked at neutral and their bodies ride as a payload.
    pub fn keep(mut self, bodies: &[&str]) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.keep = Some(bodies.iter().map(|b| b.to_string()).collect());
        }
        self
    }

    /// The frames the frame outputs of the source added last compute, in that order (as
    /// `frames = […]`): bodies' names, `frame` items', URDF links'.
    pub fn frames(mut self, frames: &[&str]) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.frames = Some(frames.iter().map(|f| f.to_string()).collect());
        }
        self
    }

    /// The contacts of the source added last, in that order (as `contacts = […]`): each frame
    /// and what it holds, e.g. `&[("left_sole", ContactKind::SixD)]`. With [`Builder::loops`],
    /// they give the type `CONTACTS`, `LOOPS`, `CONSTRAINT_ROWS` and
    /// `constrained_forward_dynamics`, and add the frames and outputs the solver reads.
    pub fn contacts(mut self, contacts: &[(&str, ContactKind)]) -> Self {
        if let Some(last) = self.sources.last_mut() {
            let contacts = contacts.iter().map(|&(frame, kind)| Contact {
                frame: frame.to_string(),
                kind,
            });
            last.contacts = Some(contacts.collect());
        }
        self
    }

    /// The loop closures of the source added last, in that order (as `loops = […]`): each
    /// loop's name, what it holds and its two frames `(name, kind, a, b)`: frame `a`'s origin
    /// held on frame `b`'s (`ContactKind::Point`) or frame `a` on frame `b`
    /// (`ContactKind::SixD`).
    pub fn loops(mut self, loops: &[(&str, ContactKind, &str, &str)]) -> Self {
        if let Some(last) = self.sources.last_mut() {
            let loops = loops.iter().map(|&(name, kind, a, b)| Loop {
                name: name.to_string(),
                kind,
                a: a.to_string(),
                b: b.to_string(),
            });
            last.loops = Some(loops.collect());
        }
        self
    }

    /// Refuse the file added last if it loads with warnings (as `strict` in `#[chain(…)]`).
    pub fn strict(mut self) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.strict = true;
        }
        self
    }

    /// Balance the inertias no rigid body has in the file added last instead of warning (as
    /// `balance_inertia` in `#[chain(…)]`; MuJoCo's `balanceinertia`).
    pub fn balance_inertia(mut self) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.balance_inertia = true;
        }
        self
    }

    /// Make each `<joint>` equality of the MJCF file added last a mimic joint (or a lock) instead
    /// of keeping its coordinates with a warning (as `mimic_equalities` in `#[chain(…)]`).
    pub fn mimic_equalities(mut self) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.mimic_equalities = true;
        }
        self
    }

    /// Quasi-static motion for the source added last (as `quasi_static`): velocity-product
    /// terms dropped.
    pub fn quasi_static(mut self) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.quasi_static = true;
        }
        self
    }

    /// Batch functions over lanes of `n` states for the source added last (as `lanes: n`;
    /// `articulated::lanes`).
    pub fn lanes(mut self, n: usize) -> Self {
        if let Some(last) = self.sources.last_mut() {
            last.lanes = Some(n);
        }
        self
    }

    /// The formatted code of every source, with a header per chain.
    ///
    /// # Errors
    /// The first description that does not load or generate, with its message (file, line and
    /// column for a `.chain` file).
    pub fn to_source(&self) -> Result<String, BuildError> {
        self.render().map(|(source, _)| source)
    }

    /// The warnings of the description files, each `file:line: warning: message` ([`Builder::write`]
    /// gives them to cargo, which shows them).
    ///
    /// # Errors
    /// As [`Builder::to_source`].
    pub fn warnings(&self) -> Result<Vec<String>, BuildError> {
        self.render().map(|(_, warnings)| warnings)
    }

    /// The source and the warnings of every description.
    fn render(&self) -> Result<(String, Vec<String>), BuildError> {
        let mut warnings = Vec::new();
        let manifest = std::env::var_os("CARGO_MANIFEST_DIR").map(PathBuf::from);
        let mut out = String::from(
            "// Generated by articulated-codegen (articulated_codegen::Builder) in build.rs.\n\
             // Do not edit: change the descriptions and rebuild.\n\n",
        );
        for entry in &self.sources {
            let (mut chain, label) = match &entry.source {
                Source::File(path, floating) => {
                    let full = match (&manifest, path.is_absolute()) {
                        (Some(dir), false) => dir.join(path),
                        _ => path.clone(),
                    };
                    let options = LoadOptions {
                        floating: *floating,
                        balance_inertia: entry.balance_inertia,
                        strict: entry.strict,
                        mimic_equalities: entry.mimic_equalities,
                    };
                    let chain = load_with(&full, options).map_err(BuildError::Load)?;
                    warnings.extend(chain.warnings.iter().map(|w| w.display_in(path)));
                    (chain, path.display().to_string())
                }
                Source::Model(d) => ((**d).clone(), format!("the model `{}`", d.model.name)),
            };
            if let Some(n) = &entry.name {
                chain.model.name = n.clone();
            }
            if let Some(s) = entry.scalar {
                chain.options.scalar = s;
            }
            if let Some(o) = &entry.outputs {
                chain.options.outputs = o.clone();
            }
            if let Some(a) = entry.accuracy {
                chain.options.accuracy = a;
            }
            chain.options.locks.extend(entry.locks.iter().cloned());
            if let Some(k) = &entry.keep {
                chain.options.keep = Some(k.clone());
            }
            if let Some(f) = &entry.frames {
                chain.options.frames = f.clone();
            }
            if let Some(c) = &entry.contacts {
                chain.options.contacts = c.clone();
            }
            if let Some(l) = &entry.loops {
                chain.options.loops = l.clone();
            }
            chain.options.quasi_static |= entry.quasi_static;
            if entry.lanes.is_some() {
                chain.options.lanes = entry.lanes;
            }
            let failed = |error| BuildError::Generate {
                source: label.clone(),
                error,
            };
            let g = generate(&chain.model, &chain.options).map_err(failed)?;
            out.push_str(&format!("// {} from {label}\n", chain.model.name));
            let width = g
                .functions
                .iter()
                .map(|f| f.output.name().len())
                .fold(24, usize::max);
            for f in &g.functions {
                out.push_str(&format!("//   {:<width$} {}\n", f.output.name(), f.ops));
            }
            out.push_str(&emit::format(g.tokens).map_err(failed)?);
            out.push('\n');
        }
        Ok((out, warnings))
    }

    /// Writes [`Builder::to_source`] to `OUT_DIR/file_name` and tells cargo to rerun when a
    /// description file changes. Returns the path written.
    ///
    /// # Errors
    /// As [`Builder::to_source`], or `OUT_DIR` unset or not writable.
    pub fn write(&self, file_name: &str) -> Result<PathBuf, BuildError> {
        let out_dir = std::env::var_os("OUT_DIR").ok_or(BuildError::NoOutDir)?;
        let path = Path::new(&out_dir).join(file_name);
        let (source, warnings) = self.render()?;
        for w in warnings {
            // Cargo shows these after the build script runs, one per line.
            println!("cargo:warning={w}");
        }
        // Whole or not at all: a failed write leaves the previous file, never half of one.
        let tmp = path.with_extension("rs.tmp");
        std::fs::write(&tmp, source)
            .and_then(|()| std::fs::rename(&tmp, &path))
            .map_err(|error| BuildError::Write {
                path: path.clone(),
                error,
            })?;
        for entry in &self.sources {
            if let Source::File(p, _) = &entry.source {
                println!("cargo:rerun-if-changed={}", p.display());
            }
        }
        Ok(path)
    }
}
