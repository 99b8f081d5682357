//! `articulated eval`: one state in, one JSON object out (the README's `articulated eval`), computed by either
//! engine: the interpreted reference, or the generator's own expression graphs
//! (`--engine symbolic`), which checks the generator without compiling what it emits.

use articulated::model::Model;
use articulated::reference::{check_q, Error, Reference, Singularity};
use articulated_codegen::options::Output;
use articulated_codegen::sym::Var;
use articulated_codegen::trace::trace;
use nalgebra::{DMatrix, DVector};
use serde_json::Value;

use crate::{load_reference, parse_vector, Engine, EvalArgs};

fn matrix_rows(m: &DMatrix<f64>) -> Value {
    Value::Array(
        m.row_iter()
            .map(|r| r.iter().copied().collect::<Vec<f64>>().into())
            .collect(),
    )
}

fn vector(v: &DVector<f64>) -> Value {
    v.iter().copied().collect::<Vec<f64>>().into()
}

/// One state: positions, velocities, accelerations, joint forces and parameter values.
struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    tau: Vec<f64>,
    params: Vec<f64>,
}

impl State {
    /// The value of one input of an expression graph.
    fn input(&self, var: Var) -> f64 {
        match var {
            Var::Q(i) => self.q[i],
            Var::V(i) => self.v[i],
            Var::A(i) => self.a[i],
            Var::Tau(i) => self.tau[i],
            Var::Param(i) => self.params[i],
            // Only joint wrenches bottom-up read a base wrench, and `eval` does not print them.
            Var::Base(_) => 0.0,
        }
    }
}

/// What `eval` prints, whichever engine computed it.
struct Dynamics {
    mass_matrix: DMatrix<f64>,
    bias: DVector<f64>,
    gravity: DVector<f64>,
    tau: DVector<f64>,
    qdd: DVector<f64>,
    /// The quantities of the whole system at `(q, v)`.
    whole: WholeBody,
}

/// Centre of mass, its velocity, the centroidal momentum `[k_G; p]`, the energies and the
/// Coriolis matrix (the same as the generated functions of those names).
struct WholeBody {
    center_of_mass: DVector<f64>,
    center_of_mass_velocity: DVector<f64>,
    centroidal_momentum: DVector<f64>,
    kinetic_energy: f64,
    potential_energy: f64,
    coriolis_matrix: DMatrix<f64>,
}

/// Runs `eval`; the JSON text, or the error message for stderr.
pub fn run(args: &EvalArgs) -> Result<String, String> {
    // Checks the model and the parameter values, for both engines.
    let (model, reference) = load_reference(&args.model, args.floating, args.params.as_deref())?;
    let params = reference.params().to_vec();
    let (nq, nv) = (reference.nq(), reference.nv());
    let q = match &args.q {
        Some(s) => parse_vector(s, "q", nq)?,
        None => model.neutral(),
    };
    let get = |arg: &Option<String>, what: &str| match arg {
        Some(s) => parse_vector(s, what, nv),
        None => Ok(vec![0.0; nv]),
    };
    let state = State {
        q,
        v: get(&args.v, "v")?,
        a: get(&args.a, "a")?,
        tau: get(&args.tau, "tau")?,
        params,
    };
    let fail = |e: Error| format!("error: {e}");
    let d = match args.engine {
        Engine::Reference => by_reference(&reference, &state).map_err(fail)?,
        Engine::Symbolic => by_graph(&model, &state)?,
    };
    let fields = [
        ("nq", Value::from(nq)),
        ("nv", Value::from(nv)),
        ("mass_matrix", matrix_rows(&d.mass_matrix)),
        ("bias", vector(&d.bias)),
        ("gravity", vector(&d.gravity)),
        ("tau", vector(&d.tau)),
        ("qdd", vector(&d.qdd)),
        ("center_of_mass", vector(&d.whole.center_of_mass)),
        (
            "center_of_mass_velocity",
            vector(&d.whole.center_of_mass_velocity),
        ),
        ("centroidal_momentum", vector(&d.whole.centroidal_momentum)),
        ("kinetic_energy", Value::from(d.whole.kinetic_energy)),
        ("potential_energy", Value::from(d.whole.potential_energy)),
        ("coriolis_matrix", matrix_rows(&d.whole.coriolis_matrix)),
    ];
    Ok(to_json(&fields))
}

