//! Integrators for second-order systems `q̇ ~ v`, `v̇ = a(t, q, v)`: a generated chain under a
//! controller, or anything else that implements [`SecondOrder`].
//!
//! | method | type | order | evaluations of `a` per step | for |
//! |---|---|---|---|---|
//! | explicit Euler | [`Euler`] | 1 | 1 | reference, tests |
//! | semi-implicit (symplectic) Euler | [`SymplecticEuler`] | 1 | 1 | cheap, bounded energy on separable systems |
//! | classic Runge–Kutta | [`Rk4`] | 4 | 4 | accuracy at a fixed step |
//! | Dormand–Prince 5(4) | [`Dopri5`] | 5 | 6 (FSAL) + rejections | accuracy to a tolerance |
//! | implicit midpoint | [`ImplicitMidpoint`] | 2 | `2 + NV` + Newton iterations | long horizons: energy bounded, no drift |
//!
//! All are Runge–Kutta–Munthe-Kaas methods (Munthe-Kaas 1998, BIT 38(1), 92–111; Hairer, Lubich
//! & Wanner 2006, *Geometric Numerical Integration*, 2nd ed., §IV.8.2): within a step the
//! configuration is `q = q_n ⊕ θ` and the Runge–Kutta method integrates the local coordinate
//! `θ` with `θ̇ = dexp⁻¹_θ(v)` ([`crate::configuration`]). So quaternion joints stay on the unit
//! sphere through the exponential map, to rounding, and no step normalizes. On chains whose
//! coordinates are all `Vector` (Euler angles, revolute and prismatic joints) `⊕` is `+`,
//! `θ̇ = v`, and each method is its textbook self.
//!
//! # The long-horizon method: implicit midpoint
//! [`ImplicitMidpoint`] is the one-stage Gauss method, solved by Newton's method with a
//! finite-difference Jacobian. We chose it over a variational integrator because it needs only
//! what a generated chain offers, the acceleration `a(t, q, v)` (a variational integrator needs
//! `∂L/∂q`, i.e. derivatives of `M(q)` that the generator does not emit), and works unchanged
//! for any [`SecondOrder`] system, quaternion joints included. It is symmetric (time-reversible:
//! stepping back by `−h` from the result returns the start, also on the manifold, because its
//! configuration update `q_n ⊕ h·w` has the midpoint `q_n ⊕ (h/2)·w` in common with its reverse)
//! and conserves quadratic invariants exactly. In the variables `(q, v)` it is not symplectic
//! where `M` depends on `q`; its energy stays bounded without drift because a symmetric method
//! applied to a reversible system (a mechanical system is, under `v → −v`) has no secular drift
//! on (near-)integrable motions (Hairer, Lubich & Wanner 2006, ch. XI and ch. V). Outside that
//! regime (chaotic swings) no such guarantee is proved; the tests measure it on the two-link.
//!
//! # Errors
//! A non-finite state, control or acceleration, a singular mass matrix, a failed Newton solve
//! or a Dormand–Prince step below its minimum stop the integration with a [`Fault`]: the time,
//! the step index and the [`Cause`] (for a non-finite value, the first one met: which vector and
//! which index). Nothing panics and no NaN is returned as a state. On error the state passed
//! to [`Integrator::advance`] is left as it was (for [`Dopri5`], at the last accepted step).
//!
//! # Allocation
//! With fixed sizes (`Const<N>`, i.e. `SVector`) nothing allocates, under `no_std` too. The
//! methods are generic over nalgebra's [`Dim`], so the same code steps a system whose size is
//! known only at run time (`Dyn`, with `alloc`): the CLI's reference engine.

mod dopri5;
#[cfg(feature = "alloc")]
mod ensemble;
mod euler;
mod midpoint;
mod rk4;

use core::fmt;
use core::marker::PhantomData;
use core::str::FromStr;

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, OVector, RealField, SVector, Scalar, U1};

pub use dopri5::{Dopri5, Dopri5Stats};
#[cfg(feature = "alloc")]
pub use ensemble::Ensemble;
pub use euler::{Euler, SymplecticEuler};
pub use midpoint::{ImplicitMidpoint, MidpointStats};
pub use rk4::Rk4;

use crate::configuration::{self, SizeMismatch};
use crate::{Chain, Coordinates, ForwardDynamics, SingularMassMatrix};

