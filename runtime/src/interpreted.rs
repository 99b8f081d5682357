//! A chain known only at run time (read from a `.chain` or URDF file, as the CLI does), stepped
//! by the same integrators as generated code: the interpreted [`Reference`] dynamics under a
//! controller, as an [`integrate::SecondOrder`](crate::integrate::SecondOrder) system on
//! run-time sizes. It allocates; for a chain known at compile time,
//! [`integrate::ControlledChain`](crate::integrate::ControlledChain) over generated code is the
//! fast, allocation-free path.

use alloc::vec::Vec;

use nalgebra::{DVector, Dyn};

use crate::integrate::{Cause, Quantity, SecondOrder};
use crate::model::{JointKind, Model};
use crate::reference::{Error, Reference, Singularity};
use crate::{Coordinates, SingularMassMatrix};

/// How each joint of `model` with coordinates sits in `q` and `v`, in joint order: what a
/// generated chain's [`Chain::COORDINATES`](crate::Chain::COORDINATES) says for the same
/// description.
pub fn coordinates_of(model: &Model) -> Vec<Coordinates> {
    model
        .joints
        .iter()
        // Mimic joints have no coordinates of their own.
        .filter(|j| j.mimic.is_none())
        .filter_map(|j| match j.kind {
            JointKind::Fixed => None,
            JointKind::SphericalQuaternion => Some(Coordinates::Quaternion),
            JointKind::FreeQuaternion => Some(Coordinates::FreeQuaternion),
            other => Some(Coordinates::Vector(other.nq())),
        })
        .collect()
}

/// The reference dynamics of a model under `controller(t, q, v) → τ`.
pub struct Interpreted<F> {
    reference: Reference,
    coordinates: Vec<Coordinates>,
    controller: F,
}

/// A controller that applies no force.
pub type Unforced = fn(f64, &DVector<f64>, &DVector<f64>) -> DVector<f64>;

impl Interpreted<Unforced> {
    /// The chain left to itself (`τ = 0`).
    pub fn unforced(reference: Reference) -> Self {
        Self::new(reference, |_, _, v| DVector::zeros(v.len()))
    }
}

impl<F> Interpreted<F>
where
    F: FnMut(f64, &DVector<f64>, &DVector<f64>) -> DVector<f64>,
{
    /// The chain of `reference` under `controller`.
    pub fn new(reference: Reference, controller: F) -> Self {
        let coordinates = coordinates_of(reference.model());
        Interpreted {
            reference,
            coordinates,
            controller,
        }
    }

    /// The reference dynamics it steps.
    pub fn reference(&self) -> &Reference {
        &self.reference
    }
}

impl<F> SecondOrder<f64, Dyn, Dyn> for Interpreted<F>
where
    F: FnMut(f64, &DVector<f64>, &DVector<f64>) -> DVector<f64>,
{
    fn coordinates(&self) -> &[Coordinates] {
        &self.coordinates
    }

    fn acceleration(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
    ) -> Result<DVector<f64>, Cause<f64>> {
        let tau = (self.controller)(t, q, v);
        if let Some(index) = tau.iter().position(|x| !x.is_finite()) {
            return Err(Cause::NonFinite {
                quantity: Quantity::Control,
                index,
            });
        }
        self.reference
            .forward_dynamics(q.as_slice(), v.as_slice(), tau.as_slice())
            .map_err(cause)
    }

    fn finite_acceleration(&self) -> bool {
        // The reference reports a non-finite result as an error.
        true
    }
}

/// The integrators' [`Cause`] of a reference error.
fn cause(e: Error) -> Cause<f64> {
    let velocity = |s: &Singularity| match s {
        Singularity::Pivot { velocity, .. }
        | Singularity::NonFiniteAcceleration { velocity, .. } => *velocity,
        Singularity::Eigenvalues { .. } => 0,
    };
    match e {
        // `M` passed its checks but `q̈` overflowed (a state that has diverged): not singular.
        Error::Singular(Singularity::NonFiniteAcceleration { velocity, .. }) => Cause::NonFinite {
            quantity: Quantity::Acceleration,
            index: velocity,
        },
        Error::Singular(s) => Cause::SingularMassMatrix(SingularMassMatrix {
            velocity: velocity(&s),
        }),
        Error::NonFinite { vector, index } => Cause::NonFinite {
            quantity: match vector {
                "q" => Quantity::Position,
                "v" => Quantity::Velocity,
                _ => Quantity::Control,
            },
            index,
        },
        Error::Quaternion { .. } => Cause::System("a quaternion in q is zero"),
        Error::NotUnitQuaternion { index, norm, .. } => Cause::NotUnitQuaternion { index, norm },
        Error::NonFiniteResult { .. } => Cause::NonFinite {
            quantity: Quantity::Acceleration,
            index: 0,
        },
        _ => Cause::System("the reference dynamics refused the state"),
    }
}
