//! What to generate from a chain, apart from the physics: the type's visibility and docs, the
//! scalar, the outputs. Every front end states them the same way: the settings of a `.chain`
//! file or of `chain!{}` (`scalar: f32;`, `outputs: [mass_matrix, bias];`), the keys of
//! `#[chain(…, scalar = f32, outputs = [mass_matrix, bias])]`, the methods of
//! [`crate::Builder`], and `articulated expand --scalar … --outputs …`.
//!
//! The physics (bodies, joints, gravity, parameters) is the
//! [`articulated_dynamics::model::Model`], which the reference dynamics reads too; a
//! [`Description`] is the two together, what every front end produces.

use std::fmt;

use proc_macro2::TokenStream;
use quote::quote;

use articulated_dynamics::model::Model;
use articulated_dynamics::prune::{self, PruneError};

pub use crate::outputs::Output;

/// The name of `x` in a table of every value with its name (each value stands in it once).
fn name_in<T: PartialEq>(all: &[(T, &'static str)], x: T) -> &'static str {
    all.iter().find(|(y, _)| *y == x).map_or("", |(_, n)| n)
}

/// Which scalar the generated code computes in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ScalarKind {
    /// `f64` (the default).
    #[default]
    F64,
    /// `f32`.
    F32,
    /// Generic over `T: nalgebra::RealField + Copy`.
    Generic,
}

impl ScalarKind {
    /// Every scalar with its name in the grammar and the attribute.
    pub const ALL: [(ScalarKind, &'static str); 3] = [
        (ScalarKind::F64, "f64"),
        (ScalarKind::F32, "f32"),
        (ScalarKind::Generic, "generic"),
    ];

    /// The scalar of that name (`f64`, `f32`, `generic`).
    pub fn from_name(name: &str) -> Option<ScalarKind> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(s, _)| *s)
    }

    /// Its name in the grammar.
    pub fn name(self) -> &'static str {
        name_in(&Self::ALL, self)
    }
}

/// What the generator optimises the generated functions for, where their formulations differ in
/// accuracy as well as in speed (`accuracy: fastest | robust` in a description).
///
/// Measured against the double-double ground truth (`articulated_dynamics::extended`; the
/// extremes table, `docs/accuracy.md`): every formulation of every output agrees to a few ulps
/// at well-conditioned states. Forward dynamics is where they part: CRBA + `LᵀDL` loses digits
/// as `ε·cond(M)` (the two-link near gimbal lock), ABA keeps them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Accuracy {
    /// The fewest operations for every output (the default).
    #[default]
    Fastest,
    /// Forward dynamics by ABA, whose error does not grow with `cond(M)`, even where CRBA +
    /// `LᵀDL` takes fewer operations; the other outputs as [`Accuracy::Fastest`] (their
    /// formulations measure alike).
    Robust,
}

impl Accuracy {
    /// Every choice with its name in the grammar and the attribute.
    pub const ALL: [(Accuracy, &'static str); 2] =
        [(Accuracy::Fastest, "fastest"), (Accuracy::Robust, "robust")];

    /// The choice of that name (`fastest`, `robust`).
    pub fn from_name(name: &str) -> Option<Accuracy> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(a, _)| *a)
    }

    /// Its name in the grammar.
    pub fn name(self) -> &'static str {
        name_in(&Self::ALL, self)
    }
}

/// What a contact declared in the description holds (`contacts: [left_sole: six_d, toe:
/// point];`): the runtime's `articulated::constraint::Kind`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ContactKind {
    /// The frame's origin: 3 rows (its classical linear acceleration, world axes), a force in
    /// world axes.
    Point,
    /// The whole frame: 6 rows (its spatial acceleration, LOCAL), a wrench `[n; f]` in the
    /// frame's axes.
    SixD,
}

impl ContactKind {
    /// Every kind with its name in the grammar, the attribute and the CLI.
    pub const ALL: [(ContactKind, &'static str); 2] =
        [(ContactKind::SixD, "six_d"), (ContactKind::Point, "point")];

    /// The kind of that name (`six_d`, `point`).
    pub fn from_name(name: &str) -> Option<ContactKind> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(k, _)| *k)
    }

