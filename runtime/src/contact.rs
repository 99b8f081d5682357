//! Simulation with contacts: spheres on a chain's frames against ground half-spaces, with
//! unilateral contact and exact Coulomb friction cones (Wieber 2005, eq. 16: contact forces push
//! and never pull, and stay inside their friction cones).
//!
//! # The scene
//! A [`Ground`] is a half-space `n·x ≥ d`, `n` its unit normal pointing to the free side. A
//! [`Sphere`] sits on a frame of the chain (`Chain::FRAMES`, an index into them) at an offset in
//! the frame's axes, with a radius (zero for a point: a sole's corner) and the friction
//! coefficient `μ` and restitution `e` of its contacts. Every pair of a sphere and a ground is a
//! possible contact; a slope is a tilted ground (or the same ground under a tilted gravity, a
//! parameter of the description).
//!
//! Joint position limits can enter the same problem ([`TimeStepper::hold_joint_limits`]): each
//! limit near its joint is a frictionless unilateral row, a hard stop.
//!
//! # Time stepping
//! A step of length `h` from `(q, v)` is velocity-level and semi-implicit (Moreau, Stewart and
//! Trinkle, Anitescu): with `M`, `nle = N·q̇ + g` and the controller's `τ` at `(t, q, v)`, the
//! free velocity is `v_f = v + h·M⁻¹·(τ − nle)`, and the contacts add impulses `λ`:
//!
//! ```text
//! v⁺ = v_f + M⁻¹·Σ Jᵢᵀ·λᵢ,      q⁺ = q ⊕ h·v⁺
//! ```
//!
//! A free base's linear velocity `u` is in its own axes, which turn within the step: the
//! frame's turning, `−ω × u` in `nle`, is taken exactly rather than explicitly (`h·ω × u` added
//! back to `v_f`, and `u⁺` carried into the axes at `q⁺`), so a free body's momentum is kept
//! to rounding in free flight; integrated explicitly, a ball rolling at 20 rad/s gains 3 % of
//! its speed in a second at 1 ms steps.
//!
//! `Jᵢ` is the velocity of contact `i`'s point (the sphere's lowest point towards the ground) in
//! its contact basis `(n, t₁, t₂)`, `uᵢ = Jᵢ·v⁺ = (u_n, u_t)`, and `λᵢ = (λ_n, λ_t)` its impulse
//! in the same basis. The impulses solve the exact Coulomb problem (De Saxcé's bipotential
//! form), contact by contact:
//!
//! - unilateral: `λ_n ≥ 0`, `u_n ≥ ξ`, `λ_n·(u_n − ξ) = 0`;
//! - the cone: `‖λ_t‖ ≤ μ·λ_n`; sticking (`u_t = 0`) inside it, sliding on its edge against the
//!   slip, `λ_t = −μ·λ_n·u_t/‖u_t‖`.
//!
//! The normal target `ξ` holds the gap: `ξ = −φ/h` for a gap `φ ≥ 0` (a pair may close its gap
//! within the step but not pass it: speculative contact, so a landing leaves no penetration to
//! first order in `h`), `ξ = −β·φ/h` for a penetration (`φ < 0`, pushed out at the rate
//! [`Settings::stabilization`]` = β`: penetration does not accumulate), and after an impact
//! (`u_n⁻ < −`[`Settings::bounce_velocity`] and the gap closing within the step) at least
//! `−e·u_n⁻`, the pre-step normal velocity reversed by the restitution `e`.
//!
//! This is not the convex relaxation (Anitescu's cone complementarity, MuJoCo's and Drake's
//! SAP family): that one asks `u_n ≥ μ·‖u_t‖` of a sliding contact, which lifts it off the
//! ground by `μ·‖u_t‖·h` each step; here a sliding contact keeps `u_n = 0`. What it costs: the
//! exact problem is not convex and its solution need not be unique (Painlevé's paradoxes); the
//! solver below may then not converge, and says so.
//!
//! # The solver
//! Projected Gauss–Seidel over the contacts (Jean and Moreau's nonsmooth contact dynamics,
//! Bullet's and Pinocchio 3's `PGSContactSolver`). For each contact in turn:
//! - sticking first: the contact's three rows solved at once with its 3 × 3 block of the
//!   Delassus matrix `G = J·M⁻¹·Jᵀ`, kept where the impulse lies inside the cone;
//! - else one projected step on the whole contact along De Saxcé's modified velocity
//!   `û = u − ξ·n + μ·‖u_t‖·n`: `λ ← proj_K(λ − û/α)`, `K` the cone and `α` a bound on the
//!   block's largest eigenvalue (as Pinocchio 3's PGS). Without the term `μ·‖u_t‖·n` this would
//!   be the convex relaxation; with it, a sliding contact converges to `u_n = ξ` and the
//!   friction opposite the slip. (Splitting the contact into a normal then a tangential update
//!   also has these fixed points, but cycled without converging on a walker falling on its
//!   heel, Painlevé-like; the whole-contact step converged there, slowly.)
//!
//! A fixed point of these updates satisfies the conditions above exactly. `M = Lᵀ·L` is
//! factored along the kinematic tree (Featherstone's sparse factorization, where the
//! coordinates are in tree order, which [`TimeStepper::new`] reads from `M`'s sparsity), and
//! each contact keeps `Wᵢ = L⁻ᵀ·Jᵢᵀ`, non-zero only on the velocities that move it and their
//! ancestors: `G = Wᵀ·W`, `uᵢ = Jᵢ·v_f + Wᵢᵀ·z` with `z = Σ Wⱼ·λⱼ` kept up to date, and
//! `v⁺ = v_f + L⁻¹·z` once the impulses are found. A sweep costs `O(contacts·nv)`; the full `G`
//! is never formed. The impulses start from the last step's (warm start), so a resting or
//! sticking contact converges in a few sweeps. The residual of a sweep is the largest
//! correction it made, in m/s (the natural map of the conditions above, scaled by `G`'s
//! diagonal blocks); the solve stops when it falls to [`Settings::tolerance`], and a step that
//! reaches [`Settings::max_iterations`] first still moves on, its [`StepReport`] saying it did
//! not converge and how far it got.
//!
//! Everything in the stepping is allocation-free for at most `P` contacts at once
//! ([`TimeStepper`], a const parameter; more is [`ContactError::Capacity`]).
//!
//! ```
//! use articulated::contact::{Ground, Settings, Sphere, TimeStepper};
//! use articulated::integrate::State;
//! use articulated::nalgebra::SVector;
//!
//! // A point mass on a prismatic joint along z (the frame `bob` is its body), dropped from
//! // 0.1 m onto the ground z ≥ 0, with no restitution: it lands and stays, and the ground then
//! // carries its weight.
//! articulated::chain! {
//!     chain Drop {
//!         gravity: [0.0, 0.0, -9.81];
//!         outputs: [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local];
//!         frames: [bob];
//!         body bob { mass: 2.0, com: [0.0, 0.0, 0.0], inertia: diag(0.01, 0.01, 0.01) }
//!         joint slide: prismatic(z) { parent: world, child: bob }
//!     }
//! }
//! let grounds = [Ground::new([0.0, 0.0, 1.0], 0.0)?];
//! let spheres = [Sphere::point(0, 0.5)];
//! let mut stepper = TimeStepper::<Drop, _, 1, 1, 1, 1>::new(
//!     &grounds, &spheres, Settings::default(), |_t, _q, _v| SVector::zeros(),
//! )?;
//! let mut state = State::new(0.0, SVector::from([0.1]), SVector::zeros());
//! for _ in 0..1000 {
//!     let report = stepper.step(&mut state, 1e-3)?;
//!     assert!(report.converged);
//! }
//! assert!(state.q[0].abs() < 1e-9 && state.v[0].abs() < 1e-9);
//! let force = stepper.forces().next().unwrap().force;
//! assert!((force[2] - 2.0 * 9.81).abs() < 1e-9);
//! # Ok::<(), articulated::contact::ContactError>(())
//! ```

