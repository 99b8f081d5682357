//! The traits a generated chain implements, and what its code needs at run time.
//!
//! For a chain `C` with `NQ` positions and `NV` velocities, `chain!{}` or `#[derive(Chain)]`
//! emits a type `C` with the constants `C::NQ`, `C::NV` and one `C::<OUTPUT>_OPS` per generated
//! function (an [`OpCounts`]), and implements [`Chain`] plus one trait per requested output:
//!
//! | trait | function | what it computes |
//! |---|---|---|
//! | [`MassMatrix`] | `C::mass_matrix(&q)` | `M(q)`, `NV × NV` |
//! | [`MassMatrixUpdate`] | `C::mass_matrix_update(&q, &mut kept)` | `M(q)` into a [`KeptMassMatrix`] |
//! | [`MassMatrixLower`] | `C::mass_matrix_lower(&q, &mut kept)` | `M(q)`'s lower triangle into a [`KeptMassMatrixLower`] |
//! | [`Bias`] | `C::bias(&q, &v)` | `N(q, q̇)·q̇`, the velocity-product terms, **without gravity** |
//! | [`Gravity`] | `C::gravity(&q)` | `g(q)`, the generalized force that holds the chain still |
//! | [`InverseDynamics`] | `C::inverse_dynamics(&q, &v, &a)` | `τ = M·a + N·q̇ + g` |
//! | [`ForwardDynamics`] | `C::forward_dynamics(&q, &v, &tau)` | `q̈`, or [`SingularMassMatrix`] |
//! | [`NonlinearEffects`] | `C::nonlinear_effects(&q, &v)` | `N·q̇ + g` in one pass |
//! | [`MassMatrixAndNonlinearEffects`] | `C::mass_matrix_and_nonlinear_effects(&q, &v)` | both, the kinematics shared |
//! | [`JointWrenches`] | `C::joint_wrenches(&q, &v, &a)` | each joint's wrench, `6 × NB` |
//! | [`JointWrenchesBottomUp`] | `C::joint_wrenches_bottom_up(&q, &v, &a, &base)` | the same from a base wrench up |
//! | [`CenterOfMass`] | `C::center_of_mass(&q)` | `x_G`, world frame |
//! | [`CenterOfMassVelocity`] | `C::center_of_mass_velocity(&q, &v)` | `ẋ_G` |
//! | [`CenterOfMassJacobian`] | `C::center_of_mass_jacobian(&q)` | `J_G`, `3 × NV` |
//! | [`CentroidalMomentum`] | `C::centroidal_momentum(&q, &v)` | `[k_G; p]`, world axes, about the centre of mass |
//! | [`CentroidalMomentumMatrix`] | `C::centroidal_momentum_matrix(&q)` | `A_G`, `6 × NV` |
//! | [`KineticEnergy`] | `C::kinetic_energy(&q, &v)` | `½·vᵀ·M·v` |
//! | [`PotentialEnergy`] | `C::potential_energy(&q)` | `−Σ m_k·gᵀ·x_k` |
//! | [`CoriolisMatrix`] | `C::coriolis_matrix(&q, &v)` | `N(q, q̇)` with `N·v = bias`, `Ṁ − 2N` skew |
//! | [`InverseDynamicsDerivatives`] | `C::inverse_dynamics_derivatives(&q, &v, &a)` | `(∂τ/∂q, ∂τ/∂v)`, `NV × NV` each |
//! | [`ForwardDynamicsDerivatives`] | `C::forward_dynamics_derivatives(&q, &v, &tau)` | `(∂q̈/∂q, ∂q̈/∂v, M⁻¹)`, or [`SingularMassMatrix`] |
//! | [`MassMatrixInverse`] | `C::mass_matrix_inverse(&q)` | `M(q)⁻¹`, or [`SingularMassMatrix`] |
//!
//! Derivatives with respect to `q` are taken along the configuration's tangent, `NV` columns
//! wide: `∂/∂δ_k` of `q ⊕ δ` ([`crate::control::tangent::retract`]), which is `∂/∂q_k` for
//! revolute, prismatic and Euler-angle coordinates, the body-frame increment `q ⊗ exp(δ/2)` for
//! a quaternion, and for a free quaternion base also the position moved by `R(q)·δ_lin`: the
//! convention of Pinocchio's `computeRNEADerivatives` and `computeABADerivatives`.
//!
//! Each takes and returns nalgebra fixed-size types and allocates nothing. A chain with runtime
//! parameters takes them through the `_with` twin of each function (`C::mass_matrix_with(&q,
//! &params)`); the plain function uses the defaults from the description.
//!
//! # Non-finite inputs
//! The functions that solve with `M` (forward dynamics, its derivatives, `M⁻¹`) return
//! `Err(SingularMassMatrix)` when a pivot or a result is not finite, so a NaN or an infinity in
//! `q`, `v`, `τ` or a parameter comes back as that error, never as a value. The others are
//! straight-line arithmetic with no check on the hot path: a NaN or an infinity in their inputs
//! propagates to their outputs as IEEE arithmetic has it (NaN in, NaN out), and finite inputs
//! give finite outputs (the generator refuses models whose numbers overflow `f64`). Inputs that
//! arrive as slices go through [`vector`] (an error for a wrong length); the integrators stop
//! with a [`crate::integrate::Fault`] naming the time, the step and the first non-finite value.

