//! Derivatives of the constrained forward dynamics with respect to `q`, `v` and `τ`: what
//! model-predictive control of a robot on its feet linearizes (Pinocchio's
//! `computeConstraintDynamicsDerivatives`).
//!
//! At the solution `(q̈, f)` of `M·q̈ + nle = τ + Jᵀ·f`, `J·q̈ + γ = 0`, the two residuals
//! `r₁ = ID(q, v, q̈) − J(q)ᵀ·f − τ` and `r₂ = c(q, v, q̈)` (the constraints' acceleration, zero
//! at the solution) vanish for every `x = (q, v, τ)`; differentiating them at fixed `(q̈, f)`,
//!
//! ```text
//! [M  −Jᵀ] [∂q̈]     [∂r₁/∂x]        ∂f = G⁻¹·(J·M⁻¹·∂r₁/∂x − ∂r₂/∂x),
//! [J   0 ] [∂f ] = − [∂r₂/∂x],  so   ∂q̈ = M⁻¹·(Jᵀ·∂f − ∂r₁/∂x),   G = J·M⁻¹·Jᵀ,
//! ```
//!
//! with `∂r₁/∂τ = −I`, `∂r₂/∂τ = 0`. The pieces are generated outputs of the chain:
//! - `∂ID/∂q`, `∂ID/∂v` at `(q, v, q̈)`: `inverse_dynamics_derivatives`;
//! - `∂(Jᵀ·f)/∂q` at fixed `f`: column `k` is `(∂J/∂δ_k)ᵀ·f`, and `∂J/∂δ_k`, the derivative
//!   along the tangent direction `e_k`, is the Jacobian's rate at the velocity `e_k`
//!   (`frame_jacobian_time_variations_*(q, e_k)`, one call per velocity coordinate): LOCAL for a
//!   six-dimensional contact (its wrench is fixed in the frame), LOCAL_WORLD_ALIGNED for a point
//!   (its force is fixed in world axes);
//! - `∂c/∂q`, `∂c/∂v` at fixed `q̈`: a point's and a loop's rows are the linear part of the
//!   classical acceleration, whose derivatives are `frame_acceleration_derivatives(q, v, q̈)`; a
//!   six-dimensional contact's are its spatial acceleration in LOCAL, `c = Wᵀ·c_w` with
//!   `c_w = [ω̇; p̈ − ω × ṗ]` in world axes (`W = world_R_frame`, blockwise), and since `c = 0`
//!   at the solution, `∂c = Wᵀ·∂c_w`: the classical acceleration's derivatives less those of
//!   `ω × ṗ`, from `frame_velocity_derivatives` turned into world axes
//!   (`∂(W·u)/∂δ_k = ω_k × (W·u) + W·∂u/∂δ_k`, `ω_k` the LOCAL_WORLD_ALIGNED Jacobian's angular
//!   column `k`);
//! - a six-dimensional loop, `J = J_a − ᵃX_b·J_b` and `c = a_a − ᵃX_b·a_b + v_a × ᵃX_b·v_b`
//!   (LOCAL; `a_a`, `a_b` do not vanish on their own): the same pieces for each frame, the
//!   spatial accelerations' derivatives in full (`∂(Wᵀ·u)/∂δ_k = Wᵀ·∂u/∂δ_k − ω_k × Wᵀ·u`, `ω_k`
//!   the LOCAL Jacobian's angular column), and the transform's
//!   `∂ᵃX_b/∂δ_k = ᵃX_b·(s_b×) − (s_a×)·ᵃX_b`, `s` the LOCAL Jacobians' columns `k`.
//!
//! `∂/∂q` is along the configuration's tangent, as every derivative output's
//! (`articulated::generated`). Exact solves only ([`Settings::default`]): redundant constraints have
//! no unique forces to differentiate.

use nalgebra::{SMatrix, SVector, Vector3};

use super::{cross_motion, Transform};
use super::{forward_dynamics, ConstraintError, ConstraintOutputs, Contact, Frames, Kind, Loop};
use super::{Settings, Solution};
use crate::{
    FrameAccelerationDerivatives, FrameJacobianTimeVariationsLocal,
    FrameJacobianTimeVariationsLocalWorldAligned, FrameVelocityDerivatives,
    InverseDynamicsDerivatives,
};

/// What the derivatives need besides [`ConstraintOutputs`]: `inverse_dynamics_derivatives`,
/// `frame_jacobian_time_variations_local`, `frame_jacobian_time_variations_local_world_aligned`,
/// `frame_acceleration_derivatives` and `frame_velocity_derivatives` (`outputs = [derivatives,
/// frames…]`); implemented by every chain that has them.
pub trait DerivativeOutputs<const NQ: usize, const NV: usize, const NF: usize>:
    ConstraintOutputs<NQ, NV, NF>
    + InverseDynamicsDerivatives<f64, NQ, NV>
    + FrameJacobianTimeVariationsLocal<f64, NQ, NV, NF>
    + FrameJacobianTimeVariationsLocalWorldAligned<f64, NQ, NV, NF>
    + FrameAccelerationDerivatives<f64, NQ, NV, NF>
    + FrameVelocityDerivatives<f64, NQ, NV, NF>
{
}