use core::fmt;

use nalgebra::allocator::Allocator;
use nalgebra::{
    DefaultAllocator, Dim, Matrix3, OMatrix, OVector, SMatrix, SVector, Vector3, U3, U6,
};

use crate::integrate::State;
use crate::{
    Chain, Coordinates, FrameJacobiansLocal, FramePlacement, FramePlacements,
    MassMatrixAndNonlinearEffects,
};

/// What the contact stepping of a generated chain needs: `mass_matrix_and_nonlinear_effects`,
/// `frame_placements` and `frame_jacobians_local`; implemented by every chain that has them.
pub trait ContactOutputs<const NQ: usize, const NV: usize, const NF: usize>:
    Chain<f64>
    + MassMatrixAndNonlinearEffects<f64, NQ, NV>
    + FramePlacements<f64, NQ, NV, NF>
    + FrameJacobiansLocal<f64, NQ, NV, NF>
{
}

impl<C, const NQ: usize, const NV: usize, const NF: usize> ContactOutputs<NQ, NV, NF> for C where
    C: Chain<f64>
        + MassMatrixAndNonlinearEffects<f64, NQ, NV>
        + FramePlacements<f64, NQ, NV, NF>
        + FrameJacobiansLocal<f64, NQ, NV, NF>
{
}

/// A ground: the half-space `n·x ≥ d`, `n` a unit normal towards the free side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    normal: Vector3<f64>,
    offset: f64,
}

impl Ground {
    /// The half-space `normal·x ≥ offset·‖normal‖` (the normal is made a unit vector, so
    /// `offset` is the plane's distance from the origin along it).
    ///
    /// # Errors
    /// [`ContactError::Ground`] for a normal that is zero or not finite, or an offset that is not
    /// finite.
    pub fn new(normal: [f64; 3], offset: f64) -> Result<Self, ContactError> {
        let n = Vector3::from(normal);
        let length = n.norm();
        if !(length.is_finite() && length > 0.0 && offset.is_finite()) {
            return Err(ContactError::Ground);
        }
        Ok(Ground {
            normal: n / length,
            offset,
        })
    }

    /// The half-space `normal·x ≥ offset` for a `normal` that is already a unit vector (what
    /// the generator emits for `grounds: […]`, having divided by its length); a constant.
    /// [`Ground::new`] takes any non-zero normal.
    pub const fn unit(normal: [f64; 3], offset: f64) -> Self {
        Ground {
            normal: Vector3::new(normal[0], normal[1], normal[2]),
            offset,
        }
    }

    /// The unit normal `n`.
    pub fn normal(&self) -> [f64; 3] {
        self.normal.into()
    }

    /// The offset `d`.
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// The signed distance `n·x − d` of a point from the plane (negative inside the ground).
    pub fn distance(&self, x: &[f64; 3]) -> f64 {
        self.normal.dot(&Vector3::from(*x)) - self.offset
    }
}

/// A contact sphere on a frame of the chain (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// The frame, an index into `Chain::FRAMES`.
    pub frame: usize,
    /// The centre in the frame's axes, from its origin (m).
    pub offset: [f64; 3],
    /// The radius (m), `0` for a point.
    pub radius: f64,
    /// The friction coefficient `μ ≥ 0` of its contacts.
    pub friction: f64,
    /// The restitution `e ∈ [0, 1]` of its contacts.
    pub restitution: f64,
}

impl Sphere {
    /// A point at the origin of frame `frame` with the friction coefficient `friction` and no
    /// restitution.
    pub fn point(frame: usize, friction: f64) -> Self {
        Sphere {
            frame,
            offset: [0.0; 3],
            radius: 0.0,
            friction,
            restitution: 0.0,
        }
    }

    /// Whether its numbers are usable: finite, radius and friction `≥ 0`, restitution in
    /// `[0, 1]`.
    fn valid(&self) -> bool {
        self.offset.iter().all(|x| x.is_finite())
            && self.radius.is_finite()
            && self.radius >= 0.0
            && self.friction.is_finite()
            && self.friction >= 0.0
            && (0.0..=1.0).contains(&self.restitution)
    }
}

/// A joint's position limits, held as unilateral constraints in the same contact problem (a
/// frictionless row `v_k ≥ ξ` at the lower limit, `−v_k ≥ ξ` at the upper, on the gap to it as
/// a contact's): a hard stop, where the drives' stops are springs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limit {
    /// The joint's position coordinate (an index into `q`).
    pub position: usize,
    /// Its velocity coordinate (an index into `v`).
    pub velocity: usize,
    /// The lower limit (`−∞` for none).
    pub lower: f64,
    /// The upper limit (`∞` for none).
    pub upper: f64,
}

/// The limits of a chain's one-coordinate joints (revolute, prismatic) that have any, from its
/// drives (`Chain::DRIVES`), into `out`; how many.
pub fn joint_limits(
    coordinates: &[Coordinates],
    drives: &[crate::Drive],
    out: &mut [Limit],
) -> usize {
    let (mut iq, mut iv, mut n) = (0, 0, 0);
    for (c, d) in coordinates.iter().zip(drives) {
        if *c == Coordinates::Vector(1) && (d.lower.is_finite() || d.upper.is_finite()) {
            if let Some(slot) = out.get_mut(n) {
                *slot = Limit {
                    position: iq,
                    velocity: iv,
                    lower: d.lower,
                    upper: d.upper,
                };
                n += 1;
            }
        }
        iq += c.nq();
        iv += c.nv();
    }
    n
}

/// How the contact problem of each step is solved (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The most Gauss–Seidel sweeps per step. Default `500`.
    pub max_iterations: usize,
    /// A step's solve stops when a sweep corrects no contact velocity by more than this (m/s).
    /// Default `1e-10`.
    pub tolerance: f64,
    /// The fraction `β` of a penetration pushed out per step. Default `0.2`.
    pub stabilization: f64,
    /// Pairs farther apart than this (m) are left out of a step. With speculative contacts a
    /// pair approaching faster than `margin/h` may pass through a ground. Default `0.01`.
    pub margin: f64,
    /// A pair approaching slower than this (m/s) does not bounce. Default `1e-3`.
    pub bounce_velocity: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_iterations: 500,
            tolerance: 1e-10,
            stabilization: 0.2,
            margin: 0.01,
            bounce_velocity: 1e-3,
        }
    }
}

