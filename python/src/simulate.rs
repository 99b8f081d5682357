//! `Model.simulate` and `Model.lqr`: the runtime's integrators and its linear-quadratic
//! regulator on the interpreted model, batches of initial states and parameters on all cores.

use articulated::control::linearize::linearize_dyn;
use articulated::control::riccati::lqr;
use articulated::control::tangent::{difference, retract};
use articulated::drives::ModelDrives;
use articulated::integrate::{Method, State, Stepper};
use articulated::interpreted::Interpreted;
use articulated::reference::Reference;
use articulated::simulate::Simulation;
use nalgebra::{DMatrix, DVector};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::batch::Arg;
use crate::model::{In, Model};
use crate::Error;

/// `τ = τ_ref − K·[q ⊖ q_ref; v − v_ref]`: the law of `Model.simulate`'s `gain`.
struct Feedback {
    q_ref: Vec<f64>,
    v_ref: Vec<f64>,
    tau_ref: Vec<f64>,
    /// `nv × 2nv`.
    gain: DMatrix<f64>,
}

/// A matrix argument of `rows × cols` (row-major, as numpy holds it).
fn matrix(name: &'static str, array: &In<'_>, rows: usize, cols: usize) -> PyResult<DMatrix<f64>> {
    use numpy::PyUntypedArrayMethods;
    if array.shape() != [rows, cols] {
        return Err(Error::new_err(format!(
            "argument `{name}` has shape {:?}, expected ({rows}, {cols})",
            array.shape()
        )));
    }
    let values: Vec<f64> = array.as_array().iter().copied().collect();
    Ok(DMatrix::from_row_slice(rows, cols, &values))
}

/// One vector argument of `width` (one state only), or `default`.
fn vector(
    name: &'static str,
    array: Option<&In<'_>>,
    width: usize,
    default: Vec<f64>,
) -> PyResult<Vec<f64>> {
    let Some(array) = array else {
        return Ok(default);
    };
    let arg = Arg::read(name, array, width)?;
    match arg.states() {
        None => Ok(arg.values().to_vec()),
        Some(_) => Err(Error::new_err(format!(
            "argument `{name}` is one vector of {width}, not a batch"
        ))),
    }
}

/// One run's result: its states (NaN after a fault) and the fault's message.
struct Run {
    q: Vec<f64>,
    v: Vec<f64>,
    fault: Option<String>,
}

#[allow(clippy::too_many_arguments)]
fn one_run(
    reference: Reference,
    coordinates: &[articulated::Coordinates],
    q0: &[f64],
    v0: &[f64],
    simulation: &Simulation<f64>,
    steps: usize,
    method: Method,
    drives: Option<&ModelDrives>,
    feedback: Option<&Feedback>,
) -> Run {
    let (nq, nv) = (q0.len(), v0.len());
    let mut delta = vec![0.0; nv];
    let mut x = DVector::zeros(2 * nv);
    let mut system = Interpreted::new(reference, |_, q: &DVector<f64>, v: &DVector<f64>| {
        let mut tau = DVector::zeros(nv);
        if let Some(f) = feedback {
            difference(coordinates, q.as_slice(), &f.q_ref, &mut delta);
            for k in 0..nv {
                x[k] = delta[k];
                x[nv + k] = v[k] - f.v_ref[k];
            }
            tau = DVector::from_column_slice(&f.tau_ref) - &f.gain * &x;
        }
        match drives {
            Some(d) => d.force(q, v, &tau),
            None => tau,
        }
    });
    let mut stepper = Stepper::new(method, 1e-9, 1e-9);
    let mut q = Vec::with_capacity((steps + 1) * nq);
    let mut v = Vec::with_capacity((steps + 1) * nv);
    let initial = State::new(
        0.0,
        DVector::from_column_slice(q0),
        DVector::from_column_slice(v0),
    );
    let result = simulation.run(
        &mut system,
        &mut stepper,
        initial,
        |s| {
            q.extend_from_slice(s.q.as_slice());
            v.extend_from_slice(s.v.as_slice());
            Ok(())
        },
        |_, _| {},
    );
    q.resize((steps + 1) * nq, f64::NAN);
    v.resize((steps + 1) * nv, f64::NAN);
    Run {
        q,
        v,
        fault: result.err().map(|f| f.to_string()),
    }
}