    /// Its name in the grammar.
    pub fn name(self) -> &'static str {
        name_in(&Self::ALL, self)
    }

    /// Its rows: 3 for a point, 6 for a six-dimensional contact.
    pub const fn rows(self) -> usize {
        match self {
            ContactKind::Point => 3,
            ContactKind::SixD => 6,
        }
    }
}

/// A ground of the contact simulation (`grounds: [floor: [0.0, 0.0, 1.0, 0.0]]`): the
/// half-space `n·x ≥ d`, the runtime's `articulated::contact::Ground`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneGround {
    /// Its name in the description.
    pub name: String,
    /// `n`, a unit vector (the lowering divides by its length).
    pub normal: [f64; 3],
    /// `d`, along the unit normal.
    pub offset: f64,
}

/// A contact sphere of the contact simulation (`spheres: [heel: sphere(left_foot, [-0.06,
/// 0.05, -0.09], 0.0)]`): the runtime's `articulated::contact::Sphere`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSphere {
    /// Its name in the description.
    pub name: String,
    /// The frame it sits on (a body, a `frame` item, a URDF link).
    pub frame: String,
    /// Its centre in the frame's axes (m).
    pub offset: [f64; 3],
    /// Its radius (m), `0` for a point.
    pub radius: f64,
}

/// A contact declared in the description: `left_sole: six_d` holds the frame `left_sole`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Contact {
    /// The frame it holds (a body, a `frame` item, a URDF link), which names the contact.
    pub frame: String,
    /// What it holds of the frame.
    pub kind: ContactKind,
}

/// A loop closure declared in the description (the runtime's `articulated::constraint::Loop`):
/// `rod: point(a, b)` holds frame `a`'s origin on frame `b`'s (3 rows, world axes);
/// `grip: six_d(a, b)` holds frame `a` on frame `b` (6 rows, `a`'s axes).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loop {
    /// Its name.
    pub name: String,
    /// What it holds.
    pub kind: ContactKind,
    /// The frame held.
    pub a: String,
    /// The frame it is held on.
    pub b: String,
}

impl Loop {
    /// Its rows: 3 for a point, 6 for a frame.
    pub const fn rows(&self) -> usize {
        self.kind.rows()
    }
}

/// The outputs the runtime's constraint solver reads (`articulated::constraint::forward_dynamics_of`),
/// generated with any declared constraint so that it can solve any subset of them at run time.
pub const CONSTRAINT_OUTPUTS: [Output; 5] = [
    Output::MassMatrixAndNonlinearEffects,
    Output::FramePlacements,
    Output::FrameJacobiansLocal,
    Output::FrameVelocities,
    Output::FrameAccelerations,
];

/// The visibility of the generated type (and of its parameter struct).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Visibility {
    /// None: private to the module.
    #[default]
    Private,
    /// `pub`.
    Public,
    /// `pub(…)` with what stands in the parentheses: `crate`, `super`, `in a::b`.
    Restricted(String),
}

impl Visibility {
    /// The visibility as tokens.
    pub fn to_tokens(&self) -> TokenStream {
        match self {
            Visibility::Private => quote!(),
            Visibility::Public => quote!(pub),
            Visibility::Restricted(inner) => {
                let inner: TokenStream = inner.parse().unwrap_or_else(|_| quote!(crate));
                quote!(pub(#inner))
            }
        }
    }
}

impl fmt::Display for Visibility {
    /// As Rust writes it: ``, `pub`, `pub(crate)`, `pub(in a::b)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Visibility::Private => Ok(()),
            Visibility::Public => write!(f, "pub"),
            Visibility::Restricted(inner) => write!(f, "pub({inner})"),
        }
    }
}

