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

/// The two-link system on a free foot (`models/two_link_foot.chain`), with the outputs its
/// contacts need: `hemami_standing` holds its sole by a six-dimensional contact,
/// `ground_contact` by four contact points.
#[derive(articulated::Chain)]
#[chain(file = "../models/two_link_foot.chain")]
pub struct Standing;

/// The two-link system with its ankle fixed: the model [`foot_law`] is designed on.
#[derive(articulated::Chain)]
#[chain(
    file = "../models/two_link.chain",
    outputs = [gravity, forward_dynamics_derivatives]
)]
pub struct FixedAnkle;

/// What a person's joints can give (N·m), as in `hemami_two_link`.
pub const COUPLE_LIMIT: f64 = 250.0;

/// The two-link system on its foot (`models/two_link_foot.chain`): positions and velocities.
type FootQ = SVector<f64, 13>;
type FootV = SVector<f64, 12>;

/// The upright LQR law of [`upright_lqr`] (designed on [`FixedAnkle`]) on the two-link system
/// standing on its foot ([`Standing`]): `τ = g(0) − K_q·q − K_v·v` on the ankle and hip,
/// saturated at [`COUPLE_LIMIT`]; nothing on the free foot.
///
/// # Errors
/// A message naming the step of the design that failed.
pub fn foot_law() -> Result<impl FnMut(f64, &FootQ, &FootV) -> FootV + Clone, String> {
    type C = FixedAnkle;
    let (_, design) = upright_lqr::<C, 6>()?;
    let (kq, kv) = articulated::control::state_feedback::split_gain::<6>(&design.k)
        .ok_or("the gain is not 6 × 12")?;
    let g0 = C::gravity(&SVector::zeros());
    Ok(move |_: f64, q: &FootQ, v: &FootV| {
        let joints = g0 - kq * q.fixed_rows::<6>(7) - kv * v.fixed_rows::<6>(6);
        let mut tau = FootV::zeros();
        tau.fixed_rows_mut::<6>(6)
            .copy_from(&joints.map(|x| x.clamp(-COUPLE_LIMIT, COUPLE_LIMIT)));
        tau
    })
}