/// A state `(t, q, v)` of a second-order system.
#[derive(Clone, Debug, PartialEq)]
pub struct State<T: Scalar, Q: Dim, V: Dim>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// Time.
    pub t: T,
    /// Positions (`NQ`).
    pub q: OVector<T, Q>,
    /// Velocities (`NV`).
    pub v: OVector<T, V>,
}

impl<T: Scalar + Copy, const NQ: usize, const NV: usize> Copy for State<T, Const<NQ>, Const<NV>> {}

impl<T: Scalar, Q: Dim, V: Dim> State<T, Q, V>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// The state `(t, q, v)`.
    pub fn new(t: T, q: OVector<T, Q>, v: OVector<T, V>) -> Self {
        State { t, q, v }
    }
}

/// What an integrator steps: positions `q` on the manifold the [`coordinates`] describe,
/// velocities `v`, and the acceleration `v̇ = a(t, q, v)`.
///
/// [`coordinates`]: SecondOrder::coordinates
pub trait SecondOrder<T: Scalar, Q: Dim, V: Dim>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// How `q` and `v` split into joints (`Σ nq = NQ`, `Σ nv = NV`; a system in a vector space
    /// returns `&[Coordinates::Vector(NQ)]`).
    fn coordinates(&self) -> &[Coordinates];
    /// `v̇ = a(t, q, v)`.
    ///
    /// The integrators look at `q` and `v` for non-finite entries only when this fails or
    /// returns a non-finite value (so a non-finite input should make it do one or the other,
    /// as generated chains do; otherwise the fault is reported when the step's result is
    /// checked, at the step's end time).
    ///
    /// # Errors
    /// Whatever keeps it from being computed: [`Cause::SingularMassMatrix`], a non-finite
    /// control ([`Cause::NonFinite`] with [`Quantity::Control`]), [`Cause::System`].
    fn acceleration(
        &mut self,
        t: T,
        q: &OVector<T, Q>,
        v: &OVector<T, V>,
    ) -> Result<OVector<T, V>, Cause<T>>;

    /// Whether [`acceleration`](SecondOrder::acceleration) never returns a non-finite value
    /// in `Ok` (then the integrators do not check it again). `false` unless overridden; true for
    /// [`ControlledChain`], whose generated forward dynamics reports a non-finite result as an
    /// error.
    fn finite_acceleration(&self) -> bool {
        false
    }
}

/// A generated chain `C` under a controller `τ = controller(t, q, v)`, with its parameters:
/// `a(t, q, v) = C::forward_dynamics_with(q, v, τ, params)`.
///
/// ```
/// # use articulated::nalgebra::SVector;
/// # use articulated::integrate::{ControlledChain, Integrator, Rk4, State};
/// articulated::chain! {
///     chain Pendulum {
///         body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }
///         joint pivot: revolute(y) { parent: world, child: bob }
///     }
/// }
/// // A damper: τ = −0.1·v.
/// let damper = |_t: f64, _q: &SVector<f64, 1>, v: &SVector<f64, 1>| -v * 0.1;
/// let mut system = ControlledChain::<f64, Pendulum, _>::new(damper);
/// let mut state = State::new(0.0, SVector::<f64, 1>::new(0.5), SVector::<f64, 1>::zeros());
/// Rk4.advance(&mut system, &mut state, 0.01, 0).unwrap();
/// assert!(state.q[0] < 0.5);
/// ```
pub struct ControlledChain<T, C: Chain<T>, F> {
    params: C::Params,
    controller: F,
    chain: PhantomData<fn() -> (C, T)>,
}

impl<T, C: Chain<T>, F> ControlledChain<T, C, F> {
    /// The chain with its default parameters under `controller`.
    pub fn new(controller: F) -> Self {
        Self::with_params(C::default_params(), controller)
    }

