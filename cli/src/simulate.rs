//! `articulated simulate`: a chain read from a file, left to itself (`τ = 0`, with its joints'
//! damping, friction and stops under `--drives`) from an initial state, stepped by one of the
//! runtime's integrators on the interpreted reference dynamics (the CLI cannot compile a
//! chain); the trajectory written as CSV with its JSON sidecar (`articulated::trajectory`:
//! each column's coordinate and unit, the integrator, the outcome) and, if asked, plotted. A
//! run that stops on a fault writes the same, up to the last good state.

use std::path::Path;

use articulated::drives::ModelDrives;
use articulated::files::write_atomically;
use articulated::integrate::{Method, State, Stepper};
use articulated::interpreted::Interpreted;
use articulated::model::Model;
use articulated::nalgebra::{DVector, Dyn};
use articulated::plot::{svg, Panel};
use articulated::reference::Reference;
use articulated::simulate::Simulation;
use articulated::trajectory::{sidecar_path, Column, Outcome, Sidecar, Trajectory};
use indicatif::{ProgressBar, ProgressStyle};

use crate::pinocchio::{Pinocchio, QOrder};
use crate::{load_described, parse_vector, SimulateArgs};

/// The position stops that a fixed-step explicit integrator cannot step at `dt`: a stop is a
/// spring and damper on the joint's inertia `I = M_kk(q0)`, whose fastest mode decays at
/// `|λ| = (c + √(c² − 4ω²))/2` with `c = stop_damping / I`, `ω² = stop_stiffness / I` (`ω`
/// when the roots are complex); Euler, symplectic Euler and RK4 are stable for
/// `|λ|·dt ≲ 2`. A light joint (a fingertip) against the default stops needs far smaller steps
/// than the rest of the chain: said before the run, rather than found as a diverged state.
fn stiff_stops(
    model: &Model,
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
///
/// A run that stops on a fault still writes what it has: the CSV of every state up to the last
/// good one, the sidecar (which names the fault) and the plot if asked; the error then says
/// what was written.
pub fn run(args: &SimulateArgs) -> Result<String, String> {
    let (mut description, mut reference) =
        load_described(&args.model, args.base, args.params.as_deref())?;
    if let Some(g) = &args.gravity {
        let g = parse_vector(g, "gravity", 3)?;
        description.model.gravity = Some(core::array::from_fn(|i| {
            articulated::model::Value::Const(g.get(i).copied().unwrap_or(0.0))
        }));
        reference = Reference::with_params(&description.model, reference.params())
            .map_err(|e| format!("error: --gravity: {e}"))?;
    }
    let model = description.model.clone();
    let (nq, nv) = (reference.nq(), reference.nv());
    // `--q-order pinocchio`: the initial state as Pinocchio writes it; the trajectory is ours
    // (its sidecar names every column).
    let pinocchio = (args.q_order == QOrder::Pinocchio).then(|| Pinocchio::of(&description));
    let q0 = match (&args.q0, &pinocchio) {
        (Some(s), None) => parse_vector(s, "q0", nq)?,
        (Some(s), Some(p)) => p.q_in(&parse_vector(s, "q0", p.nq()?)?, "q0")?,
        (None, _) => model.neutral(),
    };
    let v0 = match (&args.v0, &pinocchio) {
        (Some(s), None) => parse_vector(s, "v0", nv)?,
        (Some(s), Some(p)) => p.v_in(&parse_vector(s, "v0", nv)?, "v0")?,
        (None, _) => vec![0.0; nv],
    };
    articulated::reference::check_q(&model, &q0).map_err(|e| format!("error: --q0: {e}"))?;
    let simulation = Simulation::new(0.0, args.t_end, args.dt);
    let steps = simulation.steps().map_err(|_| {
        format!(
            "error: --t-end {} and --dt {} give no time grid: both must be finite, dt positive \
             and t-end at least 0",
            args.t_end, args.dt
        )
    })?;
    let scene = crate::ground::Scene::of(args, &model, &description.options)?;
    let method: Method = match (&args.integrator, &scene) {
        (Some(name), None) => name
            .parse()
            .map_err(|e| format!("error: --integrator `{name}`: {e}"))?,
        (None, None) => Method::Rk4,
        (Some(_), Some(_)) => {
            return Err(
                "error: --integrator: a run with --ground is stepped with contacts \
                        (semi-implicit Euler at --dt); leave --integrator out"
                    .into(),
            )
        }
        (None, Some(scene)) => {
            return with_contacts(args, &model, &reference, scene, q0, v0, &simulation, steps)
        }
    };
    if args.drives {
        for warning in stiff_stops(&model, &reference, &q0, args.dt, method) {
            eprintln!("warning: {warning}");
        }
    }
    // τ = 0, through the drives if asked.
    let drives = args.drives.then(|| ModelDrives::of(&model));
    let forces = drives.clone();
    let mut system = Interpreted::new(reference, move |_, q, v| {
        let zero = DVector::zeros(v.len());
        match &forces {
            Some(drives) => drives.force(q, v, &zero),
            None => zero,
        }
    });
    let mut stepper = Stepper::new(method, args.rtol, args.atol);
    let mut trajectory = Trajectory::new();
    let bar = progress_bar(steps);
    let initial = State::new(0.0, DVector::from_vec(q0), DVector::from_vec(v0));
    let result = simulation.record(
        &mut system,
        &mut stepper,
        initial,
        &mut trajectory,
        |k, _| {
            if k % 64 == 0 {
                bar.set_position(k as u64);
            }
        },
    );
    match result {
        Ok(()) => bar.finish_and_clear(),
        Err(_) => bar.abandon(),
    }
    if !args.drives {
        for note in limits_left(&model, &trajectory) {
            eprintln!("note: {note}");
        }
    }
    let outcome = Outcome::of(&result);
    let fault = result.err().map(|f| (outcome, f.to_string()));
    finish(
        Run {
            args,
            model: &model,
            reference: system.reference(),
            drives: drives.as_ref(),
            integrator: method.name().into(),
            forces: None,
        },
        &trajectory,
        fault,
        &format!("by {method}"),
    )
}

/// `run` with `--ground` (or a scene the description declares): the chain stepped with contacts
/// (`crate::ground`), `τ` from the drives if asked.
#[allow(clippy::too_many_arguments)]
fn with_contacts(
    args: &SimulateArgs,
    model: &Model,
    reference: &Reference,
    scene: &crate::ground::Scene,
    q0: Vec<f64>,
    v0: Vec<f64>,
    simulation: &Simulation<f64>,
    steps: usize,
) -> Result<String, String> {
    let drives = args.drives.then(|| ModelDrives::of(model));
    let run = crate::ground::simulate(
        reference,
        drives.as_ref(),
        scene,
        q0,
        v0,
        simulation,
        steps,
        progress_bar(steps),
    );
    finish(
        Run {
            args,
            model,
            reference,
            drives: drives.as_ref(),
            integrator: crate::ground::INTEGRATOR.into(),
            forces: Some(&run.forces),
        },
        &run.trajectory,
        run.fault,
        &run.note,
    )
}

/// Writes what a run produced and says how it went: the summary for stdout, or the error (the
/// fault, where the last good state stood and what was written) for stderr. `how` completes
/// the summary (`by rk4`).
fn finish(
    run: Run<'_>,
    trajectory: &Trajectory<f64, Dyn, Dyn>,
    fault: Option<(Outcome, String)>,
    how: &str,
) -> Result<String, String> {
    let args = run.args;
    let outcome = fault
        .as_ref()
        .map_or(Outcome::Completed, |(o, _)| o.clone());
    let (written, failed) = run.write(trajectory, &outcome);
    let last = trajectory.states().last();
    let Some((_, fault)) = fault else {
        return match failed {
            Some(e) => Err(e),
            None => Ok(format!(
                "{} states from t = 0 to {} s {how} written to {}",
                trajectory.len(),
                last.map_or(0.0, |s| s.t),
                args.out.display()
            )),
        };
    };
    // Where the last good state stood: a state that ran away (|v| in the thousands) says the
    // step was too long for the chain's stiffest motion.
    let reached = last.map_or_else(String::new, |s| {
        format!(
            "; the last state reached (t = {}) has max |q| = {:.3e} and max |v| = {:.3e}",
            s.t,
            s.q.amax(),
            s.v.amax()
        )
    });
    let mut kept = if written.is_empty() {
        "nothing was written".to_string()
    } else {
        format!(
            "the {} states up to t = {} were written to {}",
            trajectory.len(),
            last.map_or(0.0, |s| s.t),
            written.join(", ")
        )
    };
    if let Some(e) = failed {
        kept += &format!(" (then: {e})");
    }
    Err(format!(
        "error: the simulation stopped: {fault}{reached}; {kept}"
    ))
}

/// What a run writes, and from what.
struct Run<'a> {
    args: &'a SimulateArgs,
    model: &'a Model,
    reference: &'a Reference,
    drives: Option<&'a ModelDrives>,
    /// The sidecar's name for how it was stepped.
    integrator: String,
    /// The contact forces, with `--ground`.
    forces: Option<&'a crate::ground::Forces>,
}

