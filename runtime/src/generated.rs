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
//! | [`CentroidalMomentumRate`] | `C::centroidal_momentum_rate(&q, &v, &a)` | `ḣ_G = A_G·a + Ȧ_G·v`, laid out as `h_G` |
//! | [`CentroidalMomentumDrift`] | `C::centroidal_momentum_drift(&q, &v)` | `Ȧ_G·v`, the rate at `a = 0` |
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

/// Where a frame is: its rotation `world_R_frame` (the frame's axes in world coordinates, as
/// columns) and its origin in the world. What `frame_placements` returns per frame, Pinocchio's
/// `data.oMf[i]`.
///
/// ```
/// articulated::chain! {
///     chain Pendulum {
///         outputs: [frame_placements, frame_jacobians_local_world_aligned];
///         frames: [tip];
///         body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob }
///         frame tip { parent: bob, xyz: [0.0, 0.0, -1.0] }
///     }
/// }
/// use articulated::nalgebra::{SVector, Vector3};
/// use articulated::prelude::*;
///
/// let theta = 0.5_f64;
/// let q = SVector::from([theta]);
/// // A turn by θ about y takes the tip from (0, 0, −1) to (−sin θ, 0, −cos θ) ...
/// let [tip] = Pendulum::frame_placements(&q);
/// let expected = Vector3::new(-theta.sin(), 0.0, -theta.cos());
/// assert!((tip.translation - expected).norm() < 1e-15);
/// // ... and moves it at (−cos θ, 0, sin θ) per radian, turning about y.
/// let [j] = Pendulum::frame_jacobians_local_world_aligned(&q);
/// let column = [0.0, 1.0, 0.0, -theta.cos(), 0.0, theta.sin()];
/// assert!((0..6).all(|r| (j[(r, 0)] - column[r]).abs() < 1e-15));
/// assert_eq!(<Pendulum as Chain<f64>>::FRAMES, ["tip"]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FramePlacement<T> {
    /// `world_R_frame`: a vector in frame axes `x_f` is `rotation·x_f` in world axes.
    pub rotation: SMatrix<T, 3, 3>,
    /// The frame's origin in the world.
    pub translation: SVector<T, 3>,
}

impl<T: nalgebra::RealField + Copy> FramePlacement<T> {
    /// A point given in the frame, in the world: `rotation·p + translation`.
    pub fn transform_point(&self, p: &SVector<T, 3>) -> SVector<T, 3> {
        self.rotation * p + self.translation
    }
}

/// A generated chain, in the scalar `T`.
pub trait Chain<T> {
    /// The chain's name in its description.
    const NAME: &'static str;
    /// Its joints' coordinates, in joint order, fixed and mimic joints left out: `Σ nq = NQ`,
    /// `Σ nv = NV`.
    const COORDINATES: &'static [Coordinates];
    /// The name of each position coordinate, `NQ` of them, in order: the joint's name, and for
    /// a joint of several coordinates a component after a dot. Revolute and prismatic:
    /// `elbow`; Euler angles: `hip.rz`, `hip.ry`, `hip.rx` in the joint's sequence; a
    /// quaternion: `wrist.qw`, `.qx`, `.qy`, `.qz` (scalar first); a free Euler base: `base.x`,
    /// `.y`, `.z` then its angles; a free quaternion base: `base.x`, `.y`, `.z`, `.qw`, `.qx`,
    /// `.qy`, `.qz`.
    ///
    /// ```
    /// articulated::chain! {
    ///     chain Arm {
    ///         body upper { mass: 1.0, com: [0.0, 0.0, -0.3], inertia: diag(0.01, 0.01, 0.001) }
    ///         body fore { mass: 0.5, com: [0.0, 0.0, -0.2], inertia: diag(0.005, 0.005, 0.001) }
    ///         joint shoulder: spherical(quaternion) { parent: world, child: upper }
    ///         joint elbow: revolute(y) { parent: upper, child: fore, xyz: [0.0, 0.0, -0.6] }
    ///     }
    /// }
    /// use articulated::Chain;
    /// assert_eq!(
    ///     <Arm as Chain<f64>>::Q_NAMES,
    ///     ["shoulder.qw", "shoulder.qx", "shoulder.qy", "shoulder.qz", "elbow"]
    /// );
    /// assert_eq!(<Arm as Chain<f64>>::V_NAMES, ["shoulder.wx", "shoulder.wy", "shoulder.wz", "elbow"]);
    /// ```
    const Q_NAMES: &'static [&'static str];
    /// The name of each velocity coordinate (and of each entry of `τ`), `NV` of them, in
    /// order: as [`Q_NAMES`](Chain::Q_NAMES) where `v = q̇`; a quaternion joint's angular
    /// velocity in its child frame `wrist.wx`, `.wy`, `.wz`; a free quaternion base's
    /// `base.vx`, `.vy`, `.vz`, `.wx`, `.wy`, `.wz` (both in the child frame).
    const V_NAMES: &'static [&'static str];
    /// The frames the frame outputs compute (`frames: [tool, left_sole]` in the description),
    /// in that order: a frame output returns `[X; NF]`, entry `k` for `FRAMES[k]`. Empty when
    /// none is named.
    const FRAMES: &'static [&'static str] = &[];
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

