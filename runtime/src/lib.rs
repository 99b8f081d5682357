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
//! # The runtime: Hemami, Dariush & Barin (2005) on any generated chain
//! - To move a chain in time: its [`configuration`] space (quaternion joints on their
//!   manifold), the [`integrate`] methods (explicit and symplectic Euler, RK4, adaptive
//!   Dormand–Prince 5(4), implicit midpoint for long horizons) over any
//!   [`integrate::SecondOrder`] system such as a generated chain under a controller
//!   ([`integrate::ControlledChain`]), a [`simulate`] loop that records states into a buffer or
//!   a [`trajectory::Trajectory`], and the [`trajectory`]'s CSV form. All of it is
//!   allocation-free on fixed-size chains and works under `no_std`.
//! - To recover the couples behind a motion (§5): [`differentiate`] (Savitzky–Golay
//!   derivatives of sampled signals on their actual times, and `(q, q̇, q̈) → (v, v̇)`),
//!   [`samples`] (reading a trajectory CSV, `std`) and [`invert`] (the inverse plant).
//! - To stabilize (§4): [`control`] (linearization, Riccati/LQR, computed torque).
//! - To reach: [`ik`] (inverse kinematics of the frames a description names, by
//!   Levenberg–Marquardt on their SE(3) or position errors, within the joint limits) and
//!   [`control::operational_space`] (`Λ`, the dynamically consistent inverse, the null-space
//!   projector); both allocation-free.
//!
//! # Conventions
//! Each is checked by the example under it (the README's "Conventions" lists them all).
//!
//! **Spatial vectors are angular first** (Featherstone): a motion is `[ω; v]`, a force `[n; f]`.
//! Pinocchio orders them linear first; swap the halves when comparing.
//!
//! ```
//! use articulated::spatial::{Mat3, Motion, Transform, Vec3};
//! // Spinning at 1 rad/s about the z axis through the origin, in world coordinates.
//! let spin = Motion::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 0.0));
//! // In a frame 1 m along x (same axes), the point at its origin moves at ω × r = (0, 1, 0).
//! let there = Transform::from_pose(Mat3::identity(), Vec3::new(1.0, 0.0, 0.0));
//! let seen = there.apply_motion(spin);
//! assert_eq!(seen.ang.0, [0.0, 0.0, 1.0]); // angular first
//! assert_eq!(seen.lin.0, [0.0, 1.0, 0.0]); // then the linear velocity of the origin
//! ```
//!
//! **`bias` is `N(q, q̇)·q̇` without gravity**; `gravity(q)` holds the chain still, and
//! `τ = M·a + bias + gravity` (Pinocchio's `nonLinearEffects` is `bias + gravity`).
//!
//! ```
//! use articulated::nalgebra::SVector;
//! use articulated::prelude::*;
//!
//! articulated::chain! {
//!     chain Pendulum {
//!         body bob { mass: 2.0, com: [0.0, 0.0, -0.5], inertia: diag(0.01, 0.01, 0.01) }
//!         joint pivot: revolute(y) { parent: world, child: bob }
//!     }
//! }
//! let (q, v, zero) = (SVector::from([0.3]), SVector::from([4.0]), SVector::zeros());
//! // One joint, a constant M: no velocity-product terms, whatever the velocity.
//! assert_eq!(Pendulum::bias(&q, &v)[0], 0.0);
//! // Gravity pulls the bob back: m·g·l·sin q.
//! let g = Pendulum::gravity(&q)[0];
//! assert!((g - 2.0 * 9.81 * 0.5 * 0.3_f64.sin()).abs() < 1e-12);
//! assert!((Pendulum::inverse_dynamics(&q, &v, &zero)[0] - g).abs() < 1e-12);
//! ```
//!
//! **Euler angles are intrinsic**: `spherical(xyz)` is `R = Rx(θ1)·Ry(θ2)·Rz(θ3)`, three
//! revolute joints x, y, z through massless frames (how URDF writes a spherical joint).
//!
//! ```
//! use articulated::nalgebra::{Rotation3, SVector, Vector3};
//! use articulated::prelude::*;
//!
//! articulated::chain! {
//!     chain Ball {
//!         body arm { mass: 1.0, com: [0.3, 0.0, 1.0], inertia: diag(0.1, 0.1, 0.1) }
//!         joint ball: spherical(xyz) { parent: world, child: arm }
//!     }
//! }
//! // The potential energy m·g·z of the centre of mass for R = Rx(θ1)·Ry(θ2)·Rz(θ3) …
//! let potential = |q: [f64; 3]| {
//!     let r = Rotation3::from_axis_angle(&Vector3::x_axis(), q[0])
//!         * Rotation3::from_axis_angle(&Vector3::y_axis(), q[1])
//!         * Rotation3::from_axis_angle(&Vector3::z_axis(), q[2]);
//!     9.81 * (r * Vector3::new(0.3, 0.0, 1.0)).z
//! };
//! // … has the generated gravity as its gradient.
//! let q = [0.4, -0.3, 1.1];
//! let g = Ball::gravity(&SVector::from(q));
//! for k in 0..3 {
//!     let (mut up, mut down) = (q, q);
//!     up[k] += 1e-6;
//!     down[k] -= 1e-6;
//!     assert!((g[k] - (potential(up) - potential(down)) / 2e-6).abs() < 1e-6);
//! }
//! ```
//!
//! **Coordinates follow the joints depth first from the world**, children in declaration
//! order, whatever order the items come in.
//!
//! ```
//! use articulated::nalgebra::SVector;
//! use articulated::prelude::*;
//!
//! articulated::chain! {
//!     chain Tree {
//!         body a { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.1, 0.1, 0.1) }
//!         body b { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.1, 0.1, 0.1) }
//!         body c { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.1, 0.1, 0.1) }
//!         joint jb: revolute(y) { parent: a, child: b, xyz: [0.0, 0.0, -1.0] }
//!         joint jc: revolute(y) { parent: world, child: c }
//!         joint ja: revolute(y) { parent: world, child: a }
//!     }
//! }
//! // The world's children in declaration order (jc, then ja), then ja's child jb: q = [jc, ja, jb].
//! let g = Tree::gravity(&SVector::from([0.3, 0.0, 0.0]));
//! assert!(g[0] != 0.0 && g[1] == 0.0 && g[2] == 0.0); // only c hangs off the vertical
//! let g = Tree::gravity(&SVector::from([0.0, 0.0, 0.3]));
//! assert!(g[0] == 0.0 && g[1] != 0.0 && g[2] != 0.0); // b, through a, loads ja and jb
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
// No panic reachable from user input (issue 14): the exceptions to the indexing rule are on the
// modules below that carry them, each saying why its indices are in bounds; `unwrap` and
// `expect` appear only in tests (clippy.toml).
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod configuration;
// Dense linear algebra on matrices whose sizes the types fix, indexed by loop counters below the
// rows in use (at most the capacity `R`, checked by `System::push`) or by a frame index checked
// against `NF` first.
#[allow(clippy::indexing_slicing)]
pub mod constraint;
// Dense and tree-sparse linear algebra on `nv × nv` matrices, indexed by loop counters below
// `nv` and by parents `λ(i) < i` (`tree_parents` builds them so, or `i − 1`).
#[allow(clippy::indexing_slicing)]
pub mod contact;
// Exceptions to the panics audit (the crate denies indexing below): dense linear algebra on
// matrices whose sizes the types fix (`SMatrix<_, N, N>`, or `n × n` built here), indexed by
// loop counters below them.
#[allow(clippy::indexing_slicing)]
pub mod control;
// Savitzky–Golay windows: every index is a sample within `half_window` of a centre that
// `centres(len)` yields, and `check` has verified `q.len() = t.len()·nq` before any is read.
#[allow(clippy::indexing_slicing)]
pub mod differentiate;
pub mod drives;
#[cfg(feature = "std")]
pub mod files;
mod generated;
pub mod ik;
pub mod integrate;
#[cfg(feature = "alloc")]
pub mod interpreted;
pub mod invert;
// Lanes are `[T; N]` indexed by counters below `N` (`Split::lane` is called with `i < N`).
#[allow(clippy::indexing_slicing)]
pub mod lanes;
/// Sine and cosine together for generated code, branch-free and inlinable, with libm's kernels
/// and accuracy: [`math::sincos_array`] (several angles, faster than [`libm::sincos`]),
/// [`math::sincos`] and [`math::sincosf`] (one angle, slower than libm).
// Fixed lanes (`[f64; N]` by counters below `N`) and libm's table lookups, whose index is
// masked to the table's size.
#[allow(clippy::indexing_slicing)]
pub mod math;
// Quaternions and angle pairs moved between slices that `get(..7)`, `get(..4)`, `get(..2)`
// have just taken at those lengths.
#[allow(clippy::indexing_slicing)]
pub mod pinocchio;
#[cfg(feature = "plot")]
pub mod plot;
#[cfg(feature = "std")]
pub mod samples;
pub mod simulate;
pub mod trajectory;

pub use articulated_dynamics::drive::Drive;
pub use articulated_dynamics::scalar::{self, Scalar};
pub use articulated_dynamics::spatial;
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
    // Every output's trait and every group's (`MassMatrix`, …, `DynamicsOutputs`, …), from
    // the generator's table of outputs.
    pub use crate::output_traits::*;
    pub use crate::{
        Chain, Coordinates, KeptMassMatrix, KeptMassMatrixLower, OpCounts, SingularMassMatrix,
    };
}

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;

/// The guide's examples (`docs/guide/`), compiled and run as doctests, one item per page.
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/description.md")]
pub struct GuideDescriptionDoctests;

/// See [`GuideDescriptionDoctests`].
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/generated-code.md")]
pub struct GuideGeneratedCodeDoctests;

/// See [`GuideDescriptionDoctests`].
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/runtime.md")]
pub struct GuideRuntimeDoctests;

/// See [`GuideDescriptionDoctests`].
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/cli.md")]
pub struct GuideCliDoctests;

/// See [`GuideDescriptionDoctests`].
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/checking.md")]
pub struct GuideCheckingDoctests;

/// See [`GuideDescriptionDoctests`].
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/accuracy-and-speed.md")]
pub struct GuideAccuracyAndSpeedDoctests;
