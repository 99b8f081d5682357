//! Computed torque with a PD law on the tracking error (Paul 1972, "Modelling, trajectory
//! calculation and servoing of a computer controlled arm", Stanford AIM-177; Siciliano et
//! al., *Robotics: Modelling, Planning and Control*, 2009, §8.5.2):
//!
//! ```text
//! τ = ID(q, v, a_ref + Kp·(q_ref ⊖ q) + Kd·(v_ref − v))
//! ```
//!
//! With exact inverse dynamics the closed loop is `ë + Kd·ė + Kp·e = 0` in the error
//! `e = q_ref ⊖ q`, which decays for any positive definite `Kp`, `Kd` (critically damped for
//! `Kd = 2√Kp` on diagonal gains). `⊖` is the plain difference for `Vector` coordinates and the
//! quaternion logarithm for quaternion joints ([`super::tangent::difference`], the error
//! expressed in the current child frame, like `v`); `v_ref − v` subtracts velocities taken in
//! the reference's and the current child frames, a difference that vanishes as the error
//! does.

use nalgebra::{SMatrix, SVector};

use crate::control::tangent::difference;
use crate::control::Controller;
use crate::differentiate::{check_dimensions, CoordinatesError};
use crate::Coordinates;

/// `(q_ref, v_ref, a_ref)`: a reference that holds `q_ref` still, for [`computed_torque`].
pub fn hold<const NQ: usize, const NV: usize>(
    q_ref: SVector<f64, NQ>,
) -> impl FnMut(f64) -> (SVector<f64, NQ>, SVector<f64, NV>, SVector<f64, NV>) {
    move |_| (q_ref, SVector::zeros(), SVector::zeros())
}

/// The computed-torque + PD controller `(t, q, v) ↦ τ` (law in the [module docs](self)) for a
/// chain with these `coordinates`, gains `kp`, `kd` (`NV × NV`), a reference
/// `reference(t) = (q_ref, v_ref, a_ref)` and inverse dynamics `inverse_dynamics(q, v, a) = τ`
/// (for a generated chain `C`: `|q, v, a| C::inverse_dynamics(q, v, a)`). The controller
/// allocates nothing; a zero quaternion in `q` gives NaN couples, which a simulator reports as a
/// non-finite state.
///
/// ```
/// use articulated::control::computed_torque::{computed_torque, hold};
/// use articulated::nalgebra::{SMatrix, SVector};
/// use articulated::prelude::*;
///
/// articulated::chain! {
///     chain Pendulum {
///         body bob { mass: 1.0, com: [0.0, 0.0, 1.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob }
///     }
/// }
/// let kp = SMatrix::<f64, 1, 1>::new(25.0);
/// let kd = SMatrix::<f64, 1, 1>::new(10.0);
/// let mut control = computed_torque(
///     Pendulum::COORDINATES, kp, kd, hold(SVector::zeros()),
///     |q, v, a| Pendulum::inverse_dynamics(q, v, a),
/// )?;
/// // Tilted by 0.1 rad, at rest: τ = ID(q, 0, −25·0.1) = 1.01·(−2.5) − 9.81·sin 0.1.
/// let tau = control(0.0, &SVector::<f64, 1>::new(0.1), &SVector::zeros());
/// assert!((tau[0] - (-2.525 - 9.81 * 0.1f64.sin())).abs() < 1e-12);
/// # Ok::<(), articulated::differentiate::CoordinatesError>(())
/// ```
///
/// # Errors
/// [`CoordinatesError::Length`] when the coordinates do not add up to `NQ`, `NV`.
pub fn computed_torque<'a, const NQ: usize, const NV: usize, R, ID>(
    coordinates: &'a [Coordinates],
    kp: SMatrix<f64, NV, NV>,
    kd: SMatrix<f64, NV, NV>,
    mut reference: R,
    mut inverse_dynamics: ID,
) -> Result<impl Controller<NQ, NV> + 'a, CoordinatesError>
where
    R: FnMut(f64) -> (SVector<f64, NQ>, SVector<f64, NV>, SVector<f64, NV>) + 'a,
    ID: FnMut(&SVector<f64, NQ>, &SVector<f64, NV>, &SVector<f64, NV>) -> SVector<f64, NV> + 'a,
{
    check_dimensions(coordinates, NQ, NV)?;
    Ok(move |t: f64, q: &SVector<f64, NQ>, v: &SVector<f64, NV>| {
        let (q_ref, v_ref, a_ref) = reference(t);
        let mut e = SVector::<f64, NV>::zeros();
        // The sizes were checked above, so `difference` fills `e`.
        difference(
            coordinates,
            q_ref.as_slice(),
            q.as_slice(),
            e.as_mut_slice(),
        );
        let a = a_ref + kp * e + kd * (v_ref - v);
        inverse_dynamics(q, v, &a)
    })
}