impl<C, const NQ: usize, const NV: usize, const NF: usize> DerivativeOutputs<NQ, NV, NF> for C where
    C: ConstraintOutputs<NQ, NV, NF>
        + InverseDynamicsDerivatives<f64, NQ, NV>
        + FrameJacobianTimeVariationsLocal<f64, NQ, NV, NF>
        + FrameJacobianTimeVariationsLocalWorldAligned<f64, NQ, NV, NF>
        + FrameAccelerationDerivatives<f64, NQ, NV, NF>
        + FrameVelocityDerivatives<f64, NQ, NV, NF>
{
}

/// The constrained forward dynamics and its derivatives. The forces' rows past
/// `solution.rows` are zero, as are their derivatives.
#[derive(Clone, Debug, PartialEq)]
pub struct Derivatives<const NV: usize, const R: usize> {
    /// `q̈` and the forces.
    pub solution: Solution<NV, R>,
    /// `∂q̈/∂q` (along the tangent).
    pub dqdd_dq: SMatrix<f64, NV, NV>,
    /// `∂q̈/∂v`.
    pub dqdd_dv: SMatrix<f64, NV, NV>,
    /// `∂q̈/∂τ`.
    pub dqdd_dtau: SMatrix<f64, NV, NV>,
    /// `∂f/∂q` (along the tangent).
    pub dforces_dq: SMatrix<f64, R, NV>,
    /// `∂f/∂v`.
    pub dforces_dv: SMatrix<f64, R, NV>,
    /// `∂f/∂τ`.
    pub dforces_dtau: SMatrix<f64, R, NV>,
}

impl<const NV: usize, const R: usize> Derivatives<NV, R> {
    /// Whether every value is finite: `q̈`, the forces and the six derivatives.
    pub fn all_finite(&self) -> bool {
        let s = &self.solution;
        super::finite(&[
            s.acceleration.as_slice(),
            s.forces.as_slice(),
            self.dqdd_dq.as_slice(),
            self.dqdd_dv.as_slice(),
            self.dqdd_dtau.as_slice(),
            self.dforces_dq.as_slice(),
            self.dforces_dv.as_slice(),
            self.dforces_dtau.as_slice(),
        ])
    }
}

/// [`super::forward_dynamics_of`] (exact, no Baumgarte terms) and its derivatives with respect
/// to `q`, `v` and `τ` (module docs), for the `contacts` then the `loops` on a generated
/// chain's frames.
///
/// # Errors
/// As [`super::forward_dynamics_of`]; [`ConstraintError::NonFinite`] where a derivative is not
/// finite.
pub fn forward_dynamics_derivatives_of<
    C,
    const NQ: usize,
    const NV: usize,
    const NF: usize,
    const R: usize,
>(
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
    contacts: &[Contact],
    loops: &[Loop],
) -> Result<Derivatives<NV, R>, ConstraintError>
where
    C: DerivativeOutputs<NQ, NV, NF>,
{
    let frames = Frames::<NV, NF>::of::<C, NQ>(q, v);
    let system = frames.system::<R>(contacts, loops, None)?;
    let (m, nle) = C::mass_matrix_and_nonlinear_effects(q, v);
    let settings = Settings::default();
    let solution = forward_dynamics(&m, &nle, tau, v, &system, None, &settings)?;
    let (qdd, f) = (&solution.acceleration, &solution.forces);

    // ∂r₁/∂q = ∂ID/∂q − ∂(Jᵀ·f)/∂q, ∂r₁/∂v = ∂ID/∂v.
    let (did_dq, r1_dv) = C::inverse_dynamics_derivatives(q, v, qdd);
    let r1_dq = did_dq - force_term::<C, NQ, NV, NF, R>(q, f, &frames, contacts, loops);
    let (r2_dq, r2_dv) = constraint_term::<C, NQ, NV, NF, R>(q, v, qdd, &frames, contacts, loops);

    // The block solve, with the rows past `rows` left out (identity in `G`, zero elsewhere).
    let rows = system.rows;
    let mut j = system.jacobian;
    j.rows_mut(rows, R - rows).fill(0.0);
    let chol_m = m
        .cholesky()
        .ok_or(ConstraintError::MassMatrix { velocity: 0 })?;
    // The blocks of the KKT matrix's inverse, once: `A = M⁻¹·Jᵀ`, `B = G⁻¹·Aᵀ` and
    // `P = M⁻¹ − A·B`; then `∂q̈ = −P·∂r₁ − Bᵀ·∂r₂` and `∂f = B·∂r₁ − G⁻¹·∂r₂` (module docs,
    // with `A·G⁻¹ = Bᵀ`), which for `τ` (`∂r₁ = −I`, `∂r₂ = 0`) are `P` and `−B`. Products of
    // these, rather than a solve per right side: the solves' triangular sweeps and the copies of
    // their results were most of the time.
    let minv = chol_m.inverse();
    let a: SMatrix<f64, NV, R> = minv * j.transpose();
    let mut g: SMatrix<f64, R, R> = j * a;
    for r in rows..R {
        g[(r, r)] = 1.0;
    }
    let chol_g = g
        .cholesky()
        .ok_or(ConstraintError::Redundant { contact: 0, row: 0 })?;
    let b: SMatrix<f64, R, NV> = chol_g.solve(&a.transpose());
    let g_inv = chol_g.inverse();
    let mut p = minv;
    p.gemm(-1.0, &a, &b, 1.0);
    let derivative = |r1: &SMatrix<f64, NV, NV>, r2: &SMatrix<f64, R, NV>| {
        let mut dqdd = SMatrix::<f64, NV, NV>::zeros();
        dqdd.gemm(-1.0, &p, r1, 0.0);
        dqdd.gemm_tr(-1.0, &b, r2, 1.0);
        let mut df = SMatrix::<f64, R, NV>::zeros();
        df.gemm(1.0, &b, r1, 0.0);
        df.gemm(-1.0, &g_inv, r2, 1.0);
        (dqdd, df)
    };
    let (dqdd_dq, dforces_dq) = derivative(&r1_dq, &r2_dq);
    let (dqdd_dv, dforces_dv) = derivative(&r1_dv, &r2_dv);
    let (dqdd_dtau, dforces_dtau) = (p, -b);
    let derivatives = Derivatives {
        solution,
        dqdd_dq,
        dqdd_dv,
        dqdd_dtau,
        dforces_dq,
        dforces_dv,
        dforces_dtau,
    };
    if !derivatives.all_finite() {
        return Err(ConstraintError::NonFinite);
    }
    Ok(derivatives)
}

