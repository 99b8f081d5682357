//! The generator behind `articulated`: all logic on `proc_macro2`, so that the `chain!` macro, a
//! `build.rs` and the CLI share it.
//!
//! Pipeline: [`parse`] (tokens → [`parse::ChainDef`], spans kept) → [`lower`] (all checks at
//! once, then an [`articulated_dynamics::model::Model`]) → [`sym`] (the recursions traced over a
//! symbolic scalar into an expression graph: hash-consed, constants folded) → [`emit`]
//! (straight-line Rust) → [`generate`] (the type and trait impls). [`urdf`] builds the same Model
//! from a URDF file; [`load`] picks the front end by file extension. [`expand`] holds the macros'
//! expansions and [`Builder`] writes the same code from a `build.rs`.

pub mod build;
pub mod emit;
pub mod expand;
pub mod generate;
pub mod load;
pub mod lower;
pub mod optimize;
pub mod options;
pub mod parse;
pub mod sym;
pub mod trace;
pub mod urdf;

pub use articulated_dynamics::model;
pub use build::Builder;
