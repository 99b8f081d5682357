//! Inverse kinematics: a configuration that puts a chain's frames where they should be, by
//! Levenberg–Marquardt (damped least squares) on the frames' errors, allocation-free.
//!
//! # The problem
//! A chain generated with named frames (`frames: [tool]`, [`FramePlacements`]) gives each frame
//! `k` a [`Task`]: a [`Goal`] and a weight `w_k ≥ 0`.
//! - [`Goal::Pose`], a placement `M_t`: the error is `e = log6(M(q)⁻¹·M_t)` ([`log6`]), the
//!   twist `[ω; v]` in LOCAL (the frame's origin and axes, angular first) that moves the frame
//!   onto its target in unit time (6 rows).
//! - [`Goal::Position`], a point `p_t` of the world: `e = p_t − p(q)`, world axes (3 rows),
//!   whatever the frame's orientation.
//! - [`Goal::Free`], or a zero weight: nothing (the frame is generated for another use).
//!
//! The solver minimizes `f(q) = ½·Σ w_k·|e_k(q)|²` from a start `q0` and stops converged when
//! every frame with a goal is within [`Options::position_tolerance`] of its target point (the
//! distance between the origins, m) and, for a pose, within [`Options::rotation_tolerance`] of
//! its orientation (the angle of `R(q)ᵀ·R_t`, rad).
//!
//! # The step
//! Steps `δ` are velocity-sized and move `q` on its manifold, `q ⊕ δ`
//! ([`configuration::integrate_in_place`]: quaternion joints by the exponential map, kept unit),
//! so the Jacobians are the generated ones, with respect to `v`. Along a step the errors are
//! linearized, `e_k(q ⊕ δ) ≈ e_k − A_k·δ`:
//! - pose: `A = Jlog6(M_t⁻¹·M)·J_local`. Moving `q` by `δ` moves the frame to
//!   `M·exp(J_local·δ)`, and `log6(exp(−ξ)·X) = −log6(X⁻¹·exp(ξ)) ≈ log6(X) − Jlog6(X⁻¹)·ξ`
//!   with `X = M⁻¹·M_t`. [`jlog6`] is the exact inverse right Jacobian of SE(3) (not its
//!   approximation by the identity, which is only good near the target): the model stays
//!   faithful for large rotations, and Levenberg–Marquardt's gain ratio with it;
//! - position: `A = J_lin`, the LOCAL_WORLD_ALIGNED Jacobian's linear rows.
//!
//! `J_local = diag(Rᵀ, Rᵀ)·J_lwa`, so one generated output,
//! `frame_jacobians_local_world_aligned`, serves both goals (and operational-space control,
//! [`crate::control::operational_space`]). Each iteration solves the damped normal equations
//!
//! ```text
//! (Σ w_k·A_kᵀ·A_k + λ·I)·δ = Σ w_k·A_kᵀ·e_k
//! ```
//!
//! (`NV × NV`, Cholesky on the stack: the stacked system, at most `6·NF × NV`, is never
//! formed), scales the step down if a coordinate would move by more than
//! [`Options::max_step`] (a trust region: far from the goal the linearization is poor), and
//! accepts it when it lowers `f`.
//!
//! # Damping
//! Nielsen's rule (Madsen, Nielsen & Tingleff 2004, *Methods for non-linear least squares
//! problems*, 2nd ed., IMM DTU, §3.2, eq. 3.16 and Algorithm 3.16): `λ₀ = τ·max diag(AᵀWA)`
//! (`τ` = [`Options::initial_damping`]); after a step with gain ratio
//! `ρ = (f(q) − f(q ⊕ δ)) / (δᵀ·g − ½·δᵀ·AᵀWA·δ) > 0` (actual over predicted decrease) it is
//! accepted and `λ ← λ·max(⅓, 1 − (2ρ − 1)³)`, `ν ← 2`; otherwise it is rejected and
//! `λ ← λ·ν`, `ν ← 2ν`. `λ` is kept above [`Options::min_damping`]`·max diag(AᵀWA)`, so that a
//! redundant chain (more coordinates than task rows: `AᵀWA` singular) still gets a well-posed
//! step, the smallest that does the job. The defaults (`τ = 0.1`, steps of at most 0.5 rad)
//! were chosen on arm7 from its neutral configuration, straight up and singular: on 1,000
//! random poses of its flange, the larger starting damping reaches more of them than Nielsen's
//! suggested `τ = 10⁻³`, and the step bound more again (`tests/ik.rs` prints the rate with
//! `--nocapture` and holds it above 95 %).
//!
//! # Joint limits
//! Each coordinate of a revolute, prismatic or other vector joint stays within its drive's
//! `[lower, upper]` ([`Chain::DRIVES`](crate::Chain::DRIVES); quaternion joints have none) by
//! projecting each step, not the configuration after it: a coordinate the step would carry
//! past a limit is held at that limit and the normal equations are solved again for the
//! others (an active set, at most `NV` solves a step). So the configuration never leaves its
//! box, a coordinate stopped at a limit does not hold up the others, and the gain ratio is that
//! of the step actually taken. A start outside the limits is first clamped into them.
//!
//! # Stops
//! `Ok(`[`Solution`]`)` when converged, with the iterations (each solve of the normal
//! equations counts as one, accepted or not) and the [`Residual`]. Otherwise an [`IkError`]
//! with the reason ([`Stop`]), the best configuration found (the one of least `f`: the last
//! accepted), its residual and the iterations spent: [`Stop::MaxIterations`]; [`Stop::Stalled`]
//! (the gradient `Σ w_k·A_kᵀ·e_k`, the step, or the decrease any step within
//! [`Options::max_damping`] can give fell below its tolerance: a least-squares minimum that
//! misses the tolerances, from a target out of reach, tasks that conflict, a limit in the way
//! or a local minimum); [`Stop::Singular`] (no coordinate moves a frame with a goal, or the
//! damped equations could not be factored); [`Stop::NonFinite`]; or an input refused before
//! any step ([`Stop::Size`], [`Stop::Drives`], [`Stop::Task`]).
//!
//! ```
//! use articulated::ik::{self, Options, Task};
//! use articulated::nalgebra::{SVector, Vector3};
//! use articulated::prelude::*;
//!
//! articulated::chain! {
//!     chain Planar {
//!         outputs: [frame_placements, frame_jacobians_local_world_aligned];
//!         frames: [tip];
//!         body upper { mass: 1.0, com: [0.5, 0.0, 0.0], inertia: diag(0.01, 0.1, 0.1) }
//!         body lower { mass: 1.0, com: [0.5, 0.0, 0.0], inertia: diag(0.01, 0.1, 0.1) }
//!         joint shoulder: revolute(z) { parent: world, child: upper }
//!         joint elbow: revolute(z) {
//!             parent: upper, child: lower, xyz: [1.0, 0.0, 0.0], lower: 0.0, upper: 3.0
//!         }
//!         frame tip { parent: lower, xyz: [1.0, 0.0, 0.0] }
//!     }
//! }
//! // Reach (1, 1, 0): with the elbow bent the positive way, shoulder 0 and elbow π/2.
//! let tasks = [Task::position(Vector3::new(1.0, 1.0, 0.0))];
//! let start = SVector::from([0.3, 0.5]);
//! let solution = ik::solve::<Planar, 2, 2, 1>(&tasks, &start, &Options::default())?;
//! assert!(solution.residual.position < 1e-6);
//! let elbow = solution.q[1] - core::f64::consts::FRAC_PI_2;
//! assert!(solution.q[0].abs() < 1e-5 && elbow.abs() < 1e-5);
//!
//! // Out of reach (the arm is 2 m long): an error, with the best configuration and its residual.
//! let far = [Task::position(Vector3::new(3.0, 0.0, 0.0))];
//! let e = ik::solve::<Planar, 2, 2, 1>(&far, &start, &Options::default()).unwrap_err();
//! assert!((e.residual.position - 1.0).abs() < 1e-6); // stretched towards the target
//! # Ok::<(), ik::IkError<2>>(())
//! ```

