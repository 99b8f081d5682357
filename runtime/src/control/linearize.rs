//! Linearization of the joint-space dynamics `ẋ = f(x, u)`, `x = (q, v)`, `u = τ`, about a
//! state, by **central finite differences**.
//!
//! With `δ` a tangent displacement of the configuration (`q = q₀ ⊕ δ`, see
//! [`super::tangent`]; `δ̇ = v` to first order) the state is `x = (δ, v)` and
//!
//! ```text
//! A = ∂(δ̇, v̇)/∂(δ, v) = [[0, I], [∂v̇/∂δ, ∂v̇/∂v]],    B = ∂(δ̇, v̇)/∂τ = [[0], [∂v̇/∂τ]].
//! ```
//!
//! The `[0, I]` row is exact at the point linearized (for `Vector` coordinates everywhere);
//! the blocks of `v̇` come from the caller's closure `f(δ, v, τ) ↦ v̇` (typically
//! `C::forward_dynamics(&q₀ ⊕ δ, v, τ)`, the closure doing the retraction, so quaternion joints
//! are handled on their manifold) by central differences,
//! `∂f/∂x_j ≈ (f(x + h_j e_j) − f(x − h_j e_j)) / (2h_j)` with the step chosen per scalar,
//! `h_j = ε^(1/3)·max(1, |x_j|)`, which balances the `O(h²)` truncation against the `O(ε/h)`
//! rounding (Nocedal & Wright, *Numerical Optimization*, 2nd ed., 2006, §8.1): about 8 to 10
//! correct digits on smooth dynamics, exact up to rounding on a linear system. Each `h_j` is
//! rounded so that `x_j ± h_j` are exactly representable (so the divisor is the true step).
//!
//! [`exact`] builds the same `A` and `B` from a generated chain's exact derivatives
//! (`forward_dynamics_derivatives`: `∂q̈/∂q` along the same tangent, `∂q̈/∂v`, `M⁻¹`), with no
//! step to choose and no truncation error; prefer it wherever the chain generates them, and keep
//! [`linearize`] for dynamics given as a closure (a controlled system, a model read at run time).

use core::fmt;

use nalgebra::{DMatrix, SVector};

use crate::{ForwardDynamicsDerivatives, SingularMassMatrix};

/// Why a linearization failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinearizeError<E> {
    /// A slice does not have `nv` entries.
    Length {
        /// `"v"`, `"tau"` or the closure's output `"v_dot"`.
        slice: &'static str,
        /// Its length.
        found: usize,
        /// `nv`.
        expected: usize,
    },
    /// The dynamics closure failed.
    Dynamics(E),
    /// The closure returned a non-finite acceleration.
    NotFinite,
}

impl<E: fmt::Display> fmt::Display for LinearizeError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LinearizeError::Length {
                slice,
                found,
                expected,
            } => write!(f, "`{slice}` has {found} entries, expected {expected}"),
            LinearizeError::Dynamics(e) => write!(f, "dynamics: {e}"),
            LinearizeError::NotFinite => write!(f, "the dynamics returned a non-finite value"),
        }
    }
}

impl<E: fmt::Debug + fmt::Display> core::error::Error for LinearizeError<E> {}

/// `A` (`2nv × 2nv`) and `B` (`2nv × nv`) of `ẋ = A·x + B·u`, `x = (δ, v − v₀)`,
/// `u = τ − τ₀`.
#[derive(Clone, Debug, PartialEq)]
pub struct Linearization {
    /// The state matrix `[[0, I], [∂v̇/∂δ, ∂v̇/∂v]]`.
    pub a: DMatrix<f64>,
    /// The input matrix `[[0], [∂v̇/∂τ]]`.
    pub b: DMatrix<f64>,
}

/// The step for a scalar at `x`: `ε^(1/3)·max(1, |x|)`, rounded so that `x + h` is exact.
fn step(x: f64) -> f64 {
    let h = libm::cbrt(f64::EPSILON) * f64::max(1.0, x.abs());
    (x + h) - x
}

/// [`linearize`] for sizes known at run time: `f(δ, v, τ, v̇)` writes `v̇`.
///
/// # Errors
/// [`LinearizeError::Length`] when `v`, `tau` are not `nv` long, [`LinearizeError::Dynamics`]
/// with the closure's first error, [`LinearizeError::NotFinite`].
pub fn linearize_dyn<F, E>(
    v: &[f64],
    tau: &[f64],
    mut f: F,
) -> Result<Linearization, LinearizeError<E>>
where
    F: FnMut(&[f64], &[f64], &[f64], &mut [f64]) -> Result<(), E>,
{
    use alloc::vec;
    let nv = v.len();
    if tau.len() != nv {
        return Err(LinearizeError::Length {
            slice: "tau",
            found: tau.len(),
            expected: nv,
        });
    }
    let mut a = DMatrix::zeros(2 * nv, 2 * nv);
    let mut b = DMatrix::zeros(2 * nv, nv);
    for i in 0..nv {
        a[(i, nv + i)] = 1.0;
    }
    // x = (δ, v, τ), one block of `nv` each; δ = 0 at the point.
    let mut x = vec![0.0; 3 * nv];
    x[nv..2 * nv].copy_from_slice(v);
    x[2 * nv..].copy_from_slice(tau);
    let mut plus = vec![0.0; nv];
    let mut minus = vec![0.0; nv];
    let mut eval = |x: &[f64], out: &mut [f64]| -> Result<(), LinearizeError<E>> {
        f(&x[..nv], &x[nv..2 * nv], &x[2 * nv..], out).map_err(LinearizeError::Dynamics)?;
        if out.iter().all(|y| y.is_finite()) {
            Ok(())
        } else {
            Err(LinearizeError::NotFinite)
        }
    };
    for j in 0..3 * nv {
        let x0 = x[j];
        let h = step(x0);
        x[j] = x0 + h;
        eval(&x, &mut plus)?;
        x[j] = x0 - h;
        eval(&x, &mut minus)?;
        x[j] = x0;
        for i in 0..nv {
            let d = (plus[i] - minus[i]) / (2.0 * h);
            if j < 2 * nv {
                a[(nv + i, j)] = d;
            } else {
                b[(nv + i, j - 2 * nv)] = d;
            }
        }
    }
    Ok(Linearization { a, b })
}

