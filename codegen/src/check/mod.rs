//! The check stage: every rule of a description that is not syntax, written once, for every
//! front end (as serde_derive's `internals/check.rs` holds the rules its attributes obey).
//!
//! The front ends read their own syntax and resolve their own names (`lower` for `.chain` files
//! and `chain!{}`, `urdf`, the keys of `#[chain(…)]`); what the description then means is judged
//! here:
//! - `tree`: every body the child of one joint, a root (`world`, or URDF's one root link), no
//!   cycle; the depth-first order, and which bodies move;
//! - `mass`: masses, inertias (symmetric, positive definite or semi-definite, the triangle
//!   inequality on the principal moments), with the tolerances that tell rounding from an error;
//! - `joints`: what a mimic joint may follow, and drives ([`Drive::problem`]);
//! - `options`: which outputs and options go together with the model (`joint_wrenches_bottom_up`
//!   on a serial chain only, `accuracy: robust` without mimic joints, a scene that fits, frames
//!   and constraints on frames the model has), and sizes ([`MAX_NV`]).
//!
//! A rule returns what is wrong, worded once, and says what it is about ([`About`]: a body or a
//! joint by the front end's own numbering, an output, an option) but never where that is
//! written: each front end puts the message at its location (a span of a `.chain` file or of
//! the macro's tokens, a URDF line, a key of `#[chain(…)]`; the call site only for a model a
//! program built), and decides, by its policy, whether a problem is an error or a warning (a
//! `.chain` inertia is an error at its token, a URDF link's a warning at its line). Every
//! front end reports all the problems at once.
//!
//! `generate` runs [`program`] before it traces anything, as the last line of defence for a
//! description that no front end checked (`Builder::model`, a test): what it refuses there is at
//! the call site. The generator's own limits that only tracing can measure (operations per
//! function, constants that overflow `f64`) stay in `generate`.
//!
//! [`Drive::problem`]: articulated_dynamics::model::Drive::problem

mod joints;
mod mass;
mod options;
mod tree;

pub use joints::{drive, mimic, Follow};
pub use mass::{
    asymmetric, asymmetry, inertia, mass, principal_moments, Inertia, InertiaProblem, Strictness,
    INERTIA_ROUNDING,
};
pub use options::{declared, options, program, JointShape, MAX_NV};
pub use tree::{tree, Edge, End, Noun, Roots, Tree};

use crate::options::Output;

/// One thing wrong with a description: what it is about and what is wrong, worded for the user.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// What it is about, for the front end to find where that is written.
    pub about: About,
    /// What is wrong and what was expected.
    pub message: String,
}

/// What a [`Problem`] is about. Bodies and joints are numbered as the front end gave them to the
/// check stage (declaration order in a `.chain` file, document order in a URDF).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum About {
    /// A body (a URDF link): its declaration.
    Body(usize),
    /// A joint's parent (where a cycle is named).
    Parent(usize),
    /// A joint's child (the second parent of a body).
    Child(usize),
    /// An output asked for.
    Output(Output),
    /// The accuracy asked for (`accuracy: robust`).
    Accuracy,
    /// The lanes asked for (`lanes: 4`).
    Lanes,
    /// A joint locked or a body kept by the scene (`lock`, `keep`), or a frame named in
    /// `frames`, by name.
    Scene(String),
    /// A contact of `contacts`, by its order there.
    Contact(usize),
    /// A loop of `loops`, by its order there (its name).
    Loop(usize),
    /// One of the two frames of a loop of `loops`: the loop's order there, then 0 for the
    /// first frame, 1 for the second.
    LoopFrame(usize, usize),
    /// The description as a whole (its size, a model a program built).
    Whole,
}

impl Problem {
    fn new(about: About, message: impl Into<String>) -> Self {
        Problem {
            about,
            message: message.into(),
        }
    }
}

/// `problems` as one `syn::Error` that holds every one (`combine`d), each at the span `at` gives
/// what it is about; `None` for none.
pub fn combined(
    problems: Vec<Problem>,
    at: impl Fn(&About) -> proc_macro2::Span,
) -> Option<syn::Error> {
    problems
        .into_iter()
        .map(|p| syn::Error::new(at(&p.about), p.message))
        .reduce(|mut all, e| {
            all.combine(e);
            all
        })
}

/// A number for a message: shortest form, rounded to 9 significant decimals to hide round-off.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    let digits = 9 - x.abs().log10().floor() as i32;
    let rounded = if (0..=300).contains(&digits) {
        let p = 10f64.powi(digits);
        (x * p).round() / p
    } else {
        x
    };
    format!("{rounded}")
}