/// `∂(Jᵀ·f)/∂q` at fixed `f`: column `k` is `(∂J/∂δ_k)ᵀ·f`, the Jacobians' rates at the velocity
/// `e_k` (module docs).
fn force_term<C, const NQ: usize, const NV: usize, const NF: usize, const R: usize>(
    q: &SVector<f64, NQ>,
    f: &SVector<f64, R>,
    frames: &Frames<NV, NF>,
    contacts: &[Contact],
    loops: &[Loop],
) -> SMatrix<f64, NV, NV>
where
    C: DerivativeOutputs<NQ, NV, NF>,
{
    let points = contacts.iter().any(|c| c.kind == Kind::Point)
        || loops.iter().any(|l| l.kind == Kind::Point);
    let six_d =
        contacts.iter().any(|c| c.kind == Kind::SixD) || loops.iter().any(|l| l.kind == Kind::SixD);
    let mut djtf_dq = SMatrix::<f64, NV, NV>::zeros();
    for k in 0..NV {
        let e = SVector::<f64, NV>::from_fn(|i, _| if i == k { 1.0 } else { 0.0 });
        let local = six_d.then(|| C::frame_jacobian_time_variations_local(q, &e));
        let aligned = points.then(|| C::frame_jacobian_time_variations_local_world_aligned(q, &e));
        let mut column = SVector::<f64, NV>::zeros();
        let mut row = 0;
        for c in contacts {
            match (c.kind, &local, &aligned) {
                (Kind::SixD, Some(local), _) => {
                    column += local[c.frame].tr_mul(&f.fixed_rows::<6>(row));
                }
                (Kind::Point, _, Some(aligned)) => {
                    column += aligned[c.frame]
                        .fixed_rows::<3>(3)
                        .tr_mul(&f.fixed_rows::<3>(row));
                }
                _ => {}
            }
            row += c.kind.rows();
        }
        for l in loops {
            match (l.kind, &local, &aligned) {
                (Kind::Point, _, Some(aligned)) => {
                    let d = aligned[l.a].fixed_rows::<3>(3) - aligned[l.b].fixed_rows::<3>(3);
                    column += d.tr_mul(&f.fixed_rows::<3>(row));
                }
                (Kind::SixD, Some(local), _) => {
                    column += six_d_loop_force(
                        &Transform::between(&frames.placements[l.a], &frames.placements[l.b]),
                        (&frames.jacobians[l.a], &frames.jacobians[l.b]),
                        (&local[l.a], &local[l.b]),
                        k,
                        &f.fixed_rows::<6>(row).into(),
                    );
                }
                _ => {}
            }
            row += l.kind.rows();
        }
        djtf_dq.set_column(k, &column);
    }
    djtf_dq
}