use core::fmt;

use nalgebra::{
    Cholesky, Matrix3, Quaternion, Rotation3, SMatrix, SVector, UnitQuaternion, Vector3,
};

use crate::configuration::{self, dexp_inv, quat_exp, quat_log, SizeMismatch};
use crate::{Coordinates, Drive, FrameJacobiansLocalWorldAligned, FramePlacement, FramePlacements};

/// A twist or an error `[ω; v]`, angular first.
pub type Vec6 = SVector<f64, 6>;

// ---- SE(3): exponential, logarithm and the logarithm's Jacobian ----

/// `log3(R)`: the rotation vector `θ·u` (angle `θ ∈ [0, π]`, unit axis `u`) with
/// `R = exp([θ·u]×)`. Through the quaternion of `R` (Shepperd's method, nalgebra's
/// `UnitQuaternion::from_rotation_matrix`), so that it stays accurate near `θ = π`, where the
/// antisymmetric part of `R` vanishes. `r` should be a rotation.
pub fn log3(r: &Matrix3<f64>) -> Vector3<f64> {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r));
    let q = [q.w, q.i, q.j, q.k];
    // The shorter of the two rotations (w ≥ 0): angle in [0, π].
    let q = if q[0] < 0.0 { q.map(|x| -x) } else { q };
    Vector3::from(quat_log(q))
}