/// Why a contact step gave no state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactError {
    /// More pairs are within the margin than the stepper holds.
    Capacity {
        /// The pairs within the margin.
        needed: usize,
        /// The stepper's capacity `P`.
        capacity: usize,
    },
    /// A sphere names a frame the chain does not generate.
    UnknownFrame {
        /// The sphere, by its index.
        sphere: usize,
        /// The frame index given.
        frame: usize,
        /// How many frames the chain generates (`NF`).
        frames: usize,
    },
    /// A sphere's numbers are unusable (not finite, a negative radius or friction, a
    /// restitution outside `[0, 1]`).
    Sphere {
        /// The sphere, by its index.
        sphere: usize,
    },
    /// A ground's normal is zero or not finite, or its offset not finite.
    Ground,
    /// `M` is not positive definite: a pivot of its factorization vanished.
    MassMatrix {
        /// The velocity coordinate whose pivot vanished.
        velocity: usize,
    },
    /// The state, the step, a torque or the dynamics at the state is not finite, or the step
    /// is not positive.
    NonFinite,
}

impl fmt::Display for ContactError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ContactError::Capacity { needed, capacity } => write!(
                f,
                "{needed} sphere–ground pairs are within the contact margin, but the stepper \
                 holds {capacity}"
            ),
            ContactError::UnknownFrame {
                sphere,
                frame,
                frames,
            } => write!(
                f,
                "sphere {sphere} is on frame {frame}, not one of the chain's {frames} generated \
                 frames"
            ),
            ContactError::Sphere { sphere } => write!(
                f,
                "sphere {sphere}: its offset and radius must be finite, its radius and friction \
                 at least 0 and its restitution within [0, 1]"
            ),
            ContactError::Ground => {
                write!(
                    f,
                    "a ground needs a finite, non-zero normal and a finite offset"
                )
            }
            ContactError::MassMatrix { velocity } => write!(
                f,
                "the mass matrix is not positive definite (pivot of velocity {velocity})"
            ),
            ContactError::NonFinite => write!(
                f,
                "the state, the step, a torque or the dynamics is not finite (or the step is \
                 not positive)"
            ),
        }
    }
}

impl core::error::Error for ContactError {}

/// What one step's contact solve did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepReport {
    /// The sphere–ground pairs within the margin (the contact problem's size).
    pub contacts: usize,
    /// The Gauss–Seidel sweeps made (`0` without contacts).
    pub iterations: usize,
    /// The largest velocity correction of the last sweep (m/s).
    pub residual: f64,
    /// Whether the residual fell to the tolerance.
    pub converged: bool,
}

/// One contact's force over the last step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce {
    /// The sphere, by its index.
    pub sphere: usize,
    /// The ground, by its index.
    pub ground: usize,
    /// The contact point (the sphere's lowest point towards the ground) at the step's start,
    /// world coordinates.
    pub point: [f64; 3],
    /// The signed distance from the ground at the step's start (m; negative: penetration).
    pub distance: f64,
    /// The force the ground exerts, world axes: the impulse over the step divided by its length
    /// (N).
    pub force: [f64; 3],
}

/// A sphere–ground pair within the margin: its rows, its response and its impulse.
#[derive(Clone, Debug)]
pub(crate) struct Pair<N: Dim>
where
    DefaultAllocator: Allocator<U3, N> + Allocator<N, U3>,
{
    sphere: usize,
    ground: usize,
    /// The contact basis, columns `(n, t₁, t₂)`.
    basis: Matrix3<f64>,
    point: Vector3<f64>,
    distance: f64,
    /// `J`: the contact point's velocity in the basis, `3 × nv`.
    jacobian: OMatrix<f64, U3, N>,
    /// `W = L⁻ᵀ·Jᵀ`, `nv × 3` (`M = Lᵀ·L`, so `J·M⁻¹·Jᵀ = Wᵀ·W`): non-zero only on the
    /// velocities that move the contact and their ancestors.
    response: OMatrix<f64, N, U3>,
    /// `J·v_f`, the contact's velocity without impulses.
    free: Vector3<f64>,
    /// The Delassus block `J·M⁻¹·Jᵀ`.
    block: Matrix3<f64>,
    /// Its inverse, where it has one.
    inverse: Option<Matrix3<f64>>,
    friction: f64,
    /// The normal target `ξ`.
    target: f64,
    /// The impulse `(λ_n, λ_t)`.
    impulse: Vector3<f64>,
    /// Its impulse over the step length, in the basis.
    step: f64,
}

impl<N: Dim> Pair<N>
where
    DefaultAllocator: Allocator<U3, N> + Allocator<N, U3>,
{
    fn zeros(n: N) -> Self {
        Pair {
            sphere: 0,
            ground: 0,
            basis: Matrix3::identity(),
            point: Vector3::zeros(),
            distance: 0.0,
            jacobian: OMatrix::zeros_generic(U3, n),
            response: OMatrix::zeros_generic(n, U3),
            free: Vector3::zeros(),
            block: Matrix3::zeros(),
            inverse: None,
            friction: 0.0,
            target: 0.0,
            impulse: Vector3::zeros(),
            step: 1.0,
        }
    }

    fn force(&self) -> ContactForce {
        ContactForce {
            sphere: self.sphere,
            ground: self.ground,
            point: self.point.into(),
            distance: self.distance,
            force: (self.basis * self.impulse / self.step).into(),
        }
    }
}

/// An orthonormal basis `(n, t₁, t₂)` with `n` first, `t₁` in the plane of `n` and the world
/// axis least aligned with it (a fixed choice, so a contact's tangent axes do not turn from one
/// step to the next).
fn basis(n: &Vector3<f64>) -> Matrix3<f64> {
    let (ax, ay, az) = (n.x.abs(), n.y.abs(), n.z.abs());
    let e = if ax <= ay && ax <= az {
        Vector3::x()
    } else if ay <= az {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let t1 = (e - n * n.dot(&e)).normalize();
    let t2 = n.cross(&t1);
    Matrix3::from_columns(&[*n, t1, t2])
}

/// The frames' kinematics a step reads: each frame's placement and LOCAL Jacobian.
pub(crate) struct FrameRows<'a, N: Dim>
where
    DefaultAllocator: Allocator<U6, N>,
{
    pub(crate) placements: &'a [FramePlacement<f64>],
    pub(crate) jacobians: &'a [OMatrix<f64, U6, N>],
}

/// The dynamics at the step's start.
pub(crate) struct Dynamics<'a, N: Dim>
where
    DefaultAllocator: Allocator<N, N> + Allocator<N>,
{
    pub(crate) m: &'a OMatrix<f64, N, N>,
    pub(crate) nle: &'a OVector<f64, N>,
    pub(crate) tau: &'a OVector<f64, N>,
    pub(crate) v: &'a OVector<f64, N>,
}

/// The scene and how to solve it.
pub(crate) struct Problem<'a, N: Dim>
where
    DefaultAllocator: Allocator<N>,
{
    pub(crate) coordinates: &'a [Coordinates],
    /// The joint limits held as unilateral rows, and the positions they are read from.
    pub(crate) limits: &'a [Limit],
    pub(crate) positions: &'a [f64],
    /// Each velocity's parent in `M`'s sparsity ([`Tree`]); `None`: dense.
    pub(crate) parents: Option<&'a [usize]>,
    /// Joint damping taken implicitly (`M + h·D`), one entry per velocity.
    pub(crate) damping: Option<&'a OVector<f64, N>>,
    pub(crate) grounds: &'a [Ground],
    pub(crate) spheres: &'a [Sphere],
    pub(crate) settings: &'a Settings,
    pub(crate) h: f64,
}

/// No parent.
const ROOT: usize = usize::MAX;

/// The `sphere` of a pair that is a joint limit.
const LIMIT: usize = usize::MAX;

/// `M`'s factorization `M = Lᵀ·L` along the kinematic tree (Featherstone 2005, "Efficient
/// factorization of the joint-space inertia matrix for branched kinematic trees", IJRR 24(6)):
/// with each velocity's parent `λ(i) < i`, the entries `M_ij` (`j < i`) that can be non-zero
/// are those of `i`'s ancestors `λ(i), λ(λ(i)), …`, and `L` has the same pattern, so the
/// factorization and the solves cost the sum over velocities of their depths (squared for the
/// factorization) rather than `nv³/6` and `nv²`: on the humanoid, whose legs and arms are
/// branches, a fraction. Without parents the chain is taken as one branch (`λ(i) = i − 1`):
/// the dense factorization.
struct Tree<'a> {
    parents: Option<&'a [usize]>,
}