/// `(∂c/∂q, ∂c/∂v)` of the constraints' accelerations at fixed `q̈`, their rows in order
/// (module docs).
fn constraint_term<C, const NQ: usize, const NV: usize, const NF: usize, const R: usize>(
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
    qdd: &SVector<f64, NV>,
    frames: &Frames<NV, NF>,
    contacts: &[Contact],
    loops: &[Loop],
) -> (SMatrix<f64, R, NV>, SMatrix<f64, R, NV>)
where
    C: DerivativeOutputs<NQ, NV, NF>,
{
    let acc = C::frame_acceleration_derivatives(q, v, qdd);
    let vel = C::frame_velocity_derivatives(q, v);
    let mut r2_dq = SMatrix::<f64, R, NV>::zeros();
    let mut r2_dv = SMatrix::<f64, R, NV>::zeros();
    let mut row = 0;
    for c in contacts {
        let (da_dq, da_dv, _) = &acc[c.frame];
        match c.kind {
            Kind::Point => {
                r2_dq
                    .fixed_rows_mut::<3>(row)
                    .copy_from(&da_dq.fixed_rows::<3>(3));
                r2_dv
                    .fixed_rows_mut::<3>(row)
                    .copy_from(&da_dv.fixed_rows::<3>(3));
            }
            Kind::SixD => {
                let (dq, dv) = six_d_rows(frames, c.frame, da_dq, da_dv, &vel[c.frame]);
                r2_dq.fixed_rows_mut::<6>(row).copy_from(&dq);
                r2_dv.fixed_rows_mut::<6>(row).copy_from(&dv);
            }
        }
        row += c.kind.rows();
    }
    let classical = loops
        .iter()
        .any(|l| l.kind == Kind::SixD)
        .then(|| C::frame_accelerations(q, v, qdd));
    for l in loops {
        let ((a_dq, a_dv, _), (b_dq, b_dv, _)) = (&acc[l.a], &acc[l.b]);
        match (l.kind, &classical) {
            (Kind::SixD, Some(classical)) => {
                let local =
                    |i: usize| LocalAcceleration::of(frames, i, &classical[i], &acc[i], &vel[i]);
                let (dq, dv) = six_d_loop_rows(
                    &Transform::between(&frames.placements[l.a], &frames.placements[l.b]),
                    (&frames.jacobians[l.a], &frames.jacobians[l.b]),
                    (&local(l.a), &local(l.b)),
                );
                r2_dq.fixed_rows_mut::<6>(row).copy_from(&dq);
                r2_dv.fixed_rows_mut::<6>(row).copy_from(&dv);
            }
            _ => {
                r2_dq
                    .fixed_rows_mut::<3>(row)
                    .copy_from(&(a_dq.fixed_rows::<3>(3) - b_dq.fixed_rows::<3>(3)));
                r2_dv
                    .fixed_rows_mut::<3>(row)
                    .copy_from(&(a_dv.fixed_rows::<3>(3) - b_dv.fixed_rows::<3>(3)));
            }
        }
        row += l.kind.rows();
    }
    (r2_dq, r2_dv)
}

/// A frame's LOCAL velocity and spatial acceleration at `(q, v, q̈)` and their derivatives.
struct LocalAcceleration<const NV: usize> {
    /// `v_l = [ω_l; v_l]`, LOCAL.
    velocity: SVector<f64, 6>,
    /// `∂v_l/∂δ`, `∂v_l/∂v`.
    dvelocity: (SMatrix<f64, 6, NV>, SMatrix<f64, 6, NV>),
    /// `a_l = [Wᵀ·ω̇; Wᵀ·p̈ − ω_l × v_l]`, the spatial acceleration in LOCAL.
    acceleration: SVector<f64, 6>,
    /// `∂a_l/∂δ`, `∂a_l/∂v`.
    dacceleration: (SMatrix<f64, 6, NV>, SMatrix<f64, 6, NV>),
}

impl<const NV: usize> LocalAcceleration<NV> {
    /// From the classical acceleration `[ω̇; p̈]` (world axes) and its derivatives, and the LOCAL
    /// velocity's derivatives: `∂(Wᵀ·u)/∂δ_k = Wᵀ·∂u/∂δ_k − ω_k × Wᵀ·u`, `ω_k` the LOCAL
    /// Jacobian's angular column `k` (`W` does not depend on `v`).
    #[allow(clippy::type_complexity)]
    fn of<const NF: usize>(
        frames: &Frames<NV, NF>,
        i: usize,
        classical: &SVector<f64, 6>,
        acc: &(
            SMatrix<f64, 6, NV>,
            SMatrix<f64, 6, NV>,
            SMatrix<f64, 6, NV>,
        ),
        vel: &(SMatrix<f64, 6, NV>, SMatrix<f64, 6, NV>),
    ) -> Self {
        let w = frames.placements[i].rotation;
        let j = &frames.jacobians[i];
        let velocity = frames.velocities[i];
        let (omega, lin) = (velocity.fixed_rows::<3>(0), velocity.fixed_rows::<3>(3));
        let turned = to_local(&w, classical);
        let mut acceleration = turned;
        let lin_a = turned.fixed_rows::<3>(3) - omega.cross(&lin);
        acceleration.fixed_rows_mut::<3>(3).copy_from(&lin_a);
        let (da_dq, da_dv, _) = acc;
        let (dvel_dq, dvel_dv) = vel;
        let mut dq = SMatrix::<f64, 6, NV>::zeros();
        let mut dv = SMatrix::<f64, 6, NV>::zeros();
        for k in 0..NV {
            let omega_k: Vector3<f64> = j.fixed_view::<3, 1>(0, k).into();
            let mut c = to_local(&w, &da_dq.column(k).into());
            let (ta, tl) = (turned.fixed_rows::<3>(0), turned.fixed_rows::<3>(3));
            let (dw, dl) = (
                dvel_dq.fixed_view::<3, 1>(0, k),
                dvel_dq.fixed_view::<3, 1>(3, k),
            );
            let d_ang = c.fixed_rows::<3>(0) - omega_k.cross(&ta);
            let d_lin =
                c.fixed_rows::<3>(3) - omega_k.cross(&tl) - dw.cross(&lin) - omega.cross(&dl);
            c.fixed_rows_mut::<3>(0).copy_from(&d_ang);
            c.fixed_rows_mut::<3>(3).copy_from(&d_lin);
            dq.set_column(k, &c);
            let mut c = to_local(&w, &da_dv.column(k).into());
            let (dw, dl) = (
                dvel_dv.fixed_view::<3, 1>(0, k),
                dvel_dv.fixed_view::<3, 1>(3, k),
            );
            let d_lin = c.fixed_rows::<3>(3) - dw.cross(&lin) - omega.cross(&dl);
            c.fixed_rows_mut::<3>(3).copy_from(&d_lin);
            dv.set_column(k, &c);
        }
        LocalAcceleration {
            velocity,
            dvelocity: (*dvel_dq, *dvel_dv),
            acceleration,
            dacceleration: (dq, dv),
        }
    }
}