/// `exp3(ω)`: the rotation by the angle `|ω|` about `ω`.
pub fn exp3(omega: &Vector3<f64>) -> Matrix3<f64> {
    let [w, x, y, z] = quat_exp([omega.x, omega.y, omega.z]);
    UnitQuaternion::new_unchecked(Quaternion::new(w, x, y, z))
        .to_rotation_matrix()
        .into_inner()
}

/// `[x]×`, the matrix of `y ↦ x × y`.
fn skew(x: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -x.z, x.y, x.z, 0.0, -x.x, -x.y, x.x, 0.0)
}

/// `log6(M)`: the twist `ξ = [ω; v]` (angular first) with `M = exp6(ξ)`: `ω = log3(R)` and
/// `v = V(ω)⁻¹·p`, `V(ω)⁻¹ = I − ½·[ω]× + β(θ)·[ω]×²`, `β = (1 − (θ/2)·cot(θ/2))/θ²`
/// (Murray, Li & Sastry 1994, *A Mathematical Introduction to Robotic Manipulation*, §2.4.1;
/// `V(ω)⁻¹·p` is [`dexp_inv`]`(−ω, p)`). For `M = M_a⁻¹·M_b` it is the constant twist, in
/// `M_a`'s frame, that carries `M_a` onto `M_b` in unit time: `M_b = M_a·exp6(ξ)`.
pub fn log6(m: &FramePlacement<f64>) -> Vec6 {
    let w = log3(&m.rotation);
    let p = m.translation;
    let v = dexp_inv([-w.x, -w.y, -w.z], [p.x, p.y, p.z]);
    Vec6::new(w.x, w.y, w.z, v[0], v[1], v[2])
}

/// `exp6(ξ)` for `ξ = [ω; v]`: `R = exp3(ω)`, `p = V(ω)·v` with
/// `V = I + ((1 − cos θ)/θ²)·[ω]× + ((θ − sin θ)/θ³)·[ω]×²` (Taylor series below θ = 0.05).
/// The inverse of [`log6`] for rotations of angle below π.
pub fn exp6(xi: &Vec6) -> FramePlacement<f64> {
    let w = Vector3::new(xi[0], xi[1], xi[2]);
    let v = Vector3::new(xi[3], xi[4], xi[5]);
    let t2 = w.norm_squared();
    let (a, b) = if t2 < 0.0025 {
        (
            0.5 - t2 / 24.0 + t2 * t2 / 720.0,
            1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0,
        )
    } else {
        let t = libm::sqrt(t2);
        ((1.0 - libm::cos(t)) / t2, (t - libm::sin(t)) / (t2 * t))
    };
    let wv = w.cross(&v);
    FramePlacement {
        rotation: exp3(&w),
        translation: v + wv * a + w.cross(&wv) * b,
    }
}

/// `Jlog3(ω) = J_r(ω)⁻¹ = (θ/2)·cot(θ/2)·I + ½·[ω]× + β(θ)·ω·ωᵀ`, the inverse right Jacobian of
/// SO(3): `log3(R·exp3(ε)) = ω + Jlog3(ω)·ε + O(ε²)` for `ω = log3(R)`. Column by column from
/// [`dexp_inv`], which is the same map.
fn jlog3(w: &Vector3<f64>) -> Matrix3<f64> {
    let w = [w.x, w.y, w.z];
    let column = |e: [f64; 3]| Vector3::from(dexp_inv(w, e));
    Matrix3::from_columns(&[
        column([1.0, 0.0, 0.0]),
        column([0.0, 1.0, 0.0]),
        column([0.0, 0.0, 1.0]),
    ])
}