use core::fmt;

use nalgebra::{SMatrix, SVector};

use crate::Drive;

pub use articulated_dynamics::OpCounts;

/// A slice whose length is not the size a generated function takes ([`vector`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LengthMismatch {
    /// The length the function takes (`NQ` or `NV`).
    pub expected: usize,
    /// The slice's length.
    pub found: usize,
}

impl fmt::Display for LengthMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "expected {} entries, found {}",
            self.expected, self.found
        )
    }
}

impl core::error::Error for LengthMismatch {}

/// A slice as the fixed-size vector generated functions take, for inputs that arrive as slices
/// (a message, a `Vec`, a row of a file): an error, never a panic, when its length is not `N`.
///
/// ```
/// # use articulated::nalgebra::SVector;
/// let q: Vec<f64> = vec![0.1, 0.2, 0.3];
/// let fixed: SVector<f64, 3> = articulated::vector(&q)?;
/// assert_eq!(fixed[2], 0.3);
/// let e = articulated::vector::<f64, 4>(&q).unwrap_err();
/// assert_eq!(e.to_string(), "expected 4 entries, found 3");
/// # Ok::<(), articulated::LengthMismatch>(())
/// ```
///
/// # Errors
/// [`LengthMismatch`] when `x.len() != N`.
pub fn vector<T: nalgebra::Scalar + Copy, const N: usize>(
    x: &[T],
) -> Result<SVector<T, N>, LengthMismatch> {
    if x.len() == N {
        Ok(SVector::from_column_slice(x))
    } else {
        Err(LengthMismatch {
            expected: N,
            found: x.len(),
        })
    }
}

/// Generated forward dynamics found `M(q)` singular (or not positive definite) at this state:
/// a pivot of its factorization was not positive relative to its unreduced value, or the result
/// was not finite.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SingularMassMatrix {
    /// The velocity coordinate whose pivot failed (or whose acceleration is not finite).
    pub velocity: usize,
}

impl fmt::Display for SingularMassMatrix {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the mass matrix is singular at this state (velocity coordinate {})",
            self.velocity
        )
    }
}

impl core::error::Error for SingularMassMatrix {}

/// How one joint's coordinates sit in `q` and `v`: what an integrator needs to step a
/// configuration on its manifold. A generated chain lists its joints' in joint order
/// ([`Chain::COORDINATES`]); fixed joints, which have none, are left out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Coordinates {
    /// `n` positions and `n` velocities with `v = q̇`: a revolute or prismatic joint (`n = 1`),
    /// a spherical joint in Euler angles (`3`), a free base in Wieber's form (`6`).
    Vector(usize),
    /// A quaternion `[w, x, y, z]` (4 positions) and the child's angular velocity in the child
    /// frame (3 velocities): `spherical(quaternion)`.
    Quaternion,
    /// The child origin's position in the joint frame, then a quaternion (7 positions); the
    /// child origin's linear velocity and the angular velocity, both in the child frame
    /// (6 velocities): `free(quaternion)`, Pinocchio's free flyer.
    FreeQuaternion,
}

impl Coordinates {
    /// Number of positions.
    pub const fn nq(self) -> usize {
        match self {
            Coordinates::Vector(n) => n,
            Coordinates::Quaternion => 4,
            Coordinates::FreeQuaternion => 7,
        }
    }
    /// Number of velocities.
    pub const fn nv(self) -> usize {
        match self {
            Coordinates::Vector(n) => n,
            Coordinates::Quaternion => 3,
            Coordinates::FreeQuaternion => 6,
        }
    }
}

