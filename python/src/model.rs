//! `articulated.Model`: a model read from a file, evaluated by the interpreted reference.

use std::path::PathBuf;

use articulated::interpreted::coordinates_of;
use articulated::pinocchio::ModelLayout;
use articulated::reference::{Reference, ReferenceFrame};
use articulated::Coordinates;
use articulated_codegen::load::{load_with, LoadOptions};
use articulated_codegen::urdf::FloatingBase;
use numpy::{AllowTypeChange, PyArrayLikeDyn};
use pyo3::prelude::*;

use crate::batch::{rows, run, Arg};
use crate::Error;

/// An array argument: any array-like numpy casts to float64.
pub type In<'py> = PyArrayLikeDyn<'py, f64, AllowTypeChange>;

/// A rigid-body model read from a `.chain`, URDF or MJCF file, evaluated by the interpreted
/// reference dynamics (`articulated::reference`).
///
/// Every method takes one state (`q` of shape `(nq,)`, `v`, `a`, `tau` of shape `(nv,)`) or a
/// batch of them (`(B, nq)`, `(B, nv)`), and returns arrays with the same leading `B`. A batch
/// runs on all cores with the interpreter's lock released; the results do not depend on the
/// number of threads. Conventions: spatial vectors angular first; `bias` without gravity; the
/// quaternion free base `[x, y, z, w, qx, qy, qz]` (`to_pinocchio_q` converts).
#[pyclass(frozen, module = "articulated")]
pub struct Model {
    pub(crate) reference: Reference,
    layout: ModelLayout,
    coordinates: Vec<Coordinates>,
    path: PathBuf,
    warnings: Vec<String>,
    q_names: Vec<String>,
    v_names: Vec<String>,
}

/// `None`, `"euler"` or `"quaternion"`.
pub(crate) fn floating_base(floating: Option<&str>) -> PyResult<FloatingBase> {
    match floating {
        None | Some("none" | "fixed") => Ok(FloatingBase::Fixed),
        Some("euler") => Ok(FloatingBase::Euler),
        Some("quaternion") => Ok(FloatingBase::Quaternion),
        Some(other) => Err(Error::new_err(format!(
            "floating={other:?}: expected None, \"euler\" or \"quaternion\""
        ))),
    }
}

impl Model {
    fn with_reference(&self, reference: Reference) -> Model {
        Model {
            layout: self.layout.clone(),
            coordinates: self.coordinates.clone(),
            path: self.path.clone(),
            warnings: self.warnings.clone(),
            q_names: self.q_names.clone(),
            v_names: self.v_names.clone(),
            reference,
        }
    }

    fn nq_(&self) -> usize {
        self.reference.nq()
    }

    fn nv_(&self) -> usize {
        self.reference.nv()
    }

    /// `q`, `v`, `a` or `tau` read as one state or a batch.
    fn arg(&self, name: &'static str, array: &In<'_>) -> PyResult<Arg> {
        let width = if name == "q" { self.nq_() } else { self.nv_() };
        Arg::read(name, array, width)
    }

    fn frame_check(&self, frame: &str) -> PyResult<()> {
        if self.reference.model().frame(frame).is_some() {
            return Ok(());
        }
        Err(Error::new_err(format!(
            "no frame `{frame}` in model `{}`: a body's or a frame's name (`Model.frames`)",
            self.reference.model().name
        )))
    }
}

/// Copies a vector into `out`.
fn copy(x: &[f64], out: &mut [f64]) {
    out.copy_from_slice(x);
}

