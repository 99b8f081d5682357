//! The generator behind `articulated`: all logic on `proc_macro2`, so that the `chain!` macro, a
//! `build.rs` ([`Builder`]) and the CLI share it.
//!
//! # For users
//! - [`Builder`]: write the generated code of `.chain` and URDF files (or of models a program
//!   builds) to `OUT_DIR` from a `build.rs`;
//! - [`parse`]: the description language, its whole grammar;
//! - [`options`]: what to generate (scalar, outputs, visibility, docs);
//! - [`load`], [`urdf`]: read a description into a [`options::Description`];
//! - [`generate`]: the code of one description, as tokens or a formatted file.
//!
//! # The pipeline
//! One stage per module, in order (ARCHITECTURE.md tells the whole story):
//!
//! 1. `load`: read a file, choose the front end by extension;
//! 2. `parse`: tokens to a [`parse::ChainDef`], spans kept;
//! 3. `lower`: every check at once, then a `Description` (physics [`model::Model`] +
//!    [`options::Options`]); `urdf` builds the same from a URDF;
//! 4. `trace`: the recursions run on the symbolic scalar of `sym` into an expression graph, each
//!    output several ways, the fewest operations kept;
//! 5. `optimize`: sums regrouped by arrival time, constants rounded for `f32`;
//! 6. `emit`: straight-line Rust, one named `let` per operation;
//! 7. `generate`: the type and its trait impls;
//! 8. `expand`: the macros' expansions, with a stand-in after an error.
//!
//! The modules of stages 3–6 and 8 are internals, public for the CLI, the tests and the
//! benchmarks, and hidden from these docs.

pub mod build;
#[doc(hidden)]
pub mod emit;
#[doc(hidden)]
pub mod expand;
pub mod generate;
pub mod load;
#[doc(hidden)]
pub mod lower;
#[doc(hidden)]
pub mod optimize;
pub mod options;
pub mod parse;
#[doc(hidden)]
pub mod sym;
#[doc(hidden)]
pub mod trace;
pub mod urdf;

pub use articulated_dynamics::model;
pub use build::Builder;