/// A generated chain, in the scalar `T`.
pub trait Chain<T> {
    /// The chain's name in its description.
    const NAME: &'static str;
    /// Its joints' coordinates, in joint order, fixed and mimic joints left out: `Σ nq = NQ`,
    /// `Σ nv = NV`.
    const COORDINATES: &'static [Coordinates];
    /// Its joints' drives, one per entry of [`COORDINATES`](Chain::COORDINATES): the armature
    /// (already in the generated `M`, `τ` and `q̈`), and the damping, friction and limits that
    /// [`Drives`](crate::drives::Drives) applies in a simulation.
    const DRIVES: &'static [Drive];
    /// Its runtime parameters: `()` when it has none, else a generated struct with one public
    /// field per parameter.
    type Params: Copy;
    /// The parameter values the description gives.
    fn default_params() -> Self::Params;
}

/// `M(q)`: the joint-space mass matrix (Wieber 2005, eq. 6; Featherstone 2008, RBDA §6.2).
pub trait MassMatrix<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `M(q)` for the parameters `p`.
    fn mass_matrix_with(q: &SVector<T, NQ>, p: &Self::Params) -> SMatrix<T, NV, NV>;
    /// `M(q)` with the default parameters.
    fn mass_matrix(q: &SVector<T, NQ>) -> SMatrix<T, NV, NV> {
        Self::mass_matrix_with(q, &Self::default_params())
    }
}

/// `M(q)` written into a [`KeptMassMatrix`] (the output `mass_matrix_update`): only the entries
/// that can be non-zero, without zeroing the rest first.
pub trait MassMatrixUpdate<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `M(q)` for the parameters `p`, into `kept`.
    fn mass_matrix_update_with(
        q: &SVector<T, NQ>,
        p: &Self::Params,
        kept: &mut KeptMassMatrix<Self, T, NV>,
    );
    /// `M(q)` with the default parameters, into `kept`.
    fn mass_matrix_update(q: &SVector<T, NQ>, kept: &mut KeptMassMatrix<Self, T, NV>) {
        Self::mass_matrix_update_with(q, &Self::default_params(), kept)
    }
}

/// The lower triangle of `M(q)`, diagonal included, written into a [`KeptMassMatrixLower`] (the
/// output `mass_matrix_lower`): the entries of [`MassMatrixUpdate`] on and below the diagonal,
/// the strict upper triangle never written, so it stays zero.
///
/// That is the half of `M` that nalgebra's `Cholesky::new` and `sygemv` read, and the half
/// Pinocchio's `crba` leaves out (it fills the upper triangle). Half the stores of the whole
/// update, so less code: faster where the whole update's code sits at the size of the
/// instruction cache and the lower triangle's fits below it, as on the 37-coordinate humanoid.
/// Not everywhere faster: on a long serial chain LLVM compiles the stores, strided in memory
/// (one row of `M` is computed at a time, the storage is by column), into more code than the
/// whole update's. `BENCHMARKS.md` times both on four models; measure it on your chain.
pub trait MassMatrixLower<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// The lower triangle of `M(q)` for the parameters `p`, into `kept`.
    fn mass_matrix_lower_with(
        q: &SVector<T, NQ>,
        p: &Self::Params,
        kept: &mut KeptMassMatrixLower<Self, T, NV>,
    );
    /// The lower triangle of `M(q)` with the default parameters, into `kept`.
    fn mass_matrix_lower(q: &SVector<T, NQ>, kept: &mut KeptMassMatrixLower<Self, T, NV>) {
        Self::mass_matrix_lower_with(q, &Self::default_params(), kept)
    }
}