/// `∂ᵃX_b/∂δ_k` applied to `m`: `ᵃX_b·(s_b × m) − s_a × ᵃX_b·m`, `s_a`, `s_b` the LOCAL
/// Jacobians' columns `k` (`d(ᵃX_b)/dt = ᵃX_b·(v_b×) − (v_a×)·ᵃX_b`).
fn transform_rate(
    x: &Transform,
    s: (&SVector<f64, 6>, &SVector<f64, 6>),
    m: &SVector<f64, 6>,
) -> SVector<f64, 6> {
    x.motion(&cross_motion(s.1, m)) - cross_motion(s.0, &x.motion(m))
}

/// Column `k` of `∂(Jᵀ·f)/∂q` for a six-dimensional loop, `J = J_a − ᵃX_b·J_b` (LOCAL): column
/// `c` of `∂J/∂δ_k` is `J̇_a(e_k)_c − ∂ᵃX_b/∂δ_k·(J_b)_c − ᵃX_b·J̇_b(e_k)_c`, dotted with `f`.
fn six_d_loop_force<const NV: usize>(
    x: &Transform,
    jacobians: (&SMatrix<f64, 6, NV>, &SMatrix<f64, 6, NV>),
    rates: (&SMatrix<f64, 6, NV>, &SMatrix<f64, 6, NV>),
    k: usize,
    f: &SVector<f64, 6>,
) -> SVector<f64, NV> {
    let (ja, jb) = jacobians;
    let s: (SVector<f64, 6>, SVector<f64, 6>) = (ja.column(k).into(), jb.column(k).into());
    SVector::<f64, NV>::from_fn(|c, _| {
        let u: SVector<f64, 6> = jb.column(c).into();
        let rate_b: SVector<f64, 6> = rates.1.column(c).into();
        let column = SVector::<f64, 6>::from(rates.0.column(c))
            - transform_rate(x, (&s.0, &s.1), &u)
            - x.motion(&rate_b);
        column.dot(f)
    })
}

/// `(∂c/∂q, ∂c/∂v)` of a six-dimensional loop's acceleration `c = a_a − ᵃX_b·a_b + v_a ×
/// ᵃX_b·v_b` (LOCAL, at fixed `q̈`).
fn six_d_loop_rows<const NV: usize>(
    x: &Transform,
    jacobians: (&SMatrix<f64, 6, NV>, &SMatrix<f64, 6, NV>),
    frames: (&LocalAcceleration<NV>, &LocalAcceleration<NV>),
) -> (SMatrix<f64, 6, NV>, SMatrix<f64, 6, NV>) {
    let (a, b) = frames;
    let moved_vb = x.motion(&b.velocity);
    let mut dq = SMatrix::<f64, 6, NV>::zeros();
    let mut dv = SMatrix::<f64, 6, NV>::zeros();
    for k in 0..NV {
        let s: (SVector<f64, 6>, SVector<f64, 6>) =
            (jacobians.0.column(k).into(), jacobians.1.column(k).into());
        let rate = |m: &SVector<f64, 6>| transform_rate(x, (&s.0, &s.1), m);
        let col = |m: &SMatrix<f64, 6, NV>| -> SVector<f64, 6> { m.column(k).into() };
        let c =
            col(&a.dacceleration.0) - rate(&b.acceleration) - x.motion(&col(&b.dacceleration.0))
                + cross_motion(&col(&a.dvelocity.0), &moved_vb)
                + cross_motion(
                    &a.velocity,
                    &(rate(&b.velocity) + x.motion(&col(&b.dvelocity.0))),
                );
        dq.set_column(k, &c);
        let c = col(&a.dacceleration.1) - x.motion(&col(&b.dacceleration.1))
            + cross_motion(&col(&a.dvelocity.1), &moved_vb)
            + cross_motion(&a.velocity, &x.motion(&col(&b.dvelocity.1)));
        dv.set_column(k, &c);
    }
    (dq, dv)
}