    /// The chain with the parameters `params` under `controller`.
    pub fn with_params(params: C::Params, controller: F) -> Self {
        ControlledChain {
            params,
            controller,
            chain: PhantomData,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &C::Params {
        &self.params
    }

    /// The parameters, to change between steps.
    pub fn params_mut(&mut self) -> &mut C::Params {
        &mut self.params
    }

    /// The controller.
    pub fn controller_mut(&mut self) -> &mut F {
        &mut self.controller
    }
}

/// The controller of an unforced chain: `τ = 0`.
pub type Unforced<T, const NQ: usize, const NV: usize> =
    fn(T, &SVector<T, NQ>, &SVector<T, NV>) -> SVector<T, NV>;

fn zero_control<T: RealField + Copy, const NQ: usize, const NV: usize>(
    _t: T,
    _q: &SVector<T, NQ>,
    _v: &SVector<T, NV>,
) -> SVector<T, NV> {
    SVector::zeros()
}

impl<T: RealField + Copy, C, const NQ: usize, const NV: usize>
    ControlledChain<T, C, Unforced<T, NQ, NV>>
where
    C: ForwardDynamics<T, NQ, NV>,
{
    /// The chain with its default parameters and no applied force (`τ = 0`).
    pub fn unforced() -> Self {
        Self::new(zero_control::<T, NQ, NV>)
    }
}

impl<T, C, F, const NQ: usize, const NV: usize> SecondOrder<T, Const<NQ>, Const<NV>>
    for ControlledChain<T, C, F>
where
    T: RealField + Copy,
    C: ForwardDynamics<T, NQ, NV>,
    F: FnMut(T, &SVector<T, NQ>, &SVector<T, NV>) -> SVector<T, NV>,
{
    fn coordinates(&self) -> &[Coordinates] {
        C::COORDINATES
    }

    #[inline]
    fn finite_acceleration(&self) -> bool {
        // `ForwardDynamics` returns `SingularMassMatrix` for a non-finite result.
        true
    }

    #[inline]
    fn acceleration(
        &mut self,
        t: T,
        q: &SVector<T, NQ>,
        v: &SVector<T, NV>,
    ) -> Result<SVector<T, NV>, Cause<T>> {
        let tau = (self.controller)(t, q, v);
        // A non-finite τ makes q̈ non-finite, which the generated code reports as singular:
        // τ is looked at only then, to name the right cause.
        C::forward_dynamics_with(q, v, &tau, &self.params).map_err(|e| {
            match first_non_finite(tau.as_slice()) {
                Some(index) => Cause::NonFinite {
                    quantity: Quantity::Control,
                    index,
                },
                None => Cause::SingularMassMatrix(e),
            }
        })
    }
}

/// Which vector a non-finite value was found in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// `q`, at a step or a stage.
    Position,
    /// `v`, at a step or a stage.
    Velocity,
    /// `τ`, what the controller returned.
    Control,
    /// `v̇`, what the system returned.
    Acceleration,
}

impl Quantity {
    /// The vector's name: `"q"`, `"v"`, `"tau"`, `"acceleration"`.
    pub const fn name(self) -> &'static str {
        match self {
            Quantity::Position => "q",
            Quantity::Velocity => "v",
            Quantity::Control => "tau",
            Quantity::Acceleration => "acceleration",
        }
    }
}

/// Why an integration stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cause<T> {
    /// A NaN or infinite entry: the first one met, in `quantity` at `index`.
    NonFinite {
        /// Which vector.
        quantity: Quantity,
        /// The index of the entry.
        index: usize,
    },
    /// The chain's mass matrix is singular (or not positive definite) at this state.
    SingularMassMatrix(SingularMassMatrix),
    /// [`ImplicitMidpoint`]'s Newton iteration did not converge.
    NewtonFailed {
        /// Iterations done.
        iterations: usize,
        /// The size (max norm) of the last correction; `None` when the Newton matrix was
        /// singular.
        correction: Option<T>,
    },
    /// [`Dopri5`] needed a step below its minimum.
    StepUnderflow {
        /// The step the error control asked for.
        step: T,
        /// The smallest step allowed here: `max(min_step, 4ε·|t|)`.
        min: T,
    },
    /// [`Dopri5`] took its maximum number of steps within one call of `advance`.
    TooManySteps {
        /// That maximum.
        max_steps: usize,
    },
    /// The system's coordinates do not fit its state.
    Coordinates(SizeMismatch),
    /// The target time is not finite or not after the state's time, or a simulation's times
    /// are not finite, increasing and with a positive step.
    InvalidTime,
    /// A caller-provided buffer cannot hold the trajectory.
    BufferTooSmall {
        /// States to record.
        needed: usize,
        /// Room in the buffer.
        capacity: usize,
    },
    /// A quaternion of the state's `q` has a norm off 1 by more than
    /// [`QUATERNION_NORM_TOLERANCE`](crate::spatial::QUATERNION_NORM_TOLERANCE): a mistake in
    /// the initial state (zeros, another library's `[x, y, z, w]` order scaled, …), since the
    /// integrators keep quaternions unit to rounding.
    NotUnitQuaternion {
        /// The index of its `w` entry in `q`.
        index: usize,
        /// Its norm.
        norm: T,
    },
    /// The constrained dynamics gave no solution ([`crate::constraint::ConstrainedChain`]).
    Constraint(crate::constraint::ConstraintError),
    /// A system-specific failure, with its description.
    System(&'static str),
}

