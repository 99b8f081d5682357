//! Constrained dynamics: contacts and loop closures on a chain's frames, the forces they carry,
//! and impacts (Wieber 2005 §3.3; Hemami, Dariush & Barin 2005 §2's ground reaction force).
//!
//! A constraint holds a frame of the chain ([`Contact`]):
//! - [`Kind::Point`], 3 rows: the frame origin's classical linear acceleration, world axes; its
//!   force is in world axes (Pinocchio's `CONTACT_3D` in `LOCAL_WORLD_ALIGNED`);
//! - [`Kind::SixD`], 6 rows: the frame's spatial acceleration in LOCAL (a flat foot, a welded
//!   tool); its wrench `[n; f]` is in the frame's axes, angular first (Pinocchio's `CONTACT_6D`
//!   in `LOCAL`, whose force comes linear first).
//!
//! The forces are what the constraints exert on the bodies. With the constraints' stacked
//! Jacobian `J` and drift `γ` (their acceleration at `q̈ = 0`), forward dynamics solves
//!
//! ```text
//! M·q̈ + nle = τ + Jᵀ·f,      J·q̈ + γ = −K_D·J·v − K_P·e      (the right side: Baumgarte)
//! ```
//!
//! with `e = p − p_ref` for a point and `log6(M_ref⁻¹·M)` for a six-dimensional constraint (the
//! reference taken when it became active), both Pinocchio's conventions. An impact
//! ([`impulse_dynamics`], Pinocchio's `impulseDynamics`: bilateral on every row) solves
//! `M·(v⁺ − v⁻) = Jᵀ·p` with `J·v⁺ = −e·J·v⁻`; it loses `½(1 − e²)·(J·v⁻)ᵀ·G⁻¹·(J·v⁻)` of
//! kinetic energy, `G = J·M⁻¹·Jᵀ`, and a negative normal impulse is returned as it is (a
//! unilateral contact would have let go: the caller decides).
//!
//! Both eliminate `q̈` through the Cholesky factor of `M`, `M = L·Lᵀ`: with `W = L⁻¹·Jᵀ`,
//! `G = Wᵀ·W` and `f = G⁻¹·(b − J·q̈₀)`, `q̈ = q̈₀ + L⁻ᵀ·W·f`, `q̈₀ = M⁻¹·(τ − nle)`.
//!
//! # Redundant constraints
//! Two flat feet and a hand on a table, three points of one body on a line: the rows of `J`
//! depend on each other, `G` is singular and the forces are not unique. With
//! [`Settings::mu`]` = 0` (the default) the factorization of `G` finds the first row that
//! depends on the rows before it and [`ConstraintError::Redundant`] names its constraint. With
//! `mu > 0` the forces come from proximal iterations (Pinocchio's `ProximalSettings`),
//! `(G + μ·I)·f_{k+1} = b − J·q̈₀ + μ·f_k` from `f_0 = 0`: for consistent constraints they
//! converge to the least-norm forces, the accelerations are exact, and [`Solution`] reports the
//! iterations and the residual; inconsistent constraints (whose rows cannot all hold) never
//! converge and give [`ConstraintError::NotConverged`] with the residual reached.
//!
//! Everything here is allocation-free: the rows stack into a [`System`] of capacity `R` (a
//! const parameter: 12 holds two flat feet), and [`System::push`] refuses more.
//!
//! ```
//! use articulated::constraint::{self, Contact, Kind, Settings, System};
//! use articulated::nalgebra::{SMatrix, SVector};
//!
//! // A point mass in the plane (x, z), held on the unit circle by a rod to the origin: at
//! // (1, 0) the rod pulls along −x. At rest under gravity (0, −9.81) it cannot fall through
//! // the rod's direction, and the rod carries no force.
//! let m = SMatrix::<f64, 2, 2>::identity();
//! let nle = SVector::<f64, 2>::new(0.0, 9.81);
//! let mut system = System::<2, 1>::new();
//! system.push(&SMatrix::<f64, 1, 2>::new(1.0, 0.0), &[0.0], &[0.0])?;
//! let s = constraint::forward_dynamics(
//!     &m, &nle, &SVector::zeros(), &SVector::zeros(), &system, None, &Settings::default(),
//! )?;
//! assert!((s.acceleration[1] + 9.81).abs() < 1e-12 && s.forces[0].abs() < 1e-12);
//! # Ok::<(), constraint::ConstraintError>(())
//! ```

use core::fmt;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector, SMatrix, SVector};

use crate::ik::{between, log6};
use crate::{
    FrameAccelerations, FrameJacobiansLocal, FramePlacement, FramePlacements, FrameVelocities,
    MassMatrixAndNonlinearEffects,
};

pub mod derivatives;
#[cfg(feature = "contact-qp")]
pub mod optimal;

/// The generated outputs the constraints' rows are made of (`frame_placements`,
/// `frame_jacobians_local`, `frame_velocities`, `frame_accelerations`), for all `NF` frames;
/// implemented by every chain that has them.
pub trait FrameOutputs<const NQ: usize, const NV: usize, const NF: usize>:
    FramePlacements<f64, NQ, NV, NF>
    + FrameJacobiansLocal<f64, NQ, NV, NF>
    + FrameVelocities<f64, NQ, NV, NF>
    + FrameAccelerations<f64, NQ, NV, NF>
{
}

impl<C, const NQ: usize, const NV: usize, const NF: usize> FrameOutputs<NQ, NV, NF> for C where
    C: FramePlacements<f64, NQ, NV, NF>
        + FrameJacobiansLocal<f64, NQ, NV, NF>
        + FrameVelocities<f64, NQ, NV, NF>
        + FrameAccelerations<f64, NQ, NV, NF>
{
}

/// What the constrained dynamics of a generated chain need: [`FrameOutputs`] and
/// `mass_matrix_and_nonlinear_effects`; implemented by every chain that has them.
pub trait ConstraintOutputs<const NQ: usize, const NV: usize, const NF: usize>:
    FrameOutputs<NQ, NV, NF> + MassMatrixAndNonlinearEffects<f64, NQ, NV>
{
}

impl<C, const NQ: usize, const NV: usize, const NF: usize> ConstraintOutputs<NQ, NV, NF> for C where
    C: FrameOutputs<NQ, NV, NF> + MassMatrixAndNonlinearEffects<f64, NQ, NV>
{
}

/// What a constraint holds (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// The frame's origin: 3 rows, force in world axes.
    Point,
    /// The whole frame: 6 rows, wrench `[n; f]` in the frame's axes.
    SixD,
}

impl Kind {
    /// Its number of rows.
    pub const fn rows(self) -> usize {
        match self {
            Kind::Point => 3,
            Kind::SixD => 6,
        }
    }

    /// Its name in descriptions and on the command line: `point`, `six_d`.
    pub const fn name(self) -> &'static str {
        match self {
            Kind::Point => "point",
            Kind::SixD => "six_d",
        }
    }
}

/// A constraint on the chain's frame `frame` (an index into `Chain::FRAMES`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Contact {
    /// The frame, by its index in `Chain::FRAMES`.
    pub frame: usize,
    /// What it holds.
    pub kind: Kind,
}

impl Contact {
    /// A point contact at frame `frame`'s origin.
    pub const fn point(frame: usize) -> Self {
        Contact {
            frame,
            kind: Kind::Point,
        }
    }

    /// A six-dimensional contact (or weld) of frame `frame`.
    pub const fn six_d(frame: usize) -> Self {
        Contact {
            frame,
            kind: Kind::SixD,
        }
    }
}