/// What to generate for a chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Visibility of the generated type.
    pub visibility: Visibility,
    /// Documentation lines for the generated type, as written (`///` lines without the
    /// slashes).
    pub doc: Vec<String>,
    /// The scalar of the generated code.
    pub scalar: ScalarKind,
    /// The outputs to generate, sorted, without duplicates.
    pub outputs: Vec<Output>,
    /// Speed or accuracy, where formulations differ.
    pub accuracy: Accuracy,
    /// Joints locked at the given position coordinates (`lock: [elbow(0.3)]`): they become fixed
    /// and their bodies merge ([`articulated_dynamics::prune`]).
    pub locks: Vec<(String, Vec<f64>)>,
    /// The bodies the scene moves (`keep: [base, upper]`); every other joint is locked (at
    /// `locks`' value or neutral) and the dropped bodies ride as a payload. `None`: all.
    pub keep: Option<Vec<String>>,
    /// Quasi-static motion (`quasi_static: true`): the velocity-product terms are dropped, as
    /// if `v = 0` in every output (an approximation; `bias` is then zero).
    pub quasi_static: bool,
    /// The frames the frame outputs compute (`frames: [tool, left_sole]`), in that order:
    /// bodies' names or the model's [`Frame`](crate::model::Frame)s'.
    pub frames: Vec<String>,
    /// The contacts (`contacts: [left_sole: six_d, toe: point]`), in declaration order: with
    /// [`Options::loops`], they make the generated `constrained_forward_dynamics`
    /// ([`Options::resolved`]), and with [`Output::ForwardDynamicsDerivatives`] its derivatives,
    /// `constrained_forward_dynamics_derivatives`.
    pub contacts: Vec<Contact>,
    /// The loop closures (`loops: [rod: point(a, b)]`), in declaration order.
    pub loops: Vec<Loop>,
    /// The grounds of the contact simulation (`grounds: [floor: [0, 0, 1, 0]]`).
    pub grounds: Vec<SceneGround>,
    /// Its contact spheres (`spheres: [heel: sphere(left_foot, [x, y, z], r)]`): with them the
    /// type gains `GROUNDS` and `SPHERES` for `articulated::contact`, and the outputs its
    /// stepping reads ([`Options::resolved`]).
    pub spheres: Vec<SceneSphere>,
    /// The spheres' friction coefficient (`friction: 0.8`).
    pub friction: Option<f64>,
    /// The spheres' restitution (`restitution: 0.0`, the default).
    pub restitution: f64,
    /// States per lane value of the batch functions (`lanes: 4`): with it each output's batch
    /// twin runs the generated statements on [`LANES`] states at once (`articulated::lanes`);
    /// without it, state by state. `f64` and `f32` only.
    pub lanes: Option<usize>,
}

/// The lane counts a description may ask for (`lanes: 4`).
pub const LANES: [usize; 4] = [2, 4, 8, 16];

/// The message for a lane count that is not one of [`LANES`].
pub fn unknown_lanes(found: &str) -> String {
    format!("`lanes` must be 2, 4, 8 or 16 (states per vector value), found `{found}`")
}

impl Default for Options {
    /// A public type in `f64` with the default outputs ([`Output::DEFAULT`]) and no docs.
    fn default() -> Self {
        Options {
            visibility: Visibility::Public,
            doc: Vec::new(),
            scalar: ScalarKind::F64,
            outputs: Output::DEFAULT.to_vec(),
            accuracy: Accuracy::Fastest,
            locks: Vec::new(),
            keep: None,
            quasi_static: false,
            frames: Vec::new(),
            contacts: Vec::new(),
            loops: Vec::new(),
            grounds: Vec::new(),
            spheres: Vec::new(),
            friction: None,
            restitution: 0.0,
            lanes: None,
        }
    }
}

impl Options {
    /// Whether the scene asks for less than the whole model (locked joints or a sub-tree).
    pub fn prunes(&self) -> bool {
        !self.locks.is_empty() || self.keep.is_some()
    }

    /// The model the generator works on for this scene: `model` with the locked joints fixed,
    /// reduced to the sub-tree, and its fixed joints merged ([`articulated_dynamics::prune`]);
    /// `model` itself when nothing is pruned.
    ///
    /// # Errors
    /// A lock or a kept body that does not fit the model.
    pub fn scene_model(&self, model: &Model) -> Result<Model, PruneError> {
        if !self.prunes() {
            return Ok(model.clone());
        }
        let mut m = model.clone();
        for (joint, q) in &self.locks {
            m = prune::lock(&m, joint, q)?;
        }
        if let Some(keep) = &self.keep {
            let names: Vec<&str> = keep.iter().map(String::as_str).collect();
            m = prune::keep(&m, &names, &[])?;
        }
        Ok(prune::merge_fixed(&m))
    }