/// `M(q)` of chain `C`, kept between calls of [`MassMatrixUpdate::mass_matrix_update`], which
/// writes only the entries that can be non-zero: what a controller asks at every tick, in the
/// memory it keeps for it (as Pinocchio's `crba` writes into `data.M`).
///
/// [`MassMatrix::mass_matrix`] returns a new matrix, so it first zeroes all of it (a `memset`)
/// and then writes every entry that is not zero for all `q`. Kept, the zeros stay from one call
/// to the next: on the 37-coordinate humanoid, 700 of the 1,369 entries are zero for every `q`,
/// and the update is faster than `mass_matrix` (`BENCHMARKS.md` times both). On a chain whose
/// `M` has no zero, such as arm7, it makes no difference.
///
/// The matrix can only be read (through [`Deref`](core::ops::Deref) or
/// [`matrix`](KeptMassMatrix::matrix)): that keeps the zeros it starts with, so every update
/// leaves the whole of `M(q)`. It is typed by its chain, whose generated code knows which
/// entries are zero. With `LOWER = true` ([`KeptMassMatrixLower`]) it holds the lower triangle
/// only, the strict upper one zero: what [`MassMatrixLower::mass_matrix_lower`] writes.
///
/// ```
/// articulated::chain! {
///     chain Pendulum {
///         outputs: [mass_matrix, mass_matrix_update];
///         body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob }
///     }
/// }
/// use articulated::{KeptMassMatrix, MassMatrix, MassMatrixUpdate};
/// use articulated::nalgebra::SVector;
///
/// let mut m = KeptMassMatrix::<Pendulum, f64, 1>::new();
/// for step in 0..3 {
///     let q = SVector::<f64, 1>::new(0.1 * f64::from(step));
///     Pendulum::mass_matrix_update(&q, &mut m);
///     assert_eq!(*m, Pendulum::mass_matrix(&q));
/// }
/// ```
pub struct KeptMassMatrix<C: ?Sized, T, const NV: usize, const LOWER: bool = false> {
    matrix: SMatrix<T, NV, NV>,
    chain: core::marker::PhantomData<fn() -> C>,
}

impl<C: ?Sized, T: crate::Scalar, const NV: usize, const LOWER: bool>
    KeptMassMatrix<C, T, NV, LOWER>
{
    /// A zero matrix, ready for its first update.
    pub fn new() -> Self {
        Self {
            matrix: SMatrix::from_array_storage(nalgebra::ArrayStorage([[T::zero(); NV]; NV])),
            chain: core::marker::PhantomData,
        }
    }
}

impl<C: ?Sized, T: crate::Scalar, const NV: usize, const LOWER: bool> Default
    for KeptMassMatrix<C, T, NV, LOWER>
{
    fn default() -> Self {
        Self::new()
    }
}

impl<C: ?Sized, T, const NV: usize, const LOWER: bool> KeptMassMatrix<C, T, NV, LOWER> {
    /// The matrix as the last update left it (with `LOWER`, the lower triangle of `M`, zeros
    /// above the diagonal).
    pub fn matrix(&self) -> &SMatrix<T, NV, NV> {
        &self.matrix
    }

    /// The matrix, by value.
    pub fn into_matrix(self) -> SMatrix<T, NV, NV> {
        self.matrix
    }
}

impl<C: ?Sized, T: nalgebra::Scalar, const NV: usize> KeptMassMatrixLower<C, T, NV> {
    /// The whole of `M(q)`: the lower triangle mirrored above the diagonal (`NV·(NV − 1)/2`
    /// copies).
    pub fn symmetric(&self) -> SMatrix<T, NV, NV> {
        let mut m = self.matrix.clone();
        m.fill_upper_triangle_with_lower_triangle();
        m
    }
}

/// `M(q)`'s lower triangle of chain `C` ([`KeptMassMatrix`] with `LOWER`), kept between calls of
/// [`MassMatrixLower::mass_matrix_lower`]: deref to the matrix (zeros above the diagonal) to give
/// it to nalgebra's `Cholesky::new` or `sygemv`, which read that triangle only; `symmetric()`
/// for the whole.
///
/// ```
/// articulated::chain! {
///     chain Double {
///         outputs: [mass_matrix, mass_matrix_lower];
///         body upper { mass: 1.0, com: [0.0, 0.0, -0.5], inertia: diag(0.1, 0.1, 0.01) }
///         body lower { mass: 1.0, com: [0.0, 0.0, -0.5], inertia: diag(0.1, 0.1, 0.01) }
///         joint shoulder: revolute(y) { parent: world, child: upper }
///         joint elbow: revolute(y) { parent: upper, child: lower, xyz: [0.0, 0.0, -1.0] }
///     }
/// }
/// use articulated::{KeptMassMatrixLower, MassMatrix, MassMatrixLower};
/// use articulated::nalgebra::{Cholesky, SVector};
///
/// let q = SVector::<f64, 2>::new(0.3, -0.7);
/// let mut m = KeptMassMatrixLower::<Double, f64, 2>::new();
/// Double::mass_matrix_lower(&q, &mut m);
/// assert_eq!(m[(0, 1)], 0.0);
/// assert_eq!(m.symmetric(), Double::mass_matrix(&q));
/// let cholesky = Cholesky::new(*m).expect("M is positive definite");
/// let x = cholesky.solve(&SVector::<f64, 2>::new(1.0, 2.0));
/// assert!((Double::mass_matrix(&q) * x - SVector::<f64, 2>::new(1.0, 2.0)).norm() < 1e-12);
/// ```
pub type KeptMassMatrixLower<C, T, const NV: usize> = KeptMassMatrix<C, T, NV, true>;

