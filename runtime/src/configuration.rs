//! The configuration space of a chain: where `q` lives, how a velocity moves it, and the local
//! coordinates in which the integrators step it.
//!
//! A chain's `q` is a point of a product of manifolds, one factor per entry of
//! [`Chain::COORDINATES`](crate::Chain::COORDINATES), in that order; its tangent vectors (the
//! velocity `v`, an increment `δ`) have `NV` entries. For each [`Coordinates`]:
//!
//! | coordinates | `q` | `v` | `q ⊕ δ` |
//! |---|---|---|---|
//! | `Vector(n)` | `x ∈ ℝⁿ` | `ẋ` | `x + δ` |
//! | `Quaternion` | `Q = [w, x, y, z]`, unit | `ω`, child frame | `Q ⊗ exp(δ)` |
//! | `FreeQuaternion` | `[p; Q]`, `p` in the joint frame | `[u; ω]`, both child frame | `[p + R(Q)·δ_p; Q ⊗ exp(δ_ω)]` |
//!
//! with the quaternion exponential `exp(δ) = [cos(|δ|/2), sin(|δ|/2)·δ/|δ|]` and `R(Q)` the
//! rotation of `Q` (child frame → joint frame). Increments are **body-frame** (right
//! multiplication): a body turning at the constant angular velocity `ω` (child frame) goes from
//! `Q` to `Q ⊕ h·ω` in the time `h`, exactly, because `Q̇ = ½·Q ⊗ [0; ω]`.
//!
//! A free joint is treated as SO(3) × ℝ³, not SE(3): the position moves by the increment
//! `δ_p` rotated into the joint frame **at the start point**, `p' = p + R(Q)·δ_p`, so `δ_p` is
//! the displacement expressed in the child frame of `q`. With the velocity `u` in the child
//! frame, `ṗ = R(Q)·u`.
//!
//! # Local coordinates
//! The integrators are Runge–Kutta–Munthe-Kaas methods (Munthe-Kaas 1998, "Runge–Kutta methods on
//! Lie groups", BIT 38(1), 92–111; Hairer, Lubich & Wanner 2006, *Geometric Numerical
//! Integration*, 2nd ed., §IV.8.2): each step writes the configuration as `q = q_n ⊕ θ` around the
//! step's start `q_n` and integrates the local coordinate `θ ∈ ℝ^NV`, which lives in a vector
//! space, with an ordinary Runge–Kutta method. Its rate ([`local_velocity`]) is, per joint:
//! - `Vector`: `θ̇ = v`;
//! - `Quaternion`: `θ̇ = dexp⁻¹_θ(ω)`. From `Q = Q_n ⊗ exp(θ)` and `Q̇ = ½·Q ⊗ [0; ω]`,
//!   `ω = J_r(θ)·θ̇` with the right Jacobian of SO(3)
//!   `J_r(θ) = 1 − ((1 − cos φ)/φ²)·[θ]× + ((φ − sin φ)/φ³)·[θ]×²`, `φ = |θ|`, whose inverse is
//!   `dexp⁻¹_θ(ω) = ω + ½·θ × ω + c(φ)·θ × (θ × ω)`, `c(φ) = (1 − (φ/2)·cot(φ/2))/φ²`
//!   `= 1/12 + φ²/720 + φ⁴/30240 + …` (the Bernoulli series `Σ B_k/k!·ad_θᵏ` with `ad_θ = −θ×`,
//!   folded by `ad_θ³ = −φ²·ad_θ`). RK4 needs the series up to `1/12·θ × (θ × ω)` (the omitted
//!   terms are `O(φ⁴)·ω`, a local error `O(h⁵)`), Dormand–Prince 5 also the `φ²/720` term; we use
//!   the closed form for `φ ≥ 0.05` and the series to `φ⁴` below, which is exact to rounding for
//!   every order;
//! - `FreeQuaternion`: `θ̇_ω` as for `Quaternion`, and `θ̇_p = R(exp(θ_ω))·u`: from
//!   `p = p_n + R(Q_n)·θ_p` and `ṗ = R(Q_n ⊗ exp(θ_ω))·u`. This is exact, not truncated.
//!
//! The unit norm of a quaternion comes from the exponential map: `exp(δ)` is unit by
//! construction and a product of unit quaternions is unit, so an integrator that only ever moves
//! `q` by `⊕` keeps it unit up to rounding. Nothing the integrators call normalizes: only
//! [`normalize`] does, and the controllers' versions of `⊕` and `⊖`
//! ([`control::tangent`](crate::control::tangent), built on the functions here), which take
//! quaternions that need not be unit.
//!
//! # Sizes
//! Everything works on slices: `q` has `Σ nq` entries and tangent vectors `Σ nv`. [`check`] says
//! whether a coordinates list fits the sizes ([`dimensions`] gives them); the other functions
//! assume it does, never panic,
//! and leave alone any entry that falls outside the slices they are given. The `SVector` twins
//! ([`integrate`], [`difference`], [`local_velocity`]) allocate nothing.