fn by_reference(r: &Reference, s: &State) -> Result<Dynamics, Error> {
    Ok(Dynamics {
        mass_matrix: r.mass_matrix(&s.q)?,
        bias: r.bias(&s.q, &s.v)?,
        gravity: r.gravity(&s.q)?,
        tau: r.inverse_dynamics(&s.q, &s.v, &s.a)?,
        qdd: r.forward_dynamics(&s.q, &s.v, &s.tau)?,
        whole: WholeBody {
            center_of_mass: DVector::from_column_slice(r.center_of_mass(&s.q)?.as_slice()),
            center_of_mass_velocity: DVector::from_column_slice(
                r.center_of_mass_velocity(&s.q, &s.v)?.as_slice(),
            ),
            centroidal_momentum: DVector::from_column_slice(
                r.centroidal_momentum(&s.q, &s.v)?.as_slice(),
            ),
            kinetic_energy: r.kinetic_energy(&s.q, &s.v)?,
            potential_energy: r.potential_energy(&s.q)?,
            coriolis_matrix: r.coriolis_matrix(&s.q, &s.v)?,
        },
    })
}

/// The name of the joint that velocity `k` belongs to.
fn joint_of_v(model: &Model, k: usize) -> String {
    model
        .joint_of_velocity(k)
        .map_or_else(String::new, |j| j.name.clone())
}

/// The generator's expression graphs (`articulated_codegen::trace::trace`), evaluated in
/// `f64`: what the generated code computes, with the same checks (every forward-dynamics pivot
/// positive, every result finite), reported as the reference reports them.
fn by_graph(model: &Model, s: &State) -> Result<Dynamics, String> {
    let fail = |e: Error| format!("error: {e}");
    // As the reference: a zero quaternion names no rotation (the graph would give NaN).
    check_q(model, &s.q).map_err(fail)?;
    let nv = model.nv();
    let values = |output: Output| -> Result<Vec<f64>, String> {
        let traced = trace(model, output);
        let (values, pivots_ok) = traced.eval(|var| s.input(var));
        if !pivots_ok {
            // The generator's test failed; name the pivot that came out worst, relative to its
            // unreduced value (NaN worst of all).
            let pairs = traced.pivots.iter().flat_map(|p| &p.pairs);
            let pd: Vec<(f64, f64)> = pairs
                .map(|&(p, d)| {
                    let x = traced.graph.eval(&[p, d], |var| s.input(var));
                    (x[0], x[1])
                })
                .collect();
            let ratio = |&(p, d): &(f64, f64)| {
                let r = p / d.abs();
                if r.is_nan() {
                    f64::NEG_INFINITY
                } else {
                    r
                }
            };
            let k = (0..pd.len())
                .min_by(|&i, &j| ratio(&pd[i]).total_cmp(&ratio(&pd[j])))
                .unwrap_or(0);
            let (p, d) = pd.get(k).copied().unwrap_or((f64::NAN, f64::NAN));
            return Err(fail(Error::Singular(Singularity::Pivot {
                joint: joint_of_v(model, k),
                velocity: k,
                pivot: p,
                unreduced: d,
            })));
        }
        if let Some(k) = values.iter().position(|x| !x.is_finite()) {
            return Err(fail(if output == Output::ForwardDynamics {
                Error::Singular(Singularity::NonFiniteAcceleration {
                    joint: joint_of_v(model, k),
                    velocity: k,
                })
            } else {
                Error::NonFiniteResult {
                    output: output.name(),
                }
            }));
        }
        Ok(values)
    };
    Ok(Dynamics {
        mass_matrix: DMatrix::from_row_slice(nv, nv, &values(Output::MassMatrix)?),
        bias: DVector::from_vec(values(Output::Bias)?),
        gravity: DVector::from_vec(values(Output::Gravity)?),
        tau: DVector::from_vec(values(Output::InverseDynamics)?),
        qdd: DVector::from_vec(values(Output::ForwardDynamics)?),
        whole: WholeBody {
            center_of_mass: DVector::from_vec(values(Output::CenterOfMass)?),
            center_of_mass_velocity: DVector::from_vec(values(Output::CenterOfMassVelocity)?),
            centroidal_momentum: DVector::from_vec(values(Output::CentroidalMomentum)?),
            kinetic_energy: values(Output::KineticEnergy)?[0],
            potential_energy: values(Output::PotentialEnergy)?[0],
            coriolis_matrix: DMatrix::from_row_slice(nv, nv, &values(Output::CoriolisMatrix)?),
        },
    })
}

/// One JSON object, keys in the order given (the README's `articulated eval`), a matrix row per line, numbers
/// printed so they read back exactly.
fn to_json(fields: &[(&str, Value)]) -> String {
    let mut out = String::from("{\n");
    for (k, (key, value)) in fields.iter().enumerate() {
        let text = match value {
            Value::Array(rows) if rows.first().is_some_and(Value::is_array) => {
                let rows: Vec<String> = rows.iter().map(|r| format!("    {r}")).collect();
                format!("[\n{}\n  ]", rows.join(",\n"))
            }
            other => other.to_string(),
        };
        let comma = if k + 1 < fields.len() { "," } else { "" };
        out.push_str(&format!("  \"{key}\": {text}{comma}\n"));
    }
    out.push('}');
    out
}
