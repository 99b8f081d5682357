//! Linear state feedback about an equilibrium: the LQR law
//!
//! ```text
//! τ = τ_eq − K·(x ⊖ x_eq),    x ⊖ x_eq = (q ⊖ q_eq, v − v_eq),
//! ```
//!
//! with `K = [K_q, K_v]` (`NV × 2NV`) from [`super::riccati::lqr`] on the linearization
//! [`super::linearize`] about `(q_eq, v_eq, τ_eq)` (`τ_eq` holds the chain there, e.g.
//! `C::gravity(&q_eq)` at rest). `q ⊖ q_eq` is [`super::tangent::difference`], the tangent
//! displacement in which the linearization was taken, so the law is consistent with it for
//! quaternion joints too.

#[cfg(feature = "alloc")]
use nalgebra::DMatrix;
use nalgebra::{SMatrix, SVector};

use crate::control::tangent::difference;
use crate::control::Controller;
use crate::differentiate::{check_dimensions, CoordinatesError};
use crate::Coordinates;

#[cfg(feature = "alloc")]
/// `K = [K_q, K_v]` split into its position and velocity blocks, each `NV × NV`; `None` unless
/// `k` is `NV × 2NV`.
pub fn split_gain<const NV: usize>(
    k: &DMatrix<f64>,
) -> Option<(SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>)> {
    if k.shape() != (NV, 2 * NV) {
        return None;
    }
    let kq = SMatrix::<f64, NV, NV>::from_fn(|i, j| k[(i, j)]);
    let kv = SMatrix::<f64, NV, NV>::from_fn(|i, j| k[(i, NV + j)]);
    Some((kq, kv))
}

/// The state-feedback controller `(t, q, v) ↦ τ_eq − K_q·(q ⊖ q_eq) − K_v·(v − v_eq)` for a
/// chain with these `coordinates`. Allocates nothing when called; a zero quaternion in `q`
/// gives NaN couples.
///
/// # Errors
/// [`CoordinatesError::Length`] when the coordinates do not add up to `NQ`, `NV`.
pub fn state_feedback<'a, const NQ: usize, const NV: usize>(
    coordinates: &'a [Coordinates],
    q_eq: SVector<f64, NQ>,
    v_eq: SVector<f64, NV>,
    tau_eq: SVector<f64, NV>,
    kq: SMatrix<f64, NV, NV>,
    kv: SMatrix<f64, NV, NV>,
) -> Result<impl Controller<NQ, NV> + 'a, CoordinatesError> {
    check_dimensions(coordinates, NQ, NV)?;
    Ok(move |_t: f64, q: &SVector<f64, NQ>, v: &SVector<f64, NV>| {
        let mut dq = SVector::<f64, NV>::zeros();
        // The sizes were checked above, so `difference` fills `dq`.
        difference(
            coordinates,
            q.as_slice(),
            q_eq.as_slice(),
            dq.as_mut_slice(),
        );
        tau_eq - kq * dq - kv * (v - v_eq)
    })
}