use core::fmt;

use nalgebra::{RealField, SVector};

use crate::Coordinates;

/// A coordinates list that does not fit a state: its joints need `nq` positions and `nv`
/// velocities, the state has `expected_nq` and `expected_nv`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SizeMismatch {
    /// Positions the coordinates list describes.
    pub nq: usize,
    /// Velocities the coordinates list describes.
    pub nv: usize,
    /// Positions in the state.
    pub expected_nq: usize,
    /// Velocities in the state.
    pub expected_nv: usize,
}

impl fmt::Display for SizeMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the joints' coordinates describe {} positions and {} velocities, the state has {} \
             and {}",
            self.nq, self.nv, self.expected_nq, self.expected_nv
        )
    }
}

impl core::error::Error for SizeMismatch {}

/// `(Σ nq, Σ nv)`: the positions and velocities `coords` describes.
pub fn dimensions(coords: &[Coordinates]) -> (usize, usize) {
    coords
        .iter()
        .fold((0, 0), |(nq, nv), c| (nq + c.nq(), nv + c.nv()))
}

/// Checks that `coords` describes exactly `nq` positions and `nv` velocities.
///
/// # Errors
/// [`SizeMismatch`] with both counts.
pub fn check(coords: &[Coordinates], nq: usize, nv: usize) -> Result<(), SizeMismatch> {
    let (cq, cv) = dimensions(coords);
    if cq == nq && cv == nv {
        Ok(())
    } else {
        Err(SizeMismatch {
            nq: cq,
            nv: cv,
            expected_nq: nq,
            expected_nv: nv,
        })
    }
}

/// Whether every quaternion of `q` has unit norm, within
/// [`QUATERNION_NORM_TOLERANCE`](crate::spatial::QUATERNION_NORM_TOLERANCE) (a non-finite norm
/// is off). What the integrators check before each step: the generated functions take a
/// quaternion as the rotation of `Q/|Q|`, so one far from unit, which no integrator makes, is a
/// mistake in the state given.
///
/// # Errors
/// The index of the first such quaternion's `w` entry in `q`, and its norm.
pub fn check_unit<T: RealField + Copy>(coords: &[Coordinates], q: &[T]) -> Result<(), (usize, T)> {
    let tolerance = T::from_subset(&crate::spatial::QUATERNION_NORM_TOLERANCE);
    for (c, iq, _) in joints(coords) {
        let w = match c {
            Coordinates::Vector(_) => continue,
            Coordinates::Quaternion => iq,
            Coordinates::FreeQuaternion => iq + 3,
        };
        if let Some(&[a, b, c, d]) = q.get(w..w + 4).and_then(|s| <&[T; 4]>::try_from(s).ok()) {
            let norm = (a * a + b * b + c * c + d * d).sqrt();
            let off = (norm - T::one()).abs();
            if off > tolerance || !off.is_finite() {
                return Err((w, norm));
            }
        }
    }
    Ok(())
}

/// Each joint's coordinates with the offsets of its first position and first velocity in `q`
/// and `v`: `(c, iq, iv)`.
pub(crate) fn joints(
    coords: &[Coordinates],
) -> impl Iterator<Item = (Coordinates, usize, usize)> + '_ {
    coords.iter().scan((0, 0), |(iq, iv), &c| {
        let joint = (c, *iq, *iv);
        (*iq, *iv) = (*iq + c.nq(), *iv + c.nv());
        Some(joint)
    })
}

/// Whether every coordinate is a plain `Vector` (then `⊕` is `+` and `θ̇ = v`).
pub fn is_vector_space(coords: &[Coordinates]) -> bool {
    coords.iter().all(|c| matches!(c, Coordinates::Vector(_)))
}

/// `T` from an `f64` constant.
#[inline(always)]
pub(crate) fn k<T: RealField + Copy>(x: f64) -> T {
    nalgebra::convert(x)
}