/// A loop closure between two frames of the chain: a four-bar linkage, a parallel robot, a rod
/// between two bodies ([`Kind::Point`]), a tool held rigidly in two hands ([`Kind::SixD`]). Its
/// force acts on `a`'s body and its opposite on `b`'s:
/// - [`Kind::Point`], 3 rows: frame `a`'s origin held on frame `b`'s; the rows are the
///   difference of the two origins' classical linear accelerations, world axes (Pinocchio's
///   two-joint `CONTACT_3D` in `LOCAL_WORLD_ALIGNED`); the force is in world axes, the position
///   error `p_a − p_b`. A planar loop has fewer independent rows than three: solve it with a
///   proximal [`Settings::mu`]` > 0`.
/// - [`Kind::SixD`], 6 rows: frame `a` held on frame `b`, their relative motion in `a`'s axes,
///   `v_a − ᵃX_b·v_b` (LOCAL velocities, `ᵃX_b` the motion transform from `b` to `a`), whose
///   rate at `q̈ = 0` is the drift `γ_a − ᵃX_b·γ_b + v_a × ᵃX_b·v_b` (Pinocchio's two-joint
///   `CONTACT_6D` in `LOCAL`); the wrench `[n; f]` is about `a`'s origin in its axes, the
///   position error `log6(M_b⁻¹·M_a)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Loop {
    /// The first frame, by its index in `Chain::FRAMES`.
    pub a: usize,
    /// The second frame.
    pub b: usize,
    /// What it holds.
    pub kind: Kind,
}

impl Loop {
    /// Frame `a`'s origin held on frame `b`'s.
    pub const fn point(a: usize, b: usize) -> Self {
        Loop {
            a,
            b,
            kind: Kind::Point,
        }
    }

    /// Frame `a` held on frame `b`.
    pub const fn six_d(a: usize, b: usize) -> Self {
        Loop {
            a,
            b,
            kind: Kind::SixD,
        }
    }
}

/// Baumgarte stabilization gains: `J·q̈ + γ = −kd·J·v − kp·e` (module docs), the same on every
/// row, as Pinocchio's `BaumgarteCorrectorParameters`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Baumgarte {
    /// The position gain `K_P` (1/s²).
    pub kp: f64,
    /// The velocity gain `K_D` (1/s).
    pub kd: f64,
}

/// How the forces are solved for (module docs, "Redundant constraints").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The proximal regularization `μ`: `0` solves `G` exactly and refuses redundant
    /// constraints; `μ > 0` iterates to the least-norm forces. Default `0`.
    pub mu: f64,
    /// The most proximal iterations (with `mu > 0`). Default `100`.
    pub max_iterations: usize,
    /// The proximal iterations stop when no force changes by more than this times the largest
    /// force (or `1`, whichever is larger). Default `1e-8`: each iterate carries the rounding
    /// of a solve with `G + μ·I`, about machine epsilon times its condition number
    /// (`λ_max(G)/μ`), and a tolerance below that may never be met.
    pub tolerance: f64,
    /// A pivot of `M`'s or `G`'s factorization counts as zero below this times its unreduced
    /// value. Default [`PIVOT_TOLERANCE`], `1e-10`.
    pub pivot_tolerance: f64,
}

/// [`Settings::pivot_tolerance`]'s default, which a generated `constrained_forward_dynamics`
/// holds its pivots to as well.
pub const PIVOT_TOLERANCE: f64 = 1e-10;

impl Default for Settings {
    fn default() -> Self {
        Settings {
            mu: 0.0,
            max_iterations: 100,
            tolerance: 1e-8,
            pivot_tolerance: PIVOT_TOLERANCE,
        }
    }
}

/// Why the constrained dynamics gave no solution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConstraintError {
    /// The constraints need more rows than the [`System`] holds.
    Capacity {
        /// The rows needed.
        needed: usize,
        /// The system's capacity `R`.
        capacity: usize,
    },
    /// A contact names a frame the chain does not generate.
    UnknownFrame {
        /// The index given.
        frame: usize,
        /// How many frames the chain generates (`NF`).
        frames: usize,
    },
    /// `M` is not positive definite: a pivot of its factorization vanished.
    MassMatrix {
        /// The velocity coordinate whose pivot vanished.
        velocity: usize,
    },
    /// Row `row` of constraint `contact` depends on the rows before it (`G` is singular):
    /// redundant constraints, which [`Settings::mu`]` > 0` solves.
    Redundant {
        /// The constraint, by its order in the system (the order of `push` or of the contacts).
        contact: usize,
        /// Its row (0-based; for a six-dimensional constraint, rows 0–2 angular).
        row: usize,
    },
    /// The proximal iterations did not converge: inconsistent constraints, or too few
    /// iterations.
    NotConverged {
        /// The iterations made.
        iterations: usize,
        /// `max |J·q̈ + γ − b|` at the last iterate.
        residual: f64,
    },
    /// An input (`M`, `nle`, `τ`, `v`, a row, a gain, the restitution) is not finite, or the
    /// restitution is negative.
    NonFinite,
}

impl fmt::Display for ConstraintError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ConstraintError::Capacity { needed, capacity } => write!(
                f,
                "the constraints need {needed} rows, but the system holds {capacity}"
            ),
            ConstraintError::UnknownFrame { frame, frames } => write!(
                f,
                "frame {frame} is not one of the chain's {frames} generated frames"
            ),
            ConstraintError::MassMatrix { velocity } => write!(
                f,
                "the mass matrix is not positive definite (velocity coordinate {velocity})"
            ),
            ConstraintError::Redundant { contact, row } => write!(
                f,
                "row {row} of constraint {contact} depends on the rows before it: the \
                 constraints are redundant (solve them with a proximal mu > 0)"
            ),
            ConstraintError::NotConverged {
                iterations,
                residual,
            } => write!(
                f,
                "the proximal iterations did not converge in {iterations} (residual {residual:e}): \
                 the constraints are inconsistent"
            ),
            ConstraintError::NonFinite => {
                write!(f, "an input is not finite (or the restitution is negative)")
            }
        }
    }
}

impl core::error::Error for ConstraintError {}

/// The constraints' rows at one state, stacked: at most `R` rows over `NV` velocities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct System<const NV: usize, const R: usize> {
    /// The rows in use, the first `rows` of each field.
    pub rows: usize,
    /// `J`: each row's Jacobian, with respect to `v`.
    pub jacobian: SMatrix<f64, R, NV>,
    /// `γ = J̇·v`: each row's acceleration at `q̈ = 0`.
    pub drift: SVector<f64, R>,
    /// `e`: each row's position error from its reference (zero where there is none).
    pub error: SVector<f64, R>,
    /// Each row's constraint (its order of `push`) and its row within it.
    pub owner: [(usize, usize); R],
    /// The constraints pushed.
    pub constraints: usize,
}

impl<const NV: usize, const R: usize> Default for System<NV, R> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const NV: usize, const R: usize> System<NV, R> {
    /// The rows for the numerical core.
    fn as_rows(&self) -> Rows<'_, nalgebra::Const<NV>, nalgebra::Const<R>> {
        Rows {
            count: self.rows,
            jacobian: &self.jacobian,
            drift: &self.drift,
            error: &self.error,
            owner: &self.owner,
        }
    }

    /// No constraint.
    pub fn new() -> Self {
        System {
            rows: 0,
            jacobian: SMatrix::zeros(),
            drift: SVector::zeros(),
            error: SVector::zeros(),
            owner: [(0, 0); R],
            constraints: 0,
        }
    }

    /// Adds a constraint of `K` rows: its Jacobian, drift and position error (`&[0.0; K]`
    /// without a reference).
    ///
    /// # Errors
    /// [`ConstraintError::Capacity`] when the rows would exceed `R`.
    pub fn push<const K: usize>(
        &mut self,
        jacobian: &SMatrix<f64, K, NV>,
        drift: &[f64; K],
        error: &[f64; K],
    ) -> Result<(), ConstraintError> {
        if self.rows + K > R {
            return Err(ConstraintError::Capacity {
                needed: self.rows + K,
                capacity: R,
            });
        }
        for k in 0..K {
            let r = self.rows + k;
            self.jacobian.row_mut(r).copy_from(&jacobian.row(k));
            self.drift[r] = drift[k];
            self.error[r] = error[k];
            self.owner[r] = (self.constraints, k);
        }
        self.rows += K;
        self.constraints += 1;
        Ok(())
    }
}

