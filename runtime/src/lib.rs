//! `articulated`: rigid-body dynamics generated at compile time from a chain description.
//!
//! This crate is what users depend on. It re-exports the macros ([`chain!`],
//! [`derive@Chain`]), the traits generated chains implement ([`MassMatrix`], [`Bias`],
//! [`Gravity`], [`InverseDynamics`], [`ForwardDynamics`]; bring them in with
//! `use articulated::prelude::*;`), and, with the `alloc` feature (on through `std`, the
//! default), the chain [`model`] and the interpreted [`reference`](mod@reference) dynamics.
//!
//! Without default features it is `#![no_std]` and needs no allocator: generated code uses only
//! `core`, nalgebra's fixed-size types and `libm`.
//!
//! To move a chain in time: its [`configuration`] space (quaternion joints on their manifold),
//! the [`integrate`] methods (explicit and symplectic Euler, RK4, adaptive Dormand–Prince 5(4),
//! implicit midpoint for long horizons) over any [`integrate::SecondOrder`] system such as a
//! generated chain under a controller ([`integrate::ControlledChain`]), a [`simulate`] loop
//! that records states into a buffer or a [`trajectory::Trajectory`], and the
//! [`trajectory`]'s CSV form. All of it is allocation-free on fixed-size chains and works
//! under `no_std`.
//!
//! # Conventions
//! SI units. Spatial vectors are **angular first** (Featherstone): a motion is `[ω; v]`, a force
//! `[n; f]`. Pinocchio orders them linear first; convert when comparing.
#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod configuration;
mod generated;
pub mod integrate;
/// Sine and cosine together for generated code, branch-free and inlinable, with libm's kernels
/// and accuracy: [`math::sincos_array`] (several angles, faster than [`libm::sincos`]),
/// [`math::sincos`] and [`math::sincosf`] (one angle, slower than libm).
pub mod math;
pub mod simulate;
pub mod trajectory;

pub use articulated_dynamics::scalar::{self, Scalar};
#[cfg(feature = "alloc")]
pub use articulated_dynamics::{model, reference};
pub use articulated_macros::{chain, Chain};
pub use generated::*;
/// Re-exported for generated code (math under `no_std`).
pub use libm;
/// Re-exported for generated code and users (the fixed-size vectors and matrices).
pub use nalgebra;

/// `use articulated::prelude::*;` brings the traits of generated chains into scope, and what
/// a simulation needs.
pub mod prelude {
    pub use crate::integrate::{
        ControlledChain, Dopri5, Euler, ImplicitMidpoint, Integrator, Rk4, SecondOrder, State,
        SymplecticEuler,
    };
    pub use crate::simulate::Simulation;
    pub use crate::{
        Bias, Chain, Coordinates, ForwardDynamics, Gravity, InverseDynamics, MassMatrix, OpCounts,
        SingularMassMatrix,
    };
}