impl Run<'_> {
    /// Writes the CSV, its sidecar and the plot if asked, in that order, each whole or not at
    /// all, up to the first error: the paths written, and that error.
    fn write(
        &self,
        trajectory: &Trajectory<f64, Dyn, Dyn>,
        outcome: &Outcome,
    ) -> (Vec<String>, Option<String>) {
        let mut written = Vec::new();
        let failed = self.write_each(trajectory, outcome, &mut written).err();
        (written, failed)
    }

    fn write_each(
        &self,
        trajectory: &Trajectory<f64, Dyn, Dyn>,
        outcome: &Outcome,
        written: &mut Vec<String>,
    ) -> Result<(), String> {
        let args = self.args;
        let (nq, nv) = (self.reference.nq(), self.reference.nv());
        let mut csv = Vec::new();
        trajectory
            .write_csv(&mut csv, nq, nv)
            .map_err(|e| format!("error: {e}"))?;
        let forces = self.forces.filter(|_| args.contact_forces);
        if let Some(forces) = forces {
            csv = forces.append_to_csv(&csv);
        }
        write_atomically(&args.out, &csv)
            .map_err(|e| format!("{}: error: {e}", args.out.display()))?;
        written.push(args.out.display().to_string());
        let sidecar = sidecar_path(&args.out);
        let names = self.model.coordinate_names();
        let units = self.model.coordinate_units();
        let description = Sidecar {
            model: args.model.display().to_string(),
            name: chain_name(self.model, &args.model),
            columns: {
                let mut columns = Column::trajectory((&names.0, &units.0), (&names.1, &units.1));
                columns.extend(
                    forces
                        .map(crate::ground::Forces::columns)
                        .unwrap_or_default(),
                );
                columns
            },
            integrator: self.integrator.clone(),
            dt: args.dt,
            rows: trajectory.len(),
            t_last: trajectory.states().last().map(|s| s.t),
            outcome: outcome.clone(),
        };
        write_atomically(&sidecar, description.to_string().as_bytes())
            .map_err(|e| format!("{}: error: {e}", sidecar.display()))?;
        written.push(sidecar.display().to_string());
        if let Some(plot) = &self.args.plot {
            let figure = self.figure(trajectory)?;
            write_atomically(plot, figure.as_bytes())
                .map_err(|e| format!("{}: error: {e}", plot.display()))?;
            written.push(plot.display().to_string());
        }
        Ok(())
    }

    /// The joint coordinates, one panel per unit (angles, lengths, quaternion components),
    /// each labelled by coordinate, and the energies, against time.
    fn figure(&self, trajectory: &Trajectory<f64, Dyn, Dyn>) -> Result<String, String> {
        let states = trajectory.states();
        let stride = states.len().div_ceil(PLOT_POINTS).max(1);
        let mut kept: Vec<_> = states.iter().step_by(stride).collect();
        // The last state (where a run stopped) is always drawn.
        if let Some(last) = states.last() {
            if kept.last().is_some_and(|k| !std::ptr::eq(*k, last)) {
                kept.push(last);
            }
        }
        let name = chain_name(self.model, &self.args.model);
        let (names, _) = self.model.coordinate_names();
        let (units, _) = self.model.coordinate_units();
        let mut panels: Vec<(&str, Panel)> = Vec::new();
        for (i, (coordinate, &unit)) in names.iter().zip(&units).enumerate() {
            let index = match panels.iter().position(|(u, _)| *u == unit) {
                Some(index) => index,
                None => {
                    let (what, axis) = match unit {
                        "rad" => ("angles", "angle (rad)".to_string()),
                        "m" => ("lengths", "length (m)".to_string()),
                        "1" => ("quaternion components", "component (1)".to_string()),
                        other => ("positions", format!("q ({other})")),
                    };
                    let title = format!("{name}: {what}");
                    panels.push((unit, Panel::new(&title, "t (s)", &axis)));
                    panels.len() - 1
                }
            };
            let points = kept
                .iter()
                .filter_map(|s| s.q.get(i).map(|&q| (s.t, q)))
                .collect();
            if let Some((_, panel)) = panels.get_mut(index) {
                panel.series.push(articulated::plot::Series {
                    label: coordinate.clone(),
                    points,
                });
            }
        }
        let mut panels: Vec<Panel> = panels.into_iter().map(|(_, p)| p).collect();
        if let Some(forces) = self.forces {
            panels.push(forces.panel(&name, stride));
        }
        panels.extend(energy_panel(
            &format!("{name}: energy"),
            self.reference,
            self.drives,
            &kept,
        ));
        svg(&panels, 900, 300).map_err(|e| format!("error: {e}"))
    }
}