/// The frames' kinematics the rows are made of, for all `NF` frames of a chain at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frames<const NV: usize, const NF: usize> {
    /// `frame_placements(q)`.
    pub placements: [FramePlacement<f64>; NF],
    /// `frame_jacobians_local(q)`.
    pub jacobians: [SMatrix<f64, 6, NV>; NF],
    /// `frame_velocities(q, v)` (LOCAL).
    pub velocities: [SVector<f64, 6>; NF],
    /// `frame_accelerations(q, v, 0)`: the classical drifts, world axes.
    pub drifts: [SVector<f64, 6>; NF],
}

impl<const NV: usize, const NF: usize> Frames<NV, NF> {
    /// From a generated chain's frame outputs at `(q, v)`.
    pub fn of<C, const NQ: usize>(q: &SVector<f64, NQ>, v: &SVector<f64, NV>) -> Self
    where
        C: FrameOutputs<NQ, NV, NF>,
    {
        Frames {
            placements: C::frame_placements(q),
            jacobians: C::frame_jacobians_local(q),
            velocities: C::frame_velocities(q, v),
            drifts: C::frame_accelerations(q, v, &SVector::zeros()),
        }
    }

    /// The rows of `contacts` then `loops` (in that order), with the contacts' position errors
    /// from `references` (each frame's reference placement, indexed like the frames) where
    /// given.
    ///
    /// # Errors
    /// [`ConstraintError::UnknownFrame`], [`ConstraintError::Capacity`].
    pub fn system<const R: usize>(
        &self,
        contacts: &[Contact],
        loops: &[Loop],
        references: Option<&[FramePlacement<f64>; NF]>,
    ) -> Result<System<NV, R>, ConstraintError> {
        let known = |frame: usize| {
            if frame < NF {
                Ok(frame)
            } else {
                Err(ConstraintError::UnknownFrame { frame, frames: NF })
            }
        };
        let mut system = System::new();
        for c in contacts {
            let i = known(c.frame)?;
            let (placement, j, vel, drift) = (
                &self.placements[i],
                &self.jacobians[i],
                &self.velocities[i],
                &self.drifts[i],
            );
            match c.kind {
                Kind::Point => {
                    // LOCAL_WORLD_ALIGNED's linear rows: LOCAL's, turned to world axes.
                    let rows: SMatrix<f64, 3, NV> = placement.rotation * j.fixed_rows::<3>(3);
                    let e = references.map_or([0.0; 3], |r| point_error(placement, &r[i]));
                    system.push(&rows, &point_drift(drift), &e)?;
                }
                Kind::SixD => {
                    let e = references.map_or([0.0; 6], |r| six_d_error(placement, &r[i]));
                    system.push(j, &six_d_drift(placement, vel, drift), &e)?;
                }
            }
        }
        for l in loops {
            let (a, b) = (known(l.a)?, known(l.b)?);
            let (pa, pb) = (&self.placements[a], &self.placements[b]);
            match l.kind {
                Kind::Point => {
                    let world_rows = |i: usize| -> SMatrix<f64, 3, NV> {
                        self.placements[i].rotation * self.jacobians[i].fixed_rows::<3>(3)
                    };
                    let rows = world_rows(a) - world_rows(b);
                    let (da, db) = (point_drift(&self.drifts[a]), point_drift(&self.drifts[b]));
                    let e = point_error(pa, pb);
                    system.push(&rows, &core::array::from_fn(|r| da[r] - db[r]), &e)?;
                }
                Kind::SixD => {
                    let x = Transform::between(pa, pb);
                    let mut rows = self.jacobians[a];
                    for c in 0..NV {
                        let moved = x.motion(&self.jacobians[b].column(c).into());
                        let mut column = rows.column_mut(c);
                        column -= moved;
                    }
                    let (va, vb) = (&self.velocities[a], &self.velocities[b]);
                    let ga = SVector::from(six_d_drift(pa, va, &self.drifts[a]));
                    let gb = SVector::from(six_d_drift(pb, vb, &self.drifts[b]));
                    let drift = ga - x.motion(&gb) + cross_motion(va, &x.motion(vb));
                    system.push(&rows, &drift.into(), &six_d_error(pa, pb))?;
                }
            }
        }
        Ok(system)
    }
}

/// The motion transform `ᵃX_b` between two frames placed in the world: `b`'s coordinates to
/// `a`'s.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Transform {
    /// `ᵃR_b`.
    rotation: nalgebra::Matrix3<f64>,
    /// `b`'s origin in `a`'s axes.
    origin: nalgebra::Vector3<f64>,
}

impl Transform {
    /// `ᵃX_b` for frames placed at `a` and `b`.
    pub(crate) fn between(a: &FramePlacement<f64>, b: &FramePlacement<f64>) -> Self {
        Transform {
            rotation: a.rotation.tr_mul(&b.rotation),
            origin: a.rotation.tr_mul(&(b.translation - a.translation)),
        }
    }

    /// A motion `[ω; v]` in `b`'s coordinates, in `a`'s: `[R·ω; R·v + p × R·ω]`.
    pub(crate) fn motion(&self, m: &SVector<f64, 6>) -> SVector<f64, 6> {
        let w = self.rotation * m.fixed_rows::<3>(0);
        let v = self.rotation * m.fixed_rows::<3>(3) + self.origin.cross(&w);
        SVector::<f64, 6>::new(w[0], w[1], w[2], v[0], v[1], v[2])
    }
}

/// The motion cross product `a × b = [ω_a × ω_b; ω_a × v_b + v_a × ω_b]`.
pub(crate) fn cross_motion(a: &SVector<f64, 6>, b: &SVector<f64, 6>) -> SVector<f64, 6> {
    let (wa, va) = (a.fixed_rows::<3>(0), a.fixed_rows::<3>(3));
    let (wb, vb) = (b.fixed_rows::<3>(0), b.fixed_rows::<3>(3));
    let w = wa.cross(&wb);
    let v = wa.cross(&vb) + va.cross(&wb);
    SVector::<f64, 6>::new(w[0], w[1], w[2], v[0], v[1], v[2])
}

/// A point contact's drift: the classical linear acceleration at `q̈ = 0`, world axes.
fn point_drift(classical: &SVector<f64, 6>) -> [f64; 3] {
    [classical[3], classical[4], classical[5]]
}

/// A six-dimensional contact's drift, the spatial acceleration at `q̈ = 0` in LOCAL, from the
/// classical one in world axes (`frame_accelerations`): the angular part turned into the
/// frame's axes, the linear one less `ω × v` (LOCAL velocity `[ω; v]`).
fn six_d_drift(
    placement: &FramePlacement<f64>,
    velocity: &SVector<f64, 6>,
    classical: &SVector<f64, 6>,
) -> [f64; 6] {
    let w = placement.rotation;
    let (omega, lin) = (velocity.fixed_rows::<3>(0), velocity.fixed_rows::<3>(3));
    let dw = w.tr_mul(&classical.fixed_rows::<3>(0));
    let dv = w.tr_mul(&classical.fixed_rows::<3>(3)) - omega.cross(&lin);
    [dw[0], dw[1], dw[2], dv[0], dv[1], dv[2]]
}

