//! A free-floating chain moved by its joints alone (Wieber 2005, §4–5): the joints follow a
//! prescribed motion, the free base is unactuated, and nothing outside the chain pushes on it but
//! gravity.
//!
//! # Hybrid dynamics
//! With the base's 6 velocities first, `v = [v_b; v_j]`, the dynamics
//! `M(q)·a + nle(q, v) = [0; τ]` (Wieber 2005, eqs. 5 and 15: the actuators' forces act between
//! bodies, so the base's rows carry none) split into the base's rows
//!
//! ```text
//! M_bb·a_b + M_bj·a_j + nle_b = 0
//! ```
//!
//! and the joints' rows, which only say what the couples `τ` are. With the joint accelerations
//! `a_j(t)` prescribed, the base's follow from the first: `a_b = −M_bb⁻¹·(M_bj·a_j + nle_b)`.
//! [`Hybrid`] is that system, for the runtime's integrators, with `M` and `nle` from one generated
//! function ([`MassMatrixAndNonlinearEffects`]).
//!
//! Gravity only accelerates the centre of mass (Wieber 2005, §3.3: `𝓕_g = M·[0; g; 0]`), so the
//! momenta about the centre of mass are conserved (§4.2): `m·ẋ_G = m·ẋ_G(0) + m·g·t` and
//! `k_G = k_G(0)`. Started with zero momentum ([`Hybrid::start`]), the body turns only through the
//! nonholonomy of `k_G = 0`.
//!
//! # An independent check
//! [`momentum`] computes the centre of mass and the angular momentum about it from the
//! reference's body Jacobians (Wieber 2005, eq. 3: plain 3D kinematics, sharing no code with the
//! generated recursions):
//! `k_G = Σ_k (x_k − x_G) × m_k·ẋ_k + R_k·𝕀_k·ω_k` (the bracket of Wieber's eq. 18).
//! [`conservation`] sets it, and the generated `centroidal_momentum` and `center_of_mass`,
//! against the conservation laws over a run.
//!
//! # Orientation
//! The base's orientation is a unit quaternion `[w, x, y, z]` (child → world); how far the body
//! turned is measured in its own frame at the start, `Q_net = Q₀⁻¹ ⊗ Q`, and split into a
//! rotation about one body axis (the *twist*) and a tilt of that axis (the *swing*):
//! [`twist_angle`], [`swing_angle`].

use core::marker::PhantomData;

use articulated::integrate::{Cause, Dopri5, Dopri5Stats, SecondOrder, State};
use articulated::model::Model;
use articulated::nalgebra::{Const, Quaternion, SVector, UnitQuaternion, Vector3};
use articulated::prelude::*;
use articulated::reference::jacobian::body_jacobians;
use articulated::reference::Error as ReferenceError;

/// A joint motion prescribed in time: the joints' positions, velocities and accelerations
/// `[q_j, q̇_j, q̈_j]` at `t`.
pub trait JointMotion<const NJ: usize> {
    /// `[q_j(t), q̇_j(t), q̈_j(t)]`.
    fn at(&self, t: f64) -> [SVector<f64, NJ>; 3];
}

impl<const NJ: usize, F: Fn(f64) -> [SVector<f64, NJ>; 3]> JointMotion<NJ> for F {
    fn at(&self, t: f64) -> [SVector<f64, NJ>; 3] {
        self(t)
    }
}

/// A generated chain `C` whose first joint is `free(quaternion)` (7 positions, 6 velocities) and
/// whose `NJ` other velocities follow `motion`: `v̇ = [a_b; a_j(t)]` with the base's
/// acceleration from the first six rows of the dynamics (module docs).
pub struct Hybrid<C, P, const NJ: usize> {
    motion: P,
    chain: PhantomData<fn() -> C>,
}

impl<C, P, const NJ: usize> Hybrid<C, P, NJ> {
    /// The chain moved by `motion`.
    pub fn new(motion: P) -> Self {
        Hybrid {
            motion,
            chain: PhantomData,
        }
    }

    /// The motion.
    pub fn motion(&self) -> &P {
        &self.motion
    }
}

