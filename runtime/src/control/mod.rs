//! Stabilization (Hemami, Dariush & Barin 2005, §4): linearize a chain about an equilibrium,
//! design a linear-quadratic regulator, and feed back; or track a reference by computed torque.
//!
//! - [`tangent`]: `q ⊕ δ` and `q₁ ⊖ q₀` on each joint's configuration space (quaternions by
//!   their exponential and logarithm), no allocation.
//! - [`computed_torque`]: `τ = ID(q, v, a_ref + Kp·(q_ref ⊖ q) + Kd·(v_ref − v))` as a
//!   controller closure `(t, q, v) ↦ τ`, no allocation.
//! - [`operational_space`]: the task-space inertia `Λ = (J·M⁻¹·Jᵀ)⁻¹`, the dynamically
//!   consistent inverse `J̄ = M⁻¹·Jᵀ·Λ` and the null-space projector of torques, with a rank
//!   test, no allocation.
//! - [`state_feedback`]: `τ = τ_eq − K·(x ⊖ x_eq)`, the LQR law, no allocation.
//! - [`linearize`] (`alloc`): `A`, `B` from a generated chain's exact derivatives
//!   (`linearize::exact`), or by central differences of any forward dynamics.
//! - [`riccati`] (`alloc`): the continuous-time algebraic Riccati equation and the LQR gain.
//!
//! Designing a balance controller for a generated chain `C` upright at `q_eq` (`v_eq = 0`),
//! generated with `forward_dynamics_derivatives` among its outputs:
//!
//! ```text
//! let tau_eq = C::gravity(&q_eq);
//! let lin = linearize::exact::<C, NQ, NV>(&q_eq, &v_eq, &tau_eq)?;
//! let design = lqr(&lin.a, &lin.b, &q_weight, &r_weight)?;
//! let (kq, kv) = split_gain::<NV>(&design.k).unwrap();
//! let controller = state_feedback(C::COORDINATES, q_eq, v_eq, tau_eq, kq, kv)?;
//! ```

use nalgebra::SVector;

/// A controller: `(t, q, v) ↦ τ`, what a simulator calls at each evaluation of the dynamics.
/// Every `FnMut(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>` is one; the
/// laws here return one.
pub trait Controller<const NQ: usize, const NV: usize>:
    FnMut(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>
{
}

impl<F, const NQ: usize, const NV: usize> Controller<NQ, NV> for F where
    F: FnMut(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>
{
}

pub mod computed_torque;
#[cfg(feature = "alloc")]
pub mod linearize;
pub mod operational_space;
#[cfg(feature = "alloc")]
pub mod riccati;
pub mod state_feedback;
pub mod tangent;