/// A point's position error `p − p_ref`, world axes.
fn point_error(placement: &FramePlacement<f64>, reference: &FramePlacement<f64>) -> [f64; 3] {
    (placement.translation - reference.translation).into()
}

/// A frame's error `log6(M_ref⁻¹·M)`, angular first, in its axes.
fn six_d_error(placement: &FramePlacement<f64>, reference: &FramePlacement<f64>) -> [f64; 6] {
    log6(&between(reference, placement)).into()
}

/// The solution of a constrained system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solution<const NV: usize, const R: usize> {
    /// `q̈` ([`forward_dynamics`]) or `v⁺` ([`impulse_dynamics`]).
    pub acceleration: SVector<f64, NV>,
    /// The forces `f` (or impulses `p`), row by row as the system stacks them: the first
    /// `rows` entries.
    pub forces: SVector<f64, R>,
    /// The rows in use.
    pub rows: usize,
    /// `max |J·x − b|` over the rows: how far the solution is from holding the constraints.
    pub residual: f64,
    /// The proximal iterations made (`1` for the exact solve).
    pub iterations: usize,
}

impl<const NV: usize, const R: usize> Solution<NV, R> {
    /// The force of the constraint that starts at row `start` and has `K` rows, in its axes
    /// (module docs): `solution.force::<6>(0)` for a first six-dimensional contact.
    pub fn force<const K: usize>(&self, start: usize) -> [f64; K] {
        core::array::from_fn(|k| self.forces[start + k])
    }
}

/// Constrained forward dynamics: `q̈` and the constraint forces at a state with `M`, `nle`
/// (`N·q̇ + g`), the torques `τ`, the velocities `v` (for the Baumgarte terms) and the
/// constraints' rows (module docs).
///
/// # Errors
/// [`ConstraintError::MassMatrix`], [`ConstraintError::Redundant`],
/// [`ConstraintError::NotConverged`], [`ConstraintError::NonFinite`].
pub fn forward_dynamics<const NV: usize, const R: usize>(
    m: &SMatrix<f64, NV, NV>,
    nle: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
    v: &SVector<f64, NV>,
    system: &System<NV, R>,
    baumgarte: Option<Baumgarte>,
    settings: &Settings,
) -> Result<Solution<NV, R>, ConstraintError> {
    let rows = system.as_rows();
    let (x, forces, residual, iterations) =
        forward_core(m, nle, tau, v, &rows, baumgarte, settings)?;
    Ok(Solution {
        acceleration: x,
        forces,
        rows: system.rows,
        residual,
        iterations,
    })
}

/// Impulse dynamics: the velocities `v⁺` just after an impact at `v⁻` and the impulses, with
/// `J·v⁺ = −e·J·v⁻` on every row (bilateral, as Pinocchio's `impulseDynamics`), `e` the
/// coefficient of restitution (module docs).
///
/// # Errors
/// As [`forward_dynamics`]; [`ConstraintError::NonFinite`] also for a negative `restitution`.
pub fn impulse_dynamics<const NV: usize, const R: usize>(
    m: &SMatrix<f64, NV, NV>,
    v_minus: &SVector<f64, NV>,
    system: &System<NV, R>,
    restitution: f64,
    settings: &Settings,
) -> Result<Solution<NV, R>, ConstraintError> {
    let rows = system.as_rows();
    let (x, forces, residual, iterations) = impulse_core(m, v_minus, &rows, restitution, settings)?;
    Ok(Solution {
        acceleration: x,
        forces,
        rows: system.rows,
        residual,
        iterations,
    })
}

/// [`forward_dynamics`] of a generated chain at `(q, v, τ)` with the constraints `contacts` on
/// its frames; with Baumgarte gains, each constrained frame's reference placement (indexed like
/// `Chain::FRAMES`). Needs the outputs `mass_matrix_and_nonlinear_effects`,
/// `frame_placements`, `frame_jacobians_local`, `frame_velocities` and `frame_accelerations`.
/// [`forward_dynamics_of`] takes loops too.
///
/// # Errors
/// As [`forward_dynamics`] and [`Frames::system`].
pub fn constrained_forward_dynamics<
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
    baumgarte: Option<(Baumgarte, &[FramePlacement<f64>; NF])>,
    settings: &Settings,
) -> Result<Solution<NV, R>, ConstraintError>
where
    C: ConstraintOutputs<NQ, NV, NF>,
{
    forward_dynamics_of::<C, NQ, NV, NF, R>(q, v, tau, contacts, &[], baumgarte, settings)
}

/// [`forward_dynamics`] of a generated chain at `(q, v, τ)` with the contacts `contacts` and
/// the loop closures `loops` on its frames, their rows stacked in that order (contacts, then
/// loops: [`Frames::system`]); with Baumgarte gains, each constrained frame's reference
/// placement (indexed like `Chain::FRAMES`; a loop's error is always `p_a − p_b`). Needs the
/// outputs of [`constrained_forward_dynamics`]. A chain whose description declares its
/// constraints (`contacts: […]`, `loops: […]`) has its own `constrained_forward_dynamics(q, v,
/// τ)`, which calls this with its `CONTACTS` and `LOOPS`, no Baumgarte terms and the default
/// [`Settings`].
///
/// # Errors
/// As [`forward_dynamics`] and [`Frames::system`].
pub fn forward_dynamics_of<C, const NQ: usize, const NV: usize, const NF: usize, const R: usize>(
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
    contacts: &[Contact],
    loops: &[Loop],
    baumgarte: Option<(Baumgarte, &[FramePlacement<f64>; NF])>,
    settings: &Settings,
) -> Result<Solution<NV, R>, ConstraintError>
where
    C: ConstraintOutputs<NQ, NV, NF>,
{
    let frames = Frames::<NV, NF>::of::<C, NQ>(q, v);
    let system = frames.system::<R>(contacts, loops, baumgarte.map(|(_, r)| r))?;
    let (m, nle) = C::mass_matrix_and_nonlinear_effects(q, v);
    forward_dynamics(
        &m,
        &nle,
        tau,
        v,
        &system,
        baumgarte.map(|(g, _)| g),
        settings,
    )
}

/// [`impulse_dynamics`] of a generated chain at `(q, v⁻)` with the contacts `contacts` and the
/// loop closures `loops` on its frames, their rows stacked in that order ([`Frames::system`]):
/// a loop's rows are its frames' relative velocity, so `J·v⁺ = −e·J·v⁻` there is a closing
/// loop's impact (the impulse on `a`, its opposite on `b`). Needs the outputs of
/// [`constrained_forward_dynamics`].
///
/// # Errors
/// As [`impulse_dynamics`] and [`Frames::system`].
pub fn impulse_dynamics_of<C, const NQ: usize, const NV: usize, const NF: usize, const R: usize>(
    q: &SVector<f64, NQ>,
    v_minus: &SVector<f64, NV>,
    contacts: &[Contact],
    loops: &[Loop],
    restitution: f64,
    settings: &Settings,
) -> Result<Solution<NV, R>, ConstraintError>
where
    C: ConstraintOutputs<NQ, NV, NF>,
{
    let frames = Frames::<NV, NF>::of::<C, NQ>(q, v_minus);
    let system = frames.system::<R>(contacts, loops, None)?;
    let (m, _) = C::mass_matrix_and_nonlinear_effects(q, v_minus);
    impulse_dynamics(&m, v_minus, &system, restitution, settings)
}

/// [`impulse_dynamics`] of a generated chain at `(q, v⁻)` with the constraints `contacts`
/// ([`impulse_dynamics_of`] without loops). Needs the outputs of
/// [`constrained_forward_dynamics`].
///
/// # Errors
/// As [`impulse_dynamics`] and [`Frames::system`].
pub fn constrained_impulse_dynamics<
    C,
    const NQ: usize,
    const NV: usize,
    const NF: usize,
    const R: usize,