impl Tree<'_> {
    /// `λ(i)`.
    fn parent(&self, i: usize) -> usize {
        match self.parents {
            Some(p) => p.get(i).copied().unwrap_or(ROOT),
            None => i.checked_sub(1).unwrap_or(ROOT),
        }
    }

    /// `L` (in the lower triangle, the pattern's entries) with `M = Lᵀ·L`, or the velocity
    /// whose pivot is not above `1e-10` times its unreduced value.
    fn factor<N: Dim>(&self, m: &OMatrix<f64, N, N>) -> Result<OMatrix<f64, N, N>, ContactError>
    where
        DefaultAllocator: Allocator<N, N>,
    {
        let n = m.nrows();
        if !finite(m.iter()) {
            return Err(ContactError::NonFinite);
        }
        let mut h = m.clone();
        for k in (0..n).rev() {
            let d = h[(k, k)];
            if !(d.is_finite() && d > 1e-10 * m[(k, k)].abs()) {
                return Err(ContactError::MassMatrix { velocity: k });
            }
            let a = libm::sqrt(d);
            h[(k, k)] = a;
            let mut i = self.parent(k);
            while i != ROOT {
                h[(k, i)] /= a;
                i = self.parent(i);
            }
            let mut i = self.parent(k);
            while i != ROOT {
                let hki = h[(k, i)];
                let mut j = i;
                while j != ROOT {
                    h[(i, j)] -= hki * h[(k, j)];
                    j = self.parent(j);
                }
                i = self.parent(i);
            }
        }
        Ok(h)
    }

    /// `M⁻¹·b = L⁻¹·L⁻ᵀ·b` from the factor.
    fn solve<N: Dim>(&self, l: &OMatrix<f64, N, N>, x: OVector<f64, N>) -> OVector<f64, N>
    where
        DefaultAllocator: Allocator<N, N> + Allocator<N>,
    {
        self.solve_lower(l, self.solve_transposed(l, x))
    }

    /// `L⁻ᵀ·b`: zero but on the entries of `b` and their ancestors.
    fn solve_transposed<N: Dim>(
        &self,
        l: &OMatrix<f64, N, N>,
        mut x: OVector<f64, N>,
    ) -> OVector<f64, N>
    where
        DefaultAllocator: Allocator<N, N> + Allocator<N>,
    {
        let n = x.nrows();
        // `Lᵀ·y = b`, from the leaves: each `y_i` is final once its descendants are done.
        for i in (0..n).rev() {
            if x[i] == 0.0 {
                continue;
            }
            x[i] /= l[(i, i)];
            let xi = x[i];
            let mut j = self.parent(i);
            while j != ROOT {
                x[j] -= l[(i, j)] * xi;
                j = self.parent(j);
            }
        }
        x
    }

    /// `L⁻¹·y`.
    fn solve_lower<N: Dim>(&self, l: &OMatrix<f64, N, N>, mut x: OVector<f64, N>) -> OVector<f64, N>
    where
        DefaultAllocator: Allocator<N, N> + Allocator<N>,
    {
        // `L·x = y`, from the root.
        for i in 0..x.nrows() {
            let mut s = x[i];
            let mut j = self.parent(i);
            while j != ROOT {
                s -= l[(i, j)] * x[j];
                j = self.parent(j);
            }
            x[i] = s / l[(i, i)];
        }
        x
    }
}

