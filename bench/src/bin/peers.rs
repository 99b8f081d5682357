//! Our side of the comparison against Pinocchio and MuJoCo (`bench/peers/`, `BENCHMARKS.md`):
//! the generated functions of each model, timed on states read from a file, so that every
//! program of the comparison measures the same inputs.
//!
//! ```text
//! peers --layout MODEL                               # joints, coordinates, op counts, frames (JSON)
//! peers --states FILE --values MODEL                 # outputs at the first state (JSON)
//! peers --states FILE --time [--batches N] [--batch-ms T] MODEL   # ns per call (JSON)
//! peers --states FILE --calls K MODEL OUTPUT         # exactly K calls, then exit (callgrind)
//! ```
//!
//! The states file holds `nq nv count` and then, per state, the lines `q`, `v`, `a` and `tau`
//! in *our* convention and joint order (`bench/peers/run.py` writes one per program from a
//! single set of states). A timed call cycles through the states like the `bench_table`
//! harness: the state index, the inputs and the result all go through [`black_box`]. Each
//! output is timed in `--batches` batches of about `--batch-ms` (default 200 of 1 ms) and
//! reported as the fastest and the median batch, in ns per call.
//!
//! The models: the same `.chain` files the generator ships, each generated with the six
//! dynamics outputs of the comparison (and `mass_matrix_update` and `mass_matrix_lower`, `M`
//! and its lower triangle into a kept matrix) and
//! the eight quantities of the whole system (centre of
//! mass, its velocity and Jacobian, centroidal momentum and its matrix, kinetic and potential
//! energy, the Coriolis matrix). Adding one is one line of `models!` below (and one in
//! `run.py`'s model list).
//!
//! The models marked `derivatives` (`arm7`; the humanoid with the feature
//! `humanoid-derivatives`, which `run.sh` turns on) also have the three derivative outputs
//! ([`DERIVATIVE_OUTPUTS`]) and two kernels that are not generated: central differences of the
//! generated `inverse_dynamics` and `forward_dynamics` in `q` ([`DIFFERENCES`]), `2·NV` calls
//! each, what the analytical derivatives replace.
//!
//! Build cost: CI's `cargo test --workspace` compiles this binary too (test profile). With the
//! quantities of the whole system, `cargo test -p articulated-bench --no-run` after touching
//! this file took 29–32 s instead of 13–22 s; `chain50`'s `coriolis_matrix` (126,436
//! operations) is about 10 s of that, the humanoid's (15,393) within the noise. In release
//! (`run.sh`, once per target) `chain50`'s `coriolis_matrix` is about 85 s of this binary's
//! 147 s.
//!
//! The models given `frames [..]` in `models!` (`arm7`: its flange `link7`; the humanoid: both
//! soles and both hands) also have three frame outputs ([`FRAME_OUTPUTS`]) for those frames:
//! their placements, their Jacobians in LOCAL_WORLD_ALIGNED and the time variations of those.
//!
//! The derivative outputs: `arm7`'s are small (about 4,100 and 6,400 operations). The humanoid's
//! (`inverse_dynamics_derivatives` about 41,000 operations, `forward_dynamics_derivatives`
//! 131,000 traced whole, `mass_matrix_inverse` 21,000; measured when they were 41,000, 144,000
//! and 34,000, before `forward_dynamics_derivatives` was composed of the other two, which it is
//! now: `codegen/src/generate/composed.rs`) took this binary's release build from 53 to 120 s
//! (x86-64-v3) and from 96 to 204 s (default target), and cost 2.5–3 min in the test profile
//! (opt-level 1 with debug info; measured on a crate of their own) that CI's `cargo test
//! --workspace` builds this binary with: hence the feature `humanoid-derivatives`, off by
//! default, which `run.sh` turns on.
//!
//! The frame outputs are small enough to stay out of that feature: the humanoid's four frames
//! are a few thousand operations, and `cargo test -p articulated-bench --no-run` took no
//! measurably longer with them than without (measured while adding them).
//!
//! The models given `contacts Type [..]` in `models!` (`arm7`: its flange `link7` welded; the
//! humanoid: both soles flat on the ground) also have the constrained forward dynamics
//! ([`CONSTRAINED`]): each of those frames a six-dimensional contact, declared in a type of its
//! own, `Type`, generated from the same `.chain` file with `contacts = [..: six_d]`, whose
//! generated `constrained_forward_dynamics` is timed; beside it ([`CONSTRAINED_RUNTIME`]) the
//! runtime's [`constraint::constrained_forward_dynamics`] on the same contacts with
//! [`Settings::default`] (exact, `mu = 0`), from the five outputs the declaration adds
//! (`mass_matrix_and_nonlinear_effects`, `frame_placements`, `frame_jacobians_local`,
//! `frame_velocities`, `frame_accelerations`, for exactly the contact frames: the model's own
//! type has the hands too, for the frame outputs). Its `mass_matrix_and_nonlinear_effects` is a
//! second copy of the model's, which made no measurable difference to this binary's
//! test-profile build. For a model marked `derivatives` the contacts' type also has the outputs
//! the runtime's constrained derivatives read (`inverse_dynamics_derivatives`, the frames'
//! Jacobian rates, acceleration and velocity derivatives) and `forward_dynamics_derivatives`,
//! which gives it the generated `constrained_forward_dynamics_derivatives`: that is timed
//! ([`CONSTRAINED_DERIVATIVES`]),
//! and beside it the runtime's [`forward_dynamics_derivatives_of`]
//! ([`CONSTRAINED_DERIVATIVES_RUNTIME`]); for the humanoid, under the same feature
//! `humanoid-derivatives`.

use std::hint::black_box;
use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use articulated::constraint::derivatives::{
    forward_dynamics_derivatives_of, DerivativeOutputs as ConstraintDerivativeOutputs, Derivatives,
};
use articulated::constraint::{self, Contact, Settings};
use articulated::control::tangent::retract;
use articulated::model::JointKind;
use articulated::nalgebra::{SMatrix, SVector};
use articulated::prelude::*;
use articulated_bench::{batch, calibrate, Output};
use clap::Parser;
use serde::{Serialize, Serializer};

/// The outputs of the comparison, in the order they are timed: the six dynamics outputs, then
/// the eight quantities of the whole system.
const OUTPUTS: [Output; 14] = [
    Output::MassMatrix,
    Output::NonlinearEffects,
    Output::Gravity,
    Output::InverseDynamics,
    Output::ForwardDynamics,
    Output::MassMatrixAndNonlinearEffects,
    Output::CenterOfMass,
    Output::CenterOfMassVelocity,
    Output::CenterOfMassJacobian,
    Output::CentroidalMomentum,
    Output::CentroidalMomentumMatrix,
    Output::KineticEnergy,
    Output::PotentialEnergy,
    Output::CoriolisMatrix,
];

/// The derivative outputs, timed after [`OUTPUTS`] for the models generated with them.
const DERIVATIVE_OUTPUTS: [Output; 3] = [
    Output::InverseDynamicsDerivatives,
    Output::ForwardDynamicsDerivatives,
    Output::MassMatrixInverse,
];

/// The frame outputs, timed after the [`DIFFERENCES`] for the models generated with frames:
/// each returns one value per frame of `C::FRAMES`, all of them in one call.
const FRAME_OUTPUTS: [Output; 3] = [
    Output::FramePlacements,
    Output::FrameJacobiansLocalWorldAligned,
    Output::FrameJacobianTimeVariationsLocalWorldAligned,
];

/// The timing of the generated `constrained_forward_dynamics` of the model's contacts (`contacts
/// Type [..]` in `models!`), timed after the [`FRAME_OUTPUTS`].
const CONSTRAINED: &str = "constrained_forward_dynamics";

/// The timing of the runtime's [`constraint::constrained_forward_dynamics`] on the same contacts
/// (what a run-time choice of contacts costs): the five generated functions it reads, then its
/// dense solve.
const CONSTRAINED_RUNTIME: &str = "constrained_forward_dynamics_runtime";