impl<T: fmt::Display> fmt::Display for Cause<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Cause::NonFinite { quantity, index } => {
                write!(f, "{}[{index}] is not finite", quantity.name())
            }
            Cause::SingularMassMatrix(e) => write!(f, "{e}"),
            Cause::NewtonFailed {
                iterations,
                correction,
            } => match correction {
                Some(c) => write!(
                    f,
                    "the implicit midpoint's Newton iteration did not converge in {iterations} \
                     iterations (last correction {c})"
                ),
                None => write!(
                    f,
                    "the implicit midpoint's Newton matrix is singular (iteration {iterations})"
                ),
            },
            Cause::StepUnderflow { step, min } => write!(
                f,
                "Dormand–Prince needs a step of {step}, below its minimum {min}: the tolerance \
                 cannot be met here"
            ),
            Cause::TooManySteps { max_steps } => {
                write!(f, "Dormand–Prince took {max_steps} steps in one interval")
            }
            Cause::Coordinates(e) => write!(f, "{e}"),
            Cause::InvalidTime => write!(
                f,
                "invalid times: they must be finite, increasing, with a positive step"
            ),
            Cause::BufferTooSmall { needed, capacity } => write!(
                f,
                "the buffer holds {capacity} states, the trajectory has {needed}"
            ),
            Cause::NotUnitQuaternion { index, norm } => write!(
                f,
                "the quaternion at q[{index}..{}] has norm {norm:.4}, not 1: quaternions are \
                 `[w, x, y, z]`, scalar first",
                index + 4
            ),
            Cause::Constraint(e) => write!(f, "{e}"),
            Cause::System(what) => write!(f, "{what}"),
        }
    }
}

/// An integration stopped: at time `t`, in step `step` (the step from `t_step` to
/// `t_{step+1}`; for a stage of a Runge–Kutta method, `t` is the stage's time), for `cause`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fault<T> {
    /// When.
    pub t: T,
    /// In which step (0-based).
    pub step: usize,
    /// Why.
    pub cause: Cause<T>,
}

impl<T: fmt::Display> fmt::Display for Fault<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "integration stopped at t = {} (step {}): {}",
            self.t, self.step, self.cause
        )
    }
}

impl<T: fmt::Debug + fmt::Display> core::error::Error for Fault<T> {}

/// A method that advances a [`SecondOrder`] system.
pub trait Integrator<T: Scalar, Q: Dim, V: Dim>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// Advances `state` to the time `t_to`: one step of size `t_to − state.t` for a fixed-step
    /// method, as many steps as the error control needs for [`Dopri5`]. `step` is the index
    /// reported in a [`Fault`].
    ///
    /// # Errors
    /// A [`Fault`] (module docs); `state` is then left as it was.
    fn advance<S: SecondOrder<T, Q, V> + ?Sized>(
        &mut self,
        system: &mut S,
        state: &mut State<T, Q, V>,
        t_to: T,
        step: usize,
    ) -> Result<(), Fault<T>>;
}

/// The methods by name, for a command line or a configuration file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// [`Euler`], `euler`.
    Euler,
    /// [`SymplecticEuler`], `symplectic-euler`.
    SymplecticEuler,
    /// [`Rk4`], `rk4`.
    Rk4,
    /// [`Dopri5`], `dopri5`.
    Dopri5,
    /// [`ImplicitMidpoint`], `implicit-midpoint`.
    ImplicitMidpoint,
}