#[pymethods]
impl Model {
    /// Reads a `.chain`, `.urdf` or MJCF `.xml` file.
    ///
    /// `floating`: the base under a URDF's root link: `None` (fixed), `"euler"` (translation
    /// and `zyx` angles) or `"quaternion"` (Pinocchio's free flyer, `[x, y, z, w, qx, qy, qz]`
    /// here). `params`: runtime parameter values in declaration order (default: the file's).
    /// `mimic_equalities`: make an MJCF model's joint equalities mimic joints. Raises
    /// `articulated.Error` with the file, line and message of the first problem.
    #[staticmethod]
    #[pyo3(signature = (path, floating=None, params=None, mimic_equalities=false, strict=false))]
    fn load(
        path: PathBuf,
        floating: Option<&str>,
        params: Option<Vec<f64>>,
        mimic_equalities: bool,
        strict: bool,
    ) -> PyResult<Model> {
        let options = LoadOptions {
            floating: floating_base(floating)?,
            mimic_equalities,
            strict,
            ..LoadOptions::default()
        };
        let description = load_with(&path, options).map_err(|e| Error::new_err(e.to_string()))?;
        let model = &description.model;
        let params = params.unwrap_or_else(|| model.param_defaults());
        if params.len() != model.params.len() {
            return Err(Error::new_err(format!(
                "params has {} values, but {} declares {} ({})",
                params.len(),
                path.display(),
                model.params.len(),
                model
                    .params
                    .iter()
                    .map(|p| p.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        let reference = Reference::with_params(model, &params)
            .map_err(|e| Error::new_err(format!("{}: {e}", path.display())))?;
        let (q_names, v_names) = model.coordinate_names();
        Ok(Model {
            layout: ModelLayout::of(model, &description.continuous, &description.pinocchio_order),
            coordinates: coordinates_of(model),
            warnings: description
                .warnings
                .iter()
                .map(|w| w.display_in(&path))
                .collect(),
            path,
            q_names,
            v_names,
            reference,
        })
    }

    /// The same model with other runtime parameter values (declaration order).
    fn with_params(&self, params: Vec<f64>) -> PyResult<Model> {
        let model = self.reference.model();
        if params.len() != model.params.len() {
            return Err(Error::new_err(format!(
                "params has {} values, but the model declares {}",
                params.len(),
                model.params.len()
            )));
        }
        let reference =
            Reference::with_params(model, &params).map_err(|e| Error::new_err(e.to_string()))?;
        Ok(self.with_reference(reference))
    }

    /// The model's name in its description.
    #[getter]
    fn name(&self) -> String {
        self.reference.model().name.clone()
    }

    /// The file it was read from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// The number of position coordinates.
    #[getter]
    fn nq(&self) -> usize {
        self.nq_()
    }

    /// The number of velocities (and of entries of `tau`).
    #[getter]
    fn nv(&self) -> usize {
        self.nv_()
    }

    /// The name of each entry of `q` (`elbow`, `base.qw`, `hip.rz`).
    #[getter]
    fn q_names(&self) -> Vec<String> {
        self.q_names.clone()
    }

    /// The name of each entry of `v` and `tau`.
    #[getter]
    fn v_names(&self) -> Vec<String> {
        self.v_names.clone()
    }

    /// The names the frame methods take: every body and every declared frame.
    #[getter]
    fn frames(&self) -> Vec<String> {
        let model = self.reference.model();
        model
            .bodies
            .iter()
            .map(|b| b.name.clone())
            .chain(model.frames.iter().map(|f| f.name.clone()))
            .collect()
    }

    /// The runtime parameters' names, in declaration order.
    #[getter]
    fn param_names(&self) -> Vec<String> {
        let model = self.reference.model();
        model.params.iter().map(|p| p.name.clone()).collect()
    }

    /// The parameter values this model evaluates with.
    #[getter]
    fn params(&self) -> Vec<f64> {
        self.reference.params().to_vec()
    }

    /// What the file loaded with but deserves a look, as `file:line: warning: message`.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The neutral configuration: zero angles and positions, identity quaternions.
    fn neutral<'py>(&self, py: Python<'py>) -> PyResult<Py<PyAny>> {
        let q = self.reference.model().neutral();
        run(py, &[], &[&[q.len()]], |_, out| {
            copy(&q, out);
            Ok(())
        })
    }

    /// `M(q)`, `(nv, nv)`: the joint-space inertia matrix (Pinocchio's `crba`, symmetrized).
    fn mass_matrix(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let n = self.nv_();
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[n, n]], |x, out| {
            rows(&r.mass_matrix(x[0]).map_err(|e| e.to_string())?, out);
            Ok(())
        })
    }

    /// `M(q)⁻¹`, `(nv, nv)`; an error where `M` is singular.
    fn mass_matrix_inverse(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let n = self.nv_();
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[n, n]], |x, out| {
            rows(
                &r.mass_matrix_inverse(x[0]).map_err(|e| e.to_string())?,
                out,
            );
            Ok(())
        })
    }