    /// Whether the description declares constraints (`contacts` or `loops`).
    pub fn constrained(&self) -> bool {
        !self.contacts.is_empty() || !self.loops.is_empty()
    }

    /// The rows of the declared constraints: 3 per point contact and loop, 6 per
    /// six-dimensional contact.
    pub fn constraint_rows(&self) -> usize {
        let contacts: usize = self.contacts.iter().map(|c| c.kind.rows()).sum();
        contacts + self.loops.iter().map(Loop::rows).sum::<usize>()
    }

    /// The frames the constraints name, in declaration order (the contacts', then each loop's
    /// two), each once.
    pub fn constraint_frames(&self) -> Vec<&str> {
        let named = self.contacts.iter().map(|c| c.frame.as_str());
        let looped = self.loops.iter().flat_map(|l| [l.a.as_str(), l.b.as_str()]);
        let mut frames: Vec<&str> = Vec::new();
        for f in named.chain(looped) {
            if !frames.contains(&f) {
                frames.push(f);
            }
        }
        frames
    }

    /// The options the generator works from: with constraints declared, the frames they name
    /// appended to [`Options::frames`] (in order, where absent) and the outputs the runtime's
    /// solver reads ([`CONSTRAINT_OUTPUTS`]) added; without, these options unchanged.
    pub fn resolved(&self) -> Options {
        let mut options = self.clone();
        if !self.spheres.is_empty() {
            for s in &self.spheres {
                if !options.frames.contains(&s.frame) {
                    options.frames.push(s.frame.clone());
                }
            }
            let outputs: Vec<Output> = options
                .outputs
                .iter()
                .copied()
                .chain(SCENE_OUTPUTS)
                .collect();
            options.set_outputs(outputs);
        }
        if !self.constrained() {
            return options;
        }
        for f in self.constraint_frames() {
            if !options.frames.iter().any(|g| g == f) {
                options.frames.push(f.to_string());
            }
        }
        let outputs: Vec<Output> = options
            .outputs
            .iter()
            .copied()
            .chain(CONSTRAINT_OUTPUTS)
            .collect();
        options.set_outputs(outputs);
        options
    }

    /// Sets the outputs, sorted and without duplicates.
    pub fn set_outputs(&mut self, outputs: impl IntoIterator<Item = Output>) {
        self.outputs = outputs.into_iter().collect();
        self.outputs.sort();
        self.outputs.dedup();
    }
}

/// What `articulated::contact::TimeStepper` reads, added to a description that declares contact
/// spheres.
pub const SCENE_OUTPUTS: [Output; 3] = [
    Output::MassMatrixAndNonlinearEffects,
    Output::FramePlacements,
    Output::FrameJacobiansLocal,
];

/// A chain as a front end reads it: the physics and what to generate from it.
#[derive(Clone, Debug, PartialEq)]
pub struct Description {
    /// Bodies, joints, gravity, parameters: what the reference dynamics reads too.
    pub model: Model,
    /// Visibility, docs, scalar, outputs.
    pub options: Options,
    /// What the description holds that loads but deserves a look (a URDF link's inertia that
    /// breaks the triangle inequality, a `<mimic>` on a fixed joint): each front end reports
    /// them (the CLI on stderr, `Builder` as `cargo:warning`, the macros as a compiler
    /// warning), and a strict load refuses them.
    pub warnings: Vec<Warning>,
    /// What the file holds that the dynamics leave out by design, said once (an MJCF model's
    /// actuators and tendons): the CLI prints them on stderr; a build does not warn, and a
    /// strict load takes them.
    pub notes: Vec<Warning>,
    /// The joints a URDF declares `continuous`, in joint order (mimic joints left out): revolute
    /// joints here, one angle each, where Pinocchio stores `(cos θ, sin θ)`
    /// (`articulated::pinocchio`). Empty for other front ends.
    pub continuous: Vec<String>,
    /// A URDF's joints with coordinates in the order Pinocchio's URDF parser gives them, which
    /// may differ from ours (it takes a link's child joints in the order of their names, not
    /// the file's): what `articulated::pinocchio::Layout::with_order` needs. Empty for other
    /// front ends.
    pub pinocchio_order: Vec<String>,
}

