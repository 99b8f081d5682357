//! The shared core of `articulated`: the chain [`model`] (the IR every front end lowers to), the
//! [`Scalar`] trait the recursions are written over, spatial algebra, and the generic reference
//! dynamics. `articulated` (the runtime) re-exports it; `articulated-codegen` uses it to lower
//! descriptions and to trace the recursions symbolically.
//!
//! `#![no_std]`; the model and the reference dynamics need the `alloc` feature (on by default).
#![no_std]

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod drive;
#[cfg(feature = "extended")]
pub mod extended;
#[cfg(feature = "alloc")]
pub mod model;
pub mod op_counts;
#[cfg(feature = "alloc")]
pub mod prune;
#[cfg(feature = "alloc")]
pub mod random;
#[cfg(feature = "alloc")]
pub mod reference;
pub mod scalar;
pub mod spatial;

pub use op_counts::OpCounts;
pub use scalar::Scalar;