impl<C: ?Sized, T, const NV: usize, const LOWER: bool> core::ops::Deref
    for KeptMassMatrix<C, T, NV, LOWER>
{
    type Target = SMatrix<T, NV, NV>;

    fn deref(&self) -> &SMatrix<T, NV, NV> {
        &self.matrix
    }
}

impl<C: ?Sized, T: Clone, const NV: usize, const LOWER: bool> Clone
    for KeptMassMatrix<C, T, NV, LOWER>
{
    fn clone(&self) -> Self {
        Self {
            matrix: self.matrix.clone(),
            chain: core::marker::PhantomData,
        }
    }
}

impl<C: ?Sized, T: fmt::Debug, const NV: usize, const LOWER: bool> fmt::Debug
    for KeptMassMatrix<C, T, NV, LOWER>
{
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = if LOWER {
            "KeptMassMatrixLower"
        } else {
            "KeptMassMatrix"
        };
        f.debug_tuple(name).field(&self.matrix).finish()
    }
}

/// `N(q, q̇)·q̇`: the velocity-product terms, without gravity (Wieber 2005, eq. 7).
pub trait Bias<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `N(q, q̇)·q̇` for the parameters `p`.
    fn bias_with(q: &SVector<T, NQ>, v: &SVector<T, NV>, p: &Self::Params) -> SVector<T, NV>;
    /// `N(q, q̇)·q̇` with the default parameters.
    fn bias(q: &SVector<T, NQ>, v: &SVector<T, NV>) -> SVector<T, NV> {
        Self::bias_with(q, v, &Self::default_params())
    }
}

/// `g(q)`: the generalized force that holds the chain still against gravity (minus Wieber's
/// `𝓕_g`, eq. 14).
pub trait Gravity<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `g(q)` for the parameters `p`.
    fn gravity_with(q: &SVector<T, NQ>, p: &Self::Params) -> SVector<T, NV>;
    /// `g(q)` with the default parameters.
    fn gravity(q: &SVector<T, NQ>) -> SVector<T, NV> {
        Self::gravity_with(q, &Self::default_params())
    }
}

/// `τ = M(q)·a + N(q, q̇)·q̇ + g(q)`: the joint forces that produce the acceleration `a`
/// (Featherstone 2008, RBDA §5.3).
pub trait InverseDynamics<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `τ` for the parameters `p`.
    fn inverse_dynamics_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        a: &SVector<T, NV>,
        p: &Self::Params,
    ) -> SVector<T, NV>;
    /// `τ` with the default parameters.
    fn inverse_dynamics(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        a: &SVector<T, NV>,
    ) -> SVector<T, NV> {
        Self::inverse_dynamics_with(q, v, a, &Self::default_params())
    }
}

/// `q̈ = M(q)⁻¹·(τ − N(q, q̇)·q̇ − g(q))`, or an error where `M(q)` is singular.
pub trait ForwardDynamics<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `q̈` for the parameters `p`.
    ///
    /// # Errors
    /// [`SingularMassMatrix`] where `M(q)` is singular or the result is not finite.
    fn forward_dynamics_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        tau: &SVector<T, NV>,
        p: &Self::Params,
    ) -> Result<SVector<T, NV>, SingularMassMatrix>;
    /// `q̈` with the default parameters.
    ///
    /// # Errors
    /// [`SingularMassMatrix`] where `M(q)` is singular or the result is not finite.
    fn forward_dynamics(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        tau: &SVector<T, NV>,
    ) -> Result<SVector<T, NV>, SingularMassMatrix> {
        Self::forward_dynamics_with(q, v, tau, &Self::default_params())
    }
}