>(
    q: &SVector<f64, NQ>,
    v_minus: &SVector<f64, NV>,
    contacts: &[Contact],
    restitution: f64,
    settings: &Settings,
) -> Result<Solution<NV, R>, ConstraintError>
where
    C: ConstraintOutputs<NQ, NV, NF>,
{
    impulse_dynamics_of::<C, NQ, NV, NF, R>(q, v_minus, contacts, &[], restitution, settings)
}

/// A generated chain held by constraints, under a controller, for the integrators
/// ([`crate::integrate`]): `a(t, q, v)` is [`forward_dynamics`]'s `q̈` with the contacts and
/// loops given, their Baumgarte terms toward the contacts' placements at the initial state (and
/// toward closing each loop). The forces of the last evaluation are kept
/// ([`ConstrainedChain::last`]).
///
/// ```
/// # use articulated::nalgebra::SVector;
/// # use articulated::integrate::{Integrator, Rk4, State};
/// use articulated::constraint::{Baumgarte, ConstrainedChain, Loop, Settings};
/// articulated::chain! {
///     /// A pendulum whose bob is held on a rod to the world at (1, 0, 0) by a point loop:
///     /// the loop adds nothing while it holds.
///     chain Held {
///         body bob { mass: 1.0, com: [0.0, 0.0, 0.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob, xyz: [0.0, 0.0, 0.0] }
///         frame tip { parent: bob, xyz: [1.0, 0.0, 0.0] }
///         frame anchor { parent: world, xyz: [1.0, 0.0, 0.0] }
///         outputs: [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local,
///                   frame_velocities, frame_accelerations];
///         frames: [tip, anchor];
///     }
/// }
/// let loops = [Loop::point(0, 1)];
/// let settings = Settings { mu: 1e-8, ..Settings::default() }; // 1 of its 3 rows is free
/// let mut held = ConstrainedChain::<Held, _, 1, 1, 2, 3>::new(
///     &SVector::zeros(), &[], &loops, Some(Baumgarte { kp: 100.0, kd: 20.0 }), settings,
///     |_, _: &SVector<f64, 1>, _: &SVector<f64, 1>| SVector::zeros(),
/// )?;
/// let mut state = State::new(0.0, SVector::zeros(), SVector::zeros());
/// for step in 1..=1000 {
///     Rk4.advance(&mut held, &mut state, f64::from(step) * 1e-3, step as usize).unwrap();
/// }
/// assert!(state.q[0].abs() < 1e-9); // held where it started
/// # Ok::<(), articulated::constraint::ConstraintError>(())
/// ```
pub struct ConstrainedChain<
    'a,
    C,
    F,
    const NQ: usize,
    const NV: usize,
    const NF: usize,
    const R: usize,
> {
    contacts: &'a [Contact],
    loops: &'a [Loop],
    baumgarte: Option<Baumgarte>,
    references: [FramePlacement<f64>; NF],
    settings: Settings,
    controller: F,
    last: Option<Solution<NV, R>>,
    chain: core::marker::PhantomData<fn() -> C>,
    positions: core::marker::PhantomData<[f64; NQ]>,
}

impl<'a, C, F, const NQ: usize, const NV: usize, const NF: usize, const R: usize>
    ConstrainedChain<'a, C, F, NQ, NV, NF, R>
