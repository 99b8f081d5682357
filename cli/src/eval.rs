//! `articulated eval`: one state in, one JSON object out (`docs/guide/cli.md`, `eval`), computed by either
//! engine: the interpreted reference, or the generator's own expression graphs
//! (`--engine symbolic`), which checks the generator without compiling what it emits.

use articulated::constraint::dynamic::FrameKinematics;
use articulated::model::Model;
use articulated::reference::{check_q, Error, Reference, Singularity};
use articulated::FramePlacement;
use articulated_codegen::options::Output;
use articulated_codegen::sym::Var;
use articulated_codegen::trace::frames::FrameAt;
use articulated_codegen::trace::trace;
use nalgebra::{DMatrix, DVector};
use serde_json::Value;

use crate::contacts::{self, Kinematics};
use crate::pinocchio::{Pinocchio, QOrder};
use crate::{load_described, parse_vector, Engine, EvalArgs};

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
    /// The value of one input of an expression graph (NaN for an index the state does not
    /// have, which the graph's sizes rule out: a NaN result is then reported, not a panic).
    fn input(&self, var: Var) -> f64 {
        let (values, i) = match var {
            Var::Q(i) => (&self.q, i),
            Var::V(i) => (&self.v, i),
            Var::A(i) => (&self.a, i),
            Var::Tau(i) => (&self.tau, i),
            Var::Param(i) => (&self.params, i),
            // Only joint wrenches bottom-up read a base wrench, and only the parts of composed
            // constrained derivatives read forces: `eval` prints neither.
            Var::Base(_) | Var::Force(_) => return 0.0,
        };
        values.get(i).copied().unwrap_or(f64::NAN)
    }
}