/// `N(q, q̇)·q̇ + g(q)`: the velocity-product terms and gravity together, in one pass (inverse
/// dynamics at `a = 0`; Pinocchio's `nonLinearEffects`), cheaper than [`Bias`] then
/// [`Gravity`].
pub trait NonlinearEffects<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `N·q̇ + g` for the parameters `p`.
    fn nonlinear_effects_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        p: &Self::Params,
    ) -> SVector<T, NV>;
    /// `N·q̇ + g` with the default parameters.
    fn nonlinear_effects(q: &SVector<T, NQ>, v: &SVector<T, NV>) -> SVector<T, NV> {
        Self::nonlinear_effects_with(q, v, &Self::default_params())
    }
}

/// `(M(q), N(q, q̇)·q̇ + g(q))` from one function, which computes the kinematics both need once:
/// what a controller asks at every tick.
pub trait MassMatrixAndNonlinearEffects<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `M` and `N·q̇ + g` for the parameters `p`.
    fn mass_matrix_and_nonlinear_effects_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        p: &Self::Params,
    ) -> (SMatrix<T, NV, NV>, SVector<T, NV>);
    /// `M` and `N·q̇ + g` with the default parameters.
    fn mass_matrix_and_nonlinear_effects(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
    ) -> (SMatrix<T, NV, NV>, SVector<T, NV>) {
        Self::mass_matrix_and_nonlinear_effects_with(q, v, &Self::default_params())
    }
}

/// The wrench each joint transmits (Hemami's joint couple and reaction force), from the free
/// ends down: what the parent exerts on the child across the joint, in the child's frame about
/// its origin, `[n; f]` (angular first), gravity included. One column per joint in joint order
/// (`NB` joints, fixed ones included). The backward pass of Newton–Euler (Featherstone 2008,
/// RBDA §5.3).
pub trait JointWrenches<T, const NQ: usize, const NV: usize, const NB: usize>: Chain<T> {
    /// The wrenches at `(q, v, a)` for the parameters `p`.
    fn joint_wrenches_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        a: &SVector<T, NV>,
        p: &Self::Params,
    ) -> SMatrix<T, 6, NB>;
    /// The wrenches at `(q, v, a)` with the default parameters.
    fn joint_wrenches(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        a: &SVector<T, NV>,
    ) -> SMatrix<T, 6, NB> {
        Self::joint_wrenches_with(q, v, a, &Self::default_params())
    }
}

/// The wrench each joint transmits, as [`JointWrenches`], but from the base up (Hemami, Dariush &
/// Barin 2005, §5: "the sequence can start from the ground upwards"): from `base`, the wrench
/// the world exerts on the root body (a measured ground reaction, in the root body's frame about
/// its origin), body by body up a serial chain. With the true base wrench both agree; on measured
/// motion their difference is the consistency check of the data.
pub trait JointWrenchesBottomUp<T, const NQ: usize, const NV: usize, const NB: usize>:
    Chain<T>
{
    /// The wrenches at `(q, v, a)` from `base`, for the parameters `p`.
    fn joint_wrenches_bottom_up_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        a: &SVector<T, NV>,
        base: &SVector<T, 6>,
        p: &Self::Params,
    ) -> SMatrix<T, 6, NB>;
    /// The wrenches at `(q, v, a)` from `base`, with the default parameters.
    fn joint_wrenches_bottom_up(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        a: &SVector<T, NV>,
        base: &SVector<T, 6>,
    ) -> SMatrix<T, 6, NB> {
        Self::joint_wrenches_bottom_up_with(q, v, a, base, &Self::default_params())
    }
}

/// `x_G(q)`: the centre of mass of the whole system, world frame (Wieber 2005, §4).
pub trait CenterOfMass<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `x_G` for the parameters `p`.
    fn center_of_mass_with(q: &SVector<T, NQ>, p: &Self::Params) -> SVector<T, 3>;
    /// `x_G` with the default parameters.
    fn center_of_mass(q: &SVector<T, NQ>) -> SVector<T, 3> {
        Self::center_of_mass_with(q, &Self::default_params())
    }
}