impl Method {
    /// Every method, in the order of the module docs' table.
    pub const ALL: [Method; 5] = [
        Method::Euler,
        Method::SymplecticEuler,
        Method::Rk4,
        Method::Dopri5,
        Method::ImplicitMidpoint,
    ];

    /// The method's name: `euler`, `symplectic-euler`, `rk4`, `dopri5`, `implicit-midpoint`.
    pub const fn name(self) -> &'static str {
        match self {
            Method::Euler => "euler",
            Method::SymplecticEuler => "symplectic-euler",
            Method::Rk4 => "rk4",
            Method::Dopri5 => "dopri5",
            Method::ImplicitMidpoint => "implicit-midpoint",
        }
    }

    /// Its order of convergence.
    pub const fn order(self) -> u32 {
        match self {
            Method::Euler | Method::SymplecticEuler => 1,
            Method::Rk4 => 4,
            Method::Dopri5 => 5,
            Method::ImplicitMidpoint => 2,
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is none of [`Method::ALL`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnknownMethod;

impl fmt::Display for UnknownMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(
            "unknown integrator: expected euler, symplectic-euler, rk4, dopri5 or \
             implicit-midpoint",
        )
    }
}

impl core::error::Error for UnknownMethod {}

impl FromStr for Method {
    type Err = UnknownMethod;
    fn from_str(s: &str) -> Result<Self, UnknownMethod> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or(UnknownMethod)
    }
}

/// One of the integrators, chosen at run time ([`Method`]).
#[derive(Clone, Debug)]
pub enum Stepper<T: Scalar, Q: Dim, V: Dim>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// [`Euler`].
    Euler(Euler),
    /// [`SymplecticEuler`].
    SymplecticEuler(SymplecticEuler),
    /// [`Rk4`].
    Rk4(Rk4),
    /// [`Dopri5`].
    Dopri5(Dopri5<T, Q, V>),
    /// [`ImplicitMidpoint`].
    ImplicitMidpoint(ImplicitMidpoint<T>),
}

impl<T: RealField + Copy, Q: Dim, V: Dim> Stepper<T, Q, V>
where
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// `method` with its default settings; `rtol` and `atol` are [`Dopri5`]'s tolerances
    /// (ignored by the others).
    pub fn new(method: Method, rtol: T, atol: T) -> Self {
        match method {
            Method::Euler => Stepper::Euler(Euler),
            Method::SymplecticEuler => Stepper::SymplecticEuler(SymplecticEuler),
            Method::Rk4 => Stepper::Rk4(Rk4),
            Method::Dopri5 => Stepper::Dopri5(Dopri5::new(rtol, atol)),
            Method::ImplicitMidpoint => Stepper::ImplicitMidpoint(ImplicitMidpoint::new()),
        }
    }

    /// Which method this is.
    pub fn method(&self) -> Method {
        match self {
            Stepper::Euler(_) => Method::Euler,
            Stepper::SymplecticEuler(_) => Method::SymplecticEuler,
            Stepper::Rk4(_) => Method::Rk4,
            Stepper::Dopri5(_) => Method::Dopri5,
            Stepper::ImplicitMidpoint(_) => Method::ImplicitMidpoint,
        }
    }
}

impl<T: RealField + Copy, Q: Dim, V: Dim> Integrator<T, Q, V> for Stepper<T, Q, V>
where
    DefaultAllocator: Allocator<Q> + Allocator<V> + Allocator<V, V>,
{
    fn advance<S: SecondOrder<T, Q, V> + ?Sized>(
        &mut self,
        system: &mut S,
        state: &mut State<T, Q, V>,
        t_to: T,
        step: usize,
    ) -> Result<(), Fault<T>> {
        match self {
            Stepper::Euler(m) => m.advance(system, state, t_to, step),
            Stepper::SymplecticEuler(m) => m.advance(system, state, t_to, step),
            Stepper::Rk4(m) => m.advance(system, state, t_to, step),
            Stepper::Dopri5(m) => m.advance(system, state, t_to, step),
            Stepper::ImplicitMidpoint(m) => m.advance(system, state, t_to, step),
        }
    }
}

// ---- what the methods share ----

pub(crate) use crate::configuration::k;