/// The chain's name from its description, or the file's stem where it has none: the plots'
/// title (not the path the user typed, which may be long and absolute).
pub fn chain_name(model: &Model, path: &Path) -> String {
    if !model.name.trim().is_empty() {
        return model.name.clone();
    }
    path.file_stem()
        .map_or_else(|| "chain".into(), |s| s.to_string_lossy().into_owned())
}

/// The kinetic, potential and total energy at `states`. The potential is gravity's and, with
/// drives, the energy held in the position stops' springs (`ModelDrives::stop_energy`), so the
/// total does not jump at a stop's impact: it stays constant where nothing dissipates and only
/// falls through damping and friction. States whose energy is not finite (a run that ran away
/// before a fault) are left out; `None` if no state is left.
fn energy_panel(
    title: &str,
    reference: &Reference,
    drives: Option<&ModelDrives>,
    states: &[&State<f64, Dyn, Dyn>],
) -> Option<Panel> {
    let energy = |s: &State<f64, Dyn, Dyn>| -> Option<(f64, f64)> {
        let kinetic = reference
            .kinetic_energy(s.q.as_slice(), s.v.as_slice())
            .ok()?;
        let potential = reference.potential_energy(s.q.as_slice()).ok()?;
        let stops = drives.map_or(0.0, |d| d.stop_energy(&s.q));
        let finite = kinetic.is_finite() && (potential + stops).is_finite();
        finite.then_some((kinetic, potential + stops))
    };
    let energies: Vec<(f64, (f64, f64))> = states
        .iter()
        .filter_map(|s| energy(s).map(|e| (s.t, e)))
        .collect();
    if energies.is_empty() {
        return None;
    }
    let series = |f: fn((f64, f64)) -> f64| energies.iter().map(|&(t, e)| (t, f(e))).collect();
    let potential = if drives.is_some() {
        "potential (gravity and stops)"
    } else {
        "potential"
    };
    Some(
        Panel::new(title, "t (s)", "energy (J)")
            .with("kinetic", series(|(k, _)| k))
            .with(potential, series(|(_, p)| p))
            .with("total", series(|(k, p)| k + p)),
    )
}