/// `ẋ_G(q, v) = p / m`: the velocity of the centre of mass, world frame.
pub trait CenterOfMassVelocity<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `ẋ_G` for the parameters `p`.
    fn center_of_mass_velocity_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        p: &Self::Params,
    ) -> SVector<T, 3>;
    /// `ẋ_G` with the default parameters.
    fn center_of_mass_velocity(q: &SVector<T, NQ>, v: &SVector<T, NV>) -> SVector<T, 3> {
        Self::center_of_mass_velocity_with(q, v, &Self::default_params())
    }
}

/// `J_G(q)`, `3 × NV`: the centre of mass Jacobian, `ẋ_G = J_G·v`, world frame.
pub trait CenterOfMassJacobian<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `J_G` for the parameters `p`.
    fn center_of_mass_jacobian_with(q: &SVector<T, NQ>, p: &Self::Params) -> SMatrix<T, 3, NV>;
    /// `J_G` with the default parameters.
    fn center_of_mass_jacobian(q: &SVector<T, NQ>) -> SMatrix<T, 3, NV> {
        Self::center_of_mass_jacobian_with(q, &Self::default_params())
    }
}

/// `h_G = [k_G; p]`: the angular momentum about the centre of mass, then the linear momentum,
/// world axes (angular first, like every spatial vector here). Internal forces leave it
/// constant up to gravity, which changes `p` only (Wieber 2005, §5).
pub trait CentroidalMomentum<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `h_G` for the parameters `p`.
    fn centroidal_momentum_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        p: &Self::Params,
    ) -> SVector<T, 6>;
    /// `h_G` with the default parameters.
    fn centroidal_momentum(q: &SVector<T, NQ>, v: &SVector<T, NV>) -> SVector<T, 6> {
        Self::centroidal_momentum_with(q, v, &Self::default_params())
    }
}

/// `A_G(q)`, `6 × NV`, angular rows first: the centroidal momentum matrix, `h_G = A_G·v`
/// (Orin, Goswami & Lee 2013), what humanoid balance controllers use.
pub trait CentroidalMomentumMatrix<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `A_G` for the parameters `p`.
    fn centroidal_momentum_matrix_with(q: &SVector<T, NQ>, p: &Self::Params) -> SMatrix<T, 6, NV>;
    /// `A_G` with the default parameters.
    fn centroidal_momentum_matrix(q: &SVector<T, NQ>) -> SMatrix<T, 6, NV> {
        Self::centroidal_momentum_matrix_with(q, &Self::default_params())
    }
}

/// `½·vᵀ·M(q)·v`: the kinetic energy.
pub trait KineticEnergy<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// The kinetic energy for the parameters `p`.
    fn kinetic_energy_with(q: &SVector<T, NQ>, v: &SVector<T, NV>, p: &Self::Params) -> T;
    /// The kinetic energy with the default parameters.
    fn kinetic_energy(q: &SVector<T, NQ>, v: &SVector<T, NV>) -> T {
        Self::kinetic_energy_with(q, v, &Self::default_params())
    }
}

/// `−Σ m_k·gᵀ·x_k`: the potential energy of gravity, zero with every centre of mass at the
/// world origin.
pub trait PotentialEnergy<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// The potential energy for the parameters `p`.
    fn potential_energy_with(q: &SVector<T, NQ>, p: &Self::Params) -> T;
    /// The potential energy with the default parameters.
    fn potential_energy(q: &SVector<T, NQ>) -> T {
        Self::potential_energy_with(q, &Self::default_params())
    }
}

/// `N(q, q̇)` of Wieber 2005, eq. 7, `NV × NV`: `N·v` is [`Bias`], and `Ṁ − 2N` is
/// skew-symmetric. Where `v = q̇` (no quaternion joint) it is the matrix of the Christoffel
/// symbols of `M`, on Euler joints too.
pub trait CoriolisMatrix<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `N` for the parameters `p`.
    fn coriolis_matrix_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        p: &Self::Params,
    ) -> SMatrix<T, NV, NV>;
    /// `N` with the default parameters.
    fn coriolis_matrix(q: &SVector<T, NQ>, v: &SVector<T, NV>) -> SMatrix<T, NV, NV> {
        Self::coriolis_matrix_with(q, v, &Self::default_params())
    }
}