    /// `N(q, v)·v`, `(nv,)`: the velocity-product terms, without gravity.
    fn bias(&self, py: Python<'_>, q: In<'_>, v: In<'_>) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        run(py, &args, &[&[self.nv_()]], |x, out| {
            copy(
                r.bias(x[0], x[1]).map_err(|e| e.to_string())?.as_slice(),
                out,
            );
            Ok(())
        })
    }

    /// `g(q)`, `(nv,)`: the generalized force that holds the chain still.
    fn gravity(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[self.nv_()]], |x, out| {
            copy(r.gravity(x[0]).map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// `N(q, v)·v + g(q)`, `(nv,)` (Pinocchio's `nonLinearEffects`).
    fn nonlinear_effects(&self, py: Python<'_>, q: In<'_>, v: In<'_>) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        let zero = vec![0.0; self.nv_()];
        run(py, &args, &[&[self.nv_()]], |x, out| {
            let tau = r.inverse_dynamics(x[0], x[1], &zero);
            copy(tau.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// `τ = M·a + N·v + g`, `(nv,)` (Pinocchio's `rnea`).
    fn inverse_dynamics(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        a: In<'_>,
    ) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?, self.arg("a", &a)?];
        let r = &self.reference;
        run(py, &args, &[&[self.nv_()]], |x, out| {
            let tau = r.inverse_dynamics(x[0], x[1], x[2]);
            copy(tau.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// The accelerations `a` for the generalized forces `tau`, `(nv,)` (Pinocchio's `aba`); an
    /// error naming the joint where `M` is singular or a value is not finite.
    fn forward_dynamics(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        tau: In<'_>,
    ) -> PyResult<Py<PyAny>> {
        let args = [
            self.arg("q", &q)?,
            self.arg("v", &v)?,
            self.arg("tau", &tau)?,
        ];
        let r = &self.reference;
        run(py, &args, &[&[self.nv_()]], |x, out| {
            let a = r.forward_dynamics(x[0], x[1], x[2]);
            copy(a.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// `(∂τ/∂q, ∂τ/∂v)`, `(nv, nv)` each, `∂/∂q` along the configuration's tangent (Pinocchio's
    /// `computeRNEADerivatives`).
    fn inverse_dynamics_derivatives(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        a: In<'_>,
    ) -> PyResult<Py<PyAny>> {
        let n = self.nv_();
        let args = [self.arg("q", &q)?, self.arg("v", &v)?, self.arg("a", &a)?];
        let r = &self.reference;
        run(py, &args, &[&[n, n], &[n, n]], |x, out| {
            let (dq, dv) = r
                .inverse_dynamics_derivatives(x[0], x[1], x[2])
                .map_err(|e| e.to_string())?;
            let (first, second) = out.split_at_mut(n * n);
            rows(&dq, first);
            rows(&dv, second);
            Ok(())
        })
    }

    /// `(∂a/∂q, ∂a/∂v, M⁻¹)`, `(nv, nv)` each (Pinocchio's `computeABADerivatives`).
    fn forward_dynamics_derivatives(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        tau: In<'_>,
    ) -> PyResult<Py<PyAny>> {
        let n = self.nv_();
        let args = [
            self.arg("q", &q)?,
            self.arg("v", &v)?,
            self.arg("tau", &tau)?,
        ];
        let r = &self.reference;
        run(py, &args, &[&[n, n], &[n, n], &[n, n]], |x, out| {
            let d = r
                .forward_dynamics_derivatives(x[0], x[1], x[2])
                .map_err(|e| e.to_string())?;
            for (m, o) in d.iter().zip(out.chunks_mut(n * n)) {
                rows(m, o);
            }
            Ok(())
        })
    }

    /// `½·vᵀ·M·v`.
    fn kinetic_energy(&self, py: Python<'_>, q: In<'_>, v: In<'_>) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        run(py, &args, &[&[]], |x, out| {
            out[0] = r.kinetic_energy(x[0], x[1]).map_err(|e| e.to_string())?;
            Ok(())
        })
    }

    /// `−Σ m_k·gᵀ·x_k`.
    fn potential_energy(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[]], |x, out| {
            out[0] = r.potential_energy(x[0]).map_err(|e| e.to_string())?;
            Ok(())
        })
    }

    /// The centre of mass in the world, `(3,)`.
    fn center_of_mass(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[3]], |x, out| {
            copy(
                r.center_of_mass(x[0])
                    .map_err(|e| e.to_string())?
                    .as_slice(),
                out,
            );
            Ok(())
        })
    }

    /// The centre of mass's velocity in the world, `(3,)`.
    fn center_of_mass_velocity(&self, py: Python<'_>, q: In<'_>, v: In<'_>) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        run(py, &args, &[&[3]], |x, out| {
            let c = r.center_of_mass_velocity(x[0], x[1]);
            copy(c.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// The centre of mass's Jacobian, `(3, nv)` (Pinocchio's `jacobianCenterOfMass`).
    fn center_of_mass_jacobian(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[3, self.nv_()]], |x, out| {
            rows(
                &r.center_of_mass_jacobian(x[0]).map_err(|e| e.to_string())?,
                out,
            );
            Ok(())
        })
    }

    /// The centroidal momentum `[k_G; p]`, `(6,)`, world axes, about the centre of mass (angular
    /// first; Pinocchio's `computeCentroidalMomentum` is linear first).
    fn centroidal_momentum(&self, py: Python<'_>, q: In<'_>, v: In<'_>) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        run(py, &args, &[&[6]], |x, out| {
            let h = r.centroidal_momentum(x[0], x[1]);
            copy(h.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// The centroidal momentum matrix `A_G`, `(6, nv)`, rows as `centroidal_momentum`.
    fn centroidal_momentum_matrix(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[6, self.nv_()]], |x, out| {
            rows(
                &r.centroidal_momentum_matrix(x[0])
                    .map_err(|e| e.to_string())?,
                out,
            );
            Ok(())
        })
    }

    /// The rate of the centroidal momentum `ḣ_G = A_G·a + Ȧ_G·v`, `(6,)`, laid out as
    /// `centroidal_momentum`.
    fn centroidal_momentum_rate(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        a: In<'_>,
    ) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?, self.arg("a", &a)?];
        let r = &self.reference;
        run(py, &args, &[&[6]], |x, out| {
            let h = r.centroidal_momentum_rate(x[0], x[1], x[2]);
            copy(h.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// `Ȧ_G·v`, `(6,)`: the centroidal momentum's rate at `a = 0`.
    fn centroidal_momentum_drift(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
    ) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        run(py, &args, &[&[6]], |x, out| {
            let h = r.centroidal_momentum_drift(x[0], x[1]);
            copy(h.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// The wrench each joint transmits, `(joints, 6)`, in joint order (fixed joints
    /// included): `[couple; force]` that the parent exerts on the child, in the child frame
    /// about its origin, gravity included (Hemami's couples and reaction forces).
    fn joint_wrenches(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        a: In<'_>,
    ) -> PyResult<Py<PyAny>> {
        let args = [self.arg("q", &q)?, self.arg("v", &v)?, self.arg("a", &a)?];
        let r = &self.reference;
        let joints = r.model().joints.len();
        run(py, &args, &[&[joints, 6]], |x, out| {
            let w = r
                .joint_wrenches(x[0], x[1], x[2])
                .map_err(|e| e.to_string())?;
            for (w, o) in w.iter().zip(out.chunks_mut(6)) {
                o[..3].copy_from_slice(&w.couple);
                o[3..].copy_from_slice(&w.force);
            }
            Ok(())
        })
    }

    /// The name of each joint, in the order of `joint_wrenches`' rows.
    #[getter]
    fn joints(&self) -> Vec<String> {
        self.reference
            .model()
            .joints
            .iter()
            .map(|j| j.name.clone())
            .collect()
    }

    /// The Coriolis matrix `N(q, v)`, `(nv, nv)`, with `N·v = bias` and `Ṁ − 2N` skew.
    fn coriolis_matrix(&self, py: Python<'_>, q: In<'_>, v: In<'_>) -> PyResult<Py<PyAny>> {
        let n = self.nv_();
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        run(py, &args, &[&[n, n]], |x, out| {
            rows(
                &r.coriolis_matrix(x[0], x[1]).map_err(|e| e.to_string())?,
                out,
            );
            Ok(())
        })
    }

    /// A frame's placement in the world: `(R, p)`, `R` `(3, 3)` with the frame's axes as
    /// columns, `p` `(3,)` its origin.
    fn frame_placement(&self, py: Python<'_>, q: In<'_>, frame: &str) -> PyResult<Py<PyAny>> {
        self.frame_check(frame)?;
        let r = &self.reference;
        run(py, &[self.arg("q", &q)?], &[&[3, 3], &[3]], |x, out| {
            let (rot, p) = r.frame_placement(x[0], frame).map_err(|e| e.to_string())?;
            rows(
                &nalgebra::DMatrix::from_column_slice(3, 3, rot.as_slice()),
                &mut out[..9],
            );
            copy(p.as_slice(), &mut out[9..]);
            Ok(())
        })
    }

    /// A frame's spatial velocity `[ω; v]`, `(6,)`, in the frame (LOCAL).
    fn frame_velocity(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        frame: &str,
    ) -> PyResult<Py<PyAny>> {
        self.frame_check(frame)?;
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        run(py, &args, &[&[6]], |x, out| {
            let w = r.frame_velocity(x[0], x[1], frame);
            copy(w.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

    /// A frame's classical acceleration `[ω̇; p̈]`, `(6,)`, world axes at the frame's origin
    /// (LOCAL_WORLD_ALIGNED).
    fn frame_acceleration(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        a: In<'_>,
        frame: &str,
    ) -> PyResult<Py<PyAny>> {
        self.frame_check(frame)?;
        let args = [self.arg("q", &q)?, self.arg("v", &v)?, self.arg("a", &a)?];
        let r = &self.reference;
        run(py, &args, &[&[6]], |x, out| {
            let w = r.frame_acceleration(x[0], x[1], x[2], frame);
            copy(w.map_err(|e| e.to_string())?.as_slice(), out);
            Ok(())
        })
    }

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
        run(py, &[self.arg("q", &q)?], &[&[6, self.nv_()]], |x, out| {
            rows(
                &r.frame_jacobian(x[0], frame, rf)
                    .map_err(|e| e.to_string())?,
                out,
            );
            Ok(())
        })
    }

    /// A frame's Jacobian's time variation `J̇`, `(6, nv)`, in `reference` as `frame_jacobian`.
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
        run(py, &args, &[&[6, self.nv_()]], |x, out| {
            let j = r.frame_jacobian_time_variation(x[0], x[1], frame, rf);
            rows(&j.map_err(|e| e.to_string())?, out);
            Ok(())
        })
    }

    /// Pinocchio's `nq` for this model: one more per URDF `continuous` joint.
    #[getter]
    fn nq_pinocchio(&self) -> PyResult<usize> {
        Ok(self.pin()?.nq_pinocchio())
    }

    /// Pinocchio's names of its `q` entries, in its order (`base.qx, …, base.qw`,
    /// `wheel.cos`, `wheel.sin`).
    #[getter]
    fn q_names_pinocchio(&self) -> Vec<String> {
        self.layout.names(&self.q_names, &self.v_names).0
    }

    /// Our `q` in Pinocchio's layout: its free flyer `[x, y, z, qx, qy, qz, qw]`, spherical
    /// joints `[x, y, z, w]`, continuous joints `(cos θ, sin θ)`, its URDF joint order.
    fn to_pinocchio_q(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let layout = self.pin()?;
        run(
            py,
            &[self.arg("q", &q)?],
            &[&[layout.nq_pinocchio()]],
            |x, out| layout.q_to_pinocchio(x[0], out).map_err(|e| e.to_string()),
        )
    }

    /// Pinocchio's `q` in ours (the inverse of `to_pinocchio_q`).
    // The name the issue gives (`to_pinocchio`/`from_pinocchio`), a model's method in Python.
    #[allow(clippy::wrong_self_convention)]
    fn from_pinocchio_q(&self, py: Python<'_>, q: In<'_>) -> PyResult<Py<PyAny>> {
        let layout = self.pin()?;
        let arg = Arg::read("q", &q, layout.nq_pinocchio())?;
        run(py, &[arg], &[&[self.nq_()]], |x, out| {
            layout
                .q_from_pinocchio(x[0], out)
                .map_err(|e| e.to_string())
        })
    }

    /// Our `v` (or `a`, `tau`) in Pinocchio's joint order: the same values joint by joint.
    fn to_pinocchio_v(&self, py: Python<'_>, v: In<'_>) -> PyResult<Py<PyAny>> {
        let layout = self.pin()?;
        run(py, &[self.arg("v", &v)?], &[&[self.nv_()]], |x, out| {
            layout.v_to_pinocchio(x[0], out).map_err(|e| e.to_string())
        })
    }

    /// Pinocchio's `v` (or `a`, `tau`) in our joint order.
    // The name the issue gives (`to_pinocchio`/`from_pinocchio`), a model's method in Python.
    #[allow(clippy::wrong_self_convention)]
    fn from_pinocchio_v(&self, py: Python<'_>, v: In<'_>) -> PyResult<Py<PyAny>> {
        let layout = self.pin()?;
        run(py, &[self.arg("v", &v)?], &[&[self.nv_()]], |x, out| {
            layout
                .v_from_pinocchio(x[0], out)
                .map_err(|e| e.to_string())
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "articulated.Model({:?}, nq={}, nv={}, path={:?})",
            self.reference.model().name,
            self.nq_(),
            self.nv_(),
            self.path.display().to_string()
        )
    }
}

impl Model {
    fn pin(&self) -> PyResult<articulated::pinocchio::Layout<'_>> {
        self.layout
            .layout()
            .map_err(|e| Error::new_err(format!("Pinocchio's layout of this model: {e}")))
    }

    /// The joints' coordinates, in joint order.
    pub(crate) fn coordinates(&self) -> &[Coordinates] {
        &self.coordinates
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