/// A six-dimensional contact's `(∂c/∂q, ∂c/∂v)` (module docs) from the classical
/// acceleration's derivatives and the LOCAL velocity's.
fn six_d_rows<const NV: usize, const NF: usize>(
    frames: &Frames<NV, NF>,
    i: usize,
    da_dq: &SMatrix<f64, 6, NV>,
    da_dv: &SMatrix<f64, 6, NV>,
    velocity: &(SMatrix<f64, 6, NV>, SMatrix<f64, 6, NV>),
) -> (SMatrix<f64, 6, NV>, SMatrix<f64, 6, NV>) {
    let w = frames.placements[i].rotation;
    let local = &frames.jacobians[i];
    let vel = &frames.velocities[i];
    let omega = w * vel.fixed_rows::<3>(0);
    let pdot = w * vel.fixed_rows::<3>(3);
    let (dvel_dq, dvel_dv) = velocity;
    let mut dq = SMatrix::<f64, 6, NV>::zeros();
    let mut dv = SMatrix::<f64, 6, NV>::zeros();
    for k in 0..NV {
        // ω_k: the angular column of the LOCAL_WORLD_ALIGNED Jacobian.
        let omega_k = w * local.fixed_view::<3, 1>(0, k);
        let turn = |u: &Vector3<f64>, du: Vector3<f64>| omega_k.cross(u) + w * du;
        let d_omega = turn(&omega, dvel_dq.fixed_view::<3, 1>(0, k).into());
        let d_pdot = turn(&pdot, dvel_dq.fixed_view::<3, 1>(3, k).into());
        let mut c = SVector::<f64, 6>::from(da_dq.column(k));
        let lin = c.fixed_rows::<3>(3) - d_omega.cross(&pdot) - omega.cross(&d_pdot);
        c.fixed_rows_mut::<3>(3).copy_from(&lin);
        dq.set_column(k, &to_local(&w, &c));
        // ∂/∂v: ∂ω/∂v and ∂ṗ/∂v are the LOCAL_WORLD_ALIGNED Jacobian's columns.
        let a = w * dvel_dv.fixed_view::<3, 1>(0, k);
        let l = w * dvel_dv.fixed_view::<3, 1>(3, k);
        let mut c = SVector::<f64, 6>::from(da_dv.column(k));
        let lin = c.fixed_rows::<3>(3) - a.cross(&pdot) - omega.cross(&l);
        c.fixed_rows_mut::<3>(3).copy_from(&lin);
        dv.set_column(k, &to_local(&w, &c));
    }
    (dq, dv)
}

/// `[Wᵀ·a; Wᵀ·l]`.
fn to_local(w: &nalgebra::Matrix3<f64>, c: &SVector<f64, 6>) -> SVector<f64, 6> {
    let a = w.tr_mul(&c.fixed_rows::<3>(0));
    let l = w.tr_mul(&c.fixed_rows::<3>(3));
    SVector::<f64, 6>::new(a[0], a[1], a[2], l[0], l[1], l[2])
}

/// The parts of a composed `constrained_forward_dynamics_derivatives` put together (`f64`):
/// from the solution `(q̈, f)` and its residual, `M⁻¹`, the residuals' derivatives `∂r/∂x =
/// (∂ID/∂x, 0) + ∂c/∂x` (`x = q, v`; inverse dynamics' `id`, `NV × NV`; the constraints' `c`,
/// `N × NV`, `N = NV + R`; visited where `dq`, `dv` list their rows) and the rows `J`
/// (`R × NV`), all in the rows' axes:
///
/// - `G = J·M⁻¹·Jᵀ = L·Lᵀ`, each pivot held above `tolerance` of its unreduced value (the
///   check of the generated solve; at the first that is not, [`ConstraintError::Redundant`]
///   with the constraint and its row that `owners` lists for that row of `G`), and `G⁻¹`;
/// - the solve's linear map `N = [P Yᵀ; −Y G⁻¹]` (`[M −Jᵀ; J 0]⁻¹` with its last `R`
///   columns negated), `Y = G⁻¹·J·M⁻¹`, `P = M⁻¹ − M⁻¹·Jᵀ·Y`: `∂q̈/∂τ = P`, `∂f/∂τ = −Y`;
/// - `(∂q̈, ∂f) = −N·∂r` for `q` and `v`;
/// - [`ConstraintError::NonFinite`] where a value is not finite.
///
/// Every product column by column into a local array (vector registers), as
/// `articulated::__private::minus_product`; `M⁻¹` is symmetric, so `M⁻¹·Jᵀ` accumulates `M⁻¹`'s
/// columns. The result is the caller's to return as it is: a `Derivatives` of the humanoid is
/// 43 KB, and each move of it through a `?` or a `map_err` was a copy.
#[doc(hidden)]
#[allow(clippy::too_many_arguments)]
pub fn composed<const NV: usize, const R: usize, const N: usize>(
    solution: Solution<NV, R>,
    minv: &SMatrix<f64, NV, NV>,
    id: (&SMatrix<f64, NV, NV>, &SMatrix<f64, NV, NV>),
    dc: (&SMatrix<f64, N, NV>, &SMatrix<f64, N, NV>),
    rows: (&[&[u16]; NV], &[&[u16]; NV]),
    j: &SMatrix<f64, R, NV>,
    tolerance: f64,
    owners: &[(usize, usize); R],
) -> Result<Derivatives<NV, R>, ConstraintError> {
    // One `Result`, filled where it lies and returned on every path: the compiler then builds
    // it in the caller's place (a second local returned on another path, or an `Ok(out)` of a
    // local, was a copy of all of it).
    let mut result = Ok(Derivatives {
        solution,
        dqdd_dq: SMatrix::zeros(),
        dqdd_dv: SMatrix::zeros(),
        dqdd_dtau: SMatrix::zeros(),
        dforces_dq: SMatrix::zeros(),
        dforces_dv: SMatrix::zeros(),
        dforces_dtau: SMatrix::zeros(),
    });
    if let Ok(out) = &mut result {
        if let Err(e) = fill(out, minv, id, dc, rows, j, tolerance, owners) {
            result = Err(e);
        }
    }
    result
}