where
    C: ConstraintOutputs<NQ, NV, NF>,
    F: FnMut(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>,
{
    /// The chain held by `contacts` and `loops` from the configuration `q0` (the contacts'
    /// references are their placements there), with `baumgarte` gains, solved with `settings`,
    /// under `controller(t, q, v) → τ`.
    ///
    /// # Errors
    /// [`ConstraintError::UnknownFrame`] or [`ConstraintError::Capacity`] for constraints that
    /// cannot be assembled.
    pub fn new(
        q0: &SVector<f64, NQ>,
        contacts: &'a [Contact],
        loops: &'a [Loop],
        baumgarte: Option<Baumgarte>,
        settings: Settings,
        controller: F,
    ) -> Result<Self, ConstraintError> {
        let frames = Frames::<NV, NF>::of::<C, NQ>(q0, &SVector::zeros());
        frames.system::<R>(contacts, loops, None)?;
        Ok(ConstrainedChain {
            contacts,
            loops,
            baumgarte,
            references: frames.placements,
            settings,
            controller,
            last: None,
            chain: core::marker::PhantomData,
            positions: core::marker::PhantomData,
        })
    }

    /// The solution of the last evaluation of the acceleration (its forces, residual and
    /// iterations), `None` before the first.
    pub fn last(&self) -> Option<&Solution<NV, R>> {
        self.last.as_ref()
    }

    /// The contacts' reference placements, indexed like `Chain::FRAMES`.
    pub fn references(&self) -> &[FramePlacement<f64>; NF] {
        &self.references
    }
}

impl<C, F, const NQ: usize, const NV: usize, const NF: usize, const R: usize>
    crate::integrate::SecondOrder<f64, nalgebra::Const<NQ>, nalgebra::Const<NV>>
    for ConstrainedChain<'_, C, F, NQ, NV, NF, R>
where
    C: crate::Chain<f64> + ConstraintOutputs<NQ, NV, NF>,
    F: FnMut(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>,
{
    fn coordinates(&self) -> &[crate::Coordinates] {
        C::COORDINATES
    }

    fn finite_acceleration(&self) -> bool {
        // `forward_dynamics` reports a non-finite result as an error.
        true
    }

    fn acceleration(
        &mut self,
        t: f64,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
    ) -> Result<SVector<f64, NV>, crate::integrate::Cause<f64>> {
        let tau = (self.controller)(t, q, v);
        let frames = Frames::<NV, NF>::of::<C, NQ>(q, v);
        let system = frames
            .system::<R>(self.contacts, self.loops, Some(&self.references))
            .map_err(crate::integrate::Cause::Constraint)?;
        let (m, nle) = C::mass_matrix_and_nonlinear_effects(q, v);
        let s = forward_dynamics(&m, &nle, &tau, v, &system, self.baumgarte, &self.settings)
            .map_err(crate::integrate::Cause::Constraint)?;
        self.last = Some(s);
        Ok(s.acceleration)
    }
}

/// The joint forces and contact forces that produce given accelerations ([`inverse_dynamics`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactWrenches<const NV: usize, const R: usize> {
    /// `τ = M·q̈ + nle − Jᵀ·f`: the joints' forces; its first `unactuated` entries are what the
    /// contacts could not supply (zero, to rounding, where they can).
    pub tau: SVector<f64, NV>,
    /// The constraint forces `f`, row by row as the system stacks them (the first `rows`).
    pub forces: SVector<f64, R>,
    /// The rows in use.
    pub rows: usize,
    /// `max |τ_i|` over the unactuated entries: how far the contacts are from producing the
    /// motion (0 where they determine or over-determine the base's wrench).
    pub residual: f64,
}

/// Inverse dynamics with contacts (Hemami's estimation of the ground reaction, Wieber's
/// whole-body Newton and Euler equations): the joint forces `τ` and the constraint forces `f`
/// with `M·q̈ + nle = τ + Jᵀ·f`, where the first `unactuated` velocities (a free base: 6) have
/// no actuator, so that their rows, `J_bᵀ·f = (M·q̈ + nle)_b`, are the contacts' to supply.
/// Unique where the contacts determine `f` (one flat foot); otherwise the least-norm `f` (two
/// feet: how they share the load is not determined by the motion); where the contacts cannot
/// supply the base's wrench (a single point contact), the least-squares `f`, with the residual
/// left in `τ_b` and reported.
///
/// # Errors
/// [`ConstraintError::NonFinite`] for a value that is not finite or `unactuated > 6`.
pub fn inverse_dynamics<const NV: usize, const R: usize>(
    m: &SMatrix<f64, NV, NV>,
    nle: &SVector<f64, NV>,
    qdd: &SVector<f64, NV>,
    system: &System<NV, R>,
    unactuated: usize,
) -> Result<ContactWrenches<NV, R>, ConstraintError> {
    let u = unactuated;
    if u > 6 || u > NV || !finite(&[m.as_slice(), nle.as_slice(), qdd.as_slice()]) {
        return Err(ConstraintError::NonFinite);
    }
    if !finite(&[system.jacobian.as_slice()]) {
        return Err(ConstraintError::NonFinite);
    }
    let h = m * qdd + nle;
    let k = system.rows;
    let j = &system.jacobian;
    // f = J_b·(J_bᵀ·J_b)⁺·h_b, J_b the first u columns of J: the least-norm (least-squares
    // where rank-deficient) solution of J_bᵀ·f = h_b. Padded to 6 × 6 with the identity.
    let mut b = SMatrix::<f64, 6, 6>::identity();
    let mut hb = SVector::<f64, 6>::zeros();
    for r in 0..u {
        hb[r] = h[r];
        for c in 0..u {
            b[(r, c)] = (0..k).map(|i| j[(i, r)] * j[(i, c)]).sum();
        }
    }
    let eigen = b.symmetric_eigen();
    let largest = eigen.eigenvalues.amax();
    let mut y = SVector::<f64, 6>::zeros();
    for (e, value) in eigen.eigenvalues.iter().enumerate() {
        if *value > 1e-12 * largest {
            let v = eigen.eigenvectors.column(e);
            y += v * (v.dot(&hb) / value);
        }
    }
    let mut forces = SVector::<f64, R>::zeros();
    for i in 0..k {
        forces[i] = (0..u).map(|c| j[(i, c)] * y[c]).sum();
    }
    let tau = h - j.tr_mul(&forces);
    let residual = tau.iter().take(u).fold(0.0f64, |m, x| m.max(x.abs()));
    if !finite(&[tau.as_slice(), forces.as_slice()]) {
        return Err(ConstraintError::NonFinite);
    }
    Ok(ContactWrenches {
        tau,
        forces,
        rows: k,
        residual,
    })
}

/// The velocities without an actuator at the front of `v`: 6 under a free base (quaternion or
/// Euler), 0 otherwise.
pub fn unactuated(coordinates: &[crate::Coordinates]) -> usize {
    match coordinates.first() {
        Some(crate::Coordinates::FreeQuaternion | crate::Coordinates::Vector(6)) => 6,
        _ => 0,
    }
}

/// A contact wrench `[n; f]` given in a frame placed at `placement` (about the frame's origin,
/// in its axes: a six-dimensional contact's) as a wrench about the point `about`, world axes.
pub fn wrench_in_world(
    placement: &FramePlacement<f64>,
    wrench: &[f64; 6],
    about: &SVector<f64, 3>,
) -> [f64; 6] {
    let n = placement.rotation * SVector::<f64, 3>::new(wrench[0], wrench[1], wrench[2]);
    let f = placement.rotation * SVector::<f64, 3>::new(wrench[3], wrench[4], wrench[5]);
    let n = n + (placement.translation - about).cross(&f);
    [n[0], n[1], n[2], f[0], f[1], f[2]]
}

/// The centre of pressure of a wrench `[n; f]` (about a frame's origin, in its axes) on the
/// frame's plane `z = height`: the point of that plane about which the wrench has no moment
/// along the plane, `(x, y, height)` with `x = (height·f_x − n_y)/f_z`,
/// `y = (height·f_y + n_x)/f_z`. For a sole's wrench, its centre of pressure; for the sum of
/// the contact wrenches in world axes about the origin, on the ground `z = height`, the
/// zero-moment point. `None` where `f_z ≤ 0` (nothing pushes on the plane).
///
/// ```
/// // 100 N straight up at (0.05, −0.02) on the plane z = −0.1 of a foot frame:
/// let (p, f) = ([0.05, -0.02, -0.1], [0.0, 0.0, 100.0]);
/// let n = [p[1] * f[2] - p[2] * f[1], p[2] * f[0] - p[0] * f[2], p[0] * f[1] - p[1] * f[0]];
/// let cop = articulated::constraint::center_of_pressure(
///     &[n[0], n[1], n[2], f[0], f[1], f[2]], -0.1,
/// ).unwrap();
/// assert!((cop[0] - 0.05).abs() < 1e-15 && (cop[1] + 0.02).abs() < 1e-15);
/// ```
pub fn center_of_pressure(wrench: &[f64; 6], height: f64) -> Option<[f64; 3]> {
    let [nx, ny, _, fx, fy, fz] = *wrench;
    if fz.is_nan() || fz <= 0.0 {
        return None;
    }
    Some([(height * fx - ny) / fz, (height * fy + nx) / fz, height])
}

/// The same at run-time sizes, for a chain known only at run time (the CLI's `eval
/// --contacts`, an interpreted [`Reference`](crate::reference::Reference)): the rows in
/// growable matrices, the same numerical core.
#[cfg(feature = "alloc")]
pub mod dynamic {
    use alloc::vec::Vec;

    use nalgebra::{DMatrix, DVector, SVector};

    use super::{
        forward_core, impulse_core, point_drift, point_error, six_d_drift, six_d_error, Baumgarte,
        ConstraintError, Kind, Rows, Settings,
    };
    use crate::FramePlacement;

    /// One frame's kinematics at a state: what its constraint's rows are made of.
    #[derive(Clone, Debug, PartialEq)]
    pub struct FrameKinematics {
        /// Its placement.
        pub placement: FramePlacement<f64>,
        /// Its LOCAL Jacobian, `6 × nv`.
        pub jacobian: DMatrix<f64>,
        /// Its LOCAL velocity `[ω; v]`.
        pub velocity: SVector<f64, 6>,
        /// Its classical acceleration at `q̈ = 0`, world axes `[ω̇; p̈]`.
        pub drift: SVector<f64, 6>,
    }

    impl FrameKinematics {
        /// `frame`'s kinematics at `(q, v)` by the interpreted reference: its placement, LOCAL
        /// Jacobian, LOCAL velocity and classical acceleration at `q̈ = 0`.
        ///
        /// # Errors
        /// The reference's: an unknown frame, a wrong length, a value that is not finite.
        pub fn by_reference(
            r: &crate::reference::Reference,
            q: &[f64],
            v: &[f64],
            frame: &str,
        ) -> Result<Self, crate::reference::Error> {
            let zero = alloc::vec![0.0; r.nv()];
            let (rotation, translation) = r.frame_placement(q, frame)?;
            Ok(FrameKinematics {
                placement: FramePlacement {
                    rotation,
                    translation,
                },
                jacobian: r.frame_jacobian(q, frame, crate::reference::ReferenceFrame::Local)?,
                velocity: r.frame_velocity(q, v, frame)?,
                drift: r.frame_acceleration(q, v, &zero, frame)?,
            })
        }
    }

    /// The stacked rows ([`super::System`] at run-time sizes).
    #[derive(Clone, Debug, PartialEq)]
    pub struct System {
        /// `J`, `rows × nv`.
        pub jacobian: DMatrix<f64>,
        /// `γ`.
        pub drift: DVector<f64>,
        /// `e`.
        pub error: DVector<f64>,
        /// Each row's constraint and its row within it.
        pub owner: Vec<(usize, usize)>,
        /// The constraints pushed.
        pub constraints: usize,
    }

    impl System {
        /// No constraint, over `nv` velocities.
        pub fn new(nv: usize) -> Self {
            System {
                jacobian: DMatrix::zeros(0, nv),
                drift: DVector::zeros(0),
                error: DVector::zeros(0),
                owner: Vec::new(),
                constraints: 0,
            }
        }

        /// The rows in use.
        pub fn rows(&self) -> usize {
            self.drift.len()
        }

        /// Adds a constraint of `kind` on the frame `frame`, with its position error from
        /// `reference` where given.
        ///
        /// # Errors
        /// [`ConstraintError::NonFinite`] when `frame.jacobian` is not `6 × nv`.
        pub fn push(
            &mut self,
            kind: Kind,
            frame: &FrameKinematics,
            reference: Option<&FramePlacement<f64>>,
        ) -> Result<(), ConstraintError> {
            let nv = self.jacobian.ncols();
            if frame.jacobian.shape() != (6, nv) {
                return Err(ConstraintError::NonFinite);
            }
            let p = &frame.placement;
            let (rows, drift, error): (DMatrix<f64>, Vec<f64>, Vec<f64>) = match kind {
                Kind::Point => (
                    {
                        let turned = p.rotation * frame.jacobian.fixed_rows::<3>(3);
                        DMatrix::from_fn(3, nv, |r, c| turned[(r, c)])
                    },
                    point_drift(&frame.drift).to_vec(),
                    reference.map_or([0.0; 3], |r| point_error(p, r)).to_vec(),
                ),
                Kind::SixD => (
                    frame.jacobian.clone(),
                    six_d_drift(p, &frame.velocity, &frame.drift).to_vec(),
                    reference.map_or([0.0; 6], |r| six_d_error(p, r)).to_vec(),
                ),
            };
            let (old, k) = (self.rows(), kind.rows());
            let mut jacobian = DMatrix::zeros(old + k, nv);
            jacobian.rows_mut(0, old).copy_from(&self.jacobian);
            jacobian.rows_mut(old, k).copy_from(&rows);
            self.jacobian = jacobian;
            self.drift = DVector::from_iterator(old + k, self.drift.iter().copied().chain(drift));
            self.error = DVector::from_iterator(old + k, self.error.iter().copied().chain(error));
            self.owner.extend((0..k).map(|r| (self.constraints, r)));
            self.constraints += 1;
            Ok(())
        }
    }

    /// [`super::Solution`] at run-time sizes.
    #[derive(Clone, Debug, PartialEq)]
    pub struct Solution {
        /// `q̈` or `v⁺`.
        pub acceleration: DVector<f64>,
        /// The forces or impulses, row by row.
        pub forces: DVector<f64>,
        /// `max |J·x − b|`.
        pub residual: f64,
        /// The proximal iterations made.
        pub iterations: usize,
    }

    fn rows(system: &System) -> Rows<'_, nalgebra::Dyn, nalgebra::Dyn> {
        Rows {
            count: system.rows(),
            jacobian: &system.jacobian,
            drift: &system.drift,
            error: &system.error,
            owner: &system.owner,
        }
    }

    /// The sizes agree: `M` is `nv × nv`, the vectors `nv`.
    fn sizes(
        m: &DMatrix<f64>,
        vectors: &[&DVector<f64>],
        system: &System,
    ) -> Result<(), ConstraintError> {
        let nv = system.jacobian.ncols();
        if m.shape() == (nv, nv) && vectors.iter().all(|v| v.len() == nv) {
            Ok(())
        } else {
            Err(ConstraintError::NonFinite)
        }
    }

    /// [`super::forward_dynamics`] at run-time sizes.
    ///
    /// # Errors
    /// As [`super::forward_dynamics`]; [`ConstraintError::NonFinite`] also for sizes that
    /// disagree.
    pub fn forward_dynamics(
        m: &DMatrix<f64>,
        nle: &DVector<f64>,
        tau: &DVector<f64>,
        v: &DVector<f64>,
        system: &System,
        baumgarte: Option<Baumgarte>,
        settings: &Settings,
    ) -> Result<Solution, ConstraintError> {
        sizes(m, &[nle, tau, v], system)?;
        let (acceleration, forces, residual, iterations) =
            forward_core(m, nle, tau, v, &rows(system), baumgarte, settings)?;
        Ok(Solution {
            acceleration,
            forces,
            residual,
            iterations,
        })
    }

    /// [`super::impulse_dynamics`] at run-time sizes.
    ///
    /// # Errors
    /// As [`super::impulse_dynamics`]; [`ConstraintError::NonFinite`] also for sizes that
    /// disagree.
    pub fn impulse_dynamics(
        m: &DMatrix<f64>,
        v_minus: &DVector<f64>,
        system: &System,
        restitution: f64,
        settings: &Settings,
    ) -> Result<Solution, ConstraintError> {
        sizes(m, &[v_minus], system)?;
        let (acceleration, forces, residual, iterations) =
            impulse_core(m, v_minus, &rows(system), restitution, settings)?;
        Ok(Solution {
            acceleration,
            forces,
            residual,
            iterations,
        })
    }
}