/// The index of the first non-finite entry. The common case, all finite, is one branch-free
/// pass (`x − x` is 0 for a finite `x`, NaN otherwise).
#[inline]
pub(crate) fn first_non_finite<T: RealField + Copy>(x: &[T]) -> Option<usize> {
    #[allow(clippy::eq_op)] // x − x is not always 0: that is the point.
    let finite = x.iter().fold(true, |ok, &x| ok & ((x - x) == T::zero()));
    if finite {
        None
    } else {
        x.iter().position(|x| !x.is_finite())
    }
}

/// Checks a state: `q` then `v`.
#[inline]
pub(crate) fn check_state<T: RealField + Copy>(q: &[T], v: &[T]) -> Result<(), Cause<T>> {
    if let Some(index) = first_non_finite(q) {
        return Err(Cause::NonFinite {
            quantity: Quantity::Position,
            index,
        });
    }
    if let Some(index) = first_non_finite(v) {
        return Err(Cause::NonFinite {
            quantity: Quantity::Velocity,
            index,
        });
    }
    Ok(())
}

impl<T: Copy> Fault<T> {
    /// `cause ↦` the fault at time `t` in step `step`, for `map_err`.
    #[inline(always)]
    pub(crate) fn at(t: T, step: usize) -> impl Fn(Cause<T>) -> Fault<T> + Copy {
        move |cause| Fault { t, step, cause }
    }
}

/// `x · s`, keeping `x`'s shape (so it works for `Dyn` too).
#[inline]
pub(crate) fn scaled<T, V>(x: &OVector<T, V>, s: T) -> OVector<T, V>
where
    T: RealField + Copy,
    V: Dim,
    DefaultAllocator: Allocator<V>,
{
    x * s
}

/// A zero vector shaped like `x`.
#[inline]
pub(crate) fn zeros_like<T: RealField + Copy, V: Dim>(x: &OVector<T, V>) -> OVector<T, V>
where
    DefaultAllocator: Allocator<V>,
{
    OVector::<T, V>::zeros_generic(x.shape_generic().0, U1)
}

/// A stage's slopes `(θ̇, v̇)`.
pub(crate) type Slopes<T, V> = (OVector<T, V>, OVector<T, V>);

/// One call of [`Integrator::advance`]: the system, whether its coordinates are all vectors
/// (then `⊕` is `+` and `θ̇ = v`, and the methods skip the coordinates walk) and the step index
/// its faults carry. Every method evaluates,
/// moves `q` and reports through it.
pub(crate) struct Step<'a, T, Q, V, S: ?Sized> {
    system: &'a mut S,
    vector_space: bool,
    index: usize,
    dims: PhantomData<(T, Q, V)>,
}