/// Hamilton product `a ⊗ b` of quaternions `[w, x, y, z]`.
pub fn quat_mul<T: RealField + Copy>(a: [T; 4], b: [T; 4]) -> [T; 4] {
    let [aw, ax, ay, az] = a;
    let [bw, bx, by, bz] = b;
    [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]
}

/// `Q̄ = [w, −x, −y, −z]`, the inverse of a unit quaternion.
pub(crate) fn conjugate<T: RealField + Copy>(q: [T; 4]) -> [T; 4] {
    [q[0], -q[1], -q[2], -q[3]]
}

/// `q/|q|`: NaN for a zero quaternion.
pub(crate) fn unit<T: RealField + Copy>(q: [T; 4]) -> [T; 4] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    q.map(|x| x / n)
}

/// `a × b`.
pub(crate) fn cross<T: RealField + Copy>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm3<T: RealField + Copy>(a: [T; 3]) -> T {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The quaternion exponential `exp(δ) = [cos(φ/2), sin(φ/2)·δ/φ]`, `φ = |δ|`: the rotation by
/// the angle `φ` about `δ`. Unit for every finite `δ`.
pub fn quat_exp<T: RealField + Copy>(delta: [T; 3]) -> [T; 4] {
    let phi = norm3(delta);
    let half = phi * k(0.5);
    // sin(φ/2)/φ; below 1e-4 its Taylor series ½·(1 − φ²/24) is exact to rounding.
    let s = if phi < k(1e-4) {
        k::<T>(0.5) * (T::one() - phi * phi / k(24.0))
    } else {
        half.sin() / phi
    };
    [half.cos(), s * delta[0], s * delta[1], s * delta[2]]
}

/// The quaternion logarithm, inverse of [`quat_exp`] on unit quaternions: `δ = φ·u/|u|` with
/// `φ = 2·atan2(|u|, w) ∈ [0, 2π]` for `q = [w; u]`. No sign flip, so `exp(log(q)) = q` and not
/// `−q` (the angle exceeds π when `w < 0`).
pub fn quat_log<T: RealField + Copy>(q: [T; 4]) -> [T; 3] {
    let u = [q[1], q[2], q[3]];
    let s = norm3(u);
    let w = q[0];
    // φ/|u|; below 1e-8 with w > 0, 2·atan2(s, w)/s = 2/w·(1 − s²/(3w²) + …) = 2/w to rounding.
    let f = if s < k(1e-8) && w > T::zero() {
        k::<T>(2.0) / w
    } else if s == T::zero() {
        // w ≤ 0 and u = 0: the rotation by 2π, about an axis of our choice.
        return [k::<T>(2.0) * T::pi(), T::zero(), T::zero()];
    } else {
        k::<T>(2.0) * s.atan2(w) / s
    };
    [f * u[0], f * u[1], f * u[2]]
}

/// `R(Q)·x`, the rotation of a unit quaternion applied to `x`:
/// `x + 2w·(u × x) + 2·u × (u × x)`.
pub fn quat_rotate<T: RealField + Copy>(q: [T; 4], x: [T; 3]) -> [T; 3] {
    let u = [q[1], q[2], q[3]];
    let t = cross(u, x);
    let t = [t[0] + t[0], t[1] + t[1], t[2] + t[2]];
    let ut = cross(u, t);
    [
        x[0] + q[0] * t[0] + ut[0],
        x[1] + q[0] * t[1] + ut[1],
        x[2] + q[0] * t[2] + ut[2],
    ]
}

/// `dexp⁻¹_θ(ω) = ω + ½·θ × ω + c(φ)·θ × (θ × ω)`, `c(φ) = (1 − (φ/2)·cot(φ/2))/φ²`: the rate
/// of `θ` for `Q = Q_n ⊗ exp(θ)` turning at the body angular velocity `ω` (module docs).
/// Singular at `φ = 2π` (where `exp` folds); integrators only use small `θ`.
pub fn dexp_inv<T: RealField + Copy>(theta: [T; 3], omega: [T; 3]) -> [T; 3] {
    let phi2 = theta[0] * theta[0] + theta[1] * theta[1] + theta[2] * theta[2];
    let c = if phi2 < k(0.0025) {
        k::<T>(1.0 / 12.0) + phi2 * (k::<T>(1.0 / 720.0) + phi2 * k(1.0 / 30240.0))
    } else {
        let half = phi2.sqrt() * k(0.5);
        (T::one() - half * half.cos() / half.sin()) / phi2
    };
    let a = cross(theta, omega);
    let b = cross(theta, a);
    [
        omega[0] + k::<T>(0.5) * a[0] + c * b[0],
        omega[1] + k::<T>(0.5) * a[1] + c * b[1],
        omega[2] + k::<T>(0.5) * a[2] + c * b[2],
    ]
}

fn get3<T: Copy>(x: &[T], at: usize) -> Option<[T; 3]> {
    Some([*x.get(at)?, *x.get(at + 1)?, *x.get(at + 2)?])
}

fn get4<T: Copy>(x: &[T], at: usize) -> Option<[T; 4]> {
    Some([
        *x.get(at)?,
        *x.get(at + 1)?,
        *x.get(at + 2)?,
        *x.get(at + 3)?,
    ])
}

fn set<T: Copy, const N: usize>(x: &mut [T], at: usize, value: [T; N]) {
    if let Some(dst) = x.get_mut(at..at + N) {
        dst.copy_from_slice(&value);
    }
}

/// `q ← q ⊕ δ` (module docs), in place: `q` has `Σ nq` entries, `delta` `Σ nv`.
pub fn integrate_in_place<T: RealField + Copy>(coords: &[Coordinates], q: &mut [T], delta: &[T]) {
    for (c, iq, iv) in joints(coords) {
        match c {
            Coordinates::Vector(n) => {
                if let (Some(x), Some(d)) = (q.get_mut(iq..iq + n), delta.get(iv..iv + n)) {
                    x.iter_mut().zip(d).for_each(|(x, d)| *x += *d);
                }
            }
            Coordinates::Quaternion => {
                if let (Some(qq), Some(d)) = (get4(q, iq), get3(delta, iv)) {
                    set(q, iq, quat_mul(qq, quat_exp(d)));
                }
            }
            Coordinates::FreeQuaternion => {
                if let (Some(p), Some(qq), Some(dp), Some(dw)) = (
                    get3(q, iq),
                    get4(q, iq + 3),
                    get3(delta, iv),
                    get3(delta, iv + 3),
                ) {
                    let r = quat_rotate(qq, dp);
                    set(q, iq, [p[0] + r[0], p[1] + r[1], p[2] + r[2]]);
                    set(q, iq + 3, quat_mul(qq, quat_exp(dw)));
                }
            }
        }
    }
}

/// `δ = q1 ⊖ q0`, the increment with `q0 ⊕ δ = q1` (the logarithm map), into `delta`.
/// Quaternions are taken as unit: `Q0⁻¹ = Q0*`. For `FreeQuaternion`,
/// `δ_p = R(Q0)ᵀ·(p1 − p0)`.
pub fn difference_into<T: RealField + Copy>(
    coords: &[Coordinates],
    q0: &[T],
    q1: &[T],
    delta: &mut [T],
) {
    difference_by(coords, q0, q1, delta, |q| q, quat_log);
}

/// [`difference_into`] as the controllers take it ([`crate::control::tangent::difference`]):
/// each quaternion normalized first (a zero one gives NaN), and of the two rotations that take
/// `Q0` to `Q1` the shorter (angle in `[0, π]`; [`quat_log`] alone gives up to `2π`).
pub(crate) fn difference_shortest_into<T: RealField + Copy>(
    coords: &[Coordinates],
    q0: &[T],
    q1: &[T],
    delta: &mut [T],
) {
    let shortest = |q: [T; 4]| quat_log(if q[0] < T::zero() { q.map(|x| -x) } else { q });
    difference_by(coords, q0, q1, delta, unit, shortest);
}

/// `q1 ⊖ q0` joint by joint, each quaternion `Q` taken as `unit(Q)` and each rotation's
/// increment as `log(Q0⁻¹ ⊗ Q1)`.
#[inline(always)]
fn difference_by<T: RealField + Copy>(
    coords: &[Coordinates],
    q0: &[T],
    q1: &[T],
    delta: &mut [T],
    unit: impl Fn([T; 4]) -> [T; 4],
    log: impl Fn([T; 4]) -> [T; 3],
) {
    for (c, iq, iv) in joints(coords) {
        match c {
            Coordinates::Vector(n) => {
                if let (Some(d), Some(a), Some(b)) = (
                    delta.get_mut(iv..iv + n),
                    q0.get(iq..iq + n),
                    q1.get(iq..iq + n),
                ) {
                    for (d, (a, b)) in d.iter_mut().zip(a.iter().zip(b)) {
                        *d = *b - *a;
                    }
                }
            }
            Coordinates::Quaternion => {
                if let (Some(a), Some(b)) = (get4(q0, iq), get4(q1, iq)) {
                    set(delta, iv, log(quat_mul(conjugate(unit(a)), unit(b))));
                }
            }
            Coordinates::FreeQuaternion => {
                if let (Some(p0), Some(a), Some(p1), Some(b)) = (
                    get3(q0, iq),
                    get4(q0, iq + 3),
                    get3(q1, iq),
                    get4(q1, iq + 3),
                ) {
                    let a = conjugate(unit(a));
                    let dp = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
                    set(delta, iv, quat_rotate(a, dp));
                    set(delta, iv + 3, log(quat_mul(a, unit(b))));
                }
            }
        }
    }
}

/// The rate `θ̇` of the local coordinates `θ` (`q = q_n ⊕ θ`) for the velocity `v` at `q`,
/// into `out` (module docs: `dexp⁻¹` for rotations, the velocity rotated by `exp(θ_ω)` for a
/// free joint's position, `v` itself for vectors). All three slices have `Σ nv` entries.
pub fn local_velocity_into<T: RealField + Copy>(
    coords: &[Coordinates],
    theta: &[T],
    v: &[T],
    out: &mut [T],
) {
    for (c, _, iv) in joints(coords) {
        match c {
            Coordinates::Vector(n) => {
                if let (Some(o), Some(x)) = (out.get_mut(iv..iv + n), v.get(iv..iv + n)) {
                    o.copy_from_slice(x);
                }
            }
            Coordinates::Quaternion => {
                if let (Some(t), Some(w)) = (get3(theta, iv), get3(v, iv)) {
                    set(out, iv, dexp_inv(t, w));
                }
            }
            Coordinates::FreeQuaternion => {
                if let (Some(tw), Some(u), Some(w)) =
                    (get3(theta, iv + 3), get3(v, iv), get3(v, iv + 3))
                {
                    set(out, iv, quat_rotate(quat_exp(tw), u));
                    set(out, iv + 3, dexp_inv(tw, w));
                }
            }
        }
    }
}

/// Divides each quaternion of `q` by its norm (a zero or non-finite quaternion is left as it
/// is). The integrators never call this: their quaternions are unit by the exponential map.
pub fn normalize<T: RealField + Copy>(coords: &[Coordinates], q: &mut [T]) {
    map_quaternions(coords, q, |qq| {
        let n = (qq[0] * qq[0] + qq[1] * qq[1] + qq[2] * qq[2] + qq[3] * qq[3]).sqrt();
        if n > T::zero() && n.is_finite() {
            qq.map(|x| x / n)
        } else {
            qq
        }
    });
}

/// Replaces each quaternion `Q` of `q` (`Σ nq` entries) by `f(Q)`.
pub(crate) fn map_quaternions<T: Copy>(
    coords: &[Coordinates],
    q: &mut [T],
    f: impl Fn([T; 4]) -> [T; 4],
) {
    for (c, iq, _) in joints(coords) {
        let at = match c {
            Coordinates::Vector(_) => None,
            Coordinates::Quaternion => Some(iq),
            Coordinates::FreeQuaternion => Some(iq + 3),
        };
        if let Some((at, qq)) = at.and_then(|at| Some((at, get4(q, at)?))) {
            set(q, at, f(qq));
        }
    }
}

/// `q ⊕ δ` (module docs).
pub fn integrate<T: RealField + Copy, const NQ: usize, const NV: usize>(
    coords: &[Coordinates],
    q: &SVector<T, NQ>,
    delta: &SVector<T, NV>,
) -> SVector<T, NQ> {
    let mut out = *q;
    integrate_in_place(coords, out.as_mut_slice(), delta.as_slice());
    out
}

/// `q1 ⊖ q0`: the increment `δ` with `q0 ⊕ δ = q1` (module docs).
pub fn difference<T: RealField + Copy, const NQ: usize, const NV: usize>(
    coords: &[Coordinates],
    q0: &SVector<T, NQ>,
    q1: &SVector<T, NQ>,
) -> SVector<T, NV> {
    let mut out = SVector::<T, NV>::zeros();
    difference_into(coords, q0.as_slice(), q1.as_slice(), out.as_mut_slice());
    out
}

/// `θ̇` for `q = q_n ⊕ θ` moving at the velocity `v` (module docs).
pub fn local_velocity<T: RealField + Copy, const NV: usize>(
    coords: &[Coordinates],
    theta: &SVector<T, NV>,
    v: &SVector<T, NV>,
) -> SVector<T, NV> {
    let mut out = SVector::<T, NV>::zeros();
    local_velocity_into(coords, theta.as_slice(), v.as_slice(), out.as_mut_slice());
    out
}