/// [`composed`]'s products, into `out` (its solution set).
#[allow(clippy::too_many_arguments)]
fn fill<const NV: usize, const R: usize, const N: usize>(
    out: &mut Derivatives<NV, R>,
    minv: &SMatrix<f64, NV, NV>,
    id: (&SMatrix<f64, NV, NV>, &SMatrix<f64, NV, NV>),
    (dc_dq, dc_dv): (&SMatrix<f64, N, NV>, &SMatrix<f64, N, NV>),
    (dq, dv): (&[&[u16]; NV], &[&[u16]; NV]),
    j: &SMatrix<f64, R, NV>,
    tolerance: f64,
    owners: &[(usize, usize); R],
) -> Result<(), ConstraintError> {
    const { assert!(N == NV + R, "N is NV + R") };
    let fma = crate::math::mul_add;
    let minv_columns = &minv.data.0;
    // `Wᵀ = M⁻¹·Jᵀ`, `NV × R`, by column.
    let mut wt = [[0.0; NV]; R];
    for (r, column) in wt.iter_mut().enumerate() {
        let mut acc = [0.0; NV];
        for (k, m) in minv_columns.iter().enumerate() {
            let x = j[(r, k)];
            if x != 0.0 {
                for (acc, &m) in acc.iter_mut().zip(m) {
                    *acc = fma(x, m, *acc);
                }
            }
        }
        *column = acc;
    }
    // `G = J·Wᵀ`, then `G = L·Lᵀ` and `G⁻¹`.
    let mut g = SMatrix::<f64, R, R>::zeros();
    for (column, w) in g.data.0.iter_mut().zip(&wt) {
        let mut acc = [0.0; R];
        for (jc, &x) in j.data.0.iter().zip(w) {
            for (acc, &j) in acc.iter_mut().zip(jc) {
                *acc = fma(x, j, *acc);
            }
        }
        *column = acc;
    }
    let l = super::cholesky(&g, R, tolerance).map_err(|k| {
        let (contact, row) = owners.get(k).copied().unwrap_or((k, 0));
        ConstraintError::Redundant { contact, row }
    })?;
    let mut ginv = SMatrix::<f64, R, R>::identity();
    for mut column in ginv.column_iter_mut() {
        let mut x: SVector<f64, R> = column.clone_owned();
        super::forward(&l, &mut x, R);
        super::backward(&l, &mut x, R);
        column.copy_from(&x);
    }
    // `Yᵀ = Wᵀ·G⁻¹`, `NV × R`, by column.
    let mut yt = [[0.0; NV]; R];
    for (column, gc) in yt.iter_mut().zip(&ginv.data.0) {
        let mut acc = [0.0; NV];
        for (w, &x) in wt.iter().zip(gc) {
            for (acc, &w) in acc.iter_mut().zip(w) {
                *acc = fma(x, w, *acc);
            }
        }
        *column = acc;
    }
    // `N`, by column: `[P; −Y]` (`P = M⁻¹ − Wᵀ·Y`), then `[Yᵀ; G⁻¹]`.
    let mut map = [[0.0; N]; N];
    for (c, (column, m)) in map.iter_mut().zip(minv_columns).enumerate() {
        // `−Y`'s column `c`.
        let mut minus_y = [0.0; R];
        for (out, y) in minus_y.iter_mut().zip(&yt) {
            *out = -y.get(c).copied().unwrap_or(0.0);
        }
        let mut acc = *m;
        for (w, &x) in wt.iter().zip(&minus_y) {
            for (acc, &w) in acc.iter_mut().zip(w) {
                *acc = fma(x, w, *acc);
            }
        }
        stack(column, &acc, &minus_y);
    }
    for (column, (y, gc)) in map.iter_mut().skip(NV).zip(yt.iter().zip(&ginv.data.0)) {
        stack(column, y, gc);
    }
    for (c, column) in map.iter().take(NV).enumerate() {
        split(column, &mut out.dqdd_dtau, &mut out.dforces_dtau, c);
    }
    // `−N·∂r`, column by column, over the entries of `∂r` that can be non-zero.
    for (id, d, rows, (top, bottom)) in [
        (id.0, dc_dq, dq, (&mut out.dqdd_dq, &mut out.dforces_dq)),
        (id.1, dc_dv, dv, (&mut out.dqdd_dv, &mut out.dforces_dv)),
    ] {
        for (c, ((rows, d), id)) in rows.iter().zip(&d.data.0).zip(&id.data.0).enumerate() {
            let mut acc = [0.0; N];
            for &k in *rows {
                let k = usize::from(k);
                // The generator lists rows below `N` only.
                let (Some(&x), Some(column)) = (d.get(k), map.get(k)) else {
                    continue;
                };
                let x = x + id.get(k).copied().unwrap_or(0.0);
                for (acc, &a) in acc.iter_mut().zip(column) {
                    *acc = fma(-x, a, *acc);
                }
            }
            split(&acc, top, bottom, c);
        }
    }
    if !out.all_finite() {
        return Err(ConstraintError::NonFinite);
    }
    Ok(())
}

