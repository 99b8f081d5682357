//! `articulated`: rigid-body dynamics generated at compile time from a chain description.
//!
//! This crate is what users depend on. It re-exports the macros ([`chain!`],
//! [`derive@Chain`]), the traits generated chains implement ([`MassMatrix`], [`Bias`],
//! [`Gravity`], [`InverseDynamics`], [`ForwardDynamics`]; bring them in with
//! `use articulated::prelude::*;`), and, with the `alloc` feature (on through `std`, the
//! default), the chain [`model`] and the interpreted [`reference`](mod@reference) dynamics.
//!
//! The runtime half of Hemami, Dariush & Barin (2005) works on any generated chain:
//! [`differentiate`] (Savitzky–Golay derivatives of sampled signals on their actual times, and
//! `(q, q̇, q̈) → (v, v̇)`), [`samples`] (trajectory CSV, `std`), [`invert`] (the inverse plant:
//! the couples behind a sampled motion, §5) and [`control`] (linearization, Riccati/LQR,
//! computed torque, §4).
//!
//! Without default features it is `#![no_std]` and needs no allocator: generated code uses only
//! `core`, nalgebra's fixed-size types and `libm`.
//!
//! # Conventions
//! SI units. Spatial vectors are **angular first** (Featherstone): a motion is `[ω; v]`, a force
//! `[n; f]`. Pinocchio orders them linear first; convert when comparing.
#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod control;
pub mod differentiate;
mod generated;
pub mod invert;
/// Sine and cosine together for generated code, branch-free and inlinable, with libm's kernels
/// and accuracy: [`math::sincos_array`] (several angles, faster than [`libm::sincos`]),
/// [`math::sincos`] and [`math::sincosf`] (one angle, slower than libm).
pub mod math;
#[cfg(feature = "std")]
pub mod samples;

pub use articulated_dynamics::scalar::{self, Scalar};
#[cfg(feature = "alloc")]
pub use articulated_dynamics::{model, reference};
pub use articulated_macros::{chain, Chain};
pub use generated::*;
/// Re-exported for generated code (math under `no_std`).
pub use libm;
/// Re-exported for generated code and users (the fixed-size vectors and matrices).
pub use nalgebra;

/// `use articulated::prelude::*;` brings the traits of generated chains into scope.
pub mod prelude {
    pub use crate::{
        Bias, Chain, Coordinates, ForwardDynamics, Gravity, InverseDynamics, MassMatrix, OpCounts,
        SingularMassMatrix,
    };
}
