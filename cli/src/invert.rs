//! `articulated invert`: the inverse plant of Hemami, Dariush & Barin (2005, §5) on a chain read
//! from a file. From a sampled motion (the `t` and `q…` columns of a trajectory CSV, such as
//! `simulate` writes, or motion capture in the same form), velocities and accelerations by
//! Savitzky–Golay differentiation on the actual sample times, then the joint couples by the
//! interpreted reference's inverse dynamics, written as `t,tau0,…`, with a JSON sidecar
//! (`couples.csv.json`) naming each column's coordinate and unit as `simulate`'s does.

use articulated::differentiate::SavitzkyGolay;
use articulated::files::write_atomically;
use articulated::interpreted::coordinates_of;
use articulated::invert::couples_dyn;
use articulated::samples::{write_csv, Samples};
use articulated::trajectory::sidecar_path;
use serde_json::json;

use crate::{load_reference, InvertArgs};

/// Runs `invert`; a one-line summary for stdout, or the error message for stderr.
pub fn run(args: &InvertArgs) -> Result<String, String> {
    let (model, reference) = load_reference(&args.model, args.base, args.params.as_deref())?;
    let (nq, nv) = (reference.nq(), reference.nv());
    let shown = args.trajectory.display();
    let text = std::fs::read_to_string(&args.trajectory)
        .map_err(|e| format!("{shown}: error: cannot read: {e}"))?;
    let samples = Samples::parse_csv(&text, nq).map_err(|e| format!("{shown}: error: {e}"))?;
    let sg =
        SavitzkyGolay::new(args.half_window, args.degree).map_err(|e| format!("error: {e}"))?;
    let couples = couples_dyn(
        &coordinates_of(&model),
        nq,
        nv,
        samples.times(),
        samples.positions(),
        &sg,
        |q, v, a, tau| -> Result<(), articulated::reference::Error> {
            let t = reference.inverse_dynamics(q, v, a)?;
            tau.copy_from_slice(t.as_slice());
            Ok(())
        },
    )
    .map_err(|e| format!("{shown}: error: {e}"))?;
    let mut csv = Vec::new();
    write_csv(&mut csv, "tau", &couples.t, nv, &couples.tau).map_err(|e| format!("error: {e}"))?;
    write_atomically(&args.out, &csv).map_err(|e| format!("{}: error: {e}", args.out.display()))?;
    let sidecar = sidecar_path(&args.out);
    let description = describe(&model, args, couples.t.len());
    write_atomically(&sidecar, format!("{description:#}\n").as_bytes())
        .map_err(|e| format!("{}: error: {e}", sidecar.display()))?;
    Ok(format!(
        "couples at {} of {} samples (the first and last {} have no full window) written to {}",
        couples.t.len(),
        samples.len(),
        args.half_window,
        args.out.display()
    ))
}

/// The couples file's sidecar: the model, the motion it came from, the differentiation, and
/// each column (`t`, then `tau{k}` with velocity coordinate `k`'s name and its generalized
/// force's unit: N·m for an angle's rate, N for a length's).
fn describe(
    model: &articulated::model::Model,
    args: &InvertArgs,
    rows: usize,
) -> serde_json::Value {
    let (_, names) = model.coordinate_names();
    let (_, units) = model.coordinate_units();
    let mut columns = vec![json!({"header": "t", "name": "time", "unit": "s"})];
    for (k, (name, unit)) in names.iter().zip(&units).enumerate() {
        let force = match *unit {
            "rad/s" => "N·m",
            "m/s" => "N",
            _ => "",
        };
        columns.push(json!({"header": format!("tau{k}"), "name": name, "unit": force}));
    }
    let name = crate::simulate::chain_name(model, &args.model);
    json!({
        "format": "articulated-couples/1",
        "model": {"file": args.model.display().to_string(), "name": name},
        "trajectory": args.trajectory.display().to_string(),
        "differentiation": {"half_window": args.half_window, "degree": args.degree},
        "columns": columns,
        "rows": rows,
    })
}