/// The stacked rows, whatever their storage (the core below works on fixed and run-time sizes
/// alike).
struct Rows<'a, N: Dim, R: Dim>
where
    DefaultAllocator: Allocator<R, N> + Allocator<R>,
{
    count: usize,
    jacobian: &'a OMatrix<f64, R, N>,
    drift: &'a OVector<f64, R>,
    error: &'a OVector<f64, R>,
    owner: &'a [(usize, usize)],
}

/// `(x, f, residual, iterations)`.
type Core<N, R> = (OVector<f64, N>, OVector<f64, R>, f64, usize);

fn forward_core<N: Dim, R: Dim>(
    m: &OMatrix<f64, N, N>,
    nle: &OVector<f64, N>,
    tau: &OVector<f64, N>,
    v: &OVector<f64, N>,
    rows: &Rows<'_, N, R>,
    baumgarte: Option<Baumgarte>,
    settings: &Settings,
) -> Result<Core<N, R>, ConstraintError>
where
    DefaultAllocator: Allocator<N, N>
        + Allocator<R, N>
        + Allocator<N, R>
        + Allocator<R, R>
        + Allocator<N>
        + Allocator<R>,
{
    let gains_finite = baumgarte.is_none_or(|g| g.kp.is_finite() && g.kd.is_finite());
    if !gains_finite || !finite(&[v.as_slice(), nle.as_slice(), tau.as_slice()]) {
        return Err(ConstraintError::NonFinite);
    }
    let jv = rows.jacobian * v;
    let mut b = -rows.drift;
    if let Some(g) = baumgarte {
        b -= jv * g.kd + rows.error * g.kp;
    }
    let l = factor(m, settings)?;
    let x0 = solve_m(&l, &(tau - nle));
    solve(&l, x0, rows, b, settings)
}

fn impulse_core<N: Dim, R: Dim>(
    m: &OMatrix<f64, N, N>,
    v_minus: &OVector<f64, N>,
    rows: &Rows<'_, N, R>,
    restitution: f64,
    settings: &Settings,
) -> Result<Core<N, R>, ConstraintError>
where
    DefaultAllocator: Allocator<N, N>
        + Allocator<R, N>
        + Allocator<N, R>
        + Allocator<R, R>
        + Allocator<N>
        + Allocator<R>,
{
    let valid = restitution.is_finite() && restitution >= 0.0 && finite(&[v_minus.as_slice()]);
    if !valid {
        return Err(ConstraintError::NonFinite);
    }
    let b = rows.jacobian * v_minus * -restitution;
    let l = factor(m, settings)?;
    solve(&l, v_minus.clone(), rows, b, settings)
}

