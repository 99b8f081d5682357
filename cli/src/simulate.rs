//! `articulated simulate`: a chain read from a file, left to itself (`τ = 0`, with its joints'
//! damping, friction and stops under `--drives`) from an initial state, stepped by one of the
//! runtime's integrators on the interpreted reference dynamics (the CLI cannot compile a
//! chain); the trajectory written as CSV and, if asked, plotted.

use std::path::Path;

use articulated::drives::ModelDrives;
use articulated::files::write_atomically;
use articulated::integrate::{Method, State, Stepper};
use articulated::interpreted::Interpreted;
use articulated::nalgebra::{DVector, Dyn};
use articulated::plot::{svg, Panel};
use articulated::reference::Reference;
use articulated::simulate::Simulation;
use articulated::trajectory::Trajectory;
use indicatif::{ProgressBar, ProgressStyle};

use crate::{load_reference, parse_vector, SimulateArgs};

/// The position stops that a fixed-step explicit integrator cannot step at `dt`: a stop is a
/// spring and damper on the joint's inertia `I = M_kk(q0)`, whose fastest mode decays at
/// `|λ| = (c + √(c² − 4ω²))/2` with `c = stop_damping / I`, `ω² = stop_stiffness / I` (`ω`
/// when the roots are complex); Euler, symplectic Euler and RK4 are stable for
/// `|λ|·dt ≲ 2`. A light joint (a fingertip) against the default stops needs far smaller steps
/// than the rest of the chain: said before the run, rather than found as a diverged state.
fn stiff_stops(
    model: &articulated::model::Model,
    reference: &Reference,
    q0: &[f64],
    dt: f64,
    method: Method,
) -> Vec<String> {
    let explicit = matches!(
        method,
        Method::Euler | Method::SymplecticEuler | Method::Rk4
    );
    let Ok(m) = reference.mass_matrix(q0) else {
        return Vec::new();
    };
    let smoothing = articulated::drives::Smoothing::<f64>::default();
    let mut out = Vec::new();
    for (i, joint) in model.joints.iter().enumerate() {
        let limited = joint.drive.lower.is_finite() || joint.drive.upper.is_finite();
        if !explicit || !limited || joint.nv() != 1 {
            continue;
        }
        let k = model.v_offset(i);
        let Some(&inertia) = m.get((k, k)) else {
            continue;
        };
        let c = smoothing.stop_damping / inertia;
        let w2 = smoothing.stop_stiffness / inertia;
        let fastest = match c * c - 4.0 * w2 {
            d if d > 0.0 => 0.5 * (c + d.sqrt()),
            _ => w2.sqrt(),
        };
        let dt_max = 2.0 / fastest;
        if dt > dt_max {
            out.push(format!(
                "joint `{}`'s position stop is too stiff for --dt {dt}: on its inertia \
                 {inertia:.2e} at q0 the stop's spring ({:.0e}) and damper ({:.0e}) need steps \
                 below {dt_max:.1e}, or --integrator dopri5 (adaptive: short steps at the stop only); the state will \
                 likely run away if it reaches the stop",
                joint.name, smoothing.stop_stiffness, smoothing.stop_damping
            ));
        }
    }
    out
}

/// Points per line in the plot: a longer trajectory is thinned to about this many.
const PLOT_POINTS: usize = 2000;