/// `Jlog6(M)`, the inverse right Jacobian of SE(3) at `log6(M)`, angular first:
/// `log6(M·exp6(ε)) = log6(M) + Jlog6(M)·ε + O(ε²)`.
///
/// ```text
/// Jlog6 = [ Jlog3(ω)    0        ]      B = C·Jlog3(ω),
///         [ B           Jlog3(ω) ]      C = ((β'/θ)·(ωᵀp)·ω − (θ²·β'/θ + 2β)·p)·ωᵀ
///                                           + β·ω·pᵀ + β·(ωᵀp)·I + ½·[p]×
/// ```
///
/// with `ω = log3(R)`, `θ = |ω|`, `p` the translation of `M`, `β(θ) = 1/θ² − sin θ/(2θ(1 − cos θ))`
/// and its derivative over `θ`, `β'/θ = −2/θ⁴ + (1 + sin θ/θ)/(2θ²(1 − cos θ))` (their Taylor
/// series `1/12 + θ²/720 + θ⁴/30240` and `1/360 + θ²/7560 + θ⁴/201600` below θ = 0.1). The
/// closed form of Pinocchio's `Jlog6` (`spatial/log.hxx`), with the blocks moved to the
/// angular-first order; `tests/ik.rs` checks it against central differences of [`log6`].
pub fn jlog6(m: &FramePlacement<f64>) -> SMatrix<f64, 6, 6> {
    let w = log3(&m.rotation);
    let p = m.translation;
    let a = jlog3(&w);
    let t2 = w.norm_squared();
    let (beta, beta_dot_over_theta) = if t2 < 0.01 {
        (
            1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 / 30240.0),
            1.0 / 360.0 + t2 * (1.0 / 7560.0 + t2 / 201_600.0),
        )
    } else {
        let t = libm::sqrt(t2);
        let (s, c) = (libm::sin(t), libm::cos(t));
        let inv_2_2c = 1.0 / (2.0 * (1.0 - c));
        (
            1.0 / t2 - s / t * inv_2_2c,
            -2.0 / (t2 * t2) + (1.0 + s / t) / t2 * inv_2_2c,
        )
    };
    let wtp = w.dot(&p);
    let tmp = w * (beta_dot_over_theta * wtp) - p * (t2 * beta_dot_over_theta + 2.0 * beta);
    let c = tmp * w.transpose()
        + w * p.transpose() * beta
        + Matrix3::identity() * (wtp * beta)
        + skew(&(p * 0.5));
    let b = c * a;
    let mut j = SMatrix::<f64, 6, 6>::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(&a);
    j.fixed_view_mut::<3, 3>(3, 0).copy_from(&b);
    j.fixed_view_mut::<3, 3>(3, 3).copy_from(&a);
    j
}

/// `M_a⁻¹·M_b`: `M_b` seen from `M_a`'s frame.
pub fn between(a: &FramePlacement<f64>, b: &FramePlacement<f64>) -> FramePlacement<f64> {
    let rt = a.rotation.transpose();
    FramePlacement {
        rotation: rt * b.rotation,
        translation: rt * (b.translation - a.translation),
    }
}

// ---- Tasks, options, results ----

/// What one frame should reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Goal {
    /// Its placement: rotation `world_R_frame` (a rotation matrix) and origin, both in the
    /// world, as [`FramePlacements`] returns them.
    Pose(FramePlacement<f64>),
    /// Its origin at this point of the world, whatever its orientation.
    Position(Vector3<f64>),
    /// Nothing.
    Free,
}

/// A frame's goal and its weight in the cost `½·Σ w_k·|e_k|²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Task {
    /// What the frame should reach.
    pub goal: Goal,
    /// Its weight `w ≥ 0` (finite); `0` asks nothing of the frame.
    pub weight: f64,
}

impl Task {
    /// No goal.
    pub const FREE: Task = Task {
        goal: Goal::Free,
        weight: 0.0,
    };

    /// The whole placement, weight 1.
    pub fn pose(target: FramePlacement<f64>) -> Self {
        Task {
            goal: Goal::Pose(target),
            weight: 1.0,
        }
    }

    /// The origin's position (world), weight 1.
    pub fn position(target: Vector3<f64>) -> Self {
        Task {
            goal: Goal::Position(target),
            weight: 1.0,
        }
    }

    /// The same task with this weight.
    pub fn weighted(self, weight: f64) -> Self {
        Task { weight, ..self }
    }

    /// Whether it asks anything: a goal and a positive weight.
    fn active(&self) -> bool {
        !matches!(self.goal, Goal::Free) && self.weight > 0.0
    }
}

/// The solver's tolerances, limits and damping (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// The most solves of the normal equations (accepted steps and rejected ones). Default 100.
    pub max_iterations: usize,
    /// Converged when each frame with a goal has its origin this close to its target (m).
    /// Default `1e-6`.
    pub position_tolerance: f64,
    /// ... and each frame with a pose goal its orientation this close (the angle of
    /// `R(q)ᵀ·R_t`, rad). Default `1e-5`.
    pub rotation_tolerance: f64,
    /// Nielsen's `τ`: the first damping is `τ·max diag(AᵀWA)`. Default `0.1`.
    pub initial_damping: f64,
    /// The damping is kept at or above this times `max diag(AᵀWA)`. Default `1e-12`.
    pub min_damping: f64,
    /// Stalled when rejected steps have raised the damping above this times
    /// `max diag(AᵀWA)`. Default `1e12`.
    pub max_damping: f64,
    /// Stalled when the largest entry of a step is at most this (rad or m). Default `1e-14`.
    pub step_tolerance: f64,
    /// The largest change of one coordinate in a step (rad or m): a longer step is scaled down
    /// to it, a trust region that keeps each step where the linearization holds. Default `0.5`.
    pub max_step: f64,
    /// Stalled when the largest entry of the gradient `Σ w_k·A_kᵀ·e_k` is at most this.
    /// Default `1e-14`.
    pub gradient_tolerance: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_iterations: 100,
            position_tolerance: 1e-6,
            rotation_tolerance: 1e-5,
            initial_damping: 0.1,
            min_damping: 1e-12,
            max_damping: 1e12,
            step_tolerance: 1e-14,
            max_step: 0.5,
            gradient_tolerance: 1e-14,
        }
    }
}

