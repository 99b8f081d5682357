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

use crate::differentiate::{conjugate, dimensions, mul, mul_tr, quat_mul, rotation};
use crate::Coordinates;

/// `exp(u)` for the rotation vector `2u`: `(cos|u|, sin|u|·u/|u|)`, by its series near 0.
fn quat_exp(u: [f64; 3]) -> [f64; 4] {
    let th2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    let th = libm::sqrt(th2);
    // sin θ/θ, with its Taylor series where θ² is below the rounding of 1 − θ²/6.
    let s = if th < 1e-4 {
        1.0 - th2 / 6.0
    } else {
        libm::sin(th) / th
    };
    [libm::cos(th), s * u[0], s * u[1], s * u[2]]
}

/// `2·log(q)` of a unit quaternion, sign chosen so that `w ≥ 0`: the rotation vector.
fn quat_log2(q: [f64; 4]) -> [f64; 3] {
    let q = if q[0] < 0.0 { q.map(|x| -x) } else { q };
    let s = libm::sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    // 2·atan2(s, w)/s, → 2/w as s → 0.
    let f = if s < 1e-8 {
        2.0 / q[0]
    } else {
        2.0 * libm::atan2(s, q[0]) / s
    };
    [f * q[1], f * q[2], f * q[3]]
}

fn normalize(q: [f64; 4]) -> [f64; 4] {
    let n = libm::sqrt(q.iter().map(|x| x * x).sum::<f64>());
    q.map(|x| x / n)
}

fn quat(s: &[f64]) -> [f64; 4] {
    [s[0], s[1], s[2], s[3]]
}

fn vec3(s: &[f64]) -> [f64; 3] {
    [s[0], s[1], s[2]]
}

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
    let (mut iq, mut iv) = (0, 0);
    for c in coordinates {
        match *c {
            Coordinates::Vector(n) => {
                for a in 0..n {
                    out[iq + a] = q[iq + a] + delta[iv + a];
                }
            }
            Coordinates::Quaternion => {
                let e = quat_exp(vec3(&delta[iv..]).map(|x| 0.5 * x));
                let r = normalize(quat_mul(normalize(quat(&q[iq..])), e));
                out[iq..iq + 4].copy_from_slice(&r);
            }
            Coordinates::FreeQuaternion => {
                let q0 = normalize(quat(&q[iq + 3..]));
                let dp = mul(&rotation(q0), vec3(&delta[iv..]));
                for a in 0..3 {
                    out[iq + a] = q[iq + a] + dp[a];
                }
                let e = quat_exp(vec3(&delta[iv + 3..]).map(|x| 0.5 * x));
                let r = normalize(quat_mul(q0, e));
                out[iq + 3..iq + 7].copy_from_slice(&r);
            }
        }
        iq += c.nq();
        iv += c.nv();
    }
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
    let (mut iq, mut iv) = (0, 0);
    for c in coordinates {
        match *c {
            Coordinates::Vector(n) => {
                for a in 0..n {
                    delta[iv + a] = q1[iq + a] - q0[iq + a];
                }
            }
            Coordinates::Quaternion => {
                let a = normalize(quat(&q0[iq..]));
                let b = normalize(quat(&q1[iq..]));
                delta[iv..iv + 3].copy_from_slice(&quat_log2(quat_mul(conjugate(a), b)));
            }
            Coordinates::FreeQuaternion => {
                let a = normalize(quat(&q0[iq + 3..]));
                let b = normalize(quat(&q1[iq + 3..]));
                let dp = [0, 1, 2].map(|k| q1[iq + k] - q0[iq + k]);
                delta[iv..iv + 3].copy_from_slice(&mul_tr(&rotation(a), dp));
                delta[iv + 3..iv + 6].copy_from_slice(&quat_log2(quat_mul(conjugate(a), b)));
            }
        }
        iq += c.nq();
        iv += c.nv();
    }
    true
}