#[pymethods]
impl Model {
    /// Steps the model from `q0`, `v0` (one state or a batch `(B, nq)`, `(B, nv)`) to `t_end`
    /// at `dt` with `integrator` (`"euler"`, `"symplectic-euler"`, `"rk4"`, `"dopri5"`,
    /// `"implicit-midpoint"`), under `τ = tau_ref − gain·[q ⊖ q_ref; v − v_ref]` where `gain`
    /// (`(nv, 2nv)`, as `lqr` gives) is given, else `τ = 0`; through the joints' drives
    /// (damping, friction, stops, springs) with `drives=True`. `params`: one set of runtime
    /// parameters for all runs, or `(B, np)`, one per run. The runs go on all cores; each is
    /// computed alone, so the results do not depend on the thread count.
    ///
    /// Returns a dict: `t` `(N + 1,)`, `q` `([B,] N + 1, nq)`, `v` `([B,] N + 1, nv)`, and
    /// `faults`: per run `None`, or the message of the fault that stopped it (its states
    /// after it are NaN).
    #[pyo3(signature = (q0, v0, t_end, dt, integrator="rk4", gain=None, q_ref=None, v_ref=None, tau_ref=None, params=None, drives=false))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        q0: In<'py>,
        v0: In<'py>,
        t_end: f64,
        dt: f64,
        integrator: &str,
        gain: Option<In<'py>>,
        q_ref: Option<In<'py>>,
        v_ref: Option<In<'py>>,
        tau_ref: Option<In<'py>>,
        params: Option<In<'py>>,
        drives: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (nq, nv) = (self.reference.nq(), self.reference.nv());
        let method: Method = integrator
            .parse()
            .map_err(|e| Error::new_err(format!("integrator={integrator:?}: {e}")))?;
        let simulation = Simulation::new(0.0, t_end, dt);
        let steps = simulation.steps().map_err(|_| {
            Error::new_err(format!(
                "t_end={t_end} and dt={dt} give no time grid: both must be finite, dt positive and \
                 t_end at least 0"
            ))
        })?;
        let q0 = Arg::read("q0", &q0, nq)?;
        let v0 = Arg::read("v0", &v0, nv)?;
        let feedback = match &gain {
            None => None,
            Some(g) => Some(Feedback {
                gain: matrix("gain", g, nv, 2 * nv)?,
                q_ref: vector(
                    "q_ref",
                    q_ref.as_ref(),
                    nq,
                    self.reference.model().neutral(),
                )?,
                v_ref: vector("v_ref", v_ref.as_ref(), nv, vec![0.0; nv])?,
                tau_ref: vector("tau_ref", tau_ref.as_ref(), nv, vec![0.0; nv])?,
            }),
        };
        let np = self.reference.params().len();
        let params = match &params {
            None => Arg::constant("params", self.reference.params()),
            Some(p) => Arg::read("params", p, np)?,
        };
        let batch = crate::batch::states_of([&q0, &v0])?;
        let n = batch.unwrap_or(1);
        if let Some(b) = params.states() {
            if batch != Some(b) {
                return Err(Error::new_err(format!(
                    "params holds {b} sets, but there are {n} runs: give one set, or one per run"
                )));
            }
        }
        let model = self.reference.model();
        let drives = drives.then(|| ModelDrives::of(model));
        let coordinates = self.coordinates();
        // Each run's reference (its own parameters), built before the threads start.
        let references = (0..n)
            .map(|k| Reference::with_params(model, params.state(k)))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| Error::new_err(e.to_string()))?;
        let runs: Vec<Run> = py.detach(|| {
            references
                .into_par_iter()
                .enumerate()
                .map(|(k, r)| {
                    one_run(
                        r,
                        coordinates,
                        q0.state(k),
                        v0.state(k),
                        &simulation,
                        steps,
                        method,
                        drives.as_ref(),
                        feedback.as_ref(),
                    )
                })
                .collect()
        });
        let t: Vec<f64> = (0..=steps).map(|k| simulation.time(k, steps)).collect();
        let dict = PyDict::new(py);
        dict.set_item("t", numpy::PyArray1::from_vec(py, t))?;
        let stack = |part: fn(&Run) -> &Vec<f64>, width: usize| {
            let values: Vec<f64> = runs.iter().flat_map(|r| part(r).iter().copied()).collect();
            let dims: Vec<usize> = batch.into_iter().chain([steps + 1, width]).collect();
            numpy::ndarray::ArrayD::from_shape_vec(numpy::ndarray::IxDyn(&dims), values)
                .map_err(|e| Error::new_err(e.to_string()))
        };
        use numpy::IntoPyArray;
        dict.set_item("q", stack(|r| &r.q, nq)?.into_pyarray(py))?;
        dict.set_item("v", stack(|r| &r.v, nv)?.into_pyarray(py))?;
        let faults: Vec<Option<String>> = runs.into_iter().map(|r| r.fault).collect();
        match batch {
            Some(_) => dict.set_item("faults", faults)?,
            None => dict.set_item("faults", faults.into_iter().next().flatten())?,
        }
        Ok(dict)
    }

    /// A linear-quadratic regulator about the equilibrium `q_eq` (`v = 0` unless `v_eq`):
    /// the model linearized by central differences along the configuration's tangent,
    /// `x = [q ⊖ q_eq; v − v_eq]`, `u = τ − tau_eq`, then the continuous-time Riccati
    /// equation with the weights `q_weight` (`(2nv, 2nv)`) and `r_weight` (`(nv, nv)`).
    /// Returns `(gain, tau_eq)`: `gain` `(nv, 2nv)` for `simulate(gain=…, q_ref=q_eq,
    /// tau_ref=tau_eq)`, `tau_eq` the forces that hold the equilibrium (gravity and bias).
    #[pyo3(signature = (q_eq, q_weight, r_weight, v_eq=None))]
    fn lqr<'py>(
        &self,
        py: Python<'py>,
        q_eq: In<'py>,
        q_weight: In<'py>,
        r_weight: In<'py>,
        v_eq: Option<In<'py>>,
    ) -> PyResult<(Py<PyAny>, Py<PyAny>)> {
        let (nq, nv) = (self.reference.nq(), self.reference.nv());
        let q_eq = vector("q_eq", Some(&q_eq), nq, vec![])?;
        let v_eq = vector("v_eq", v_eq.as_ref(), nv, vec![0.0; nv])?;
        let qw = matrix("q_weight", &q_weight, 2 * nv, 2 * nv)?;
        let rw = matrix("r_weight", &r_weight, nv, nv)?;
        let r = &self.reference;
        let zero = vec![0.0; nv];
        let tau_eq = r
            .inverse_dynamics(&q_eq, &v_eq, &zero)
            .map_err(|e| Error::new_err(e.to_string()))?;
        let coordinates = self.coordinates();
        let mut q = vec![0.0; nq];
        let lin = linearize_dyn(&v_eq, tau_eq.as_slice(), |delta, v, tau, out| {
            retract(coordinates, &q_eq, delta, &mut q);
            let a = r.forward_dynamics(&q, v, tau)?;
            out.copy_from_slice(a.as_slice());
            Ok::<(), articulated::reference::Error>(())
        })
        .map_err(|e| Error::new_err(format!("linearizing at q_eq: {e}")))?;
        let design =
            lqr(&lin.a, &lin.b, &qw, &rw).map_err(|e| Error::new_err(format!("LQR: {e}")))?;
        let gain: Vec<f64> = (0..nv)
            .flat_map(|i| (0..2 * nv).map(move |j| (i, j)))
            .map(|(i, j)| design.k[(i, j)])
            .collect();
        let gain = numpy::ndarray::Array2::from_shape_vec((nv, 2 * nv), gain)
            .map_err(|e| Error::new_err(e.to_string()))?;
        use numpy::IntoPyArray;
        Ok((
            gain.into_pyarray(py).into_any().unbind(),
            numpy::PyArray1::from_vec(py, tau_eq.as_slice().to_vec())
                .into_any()
                .unbind(),
        ))
    }
}