/// A problem that does not stop a description from loading, at its line where known.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// The 1-based line in the description's file.
    pub line: Option<usize>,
    /// What it is, and what was done about it.
    pub message: String,
}

impl Warning {
    /// `file:line: warning: message`, as compilers write it.
    pub fn display_in(&self, file: &std::path::Path) -> String {
        match self.line {
            Some(l) => format!("{}:{l}: warning: {}", file.display(), self.message),
            None => format!("{}: warning: {}", file.display(), self.message),
        }
    }
}

impl Description {
    /// A model with the default [`Options`].
    pub fn new(model: Model) -> Self {
        Description {
            model,
            options: Options::default(),
            warnings: Vec::new(),
            notes: Vec::new(),
            continuous: Vec::new(),
            pinocchio_order: Vec::new(),
        }
    }
}

/// "`a`", "`a` or `b`", "`a`, `b` or `c`": the expected names in a message.
pub(crate) fn one_of(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => format!("`{one}`"),
        [rest @ .., last] => {
            let rest: Vec<String> = rest.iter().map(|n| format!("`{n}`")).collect();
            format!("{} or `{last}`", rest.join(", "))
        }
    }
}

/// The message for an unknown output name.
pub fn unknown_output(found: &str) -> String {
    let names: Vec<&str> = Output::ALL.iter().map(|(_, n)| *n).collect();
    let groups: Vec<&str> = crate::outputs::Group::ALL.iter().map(|(_, n)| *n).collect();
    let hint = did_you_mean(found, names.iter().chain(&groups).copied());
    format!(
        "unknown output `{found}`:{hint} expected one of {}, or a group: {}",
        one_of(&names),
        one_of(&groups)
    )
}

/// ` did you mean `name`?` for the name among `known` nearest to `found`, where one is near (a
/// typo: at most 2 edits, more for long names), else nothing: said first, as rustc does.
pub(crate) fn did_you_mean<'a>(found: &str, known: impl IntoIterator<Item = &'a str>) -> String {
    known
        .into_iter()
        .map(|n| (strsim::damerau_levenshtein(found, n), n))
        .min()
        .filter(|&(d, n)| d <= 2.max(n.len() / 5))
        .map_or_else(String::new, |(_, n)| format!(" did you mean `{n}`?"))
}

/// The message for an unknown contact kind.
pub fn unknown_contact_kind(found: &str) -> String {
    let hint = did_you_mean(found, ContactKind::ALL.iter().map(|(_, n)| *n));
    format!(
        "unknown contact kind `{found}`:{hint} expected `six_d` (the whole frame held: 6 rows, a \
         wrench in its axes) or `point` (its origin held: 3 rows, a force in world axes)"
    )
}

/// The message for an unknown loop kind.
pub fn unknown_loop_kind(found: &str) -> String {
    let hint = did_you_mean(found, ContactKind::ALL.iter().map(|(_, n)| *n));
    format!(
        "unknown loop kind `{found}`:{hint} expected `point(a, b)` (frame `a`'s origin held on \
         frame `b`'s: 3 rows, a force in world axes) or `six_d(a, b)` (frame `a` held on frame \
         `b`: 6 rows, a wrench in `a`'s axes)"
    )
}

/// The message for an unknown scalar name.
pub(crate) fn unknown_scalar(found: &str) -> String {
    let names: Vec<&str> = ScalarKind::ALL.iter().map(|(_, n)| *n).collect();
    format!("unknown scalar `{found}`: expected {}", one_of(&names))
}

/// The message for an unknown accuracy choice.
pub(crate) fn unknown_accuracy(found: &str) -> String {
    let names: Vec<&str> = Accuracy::ALL.iter().map(|(_, n)| *n).collect();
    format!("unknown accuracy `{found}`: expected {}", one_of(&names))
}