/// What the base's rows give: `a_b` from `M`, `nle` and the joints' accelerations, or the
/// velocity `v_b` for zero momentum from `v_j` (the same solve with `nle = 0`).
fn solve_base<const NV: usize, const NJ: usize>(
    m: &articulated::nalgebra::SMatrix<f64, NV, NV>,
    nle_b: &SVector<f64, 6>,
    x_j: &SVector<f64, NJ>,
) -> Result<SVector<f64, 6>, Cause<f64>> {
    let m_bb = m.fixed_view::<6, 6>(0, 0).into_owned();
    let m_bj = m.fixed_view::<6, NJ>(0, 6);
    let rhs = -(nle_b + m_bj * x_j);
    let chol = m_bb.cholesky().ok_or(Cause::System(
        "the base's 6 × 6 block of the mass matrix is not positive definite",
    ))?;
    Ok(chol.solve(&rhs))
}

/// `NV = 6 + NJ` and `NQ = 7 + NJ`: a quaternion free base, then the joints (checked at compile
/// time, where the sizes meet).
struct Sizes<const NQ: usize, const NV: usize, const NJ: usize>;

impl<const NQ: usize, const NV: usize, const NJ: usize> Sizes<NQ, NV, NJ> {
    const OK: () = assert!(NV == 6 + NJ && NQ == 7 + NJ);
}

impl<C, P: JointMotion<NJ>, const NJ: usize> Hybrid<C, P, NJ> {
    /// The state at `t` with the base at `position` (world frame) turned by `orientation`, the
    /// joints where the motion puts them, and the base's velocity that makes the chain's momenta
    /// zero: the first six rows of `M·v` are the chain's momentum (linear and angular, in the
    /// base frame about its origin: Wieber 2005, eq. 11 times `q̇`), so
    /// `v_b = −M_bb⁻¹·M_bj·q̇_j`.
    ///
    /// # Errors
    /// [`Cause::System`] if `M_bb` is not positive definite (a non-finite input).
    pub fn start<const NQ: usize, const NV: usize>(
        &self,
        t: f64,
        position: [f64; 3],
        orientation: UnitQuaternion<f64>,
    ) -> Result<State<f64, Const<NQ>, Const<NV>>, Cause<f64>>
    where
        C: MassMatrixAndNonlinearEffects<f64, NQ, NV>,
    {
        let () = Sizes::<NQ, NV, NJ>::OK;
        let [q_j, v_j, _] = self.motion.at(t);
        let o = orientation.into_inner();
        let mut q = SVector::<f64, NQ>::zeros();
        q.fixed_rows_mut::<3>(0).copy_from_slice(&position);
        q.fixed_rows_mut::<4>(3)
            .copy_from_slice(&[o.w, o.i, o.j, o.k]);
        q.fixed_rows_mut::<NJ>(7).copy_from(&q_j);
        let mut v = SVector::<f64, NV>::zeros();
        v.fixed_rows_mut::<NJ>(6).copy_from(&v_j);
        let m = C::mass_matrix_and_nonlinear_effects(&q, &v).0;
        let v_b = solve_base(&m, &SVector::zeros(), &v_j)?;
        v.fixed_rows_mut::<6>(0).copy_from(&v_b);
        Ok(State::new(t, q, v))
    }
}

impl<C, P, const NQ: usize, const NV: usize, const NJ: usize> SecondOrder<f64, Const<NQ>, Const<NV>>
    for Hybrid<C, P, NJ>
where
    C: MassMatrixAndNonlinearEffects<f64, NQ, NV>,
    P: JointMotion<NJ>,
{
    fn coordinates(&self) -> &[Coordinates] {
        C::COORDINATES
    }

    fn acceleration(
        &mut self,
        t: f64,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
    ) -> Result<SVector<f64, NV>, Cause<f64>> {
        let () = Sizes::<NQ, NV, NJ>::OK;
        let [_, _, a_j] = self.motion.at(t);
        let (m, nle) = C::mass_matrix_and_nonlinear_effects(q, v);
        let a_b = solve_base(&m, &nle.fixed_rows::<6>(0).into_owned(), &a_j)?;
        let mut a = SVector::<f64, NV>::zeros();
        a.fixed_rows_mut::<6>(0).copy_from(&a_b);
        a.fixed_rows_mut::<NJ>(6).copy_from(&a_j);
        Ok(a)
    }
}