/// The timing of the generated `constrained_forward_dynamics_derivatives` of the model's contacts,
/// for a model marked `derivatives`: the constrained solve with `∂q̈` and `∂f` with respect to
/// `q`, `v` and `τ`.
const CONSTRAINED_DERIVATIVES: &str = "constrained_forward_dynamics_derivatives";

/// The timing of the runtime's [`forward_dynamics_derivatives_of`] on the same contacts (any
/// subset of them at run time): from generated outputs and dense products.
const CONSTRAINED_DERIVATIVES_RUNTIME: &str = "constrained_forward_dynamics_derivatives_runtime";

/// A generated `constrained_forward_dynamics_derivatives`.
type ConstrainedDerivativesFn<const NQ: usize, const NV: usize, const R: usize> =
    fn(
        &SVector<f64, NQ>,
        &SVector<f64, NV>,
        &SVector<f64, NV>,
    ) -> Result<Derivatives<NV, R>, constraint::ConstraintError>;

/// The timing of `C::mass_matrix_update(&q, &mut kept)`: `M` into a [`KeptMassMatrix`], only the
/// entries that can be non-zero written (reported beside `mass_matrix`).
const MASS_MATRIX_UPDATE: &str = "mass_matrix_update";

/// The timing of `C::mass_matrix_lower(&q, &mut kept)`: `M`'s lower triangle into a
/// [`KeptMassMatrixLower`], the half of `M` Pinocchio's `crba` also leaves out (it fills the upper
/// one).
const MASS_MATRIX_LOWER: &str = "mass_matrix_lower";

/// The kernels that are not generated functions: `∂τ/∂q` and `∂q̈/∂q` by central differences of
/// the generated `inverse_dynamics` and `forward_dynamics` ([`central_differences`]), timed after
/// [`DERIVATIVE_OUTPUTS`].
const DIFFERENCES: [&str; 2] = [
    "inverse_dynamics_differences",
    "forward_dynamics_differences",
];

/// The step of [`central_differences`].
const STEP: f64 = 1e-6;

/// A generated model with the outputs of the comparison.
trait Peer<const NQ: usize, const NV: usize>:
    DynamicsOutputs<f64, NQ, NV> + KeptOutputs<f64, NQ, NV> + WholeBodyOutputs<f64, NQ, NV>
{
    /// The `.chain` file the type is generated from (absolute, for `--layout`).
    const CHAIN: &'static str;
    /// Whether the model is generated with the [`DERIVATIVE_OUTPUTS`].
    const DERIVATIVES: bool = false;
    /// The generator's operation counts of `output` (`C::<OUTPUT>_OPS`).
    fn ops(output: Output) -> OpCounts;
    /// Hands `visitor` the closures of the [`DERIVATIVE_OUTPUTS`] and the [`DIFFERENCES`], for a
    /// model generated with them ([`each_derivative`]); nothing otherwise.
    fn each_derivative<V: Visit>(_states: &[State<NQ, NV>], _visitor: &mut V) {}
    /// The derivative outputs at `x` ([`derivative_values`]); `None` for a model without them.
    fn derivative_values(_x: &State<NQ, NV>) -> Option<DerivativeValues> {
        None
    }
    /// Hands `visitor` the closures of the [`FRAME_OUTPUTS`], for a model generated with them
    /// ([`each_frame`]); nothing otherwise.
    fn each_frame<V: Visit>(_states: &[State<NQ, NV>], _visitor: &mut V) {}
    /// The frame outputs at `x` ([`frame_values`]); `None` for a model without them.
    fn frame_values(_x: &State<NQ, NV>) -> Option<FrameValues> {
        None
    }
    /// The contact frames of [`CONSTRAINED`] (`C::FRAMES` of its type); empty for a model
    /// without it.
    const CONTACTS: &'static [&'static str] = &[];
    /// The generator's operation counts of [`CONSTRAINED`] and of the five generated functions
    /// [`CONSTRAINED_RUNTIME`] calls (zeros for a model without them).
    fn constrained_ops() -> (usize, usize) {
        (0, 0)
    }
    /// The generator's operation count of [`CONSTRAINED_DERIVATIVES`], for a model marked
    /// `derivatives` and given contacts.
    fn constrained_derivative_ops() -> Option<usize> {
        None
    }
    /// Hands `visitor` the closures of [`CONSTRAINED`] and [`CONSTRAINED_RUNTIME`], for a
    /// model given contacts ([`each_constrained`]); nothing otherwise.
    fn each_constrained<V: Visit>(_states: &[State<NQ, NV>], _visitor: &mut V) {}
    /// [`CONSTRAINED`] on `states` ([`constrained_values`]); `None` for a model without it.
    fn constrained_values(_states: &[State<NQ, NV>]) -> Option<ConstrainedValues> {
        None
    }
}

/// What a model marked `derivatives` in `models!` implements besides [`Peer`].
trait DerivativePeer<const NQ: usize, const NV: usize>:
    Peer<NQ, NV> + DerivativeOutputs<f64, NQ, NV>
{
}

impl<C, const NQ: usize, const NV: usize> DerivativePeer<NQ, NV> for C where
    C: Peer<NQ, NV> + DerivativeOutputs<f64, NQ, NV>
{
}

/// What a model given `frames [..]` in `models!` implements besides [`Peer`], with `NF` its
/// number of frames.
trait FramePeer<const NQ: usize, const NV: usize, const NF: usize>:
    Peer<NQ, NV>
    + FramePlacements<f64, NQ, NV, NF>
    + FrameJacobiansLocalWorldAligned<f64, NQ, NV, NF>
    + FrameJacobianTimeVariationsLocalWorldAligned<f64, NQ, NV, NF>
{
}

impl<C, const NQ: usize, const NV: usize, const NF: usize> FramePeer<NQ, NV, NF> for C where
    C: Peer<NQ, NV>
        + FramePlacements<f64, NQ, NV, NF>
        + FrameJacobiansLocalWorldAligned<f64, NQ, NV, NF>
        + FrameJacobianTimeVariationsLocalWorldAligned<f64, NQ, NV, NF>
{
}

/// What the type of a model's contacts (`contacts Type [..]` in `models!`) implements: the
/// outputs [`constraint::constrained_forward_dynamics`] needs, with `NF` its contact frames.
trait ConstrainedPeer<const NQ: usize, const NV: usize, const NF: usize>:
    Chain<f64>
    + articulated::MassMatrixAndNonlinearEffects<f64, NQ, NV>
    + FramePlacements<f64, NQ, NV, NF>
    + FrameJacobiansLocal<f64, NQ, NV, NF>
    + FrameVelocities<f64, NQ, NV, NF>
    + FrameAccelerations<f64, NQ, NV, NF>
{
}

impl<C, const NQ: usize, const NV: usize, const NF: usize> ConstrainedPeer<NQ, NV, NF> for C where
    C: Chain<f64>
        + articulated::MassMatrixAndNonlinearEffects<f64, NQ, NV>
        + FramePlacements<f64, NQ, NV, NF>
        + FrameJacobiansLocal<f64, NQ, NV, NF>
        + FrameVelocities<f64, NQ, NV, NF>
        + FrameAccelerations<f64, NQ, NV, NF>
{
}