/// Every value of every part finite. Part by part, and within a part without stopping at the
/// first that is not: a chain of iterators over them all, or a loop that can stop early, is a
/// loop the compiler does not vectorize.
fn finite(parts: &[&[f64]]) -> bool {
    parts
        .iter()
        .all(|p| p.iter().fold(true, |ok, x| ok & x.is_finite()))
}

/// `L` with `M = L·Lᵀ` (lower triangle), refusing a pivot below `pivot_tolerance` times its
/// unreduced value (or a non-finite one).
pub(crate) fn factor<N: Dim>(
    m: &OMatrix<f64, N, N>,
    settings: &Settings,
) -> Result<OMatrix<f64, N, N>, ConstraintError>
where
    DefaultAllocator: Allocator<N, N>,
{
    if !finite(&[m.as_slice()]) {
        return Err(ConstraintError::NonFinite);
    }
    cholesky(m, m.nrows(), settings.pivot_tolerance)
        .map_err(|velocity| ConstraintError::MassMatrix { velocity })
}

/// The Cholesky factor of the leading `n × n` block of `a` (the rest left as it is), or the
/// first row whose pivot is not above `tolerance` times its unreduced diagonal entry.
pub(crate) fn cholesky<N: Dim>(
    a: &OMatrix<f64, N, N>,
    n: usize,
    tolerance: f64,
) -> Result<OMatrix<f64, N, N>, usize>
where
    DefaultAllocator: Allocator<N, N>,
{
    let mut l = a.clone();
    for j in 0..n {
        let mut d = l[(j, j)];
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        if !d.is_finite() || d <= tolerance * a[(j, j)].abs() {
            return Err(j);
        }
        let d = libm::sqrt(d);
        l[(j, j)] = d;
        for i in j + 1..n {
            let mut s = l[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = s / d;
        }
        for i in 0..j {
            l[(i, j)] = 0.0;
        }
    }
    Ok(l)
}

/// `x` with `L·x = b` for the leading `n` entries.
pub(crate) fn forward<N: Dim>(l: &OMatrix<f64, N, N>, b: &mut OVector<f64, N>, n: usize)
where
    DefaultAllocator: Allocator<N, N> + Allocator<N>,
{
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[(i, k)] * b[k];
        }
        b[i] = s / l[(i, i)];
    }
}

/// `x` with `Lᵀ·x = b` for the leading `n` entries.
pub(crate) fn backward<N: Dim>(l: &OMatrix<f64, N, N>, b: &mut OVector<f64, N>, n: usize)
where
    DefaultAllocator: Allocator<N, N> + Allocator<N>,
{
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[(k, i)] * b[k];
        }
        b[i] = s / l[(i, i)];
    }
}

/// `M⁻¹·b` from `M`'s factor.
pub(crate) fn solve_m<N: Dim>(l: &OMatrix<f64, N, N>, b: &OVector<f64, N>) -> OVector<f64, N>
where
    DefaultAllocator: Allocator<N, N> + Allocator<N>,
{
    let mut x = b.clone();
    let n = x.nrows();
    forward(l, &mut x, n);
    backward(l, &mut x, n);
    x
}

/// `x = x₀ + M⁻¹·Jᵀ·f` with `J·x = b` (module docs), `l` the factor of `M`.
fn solve<N: Dim, R: Dim>(
    l: &OMatrix<f64, N, N>,
    x0: OVector<f64, N>,
    rows: &Rows<'_, N, R>,
    mut b: OVector<f64, R>,
    settings: &Settings,
) -> Result<Core<N, R>, ConstraintError>
where
    DefaultAllocator: Allocator<N, N>
        + Allocator<R, N>
        + Allocator<N, R>
        + Allocator<R, R>
        + Allocator<N>
        + Allocator<R>,
{
    let k = rows.count;
    let j = rows.jacobian;
    let (n_dim, r_dim) = (x0.shape_generic().0, b.shape_generic().0);
    let n = x0.nrows();
    // Rows past `count` take no part: zero right side, identity in `G`.
    for r in k..b.nrows() {
        b[r] = 0.0;
    }
    if !finite(&[
        j.as_slice(),
        rows.drift.as_slice(),
        rows.error.as_slice(),
        b.as_slice(),
        x0.as_slice(),
    ]) {
        return Err(ConstraintError::NonFinite);
    }
    // W = L⁻¹·Jᵀ, column by column; G = Wᵀ·W.
    let mut w = OMatrix::<f64, N, R>::zeros_generic(n_dim, r_dim);
    for r in 0..k {
        let mut col: OVector<f64, N> = j.row(r).transpose();
        forward(l, &mut col, n);
        w.set_column(r, &col);
    }
    let mut g = OMatrix::<f64, R, R>::identity_generic(r_dim, r_dim);
    for r in 0..k {
        for c in 0..=r {
            let x = w.column(r).dot(&w.column(c));
            g[(r, c)] = x;
            g[(c, r)] = x;
        }
    }
    let mut rhs = &b - j * &x0;
    for r in k..rhs.nrows() {
        rhs[r] = 0.0;
    }
    let (forces, iterations) = if settings.mu == 0.0 {
        let lg = cholesky(&g, k, settings.pivot_tolerance).map_err(|row| {
            let (contact, row) = rows.owner.get(row).copied().unwrap_or((0, row));
            ConstraintError::Redundant { contact, row }
        })?;
        let mut f = rhs;
        forward(&lg, &mut f, k);
        backward(&lg, &mut f, k);
        (f, 1)
    } else {
        if !(settings.mu > 0.0 && settings.mu.is_finite()) {
            return Err(ConstraintError::NonFinite);
        }
        let mut shifted = g;
        for r in 0..k {
            shifted[(r, r)] += settings.mu;
        }
        let lg = cholesky(&shifted, k, 0.0).map_err(|_| ConstraintError::NonFinite)?;
        let mut f = OVector::<f64, R>::zeros_generic(r_dim, nalgebra::Const::<1>);
        let mut done = None;
        for it in 1..=settings.max_iterations {
            let mut next = &rhs + &f * settings.mu;
            forward(&lg, &mut next, k);
            backward(&lg, &mut next, k);
            let step = (&next - &f).amax();
            f = next;
            if step <= settings.tolerance * f.amax().max(1.0) {
                done = Some(it);
                break;
            }
        }
        match done {
            Some(it) => (f, it),
            None => {
                let x = &x0 + solve_back(l, &w, &f);
                return Err(ConstraintError::NotConverged {
                    iterations: settings.max_iterations,
                    residual: residual(j, &x, &b, k),
                });
            }
        }
    };
    let x = &x0 + solve_back(l, &w, &forces);
    let residual = residual(j, &x, &b, k);
    if !finite(&[x.as_slice(), forces.as_slice()]) {
        return Err(ConstraintError::NonFinite);
    }
    Ok((x, forces, residual, iterations))
}

/// `L⁻ᵀ·W·f = M⁻¹·Jᵀ·f`.
fn solve_back<N: Dim, R: Dim>(
    l: &OMatrix<f64, N, N>,
    w: &OMatrix<f64, N, R>,
    f: &OVector<f64, R>,
) -> OVector<f64, N>
where
    DefaultAllocator: Allocator<N, N> + Allocator<N, R> + Allocator<N> + Allocator<R>,
{
    let mut y = w * f;
    let n = y.nrows();
    backward(l, &mut y, n);
    y
}

/// `max |J·x − b|` over the first `k` rows.
fn residual<N: Dim, R: Dim>(
    j: &OMatrix<f64, R, N>,
    x: &OVector<f64, N>,
    b: &OVector<f64, R>,
    k: usize,
) -> f64
where
    DefaultAllocator: Allocator<R, N> + Allocator<N> + Allocator<R>,
{
    let jx = j * x;
    (0..k).fold(0.0, |m: f64, r| m.max((jx[r] - b[r]).abs()))
}