/// Column `c` of `top` (the first `NV` values of `column`) and of `bottom` (the rest).
#[inline(always)]
fn split<const NV: usize, const R: usize, const N: usize>(
    column: &[f64; N],
    top: &mut SMatrix<f64, NV, NV>,
    bottom: &mut SMatrix<f64, R, NV>,
    c: usize,
) {
    if let (Some(t), Some(b)) = (top.data.0.get_mut(c), bottom.data.0.get_mut(c)) {
        for (out, &x) in t.iter_mut().zip(column) {
            *out = x;
        }
        for (out, &x) in b.iter_mut().zip(column.iter().skip(NV)) {
            *out = x;
        }
    }
}

/// `column = [top; bottom]`.
#[inline(always)]
fn stack<const NV: usize, const R: usize, const N: usize>(
    column: &mut [f64; N],
    top: &[f64; NV],
    bottom: &[f64; R],
) {
    for (out, &x) in column.iter_mut().zip(top) {
        *out = x;
    }
    for (out, &x) in column.iter_mut().skip(NV).zip(bottom) {
        *out = x;
    }
}

#[cfg(test)]
#[allow(clippy::indexing_slicing)]
mod tests {
    use super::*;

    /// Two unit masses, one row holding the first (`J = [1 0]`, `M = 1`): `∂q̈/∂τ` is the
    /// projection on the free coordinate, `diag(0, 1)`, and `∂f/∂τ = −G⁻¹·J·M⁻¹ = [−1 0]`;
    /// with `∂r = 0` the other derivatives vanish.
    fn parts(j: [f64; 2], id_entry: f64) -> Result<Derivatives<2, 1>, ConstraintError> {
        let solution = Solution {
            acceleration: SVector::<f64, 2>::zeros(),
            forces: SVector::<f64, 1>::zeros(),
            rows: 1,
            residual: 0.0,
            iterations: 1,
        };
        let minv = SMatrix::<f64, 2, 2>::identity();
        let mut id = SMatrix::<f64, 2, 2>::zeros();
        id[(1, 1)] = id_entry;
        let dc = SMatrix::<f64, 3, 2>::zeros();
        let all: &[u16] = &[0, 1, 2];
        let rows = [all, all];
        let j = SMatrix::<f64, 1, 2>::new(j[0], j[1]);
        composed::<2, 1, 3>(
            solution,
            &minv,
            (&id, &id),
            (&dc, &dc),
            (&rows, &rows),
            &j,
            1e-10,
            &[(4, 2)],
        )
    }

    #[test]
    fn composed_projects_on_the_free_coordinate() {
        let d = parts([1.0, 0.0], 0.0).unwrap();
        assert_eq!(d.dqdd_dtau, SMatrix::<f64, 2, 2>::new(0.0, 0.0, 0.0, 1.0));
        assert_eq!(d.dforces_dtau, SMatrix::<f64, 1, 2>::new(-1.0, 0.0));
        assert_eq!(d.dqdd_dq, SMatrix::<f64, 2, 2>::zeros());
    }

    /// A row of zeros is redundant: the error names the constraint and row that `owners` gives.
    #[test]
    fn composed_names_a_redundant_row_by_its_owner() {
        assert_eq!(
            parts([0.0, 0.0], 0.0).unwrap_err(),
            ConstraintError::Redundant { contact: 4, row: 2 }
        );
    }

    /// A derivative that is not finite is an error, not a value.
    #[test]
    fn composed_refuses_a_derivative_that_is_not_finite() {
        assert_eq!(
            parts([1.0, 0.0], f64::NAN).unwrap_err(),
            ConstraintError::NonFinite
        );
    }
}