/// A configuration off every special pose: each coordinate from a fixed pseudo-random stream
/// (`seed`), quaternions made unit.
fn sample_configuration(coordinates: &[Coordinates], seed: u64, q: &mut [f64]) {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        // 53 bits into [-1, 1).
        (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    for x in q.iter_mut() {
        *x = next();
    }
    crate::configuration::normalize(coordinates, q);
}

/// Each velocity's parent `λ(i)` in the sparsity of `M` ([`Tree`]), read from `M` at a few
/// configurations (an entry zero at all of them is zero at every configuration: the coupling
/// of two branches, or of a free base's linear velocities). The pattern is first filled as the
/// factorization `M = Lᵀ·L` fills it (eliminating `k` couples every pair of its non-zeros
/// `i, j < k`); then `λ(i)` is the last `j < i` of row `i`, and `false` says that some other
/// entry of the row is not on `i`'s line of ancestors (coordinates not in tree order), where
/// the dense factorization is used.
pub(crate) fn tree_parents<N: Dim>(samples: &[OMatrix<f64, N, N>], parents: &mut [usize]) -> bool
where
    DefaultAllocator: Allocator<N, N>,
{
    let Some(first) = samples.first() else {
        return false;
    };
    let n = parents.len();
    if first.shape() != (n, n) {
        return false;
    }
    let mut pattern = first.map(|_| false);
    for m in samples {
        pattern.zip_apply(m, |p, x| *p |= x != 0.0);
    }
    for k in (0..n).rev() {
        for i in 0..k {
            if pattern[(k, i)] {
                for j in 0..i {
                    if pattern[(k, j)] {
                        pattern[(i, j)] = true;
                    }
                }
            }
        }
    }
    for (i, parent) in parents.iter_mut().enumerate() {
        *parent = (0..i).rev().find(|&j| pattern[(i, j)]).unwrap_or(ROOT);
    }
    let tree = Tree {
        parents: Some(parents),
    };
    let on_line = |i: usize, k: usize| {
        let mut a = tree.parent(i);
        while a != ROOT {
            if a == k {
                return true;
            }
            a = tree.parent(a);
        }
        false
    };
    (0..n).all(|i| (0..i).all(|k| !pattern[(i, k)] || on_line(i, k)))
}

/// Checks every sphere against `frames` generated frames.
pub(crate) fn check_scene(spheres: &[Sphere], frames: usize) -> Result<(), ContactError> {
    for (i, s) in spheres.iter().enumerate() {
        if s.frame >= frames {
            return Err(ContactError::UnknownFrame {
                sphere: i,
                frame: s.frame,
                frames,
            });
        }
        if !s.valid() {
            return Err(ContactError::Sphere { sphere: i });
        }
    }
    Ok(())
}

/// One step's velocities `v⁺` (module docs): the pairs within the margin go into `pairs` (their
/// count returned with the report), warm-started from `warm` (the last step's pairs and
/// impulses).
pub(crate) fn step_velocity<N: Dim>(
    dynamics: &Dynamics<'_, N>,
    frames: &FrameRows<'_, N>,
    problem: &Problem<'_, N>,
    pairs: &mut [Pair<N>],
    warm: &[(usize, usize, Vector3<f64>)],
) -> Result<(OVector<f64, N>, usize, StepReport), ContactError>
where
    DefaultAllocator: Allocator<N, N>
        + Allocator<N>
        + Allocator<U3, N>
        + Allocator<N, U3>
        + Allocator<U6, N>
        + Allocator<U3>,
{
    let tree = Tree {
        parents: problem.parents,
    };
    let (l, mut v_plus) = free_velocity(&tree, dynamics, problem)?;
    let inputs = PairInputs {
        tree: &tree,
        l: &l,
        v: dynamics.v,
        v_plus: &v_plus,
        h: problem.h,
        settings: problem.settings,
        warm,
    };
    let mut slots = Slots {
        pairs,
        count: 0,
        needed: 0,
    };
    sphere_pairs(frames, problem, &inputs, &mut slots)?;
    limit_pairs(problem, &inputs, &mut slots)?;
    let Slots {
        pairs,
        count,
        needed,
    } = slots;
    if needed > pairs.len() {
        return Err(ContactError::Capacity {
            needed,
            capacity: pairs.len(),
        });
    }
    let active = pairs.get_mut(..count).unwrap_or_default();
    let (report, z) = solve_impulses(active, dynamics.v.map(|_| 0.0), problem.settings)?;
    if count > 0 {
        v_plus += tree.solve_lower(&l, z);
    }
    if !finite(v_plus.iter()) {
        return Err(ContactError::NonFinite);
    }
    Ok((v_plus, count, report))
}

/// `(L, v_f)`: [`free_velocity`]'s factor and free velocity.
type Free<N> = (OMatrix<f64, N, N>, OVector<f64, N>);

/// `M + h·D` factored along the tree, and the free velocity `v_f = v + h·M⁻¹·(τ − nle)` with
/// each free base's turning axes taken exactly (module docs).
fn free_velocity<N: Dim>(
    tree: &Tree<'_>,
    dynamics: &Dynamics<'_, N>,
    problem: &Problem<'_, N>,
) -> Result<Free<N>, ContactError>
where
    DefaultAllocator: Allocator<N, N> + Allocator<N>,
{
    let Dynamics { m, nle, tau, v } = *dynamics;
    let h = problem.h;
    if !(h.is_finite() && h > 0.0 && finite(v.iter()) && finite(nle.iter()) && finite(tau.iter())) {
        return Err(ContactError::NonFinite);
    }
    let mut m = m.clone();
    if let Some(d) = problem.damping {
        if d.len() != v.len() || !finite(d.iter()) || d.iter().any(|d| *d < 0.0) {
            return Err(ContactError::NonFinite);
        }
        for (k, d) in d.iter().enumerate() {
            if let Some(e) = m.get_mut((k, k)) {
                *e += h * d;
            }
        }
    }
    let l = tree.factor(&m)?;
    let mut v_plus = v + tree.solve(&l, tau - nle) * h;
    for at in free_bases(problem.coordinates) {
        if let (Some(u), Some(w)) = (vector3(v, at), vector3(v, at + 3)) {
            let free = vector3(&v_plus, at).unwrap_or(u) + w.cross(&u) * h;
            set3(&mut v_plus, at, free);
        }
    }
    Ok((l, v_plus))
}

/// The pairs of a step as they are found: `count` filled, `needed` within the margin (more than
/// the capacity is an error once all are counted).
struct Slots<'p, N: Dim>
where
    DefaultAllocator: Allocator<U3, N> + Allocator<N, U3>,
{
    pairs: &'p mut [Pair<N>],
    count: usize,
    needed: usize,
}

impl<N: Dim> Slots<'_, N>
where
    DefaultAllocator: Allocator<U3, N> + Allocator<N, U3>,
{
    /// The next pair to fill, `None` past the capacity (still counted as needed).
    fn next(&mut self) -> Option<&mut Pair<N>> {
        self.needed += 1;
        let pair = self.pairs.get_mut(self.count)?;
        self.count += 1;
        Some(pair)
    }
}

/// What completes a pair once its rows `J` are set.
struct PairInputs<'a, N: Dim>
where
    DefaultAllocator: Allocator<N, N> + Allocator<N>,
{
    tree: &'a Tree<'a>,
    l: &'a OMatrix<f64, N, N>,
    v: &'a OVector<f64, N>,
    v_plus: &'a OVector<f64, N>,
    h: f64,
    settings: &'a Settings,
    warm: &'a [(usize, usize, Vector3<f64>)],
}

impl<N: Dim> PairInputs<'_, N>
where
    DefaultAllocator:
        Allocator<N, N> + Allocator<N> + Allocator<U3, N> + Allocator<N, U3> + Allocator<U3>,
{
    /// A pair's response `W`, Delassus block, free velocity, normal target (module docs) and
    /// warm start, from its rows, distance and friction.
    fn finish(&self, pair: &mut Pair<N>, restitution: f64) -> Result<(), ContactError> {
        let (h, settings) = (self.h, self.settings);
        for c in 0..3 {
            let column = self
                .tree
                .solve_transposed(self.l, pair.jacobian.row(c).transpose());
            pair.response.set_column(c, &column);
        }
        pair.block = pair.response.tr_mul(&pair.response);
        pair.free = &pair.jacobian * self.v_plus;
        pair.inverse = pair.block.try_inverse();
        pair.step = h;
        let approach = pair.jacobian.row(0).tr_dot(self.v);
        let distance = pair.distance;
        let mut target = if distance >= 0.0 {
            -distance / h
        } else {
            -settings.stabilization * distance / h
        };
        if restitution > 0.0
            && approach < -settings.bounce_velocity
            && distance + h * pair.free.x < 0.0
        {
            target = target.max(-restitution * approach);
        }
        pair.target = target;
        pair.impulse = self
            .warm
            .iter()
            .find(|(ws, wg, _)| *ws == pair.sphere && *wg == pair.ground)
            .map_or(Vector3::zeros(), |(_, _, impulse)| {
                cone(impulse, pair.friction)
            });
        if finite(pair.block.iter()) {
            Ok(())
        } else {
            Err(ContactError::NonFinite)
        }
    }
}

/// The sphere–ground pairs within the margin.
fn sphere_pairs<N: Dim>(
    frames: &FrameRows<'_, N>,
    problem: &Problem<'_, N>,
    inputs: &PairInputs<'_, N>,
    slots: &mut Slots<'_, N>,
) -> Result<(), ContactError>
where
    DefaultAllocator: Allocator<N, N>
        + Allocator<N>
        + Allocator<U3, N>
        + Allocator<N, U3>
        + Allocator<U6, N>
        + Allocator<U3>,
{
    for (s, sphere) in problem.spheres.iter().enumerate() {
        let (Some(placement), Some(j)) = (
            frames.placements.get(sphere.frame),
            frames.jacobians.get(sphere.frame),
        ) else {
            return Err(ContactError::NonFinite);
        };
        let arm = placement.rotation * Vector3::from(sphere.offset);
        let centre = placement.translation + arm;
        for (g, ground) in problem.grounds.iter().enumerate() {
            let n = ground.normal;
            let distance = n.dot(&centre) - ground.offset - sphere.radius;
            if !distance.is_finite() {
                return Err(ContactError::NonFinite);
            }
            if distance > problem.settings.margin {
                continue;
            }
            let Some(pair) = slots.next() else {
                continue;
            };
            // The point's world velocity: `R·v_o + (R·ω) × δ`, `δ` from the frame's origin to
            // the point, so `J_c = R·J_v − [δ]×·R·J_ω`.
            let delta = arm - n * sphere.radius;
            let b = basis(&n);
            let turned_v = placement.rotation * j.fixed_rows::<3>(3);
            let turned_w = placement.rotation * j.fixed_rows::<3>(0);
            let world = turned_v - delta.cross_matrix() * turned_w;
            pair.jacobian = b.transpose() * world;
            pair.sphere = s;
            pair.ground = g;
            pair.basis = b;
            pair.point = centre - n * sphere.radius;
            pair.distance = distance;
            pair.friction = sphere.friction;
            inputs.finish(pair, sphere.restitution)?;
        }
    }
    Ok(())
}

/// The joints near a limit: one frictionless row each, `±v_k ≥ ξ` on the gap to the limit.
fn limit_pairs<N: Dim>(
    problem: &Problem<'_, N>,
    inputs: &PairInputs<'_, N>,
    slots: &mut Slots<'_, N>,
) -> Result<(), ContactError>
where
    DefaultAllocator:
        Allocator<N, N> + Allocator<N> + Allocator<U3, N> + Allocator<N, U3> + Allocator<U3>,
{
    for (k, limit) in problem.limits.iter().enumerate() {
        let Some(&position) = problem.positions.get(limit.position) else {
            return Err(ContactError::NonFinite);
        };
        for (side, gap, sign) in [
            (0, position - limit.lower, 1.0),
            (1, limit.upper - position, -1.0),
        ] {
            if gap.is_nan() {
                return Err(ContactError::NonFinite);
            }
            if gap > problem.settings.margin {
                continue;
            }
            let Some(pair) = slots.next() else {
                continue;
            };
            pair.jacobian.fill(0.0);
            if let Some(e) = pair.jacobian.get_mut((0, limit.velocity)) {
                *e = sign;
            }
            pair.sphere = LIMIT;
            pair.ground = 2 * k + side;
            pair.basis = Matrix3::identity() * sign;
            pair.point = Vector3::zeros();
            pair.distance = gap;
            pair.friction = 0.0;
            inputs.finish(pair, 0.0)?;
        }
    }
    Ok(())
}

/// Gauss–Seidel sweeps over the `active` pairs until the tolerance or the most sweeps: the
/// report and `z = Σ Wᵢ·λᵢ` (so that `v⁺ = v_f + L⁻¹·z`), `z` starting from `zero`.
fn solve_impulses<N: Dim>(
    active: &mut [Pair<N>],
    zero: OVector<f64, N>,
    settings: &Settings,
) -> Result<(StepReport, OVector<f64, N>), ContactError>
where
    DefaultAllocator: Allocator<N> + Allocator<U3, N> + Allocator<N, U3> + Allocator<U3>,
{
    let mut z = zero;
    for pair in active.iter() {
        z += &pair.response * pair.impulse;
    }
    let mut report = StepReport {
        contacts: active.len(),
        iterations: 0,
        residual: 0.0,
        converged: active.is_empty(),
    };
    while !report.converged && report.iterations < settings.max_iterations {
        report.iterations += 1;
        report.residual = sweep(active, &mut z);
        if !report.residual.is_finite() {
            return Err(ContactError::NonFinite);
        }
        report.converged = report.residual <= settings.tolerance;
    }
    Ok((report, z))
}

/// The velocity offsets of the free bases with a quaternion among `coordinates`.
fn free_bases(coordinates: &[Coordinates]) -> impl Iterator<Item = usize> + '_ {
    coordinates
        .iter()
        .scan(0, |at, c| {
            let start = *at;
            *at += c.nv();
            Some((start, *c))
        })
        .filter(|(_, c)| *c == Coordinates::FreeQuaternion)
        .map(|(at, _)| at)
}