/// For a run without drives, one line per joint with limits that its coordinate left during
/// the run: how far it went, and that limits need `--drives`.
fn limits_left(model: &Model, trajectory: &Trajectory<f64, Dyn, Dyn>) -> Vec<String> {
    let units = model.coordinate_units().0;
    let mut notes = Vec::new();
    for (j, joint) in model.joints.iter().enumerate() {
        let (lower, upper) = (joint.drive.lower, joint.drive.upper);
        if joint.nq() != 1 || !(lower.is_finite() || upper.is_finite()) {
            continue;
        }
        let i = model.q_offset(j);
        // The state farthest outside the range, and by how much.
        let mut farthest: Option<(f64, f64, f64)> = None;
        for s in trajectory.states() {
            let Some(&x) = s.q.get(i) else { continue };
            let past = (x - upper).max(lower - x);
            if past > 0.0 && farthest.is_none_or(|(_, _, p)| past > p) {
                farthest = Some((s.t, x, past));
            }
        }
        let Some((t, x, _)) = farthest else { continue };
        let unit = units.get(i).copied().unwrap_or("");
        notes.push(format!(
            "joint `{}` left its range [{}, {}] {unit} (reached {} {unit} at t = {} s): limits \
             are applied only with --drives",
            joint.name,
            bound(lower),
            bound(upper),
            short(x),
            short(t)
        ));
    }
    notes
}

