//! The generator behind `articulated`: all logic on `proc_macro2`, so that the `chain!` macro, a
//! `build.rs` and the CLI share it.
//!
//! Pipeline: [`parse`] (tokens → [`parse::ChainDef`], spans kept) → [`lower`] (checks, then
//! [`articulated_dynamics::model::Model`]). [`urdf`] builds the same Model from a URDF file.

pub mod emit;
pub mod lower;
pub mod parse;
pub mod sym;
pub mod urdf;

pub use articulated_dynamics::model;
