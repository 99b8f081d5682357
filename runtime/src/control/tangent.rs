//! Moving a configuration along a velocity-sized displacement, and the displacement between two
//! configurations: `q ⊕ δ` and `q₁ ⊖ q₀`, joint by joint after the chain's [`Coordinates`].
//!
//! `δ` has one entry per velocity coordinate and is expressed like `v`:
//! - [`Coordinates::Vector`]: `q ⊕ δ = q + δ`, `q₁ ⊖ q₀ = q₁ − q₀`.
//! - [`Coordinates::Quaternion`]: a rotation vector in the child frame,
//!   `q ⊕ δ = q ⊗ exp(δ/2)` with `exp(u) = (cos|u|, sin|u|·u/|u|)`, and its inverse
//!   `q₁ ⊖ q₀ = 2·log(q̄₀ ⊗ q₁)`, `log` of the unit quaternion with `w ≥ 0` (the shorter of the
//!   two rotations, angle in `[0, π]`).
//! - [`Coordinates::FreeQuaternion`]: the rotation as above, and the translation in the child
//!   frame of `q₀` (like the linear velocity): `p ⊕ δ = p + R(q)·δ_lin`,
//!   `δ_lin = R(q₀)ᵀ·(p₁ − p₀)`.
//!
//! So `q₀ ⊕ (q₁ ⊖ q₀) = q₁` (up to the sign of a quaternion), and `d/dε (q ⊕ ε·v)` at `ε = 0` is
//! the configuration rate of velocity `v`: linearizing in `δ` gives `δ̇ = v` to first order,
//! the `[0, I]` row of the state matrix ([`super::linearize`]). These are the exponential map
//! of each joint's group taken one factor at a time (rotation and translation separately, not
//! the screw motion of SE(3)); both retractions agree to first order, which is all a
//! linearization or a PD law needs.
//!
//! Both are thin wrappers over the integrators' maps in [`crate::configuration`] (`exp(δ/2)`
//! above is [`quat_exp`]`(δ)` there): [`retract`] is [`integrate_in_place`] between two
//! normalizations, [`difference`] is [`difference_into`] on normalized quaternions with the
//! shorter rotation; what they add is the length check and, for [`difference`], the argument
//! order `(q₁, q₀)`.
//!
//! [`quat_exp`]: crate::configuration::quat_exp
//! [`difference_into`]: crate::configuration::difference_into

use crate::configuration::{
    difference_shortest_into, dimensions, integrate_in_place, map_quaternions, unit,
};
use crate::Coordinates;

/// `true` when the slices have the lengths the coordinates need (`q`, `q_out`: `Σ nq`;
/// `delta`: `Σ nv`).
fn fits(coordinates: &[Coordinates], q: &[f64], delta: &[f64], q_out: &[f64]) -> bool {
    let (nq, nv) = dimensions(coordinates);
    q.len() == nq && q_out.len() == nq && delta.len() == nv
}

/// `q ⊕ δ` into `out` (definition in the [module docs](self)); quaternions are normalized.
/// Allocates nothing. A zero quaternion in `q` gives NaN in `out`.
///
/// Returns `false`, leaving `out` untouched, when the lengths do not fit the coordinates
/// (`q`, `out`: `Σ nq`; `delta`: `Σ nv`).
pub fn retract(coordinates: &[Coordinates], q: &[f64], delta: &[f64], out: &mut [f64]) -> bool {
    if !fits(coordinates, q, delta, out) {
        return false;
    }
    out.copy_from_slice(q);
    map_quaternions(coordinates, out, unit);
    integrate_in_place(coordinates, out, delta);
    map_quaternions(coordinates, out, unit);
    true
}

/// `q₁ ⊖ q₀` into `delta`: the displacement, expressed like `v` at `q₀`, with
/// `q₀ ⊕ δ = q₁` (definition in the [module docs](self)). Quaternions need not be unit; a
/// zero one gives NaN. Allocates nothing.
///
/// Returns `false`, leaving `delta` untouched, when the lengths do not fit the coordinates
/// (`q1`, `q0`: `Σ nq`; `delta`: `Σ nv`).
pub fn difference(coordinates: &[Coordinates], q1: &[f64], q0: &[f64], delta: &mut [f64]) -> bool {
    if !fits(coordinates, q0, delta, q1) {
        return false;
    }
    difference_shortest_into(coordinates, q0, q1, delta);
    true
}