/// `(∂τ/∂q, ∂τ/∂v)` of [`InverseDynamics`], `NV × NV` each (`∂τ/∂a = M`); `∂/∂q` along the
/// configuration's tangent (`q ⊕ δ`, [`crate::control::tangent::retract`]).
pub trait InverseDynamicsDerivatives<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// The derivatives for the parameters `p`.
    fn inverse_dynamics_derivatives_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        a: &SVector<T, NV>,
        p: &Self::Params,
    ) -> (SMatrix<T, NV, NV>, SMatrix<T, NV, NV>);
    /// The derivatives with the default parameters.
    fn inverse_dynamics_derivatives(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        a: &SVector<T, NV>,
    ) -> (SMatrix<T, NV, NV>, SMatrix<T, NV, NV>) {
        Self::inverse_dynamics_derivatives_with(q, v, a, &Self::default_params())
    }
}

/// The three matrices of [`ForwardDynamicsDerivatives`]: `∂q̈/∂q`, `∂q̈/∂v` and `M⁻¹ = ∂q̈/∂τ`.
pub type FdDerivatives<T, const NV: usize> =
    (SMatrix<T, NV, NV>, SMatrix<T, NV, NV>, SMatrix<T, NV, NV>);

/// `(∂q̈/∂q, ∂q̈/∂v, M⁻¹)` of [`ForwardDynamics`], `NV × NV` each (`∂q̈/∂τ = M⁻¹`); `∂/∂q`
/// along the configuration's tangent (`q ⊕ δ`, [`crate::control::tangent::retract`]).
pub trait ForwardDynamicsDerivatives<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// The derivatives for the parameters `p`.
    ///
    /// # Errors
    /// [`SingularMassMatrix`] where `M(q)` is singular or `q̈` is not finite.
    fn forward_dynamics_derivatives_with(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        tau: &SVector<T, NV>,
        p: &Self::Params,
    ) -> Result<FdDerivatives<T, NV>, SingularMassMatrix>;
    /// The derivatives with the default parameters.
    ///
    /// # Errors
    /// [`SingularMassMatrix`] where `M(q)` is singular or `q̈` is not finite.
    fn forward_dynamics_derivatives(
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
        tau: &SVector<T, NV>,
    ) -> Result<FdDerivatives<T, NV>, SingularMassMatrix> {
        Self::forward_dynamics_derivatives_with(q, v, tau, &Self::default_params())
    }
}

/// `M(q)⁻¹`, or an error where `M(q)` is singular.
pub trait MassMatrixInverse<T, const NQ: usize, const NV: usize>: Chain<T> {
    /// `M⁻¹` for the parameters `p`.
    ///
    /// # Errors
    /// [`SingularMassMatrix`] where `M(q)` is singular.
    fn mass_matrix_inverse_with(
        q: &SVector<T, NQ>,
        p: &Self::Params,
    ) -> Result<SMatrix<T, NV, NV>, SingularMassMatrix>;
    /// `M⁻¹` with the default parameters.
    ///
    /// # Errors
    /// [`SingularMassMatrix`] where `M(q)` is singular.
    fn mass_matrix_inverse(q: &SVector<T, NQ>) -> Result<SMatrix<T, NV, NV>, SingularMassMatrix> {
        Self::mass_matrix_inverse_with(q, &Self::default_params())
    }
}

/// Helpers the generated code calls; not part of the public API.
#[doc(hidden)]
pub mod __private {
    /// `pivot > tol·scale`, false for NaN: a factorization pivot that is positive relative to
    /// its unreduced value.
    #[inline(always)]
    pub fn positive_pivot<T: PartialOrd + Copy + core::ops::Mul<Output = T>>(
        pivot: T,
        scale: T,
        tol: T,
    ) -> bool {
        pivot > tol * scale
    }

    /// `true`: the generator found the chain's `M(q)` singular at every configuration, and the
    /// function that calls this refuses every state (a call, not a literal `if true`, so that
    /// the statements after it are not reported as unreachable).
    #[inline(always)]
    pub const fn singular_at_every_configuration() -> bool {
        true
    }

    /// The entries of a [`KeptMassMatrix`](super::KeptMassMatrix), for the generated update,
    /// which writes only entries that can be non-zero (and with `LOWER`, only on and below the
    /// diagonal).
    #[inline(always)]
    pub fn kept_entries<C: ?Sized, T, const NV: usize, const LOWER: bool>(
        kept: &mut super::KeptMassMatrix<C, T, NV, LOWER>,
    ) -> &mut nalgebra::SMatrix<T, NV, NV> {
        &mut kept.matrix
    }
}
