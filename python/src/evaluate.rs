//! What `articulated.Model` evaluates: each output of the interpreted reference as a method
//! over one state or a batch, declared once in [`outputs!`] by its arguments, shape and call.

use articulated::reference::{Error as ReferenceError, Reference, ReferenceFrame, Wrench};
use nalgebra::{DMatrix, DVector, Matrix3, SVector, Vector3};
use pyo3::prelude::*;

use crate::batch::{rows, run};
use crate::model::{In, Model};
use crate::Error;

/// A value of the reference written into one state's output, row-major, part after part.
trait Out {
    fn put(&self, out: &mut [f64]);
}

impl Out for f64 {
    fn put(&self, out: &mut [f64]) {
        out[0] = *self;
    }
}

impl Out for DVector<f64> {
    fn put(&self, out: &mut [f64]) {
        out.copy_from_slice(self.as_slice());
    }
}

impl<const N: usize> Out for SVector<f64, N> {
    fn put(&self, out: &mut [f64]) {
        out.copy_from_slice(self.as_slice());
    }
}

impl Out for DMatrix<f64> {
    fn put(&self, out: &mut [f64]) {
        rows(self, out);
    }
}

impl Out for (DMatrix<f64>, DMatrix<f64>) {
    fn put(&self, out: &mut [f64]) {
        let (first, second) = out.split_at_mut(self.0.len());
        self.0.put(first);
        self.1.put(second);
    }
}

impl Out for [DMatrix<f64>; 3] {
    fn put(&self, out: &mut [f64]) {
        for (m, o) in self.iter().zip(out.chunks_mut(self[0].len())) {
            m.put(o);
        }
    }
}

/// A frame's placement: `R` (its axes as columns), then `p`.
impl Out for (Matrix3<f64>, Vector3<f64>) {
    fn put(&self, out: &mut [f64]) {
        let (r, p) = out.split_at_mut(9);
        for (k, x) in r.iter_mut().enumerate() {
            *x = self.0[(k / 3, k % 3)];
        }
        p.copy_from_slice(self.1.as_slice());
    }
}

/// Each joint's `[couple; force]`.
impl Out for Vec<Wrench> {
    fn put(&self, out: &mut [f64]) {
        for (w, o) in self.iter().zip(out.chunks_mut(6)) {
            o[..3].copy_from_slice(&w.couple);
            o[3..].copy_from_slice(&w.force);
        }
    }
}

/// The sizes an output's shape is written in.
struct Sizes {
    nv: usize,
    joints: usize,
}

/// A size of a shape: `nv`, `joints` or a number.
macro_rules! dim {
    ($s:ident, nv) => {
        $s.nv
    };
    ($s:ident, joints) => {
        $s.joints
    };
    ($s:ident, $n:literal) => {
        $n
    };
}

