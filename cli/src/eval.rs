//! `articulated eval`: one state in, one JSON object out (DESIGN.md §6).

use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use nalgebra::{DMatrix, DVector};
use serde_json::Value;

use crate::{Engine, EvalArgs};

/// Parses a comma-separated vector of `len` finite numbers; `what` names it in errors.
fn parse_vector(text: &str, what: &str, len: usize) -> Result<Vec<f64>, String> {
    let text = text.trim();
    let items: Vec<&str> = if text.is_empty() {
        Vec::new()
    } else {
        text.split(',').map(str::trim).collect()
    };
    if items.len() != len {
        return Err(format!(
            "error: --{what} has {} values, but the model needs {len}",
            items.len()
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, s)| match s.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(x) => Err(format!(
                "error: --{what}[{i}] is {x}: values must be finite"
            )),
            Err(_) => Err(format!("error: --{what}[{i}] = `{s}` is not a number")),
        })
        .collect()
}

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

/// Runs `eval`; the JSON text, or the error message for stderr.
pub fn run(args: &EvalArgs) -> Result<String, String> {
    if args.engine == Engine::Symbolic {
        return Err(
            "error: --engine symbolic needs the generator's expression graph, which is not built \
             yet; use --engine reference"
                .to_string(),
        );
    }
    let model = load_model(&args.model, args.floating).map_err(|e| e.to_string())?;
    let reference = match &args.params {
        None => Reference::new(&model),
        Some(p) => Reference::with_params(&model, &parse_vector(p, "params", model.params.len())?),
    }
    .map_err(|e| format!("{}: error: {e}", args.model.display()))?;
    let (nq, nv) = (reference.nq(), reference.nv());
    let q = match &args.q {
        Some(s) => parse_vector(s, "q", nq)?,
        None => model.neutral(),
    };
    let zeros = vec![0.0; nv];
    let get = |arg: &Option<String>, what: &str| match arg {
        Some(s) => parse_vector(s, what, nv),
        None => Ok(zeros.clone()),
    };
    let (v, a, tau) = (
        get(&args.v, "v")?,
        get(&args.a, "a")?,
        get(&args.tau, "tau")?,
    );
    let fail = |e: articulated::reference::Error| format!("error: {e}");
    let fields = [
        ("nq", Value::from(nq)),
        ("nv", Value::from(nv)),
        (
            "mass_matrix",
            matrix_rows(&reference.mass_matrix(&q).map_err(fail)?),
        ),
        ("bias", vector(&reference.bias(&q, &v).map_err(fail)?)),
        ("gravity", vector(&reference.gravity(&q).map_err(fail)?)),
        (
            "tau",
            vector(&reference.inverse_dynamics(&q, &v, &a).map_err(fail)?),
        ),
        (
            "qdd",
            vector(&reference.forward_dynamics(&q, &v, &tau).map_err(fail)?),
        ),
    ];
    Ok(to_json(&fields))
}

/// One JSON object, keys in the order given (DESIGN.md §6), a matrix row per line, numbers
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