/// The type of a model's contacts (for `models!`): the same `.chain` file, the outputs of
/// [`ConstrainedPeer`] for exactly the contact frames, and after `derivatives` those of
/// [`ConstraintDerivativeOutputs`] for
/// [`CONSTRAINED_DERIVATIVES`].
macro_rules! contact_type {
    ($kind:ident [] [] $(#[$attr:meta])* $file:literal) => {};
    (plain [$cty:ident] [$($contact:ident),+] $(#[$attr:meta])* $file:literal) => {
        contact_type!(@outputs [] [$cty] [$($contact),+] $(#[$attr])* $file);
    };
    (derivatives [$cty:ident] [$($contact:ident),+] $(#[$attr:meta])* $file:literal) => {
        contact_type!(
            @outputs [
                inverse_dynamics_derivatives,
                forward_dynamics_derivatives,
                frame_jacobian_time_variations_local,
                frame_jacobian_time_variations_local_world_aligned,
                frame_acceleration_derivatives,
                frame_velocity_derivatives
            ]
            [$cty] [$($contact),+] $(#[$attr])* $file
        );
    };
    (
        @outputs [$($extra:ident),*] [$cty:ident] [$($contact:ident),+]
        $(#[$attr:meta])* $file:literal
    ) => {
        $(#[$attr])*
        #[doc = concat!("The generated `", $file, "` with its contact frames, for [`CONSTRAINED`].")]
        #[derive(articulated::Chain)]
        #[chain(
            file = $file,
            outputs = [
                mass_matrix_and_nonlinear_effects,
                frame_placements,
                frame_jacobians_local,
                frame_velocities,
                frame_accelerations
                $(, $extra)*
            ],
            frames = [$($contact),+],
            contacts = [$($contact: six_d),+]
        )]
        struct $cty;
    };
}

/// The members of a `Peer` impl that a model given contacts overrides (for `models!`): `R`, the
/// rows, is six per contact.
macro_rules! contact_members {
    ($kind:ident [] $ty:ident) => {};
    ($kind:ident [$cty:ident] $ty:ident) => {
        const CONTACTS: &'static [&'static str] = <$cty as Chain<f64>>::FRAMES;
        fn constrained_ops() -> (usize, usize) {
            let runtime = [
                $cty::MASS_MATRIX_AND_NONLINEAR_EFFECTS_OPS,
                $cty::FRAME_PLACEMENTS_OPS,
                $cty::FRAME_JACOBIANS_LOCAL_OPS,
                $cty::FRAME_VELOCITIES_OPS,
                $cty::FRAME_ACCELERATIONS_OPS,
            ]
            .iter()
            .map(OpCounts::total)
            .sum();
            ($cty::CONSTRAINED_FORWARD_DYNAMICS_OPS.total(), runtime)
        }
        fn constrained_derivative_ops() -> Option<usize> {
            constrained_derivatives!(ops $kind $cty)
        }
        fn each_constrained<V: Visit>(states: &[State<{ $ty::NQ }, { $ty::NV }>], visitor: &mut V) {
            each_constrained::<$cty, V, { $ty::NQ }, { $ty::NV }, { $cty::NF }, { 6 * $cty::NF }>(
                states,
                $cty::constrained_forward_dynamics,
                visitor,
            );
            constrained_derivatives!(
                $kind $cty, V, { $ty::NQ }, { $ty::NV }, { $cty::NF }, { 6 * $cty::NF }, states, visitor
            );
        }
        fn constrained_values(
            states: &[State<{ $ty::NQ }, { $ty::NV }>],
        ) -> Option<ConstrainedValues> {
            Some(constrained_values::<
                $cty,
                { $ty::NQ },
                { $ty::NV },
                { $cty::NF },
                { 6 * $cty::NF },
            >(states, $cty::constrained_forward_dynamics))
        }
    };
}

/// [`CONSTRAINED_DERIVATIVES`] on `states` for the contacts' type of a model marked
/// `derivatives` (for `models!`); nothing for a `plain` one.
macro_rules! constrained_derivatives {
    (derivatives $cty:ident, $v:ident, $nq:expr, $nv:expr, $nf:expr, $r:expr, $states:ident, $visitor:ident) => {
        each_constrained_derivative::<$cty, $v, $nq, $nv, $nf, $r>(
            $states,
            $cty::constrained_forward_dynamics_derivatives,
            $visitor,
        )
    };
    (ops derivatives $cty:ident) => {
        Some($cty::CONSTRAINED_FORWARD_DYNAMICS_DERIVATIVES_OPS.total())
    };
    (ops plain $cty:ident) => {
        None
    };
    (plain $($rest:tt)*) => {};
}

/// The generated type of one model (for `models!`): the outputs of the comparison, the
/// [`DERIVATIVE_OUTPUTS`] after `derivatives`, and the [`FRAME_OUTPUTS`] of the frames in
/// `frames [..]` where there are any.
macro_rules! peer_type {
    (derivatives $($rest:tt)*) => {
        peer_type!(
            @outputs [derivatives]
            $($rest)*
        );
    };
    (plain $($rest:tt)*) => {
        peer_type!(@outputs [] $($rest)*);
    };
    (@outputs [$($extra:ident),*] [] $(#[$attr:meta])* $ty:ident, $file:literal) => {
        $(#[$attr])*
        #[doc = concat!("The generated `", $file, "`.")]
        #[derive(articulated::Chain)]
        #[chain(
            file = $file,
            outputs = [dynamics, kept, whole_body $(, $extra)*]
        )]
        struct $ty;
    };
    (
        @outputs [$($extra:ident),*] [$($frame:ident),+]
        $(#[$attr:meta])* $ty:ident, $file:literal
    ) => {
        $(#[$attr])*
        #[doc = concat!("The generated `", $file, "`, with frames.")]
        #[derive(articulated::Chain)]
        #[chain(
            file = $file,
            outputs = [
                dynamics,
                kept,
                whole_body,
                $($extra,)*
                frame_placements,
                frame_jacobians_local_world_aligned,
                frame_jacobian_time_variations_local_world_aligned
            ],
            frames = [$($frame),+]
        )]
        struct $ty;
    };
}

/// The members of a `Peer` impl that a model given frames overrides (for `models!`).
macro_rules! frame_members {
    ([] $ty:ident) => {};
    ([$($frame:ident),+] $ty:ident) => {
        fn each_frame<V: Visit>(states: &[State<{ $ty::NQ }, { $ty::NV }>], visitor: &mut V) {
            each_frame::<$ty, V, { $ty::NQ }, { $ty::NV }, { $ty::NF }>(states, visitor);
        }
        fn frame_values(x: &State<{ $ty::NQ }, { $ty::NV }>) -> Option<FrameValues> {
            Some(frame_values::<$ty, { $ty::NQ }, { $ty::NV }, { $ty::NF }>(
                x,
            ))
        }
    };
}

/// The operation counts of the frame outputs of a model given frames (for `models!`).
macro_rules! frame_ops {
    ([] $ty:ident, $output:expr) => {
        OpCounts::default()
    };
    ([$($frame:ident),+] $ty:ident, $output:expr) => {
        match $output {
            Output::FramePlacements => $ty::FRAME_PLACEMENTS_OPS,
            Output::FrameJacobiansLocalWorldAligned => $ty::FRAME_JACOBIANS_LOCAL_WORLD_ALIGNED_OPS,
            Output::FrameJacobianTimeVariationsLocalWorldAligned => {
                $ty::FRAME_JACOBIAN_TIME_VARIATIONS_LOCAL_WORLD_ALIGNED_OPS
            }
            _ => OpCounts::default(),
        }
    };
}

/// The members of a `Peer` impl that a model marked `derivatives` overrides (for `models!`).
macro_rules! derivative_members {
    (derivatives $ty:ident) => {
        const DERIVATIVES: bool = true;
        fn each_derivative<V: Visit>(states: &[State<{ $ty::NQ }, { $ty::NV }>], visitor: &mut V) {
            each_derivative::<$ty, V, { $ty::NQ }, { $ty::NV }>(states, visitor);
        }
        fn derivative_values(x: &State<{ $ty::NQ }, { $ty::NV }>) -> Option<DerivativeValues> {
            Some(derivative_values::<$ty, { $ty::NQ }, { $ty::NV }>(x))
        }
    };
    (plain $ty:ident) => {};
}

/// The operation counts of the derivative outputs of a model marked `derivatives` (for
/// `models!`).
macro_rules! derivative_ops {
    (derivatives $ty:ident, $output:expr) => {
        match $output {
            Output::InverseDynamicsDerivatives => $ty::INVERSE_DYNAMICS_DERIVATIVES_OPS,
            Output::ForwardDynamicsDerivatives => $ty::FORWARD_DYNAMICS_DERIVATIVES_OPS,
            Output::MassMatrixInverse => $ty::MASS_MATRIX_INVERSE_OPS,
            _ => OpCounts::default(),
        }
    };
    (plain $ty:ident, $output:expr) => {
        OpCounts::default()
    };
}

/// Declares each model: a generated type, its `Peer` impl, and its entry in [`with_model`].
/// `derivatives` generates the [`DERIVATIVE_OUTPUTS`] too, `plain` does not; `frames [a, b]`
/// generates the [`FRAME_OUTPUTS`] for the frames `a` and `b` (a body's name, or a frame the
/// file declares), `frames []` none; `contacts Type [a, b]` generates `Type` for [`CONSTRAINED`]
/// with `a` and `b` six-dimensional contacts, `contacts []` none; attributes (a `cfg`) apply to
/// all of them.
macro_rules! models {
    ($(
        $(#[$attr:meta])*
        $name:literal => $ty:ident, $file:literal, $kind:ident, frames [$($frame:ident),*],
            contacts $($cty:ident)? [$($contact:ident),*];
    )*) => {
        $(
            peer_type!($kind [$($frame),*] $(#[$attr])* $ty, $file);
            contact_type!($kind [$($cty)?] [$($contact),*] $(#[$attr])* $file);

            $(#[$attr])*
            impl Peer<{ $ty::NQ }, { $ty::NV }> for $ty {
                const CHAIN: &'static str = concat!(env!("CARGO_MANIFEST_DIR"), "/", $file);
                fn ops(output: Output) -> OpCounts {
                    match output {
                        Output::MassMatrix => $ty::MASS_MATRIX_OPS,
                        Output::NonlinearEffects => $ty::NONLINEAR_EFFECTS_OPS,
                        Output::Gravity => $ty::GRAVITY_OPS,
                        Output::InverseDynamics => $ty::INVERSE_DYNAMICS_OPS,
                        Output::ForwardDynamics => $ty::FORWARD_DYNAMICS_OPS,
                        Output::MassMatrixAndNonlinearEffects => {
                            $ty::MASS_MATRIX_AND_NONLINEAR_EFFECTS_OPS
                        }
                        Output::CenterOfMass => $ty::CENTER_OF_MASS_OPS,
                        Output::CenterOfMassVelocity => $ty::CENTER_OF_MASS_VELOCITY_OPS,
                        Output::CenterOfMassJacobian => $ty::CENTER_OF_MASS_JACOBIAN_OPS,
                        Output::CentroidalMomentum => $ty::CENTROIDAL_MOMENTUM_OPS,
                        Output::CentroidalMomentumMatrix => $ty::CENTROIDAL_MOMENTUM_MATRIX_OPS,
                        Output::KineticEnergy => $ty::KINETIC_ENERGY_OPS,
                        Output::PotentialEnergy => $ty::POTENTIAL_ENERGY_OPS,
                        Output::CoriolisMatrix => $ty::CORIOLIS_MATRIX_OPS,
                        Output::InverseDynamicsDerivatives
                        | Output::ForwardDynamicsDerivatives
                        | Output::MassMatrixInverse => derivative_ops!($kind $ty, output),
                        _ => frame_ops!([$($frame),*] $ty, output),
                    }
                }
                derivative_members!($kind $ty);
                frame_members!([$($frame),*] $ty);
                contact_members!($kind [$($cty)?] $ty);
            }
        )*

        /// Runs `cmd` on the model called `name`; `Err` if there is none.
        fn with_model(name: &str, cmd: &Command) -> Result<(), String> {
            match name {
                $($(#[$attr])* $name => run::<$ty, { $ty::NQ }, { $ty::NV }>(cmd),)*
                _ => {
                    let mut known: Vec<&str> = Vec::new();
                    $($(#[$attr])* known.push($name);)*
                    Err(format!("unknown model `{name}` (known: {})", known.join(", ")))
                }
            }
        }
    };
}

models! {
    "arm7" => Arm7, "../models/arm7.chain", derivatives, frames [link7],
        contacts Arm7Welded [link7];
    "arm7_floating" => Arm7Floating, "peers/arm7_floating.chain", plain, frames [], contacts [];
    #[cfg(feature = "humanoid-derivatives")]
    "humanoid" => Humanoid, "../models/humanoid.chain", derivatives,
        frames [left_foot, right_foot, left_hand, right_hand],
        contacts HumanoidFeet [left_foot, right_foot];
    #[cfg(not(feature = "humanoid-derivatives"))]
    "humanoid" => Humanoid, "../models/humanoid.chain", plain,
        frames [left_foot, right_foot, left_hand, right_hand],
        contacts HumanoidFeet [left_foot, right_foot];
    "chain50" => Chain50, "../models/chain50.chain", plain, frames [], contacts [];
}

/// Our side of the comparison against Pinocchio and MuJoCo (`bench/peers/run.py` runs it):
/// the generated functions of one model on the states of a file, as JSON.
#[derive(Parser)]
#[command(
    name = "peers",
    override_usage = "peers --layout MODEL
       peers --states FILE --values MODEL
       peers --states FILE --time [--batches N] [--batch-ms T] MODEL
       peers --states FILE --calls K MODEL OUTPUT",
    group = clap::ArgGroup::new("mode").required(true).args(["layout", "values", "time", "calls"])
)]
struct Cli {
    /// Print the model's joints, coordinates and op counts (JSON).
    #[arg(long)]
    layout: bool,
    /// Print the outputs at the first state of the states file (JSON).
    #[arg(long, requires = "states")]
    values: bool,
    /// Time every output on the states of the states file: ns per call (JSON).
    #[arg(long, requires = "states")]
    time: bool,
    /// Make exactly K calls of OUTPUT on the states of the states file, then exit (callgrind).
    #[arg(long, value_name = "K", requires_all = ["states", "output"])]
    calls: Option<usize>,
    /// The states file: `nq nv count`, then per state the lines q, v, a, tau (our convention).
    #[arg(long, value_name = "FILE")]
    states: Option<String>,
    /// Batches per output (--time); at least 1.
    #[arg(long, value_name = "N", default_value_t = 200)]
    batches: usize,
    /// Target duration of one batch in milliseconds (--time).
    #[arg(long, value_name = "T", default_value_t = 1.0)]
    batch_ms: f64,
    /// The model: arm7, arm7_floating, humanoid, chain50.
    model: String,
    /// With --calls: the output or kernel to call (an output's name, frame outputs included,
    /// mass_matrix_update, mass_matrix_lower, inverse_dynamics_differences,
    /// forward_dynamics_differences, constrained_forward_dynamics,
    /// constrained_forward_dynamics_runtime, constrained_forward_dynamics_derivatives,
    /// constrained_forward_dynamics_derivatives_runtime).
    #[arg(requires = "calls")]
    output: Option<String>,
}

/// What the command line asks for.
enum Command {
    /// Print the joints, coordinates and op counts.
    Layout,
    /// Print the outputs at the first state of the file.
    Values(String),
    /// Time every output.
    Time {
        /// The states file.
        states: String,
        /// Batches per output.
        batches: usize,
        /// Target duration of one batch.
        batch: Duration,
    },
    /// Make exactly `calls` calls of `output`.
    Calls {
        /// The states file.
        states: String,
        /// How many calls.
        calls: usize,
        /// Which output or kernel ([`OUTPUTS`], [`DERIVATIVE_OUTPUTS`], [`DIFFERENCES`],
        /// [`FRAME_OUTPUTS`], [`CONSTRAINED`], [`CONSTRAINED_RUNTIME`]).
        output: String,
    },
}

/// One input state, in our convention.
struct State<const NQ: usize, const NV: usize> {
    /// Positions.
    q: SVector<f64, NQ>,
    /// Velocities.
    v: SVector<f64, NV>,
    /// Accelerations (the input of inverse dynamics).
    a: SVector<f64, NV>,
    /// Joint forces (the input of forward dynamics).
    tau: SVector<f64, NV>,
}

/// Reads a states file: `nq nv count`, then `count` times `q`, `v`, `a`, `tau`.
fn read_states<const NQ: usize, const NV: usize>(path: &str) -> Result<Vec<State<NQ, NV>>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut nums = text
        .split_whitespace()
        .map(|w| w.parse::<f64>().map_err(|e| format!("{path}: `{w}`: {e}")));
    let mut next = || {
        nums.next()
            .unwrap_or_else(|| Err(format!("{path}: too short")))
    };
    let (nq, nv, count) = (next()?, next()?, next()?);
    if nq != NQ as f64 || nv != NV as f64 {
        return Err(format!(
            "{path}: nq {nq}, nv {nv}, but the model has nq {NQ}, nv {NV}"
        ));
    }
    let count = count as usize;
    if count == 0 || !count.is_power_of_two() {
        return Err(format!("{path}: {count} states, want a power of two"));
    }
    let mut states = Vec::with_capacity(count);
    for _ in 0..count {
        let mut vector =
            |n: usize| -> Result<Vec<f64>, String> { (0..n).map(|_| next()).collect() };
        states.push(State {
            q: SVector::from_column_slice(&vector(NQ)?),
            v: SVector::from_column_slice(&vector(NV)?),
            a: SVector::from_column_slice(&vector(NV)?),
            tau: SVector::from_column_slice(&vector(NV)?),
        });
    }
    Ok(states)
}

/// Receives one closure per output; each makes one call on state `i` (masked to the states).
trait Visit {
    /// Called once per output, by name, in the order of [`OUTPUTS`], then
    /// [`DERIVATIVE_OUTPUTS`] and [`DIFFERENCES`], then [`FRAME_OUTPUTS`], then [`CONSTRAINED`]
    /// and [`CONSTRAINED_RUNTIME`], where the model has them.
    fn visit<F: FnMut(usize)>(&mut self, name: &'static str, f: F);
}

/// Hands `visitor` the closure of every output of model `M` on `states`.
fn each_output<M, V, const NQ: usize, const NV: usize>(states: &[State<NQ, NV>], visitor: &mut V)
where
    M: Peer<NQ, NV>,
    V: Visit,
{
    let mask = states.len() - 1;
    let s = |i: usize| &states[i & mask];
    visitor.visit(Output::MassMatrix.name(), |i| {
        black_box(M::mass_matrix(black_box(&s(i).q)));
    });
    // `M` into a kept matrix, as Pinocchio's `crba` writes into `data.M`.
    let mut kept = KeptMassMatrix::<M, f64, NV>::new();
    visitor.visit(MASS_MATRIX_UPDATE, |i| {
        M::mass_matrix_update(black_box(&s(i).q), &mut kept);
        black_box(&kept);
    });
    let mut lower = KeptMassMatrixLower::<M, f64, NV>::new();
    visitor.visit(MASS_MATRIX_LOWER, |i| {
        M::mass_matrix_lower(black_box(&s(i).q), &mut lower);
        black_box(&lower);
    });
    visitor.visit(Output::NonlinearEffects.name(), |i| {
        let x = s(i);
        black_box(M::nonlinear_effects(black_box(&x.q), black_box(&x.v)));
    });
    visitor.visit(Output::Gravity.name(), |i| {
        black_box(M::gravity(black_box(&s(i).q)));
    });
    visitor.visit(Output::InverseDynamics.name(), |i| {
        let x = s(i);
        black_box(M::inverse_dynamics(
            black_box(&x.q),
            black_box(&x.v),
            black_box(&x.a),
        ));
    });
    visitor.visit(Output::ForwardDynamics.name(), |i| {
        let x = s(i);
        let _ = black_box(M::forward_dynamics(
            black_box(&x.q),
            black_box(&x.v),
            black_box(&x.tau),
        ));
    });
    visitor.visit(Output::MassMatrixAndNonlinearEffects.name(), |i| {
        let x = s(i);
        black_box(M::mass_matrix_and_nonlinear_effects(
            black_box(&x.q),
            black_box(&x.v),
        ));
    });
    visitor.visit(Output::CenterOfMass.name(), |i| {
        black_box(M::center_of_mass(black_box(&s(i).q)));
    });
    visitor.visit(Output::CenterOfMassVelocity.name(), |i| {
        let x = s(i);
        black_box(M::center_of_mass_velocity(black_box(&x.q), black_box(&x.v)));
    });
    visitor.visit(Output::CenterOfMassJacobian.name(), |i| {
        black_box(M::center_of_mass_jacobian(black_box(&s(i).q)));
    });
    visitor.visit(Output::CentroidalMomentum.name(), |i| {
        let x = s(i);
        black_box(M::centroidal_momentum(black_box(&x.q), black_box(&x.v)));
    });
    visitor.visit(Output::CentroidalMomentumMatrix.name(), |i| {
        black_box(M::centroidal_momentum_matrix(black_box(&s(i).q)));
    });
    visitor.visit(Output::KineticEnergy.name(), |i| {
        let x = s(i);
        black_box(M::kinetic_energy(black_box(&x.q), black_box(&x.v)));
    });
    visitor.visit(Output::PotentialEnergy.name(), |i| {
        black_box(M::potential_energy(black_box(&s(i).q)));
    });
    visitor.visit(Output::CoriolisMatrix.name(), |i| {
        let x = s(i);
        black_box(M::coriolis_matrix(black_box(&x.q), black_box(&x.v)));
    });
    M::each_derivative(states, visitor);
    M::each_frame(states, visitor);
    M::each_constrained(states, visitor);
}

/// `∂f/∂q` at `q` by central differences along the configuration's tangent
/// (`control::tangent::retract`, the convention of the derivative outputs), step [`STEP`]: `2·NV`
/// calls of `f`.
fn central_differences<const NQ: usize, const NV: usize>(
    coordinates: &[Coordinates],
    q: &SVector<f64, NQ>,
    mut f: impl FnMut(&SVector<f64, NQ>) -> SVector<f64, NV>,
) -> SMatrix<f64, NV, NV> {
    let mut out = SMatrix::<f64, NV, NV>::zeros();
    let mut delta = SVector::<f64, NV>::zeros();
    let (mut plus, mut minus) = (*q, *q);
    for k in 0..NV {
        delta[k] = STEP;
        retract(
            coordinates,
            q.as_slice(),
            delta.as_slice(),
            plus.as_mut_slice(),
        );
        delta[k] = -STEP;
        retract(
            coordinates,
            q.as_slice(),
            delta.as_slice(),
            minus.as_mut_slice(),
        );
        delta[k] = 0.0;
        out.set_column(k, &((f(&plus) - f(&minus)) / (2.0 * STEP)));
    }
    out
}

/// `∂τ/∂q` by [`central_differences`] of the generated `inverse_dynamics`.
fn inverse_dynamics_differences<M: Peer<NQ, NV>, const NQ: usize, const NV: usize>(
    x: &State<NQ, NV>,
) -> SMatrix<f64, NV, NV> {
    central_differences(<M as Chain<f64>>::COORDINATES, &x.q, |q| {
        M::inverse_dynamics(black_box(q), black_box(&x.v), black_box(&x.a))
    })
}

/// `∂q̈/∂q` by [`central_differences`] of the generated `forward_dynamics` (NaN where `M` is
/// singular).
fn forward_dynamics_differences<M: Peer<NQ, NV>, const NQ: usize, const NV: usize>(
    x: &State<NQ, NV>,
) -> SMatrix<f64, NV, NV> {
    central_differences(<M as Chain<f64>>::COORDINATES, &x.q, |q| {
        M::forward_dynamics(black_box(q), black_box(&x.v), black_box(&x.tau))
            .unwrap_or_else(|_| SVector::repeat(f64::NAN))
    })
}

/// Hands `visitor` the closures of the [`DERIVATIVE_OUTPUTS`] and the [`DIFFERENCES`] of model
/// `M` on `states`.
fn each_derivative<M, V, const NQ: usize, const NV: usize>(
    states: &[State<NQ, NV>],
    visitor: &mut V,
) where
    M: DerivativePeer<NQ, NV>,
    V: Visit,
{
    let mask = states.len() - 1;
    let s = |i: usize| &states[i & mask];
    visitor.visit(Output::InverseDynamicsDerivatives.name(), |i| {
        let x = s(i);
        black_box(M::inverse_dynamics_derivatives(
            black_box(&x.q),
            black_box(&x.v),
            black_box(&x.a),
        ));
    });
    visitor.visit(Output::ForwardDynamicsDerivatives.name(), |i| {
        let x = s(i);
        let _ = black_box(M::forward_dynamics_derivatives(
            black_box(&x.q),
            black_box(&x.v),
            black_box(&x.tau),
        ));
    });
    visitor.visit(Output::MassMatrixInverse.name(), |i| {
        let _ = black_box(M::mass_matrix_inverse(black_box(&s(i).q)));
    });
    visitor.visit(DIFFERENCES[0], |i| {
        black_box(inverse_dynamics_differences::<M, NQ, NV>(black_box(s(i))));
    });
    visitor.visit(DIFFERENCES[1], |i| {
        black_box(forward_dynamics_differences::<M, NQ, NV>(black_box(s(i))));
    });
}

/// Hands `visitor` the closures of the [`FRAME_OUTPUTS`] of model `M` on `states`: each call
/// computes all `NF` frames.
fn each_frame<M, V, const NQ: usize, const NV: usize, const NF: usize>(
    states: &[State<NQ, NV>],
    visitor: &mut V,
) where
    M: FramePeer<NQ, NV, NF>,
    V: Visit,
{
    let mask = states.len() - 1;
    let s = |i: usize| &states[i & mask];
    visitor.visit(Output::FramePlacements.name(), |i| {
        black_box(M::frame_placements(black_box(&s(i).q)));
    });
    visitor.visit(Output::FrameJacobiansLocalWorldAligned.name(), |i| {
        black_box(M::frame_jacobians_local_world_aligned(black_box(&s(i).q)));
    });
    visitor.visit(
        Output::FrameJacobianTimeVariationsLocalWorldAligned.name(),
        |i| {
            let x = s(i);
            black_box(M::frame_jacobian_time_variations_local_world_aligned(
                black_box(&x.q),
                black_box(&x.v),
            ));
        },
    );
}

/// The contacts of [`CONSTRAINED`]: each of the `NF` frames of its type a six-dimensional
/// contact, in their order.
fn six_d_contacts<const NF: usize>() -> [Contact; NF] {
    core::array::from_fn(Contact::six_d)
}

/// A generated `constrained_forward_dynamics` (`generated` below).
type Solve<const NQ: usize, const NV: usize, const R: usize> =
    fn(
        &SVector<f64, NQ>,
        &SVector<f64, NV>,
        &SVector<f64, NV>,
    ) -> Result<(SVector<f64, NV>, SVector<f64, R>), constraint::ConstraintError>;

/// Hands `visitor` the closures of [`CONSTRAINED`] (`generated`, the type's own) and
/// [`CONSTRAINED_RUNTIME`] on `states`, with `K` the type of the model's contacts (`NF` frames,
/// `R = 6·NF` rows).
fn each_constrained<K, V, const NQ: usize, const NV: usize, const NF: usize, const R: usize>(
    states: &[State<NQ, NV>],
    generated: Solve<NQ, NV, R>,
    visitor: &mut V,
) where
    K: ConstrainedPeer<NQ, NV, NF>,
    V: Visit,
{
    let mask = states.len() - 1;
    let s = |i: usize| &states[i & mask];
    let contacts = six_d_contacts::<NF>();
    let settings = Settings::default();
    visitor.visit(CONSTRAINED, |i| {
        let x = s(i);
        let _ = black_box(generated(
            black_box(&x.q),
            black_box(&x.v),
            black_box(&x.tau),
        ));
    });
    visitor.visit(CONSTRAINED_RUNTIME, |i| {
        let x = s(i);
        let _ = black_box(
            constraint::constrained_forward_dynamics::<K, NQ, NV, NF, R>(
                black_box(&x.q),
                black_box(&x.v),
                black_box(&x.tau),
                black_box(&contacts),
                None,
                &settings,
            ),
        );
    });
}

/// Hands `visitor` the closures of [`CONSTRAINED_DERIVATIVES`] (`generated`, the contacts' type's
/// `constrained_forward_dynamics_derivatives`) and [`CONSTRAINED_DERIVATIVES_RUNTIME`] on
/// `states`, with `K` the type of the model's contacts (`NF` frames, `R = 6·NF` rows), generated
/// with the derivative outputs.
fn each_constrained_derivative<
    K,
    V,
    const NQ: usize,
    const NV: usize,
    const NF: usize,
    const R: usize,
>(
    states: &[State<NQ, NV>],
    generated: ConstrainedDerivativesFn<NQ, NV, R>,
    visitor: &mut V,
) where
    K: ConstraintDerivativeOutputs<NQ, NV, NF>,
    V: Visit,
{
    let mask = states.len() - 1;
    let contacts = six_d_contacts::<NF>();
    visitor.visit(CONSTRAINED_DERIVATIVES, |i| {
        let x = &states[i & mask];
        let _ = black_box(generated(
            black_box(&x.q),
            black_box(&x.v),
            black_box(&x.tau),
        ));
    });
    visitor.visit(CONSTRAINED_DERIVATIVES_RUNTIME, |i| {
        let x = &states[i & mask];
        let _ = black_box(forward_dynamics_derivatives_of::<K, NQ, NV, NF, R>(
            black_box(&x.q),
            black_box(&x.v),
            black_box(&x.tau),
            black_box(&contacts),
            &[],
        ));
    });
}

/// Times each output: `batches` batches of about `batch`, the fastest and the median.
struct Timer {
    /// Batches per output.
    batches: usize,
    /// Target duration of one batch.
    batch: Duration,
    /// One member per output.
    timings: Members<Timing>,
}

/// The timing of one output (`--time`), in ns per call.
#[derive(Serialize)]
struct Timing {
    /// The fastest batch, to 3 decimals.
    min: f64,
    /// The median batch, to 3 decimals.
    median: f64,
    /// Calls in each batch.
    calls_per_batch: usize,
}

/// A JSON object whose members keep their order (a `serde_json::Map` sorts them).
struct Members<V>(Vec<(&'static str, V)>);

impl<V: Serialize> Serialize for Members<V> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

/// `x` rounded to 3 decimals as printed (`{:.3}`), the precision of a timing.
fn three_decimals(x: f64) -> f64 {
    format!("{x:.3}").parse().unwrap_or(x)
}

impl Visit for Timer {
    fn visit<F: FnMut(usize)>(&mut self, name: &'static str, mut f: F) {
        let n = calibrate(&mut f, self.batch);
        let mut ns: Vec<f64> = (0..self.batches)
            .map(|_| batch(&mut f, n).as_secs_f64() * 1e9 / n as f64)
            .collect();
        ns.sort_by(f64::total_cmp);
        self.timings.0.push((
            name,
            Timing {
                min: three_decimals(ns[0]),
                median: three_decimals(ns[ns.len() / 2]),
                calls_per_batch: n,
            },
        ));
    }
}

/// Makes exactly `calls` calls of one output (for callgrind).
struct Only<'a> {
    /// Which output.
    output: &'a str,
    /// How many calls.
    calls: usize,
    /// Whether the model has that output.
    found: bool,
}

impl Visit for Only<'_> {
    fn visit<F: FnMut(usize)>(&mut self, name: &'static str, mut f: F) {
        if name == self.output {
            black_box(batch(&mut f, self.calls));
            self.found = true;
        }
    }
}

/// A matrix row by row (how the JSON holds matrices).
type Rows = Vec<Vec<f64>>;

/// `m` row by row.
fn rows<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> Rows {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}

/// `v` as a list.
fn vector<const N: usize>(v: &SVector<f64, N>) -> Vec<f64> {
    v.iter().copied().collect()
}

/// One joint with coordinates (`--layout`).
#[derive(Serialize)]
struct Joint {
    /// Its name in the `.chain` file.
    name: String,
    /// `revolute`, `prismatic`, `free` or `other`.
    kind: &'static str,
    /// Where its positions start in `q`.
    iq: usize,
    /// How many positions.
    nq: usize,
    /// Where its velocities start in `v`.
    iv: usize,
    /// How many velocities.
    nv: usize,
}

/// What `--layout` prints.
#[derive(Serialize)]
struct Layout {
    /// Positions.
    nq: usize,
    /// Velocities.
    nv: usize,
    /// The joints with coordinates, in order.
    joints: Vec<Joint>,
    /// The generator's operation count of each output.
    ops: Members<usize>,
    /// Whether the model has the [`DERIVATIVE_OUTPUTS`].
    derivatives: bool,
    /// The frames of the [`FRAME_OUTPUTS`], in their order (`C::FRAMES`); empty for a model
    /// without them.
    frames: &'static [&'static str],
    /// The six-dimensional contacts of [`CONSTRAINED`], in their order (the frames of its
    /// type); empty for a model without it.
    contacts: &'static [&'static str],
}

/// The joints with coordinates of model `M` (name, kind, where its coordinates start), and
/// the op counts of each output.
fn layout<M: Peer<NQ, NV>, const NQ: usize, const NV: usize>() -> Result<Layout, String> {
    let model = articulated_codegen::load::load_model(Path::new(M::CHAIN), false)
        .map_err(|e| format!("{}: {e}", M::CHAIN))?;
    let mut joints = Vec::new();
    let (mut iq, mut iv) = (0, 0);
    for j in model.joints.iter().filter(|j| j.kind != JointKind::Fixed) {
        let kind = match j.kind {
            JointKind::Revolute { .. } => "revolute",
            JointKind::Prismatic { .. } => "prismatic",
            JointKind::FreeQuaternion => "free",
            _ => "other",
        };
        joints.push(Joint {
            name: j.name.clone(),
            kind,
            iq,
            nq: j.kind.nq(),
            iv,
            nv: j.kind.nv(),
        });
        iq += j.kind.nq();
        iv += j.kind.nv();
    }
    if (iq, iv) != (NQ, NV) {
        return Err(format!(
            "{}: the joints add up to nq {iq}, nv {iv}, the generated type has {NQ}, {NV}",
            M::CHAIN
        ));
    }
    let derivatives: &[Output] = if M::DERIVATIVES {
        &DERIVATIVE_OUTPUTS
    } else {
        &[]
    };
    let frames: &[Output] = if <M as Chain<f64>>::FRAMES.is_empty() {
        &[]
    } else {
        &FRAME_OUTPUTS
    };
    let mut ops: Vec<_> = OUTPUTS
        .iter()
        .chain(derivatives)
        .chain(frames)
        .map(|&o| (o.name(), M::ops(o).total()))
        .collect();
    if !M::CONTACTS.is_empty() {
        // The runtime's: the generated part only, its solve not counted.
        let (generated, runtime) = M::constrained_ops();
        ops.push((CONSTRAINED, generated));
        ops.push((CONSTRAINED_RUNTIME, runtime));
        if let Some(derivatives) = M::constrained_derivative_ops() {
            ops.push((CONSTRAINED_DERIVATIVES, derivatives));
        }
    }
    Ok(Layout {
        nq: NQ,
        nv: NV,
        joints,
        ops: Members(ops),
        derivatives: M::DERIVATIVES,
        frames: <M as Chain<f64>>::FRAMES,
        contacts: M::CONTACTS,
    })
}

/// `inverse_dynamics_derivatives` (`--values`).
#[derive(Serialize)]
struct InverseDynamicsDerivatives {
    /// `∂τ/∂q`.
    dtau_dq: Rows,
    /// `∂τ/∂v`.
    dtau_dv: Rows,
}

/// `forward_dynamics_derivatives` (`--values`).
#[derive(Serialize)]
struct ForwardDynamicsDerivatives {
    /// `∂q̈/∂q`.
    ddq_dq: Rows,
    /// `∂q̈/∂v`.
    ddq_dv: Rows,
    /// `M⁻¹`.
    minv: Rows,
}

/// The [`DERIVATIVE_OUTPUTS`] and [`DIFFERENCES`] at one state (`--values`; `None`, `null`,
/// where `M` is singular).
#[derive(Serialize)]
struct DerivativeValues {
    /// `inverse_dynamics_derivatives`.
    inverse_dynamics_derivatives: InverseDynamicsDerivatives,
    /// `forward_dynamics_derivatives`.
    forward_dynamics_derivatives: Option<ForwardDynamicsDerivatives>,
    /// `mass_matrix_inverse`.
    mass_matrix_inverse: Option<Rows>,
    /// [`inverse_dynamics_differences`].
    inverse_dynamics_differences: Rows,
    /// [`forward_dynamics_differences`] (NaN, `null`, where `M` is singular).
    forward_dynamics_differences: Rows,
}

/// The [`DERIVATIVE_OUTPUTS`] and [`DIFFERENCES`] of model `M` at `x`.
fn derivative_values<M: DerivativePeer<NQ, NV>, const NQ: usize, const NV: usize>(
    x: &State<NQ, NV>,
) -> DerivativeValues {
    let (dtau_dq, dtau_dv) = M::inverse_dynamics_derivatives(&x.q, &x.v, &x.a);
    DerivativeValues {
        inverse_dynamics_derivatives: InverseDynamicsDerivatives {
            dtau_dq: rows(&dtau_dq),
            dtau_dv: rows(&dtau_dv),
        },
        forward_dynamics_derivatives: M::forward_dynamics_derivatives(&x.q, &x.v, &x.tau)
            .ok()
            .map(|(dq, dv, minv)| ForwardDynamicsDerivatives {
                ddq_dq: rows(&dq),
                ddq_dv: rows(&dv),
                minv: rows(&minv),
            }),
        mass_matrix_inverse: M::mass_matrix_inverse(&x.q).ok().map(|m| rows(&m)),
        inverse_dynamics_differences: rows(&inverse_dynamics_differences::<M, NQ, NV>(x)),
        forward_dynamics_differences: rows(&forward_dynamics_differences::<M, NQ, NV>(x)),
    }
}

/// One frame's placement (`--values`).
#[derive(Serialize)]
struct Placement {
    /// `world_R_frame`, row by row.
    rotation: Rows,
    /// The frame's origin in the world.
    translation: Vec<f64>,
}

/// The [`FRAME_OUTPUTS`] at one state (`--values`), one entry per frame in the order of
/// `C::FRAMES`; the Jacobians and their rates angular rows first, columns in our joint order.
#[derive(Serialize)]
struct FrameValues {
    /// `frame_placements`.
    frame_placements: Vec<Placement>,
    /// `frame_jacobians_local_world_aligned`.
    frame_jacobians_local_world_aligned: Vec<Rows>,
    /// `frame_jacobian_time_variations_local_world_aligned`.
    frame_jacobian_time_variations_local_world_aligned: Vec<Rows>,
}

/// The [`FRAME_OUTPUTS`] of model `M` at `x`.
fn frame_values<M: FramePeer<NQ, NV, NF>, const NQ: usize, const NV: usize, const NF: usize>(
    x: &State<NQ, NV>,
) -> FrameValues {
    FrameValues {
        frame_placements: M::frame_placements(&x.q)
            .iter()
            .map(|p| Placement {
                rotation: rows(&p.rotation),
                translation: vector(&p.translation),
            })
            .collect(),
        frame_jacobians_local_world_aligned: M::frame_jacobians_local_world_aligned(&x.q)
            .iter()
            .map(rows)
            .collect(),
        frame_jacobian_time_variations_local_world_aligned:
            M::frame_jacobian_time_variations_local_world_aligned(&x.q, &x.v)
                .iter()
                .map(rows)
                .collect(),
    }
}

/// [`CONSTRAINED`] at the first state (`--values`), and the states where it fails.
#[derive(Serialize)]
struct ConstrainedValues {
    /// `q̈` (`null` where the first state fails).
    acceleration: Option<Vec<f64>>,
    /// Each contact's wrench `[n; f]` in its frame, in the order of the contacts.
    forces: Option<Vec<Vec<f64>>>,
    /// `max |J·q̈ + γ|` over the rows, of the runtime's solution.
    residual: Option<f64>,
    /// `state k: the error`, for every state of the file whose solve fails (a timed call on it
    /// would return early): the driver stops on any.
    errors: Vec<String>,
}

/// [`CONSTRAINED`] of the contacts' type `K` on `states` (`generated`, its own function): the
/// solution at the first, the errors of all, and of [`CONSTRAINED_RUNTIME`] on the same contacts
/// where it fails or differs from it by more than 1e-10 of the largest entry.
fn constrained_values<K, const NQ: usize, const NV: usize, const NF: usize, const R: usize>(
    states: &[State<NQ, NV>],
    generated: Solve<NQ, NV, R>,
) -> ConstrainedValues
where
    K: ConstrainedPeer<NQ, NV, NF>,
{
    let contacts = six_d_contacts::<NF>();
    let runtime = |x: &State<NQ, NV>| {
        constraint::constrained_forward_dynamics::<K, NQ, NV, NF, R>(
            &x.q,
            &x.v,
            &x.tau,
            &contacts,
            None,
            &Settings::default(),
        )
    };
    let differ = |a: &[f64], b: &[f64]| {
        let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        a.iter().zip(b).any(|(a, b)| (a - b).abs() > 1e-10 * scale)
    };
    let errors = states
        .iter()
        .enumerate()
        .filter_map(|(k, x)| match (generated(&x.q, &x.v, &x.tau), runtime(x)) {
            (Err(e), _) => Some(format!("state {k}: {e}")),
            (_, Err(e)) => Some(format!("state {k}: the runtime's: {e}")),
            (Ok((qdd, f)), Ok(s))
                if differ(qdd.as_slice(), s.acceleration.as_slice())
                    || differ(f.as_slice(), s.forces.as_slice()) =>
            {
                Some(format!(
                    "state {k}: the generated and the runtime's solutions differ"
                ))
            }
            _ => None,
        })
        .collect();
    let first = generated(&states[0].q, &states[0].v, &states[0].tau).ok();
    let residual = runtime(&states[0]).ok().map(|s| s.residual);
    ConstrainedValues {
        acceleration: first.as_ref().map(|s| vector(&s.0)),
        forces: first.as_ref().map(|s| {
            (0..NF)
                .map(|k| s.1.as_slice()[6 * k..6 * k + 6].to_vec())
                .collect()
        }),
        residual,
        errors,
    }
}

/// `mass_matrix_and_nonlinear_effects` (`--values`).
#[derive(Serialize)]
struct MassMatrixAndNonlinearEffects {
    /// `M`.
    mass_matrix: Rows,
    /// `h`.
    nonlinear_effects: Vec<f64>,
}

/// What `--values` prints: the outputs at the first state (matrices row by row).
#[derive(Serialize)]
struct Values {
    mass_matrix: Rows,
    nonlinear_effects: Vec<f64>,
    gravity: Vec<f64>,
    inverse_dynamics: Vec<f64>,
    /// `None` (`null`) where `M` is singular.
    forward_dynamics: Option<Vec<f64>>,
    mass_matrix_and_nonlinear_effects: MassMatrixAndNonlinearEffects,
    center_of_mass: Vec<f64>,
    center_of_mass_velocity: Vec<f64>,
    center_of_mass_jacobian: Rows,
    centroidal_momentum: Vec<f64>,
    centroidal_momentum_matrix: Rows,
    kinetic_energy: f64,
    potential_energy: f64,
    coriolis_matrix: Rows,
    /// `M` from [`KeptMassMatrixLower::symmetric`].
    mass_matrix_lower: Rows,
    /// For the models generated with them.
    #[serde(flatten)]
    derivatives: Option<DerivativeValues>,
    /// For the models generated with frames.
    #[serde(flatten)]
    frames: Option<FrameValues>,
    /// For the models given contacts.
    #[serde(skip_serializing_if = "Option::is_none")]
    constrained_forward_dynamics: Option<ConstrainedValues>,
}

/// The outputs of model `M` at the first of `states` (and [`CONSTRAINED`]'s errors on all).
fn values<M: Peer<NQ, NV>, const NQ: usize, const NV: usize>(states: &[State<NQ, NV>]) -> Values {
    let x = &states[0];
    let (m2, nle2) = M::mass_matrix_and_nonlinear_effects(&x.q, &x.v);
    let mut lower = KeptMassMatrixLower::<M, f64, NV>::new();
    M::mass_matrix_lower(&x.q, &mut lower);
    Values {
        mass_matrix: rows(&M::mass_matrix(&x.q)),
        nonlinear_effects: vector(&M::nonlinear_effects(&x.q, &x.v)),
        gravity: vector(&M::gravity(&x.q)),
        inverse_dynamics: vector(&M::inverse_dynamics(&x.q, &x.v, &x.a)),
        forward_dynamics: M::forward_dynamics(&x.q, &x.v, &x.tau)
            .ok()
            .map(|a| vector(&a)),
        mass_matrix_and_nonlinear_effects: MassMatrixAndNonlinearEffects {
            mass_matrix: rows(&m2),
            nonlinear_effects: vector(&nle2),
        },
        center_of_mass: vector(&M::center_of_mass(&x.q)),
        center_of_mass_velocity: vector(&M::center_of_mass_velocity(&x.q, &x.v)),
        center_of_mass_jacobian: rows(&M::center_of_mass_jacobian(&x.q)),
        centroidal_momentum: vector(&M::centroidal_momentum(&x.q, &x.v)),
        centroidal_momentum_matrix: rows(&M::centroidal_momentum_matrix(&x.q)),
        kinetic_energy: M::kinetic_energy(&x.q, &x.v),
        potential_energy: M::potential_energy(&x.q),
        coriolis_matrix: rows(&M::coriolis_matrix(&x.q, &x.v)),
        mass_matrix_lower: rows(&lower.symmetric()),
        derivatives: M::derivative_values(x),
        frames: M::frame_values(x),
        constrained_forward_dynamics: M::constrained_values(states),
    }
}

/// `value` as one line of JSON on stdout.
fn print_json(value: &impl Serialize) -> Result<(), String> {
    let text = serde_json::to_string(value).map_err(|e| e.to_string())?;
    println!("{text}");
    Ok(())
}

/// Runs `cmd` on model `M`.
fn run<M: Peer<NQ, NV>, const NQ: usize, const NV: usize>(cmd: &Command) -> Result<(), String> {
    match cmd {
        Command::Layout => print_json(&layout::<M, NQ, NV>()?)?,
        Command::Values(path) => print_json(&values::<M, NQ, NV>(&read_states(path)?))?,
        Command::Time {
            states,
            batches,
            batch,
        } => {
            let states = read_states::<NQ, NV>(states)?;
            let mut timer = Timer {
                batches: *batches,
                batch: *batch,
                timings: Members(Vec::new()),
            };
            each_output::<M, _, NQ, NV>(&states, &mut timer);
            print_json(&timer.timings)?;
        }
        Command::Calls {
            states,
            calls,
            output,
        } => {
            let states = read_states::<NQ, NV>(states)?;
            let mut only = Only {
                output,
                calls: *calls,
                found: false,
            };
            each_output::<M, _, NQ, NV>(&states, &mut only);
            if !only.found {
                return Err(format!("unknown output `{output}` for this model"));
            }
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let states = || cli.states.clone().unwrap_or_default();
    let cmd = if cli.layout {
        Command::Layout
    } else if cli.values {
        Command::Values(states())
    } else if cli.time {
        Command::Time {
            states: states(),
            batches: cli.batches.max(1),
            batch: Duration::from_secs_f64(cli.batch_ms * 1e-3),
        }
    } else {
        Command::Calls {
            states: states(),
            calls: cli.calls.unwrap_or_default(),
            output: cli.output.clone().unwrap_or_default(),
        }
    };
    match with_model(&cli.model, &cmd) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("peers: {e}");
            ExitCode::FAILURE
        }
    }
}
