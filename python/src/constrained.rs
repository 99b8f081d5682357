//! `Model.constrained_forward_dynamics` and `Model.impulse_dynamics`: contacts and loops on the
//! model's frames chosen at call time, solved by the runtime's constraint core at run-time
//! sizes (`articulated::constraint::dynamic`) on the interpreted reference's kinematics.

use articulated::constraint::dynamic::{self, FrameKinematics, System};
use articulated::constraint::{Baumgarte, Kind, Settings};
use articulated::reference::Reference;
use nalgebra::DVector;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::batch::run;
use crate::model::{In, Model};
use crate::Error;

/// `contacts`: `{frame: "six_d" | "point"}` or a sequence of `(frame, kind)` pairs, in order.
fn contacts_of(model: &Model, contacts: &Bound<'_, PyAny>) -> PyResult<Vec<(String, Kind)>> {
    let pairs: Vec<(String, String)> = match contacts.cast::<PyDict>() {
        Ok(dict) => dict.items().extract()?,
        Err(_) => contacts.extract().map_err(|_| {
            Error::new_err(
                "contacts: expected {frame: \"six_d\" | \"point\"} or a list of (frame, kind) pairs",
            )
        })?,
    };
    if pairs.is_empty() {
        return Err(Error::new_err("contacts: name at least one frame"));
    }
    pairs
        .into_iter()
        .map(|(frame, kind)| {
            model.frame_check(&frame)?;
            let kind = match kind.as_str() {
                "six_d" => Kind::SixD,
                "point" => Kind::Point,
                other => {
                    return Err(Error::new_err(format!(
                        "contacts: `{frame}`: kind {other:?}, expected \"six_d\" or \"point\""
                    )))
                }
            };
            Ok((frame, kind))
        })
        .collect()
}

/// The stacked rows of `contacts` at `(q, v)`, and `M`.
fn system(
    r: &Reference,
    contacts: &[(String, Kind)],
    q: &[f64],
    v: &[f64],
) -> Result<(nalgebra::DMatrix<f64>, System), String> {
    let m = r.mass_matrix(q).map_err(|e| e.to_string())?;
    let mut system = System::new(r.nv());
    for (frame, kind) in contacts {
        let k = FrameKinematics::by_reference(r, q, v, frame)
            .map_err(|e| format!("frame `{frame}`: {e}"))?;
        system.push(*kind, &k, None).map_err(|e| e.to_string())?;
    }
    Ok((m, system))
}

/// The settings of `mu` (0: exact, refusing redundant constraints; > 0: proximal iterations to
/// the least-norm forces).
fn settings(mu: f64) -> PyResult<Settings> {
    if !(mu.is_finite() && mu >= 0.0) {
        return Err(Error::new_err(format!(
            "mu={mu}: expected a finite number ≥ 0"
        )));
    }
    Ok(Settings {
        mu,
        ..Settings::default()
    })
}

#[pymethods]
impl Model {
    /// The accelerations and contact forces under `contacts` (`{frame: "six_d" | "point"}`, in
    /// order): `M·a + nle = τ + Σ Jᵀ·f` with `J·a + γ = −K_D·J·v` (`baumgarte=(K_P, K_D)`; the
    /// position term needs a reference the call does not keep). A point contact's force is in
    /// world axes (3 rows), a six-dimensional contact's wrench `[n; f]` in its frame (6 rows).
    /// `mu > 0` solves redundant contacts by proximal iterations (the least-norm forces);
    /// `mu = 0` (default) refuses them with an error that names them.
    /// Returns `(a (nv,), forces (rows,), residual)`, `residual = max |J·a + γ|`.
    #[pyo3(signature = (q, v, tau, contacts, baumgarte=None, mu=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn constrained_forward_dynamics(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        tau: In<'_>,
        contacts: &Bound<'_, PyAny>,
        baumgarte: Option<(f64, f64)>,
        mu: f64,
    ) -> PyResult<Py<PyAny>> {
        let contacts = contacts_of(self, contacts)?;
        let rows: usize = contacts.iter().map(|(_, k)| k.rows()).sum();
        let settings = settings(mu)?;
        let gains = baumgarte.map(|(kp, kd)| Baumgarte { kp, kd });
        let args = [
            self.arg("q", &q)?,
            self.arg("v", &v)?,
            self.arg("tau", &tau)?,
        ];
        let r = &self.reference;
        let nv = r.nv();
        run(py, &args, &[&[nv], &[rows], &[]], |x, out| {
            let (m, system) = system(r, &contacts, x[0], x[1])?;
            let nle = r
                .inverse_dynamics(x[0], x[1], &vec![0.0; nv])
                .map_err(|e| e.to_string())?;
            let (tau, v) = (
                DVector::from_column_slice(x[2]),
                DVector::from_column_slice(x[1]),
            );
            let s = dynamic::forward_dynamics(&m, &nle, &tau, &v, &system, gains, &settings)
                .map_err(|e| e.to_string())?;
            out[..nv].copy_from_slice(s.acceleration.as_slice());
            out[nv..nv + rows].copy_from_slice(s.forces.as_slice());
            out[nv + rows] = s.residual;
            Ok(())
        })
    }

    /// An impact on `contacts` (as `constrained_forward_dynamics`): the velocities after it and
    /// the impulses, `M·(v⁺ − v) = Σ Jᵀ·p` with `J·v⁺ = −restitution·J·v`, every row
    /// bilateral (Pinocchio's `impulseDynamics`: a negative normal impulse is reported, not
    /// hidden). Returns `(v_plus (nv,), impulses (rows,), residual)`.
    #[pyo3(signature = (q, v, contacts, restitution=0.0, mu=0.0))]
    fn impulse_dynamics(
        &self,
        py: Python<'_>,
        q: In<'_>,
        v: In<'_>,
        contacts: &Bound<'_, PyAny>,
        restitution: f64,
        mu: f64,
    ) -> PyResult<Py<PyAny>> {
        let contacts = contacts_of(self, contacts)?;
        let rows: usize = contacts.iter().map(|(_, k)| k.rows()).sum();
        let settings = settings(mu)?;
        if !(restitution.is_finite() && restitution >= 0.0) {
            return Err(Error::new_err(format!(
                "restitution={restitution}: expected a finite number ≥ 0"
            )));
        }
        let args = [self.arg("q", &q)?, self.arg("v", &v)?];
        let r = &self.reference;
        let nv = r.nv();
        run(py, &args, &[&[nv], &[rows], &[]], |x, out| {
            let (m, system) = system(r, &contacts, x[0], x[1])?;
            let v = DVector::from_column_slice(x[1]);
            let s = dynamic::impulse_dynamics(&m, &v, &system, restitution, &settings)
                .map_err(|e| e.to_string())?;
            out[..nv].copy_from_slice(s.acceleration.as_slice());
            out[nv..nv + rows].copy_from_slice(s.forces.as_slice());
            out[nv + rows] = s.residual;
            Ok(())
        })
    }
}
