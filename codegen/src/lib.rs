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
//!    [`options::Options`]); `urdf` builds the same from a URDF; both have the rules that are
//!    not syntax judged by `check`, written once, and put each problem at its own location;
//! 4. `trace`: the recursions run on the symbolic scalar of `sym` into an expression graph, each
//!    output several ways, the fewest operations kept;
//! 5. `optimize`: sums regrouped by arrival time, constants rounded for `f32`;
//! 6. `emit`: straight-line Rust, one named `let` per operation;
//! 7. `generate`: the type and its trait impls; stages 4–6 run inside it, one output at a time
//!    (`generate::Context::function` reads as that pipeline, in one short function);
//! 8. `expand`: the macros' expansions, with a stand-in after an error.
//!
//! Each output is described once, in [`outputs`]: its name, trait, arguments, result and docs;
//! stages 7 and 8 and the runtime's traits read it there.
//!
//! The modules of stages 3–6 and 8 are internals, public for the CLI, the tests and the
//! benchmarks, and hidden from these docs.
//!
//! No panic is reachable from a description (issue 14): `unwrap`, `expect`, `panic!` and
//! indexing are denied. What reads the user's text and tokens (`parse`, `load`, `expand`,
//! `build`, `options`) holds to that without exception. The stages after it index vectors they
//! sized themselves from the checked model (bodies, joints, velocity coordinates, graph nodes),
//! never by a number read from the input: those modules carry the one exception, and the
//! fuzzers (`fuzz/`) drive them with arbitrary descriptions.
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

pub mod build;
#[doc(hidden)]
// 3×3 inertias by counters below 3.
#[allow(clippy::indexing_slicing)]
pub mod check;
#[doc(hidden)]
#[allow(clippy::indexing_slicing)] // Variables indexed by the graph's own numbering.
pub mod emit;
#[doc(hidden)]
pub mod expand;
#[allow(clippy::indexing_slicing)] // Outputs by velocity coordinates of the checked model.
pub mod generate;
#[allow(clippy::indexing_slicing)]
pub mod import;
pub mod load;
// Bodies and joints by the positions of the importer's own vectors, 3×3 inertias by counters
// below 3.
#[doc(hidden)]
// Declarations by the positions the lowering gave them (a name's index from a map built over
// the same vector), 3×3 inertias by counters below 3.
#[allow(clippy::indexing_slicing)]
pub mod lower;
#[allow(clippy::indexing_slicing)]
pub mod mjcf;
#[doc(hidden)]
#[allow(clippy::indexing_slicing)] // Terms and nodes by the graph's own numbering.
pub mod optimize;
pub mod options;
// Specs by their output's discriminant (the table declares both), and const loops below the
// table's length.
#[allow(clippy::indexing_slicing)]
pub mod outputs;
pub mod parse;
#[doc(hidden)]
#[allow(clippy::indexing_slicing)] // Nodes by the graph's own numbering.
pub mod sym;
#[doc(hidden)]
#[allow(clippy::indexing_slicing)] // Tree nodes and coordinates of the checked model.
pub mod trace;
// Links and joints by the positions of urdf-rs's vectors (found by name in maps built over
// them), 3×3 inertias by counters below 3.
#[allow(clippy::indexing_slicing)]
pub mod urdf;

pub use articulated_dynamics::model;
pub use build::Builder;
