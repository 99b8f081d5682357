//! `articulated invert`: the inverse plant of Hemami, Dariush & Barin (2005, §5) on a chain read
//! from a file. From a sampled motion (the `t` and `q…` columns of a trajectory CSV, such as
//! `simulate` writes, or motion capture in the same form), velocities and accelerations by
//! Savitzky–Golay differentiation on the actual sample times, then the joint couples by the
//! interpreted reference's inverse dynamics, written as `t,tau0,…`.

use articulated::differentiate::SavitzkyGolay;
use articulated::files::write_atomically;
use articulated::interpreted::coordinates_of;
use articulated::invert::couples_dyn;
use articulated::samples::{write_csv, Samples};

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
    Ok(format!(
        "couples at {} of {} samples (the first and last {} have no full window) written to {}",
        couples.t.len(),
        samples.len(),
        args.half_window,
        args.out.display()
    ))
}