/// How far the frames are from their goals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Residual {
    /// The largest distance from a frame's origin to its target point (m), over the frames with
    /// a goal; 0 when none has one.
    pub position: f64,
    /// The largest angle from a frame's orientation to its target's (rad), over the frames with
    /// a pose goal; 0 when none has one.
    pub rotation: f64,
    /// The weighted cost `½·Σ w_k·|e_k|²` the solver minimizes.
    pub cost: f64,
}

impl Residual {
    /// Not evaluated: the input was refused before any evaluation.
    pub const UNKNOWN: Residual = Residual {
        position: f64::NAN,
        rotation: f64::NAN,
        cost: f64::NAN,
    };
}

/// A configuration that reaches every goal within the tolerances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solution<const NQ: usize> {
    /// The configuration (quaternions unit, coordinates within their limits).
    pub q: SVector<f64, NQ>,
    /// The solves of the normal equations it took (0: `q0` was already there).
    pub iterations: usize,
    /// Its distance to the goals.
    pub residual: Residual,
}

/// Why the solver stopped short of the tolerances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stop {
    /// The chain's coordinates do not describe `NQ` positions and `NV` velocities.
    Size(SizeMismatch),
    /// There are drives (limits) but not one per joint's coordinates.
    Drives {
        /// Drives given.
        drives: usize,
        /// Entries in the coordinates list.
        joints: usize,
    },
    /// A task's weight is negative or not finite, or its target is not finite.
    Task {
        /// The frame's index.
        frame: usize,
    },
    /// [`Options::max_iterations`] solves without reaching the tolerances.
    MaxIterations,
    /// The gradient, the step or the decrease fell below its tolerance away from the goals: a
    /// least-squares minimum that misses them (a target out of reach, tasks that conflict, a
    /// joint limit in the way, or a local minimum).
    Stalled,
    /// No coordinate moves a frame that has a goal (the tasks' Jacobian is zero), or the damped
    /// normal equations could not be factored.
    Singular,
    /// `q0` holds a value that is not finite, or the kinematics gave one (from the chain's
    /// parameters, or a start far out on a free joint).
    NonFinite,
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stop::Size(e) => write!(f, "{e}"),
            Stop::Drives { drives, joints } => write!(
                f,
                "{drives} drives for {joints} joints (give one per entry of the coordinates, \
                 or none)"
            ),
            Stop::Task { frame } => write!(
                f,
                "the task of frame {frame} has a negative or non-finite weight, or a non-finite \
                 target"
            ),
            Stop::MaxIterations => write!(f, "not converged within the iterations allowed"),
            Stop::Stalled => write!(
                f,
                "stalled at a least-squares minimum that misses the tolerances (a target out of \
                 reach, conflicting tasks, a joint limit or a local minimum)"
            ),
            Stop::Singular => write!(
                f,
                "singular: no coordinate moves the frames that have goals, or the damped normal \
                 equations could not be factored"
            ),
            Stop::NonFinite => write!(f, "the start or the kinematics is not finite"),
        }
    }
}

/// The solver stopped without converging: why, the best configuration found (least cost, within
/// the limits), its residual and the iterations spent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkError<const NQ: usize> {
    /// Why it stopped.
    pub stop: Stop,
    /// The best configuration found (`q0`, normalized and clamped, if no step was taken).
    pub q: SVector<f64, NQ>,
    /// Its residual ([`Residual::UNKNOWN`] for an input refused before any evaluation).
    pub residual: Residual,
    /// The solves of the normal equations spent.
    pub iterations: usize,
}

impl<const NQ: usize> fmt::Display for IkError<NQ> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "inverse kinematics stopped after {} iterations: {}; best residual {:.3e} m, \
             {:.3e} rad",
            self.iterations, self.stop, self.residual.position, self.residual.rotation
        )
    }
}

impl<const NQ: usize> core::error::Error for IkError<NQ> {}

// ---- The solver ----