/// A limit as given, `−∞` or `∞` when there is none.
fn bound(x: f64) -> String {
    match x {
        f64::NEG_INFINITY => "−∞".into(),
        f64::INFINITY => "∞".into(),
        x => format!("{x}"),
    }
}

/// `x` to four decimals (trailing zeros dropped), or in scientific notation when large.
fn short(x: f64) -> String {
    if x.abs() >= 1e6 {
        return format!("{x:.3e}");
    }
    let text = format!("{x:.4}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    match text {
        "-0" | "" => "0".into(),
        t => t.into(),
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use articulated::integrate::Rk4;

    /// Issue 31: with `--drives` the plotted total energy jumped at a stop's impact, the
    /// stop's spring energy left out. A pendulum thrown into its stop, with no damping
    /// anywhere (the stops' dampers off), keeps the plotted total to RK4's accuracy through
    /// the impact; the same states without the spring term lose, at the deepest point, the
    /// kinetic energy the spring took.
    #[test]
    fn the_plotted_total_energy_includes_the_stops_springs() {
        let dir = std::env::temp_dir().join(format!("articulated-energy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("pendulum.chain");
        std::fs::write(
            &path,
            "chain Pendulum {\n\
             body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }\n\
             joint pivot: revolute(y) { parent: world, child: bob, lower: -0.5, upper: 0.5 }\n\
             }\n",
        )
        .unwrap();
        let model = articulated_codegen::load::load_model(&path, false).unwrap();
        std::fs::remove_dir_all(&dir).ok();
        let reference = Reference::new(&model).unwrap();
        let mut drives = ModelDrives::of(&model);
        drives.smoothing.stop_damping = 0.0;
        let forces = drives.clone();
        let mut system = Interpreted::new(Reference::new(&model).unwrap(), move |_, q, v| {
            forces.force(q, v, &DVector::zeros(v.len()))
        });
        let mut trajectory = Trajectory::new();
        let start = State::new(
            0.0,
            DVector::from_vec(vec![0.4]),
            DVector::from_vec(vec![2.0]),
        );
        Simulation::new(0.0, 1.0, 1e-4)
            .record(&mut system, &mut Rk4, start, &mut trajectory, |_, _| {})
            .unwrap();
        let states: Vec<_> = trajectory.states().iter().collect();
        let deepest = states.iter().map(|s| s.q[0]).fold(f64::MIN, f64::max);
        assert!(
            deepest > 0.51,
            "the stop is reached and pressed into: {deepest}"
        );
        let first_in = states.iter().position(|s| s.q[0] > 0.5).unwrap();
        assert!(
            states[first_in..].iter().any(|s| s.q[0] < 0.5),
            "and it bounces back: the impact is over"
        );
        let total = |drives: Option<&ModelDrives>| -> Vec<f64> {
            let panel = energy_panel("energy", &reference, drives, &states).unwrap();
            assert_eq!(panel.series[2].label, "total");
            panel.series[2].points.iter().map(|p| p.1).collect()
        };
        let spread = |e: &[f64]| {
            let (lo, hi) = e
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
            hi - lo
        };
        // The kinetic energy at stake: about ½·I·v² ≈ 2 J. RK4 steps across the stop's kink
        // (the force is continuous, its slope is not) with a larger error than elsewhere:
        // 2.8e-5 J at this step, 2.5e-6 J at half of it.
        let with = spread(&total(Some(&drives)));
        assert!(with < 1e-4, "the total varies by {with:e} J");
        let without = spread(&total(None));
        assert!(
            without > 0.5,
            "without the springs it varies by {without:e} J"
        );
    }
}