/// What `eval` prints, whichever engine computed it: each quantity under its key, or the
/// message saying why it could not be computed at this state (forward dynamics where `M` is
/// singular); the others are printed all the same.
type Fields = Vec<(&'static str, Result<Value, String>)>;

/// The condition number of `M` from its eigenvalues, infinite where one is not positive.
fn condition(m: &DMatrix<f64>) -> f64 {
    if m.is_empty() {
        return 1.0;
    }
    let eig = m.clone().symmetric_eigenvalues();
    let (lo, hi) = (eig.min(), eig.max());
    if lo > 0.0 {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// Runs `eval`: the JSON text, and one message per quantity that could not be computed (the
/// caller exits with failure if there is any); or the error message when nothing could be.
pub fn run(args: &EvalArgs) -> Result<(String, Vec<String>), String> {
    // Checks the model and the parameter values, for both engines.
    let (description, reference) = load_described(&args.model, args.base, args.params.as_deref())?;
    let model = &description.model;
    let params = reference.params().to_vec();
    let (nq, nv) = (reference.nq(), reference.nv());
    let pinocchio = (args.q_order == QOrder::Pinocchio).then(|| Pinocchio::of(&description));
    let q = match (&args.q, &pinocchio) {
        (Some(s), None) => parse_vector(s, "q", nq)?,
        (Some(s), Some(p)) => p.q_in(&parse_vector(s, "q", p.nq()?)?, "q")?,
        (None, _) => model.neutral(),
    };
    let get = |arg: &Option<String>, what: &str| match (arg, &pinocchio) {
        (Some(s), None) => parse_vector(s, what, nv),
        (Some(s), Some(p)) => p.v_in(&parse_vector(s, what, nv)?, what),
        (None, _) => Ok(vec![0.0; nv]),
    };
    let state = State {
        q,
        v: get(&args.v, "v")?,
        a: get(&args.a, "a")?,
        tau: get(&args.tau, "tau")?,
        params,
    };
    // A `q` that names no configuration fails every quantity alike: one error, nothing printed.
    check_q(model, &state.q).map_err(|e| format!("error: {e}"))?;
    let mut computed = match args.engine {
        Engine::Reference => by_reference(&reference, &state),
        Engine::Symbolic => by_graph(model, &state),
    };
    let (mut q_names, mut v_names) = model.coordinate_names();
    let mut shown_nq = nq;
    if let Some(p) = &pinocchio {
        (q_names, v_names) = p.names(&q_names, &v_names);
        shown_nq = p.nq()?;
        let sources = p.v_sources()?;
        for (key, value) in &mut computed {
            if let (true, Ok(v)) = (BY_VELOCITY.contains(key), value.as_mut()) {
                *v = in_order(v, &sources);
            }
        }
    }
    let mut fields = vec![
        ("nq", Ok(Value::from(shown_nq))),
        ("nv", Ok(Value::from(nv))),
        (
            "coordinates",
            Ok(serde_json::json!({ "q": q_names, "v": v_names })),
        ),
        ("drives", Ok(drives(model))),
        ("mimic", Ok(mimics(model))),
    ];
    fields.extend(computed);
    if let Some(list) = &args.frames {
        let names: Vec<String> = list.split(',').map(|f| f.trim().to_string()).collect();
        check_frames(model, &names)?;
        let mut value = match args.engine {
            Engine::Reference => frames_by_reference(&reference, &names, &state),
            Engine::Symbolic => frames_by_graph(model, &names, &state),
        };
        if let (Some(p), Ok(v)) = (&pinocchio, value.as_mut()) {
            reorder_jacobians(v, &p.v_sources()?);
        }
        fields.push(("frames", value));
    }
    if let Some(list) = &args.contacts {
        fields.extend(constrained(
            args,
            list,
            model,
            &reference,
            &state,
            pinocchio.as_ref(),
        )?);
    }
    let mut errors = Vec::new();
    let values: Vec<(&str, Value)> = fields
        .into_iter()
        .map(|(key, value)| match value {
            Ok(v) => (key, v),
            Err(message) => {
                errors.push(format!("error: `{key}`: {message}"));
                let mut object = serde_json::Map::new();
                object.insert("error".into(), Value::from(message));
                (key, Value::Object(object))
            }
        })
        .collect();
    Ok((to_json(&values), errors))
}

/// `--contacts LIST` (with `--baumgarte`, `--restitution`): the constrained accelerations and
/// forces, and the impulse dynamics where a restitution is given, as `eval` prints them.
fn constrained(
    args: &EvalArgs,
    list: &str,
    model: &Model,
    reference: &Reference,
    state: &State,
    pinocchio: Option<&Pinocchio>,
) -> Result<Fields, String> {
    let contacts = contacts::parse(list)?;
    let names: Vec<String> = contacts.iter().map(|c| c.0.clone()).collect();
    // A frame may carry two constraints (redundant ones are the solver's to name).
    let mut distinct = names.clone();
    distinct.sort();
    distinct.dedup();
    check_frames(model, &distinct).map_err(|e| e.replace("--frames", "--contacts"))?;
    let gains = args
        .baumgarte
        .as_deref()
        .map(contacts::parse_gains)
        .transpose()?;
    let restitution = args
        .restitution
        .as_deref()
        .map(contacts::parse_restitution)
        .transpose()?;
    let kinematics = match args.engine {
        Engine::Reference => contact_kinematics_by_reference(reference, &names, state),
        Engine::Symbolic => contact_kinematics_by_graph(model, &names, state),
    };
    let (mut constrained, mut impulse) = match kinematics {
        Ok(k) => contacts::solve(&k, &contacts, &state.v, &state.tau, gains, restitution),
        Err(e) => (Err(e.clone()), restitution.map(|_| Err(e))),
    };
    if let Some(p) = pinocchio {
        let sources = p.v_sources()?;
        for (value, key) in [(constrained.as_mut().ok(), "qdd")]
            .into_iter()
            .chain([(impulse.as_mut().and_then(|i| i.as_mut().ok()), "v_plus")])
        {
            if let Some(Value::Object(object)) = value {
                if let Some(x) = object.get_mut(key) {
                    *x = in_order(x, &sources);
                }
            }
        }
    }
    let mut fields: Fields = vec![("constrained", constrained)];
    fields.extend(impulse.map(|i| ("impulse", i)));
    Ok(fields)
}

/// The outputs indexed by velocity (vectors of `nv`, matrices `nv × nv`), which
/// `--q-order pinocchio` prints in Pinocchio's joint order.
const BY_VELOCITY: [&str; 6] = [
    "mass_matrix",
    "bias",
    "gravity",
    "tau",
    "qdd",
    "coriolis_matrix",
];

/// A vector's entries, or a matrix's rows and columns, taken from the indices `sources`.
fn in_order(value: &Value, sources: &[usize]) -> Value {
    let pick = |row: &Vec<Value>| -> Value {
        sources
            .iter()
            .map(|&k| row.get(k).cloned().unwrap_or(Value::Null))
            .collect()
    };
    match value {
        Value::Array(rows) if rows.first().is_some_and(Value::is_array) => sources
            .iter()
            .map(|&k| match rows.get(k) {
                Some(Value::Array(row)) => pick(row),
                _ => Value::Null,
            })
            .collect(),
        Value::Array(entries) => pick(entries),
        other => other.clone(),
    }
}

/// The joints whose description gives a drive, in joint order: `{"joint": name, "armature": …,
/// "damping": …, "friction": …, "lower": …, "upper": …, "velocity": …, "effort": …}`, `null`
/// for a limit not given.
fn drives(model: &Model) -> Value {
    let number = |x: f64| {
        if x.is_finite() {
            Value::from(x)
        } else {
            Value::Null
        }
    };
    let joints = model.joints.iter().filter(|j| !j.drive.is_free()).map(|j| {
        let d = j.drive;
        let mut object = serde_json::Map::new();
        object.insert("joint".into(), Value::from(j.name.as_str()));
        for (key, x) in [
            ("armature", d.armature),
            ("damping", d.damping),
            ("friction", d.friction),
            ("lower", d.lower),
            ("upper", d.upper),
            ("velocity", d.velocity),
            ("effort", d.effort),
        ] {
            object.insert(key.into(), number(x));
        }
        Value::Object(object)
    });
    Value::Array(joints.collect())
}

/// The mimic joints, in joint order: `{"joint": name, "follows": name, "multiplier": …,
/// "offset": …}`; they have no entries in `q` and `v`.
fn mimics(model: &Model) -> Value {
    let joints = model.joints.iter().filter_map(|j| {
        let m = j.mimic?;
        let followed = model.joints.get(m.joint)?;
        Some(serde_json::json!({
            "joint": j.name,
            "follows": followed.name,
            "multiplier": m.multiplier,
            "offset": m.offset,
        }))
    });
    Value::Array(joints.collect())
}

fn by_reference(r: &Reference, s: &State) -> Fields {
    let text = |e: Error| e.to_string();
    // Where nothing moves (a quadrotor's fixed links on a fixed base: nv = 0) no body is left
    // and the centre of mass is no point: it and the centroidal momentum are `null`, the rest
    // empty.
    let nothing_moves = r.nv() == 0;
    let column = |v: Result<nalgebra::Vector3<f64>, Error>| match v {
        _ if nothing_moves => Ok(Value::Null),
        v => v
            .map(|v| vector(&DVector::from_column_slice(v.as_slice())))
            .map_err(text),
    };
    let m = r.mass_matrix(&s.q);
    let cond = m.as_ref().map(condition).map_err(|e| e.clone());
    vec![
        (
            "mass_matrix",
            m.as_ref().map(matrix_rows).map_err(|e| text(e.clone())),
        ),
        (
            "mass_matrix_condition",
            cond.map(condition_value).map_err(text),
        ),
        ("bias", r.bias(&s.q, &s.v).map(|x| vector(&x)).map_err(text)),
        ("gravity", r.gravity(&s.q).map(|x| vector(&x)).map_err(text)),
        (
            "tau",
            r.inverse_dynamics(&s.q, &s.v, &s.a)
                .map(|x| vector(&x))
                .map_err(text),
        ),
        (
            "qdd",
            r.forward_dynamics(&s.q, &s.v, &s.tau)
                .map(|x| vector(&x))
                .map_err(text),
        ),
        ("center_of_mass", column(r.center_of_mass(&s.q))),
        (
            "center_of_mass_velocity",
            column(r.center_of_mass_velocity(&s.q, &s.v)),
        ),
        (
            "centroidal_momentum",
            match r.centroidal_momentum(&s.q, &s.v) {
                _ if nothing_moves => Ok(Value::Null),
                h => h
                    .map(|x| vector(&DVector::from_column_slice(x.as_slice())))
                    .map_err(text),
            },
        ),
        (
            "centroidal_momentum_rate",
            match r.centroidal_momentum_rate(&s.q, &s.v, &s.a) {
                _ if nothing_moves => Ok(Value::Null),
                h => h
                    .map(|x| vector(&DVector::from_column_slice(x.as_slice())))
                    .map_err(text),
            },
        ),
        (
            "kinetic_energy",
            r.kinetic_energy(&s.q, &s.v).map(Value::from).map_err(text),
        ),
        (
            "potential_energy",
            r.potential_energy(&s.q).map(Value::from).map_err(text),
        ),
        (
            "coriolis_matrix",
            r.coriolis_matrix(&s.q, &s.v)
                .map(|x| matrix_rows(&x))
                .map_err(text),
        ),
    ]
}

/// `cond(M)` as JSON: a number, or the string `"infinite"` where `M` is singular.
fn condition_value(c: f64) -> Value {
    if c.is_finite() {
        Value::from(c)
    } else {
        Value::from("infinite")
    }
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
fn by_graph(model: &Model, s: &State) -> Fields {
    let nv = model.nv();
    let values = |output: Output| -> Result<Vec<f64>, String> {
        let traced = trace(model, output);
        let (values, pivots_ok) = traced.eval(|var| s.input(var));
        if !pivots_ok {
            // The generator's test failed; name the pivot that came out worst, relative to its
            // unreduced value (NaN worst of all).
            let pairs = traced.pivots.iter().flat_map(|p| &p.pairs);
            let pd: Vec<(f64, f64)> = pairs
                .map(
                    |&(p, d)| match traced.graph.eval(&[p, d], |var| s.input(var))[..] {
                        [p, d] => (p, d),
                        _ => (f64::NAN, f64::NAN),
                    },
                )
                .collect();
            let ratio = |&(p, d): &(f64, f64)| {
                let r = p / d.abs();
                if r.is_nan() {
                    f64::NEG_INFINITY
                } else {
                    r
                }
            };
            let (k, (p, d)) = pd
                .iter()
                .copied()
                .enumerate()
                .min_by(|(_, a), (_, b)| ratio(a).total_cmp(&ratio(b)))
                .unwrap_or((0, (f64::NAN, f64::NAN)));
            return Err(Error::Singular(Singularity::Pivot {
                joint: joint_of_v(model, k),
                velocity: k,
                pivot: p,
                unreduced: d,
            })
            .to_string());
        }
        if let Some(k) = values.iter().position(|x| !x.is_finite()) {
            return Err(if output == Output::ForwardDynamics {
                Error::Singular(Singularity::NonFiniteAcceleration {
                    joint: joint_of_v(model, k),
                    velocity: k,
                })
            } else {
                Error::NonFiniteResult {
                    output: output.name(),
                }
            }
            .to_string());
        }
        Ok(values)
    };
    let square = |x: Vec<f64>| DMatrix::from_row_slice(nv, nv, &x);
    let vec_of = |x: Vec<f64>| vector(&DVector::from_vec(x));
    let scalar = |x: Vec<f64>| Value::from(x.first().copied().unwrap_or(f64::NAN));
    let m = values(Output::MassMatrix).map(square);
    vec![
        (
            "mass_matrix",
            m.as_ref().map(matrix_rows).map_err(String::clone),
        ),
        (
            "mass_matrix_condition",
            m.as_ref()
                .map(|m| condition_value(condition(m)))
                .map_err(String::clone),
        ),
        ("bias", values(Output::Bias).map(vec_of)),
        ("gravity", values(Output::Gravity).map(vec_of)),
        ("tau", values(Output::InverseDynamics).map(vec_of)),
        ("qdd", values(Output::ForwardDynamics).map(vec_of)),
        ("center_of_mass", values(Output::CenterOfMass).map(vec_of)),
        (
            "center_of_mass_velocity",
            values(Output::CenterOfMassVelocity).map(vec_of),
        ),
        (
            "centroidal_momentum",
            values(Output::CentroidalMomentum).map(vec_of),
        ),
        (
            "centroidal_momentum_rate",
            values(Output::CentroidalMomentumRate).map(vec_of),
        ),
        ("kinetic_energy", values(Output::KineticEnergy).map(scalar)),
        (
            "potential_energy",
            values(Output::PotentialEnergy).map(scalar),
        ),
        (
            "coriolis_matrix",
            values(Output::CoriolisMatrix).map(|x| matrix_rows(&square(x))),
        ),
    ]
}

/// One JSON object, keys in the order given (`docs/guide/cli.md`, `eval`), a matrix row per line, numbers
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

/// The frames `names` exist on `model` (the check stage's rule, as for `frames: [...]`).
fn check_frames(model: &Model, names: &[String]) -> Result<(), String> {
    let options = articulated_codegen::options::Options {
        frames: names.to_vec(),
        outputs: vec![Output::FramePlacements],
        ..Default::default()
    };
    let problems = articulated_codegen::check::options(model, &options);
    match problems.first() {
        None => Ok(()),
        Some(_) => Err(problems
            .iter()
            .map(|p| format!("error: --frames: {}", p.message))
            .collect::<Vec<_>>()
            .join("\n")),
    }
}

/// The three reference frames' keys, in the order of the outputs.
const REFERENCE_FRAMES: [&str; 3] = ["local", "world", "local_world_aligned"];

/// One frame's values as `eval` prints them (DESIGN §9): `rotation` (rows), `translation`,
/// `velocity` (LOCAL), `acceleration` (classical, LOCAL_WORLD_ALIGNED), and the Jacobians and
/// their time variations by reference frame (rows).
fn frame_json(
    placement: &[f64],
    velocity: &[f64],
    acceleration: &[f64],
    jacobians: [&[f64]; 3],
    rates: [&[f64]; 3],
    nv: usize,
) -> Value {
    let rows = |x: &[f64], cols: usize| -> Value {
        Value::Array(
            x.chunks(cols.max(1))
                .map(|r| Value::from(r.to_vec()))
                .collect(),
        )
    };
    let by_frame = |m: [&[f64]; 3]| -> Value {
        let mut object = serde_json::Map::new();
        for (key, x) in REFERENCE_FRAMES.iter().zip(m) {
            object.insert((*key).into(), rows(x, nv));
        }
        Value::Object(object)
    };
    serde_json::json!({
        "rotation": rows(placement.get(..9).unwrap_or_default(), 3),
        "translation": placement.get(9..12).unwrap_or_default(),
        "velocity": velocity,
        "acceleration": acceleration,
        "jacobian": by_frame(jacobians),
        "jacobian_time_variation": by_frame(rates),
    })
}

/// The frame outputs, in the order [`frame_json`] takes them.
const FRAME_OUTPUTS: [Output; 9] = [
    Output::FramePlacements,
    Output::FrameVelocities,
    Output::FrameAccelerations,
    Output::FrameJacobiansLocal,
    Output::FrameJacobiansWorld,
    Output::FrameJacobiansLocalWorldAligned,
    Output::FrameJacobianTimeVariationsLocal,
    Output::FrameJacobianTimeVariationsWorld,
    Output::FrameJacobianTimeVariationsLocalWorldAligned,
];

/// The frames `names` of `model` as the frame traces take them (names `check_frames` has
/// accepted; any other is left out).
fn frames_at(model: &Model, names: &[String]) -> Vec<FrameAt> {
    names
        .iter()
        .filter_map(|name| {
            let (parent, placement) = model.frame(name)?;
            Some(FrameAt {
                name: name.clone(),
                parent,
                placement,
            })
        })
        .collect()
}

/// The frames by the generator's expression graphs (`trace::frames`).
fn frames_by_graph(model: &Model, names: &[String], s: &State) -> Result<Value, String> {
    let at = frames_at(model, names);
    let nv = model.nv();
    let per_frame: Vec<Vec<f64>> = FRAME_OUTPUTS
        .iter()
        .map(|&output| {
            let traced = articulated_codegen::trace::frames::trace(model, output, &at, false);
            traced.eval(|var| s.input(var)).0
        })
        .collect();
    let mut object = serde_json::Map::new();
    for (k, name) in names.iter().enumerate() {
        let part = |o: usize, size: usize| -> &[f64] {
            per_frame
                .get(o)
                .and_then(|x| x.get(k * size..(k + 1) * size))
                .unwrap_or_default()
        };
        let j = 6 * nv;
        let value = frame_json(
            part(0, 12),
            part(1, 6),
            part(2, 6),
            [part(3, j), part(4, j), part(5, j)],
            [part(6, j), part(7, j), part(8, j)],
            nv,
        );
        if let Some(x) = per_frame.iter().flatten().find(|x| !x.is_finite()) {
            return Err(format!("frame `{name}`: a value is not finite ({x})"));
        }
        object.insert(name.clone(), value);
    }
    Ok(Value::Object(object))
}

/// The frames by the interpreted reference.
fn frames_by_reference(r: &Reference, names: &[String], s: &State) -> Result<Value, String> {
    use articulated::reference::ReferenceFrame::{Local, LocalWorldAligned, World};
    let nv = r.nv();
    let flat = |m: &DMatrix<f64>| -> Vec<f64> {
        (0..m.nrows())
            .flat_map(|i| (0..m.ncols()).map(move |j| (i, j)))
            .map(|ij| m[ij])
            .collect()
    };
    let mut object = serde_json::Map::new();
    for name in names {
        let text = |e: Error| format!("frame `{name}`: {e}");
        let (rotation, translation) = r.frame_placement(&s.q, name).map_err(text)?;
        let placement: Vec<f64> = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|ij| rotation.get(ij).copied().unwrap_or(f64::NAN))
            .chain(translation.iter().copied())
            .collect();
        let velocity = r.frame_velocity(&s.q, &s.v, name).map_err(text)?;
        let acceleration = r.frame_acceleration(&s.q, &s.v, &s.a, name).map_err(text)?;
        let mut jacobians = Vec::new();
        let mut rates = Vec::new();
        for frame in [Local, World, LocalWorldAligned] {
            jacobians.push(flat(&r.frame_jacobian(&s.q, name, frame).map_err(text)?));
            rates.push(flat(
                &r.frame_jacobian_time_variation(&s.q, &s.v, name, frame)
                    .map_err(text)?,
            ));
        }
        let three = |m: &[Vec<f64>]| -> [Vec<f64>; 3] {
            [0, 1, 2].map(|k| m.get(k).cloned().unwrap_or_default())
        };
        let (j, d) = (three(&jacobians), three(&rates));
        let value = frame_json(
            &placement,
            velocity.as_slice(),
            acceleration.as_slice(),
            [&j[0], &j[1], &j[2]],
            [&d[0], &d[1], &d[2]],
            nv,
        );
        object.insert(name.clone(), value);
    }
    Ok(Value::Object(object))
}

/// `--q-order pinocchio`: every Jacobian's columns in Pinocchio's order.
fn reorder_jacobians(frames: &mut Value, sources: &[usize]) {
    let Value::Object(frames) = frames else {
        return;
    };
    for frame in frames.values_mut() {
        for key in ["jacobian", "jacobian_time_variation"] {
            let Some(Value::Object(by_frame)) = frame.get_mut(key) else {
                continue;
            };
            for rows in by_frame.values_mut() {
                if let Value::Array(rows) = rows {
                    for row in rows.iter_mut() {
                        if let Value::Array(entries) = row {
                            *row = sources
                                .iter()
                                .map(|&k| entries.get(k).cloned().unwrap_or(Value::Null))
                                .collect();
                        }
                    }
                }
            }
        }
    }
}

/// What the constraints of `--contacts` are made of, by the interpreted reference: `M`,
/// `nle = N·q̇ + g`, and each frame's placement, LOCAL Jacobian, LOCAL velocity and classical
/// acceleration at `q̈ = 0`.
fn contact_kinematics_by_reference(
    r: &Reference,
    names: &[String],
    s: &State,
) -> Result<Kinematics, String> {
    let text = |e: Error| e.to_string();
    let m = r.mass_matrix(&s.q).map_err(text)?;
    let nle = r.bias(&s.q, &s.v).map_err(text)? + r.gravity(&s.q).map_err(text)?;
    let frames = names
        .iter()
        .map(|name| {
            FrameKinematics::by_reference(r, &s.q, &s.v, name)
                .map_err(|e| format!("frame `{name}`: {e}"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Kinematics { m, nle, frames })
}

/// [`contact_kinematics_by_reference`] by the generator's expression graphs.
fn contact_kinematics_by_graph(
    model: &Model,
    names: &[String],
    s: &State,
) -> Result<Kinematics, String> {
    let nv = model.nv();
    let at = frames_at(model, names);
    // The drifts are the classical accelerations at q̈ = 0.
    let still = State {
        a: vec![0.0; nv],
        q: s.q.clone(),
        v: s.v.clone(),
        tau: s.tau.clone(),
        params: s.params.clone(),
    };
    let finite = |what: &str, x: Vec<f64>| -> Result<Vec<f64>, String> {
        match x.iter().find(|x| !x.is_finite()) {
            Some(bad) => Err(format!("{what}: a value is not finite ({bad})")),
            None => Ok(x),
        }
    };
    let m = finite(
        "mass_matrix",
        trace(model, Output::MassMatrix).eval(|v| s.input(v)).0,
    )?;
    let nle = finite(
        "nonlinear_effects",
        trace(model, Output::NonlinearEffects)
            .eval(|v| s.input(v))
            .0,
    )?;
    let frame = |output: Output| -> Result<Vec<f64>, String> {
        let traced = articulated_codegen::trace::frames::trace(model, output, &at, false);
        finite(output.name(), traced.eval(|v| still.input(v)).0)
    };
    let (placements, jacobians) = (
        frame(Output::FramePlacements)?,
        frame(Output::FrameJacobiansLocal)?,
    );
    let (velocities, drifts) = (
        frame(Output::FrameVelocities)?,
        frame(Output::FrameAccelerations)?,
    );
    let nf = at.len();
    let sizes = [
        (m.len(), nv * nv),
        (nle.len(), nv),
        (placements.len(), 12 * nf),
        (jacobians.len(), 6 * nv * nf),
        (velocities.len(), 6 * nf),
        (drifts.len(), 6 * nf),
    ];
    if sizes.iter().any(|(found, expected)| found != expected) {
        return Err(format!(
            "the expression graphs' sizes are not the model's: {sizes:?}"
        ));
    }
    let part = |x: &[f64], k: usize, size: usize| -> Vec<f64> {
        x.get(k * size..(k + 1) * size).unwrap_or_default().to_vec()
    };
    let frames = (0..at.len())
        .map(|k| {
            let p = part(&placements, k, 12);
            let six = |x: &[f64]| nalgebra::Vector6::from_iterator(part(x, k, 6));
            FrameKinematics {
                placement: FramePlacement {
                    rotation: nalgebra::Matrix3::from_row_iterator(p.iter().take(9).copied()),
                    translation: nalgebra::Vector3::from_iterator(p.iter().skip(9).copied()),
                },
                jacobian: DMatrix::from_row_slice(6, nv, &part(&jacobians, k, 6 * nv)),
                velocity: six(&velocities),
                drift: six(&drifts),
            }
        })
        .collect();
    Ok(Kinematics {
        m: DMatrix::from_row_slice(nv, nv, &m),
        nle: DVector::from_vec(nle),
        frames,
    })
}