/// Inverse kinematics for a generated chain `C` (module docs): a configuration near `q0` that
/// puts each of `C::FRAMES` on its task, within the limits of `C::DRIVES`. Needs the outputs
/// `frame_placements` and `frame_jacobians_local_world_aligned`; uses the description's
/// parameters (for others, [`solve_with`]). Allocates nothing.
///
/// # Errors
/// [`IkError`]: why it stopped, the best configuration, its residual (module docs).
pub fn solve<C, const NQ: usize, const NV: usize, const NF: usize>(
    tasks: &[Task; NF],
    q0: &SVector<f64, NQ>,
    options: &Options,
) -> Result<Solution<NQ>, IkError<NQ>>
where
    C: FramePlacements<f64, NQ, NV, NF> + FrameJacobiansLocalWorldAligned<f64, NQ, NV, NF>,
{
    solve_with(
        <C as crate::Chain<f64>>::COORDINATES,
        <C as crate::Chain<f64>>::DRIVES,
        |q| C::frame_placements(q),
        |q| C::frame_jacobians_local_world_aligned(q),
        tasks,
        q0,
        options,
    )
}

/// [`solve`] on any kinematics: the joints' `coordinates`, their `drives` (one per entry of
/// `coordinates`, whose `lower` and `upper` bound each coordinate of a vector joint; empty for
/// no limits), the frames' `placements(q)` and their LOCAL_WORLD_ALIGNED Jacobians
/// `jacobians(q)` (`6 × NV`, angular rows first, with respect to `v`). For a generated chain
/// with parameters: `|q| C::frame_placements_with(q, &p)`. Allocates nothing.
///
/// # Errors
/// [`IkError`]: why it stopped, the best configuration, its residual (module docs).
pub fn solve_with<const NQ: usize, const NV: usize, const NF: usize, P, J>(
    coordinates: &[Coordinates],
    drives: &[Drive],
    mut placements: P,
    mut jacobians: J,
    tasks: &[Task; NF],
    q0: &SVector<f64, NQ>,
    options: &Options,
) -> Result<Solution<NQ>, IkError<NQ>>
where
    P: FnMut(&SVector<f64, NQ>) -> [FramePlacement<f64>; NF],
    J: FnMut(&SVector<f64, NQ>) -> [SMatrix<f64, 6, NV>; NF],
{
    let refuse = |stop| IkError {
        stop,
        q: *q0,
        residual: Residual::UNKNOWN,
        iterations: 0,
    };
    configuration::check(coordinates, NQ, NV).map_err(|e| refuse(Stop::Size(e)))?;
    if !drives.is_empty() && drives.len() != coordinates.len() {
        return Err(refuse(Stop::Drives {
            drives: drives.len(),
            joints: coordinates.len(),
        }));
    }
    if let Some(frame) = tasks.iter().position(|t| !valid(t)) {
        return Err(refuse(Stop::Task { frame }));
    }
    if !q0.iter().all(|x| x.is_finite()) {
        return Err(refuse(Stop::NonFinite));
    }
    let limits = Limits::<NV>::new(coordinates, drives);

    let mut q = *q0;
    configuration::normalize(coordinates, q.as_mut_slice());
    limits.clamp(&mut q);
    let mut iterations = 0;
    let mut placed = placements(&q);
    let mut now = Errors::at(tasks, &placed);
    let stop = |stop, q, residual, iterations| IkError {
        stop,
        q,
        residual,
        iterations,
    };
    if !now.residual.cost.is_finite() {
        return Err(stop(Stop::NonFinite, q, now.residual, 0));
    }
    if converged(&now.residual, options) {
        return Ok(Solution {
            q,
            iterations,
            residual: now.residual,
        });
    }
    let (mut h, mut g) = now.normal_equations(tasks, &placed, &jacobians(&q));
    let scale = |h: &SMatrix<f64, NV, NV>| h.diagonal().max();
    if scale(&h).is_nan() || scale(&h) <= 0.0 {
        let why = if scale(&h).is_finite() {
            Stop::Singular
        } else {
            Stop::NonFinite
        };
        return Err(stop(why, q, now.residual, 0));
    }
    let mut lambda = options.initial_damping * scale(&h);
    let mut nu = 2.0;
    loop {
        if converged(&now.residual, options) {
            return Ok(Solution {
                q,
                iterations,
                residual: now.residual,
            });
        }
        if g.amax() <= options.gradient_tolerance {
            return Err(stop(Stop::Stalled, q, now.residual, iterations));
        }
        if iterations >= options.max_iterations {
            return Err(stop(Stop::MaxIterations, q, now.residual, iterations));
        }
        iterations += 1;
        let Some(delta) = limits.step(&h, &g, lambda, &q, options.max_step) else {
            return Err(stop(Stop::Singular, q, now.residual, iterations));
        };
        if delta.amax() <= options.step_tolerance {
            return Err(stop(Stop::Stalled, q, now.residual, iterations));
        }
        let predicted = delta.dot(&g) - 0.5 * delta.dot(&(h * delta));
        let mut next = q;
        configuration::integrate_in_place(coordinates, next.as_mut_slice(), delta.as_slice());
        configuration::normalize(coordinates, next.as_mut_slice());
        // Rounding only: the step was cut at the limits.
        limits.clamp(&mut next);
        let there = placements(&next);
        let then = Errors::at(tasks, &there);
        let rho = (now.residual.cost - then.residual.cost) / predicted;
        if predicted > 0.0 && rho > 0.0 && then.residual.cost.is_finite() {
            (q, placed, now) = (next, there, then);
            (h, g) = now.normal_equations(tasks, &placed, &jacobians(&q));
            if !(h.iter().all(|x| x.is_finite()) && g.iter().all(|x| x.is_finite())) {
                return Err(stop(Stop::NonFinite, q, now.residual, iterations));
            }
            let r = 2.0 * rho - 1.0;
            let cube: f64 = r * r * r;
            lambda = (lambda * (1.0 - cube).max(1.0 / 3.0)).max(options.min_damping * scale(&h));
            nu = 2.0;
        } else {
            lambda *= nu;
            nu *= 2.0;
            if lambda.is_nan() || lambda > options.max_damping * scale(&h) {
                return Err(stop(Stop::Stalled, q, now.residual, iterations));
            }
        }
    }
}