/// The base's orientation in a state `q` of a chain on a `free(quaternion)` base.
pub fn base_orientation(q: &[f64]) -> UnitQuaternion<f64> {
    UnitQuaternion::new_normalize(Quaternion::new(q[3], q[4], q[5], q[6]))
}

/// The angle of `r`'s rotation about the unit `axis`: `r = swing ⊗ twist` with the twist about
/// `axis` and the swing about an axis perpendicular to it (the swing–twist decomposition); the
/// twist's angle is `2·atan2(⟨r_xyz, axis⟩, r_w)`, in `(−2π, 2π]`, continuous wherever the
/// quaternion is (keep `r` on the branch its integration gives: no sign flips).
pub fn twist_angle(r: &Quaternion<f64>, axis: &Vector3<f64>) -> f64 {
    2.0 * r.imag().dot(axis).atan2(r.w)
}

/// How far `r` tilts `axis`: the angle between `axis` and its image.
pub fn swing_angle(r: &UnitQuaternion<f64>, axis: &Vector3<f64>) -> f64 {
    (r * axis).angle(axis)
}

/// The centre of mass and the momenta of a chain at `(q, v)`, from body Jacobians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Momentum {
    /// The centre of mass `x_G` (world frame).
    pub com: Vector3<f64>,
    /// Its velocity `ẋ_G`.
    pub com_velocity: Vector3<f64>,
    /// The angular momentum about the centre of mass, `k_G` (world axes).
    pub k_g: Vector3<f64>,
    /// `Σ_k |k_k|`, each body's own angular momentum about the centre of mass as it moves,
    /// `k_k = (x_k − x_G) × m_k·(ẋ_k − ẋ_G) + R_k·𝕀_k·ω_k`, in magnitude: a scale for `|k_G|`
    /// that is not zero when the bodies move relative to each other, even though their sum is
    /// (the `ẋ_G` terms sum to zero, `Σ_k m_k·(x_k − x_G) = 0`, so `Σ_k k_k = k_G`; leaving them
    /// in would let a fast fall inflate the scale).
    pub scale: f64,
}

/// [`Momentum`] at `(q, v)`, from the reference's body Jacobians
/// ([`articulated::reference::jacobian::body_jacobians`]: `ẋ_k = J_tk·v`, `ω_k = J_Rk·v`,
/// Wieber 2005, eq. 3), independent of the generated code.
///
/// # Errors
/// Those of `body_jacobians` (wrong lengths, non-finite entries, a model with parameters given
/// no values).
pub fn momentum(model: &Model, q: &[f64], v: &[f64]) -> Result<Momentum, ReferenceError> {
    let bodies = body_jacobians(model, &model.param_defaults(), q, v)?;
    let vel = articulated::nalgebra::DVector::from_column_slice(v);
    let mass: f64 = bodies.iter().map(|b| b.mass).sum();
    let mut com = Vector3::zeros();
    let mut com_velocity = Vector3::zeros();
    let mut moving = Vec::with_capacity(bodies.len());
    for b in &bodies {
        let x_dot = Vector3::from_column_slice((&b.jt * &vel).as_slice());
        let omega = Vector3::from_column_slice((&b.jr * &vel).as_slice());
        com += b.com * (b.mass / mass);
        com_velocity += x_dot * (b.mass / mass);
        moving.push((b, x_dot, omega));
    }
    let (mut k_g, mut scale) = (Vector3::zeros(), 0.0);
    for (b, x_dot, omega) in moving {
        let k = (b.com - com).cross(&((x_dot - com_velocity) * b.mass))
            + b.rotation * (b.inertia * omega);
        k_g += k;
        scale += k.norm();
    }
    Ok(Momentum {
        com,
        com_velocity,
        k_g,
        scale,
    })
}