/// Entries `at..at + 3` of `v`.
fn vector3<N: Dim>(v: &OVector<f64, N>, at: usize) -> Option<Vector3<f64>>
where
    DefaultAllocator: Allocator<N>,
{
    Some(Vector3::new(*v.get(at)?, *v.get(at + 1)?, *v.get(at + 2)?))
}

/// Sets entries `at..at + 3` of `v` (those that exist).
fn set3<N: Dim>(v: &mut OVector<f64, N>, at: usize, x: Vector3<f64>)
where
    DefaultAllocator: Allocator<N>,
{
    for (k, x) in x.iter().enumerate() {
        if let Some(e) = v.get_mut(at + k) {
            *e = *x;
        }
    }
}

/// `v⁺` after `q ⊕ h·v⁺`: each free base's linear velocity, given in its axes at `q`, carried
/// into its axes at `q⁺` (turned by `exp(−h·ω⁺)`).
pub(crate) fn carry_free_bases<N: Dim>(coordinates: &[Coordinates], v: &mut OVector<f64, N>, h: f64)
where
    DefaultAllocator: Allocator<N>,
{
    for at in free_bases(coordinates) {
        if let (Some(u), Some(w)) = (vector3(v, at), vector3(v, at + 3)) {
            let turn = crate::configuration::quat_exp((w * -h).into());
            set3(
                v,
                at,
                crate::configuration::quat_rotate(turn, u.into()).into(),
            );
        }
    }
}

/// Whether every entry is finite.
fn finite<'a>(mut x: impl Iterator<Item = &'a f64>) -> bool {
    x.all(|x| x.is_finite())
}

/// `λ` moved into its cone: `λ_n ≥ 0`, `‖λ_t‖ ≤ μ·λ_n`.
fn cone(impulse: &Vector3<f64>, friction: f64) -> Vector3<f64> {
    let n = impulse.x.max(0.0);
    let t = disk(impulse.y, impulse.z, friction * n);
    Vector3::new(n, t.0, t.1)
}

