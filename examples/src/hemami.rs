//! What Hemami's two-link examples share (`hemami_two_link`, `hemami_standing`): the LQR design
//! about upright on the fixed-ankle model.

use articulated::control::linearize::{exact, Linearization};
use articulated::control::riccati::{lqr, Lqr};
use articulated::nalgebra::{DMatrix, SVector};
use articulated::{ForwardDynamicsDerivatives, Gravity};

/// The linearization about upright (`q = v = 0`, `τ = g(0)`) from the generated exact
/// derivatives of forward dynamics, and the LQR design on it with `Q = diag(100·I, 10·I)`,
/// `R = 0.01·I`.
///
/// # Errors
/// A message naming the step that failed.
pub fn upright_lqr<C, const N: usize>() -> Result<(Linearization, Lqr), String>
where
    C: ForwardDynamicsDerivatives<f64, N, N> + Gravity<f64, N, N>,
{
    let upright = SVector::<f64, N>::zeros();
    let lin = exact::<C, N, N>(&upright, &upright, &C::gravity(&upright))
        .map_err(|e| format!("linearization: {e}"))?;
    let mut q = DMatrix::<f64>::zeros(2 * N, 2 * N);
    for i in 0..N {
        q[(i, i)] = 100.0;
        q[(N + i, N + i)] = 10.0;
    }
    let design = lqr(&lin.a, &lin.b, &q, &(DMatrix::identity(N, N) * 0.01))
        .map_err(|e| format!("LQR: {e}"))?;
    Ok((lin, design))
}