/// How well a run kept the conservation laws of a free-floating chain under internal forces and
/// gravity (Wieber 2005, §4.2): the angular momentum about the centre of mass stays zero, the
/// centre of mass falls freely. Each is measured twice: by the generated `centroidal_momentum`
/// and `center_of_mass`, and by [`momentum`] (the reference's body Jacobians, independent of
/// the generated code).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conservation {
    /// `max_t |k_G(t)| / max_t Σ_k |k_k(t)|`, `k_G` generated.
    pub momentum: f64,
    /// The same with `k_G` from body Jacobians.
    pub momentum_check: f64,
    /// `max_t Σ_k |k_k(t)|` (kg·m²/s): the scale, the bodies' own angular momenta about the
    /// centre of mass (body Jacobians; [`Momentum::scale`]).
    pub momentum_scale: f64,
    /// `max_t |x_G(t) − (x_G(0) + ẋ_G(0)·t + ½·g·t²)|` (m), `x_G` generated.
    pub com: f64,
    /// The same with `x_G` from body Jacobians.
    pub com_check: f64,
    /// `max_t |p(t) − p(0) − m·g·t|` (kg·m/s), the generated linear momentum.
    pub linear_momentum: f64,
}

/// [`Conservation`] over the recorded `states` of the generated chain `C` (gravity `g =
/// [0, 0, −9.81]`), `model` being its description loaded by the reference.
///
/// # Errors
/// The reference's, as text; no states.
pub fn conservation<C, const NQ: usize, const NV: usize>(
    model: &Model,
    states: &[State<f64, Const<NQ>, Const<NV>>],
) -> Result<Conservation, String>
where
    C: CentroidalMomentum<f64, NQ, NV> + CenterOfMass<f64, NQ, NV>,
{
    let g = Vector3::new(0.0, 0.0, -9.81);
    let params = model.param_defaults();
    let mass: f64 = model.bodies.iter().map(|b| b.mass.get(&params)).sum();
    let first = states.first().ok_or("no states")?;
    let t0 = first.t;
    let m0 = momentum(model, first.q.as_slice(), first.v.as_slice()).map_err(|e| e.to_string())?;
    let x0 = C::center_of_mass(&first.q);
    let p0 = C::centroidal_momentum(&first.q, &first.v)
        .fixed_rows::<3>(3)
        .into_owned();
    let mut c = Conservation {
        momentum: 0.0,
        momentum_check: 0.0,
        momentum_scale: 0.0,
        com: 0.0,
        com_check: 0.0,
        linear_momentum: 0.0,
    };
    for s in states {
        let m = momentum(model, s.q.as_slice(), s.v.as_slice()).map_err(|e| e.to_string())?;
        let h = C::centroidal_momentum(&s.q, &s.v);
        let t = s.t - t0;
        let fallen = m0.com_velocity * t + g * (0.5 * t * t);
        c.momentum = c.momentum.max(h.fixed_rows::<3>(0).norm());
        c.momentum_check = c.momentum_check.max(m.k_g.norm());
        c.momentum_scale = c.momentum_scale.max(m.scale);
        c.com = c.com.max((C::center_of_mass(&s.q) - (x0 + fallen)).norm());
        c.com_check = c.com_check.max((m.com - (m0.com + fallen)).norm());
        c.linear_momentum = c
            .linear_momentum
            .max((h.fixed_rows::<3>(3) - p0 - g * (mass * t)).norm());
    }
    c.momentum /= c.momentum_scale;
    c.momentum_check /= c.momentum_scale;
    Ok(c)
}

/// Runs `system` from `start` to `t_end` with Dormand–Prince at the tolerances `rtol`, `atol`,
/// recording the state every `dt` (the start included); returns the states and the integrator's
/// counters.
///
/// # Errors
/// An integration fault, as text.
#[allow(clippy::type_complexity)]
pub fn record<S, const NQ: usize, const NV: usize>(
    system: &mut S,
    start: State<f64, Const<NQ>, Const<NV>>,
    (t_end, dt): (f64, f64),
    (rtol, atol): (f64, f64),
) -> Result<(Vec<State<f64, Const<NQ>, Const<NV>>>, Dopri5Stats), String>
where
    S: SecondOrder<f64, Const<NQ>, Const<NV>>,
{
    let mut dopri = Dopri5::new(rtol, atol);
    let mut states = Vec::new();
    Simulation::new(start.t, t_end, dt)
        .run(
            system,
            &mut dopri,
            start,
            |s| {
                states.push(*s);
                Ok(())
            },
            |_, _| {},
        )
        .map_err(|f| f.to_string())?;
    Ok((states, dopri.stats()))
}