// The traits of the outputs (`MassMatrix`, `Bias`, … `MassMatrixInverse`), each with its docs,
// from the generator's table of outputs (`articulated_codegen::outputs`), where each output is
// described once.
articulated_macros::__output_traits!();

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

/// The three matrices of [`ForwardDynamicsDerivatives`]: `∂q̈/∂q`, `∂q̈/∂v` and `M⁻¹ = ∂q̈/∂τ`.
pub type FdDerivatives<T, const NV: usize> =
    (SMatrix<T, NV, NV>, SMatrix<T, NV, NV>, SMatrix<T, NV, NV>);

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

    /// The rows of a result column [`minus_product`] accumulates at once: as many as the vector
    /// registers hold with room for the operands (sixteen registers of four `f64` with AVX, of
    /// two without). With AVX a column of the humanoid's 37 is one pass; without, a column of
    /// 37 in one pass kept half its sums on the stack, reloaded and stored again for every
    /// entry of `D`.
    const BLOCK: usize = if cfg!(target_feature = "avx") { 40 } else { 20 };

    /// `−A·D` for `N × N` matrices, visiting only the entries of `D` that `rows` lists
    /// (`rows[c]`: the rows of column `c` that can be non-zero; the others are taken as zero),
    /// with `fma(a, b, c) = a·b + c`. What a composed `forward_dynamics_derivatives` returns,
    /// `∂q̈/∂x = −M⁻¹·∂τ/∂x` (`A = M⁻¹`, `D = ∂τ/∂x`), where the generator found the
    /// derivatives of inverse dynamics sparse (a joint's torque does not depend on the
    /// coordinates below it, nor on a base's position).
    ///
    /// Column by column, `BLOCK` rows at a time: each block's sums stay in vector registers
    /// while `A`'s columns stream past, and are stored once. Written out here rather than left
    /// to nalgebra's product, which is dense and, for sizes it does not specialize, goes through
    /// its generic kernel, slower on the humanoid's.
    #[inline]
    pub fn minus_product<T: nalgebra::RealField + Copy, const N: usize>(
        a: &nalgebra::SMatrix<T, N, N>,
        d: &nalgebra::SMatrix<T, N, N>,
        rows: &[&[u16]; N],
        fma: impl Fn(T, T, T) -> T,
    ) -> nalgebra::SMatrix<T, N, N> {
        in_blocks::<T, N, BLOCK>(a, d, rows, T::zero(), fma)
    }

    /// `−A·D` as [`minus_product`] computes it, `B` rows of a result column at a time, for
    /// the scalars and for the lanes alike.
    #[inline(always)]
    fn in_blocks<T, const N: usize, const B: usize>(
        a: &nalgebra::SMatrix<T, N, N>,
        d: &nalgebra::SMatrix<T, N, N>,
        rows: &[&[u16]; N],
        zero: T,
        fma: impl Fn(T, T, T) -> T,
    ) -> nalgebra::SMatrix<T, N, N>
    where
        T: nalgebra::Scalar + Copy + core::ops::Neg<Output = T>,
    {
        let mut out = nalgebra::SMatrix::<T, N, N>::from_array_storage(nalgebra::ArrayStorage(
            [[zero; N]; N],
        ));
        for ((out, rows), d) in out.data.0.iter_mut().zip(rows).zip(&d.data.0) {
            for start in (0..N).step_by(B) {
                let len = B.min(N - start);
                let mut acc = [zero; B];
                for &k in *rows {
                    let k = usize::from(k);
                    // The generator lists rows below `N` only.
                    let (Some(&x), Some(column)) = (d.get(k), a.data.0.get(k)) else {
                        continue;
                    };
                    for (acc, &a) in acc.iter_mut().zip(&column[start..]).take(len) {
                        *acc = fma(-x, a, *acc);
                    }
                }
                for (out, acc) in out[start..].iter_mut().zip(acc).take(len) {
                    *out = acc;
                }
            }
        }
        out
    }

    /// The rows of a result column [`lanes_minus_product`] accumulates at once: each row a
    /// whole vector register of lanes, so eight, with room left for the operands among sixteen
    /// registers.
    const LANE_BLOCK: usize = 8;

    /// [`minus_product`] in lanes, for a composed `forward_dynamics_derivatives`' batch twin:
    /// `−A·D` lane by lane, each entry's sum over the same rows in the same order, with the
    /// lanes' own `mul_add`, so that each lane is the scalar product of its state bit for bit.
    #[inline]
    pub fn lanes_minus_product<L: crate::lanes::Simd, const N: usize>(
        a: &nalgebra::SMatrix<L, N, N>,
        d: &nalgebra::SMatrix<L, N, N>,
        rows: &[&[u16]; N],
    ) -> nalgebra::SMatrix<L, N, N> {
        in_blocks::<L, N, LANE_BLOCK>(a, d, rows, L::ZERO, L::mul_add)
    }

    /// The parts of a composed `constrained_forward_dynamics_derivatives` put together.
    pub use crate::constraint::derivatives::composed as constrained_derivatives;
}