/// The projection onto the cone `‖t‖ ≤ μ·n` of `(n, t)`.
fn cone_projection(x: &Vector3<f64>, mu: f64) -> Vector3<f64> {
    let t = libm::hypot(x.y, x.z);
    if mu * t <= -x.x {
        Vector3::zeros()
    } else if t <= mu * x.x {
        *x
    } else if t == 0.0 {
        Vector3::zeros()
    } else {
        let n = (x.x + mu * t) / (1.0 + mu * mu);
        Vector3::new(n, mu * n * x.y / t, mu * n * x.z / t)
    }
}

/// `(x, y)` moved into the disk of radius `r`.
fn disk(x: f64, y: f64, r: f64) -> (f64, f64) {
    let norm = libm::hypot(x, y);
    if norm <= r {
        (x, y)
    } else if norm > 0.0 {
        (x * r / norm, y * r / norm)
    } else {
        (0.0, 0.0)
    }
}

/// One projected Gauss–Seidel sweep over the pairs (module docs), `v⁺` kept up to date; the
/// largest velocity correction it made.
fn sweep<N: Dim>(pairs: &mut [Pair<N>], z: &mut OVector<f64, N>) -> f64
where
    DefaultAllocator: Allocator<N> + Allocator<U3, N> + Allocator<N, U3> + Allocator<U3>,
{
    let mut residual: f64 = 0.0;
    for pair in pairs.iter_mut() {
        let g = &pair.block;
        let u: Vector3<f64> = pair.free + pair.response.tr_mul(z);
        let before = pair.impulse;
        // Sticking: the block's solve, kept where it lies inside the cone (the contact's three
        // rows at once converge faster than one after the other).
        let error = u - Vector3::new(pair.target, 0.0, 0.0);
        if let Some(inverse) = pair.inverse {
            let stick = before - inverse * error;
            if stick.x >= 0.0 && libm::hypot(stick.y, stick.z) <= pair.friction * stick.x {
                residual = residual.max(error.amax());
                *z += &pair.response * (stick - before);
                pair.impulse = stick;
                continue;
            }
        }
        // Else one projected step on the whole contact, on De Saxcé's modified velocity
        // `û = u − ξ·n + μ·‖u_t‖·n` (its fixed points are the exact Coulomb law):
        // `λ ← proj_K(λ − û/α)`, `α ≥` the block's largest eigenvalue (its largest absolute
        // row sum).
        let alpha = (0..3)
            .map(|r| g.row(r).iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let slip = libm::hypot(error.y, error.z);
        let modified = error + Vector3::new(pair.friction * slip, 0.0, 0.0);
        let after = cone_projection(&(before - modified / alpha), pair.friction);
        residual = residual.max(alpha * (after - before).amax());
        *z += &pair.response * (after - before);
        pair.impulse = after;
    }
    residual
}

/// A generated chain stepped with contacts (module docs), under `controller(t, q, v) → τ`;
/// `P` the most sphere–ground pairs within the margin at once.
pub struct TimeStepper<'a, C, F, const NQ: usize, const NV: usize, const NF: usize, const P: usize>
{
    grounds: &'a [Ground],
    spheres: &'a [Sphere],
    settings: Settings,
    controller: F,
    pairs: [Pair<nalgebra::Const<NV>>; P],
    count: usize,
    warm: [(usize, usize, Vector3<f64>); P],
    /// `M`'s tree ([`Tree`]), `None` where it is not in tree order.
    parents: Option<[usize; NV]>,
    /// The joint limits held ([`TimeStepper::hold_joint_limits`]), the first `limit_count`.
    limits: [Limit; NV],
    limit_count: usize,
    damping: Option<SVector<f64, NV>>,
    chain: core::marker::PhantomData<fn() -> C>,
    positions: core::marker::PhantomData<[f64; NQ]>,
}

impl<'a, C, F, const NQ: usize, const NV: usize, const NF: usize, const P: usize>
    TimeStepper<'a, C, F, NQ, NV, NF, P>
where
    C: ContactOutputs<NQ, NV, NF>,
    F: FnMut(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>,
{
    /// The chain among `grounds` with `spheres` on its frames, solved with `settings`.
    ///
    /// # Errors
    /// [`ContactError::UnknownFrame`] or [`ContactError::Sphere`] for a sphere that cannot be
    /// used.
    pub fn new(
        grounds: &'a [Ground],
        spheres: &'a [Sphere],
        settings: Settings,
        controller: F,
    ) -> Result<Self, ContactError> {
        check_scene(spheres, NF)?;
        // `M`'s sparsity from two configurations off every special pose.
        let samples = [1, 2].map(|seed| {
            let mut q = SVector::<f64, NQ>::zeros();
            sample_configuration(C::COORDINATES, seed, q.as_mut_slice());
            C::mass_matrix_and_nonlinear_effects(&q, &SVector::zeros()).0
        });
        let mut parents = [ROOT; NV];
        let tree = tree_parents(&samples, &mut parents);
        Ok(TimeStepper {
            parents: tree.then_some(parents),
            limits: [Limit {
                position: 0,
                velocity: 0,
                lower: f64::NEG_INFINITY,
                upper: f64::INFINITY,
            }; NV],
            limit_count: 0,
            damping: None,
            grounds,
            spheres,
            settings,
            controller,
            pairs: core::array::from_fn(|_| Pair::zeros(nalgebra::Const::<NV>)),
            count: 0,
            warm: [(usize::MAX, usize::MAX, Vector3::zeros()); P],
            chain: core::marker::PhantomData,
            positions: core::marker::PhantomData,
        })
    }

    /// Steps `state` by `h` (module docs); the state is left as it was on an error.
    ///
    /// # Errors
    /// [`ContactError::NonFinite`], [`ContactError::MassMatrix`], [`ContactError::Capacity`].
    pub fn step(
        &mut self,
        state: &mut State<f64, nalgebra::Const<NQ>, nalgebra::Const<NV>>,
        h: f64,
    ) -> Result<StepReport, ContactError> {
        if !state.q.iter().all(|x| x.is_finite()) {
            return Err(ContactError::NonFinite);
        }
        let tau = (self.controller)(state.t, &state.q, &state.v);
        let (m, nle) = C::mass_matrix_and_nonlinear_effects(&state.q, &state.v);
        let placements = C::frame_placements(&state.q);
        let jacobians: [SMatrix<f64, 6, NV>; NF] = C::frame_jacobians_local(&state.q);
        for (w, pair) in self.warm.iter_mut().zip(&self.pairs).take(self.count) {
            *w = (pair.sphere, pair.ground, pair.impulse);
        }
        let warm = self.warm.get(..self.count).unwrap_or_default();
        let (v_plus, count, report) = step_velocity(
            &Dynamics {
                m: &m,
                nle: &nle,
                tau: &tau,
                v: &state.v,
            },
            &FrameRows {
                placements: &placements,
                jacobians: &jacobians,
            },
            &Problem {
                coordinates: C::COORDINATES,
                limits: self.limits.get(..self.limit_count).unwrap_or_default(),
                positions: state.q.as_slice(),
                parents: self.parents.as_ref().map(|p| p.as_slice()),
                damping: self.damping.as_ref(),
                grounds: self.grounds,
                spheres: self.spheres,
                settings: &self.settings,
                h,
            },
            &mut self.pairs,
            warm,
        )?;
        self.count = count;
        state.q = crate::configuration::integrate(C::COORDINATES, &state.q, &(v_plus * h));
        state.v = v_plus;
        carry_free_bases(C::COORDINATES, &mut state.v, h);
        state.t += h;
        Ok(report)
    }

    /// The contacts of the last step and their forces.
    pub fn forces(&self) -> impl Iterator<Item = ContactForce> + '_ {
        self.pairs
            .iter()
            .take(self.count)
            .filter(|p| p.sphere != LIMIT)
            .map(Pair::force)
    }

    /// The joint limits that held in the last step: each one's velocity coordinate and the
    /// generalized force it exerted over the step (N·m or N; positive pushes the coordinate
    /// up, off its lower limit).
    pub fn limit_forces(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        let limits = &self.limits;
        self.pairs
            .iter()
            .take(self.count)
            .filter(|p| p.sphere == LIMIT)
            .filter_map(move |p| {
                let limit = limits.get(p.ground / 2)?;
                let sign = if p.ground % 2 == 0 { 1.0 } else { -1.0 };
                Some((limit.velocity, sign * p.impulse.x / p.step))
            })
    }

    /// Holds the joints' position limits (`Chain::DRIVES`: the `.chain` joints' `lower` and
    /// `upper`, a URDF's `<limit>`) as unilateral constraints in the contact problem; off by
    /// default, as the drives' stops are. The pairs near a limit count against `P`.
    pub fn hold_joint_limits(&mut self) {
        self.limit_count = joint_limits(C::COORDINATES, C::DRIVES, &mut self.limits);
    }

    /// Joint damping `τ = −d·v` taken implicitly, one coefficient per velocity (N·s/m or
    /// N·m·s/rad): the step solves with `M + h·diag(d)` (as MuJoCo's joint damping), so a
    /// damper far stiffer than `M/h` stays stable, where given to the controller it would make
    /// light links diverge.
    ///
    /// # Errors
    /// [`ContactError::NonFinite`] for a coefficient that is negative or not finite.
    pub fn set_damping(&mut self, damping: SVector<f64, NV>) -> Result<(), ContactError> {
        if !damping.iter().all(|d| d.is_finite() && *d >= 0.0) {
            return Err(ContactError::NonFinite);
        }
        self.damping = Some(damping);
        Ok(())
    }

    /// Whether `M` is factored along the chain's tree (else densely): what the sparsity of
    /// `M` at two configurations says.
    pub fn factors_along_the_tree(&self) -> bool {
        self.parents.is_some()
    }

    /// The controller, to change its gains or read its state.
    pub fn controller_mut(&mut self) -> &mut F {
        &mut self.controller
    }
}

/// The same stepping at run-time sizes, for a chain evaluated by other means than generated
/// code (the CLI's interpreted reference).
#[cfg(feature = "alloc")]
pub mod dynamic {
    use alloc::vec::Vec;

    use nalgebra::{DMatrix, DVector, Dyn, Matrix6xX, Vector3};

    use super::{
        step_velocity, ContactError, ContactForce, Dynamics, FrameRows, Ground, Pair, Problem,
        Settings, Sphere, StepReport,
    };
    use crate::{Coordinates, FramePlacement};

    /// The pairs of the last step, their impulses kept to start the next.
    #[derive(Clone, Debug, Default)]
    pub struct TimeStepper {
        pairs: Vec<Pair<Dyn>>,
        count: usize,
    }

    /// A state's dynamics and the frames' kinematics, as the caller computed them.
    pub struct At<'a> {
        /// `M(q)`.
        pub m: &'a DMatrix<f64>,
        /// `nle = N·q̇ + g`.
        pub nle: &'a DVector<f64>,
        /// The torques.
        pub tau: &'a DVector<f64>,
        /// Each frame's placement (the spheres' frames index them).
        pub placements: &'a [FramePlacement<f64>],
        /// Each frame's LOCAL Jacobian.
        pub jacobians: &'a [Matrix6xX<f64>],
        /// Joint damping taken implicitly, one entry per velocity (N·s/m or N·m·s/rad).
        pub damping: Option<&'a DVector<f64>>,
        /// Joint limits held as unilateral constraints ([`super::joint_limits`]).
        pub limits: &'a [super::Limit],
    }

    impl TimeStepper {
        /// No contact yet.
        pub fn new() -> Self {
            Self::default()
        }

        /// Steps `(q, v)` by `h` from the dynamics `at` there, `coordinates` saying how `q`
        /// moves (module docs); `q` and `v` are left as they were on an error.
        ///
        /// # Errors
        /// As [`super::TimeStepper::step`], and [`ContactError::UnknownFrame`] or
        /// [`ContactError::Sphere`] for a sphere that cannot be used.
        #[allow(clippy::too_many_arguments)]
        pub fn step(
            &mut self,
            coordinates: &[Coordinates],
            q: &mut DVector<f64>,
            v: &mut DVector<f64>,
            at: &At<'_>,
            grounds: &[Ground],
            spheres: &[Sphere],
            settings: &Settings,
            h: f64,
        ) -> Result<StepReport, ContactError> {
            super::check_scene(spheres, at.placements.len().min(at.jacobians.len()))?;
            let nv = v.len();
            let sizes = at.m.shape() == (nv, nv)
                && at.nle.len() == nv
                && at.tau.len() == nv
                && at.jacobians.iter().all(|j| j.ncols() == nv);
            if !sizes || !q.iter().all(|x| x.is_finite()) {
                return Err(ContactError::NonFinite);
            }
            let warm: Vec<(usize, usize, Vector3<f64>)> = self
                .pairs
                .iter()
                .take(self.count)
                .map(|p| (p.sphere, p.ground, p.impulse))
                .collect();
            let capacity = spheres.len() * grounds.len() + 2 * at.limits.len();
            self.pairs.resize_with(capacity, || Pair::zeros(Dyn(nv)));
            let (v_plus, count, report) = step_velocity(
                &Dynamics {
                    m: at.m,
                    nle: at.nle,
                    tau: at.tau,
                    v,
                },
                &FrameRows {
                    placements: at.placements,
                    jacobians: at.jacobians,
                },
                &Problem {
                    coordinates,
                    limits: at.limits,
                    positions: q.as_slice(),
                    parents: None,
                    damping: at.damping,
                    grounds,
                    spheres,
                    settings,
                    h,
                },
                &mut self.pairs,
                &warm,
            )?;
            self.count = count;
            crate::configuration::integrate_in_place(
                coordinates,
                q.as_mut_slice(),
                (&v_plus * h).as_slice(),
            );
            *v = v_plus;
            super::carry_free_bases(coordinates, v, h);
            Ok(report)
        }

        /// The contacts of the last step and their forces.
        pub fn forces(&self) -> impl Iterator<Item = ContactForce> + '_ {
            self.pairs
                .iter()
                .take(self.count)
                .filter(|p| p.sphere != super::LIMIT)
                .map(Pair::force)
        }
    }
}