impl<'a, T, Q, V, S> Step<'a, T, Q, V, S>
where
    T: RealField + Copy,
    Q: Dim,
    V: Dim,
    S: SecondOrder<T, Q, V> + ?Sized,
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    /// What every `advance` checks first: the coordinates fit, `t_to` is finite and after
    /// `state.t`, and with `check`, the state is finite (the methods whose first evaluation is
    /// at the state itself leave that to [`Step::evaluate`]). Returns the step `t_to − t`; a
    /// fault is at `state.t`.
    pub(crate) fn begin(
        system: &'a mut S,
        state: &State<T, Q, V>,
        t_to: T,
        index: usize,
        check: bool,
    ) -> Result<(Self, T), Fault<T>> {
        let t = state.t;
        // One pass over the joints: sizes and whether all are vectors.
        let (nq, nv, vector_space) =
            system
                .coordinates()
                .iter()
                .fold((0, 0, true), |(nq, nv, vs), c| {
                    (
                        nq + c.nq(),
                        nv + c.nv(),
                        vs & matches!(c, Coordinates::Vector(_)),
                    )
                });
        let fault = Fault::at(t, index);
        if (nq, nv) != (state.q.len(), state.v.len()) {
            return Err(fault(Cause::Coordinates(SizeMismatch {
                nq,
                nv,
                expected_nq: state.q.len(),
                expected_nv: state.v.len(),
            })));
        }
        if !(t.is_finite() && t_to.is_finite() && t_to > t) {
            return Err(fault(Cause::InvalidTime));
        }
        if check {
            check_state(state.q.as_slice(), state.v.as_slice()).map_err(fault)?;
        }
        if !vector_space {
            crate::configuration::check_unit(system.coordinates(), state.q.as_slice())
                .map_err(|(index, norm)| fault(Cause::NotUnitQuaternion { index, norm }))?;
        }
        let step = Step {
            system,
            vector_space,
            index,
            dims: PhantomData,
        };
        Ok((step, t_to - t))
    }

    /// `cause ↦` the fault at time `t` in this step.
    #[inline(always)]
    pub(crate) fn at(&self, t: T) -> impl Fn(Cause<T>) -> Fault<T> {
        Fault::at(t, self.index)
    }

    /// Whether all coordinates are vectors.
    #[inline(always)]
    pub(crate) fn vector_space(&self) -> bool {
        self.vector_space
    }

    /// The system's coordinates.
    #[inline(always)]
    pub(crate) fn coordinates(&self) -> &[Coordinates] {
        self.system.coordinates()
    }

    /// `a(t, q, v)`, a fault at `t` naming the first non-finite input or output.
    #[inline(always)]
    pub(crate) fn evaluate(
        &mut self,
        t: T,
        q: &OVector<T, Q>,
        v: &OVector<T, V>,
    ) -> Result<OVector<T, V>, Fault<T>> {
        let a = self.system.acceleration(t, q, v).and_then(|a| {
            if self.system.finite_acceleration() {
                return Ok(a);
            }
            match first_non_finite(a.as_slice()) {
                Some(index) => Err(Cause::NonFinite {
                    quantity: Quantity::Acceleration,
                    index,
                }),
                None => Ok(a),
            }
        });
        // A non-finite q or v makes the acceleration fail or come out non-finite (the generated
        // forward dynamics propagates NaN), so the inputs are checked only then, to name the
        // first non-finite quantity: q, v, then what the system found (τ, the acceleration).
        match a {
            Ok(a) => Ok(a),
            Err(cause) => {
                let first = check_state(q.as_slice(), v.as_slice()).err();
                Err(self.at(t)(first.unwrap_or(cause)))
            }
        }
    }

    /// `q ⊕ θ`.
    #[inline(always)]
    pub(crate) fn retract(&self, q: &OVector<T, Q>, theta: &OVector<T, V>) -> OVector<T, Q> {
        let mut out = q.clone();
        if self.vector_space {
            let x = out.as_mut_slice();
            x.iter_mut()
                .zip(theta.as_slice())
                .for_each(|(x, d)| *x += *d);
        } else {
            configuration::integrate_in_place(
                self.coordinates(),
                out.as_mut_slice(),
                theta.as_slice(),
            );
        }
        out
    }

    /// `θ̇` at `θ` for the velocity `vel` ([`configuration::local_velocity_into`]).
    #[inline(always)]
    pub(crate) fn local_velocity(
        &self,
        theta: &OVector<T, V>,
        vel: &OVector<T, V>,
    ) -> OVector<T, V> {
        let mut out = vel.clone();
        if !self.vector_space {
            configuration::local_velocity_into(
                self.coordinates(),
                theta.as_slice(),
                vel.as_slice(),
                out.as_mut_slice(),
            );
        }
        out
    }

    /// One stage of a Runge–Kutta–Munthe-Kaas method at the local coordinates `θ` and velocity
    /// `vel`: the slopes `(θ̇, v̇)` at `(t, q_n ⊕ θ, vel)`; a fault at `t`.
    #[inline(always)]
    pub(crate) fn stage(
        &mut self,
        t: T,
        q_n: &OVector<T, Q>,
        theta: &OVector<T, V>,
        vel: &OVector<T, V>,
    ) -> Result<Slopes<T, V>, Fault<T>> {
        let q = self.retract(q_n, theta);
        let k_theta = self.local_velocity(theta, vel);
        let k_v = self.evaluate(t, &q, vel)?;
        Ok((k_theta, k_v))
    }

    /// Commits a step's result after checking it is finite; on failure the fault is at `t_to`.
    pub(crate) fn commit(
        &self,
        state: &mut State<T, Q, V>,
        t_to: T,
        q: OVector<T, Q>,
        v: OVector<T, V>,
    ) -> Result<(), Fault<T>> {
        check_state(q.as_slice(), v.as_slice()).map_err(self.at(t_to))?;
        state.t = t_to;
        state.q = q;
        state.v = v;
        Ok(())
    }
}