/// One method per output: its docs, `name(arguments[; frame])`, the shape of each part for one
/// state, and the reference's call on the state's arguments `x` (and the frame's name).
macro_rules! outputs {
    ($(
        $(#[doc = $doc:literal])*
        fn $name:ident($($arg:ident),* $(; $frame:ident)?) -> [$([$($dim:tt),*]),+]
            = |$r:ident, $x:ident $(, $f:ident)?| $call:expr;
    )*) => {$(
        #[pymethods]
        impl Model {
            $(#[doc = $doc])*
            fn $name(
                &self,
                py: Python<'_>,
                $($arg: In<'_>,)*
                $($frame: &str,)?
            ) -> PyResult<Py<PyAny>> {
                $(self.frame_check($frame)?; let $f = $frame;)?
                let args = [$(self.arg(stringify!($arg), &$arg)?),*];
                // Unread where the shape is all numbers.
                let _sizes = Sizes { nv: self.reference.nv(), joints: self.reference.model().joints.len() };
                let $r: &Reference = &self.reference;
                run(py, &args, &[$(&[$(dim!(_sizes, $dim)),*]),+], |$x, out| {
                    let value: Result<_, ReferenceError> = $call;
                    value.map_err(|e| e.to_string())?.put(out);
                    Ok(())
                })
            }
        }
    )*};
}

outputs! {
    /// `M(q)`, `(nv, nv)`: the joint-space inertia matrix (Pinocchio's `crba`).
    fn mass_matrix(q) -> [[nv, nv]] = |r, x| r.mass_matrix(x[0]);
    /// `M(q)⁻¹`, `(nv, nv)`; an error where `M` is singular.
    fn mass_matrix_inverse(q) -> [[nv, nv]] = |r, x| r.mass_matrix_inverse(x[0]);
    /// `N(q, v)·v`, `(nv,)`: the velocity-product terms, without gravity.
    fn bias(q, v) -> [[nv]] = |r, x| r.bias(x[0], x[1]);
    /// `g(q)`, `(nv,)`: the generalized force that holds the chain still.
    fn gravity(q) -> [[nv]] = |r, x| r.gravity(x[0]);
    /// `N(q, v)·v + g(q)`, `(nv,)` (Pinocchio's `nonLinearEffects`).
    fn nonlinear_effects(q, v) -> [[nv]] =
        |r, x| r.inverse_dynamics(x[0], x[1], &vec![0.0; x[1].len()]);
    /// `τ = M·a + N·v + g`, `(nv,)` (Pinocchio's `rnea`).
    fn inverse_dynamics(q, v, a) -> [[nv]] = |r, x| r.inverse_dynamics(x[0], x[1], x[2]);
    /// The accelerations `a` for the generalized forces `tau`, `(nv,)` (Pinocchio's `aba`);
    /// an error naming the joint where `M` is singular or a value is not finite.
    fn forward_dynamics(q, v, tau) -> [[nv]] = |r, x| r.forward_dynamics(x[0], x[1], x[2]);
    /// `(∂τ/∂q, ∂τ/∂v)`, `(nv, nv)` each, `∂/∂q` along the configuration's tangent
    /// (Pinocchio's `computeRNEADerivatives`).
    fn inverse_dynamics_derivatives(q, v, a) -> [[nv, nv], [nv, nv]] =
        |r, x| r.inverse_dynamics_derivatives(x[0], x[1], x[2]);
    /// `(∂a/∂q, ∂a/∂v, M⁻¹)`, `(nv, nv)` each (Pinocchio's `computeABADerivatives`).
    fn forward_dynamics_derivatives(q, v, tau) -> [[nv, nv], [nv, nv], [nv, nv]] =
        |r, x| r.forward_dynamics_derivatives(x[0], x[1], x[2]);
    /// `½·vᵀ·M·v`.
    fn kinetic_energy(q, v) -> [[]] = |r, x| r.kinetic_energy(x[0], x[1]);
    /// `−Σ m_k·gᵀ·x_k`.
    fn potential_energy(q) -> [[]] = |r, x| r.potential_energy(x[0]);
    /// The centre of mass in the world, `(3,)`.
    fn center_of_mass(q) -> [[3]] = |r, x| r.center_of_mass(x[0]);
    /// The centre of mass's velocity in the world, `(3,)`.
    fn center_of_mass_velocity(q, v) -> [[3]] = |r, x| r.center_of_mass_velocity(x[0], x[1]);
    /// The centre of mass's Jacobian, `(3, nv)` (Pinocchio's `jacobianCenterOfMass`).
    fn center_of_mass_jacobian(q) -> [[3, nv]] = |r, x| r.center_of_mass_jacobian(x[0]);
    /// The centroidal momentum `[k_G; p]`, `(6,)`, world axes, about the centre of mass
    /// (angular first; Pinocchio's `computeCentroidalMomentum` is linear first).
    fn centroidal_momentum(q, v) -> [[6]] = |r, x| r.centroidal_momentum(x[0], x[1]);
    /// The centroidal momentum matrix `A_G`, `(6, nv)`, rows as `centroidal_momentum`.
    fn centroidal_momentum_matrix(q) -> [[6, nv]] = |r, x| r.centroidal_momentum_matrix(x[0]);
    /// The rate of the centroidal momentum `ḣ_G = A_G·a + Ȧ_G·v`, `(6,)`, laid out as
    /// `centroidal_momentum`.
    fn centroidal_momentum_rate(q, v, a) -> [[6]] =
        |r, x| r.centroidal_momentum_rate(x[0], x[1], x[2]);
    /// `Ȧ_G·v`, `(6,)`: the centroidal momentum's rate at `a = 0`.
    fn centroidal_momentum_drift(q, v) -> [[6]] = |r, x| r.centroidal_momentum_drift(x[0], x[1]);
    /// The wrench each joint transmits, `(joints, 6)`, in joint order (fixed joints included,
    /// `Model.joints` names them): `[couple; force]` that the parent exerts on the child, in
    /// the child frame about its origin, gravity included (Hemami's couples and reaction
    /// forces).
    fn joint_wrenches(q, v, a) -> [[joints, 6]] = |r, x| r.joint_wrenches(x[0], x[1], x[2]);
    /// The Coriolis matrix `N(q, v)`, `(nv, nv)`, with `N·v = bias` and `Ṁ − 2N` skew.
    fn coriolis_matrix(q, v) -> [[nv, nv]] = |r, x| r.coriolis_matrix(x[0], x[1]);
    /// A frame's placement in the world: `(R, p)`, `R` `(3, 3)` with the frame's axes as
    /// columns, `p` `(3,)` its origin.
    fn frame_placement(q; frame) -> [[3, 3], [3]] = |r, x, f| r.frame_placement(x[0], f);
    /// A frame's spatial velocity `[ω; v]`, `(6,)`, in the frame (LOCAL).
    fn frame_velocity(q, v; frame) -> [[6]] = |r, x, f| r.frame_velocity(x[0], x[1], f);
    /// A frame's classical acceleration `[ω̇; p̈]`, `(6,)`, world axes at the frame's origin
    /// (LOCAL_WORLD_ALIGNED).
    fn frame_acceleration(q, v, a; frame) -> [[6]] =
        |r, x, f| r.frame_acceleration(x[0], x[1], x[2], f);
}

#[pymethods]
impl Model {
    /// A frame's Jacobian, `(6, nv)`, angular rows first, in `reference`: `"local"`,
    /// `"world"` or `"local_world_aligned"` (Pinocchio's `getFrameJacobian` with `LOCAL`,
    /// `WORLD`, `LOCAL_WORLD_ALIGNED`, its rows swapped).
    #[pyo3(signature = (q, frame, reference="local"))]
    fn frame_jacobian(
        &self,
        py: Python<'_>,
        q: In<'_>,
        frame: &str,
        reference: &str,
    ) -> PyResult<Py<PyAny>> {
        self.frame_check(frame)?;
        let rf = reference_frame(reference)?;
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[6, r.nv()]], |x, out| {
            rows(
                &r.frame_jacobian(x[0], frame, rf)
                    .map_err(|e| e.to_string())?,
                out,
            );
            Ok(())
        })
    }

    /// A frame's Jacobian's time variation `J̇`, `(6, nv)`, in `reference` as
    /// `frame_jacobian`.
    #[pyo3(signature = (q, v, frame, reference="local"))]
    fn frame_jacobian_time_variation(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        frame: &str,
        reference: &str,
    ) -> PyResult<Py<PyAny>> {
        self.frame_check(frame)?;
        let rf = reference_frame(reference)?;
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        run(py, &args, &[&[6, r.nv()]], |x, out| {
            let j = r.frame_jacobian_time_variation(x[0], x[1], frame, rf);
            rows(&j.map_err(|e| e.to_string())?, out);
            Ok(())
        })
    }
}

/// `"local"`, `"world"` or `"local_world_aligned"`.
fn reference_frame(name: &str) -> PyResult<ReferenceFrame> {
    ReferenceFrame::ALL
        .into_iter()
        .find(|r| r.name() == name)
        .ok_or_else(|| {
            Error::new_err(format!(
                "reference={name:?}: expected \"local\", \"world\" or \"local_world_aligned\""
            ))
        })
}