/// `A` and `B` about the configuration the closure is centred on, the velocity `v` and the
/// couples `tau`, from `f(δ, v, τ) ↦ v̇` by central differences (see the
/// [module docs](self)). For a generated chain `C` about `q₀`:
///
/// ```
/// use articulated::control::{linearize::linearize, tangent::retract};
/// use articulated::nalgebra::SVector;
/// use articulated::prelude::*;
///
/// articulated::chain! {
///     chain Pendulum {
///         body bob { mass: 1.0, com: [0.0, 0.0, 1.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob }
///     }
/// }
/// // Upright (the bob 1 m above the pivot): v̇ = (m g l·δ + τ)/(I_yy + m l²).
/// let q0 = SVector::<f64, 1>::zeros();
/// let lin = linearize(&SVector::zeros(), &SVector::zeros(), |d: &SVector<f64, 1>, v, tau| {
///     let mut q = SVector::<f64, 1>::zeros();
///     retract(Pendulum::COORDINATES, q0.as_slice(), d.as_slice(), q.as_mut_slice());
///     Pendulum::forward_dynamics(&q, v, tau)
/// })?;
/// assert!((lin.a[(1, 0)] - 9.81 / 1.01).abs() < 1e-7 && (lin.b[(1, 0)] - 1.0 / 1.01).abs() < 1e-8);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`LinearizeError::Dynamics`] with the closure's first error, [`LinearizeError::NotFinite`].
pub fn linearize<const NV: usize, F, E>(
    v: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
    mut f: F,
) -> Result<Linearization, LinearizeError<E>>
where
    F: FnMut(
        &SVector<f64, NV>,
        &SVector<f64, NV>,
        &SVector<f64, NV>,
    ) -> Result<SVector<f64, NV>, E>,
{
    linearize_dyn(v.as_slice(), tau.as_slice(), |d, v, t, out| {
        let y = f(
            &SVector::from_column_slice(d),
            &SVector::from_column_slice(v),
            &SVector::from_column_slice(t),
        )?;
        out.copy_from_slice(y.as_slice());
        Ok(())
    })
}

/// `A` and `B` about `(q, v, τ)` from the exact derivatives a generated chain `C` emits with
/// `forward_dynamics_derivatives` in its `outputs`: `A = [[0, I], [∂q̈/∂q, ∂q̈/∂v]]`,
/// `B = [[0], [M⁻¹]]`, in the state `x = (δ, v)` of the [module docs](self) (`∂q̈/∂q` is taken
/// along the same tangent `δ`, so the result is what [`linearize`] approximates).
///
/// ```
/// use articulated::control::linearize::exact;
/// use articulated::nalgebra::SVector;
///
/// articulated::chain! {
///     chain Pendulum {
///         outputs: [forward_dynamics_derivatives];
///         body bob { mass: 1.0, com: [0.0, 0.0, 1.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob }
///     }
/// }
/// // Upright: v̇ = (m g l·δ + τ)/(I_yy + m l²), exactly.
/// let zero = SVector::<f64, 1>::zeros();
/// let lin = exact::<Pendulum, 1, 1>(&zero, &zero, &zero)?;
/// assert!((lin.a[(1, 0)] - 9.81 / 1.01).abs() < 1e-14 && (lin.b[(1, 0)] - 1.0 / 1.01).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`SingularMassMatrix`] where `M(q)` is singular or `q̈` is not finite.
pub fn exact<C, const NQ: usize, const NV: usize>(
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
) -> Result<Linearization, SingularMassMatrix>
where
    C: ForwardDynamicsDerivatives<f64, NQ, NV>,
{
    let (dq, dv, minv) = C::forward_dynamics_derivatives(q, v, tau)?;
    let mut a = DMatrix::zeros(2 * NV, 2 * NV);
    let mut b = DMatrix::zeros(2 * NV, NV);
    for i in 0..NV {
        a[(i, NV + i)] = 1.0;
        for j in 0..NV {
            a[(NV + i, j)] = dq[(i, j)];
            a[(NV + i, NV + j)] = dv[(i, j)];
            b[(NV + i, j)] = minv[(i, j)];
        }
    }
    Ok(Linearization { a, b })
}