/// Whether a task's weight and target are finite, the weight not negative.
fn valid(task: &Task) -> bool {
    let target = match &task.goal {
        Goal::Pose(m) => m
            .rotation
            .iter()
            .chain(m.translation.iter())
            .all(|x| x.is_finite()),
        Goal::Position(p) => p.iter().all(|x| x.is_finite()),
        Goal::Free => true,
    };
    target && task.weight.is_finite() && task.weight >= 0.0
}

/// Whether every frame is within the tolerances.
fn converged(r: &Residual, options: &Options) -> bool {
    r.position <= options.position_tolerance && r.rotation <= options.rotation_tolerance
}

/// Each frame's error `e_k` (`[ω; v]` for a pose; `[0; p_t − p]` for a position), and the
/// residual.
struct Errors<const NF: usize> {
    e: [Vec6; NF],
    residual: Residual,
}

impl<const NF: usize> Errors<NF> {
    fn at(tasks: &[Task; NF], placements: &[FramePlacement<f64>; NF]) -> Self {
        let mut e = [Vec6::zeros(); NF];
        let mut residual = Residual {
            position: 0.0,
            rotation: 0.0,
            cost: 0.0,
        };
        for ((task, m), e) in tasks.iter().zip(placements).zip(e.iter_mut()) {
            if !task.active() {
                continue;
            }
            let distance = match &task.goal {
                Goal::Pose(target) => {
                    let x = between(m, target);
                    *e = log6(&x);
                    let angle = e.fixed_rows::<3>(0).norm();
                    residual.rotation = residual.rotation.max(angle);
                    (target.translation - m.translation).norm()
                }
                Goal::Position(target) => {
                    e.fixed_rows_mut::<3>(3)
                        .copy_from(&(target - m.translation));
                    e.fixed_rows::<3>(3).norm()
                }
                Goal::Free => 0.0,
            };
            // `max` would drop a NaN: keep it, so that a non-finite state is seen.
            if distance.is_nan() || distance > residual.position {
                residual.position = distance;
            }
            residual.cost += 0.5 * task.weight * e.norm_squared();
        }
        Errors { e, residual }
    }

    /// `(Σ w_k·A_kᵀ·A_k, Σ w_k·A_kᵀ·e_k)` at the placements and LOCAL_WORLD_ALIGNED Jacobians
    /// the errors were taken at.
    fn normal_equations<const NV: usize>(
        &self,
        tasks: &[Task; NF],
        placements: &[FramePlacement<f64>; NF],
        jacobians: &[SMatrix<f64, 6, NV>; NF],
    ) -> (SMatrix<f64, NV, NV>, SVector<f64, NV>) {
        let mut h = SMatrix::<f64, NV, NV>::zeros();
        let mut g = SVector::<f64, NV>::zeros();
        for (((task, m), j), e) in tasks.iter().zip(placements).zip(jacobians).zip(&self.e) {
            if !task.active() {
                continue;
            }
            match &task.goal {
                Goal::Pose(target) => {
                    let rt = m.rotation.transpose();
                    let mut local = SMatrix::<f64, 6, NV>::zeros();
                    local
                        .fixed_rows_mut::<3>(0)
                        .copy_from(&(rt * j.fixed_rows::<3>(0)));
                    local
                        .fixed_rows_mut::<3>(3)
                        .copy_from(&(rt * j.fixed_rows::<3>(3)));
                    let a = jlog6(&between(target, m)) * local;
                    h += a.transpose() * a * task.weight;
                    g += a.transpose() * e * task.weight;
                }
                Goal::Position(_) => {
                    let a = j.fixed_rows::<3>(3);
                    h += a.transpose() * a * task.weight;
                    g += a.transpose() * e.fixed_rows::<3>(3) * task.weight;
                }
                Goal::Free => {}
            }
        }
        (h, g)
    }
}

