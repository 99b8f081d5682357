//! `articulated.Model`: a model read from a file, evaluated by the interpreted reference.

use std::path::PathBuf;

use articulated::interpreted::coordinates_of;
use articulated::pinocchio::ModelLayout;
use articulated::reference::Reference;
use articulated::Coordinates;
use articulated_codegen::load::{load_with, LoadOptions};
use articulated_codegen::urdf::FloatingBase;
use numpy::{AllowTypeChange, PyArrayLikeDyn};
use pyo3::prelude::*;

use crate::batch::{run, Arg};
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
    pub(crate) fn arg(&self, name: &'static str, array: &In<'_>) -> PyResult<Arg> {
        let width = if name == "q" { self.nq_() } else { self.nv_() };
        Arg::read(name, array, width)
    }

    pub(crate) fn frame_check(&self, frame: &str) -> PyResult<()> {
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