/// Runs `simulate`; a one-line summary for stdout, or the error message for stderr.
pub fn run(args: &SimulateArgs) -> Result<String, String> {
    let (model, reference) = load_reference(&args.model, args.base, args.params.as_deref())?;
    let (nq, nv) = (reference.nq(), reference.nv());
    let q0 = match &args.q0 {
        Some(s) => parse_vector(s, "q0", nq)?,
        None => model.neutral(),
    };
    let v0 = match &args.v0 {
        Some(s) => parse_vector(s, "v0", nv)?,
        None => vec![0.0; nv],
    };
    let method: Method = args
        .integrator
        .parse()
        .map_err(|e| format!("error: --integrator `{}`: {e}", args.integrator))?;
    let simulation = Simulation::new(0.0, args.t_end, args.dt);
    let steps = simulation.steps().map_err(|_| {
        format!(
            "error: --t-end {} and --dt {} give no time grid: both must be finite, dt positive \
             and t-end at least 0",
            args.t_end, args.dt
        )
    })?;
    if args.drives {
        for warning in stiff_stops(&model, &reference, &q0, args.dt, method) {
            eprintln!("warning: {warning}");
        }
    }
    // τ = 0, through the drives if asked.
    let drives = args.drives.then(|| ModelDrives::of(&model));
    let mut system = Interpreted::new(reference, move |_, q, v| {
        let zero = DVector::zeros(v.len());
        match &drives {
            Some(drives) => drives.force(q, v, &zero),
            None => zero,
        }
    });
    let mut stepper = Stepper::new(method, args.rtol, args.atol);
    let mut trajectory = Trajectory::new();
    let bar = progress_bar(steps);
    let initial = State::new(0.0, DVector::from_vec(q0), DVector::from_vec(v0));
    simulation
        .record(
            &mut system,
            &mut stepper,
            initial,
            &mut trajectory,
            |k, _| {
                if k % 64 == 0 {
                    bar.set_position(k as u64);
                }
            },
        )
        .map_err(|fault| {
            bar.abandon();
            // Where the last good state stood: a state that ran away (|v| in the thousands)
            // says the step was too long for the chain's stiffest motion.
            let last = trajectory.states().last().map_or_else(String::new, |s| {
                format!(
                    "; the last state reached (t = {}) has max |q| = {:.3e} and max |v| = {:.3e}",
                    s.t,
                    s.q.amax(),
                    s.v.amax()
                )
            });
            format!(
                "error: the simulation stopped: {fault}{last}; nothing was written to {}",
                args.out.display()
            )
        })?;
    bar.finish_and_clear();

    let mut csv = Vec::new();
    trajectory
        .write_csv(&mut csv, nq, nv)
        .map_err(|e| format!("error: {e}"))?;
    write_atomically(&args.out, &csv).map_err(|e| format!("{}: error: {e}", args.out.display()))?;
    if let Some(plot) = &args.plot {
        let figure = figure(system.reference(), &trajectory, &args.model)?;
        write_atomically(plot, figure.as_bytes())
            .map_err(|e| format!("{}: error: {e}", plot.display()))?;
    }
    let last = trajectory.states().last().map_or(0.0, |s| s.t);
    Ok(format!(
        "{} states from t = 0 to {last} s by {method} written to {}",
        trajectory.len(),
        args.out.display()
    ))
}

/// A bar on stderr for long runs; hidden when stderr is not a terminal.
fn progress_bar(steps: usize) -> ProgressBar {
    let bar = ProgressBar::new(steps as u64);
    if let Ok(style) =
        ProgressStyle::with_template("{bar:40} {pos}/{len} steps, {elapsed} elapsed, {eta} left")
    {
        bar.set_style(style);
    }
    bar
}

/// The joint coordinates and the energies against time.
fn figure(
    reference: &Reference,
    trajectory: &Trajectory<f64, Dyn, Dyn>,
    model: &Path,
) -> Result<String, String> {
    let states = trajectory.states();
    let stride = states.len().div_ceil(PLOT_POINTS).max(1);
    let kept: Vec<_> = states.iter().step_by(stride).collect();
    let name = model.display();
    let mut positions = Panel::new(&format!("{name}: positions"), "t (s)", "q");
    for i in 0..reference.nq() {
        positions = positions.with(
            &format!("q{i}"),
            kept.iter()
                .filter_map(|s| s.q.get(i).map(|&q| (s.t, q)))
                .collect(),
        );
    }
    let energy = |s: &State<f64, Dyn, Dyn>| -> Result<(f64, f64), String> {
        let kinetic = reference.kinetic_energy(s.q.as_slice(), s.v.as_slice());
        let potential = reference.potential_energy(s.q.as_slice());
        match (kinetic, potential) {
            (Ok(k), Ok(p)) => Ok((k, p)),
            (Err(e), _) | (_, Err(e)) => Err(format!("error: energy at t = {}: {e}", s.t)),
        }
    };
    let energies = kept
        .iter()
        .map(|s| energy(s).map(|e| (s.t, e)))
        .collect::<Result<Vec<_>, _>>()?;
    let series = |f: fn((f64, f64)) -> f64| energies.iter().map(|&(t, e)| (t, f(e))).collect();
    let energy_panel = Panel::new(&format!("{name}: energy"), "t (s)", "energy (J)")
        .with("kinetic", series(|(k, _)| k))
        .with("potential", series(|(_, p)| p))
        .with("total", series(|(k, p)| k + p));
    svg(&[positions, energy_panel], 900, 360).map_err(|e| format!("error: {e}"))
}