/// Each velocity coordinate's bounds, and the position coordinate it moves (vector joints only:
/// for those `δ_i` adds to `q_at[i]`).
struct Limits<const NV: usize> {
    lower: [f64; NV],
    upper: [f64; NV],
    at: [Option<usize>; NV],
}

impl<const NV: usize> Limits<NV> {
    fn new(coordinates: &[Coordinates], drives: &[Drive]) -> Self {
        let mut limits = Limits {
            lower: [f64::NEG_INFINITY; NV],
            upper: [f64::INFINITY; NV],
            at: [None; NV],
        };
        for (k, (c, iq, iv)) in configuration::joints(coordinates).enumerate() {
            let (Coordinates::Vector(n), Some(d)) = (c, drives.get(k)) else {
                continue;
            };
            for i in 0..n {
                if let (Some(lo), Some(hi), Some(at)) = (
                    limits.lower.get_mut(iv + i),
                    limits.upper.get_mut(iv + i),
                    limits.at.get_mut(iv + i),
                ) {
                    // A NaN bound is none.
                    *lo = if d.lower.is_nan() {
                        f64::NEG_INFINITY
                    } else {
                        d.lower
                    };
                    *hi = if d.upper.is_nan() {
                        f64::INFINITY
                    } else {
                        d.upper
                    };
                    *at = Some(iq + i);
                }
            }
        }
        limits
    }

    /// The bounded coordinates of `q` moved into their bounds.
    fn clamp<const NQ: usize>(&self, q: &mut SVector<f64, NQ>) {
        for ((lo, hi), at) in self.lower.iter().zip(&self.upper).zip(&self.at) {
            if let Some(x) = at.and_then(|at| q.get_mut(at)) {
                *x = x.max(*lo).min(*hi);
            }
        }
    }

    /// The damped step from `q`, projected on the limits (module docs): each coordinate that
    /// would leave its range is held at its bound and the others solved again. `None` when
    /// the damped matrix cannot be factored.
    fn step<const NQ: usize>(
        &self,
        h: &SMatrix<f64, NV, NV>,
        g: &SVector<f64, NV>,
        lambda: f64,
        q: &SVector<f64, NQ>,
        max_step: f64,
    ) -> Option<SVector<f64, NV>> {
        // Nothing in `h`'s diagonal is negative: it is a sum of squares.
        let damped = h + SMatrix::<f64, NV, NV>::identity() * lambda;
        let mut held = [None::<f64>; NV];
        let mut delta = SVector::<f64, NV>::zeros();
        for _ in 0..=NV {
            let mut m = damped;
            let mut rhs = *g;
            // The held coordinates' contributions move to the right-hand side, and their rows
            // and columns become the identity: `δ_i = d_i`.
            for (i, d) in held.iter().enumerate() {
                if let Some(d) = d {
                    for (j, r) in rhs.iter_mut().enumerate() {
                        if held.get(j).is_some_and(|h| h.is_none()) {
                            *r -= m.get((j, i)).copied().unwrap_or(0.0) * d;
                        }
                    }
                }
            }
            for (i, d) in held.iter().enumerate() {
                if let Some(d) = d {
                    m.fill_row(i, 0.0);
                    m.fill_column(i, 0.0);
                    if let (Some(mii), Some(ri)) = (m.get_mut((i, i)), rhs.get_mut(i)) {
                        *mii = 1.0;
                        *ri = *d;
                    }
                }
            }
            delta = Cholesky::new(m)?.solve(&rhs);
            if delta.amax() > max_step {
                delta *= max_step / delta.amax();
            }
            let mut more = false;
            for (i, slot) in held.iter_mut().enumerate() {
                let (Some(lo), Some(hi), Some(Some(at)), Some(di)) = (
                    self.lower.get(i),
                    self.upper.get(i),
                    self.at.get(i),
                    delta.get(i),
                ) else {
                    continue;
                };
                let Some(x) = q.get(*at) else { continue };
                if slot.is_none() && (x + di > *hi || x + di < *lo) {
                    *slot = Some(if x + di > *hi { hi - x } else { lo - x });
                    more = true;
                }
            }
            if !more {
                break;
            }
        }
        delta.iter().all(|x| x.is_finite()).then_some(delta)
    }
}
